//! `tessella bench`: the machine's memory bandwidth, then refinement measured against it and
//! against baselines timed in the same run: one-shot refinement on all cores against one core,
//! every scheme refined per frame (the roofline table), a deforming mesh updated per frame
//! against rebuilt per frame, and the file writers. `--json` prints the same numbers as one
//! object. The measurements are tessella-bench's ([`tessella_bench::cpu`], and its `gpu` and
//! `gl` modules for `--gpu` and `--gl`); this command picks them and prints them.

use crate::args::BenchArgs;
use tessella_bench::cpu::{bandwidth_line, Bandwidth, Report};
use tessella_core::{samples, Mesh};

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
    let report = Report::measure(
        name,
        &mesh,
        &args.levels,
        repeat,
        bandwidth,
        args.mesh.is_none(),
    )?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print!("{}", report.tables());
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
    use tessella_core::Scheme;
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
    println!();
    println!("An animated mesh (the animated creature on 5,120 triangles, `wave` clip, PN) on its three paths to the pattern renderer, adapter: {label}");
    println!();
    let poser = tessella_core::animation::Poser::new(samples::animated_creature(4))?;
    let wave = poser.clip_index("wave")?;
    let rows =
        tessella_bench::gpu_animated::animated_paths(&ctx, &poser, wave, &[8, 16], 8, (512, 512))?;
    print!(
        "{}",
        tessella_bench::gpu_animated::animated_paths_table(&rows)
    );
    Ok(())
}
