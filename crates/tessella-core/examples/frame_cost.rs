//! Per-frame evaluation for instruction counting and timing:
//! `cargo run --release --example frame_cost -p tessella-core -- SCHEME NORMALS LEVEL FRAMES
//! [SUBDIVISIONS]`.
//!
//! Runs `Plan::evaluate` (positions + normals into reused buffers) FRAMES times on the
//! 5120-triangle icosphere. Under `valgrind --tool=callgrind` the difference between two
//! frame counts, divided by the extra vertices, is the instruction count per refined vertex
//! (`scripts/frame_cost.sh` does that), a figure that does not move with the machine's load.
use std::time::Instant;
use tessella_core::refine::{Plan, VertexOutput};
use tessella_core::{samples, NormalMode, RefineOptions, Scheme};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.into());
    let scheme: Scheme = arg(0, "pn").parse()?;
    let normals: NormalMode = arg(1, "quadratic").parse()?;
    let level: u32 = arg(2, "32").parse()?;
    let frames: usize = arg(3, "4").parse::<usize>()?.max(1);
    // The 5120-triangle icosphere (4 subdivisions) unless told: fewer keep a frame in cache.
    let mesh = samples::icosphere(arg(4, "4").parse()?);
    let options = RefineOptions::new(scheme, level).with_normals(normals);
    let plan = Plan::new(&mesh, &options)?;
    let frame = plan.frame(&mesh)?;
    let n = plan.vertex_count();
    let (mut positions, mut out_normals) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
    let mut times = Vec::with_capacity(frames);
    for _ in 0..frames {
        let start = Instant::now();
        plan.evaluate(
            &frame,
            VertexOutput::Separate {
                positions: &mut positions,
                normals: Some(&mut out_normals),
                uvs: None,
            },
        )?;
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let (best, median) = (times[0], times[times.len() / 2]);
    let check: f32 = positions.iter().chain(&out_normals).map(|p| p[0]).sum();
    println!(
        "{n} vertices, best of {frames}: {:.3} ms, {:.1} M vertices/s; median {:.3} ms, {:.1} M \
         vertices/s (checksum {check})",
        best * 1e3,
        n as f64 / best / 1e6,
        median * 1e3,
        n as f64 / median / 1e6
    );
    Ok(())
}
