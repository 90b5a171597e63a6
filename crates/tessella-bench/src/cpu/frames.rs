//! `tessella bench`'s per-frame measurements: the machine's memory bandwidth (the roofline),
//! every scheme refined per frame into reused buffers against it, and a deforming mesh refined
//! by updating a plan's frame against rebuilding everything per frame.

use rayon::prelude::*;
use serde::Serialize;
use std::time::{Duration, Instant};
use tessella_core::refine::{Frame, Plan, VertexOutput};
use tessella_core::{samples, Mesh, NormalMode, RefineError, RefineOptions, Refiner, Scheme};

/// One frame's coarse positions and normals.
type FrameData = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// Bytes of the buffers bandwidth is measured on: larger than the last-level cache this
/// machine reports (STREAM's rule is four times; a 1 GiB buffer is what a shared 24 GiB
/// machine affords for the copy's two).
const BANDWIDTH_BYTES: usize = 1 << 30;

/// Bytes written per refined vertex in the per-frame tables: a position and a normal.
pub const BYTES_PER_VERTEX: usize = 24;

pub fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

/// The reused output of the per-frame measurements: a position and a normal per refined
/// vertex (the [`BYTES_PER_VERTEX`] the tables count), no UVs. One type, so that every table
/// times the same write.
pub(super) struct FrameOutput {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
}

impl FrameOutput {
    /// Buffers for `plan`'s refined vertices.
    pub(super) fn new(plan: &Plan) -> FrameOutput {
        let n = plan.vertex_count();
        FrameOutput {
            positions: vec![[0.0; 3]; n],
            normals: vec![[0.0; 3]; n],
        }
    }

    /// Evaluates `frame` of `plan` into the buffers.
    pub(super) fn evaluate(&mut self, plan: &Plan, frame: &Frame) -> Result<(), RefineError> {
        plan.evaluate(
            frame,
            VertexOutput::Separate {
                positions: &mut self.positions,
                normals: Some(&mut self.normals),
                uvs: None,
            },
        )
    }
}

/// What the machine's memory takes, measured the way STREAM does: on all threads, over
/// buffers larger than the caches, with vector stores, and with non-temporal stores where the
/// platform has them (x86-64), reported separately. Each figure is the median of the passes;
/// the page faults of the first pass are not timed.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Bandwidth {
    pub threads: usize,
    /// The fill rate the tables compare with: the faster of the two fills below, what the
    /// machine can write.
    pub fill_bytes_per_s: f64,
    /// Bytes per second written with plain vector stores (each line read before it is
    /// written, unless the processor elides it).
    pub fill_plain_bytes_per_s: f64,
    /// Bytes per second written with non-temporal stores (no read for ownership; on
    /// platforms without them, the plain fill again).
    pub fill_nt_bytes_per_s: f64,
    /// Bytes per second written with plain vector stores by one thread: the like-for-like
    /// figure for a one-thread peer (numpy's `ndarray.fill`), which checks this measurement.
    pub fill_plain_one_thread_bytes_per_s: f64,
    /// Bytes per second moved by `copy_from_slice` (the C library's `memcpy`), reads and
    /// writes both counted (as STREAM's Copy).
    pub copy_bytes_per_s: f64,
    /// The same with vector loads and non-temporal stores.
    pub copy_nt_bytes_per_s: f64,
    /// Bytes per second written into freshly allocated memory: every page faulted in and
    /// zeroed by the system first. What one-shot output (new arrays every call) is bounded by.
    pub fresh_fill_bytes_per_s: f64,
}

/// Non-temporal stores: write-combined lines that skip the read for ownership and the caches,
/// how a stream far larger than the caches is written fastest; the core's, which the
/// evaluator's sinks use (plain stores on other platforms).
mod streaming {
    pub use tessella_core::refine::{stream_copy as copy, stream_fill as fill};
}

