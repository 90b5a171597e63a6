//! `tessella pattern`: the refinement pattern as JSON.

use crate::args::PatternArgs;
use anyhow::bail;
use serde::Serialize;
use std::io::Write;
use tessella_core::Pattern;

/// The largest level printed: 4096 is 8.4 million points, already a 300 MB JSON file.
const MAX_LEVEL: u32 = 4096;

#[derive(Serialize)]
struct PatternJson<'a> {
    level: u32,
    /// Barycentric (l1, l2, l3) of each point, weights of the coarse corners P1, P2, P3.
    points: &'a [[f64; 3]],
    /// Small triangles, counter-clockwise like the coarse triangle.
    triangles: &'a [[u32; 3]],
}

pub fn run(args: &PatternArgs) -> anyhow::Result<()> {
    if args.level == 0 {
        bail!("level 0 is not a pattern; the level is the number of segments per edge, 1 or more");
    }
    if args.level > MAX_LEVEL {
        bail!(
            "level {} is too large to print (at most {MAX_LEVEL})",
            args.level
        );
    }
    let pattern = Pattern::uniform(args.level);
    let json = PatternJson {
        level: pattern.level,
        points: &pattern.points,
        triangles: &pattern.triangles,
    };
    match &args.output {
        Some(path) => tessella_io::write_atomic(path, |out| {
            serde_json::to_writer(&mut *out, &json)?;
            writeln!(out)
        })?,
        None => {
            let mut out = std::io::stdout().lock();
            serde_json::to_writer(&mut out, &json)?;
            writeln!(out)?;
        }
    }
    Ok(())
}
