//! The baselines `tessella batch` is measured against (docs/performance.md): the same meshes
//! refined in one process, one file per rayon thread as the batch runs them.
//!
//!     cargo run --release -p tessella-cli --example batch_baseline -- LEVEL [--write DIR] FILES...
//!
//! Without `--write`: every file is read first (untimed), then all are refined in memory,
//! no files written. With `--write DIR`: each file is read, refined in memory and written
//! to DIR by `tessella_io::write_mesh`, all timed: the batch's work without its scheduling,
//! skipping, manifest and streaming.

use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tessella_core::{RefineOptions, Scheme};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let level: u32 = args
        .first()
        .ok_or("usage: LEVEL [--write DIR] FILES...")?
        .parse()?;
    args.remove(0);
    let write: Option<PathBuf> = match args.first().map(String::as_str) {
        Some("--write") => {
            let dir = PathBuf::from(args.get(1).ok_or("--write needs a folder")?);
            args.drain(..2);
            std::fs::create_dir_all(&dir)?;
            Some(dir)
        }
        _ => None,
    };
    let options = RefineOptions::new(Scheme::Pn, level);
    let start;
    let triangles: usize = match &write {
        None => {
            let meshes = args
                .iter()
                .map(|p| tessella_io::read_mesh(Path::new(p)))
                .collect::<Result<Vec<_>, _>>()?;
            start = Instant::now();
            meshes
                .par_iter()
                .map(|m| tessella_core::refine(m, &options).map(|r| r.triangles.len()))
                .collect::<Result<Vec<_>, _>>()?
                .into_iter()
                .sum()
        }
        Some(dir) => {
            start = Instant::now();
            args.par_iter()
                .map(
                    |p| -> Result<usize, Box<dyn std::error::Error + Send + Sync>> {
                        let path = Path::new(p);
                        let mesh = tessella_io::read_mesh(path)?;
                        let refined = tessella_core::refine(&mesh, &options)?;
                        let out = dir.join(path.file_name().ok_or("a file name")?);
                        tessella_io::write_mesh(&out, (&refined).into(), &Default::default())?;
                        Ok(refined.triangles.len())
                    },
                )
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| e.to_string())?
                .into_iter()
                .sum()
        }
    };
    println!(
        "{} meshes, {triangles} triangles in {:.3} s",
        args.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