impl Bandwidth {
    pub fn measure(repeat: usize) -> Bandwidth {
        let threads = rayon::current_num_threads().max(1);
        let mut dst = vec![0.0f32; BANDWIDTH_BYTES / 4];
        let src = vec![1.0f32; BANDWIDTH_BYTES / 4];
        let chunk = dst.len().div_ceil(threads);
        let time = |pass: &mut dyn FnMut(f32)| {
            pass(0.0);
            median(
                (0..repeat.max(3))
                    .map(|i| {
                        let start = Instant::now();
                        pass(i as f32);
                        start.elapsed()
                    })
                    .collect(),
            )
        };
        let fill_plain = time(&mut |value| {
            dst.par_chunks_mut(chunk)
                .for_each(|c| c.fill(std::hint::black_box(value)))
        });
        let fill_one = time(&mut |value| dst.fill(std::hint::black_box(value)));
        let fill_nt = time(&mut |value| {
            dst.par_chunks_mut(chunk)
                .for_each(|c| streaming::fill(c, std::hint::black_box(value)))
        });
        let copy = time(&mut |_| {
            dst.par_chunks_mut(chunk)
                .zip(src.par_chunks(chunk))
                .for_each(|(d, s)| d.copy_from_slice(std::hint::black_box(s)))
        });
        let copy_nt = time(&mut |_| {
            dst.par_chunks_mut(chunk)
                .zip(src.par_chunks(chunk))
                .for_each(|(d, s)| {
                    streaming::copy(d, std::hint::black_box(s));
                })
        });
        std::hint::black_box(&dst);
        drop((dst, src));
        let fresh = median(
            (0..repeat.max(3))
                .map(|i| {
                    let start = Instant::now();
                    let mut fresh = vec![0.0f32; BANDWIDTH_BYTES / 4];
                    fresh
                        .par_chunks_mut(chunk)
                        .for_each(|c| c.fill(std::hint::black_box(i as f32)));
                    let time = start.elapsed();
                    std::hint::black_box(fresh);
                    time
                })
                .collect(),
        );
        let rate = |bytes: usize, d: Duration| bytes as f64 / d.as_secs_f64();
        let (plain, nt) = (
            rate(BANDWIDTH_BYTES, fill_plain),
            rate(BANDWIDTH_BYTES, fill_nt),
        );
        Bandwidth {
            threads,
            fill_bytes_per_s: plain.max(nt),
            fill_plain_bytes_per_s: plain,
            fill_nt_bytes_per_s: nt,
            fill_plain_one_thread_bytes_per_s: rate(BANDWIDTH_BYTES, fill_one),
            copy_bytes_per_s: rate(2 * BANDWIDTH_BYTES, copy),
            copy_nt_bytes_per_s: rate(2 * BANDWIDTH_BYTES, copy_nt),
            fresh_fill_bytes_per_s: rate(BANDWIDTH_BYTES, fresh),
        }
    }
}

/// One row of the roofline table: a scheme refined per frame (plan and frame reused, nets
/// not rebuilt, indices not rewritten), positions and normals into reused separate arrays.
#[derive(Debug, Clone, Serialize)]
pub struct RooflineRow {
    pub scheme: String,
    pub normals: String,
    pub level: u32,
    pub vertices: usize,
    pub ms: f64,
    pub vertices_per_s: f64,
    pub bytes_per_vertex: usize,
    pub bytes_per_s: f64,
    /// `bytes_per_s` over the fill rate.
    pub of_fill: f64,
    /// Vertices per second against PN with quadratic normals at the same level.
    pub vs_pn: f64,
}

/// The schemes of the roofline table, PN first (the others are compared with it).
pub fn roofline_schemes() -> Vec<(Scheme, NormalMode)> {
    vec![
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
        (Scheme::Png1, NormalMode::Quadratic),
        (Scheme::PHONG, NormalMode::Quadratic),
        (Scheme::Flat, NormalMode::Quadratic),
    ]
}

/// Times `evaluate` of each scheme at each level on `mesh` (median of `repeat`).
pub fn roofline(
    mesh: &Mesh,
    levels: &[u32],
    repeat: usize,
    bandwidth: &Bandwidth,
) -> anyhow::Result<Vec<RooflineRow>> {
    let mut rows = Vec::new();
    for &level in levels {
        let mut pn_rate = None;
        for (scheme, normals) in roofline_schemes() {
            let options = RefineOptions::new(scheme, level).with_normals(normals);
            let plan = Plan::new(mesh, &options)?;
            let frame = plan.frame(mesh)?;
            let n = plan.vertex_count();
            let mut out = FrameOutput::new(&plan);
            let mut once = || -> anyhow::Result<Duration> {
                let start = Instant::now();
                out.evaluate(&plan, &frame)?;
                Ok(start.elapsed())
            };
            once()?; // warm up: fault the output pages in
            let time = median((0..repeat).map(|_| once()).collect::<Result<_, _>>()?);
            let rate = n as f64 / time.as_secs_f64();
            let pn = *pn_rate.get_or_insert(rate);
            let bytes = rate * BYTES_PER_VERTEX as f64;
            rows.push(RooflineRow {
                scheme: scheme.name().to_string(),
                normals: normals.to_string(),
                level,
                vertices: n,
                ms: time.as_secs_f64() * 1e3,
                vertices_per_s: rate,
                bytes_per_vertex: BYTES_PER_VERTEX,
                bytes_per_s: bytes,
                of_fill: bytes / bandwidth.fill_bytes_per_s,
                vs_pn: rate / pn,
            });
        }
    }
    Ok(rows)
}

