//! `tessella bench`: the machine's memory bandwidth, then refinement measured against it and
//! against baselines timed in the same run: one-shot refinement on all cores against one core,
//! every scheme refined per frame (the roofline table), a deforming mesh updated per frame
//! against rebuilt per frame, and the file writers. `--json` prints the same numbers as one
//! object.

use super::bench_frames::{self, median, Bandwidth, DeformRow, RooflineRow};
use super::bench_write::{self, WriteRow};
use crate::args::BenchArgs;
use anyhow::Context;
use serde::Serialize;
use std::time::{Duration, Instant};
use tessella_core::{samples, Mesh, RefineOptions, RefinedMesh, Refiner, Scheme};

/// Median time of `repeat` refinements into reused buffers.
fn time_refine(refiner: &Refiner, repeat: usize) -> Duration {
    let mut out = RefinedMesh::default();
    refiner.refine_into(&mut out, &|_| {}); // warm up: allocate, fault pages in
    median(
        (0..repeat)
            .map(|_| {
                let start = Instant::now();
                refiner.refine_into(&mut out, &|_| {});
                start.elapsed()
            })
            .collect(),
    )
}

/// One row of the one-shot table: PN refined with indices into reused buffers.
#[derive(Debug, Clone, Serialize)]
struct OneShotRow {
    level: u32,
    vertices: u64,
    triangles: u64,
    /// Topology, control nets, stencil and layout.
    prepare_ms: f64,
    ms: f64,
    vertices_per_s: f64,
    one_thread_ms: f64,
    one_thread_vertices_per_s: f64,
    /// `Refiner::refine`: new arrays every call (what Python's `tessella.refine` does).
    fresh_ms: f64,
    fresh_vertices_per_s: f64,
    /// Bytes of the output: positions, normals, triangles.
    output_bytes: u64,
    /// Output bytes per second of the fresh call over the fresh-memory fill rate.
    fresh_of_fresh_fill: f64,
}

/// Everything `tessella bench` measures on the CPU, in one run.
#[derive(Debug, Serialize)]
struct Report {
    mesh: String,
    faces: usize,
    repeat: usize,
    bandwidth: Bandwidth,
    one_shot: Vec<OneShotRow>,
    per_frame: Vec<RooflineRow>,
    deforming: Vec<DeformRow>,
    /// The mesh refined at `write_level`, written in every format.
    write_level: u32,
    writers: Vec<WriteRow>,
}

fn one_shot(
    mesh: &Mesh,
    levels: &[u32],
    repeat: usize,
    bandwidth: &Bandwidth,
) -> anyhow::Result<Vec<OneShotRow>> {
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("cannot start a one-thread pool")?;
    let mut rows = Vec::new();
    for &level in levels {
        let start = Instant::now();
        let refiner = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, level))?;
        let prepare = start.elapsed();
        let vertices = refiner.layout().vertex_count;
        let many = time_refine(&refiner, repeat);
        let one = single.install(|| time_refine(&refiner, repeat));
        let fresh = median(
            (0..repeat)
                .map(|_| {
                    let start = Instant::now();
                    let out = refiner.refine();
                    let time = start.elapsed();
                    std::hint::black_box(out);
                    time
                })
                .collect(),
        );
        let rate = |d: Duration| vertices as f64 / d.as_secs_f64();
        let output_bytes = vertices * 24 + refiner.layout().triangle_count * 12;
        rows.push(OneShotRow {
            fresh_ms: fresh.as_secs_f64() * 1e3,
            fresh_vertices_per_s: rate(fresh),
            output_bytes,
            fresh_of_fresh_fill: output_bytes as f64
                / fresh.as_secs_f64()
                / bandwidth.fresh_fill_bytes_per_s,
            level,
            vertices,
            triangles: refiner.layout().triangle_count,
            prepare_ms: prepare.as_secs_f64() * 1e3,
            ms: many.as_secs_f64() * 1e3,
            vertices_per_s: rate(many),
            one_thread_ms: one.as_secs_f64() * 1e3,
            one_thread_vertices_per_s: rate(one),
        });
    }
    Ok(rows)
}

fn one_shot_table(rows: &[OneShotRow], threads: usize) -> String {
    let mut s = format!(
        "| level | vertices | triangles | prepare (ms) | reused, {threads} threads (ms) | M vertices/s | 1 thread (ms) | M vertices/s | speed-up | new arrays (ms) | M vertices/s | of fresh fill |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {:.1} | {:.2} | {:.1} | {:.2}x | {:.2} | {:.1} | {:.0}% |\n",
            r.level,
            r.vertices,
            r.triangles,
            r.prepare_ms,
            r.ms,
            r.vertices_per_s / 1e6,
            r.one_thread_ms,
            r.one_thread_vertices_per_s / 1e6,
            r.ms.recip() * r.one_thread_ms,
            r.fresh_ms,
            r.fresh_vertices_per_s / 1e6,
            100.0 * r.fresh_of_fresh_fill
        );
    }
    s
}

/// The bandwidth figures, one line.
fn bandwidth_line(b: &Bandwidth) -> String {
    let gb = |x: f64| x / 1e9;
    format!(
        "Memory bandwidth, {} threads: fill {:.1} GB/s (plain stores {:.1}, non-temporal {:.1}; plain, 1 thread {:.1}), copy {:.1} GB/s (read + write; memcpy {:.1}, non-temporal {:.1}), fill of freshly allocated memory {:.1} GB/s (page faults included)",
        b.threads,
        gb(b.fill_bytes_per_s),
        gb(b.fill_plain_bytes_per_s),
        gb(b.fill_nt_bytes_per_s),
        gb(b.fill_plain_one_thread_bytes_per_s),
        gb(b.copy_bytes_per_s.max(b.copy_nt_bytes_per_s)),
        gb(b.copy_bytes_per_s),
        gb(b.copy_nt_bytes_per_s),
        gb(b.fresh_fill_bytes_per_s)
    )
}

