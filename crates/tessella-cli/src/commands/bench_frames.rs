//! `tessella bench`'s deforming-mesh table: a mesh twisting frame after frame, refined by
//! updating a plan's frame (O(coarse) nets, then vertices written into reused buffers, indices
//! not rewritten) against rebuilding everything per frame (mesh, topology, nets, stencil,
//! pattern, fresh buffers and indices), with the machine's memory fill rate measured in the
//! same run as the roofline.

use rayon::prelude::*;
use std::time::{Duration, Instant};
use tessella_core::refine::{Plan, VertexOutput};
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme};

/// One frame's coarse positions and normals.
type FrameData = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// Bytes of the buffer the fill rate is measured on: far larger than any cache.
const FILL_BYTES: usize = 512 << 20;

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

/// Bytes per second all threads write into memory with plain stores (`fill`), median of
/// `repeat` passes over a buffer much larger than the caches; the page faults of the first
/// pass are not timed.
pub fn fill_rate(repeat: usize) -> f64 {
    let mut buffer = vec![0.0f32; FILL_BYTES / 4];
    let threads = rayon::current_num_threads().max(1);
    let chunk = buffer.len().div_ceil(threads);
    let mut pass = |value: f32| {
        buffer
            .par_chunks_mut(chunk)
            .for_each(|c| c.fill(std::hint::black_box(value)));
    };
    pass(1.0);
    let time = median(
        (0..repeat.max(3))
            .map(|i| {
                let start = Instant::now();
                pass(i as f32);
                start.elapsed()
            })
            .collect(),
    );
    std::hint::black_box(&buffer);
    FILL_BYTES as f64 / time.as_secs_f64()
}

/// Prints the table for `mesh` (named `name`) at `levels`.
pub fn table(
    name: &str,
    mesh: &Mesh,
    levels: &[u32],
    repeat: usize,
    fill: f64,
) -> anyhow::Result<()> {
    let frames: Vec<FrameData> = (0..8)
        .map(|i| samples::twist(mesh, 10.0 * i as f32))
        .collect();
    println!();
    println!(
        "Deforming mesh ({name}, {} coarse triangles, twisting), PN, welded, positions + normals; per frame, median of {repeat}; fill rate {:.1} GB/s:",
        mesh.face_count(),
        fill / 1e9
    );
    println!();
    println!("| level | vertices | rebuild (ms) | update + evaluate (ms) | speed-up | update (ms) | GB/s written | of fill rate |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &level in levels {
        let options = RefineOptions::new(Scheme::Pn, level);
        let plan = Plan::new(mesh, &options)?;
        let mut frame = plan.frame(mesh)?;
        let n = plan.vertex_count();
        let (mut positions, mut normals) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
        let mut at = 0;
        let mut step = |update_only: bool| -> anyhow::Result<Duration> {
            let (p, nr) = &frames[at % frames.len()];
            at += 1;
            let start = Instant::now();
            plan.update(&mut frame, p, Some(nr))?;
            if !update_only {
                plan.evaluate(
                    &frame,
                    VertexOutput::Separate {
                        positions: &mut positions,
                        normals: Some(&mut normals),
                        uvs: None,
                    },
                )?;
            }
            Ok(start.elapsed())
        };
        step(false)?; // warm up: fault the output pages in
        let per_frame = median((0..repeat).map(|_| step(false)).collect::<Result<_, _>>()?);
        let update = median((0..repeat).map(|_| step(true)).collect::<Result<_, _>>()?);
        let rebuild = median(
            (0..repeat)
                .map(|i| -> anyhow::Result<Duration> {
                    let (p, nr) = &frames[i % frames.len()];
                    let start = Instant::now();
                    let m =
                        Mesh::new(p.clone(), Some(nr.clone()), None, mesh.triangles().to_vec())?;
                    let out = Refiner::new(&m, &options)?.refine();
                    let time = start.elapsed();
                    std::hint::black_box(out);
                    Ok(time)
                })
                .collect::<Result<_, _>>()?,
        );
        let bytes = (n * 24) as f64;
        let rate = bytes / per_frame.as_secs_f64();
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        println!(
            "| {level} | {n} | {:.2} | {:.2} | {:.1}x | {:.3} | {:.2} | {:.0}% |",
            ms(rebuild),
            ms(per_frame),
            rebuild.as_secs_f64() / per_frame.as_secs_f64(),
            ms(update),
            rate / 1e9,
            100.0 * rate / fill
        );
    }
    Ok(())
}
