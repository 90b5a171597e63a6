//! `tessella pattern`: a refinement pattern (the uniform grid, or the GPU tessellator's pattern
//! for given levels) as JSON, or drawn as SVG.

use crate::args::PatternArgs;
use anyhow::{bail, Context};
use serde::Serialize;
use std::io::Write;
use std::path::Path;
use tessella_core::tessellator::{self, Partitioning, TessLevels};
use tessella_core::Pattern;

use super::pattern_svg::{self, Built};

/// The largest level printed: 4096 is 8.4 million points, already a 300 MB JSON file.
const MAX_LEVEL: u32 = 4096;

#[derive(Serialize)]
struct PatternJson<'a> {
    level: u32,
    /// Barycentric (l1, l2, l3) of each point, weights of the coarse corners P1, P2, P3.
    points: &'a [[f64; 3]],
    /// Small triangles, counter-clockwise like the coarse triangle.
    triangles: &'a [[u32; 3]],
    /// Tessellator spacings: the spacing, and the levels after clamping and rounding (absent
    /// when the patch is culled).
    #[serde(skip_serializing_if = "Option::is_none")]
    spacing: Option<Partitioning>,
    #[serde(skip_serializing_if = "Option::is_none")]
    levels: Option<TessLevels>,
    #[serde(skip_serializing_if = "Option::is_none")]
    culled: Option<bool>,
}

pub fn run(args: &PatternArgs) -> anyhow::Result<()> {
    let built = build(args)?;
    if let (Some(requested), None) = (built.requested, built.processed) {
        eprintln!(
            "note: outer levels {:?}: a level <= 0 or NaN culls the patch, so the pattern is \
             empty (the GPU draws nothing)",
            requested.outer
        );
    }
    let p = &built.pattern;
    let json = PatternJson {
        level: p.level,
        points: &p.points,
        triangles: &p.triangles,
        spacing: built.spacing,
        levels: built.processed.map(|l| l.levels),
        culled: built.spacing.map(|_| built.processed.is_none()),
    };
    if let Some(svg) = &args.svg {
        write_svg(svg, &built)?;
    }
    match &args.output {
        Some(path) if is_svg(path) => write_svg(path, &built)?,
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

fn is_svg(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

fn write_svg(path: &Path, built: &Built) -> anyhow::Result<()> {
    let text = pattern_svg::draw(built).context("formatting the SVG drawing")?;
    tessella_io::write_atomic(path, |out| out.write_all(text.as_bytes()))
        .with_context(|| format!("writing the drawing {}", path.display()))
}

/// The pattern the arguments ask for.
fn build(args: &PatternArgs) -> anyhow::Result<Built> {
    let spacing = match args.spacing.tessellator() {
        None => return build_grid(args),
        Some(spacing) => spacing,
    };
    let level = args.level.map(|l| l as f32);
    let Some(inner) = args.inner.or(level) else {
        bail!("give the tessellator levels: --level F, or --inner F and --outer A,B,C");
    };
    let outer = match (args.outer.as_slice(), level) {
        (&[a, b, c], _) => [a, b, c],
        ([], Some(l)) => [l; 3],
        ([], None) => bail!("give the outer levels: --outer A,B,C or --level F"),
        (other, _) => bail!(
            "--outer takes three levels A,B,C (edges l1 = 0, l2 = 0, l3 = 0), not {}",
            other.len()
        ),
    };
    let requested = TessLevels { inner, outer };
    Ok(Built {
        pattern: tessellator::tessellate(spacing, requested),
        spacing: Some(spacing),
        processed: tessellator::process_levels(spacing, requested),
        requested: Some(requested),
    })
}

fn build_grid(args: &PatternArgs) -> anyhow::Result<Built> {
    if args.inner.is_some() || !args.outer.is_empty() {
        bail!(
            "--inner and --outer are tessellator levels; use --spacing equal, fractional-odd \
             or fractional-even"
        );
    }
    let Some(level) = args.level else {
        bail!("give the level: --level N (segments per edge)");
    };
    if level.fract() != 0.0 || !level.is_finite() {
        bail!(
            "grid levels are whole numbers of segments per edge, not {level}; fractional levels \
             need --spacing fractional-odd or fractional-even"
        );
    }
    if level < 1.0 {
        bail!("level {level} is not a pattern; the level is the number of segments per edge, 1 or more");
    }
    if level > MAX_LEVEL as f64 {
        bail!("level {level} is too large to print (at most {MAX_LEVEL})");
    }
    Ok(Built {
        pattern: Pattern::uniform(level as u32),
        spacing: None,
        processed: None,
        requested: None,
    })
}