fn print_tables(report: &Report) {
    let b = &report.bandwidth;
    println!("{}", bandwidth_line(b));
    println!();
    println!(
        "One-shot refinement, PN, welded, positions + quadratic normals + indices, into reused buffers and into new arrays (the output bytes against the fresh-memory fill rate); {} ({} coarse triangles); median of {}:",
        report.mesh, report.faces, report.repeat
    );
    println!();
    print!("{}", one_shot_table(&report.one_shot, b.threads));
    println!();
    println!(
        "Per frame (plan and nets reused, indices not rewritten), positions + normals into reused arrays, against the fill rate; {}:",
        report.mesh
    );
    println!();
    print!("{}", bench_frames::roofline_table(&report.per_frame));
    println!();
    println!("Deforming mesh (twisting), PN: plan update + evaluate against rebuilding everything per frame:");
    println!();
    print!("{}", bench_frames::deforming_table(&report.deforming));
    println!();
    println!(
        "File writers, {} refined at level {} ({} vertices), against the copy bandwidth:",
        report.mesh,
        report.write_level,
        report
            .per_frame
            .iter()
            .find(|r| r.level == report.write_level)
            .map_or(0, |r| r.vertices)
    );
    println!();
    print!("{}", bench_write::writers_table(&report.writers));
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    #[cfg(not(feature = "gl"))]
    if args.gl {
        anyhow::bail!(
            "bench --gl needs the `gl` feature, and this tessella was built without it; rebuild \
             with it (cargo build -p tessella-cli --features gl)"
        );
    }
    if args.json && (args.gpu || args.gl) {
        anyhow::bail!("--json covers the CPU measurements; run --gpu or --gl without --json");
    }
    let mesh: Mesh = match &args.mesh {
        Some(path) => tessella_io::read_mesh(path)?,
        None => samples::icosphere_4k(),
    };
    let name = match &args.mesh {
        Some(path) => path.display().to_string(),
        None => "icosphere-4k".to_string(),
    };
    let repeat = args.repeat.max(1);
    let bandwidth = Bandwidth::measure(repeat);
    if args.bandwidth_only {
        if args.json {
            println!("{}", serde_json::to_string_pretty(&bandwidth)?);
        } else {
            println!("{}", bandwidth_line(&bandwidth));
        }
        return Ok(());
    }
    let one_shot = one_shot(&mesh, &args.levels, repeat, &bandwidth)?;
    let per_frame = bench_frames::roofline(&mesh, &args.levels, repeat, &bandwidth)?;
    let mut deforming = bench_frames::deforming(&name, &mesh, &args.levels, repeat, &bandwidth)?;
    if args.mesh.is_none() {
        let creature = samples::creature();
        deforming.extend(bench_frames::deforming(
            "creature",
            &creature,
            &args.levels,
            repeat,
            &bandwidth,
        )?);
    }
    // Writers: the largest level up to 32 (a few hundred MB at most of files).
    let write_level = args
        .levels
        .iter()
        .copied()
        .filter(|&l| l <= 32)
        .max()
        .unwrap_or(args.levels.iter().copied().min().unwrap_or(1));
    let refined = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, write_level))?.refine();
    let writers = bench_write::writers(&refined, repeat, &bandwidth)?;
    let report = Report {
        mesh: name,
        faces: mesh.face_count(),
        repeat,
        bandwidth,
        one_shot,
        per_frame,
        deforming,
        write_level,
        writers,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print_tables(&report);
    if args.gpu {
        #[cfg(feature = "gpu")]
        gpu_tables(&mesh, args)?;
        #[cfg(not(feature = "gpu"))]
        return Err(super::no_gpu("bench --gpu"));
    }
    #[cfg(feature = "gl")]
    if args.gl {
        super::bench_gl::run(args)?;
    }
    Ok(())
}

/// The GPU measurements, labelled with the adapter (a software adapter's numbers say so).
#[cfg(feature = "gpu")]
fn gpu_tables(mesh: &Mesh, args: &BenchArgs) -> anyhow::Result<()> {
    use tessella_bench::gpu as bench;
    let ctx = super::gpu::render_context()?;
    let label = ctx.adapter_label();
    let repeat = args.repeat.clamp(1, 5) as u32;
    println!();
    println!("GPU compute refinement against the CPU, PN, adapter: {label}");
    println!();
    let rows = bench::refine_throughput(&ctx, mesh, Scheme::Pn, &args.levels, repeat)?;
    print!("{}", bench::refine_table(&rows));
    println!();
    println!("GMR Figure 7: static refined vertex buffer against the instanced pattern, adapter: {label}");
    println!();
    let rows = bench::figure7(&ctx, &bench::Figure7Config::default())?;
    print!("{}", bench::figure7_table(&rows));
    println!();
    println!("Frame time by scheme, instanced pattern level 64, adapter: {label}");
    println!();
    let creature = samples::creature();
    let rows = bench::scheme_frame_times(
        &ctx,
        &creature,
        &[Scheme::Pn, Scheme::Png1],
        64,
        10,
        (512, 512),
    )?;
    print!("{}", bench::scheme_table(&rows));
    println!();
    println!("Levels that change every frame (PN, per-edge levels 1..24 moving each frame): a new plan and renderer per frame against one AdaptiveRenderer; then the draw alone, adapter: {label}");
    println!();
    let rows = bench::changing_levels(&ctx, &samples::icosphere(2), 24.0, 8, (512, 512))?;
    print!("{}", bench::changing_levels_table(&rows));
    Ok(())
}