/// Markdown table of [`roofline`] rows.
pub fn roofline_table(rows: &[RooflineRow]) -> String {
    let mut s = String::from(
        "| level | scheme | normals | vertices | ms | M vertices/s | bytes/vertex | GB/s written | of fill rate | vs PN |\n\
         |---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.2} | {:.1} | {} | {:.2} | {:.0}% | {:.2}x |\n",
            r.level,
            r.scheme,
            r.normals,
            r.vertices,
            r.ms,
            r.vertices_per_s / 1e6,
            r.bytes_per_vertex,
            r.bytes_per_s / 1e9,
            100.0 * r.of_fill,
            r.vs_pn
        );
    }
    s
}

/// One row of the deforming-mesh table.
#[derive(Debug, Clone, Serialize)]
pub struct DeformRow {
    pub mesh: String,
    pub faces: usize,
    pub level: u32,
    pub vertices: usize,
    /// Mesh, topology, nets, stencil, pattern, fresh buffers and indices, every frame.
    pub rebuild_ms: f64,
    /// Plan reused: nets updated in O(coarse), vertices written into reused buffers.
    pub update_evaluate_ms: f64,
    /// The nets update alone.
    pub update_ms: f64,
    pub bytes_per_s: f64,
    pub of_fill: f64,
}

/// A mesh twisting frame after frame (PN, welded, positions + normals), refined by updating a
/// plan's frame against rebuilding everything per frame.
pub fn deforming(
    name: &str,
    mesh: &Mesh,
    levels: &[u32],
    repeat: usize,
    bandwidth: &Bandwidth,
) -> anyhow::Result<Vec<DeformRow>> {
    let frames: Vec<FrameData> = (0..8)
        .map(|i| samples::twist(mesh, 10.0 * i as f32))
        .collect();
    let mut rows = Vec::new();
    for &level in levels {
        let options = RefineOptions::new(Scheme::Pn, level);
        let plan = Plan::new(mesh, &options)?;
        let mut frame = plan.frame(mesh)?;
        let n = plan.vertex_count();
        let mut out = FrameOutput::new(&plan);
        let mut at = 0;
        let mut step = |update_only: bool| -> anyhow::Result<Duration> {
            let (p, nr) = &frames[at % frames.len()];
            at += 1;
            let start = Instant::now();
            plan.update(&mut frame, p, Some(nr))?;
            if !update_only {
                out.evaluate(&plan, &frame)?;
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
        let rate = (n * BYTES_PER_VERTEX) as f64 / per_frame.as_secs_f64();
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        rows.push(DeformRow {
            mesh: name.to_string(),
            faces: mesh.face_count(),
            level,
            vertices: n,
            rebuild_ms: ms(rebuild),
            update_evaluate_ms: ms(per_frame),
            update_ms: ms(update),
            bytes_per_s: rate,
            of_fill: rate / bandwidth.fill_bytes_per_s,
        });
    }
    Ok(rows)
}

/// Markdown table of [`deforming`] rows.
pub fn deforming_table(rows: &[DeformRow]) -> String {
    let mut s = String::from(
        "| mesh | level | vertices | rebuild (ms) | update + evaluate (ms) | speed-up | update (ms) | GB/s written | of fill rate |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {:.1}x | {:.3} | {:.2} | {:.0}% |\n",
            r.mesh,
            r.level,
            r.vertices,
            r.rebuild_ms,
            r.update_evaluate_ms,
            r.rebuild_ms / r.update_evaluate_ms,
            r.update_ms,
            r.bytes_per_s / 1e9,
            100.0 * r.of_fill
        );
    }
    s
}
