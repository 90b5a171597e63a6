//! The baseline `tessella batch` is measured against (docs/performance.md): the same meshes
//! refined in one process without files. Reads every mesh file named on the command line
//! first (untimed), then refines them all in memory, one file per rayon thread as the batch
//! does, and prints the seconds.
//!
//!     cargo run --release -p tessella-cli --example batch_baseline -- LEVEL FILES...

use rayon::prelude::*;
use std::time::Instant;
use tessella_core::{RefineOptions, Scheme};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let level: u32 = args.first().ok_or("usage: LEVEL FILES...")?.parse()?;
    let meshes = args[1..]
        .iter()
        .map(|p| tessella_io::read_mesh(std::path::Path::new(p)))
        .collect::<Result<Vec<_>, _>>()?;
    let options = RefineOptions::new(Scheme::Pn, level);
    let start = Instant::now();
    let triangles: usize = meshes
        .par_iter()
        .map(|m| tessella_core::refine(m, &options).map(|r| r.triangles.len()))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .sum();
    println!(
        "{} meshes, {triangles} triangles in {:.3} s",
        meshes.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
