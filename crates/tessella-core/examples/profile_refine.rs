//! Times the phases of one refinement: `cargo run --release --example profile_refine -p tessella-core [level]`.
use std::time::Instant;
use tessella_core::{samples, RefineOptions, RefinedMesh, Refiner, Scheme};

fn main() {
    let level: u32 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    let mesh = samples::icosphere_4k();
    let t = Instant::now();
    let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, level)).unwrap();
    println!("prepare: {:?}", t.elapsed());
    let mut out = RefinedMesh::default();
    for i in 0..8 {
        let t = Instant::now();
        refiner.refine_into(&mut out, &|_| {});
        let dt = t.elapsed();
        if i > 0 {
            println!(
                "refine: {:?} = {:.1} M vertices/s",
                dt,
                out.positions.len() as f64 / dt.as_secs_f64() / 1e6
            );
        }
    }
}
