//! `tessella bench`: refinement throughput, all cores against one core in the same run.

use crate::args::BenchArgs;
use anyhow::Context;
use std::time::{Duration, Instant};
use tessella_core::{samples, Mesh, RefineOptions, RefinedMesh, Refiner, Scheme};

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

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

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    #[cfg(not(feature = "gl"))]
    if args.gl {
        anyhow::bail!(
            "bench --gl needs the `gl` feature, and this tessella was built without it; rebuild \
             with it (cargo build -p tessella-cli --features gl)"
        );
    }
    let mesh: Mesh = match &args.mesh {
        Some(path) => tessella_io::read_mesh(path)?,
        None => samples::icosphere_4k(),
    };
    let repeat = args.repeat.max(1);
    let threads = rayon::current_num_threads();
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("cannot start a one-thread pool")?;
    println!("CPU refinement, PN, welded, positions + quadratic normals + indices; {} coarse triangles; median of {repeat}", mesh.face_count());
    println!();
    println!("| level | vertices | triangles | prepare (ms) | refine {threads} threads (ms) | M vertices/s | 1 thread (ms) | M vertices/s | speed-up |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &level in &args.levels {
        let options = RefineOptions::new(Scheme::Pn, level);
        let start = Instant::now();
        let refiner = Refiner::new(&mesh, &options)?;
        let prepare = start.elapsed();
        let vertices = refiner.layout().vertex_count;
        let many = time_refine(&refiner, repeat);
        let one = single.install(|| time_refine(&refiner, repeat));
        let rate = |d: Duration| vertices as f64 / d.as_secs_f64() / 1e6;
        println!(
            "| {level} | {vertices} | {} | {:.2} | {:.2} | {:.1} | {:.2} | {:.1} | {:.2}x |",
            refiner.layout().triangle_count,
            prepare.as_secs_f64() * 1e3,
            many.as_secs_f64() * 1e3,
            rate(many),
            one.as_secs_f64() * 1e3,
            rate(one),
            one.as_secs_f64() / many.as_secs_f64()
        );
    }

    // Every scheme at one level, relative to PN measured in the same run.
    let level = 16;
    println!();
    println!("All schemes at level {level}, {threads} threads, relative to PN (prepare = topology + control nets + stencil):");
    println!();
    println!("| scheme | prepare (ms) | refine (ms) | M vertices/s | throughput vs PN |");
    println!("|---|---:|---:|---:|---:|");
    let schemes = [
        Scheme::Pn,
        Scheme::Flat,
        Scheme::PHONG,
        Scheme::PnAen,
        Scheme::ScalarTagged,
        Scheme::Png1,
    ];
    let mut pn_rate = None;
    for scheme in schemes {
        let start = Instant::now();
        let refiner = Refiner::new(&mesh, &RefineOptions::new(scheme, level))?;
        let prepare = start.elapsed();
        let time = time_refine(&refiner, repeat);
        let rate = refiner.layout().vertex_count as f64 / time.as_secs_f64() / 1e6;
        let pn = *pn_rate.get_or_insert(rate);
        println!(
            "| {} | {:.2} | {:.2} | {rate:.1} | {:.2}x |",
            scheme.name(),
            prepare.as_secs_f64() * 1e3,
            time.as_secs_f64() * 1e3,
            rate / pn
        );
    }
    let fill = super::bench_frames::fill_rate(repeat);
    let name = match &args.mesh {
        Some(path) => path.display().to_string(),
        None => "icosphere-4k".to_string(),
    };
    super::bench_frames::table(&name, &mesh, &args.levels, repeat, fill)?;
    if args.mesh.is_none() {
        super::bench_frames::table("creature", &samples::creature(), &args.levels, repeat, fill)?;
    }
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
    use tessella_view::bench;
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
    Ok(())
}
