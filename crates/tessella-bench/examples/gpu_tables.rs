//! Prints the GPU benchmark tables: `cargo run --release -p tessella-bench --example gpu_tables`
//! (`tessella bench --gpu` prints the same tables).

use tessella_bench::gpu::{
    figure7, figure7_table, refine_table, refine_throughput, scheme_frame_times, scheme_table,
    Figure7Config,
};
use tessella_bench::gpu_animated::{animated_paths, animated_paths_table};
use tessella_core::animation::Poser;
use tessella_core::{samples, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext, GpuError};

fn main() {
    let ctx = match GpuContext::new(AdapterChoice::Auto) {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let frames = std::env::var("FRAMES")
        .ok()
        .and_then(|f| f.parse().ok())
        .unwrap_or(5);
    let run = || -> Result<(), GpuError> {
        let mesh = samples::icosphere(2);
        let rows = refine_throughput(&ctx, &mesh, Scheme::Pn, &[4, 16, 64], 3)?;
        println!("{}", refine_table(&rows));
        let config = Figure7Config {
            frames,
            ..Default::default()
        };
        println!("{}", figure7_table(&figure7(&ctx, &config)?));
        let schemes = [Scheme::Pn, Scheme::Png1];
        let rows =
            scheme_frame_times(&ctx, &samples::creature(), &schemes, 64, frames, (512, 512))?;
        println!("{}", scheme_table(&rows));
        let poser = Poser::new(samples::animated_creature(4)).map_err(GpuError::from)?;
        let wave = poser.clip_index("wave").map_err(GpuError::from)?;
        let rows = animated_paths(&ctx, &poser, wave, &[8, 16], frames, (512, 512))?;
        println!("{}", animated_paths_table(&rows));
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
