//! `tessella demo`: every bundled sample, every scheme, one table.

use crate::args::DemoArgs;
use anyhow::Context;
use std::path::Path;
use std::time::Instant;
use tessella_core::{refine, samples, Mesh, RefineOptions, RefinedMesh, Scheme, Tags};
use tessella_io::{write_mesh, MeshView, WriteOptions};

/// The schemes the demo compares, in its table's order; `info --quality` compares the same.
pub const SCHEMES: [Scheme; 6] = [
    Scheme::Flat,
    Scheme::PHONG,
    Scheme::Pn,
    Scheme::PnAen,
    Scheme::ScalarTagged,
    Scheme::Png1,
];

/// Largest distance between matching vertices of two refinements with the same layout.
fn max_offset(a: &RefinedMesh, b: &RefinedMesh) -> f32 {
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f32::max)
}

pub fn run(args: &DemoArgs) -> anyhow::Result<()> {
    if let Some(dir) = &args.output {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    println!("| sample | scheme | coarse triangles | vertices | triangles | time (ms) | max offset from coarse (% of diagonal) |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for name in samples::NAMES.iter().filter(|n| **n != "icosphere-4k") {
        let mesh: Mesh = samples::by_name(name).expect("listed sample");
        // The flat refinement has the same layout, so vertex i of every scheme sits at the same
        // barycentric point of the same coarse triangle: the offset is how far the curve bulges.
        let flat = refine(&mesh, &RefineOptions::new(Scheme::Flat, args.level))?;
        for scheme in SCHEMES {
            let start = Instant::now();
            let mut options = RefineOptions::new(scheme, args.level);
            if scheme == Scheme::ScalarTagged {
                // Hard edges in the sample become creases, as `tessella refine` does.
                options = options.with_tags(Tags::from_split_normals(&mesh));
            }
            let out = match refine(&mesh, &options) {
                Ok(out) => out,
                Err(e) => {
                    println!(
                        "| {name} | {} | {} | refused: {e} | | | |",
                        scheme.name(),
                        mesh.face_count()
                    );
                    continue;
                }
            };
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let offset = 100.0 * max_offset(&out, &flat) / mesh.diagonal();
            println!(
                "| {name} | {} | {} | {} | {} | {ms:.2} | {offset:.2} |",
                scheme.name(),
                mesh.face_count(),
                out.positions.len(),
                out.triangles.len()
            );
            if let Some(dir) = &args.output {
                let path = dir.join(format!("{name}-{}-level{}.obj", scheme.name(), args.level));
                write_mesh(&path, MeshView::from(&out), &WriteOptions::default())?;
            }
        }
    }
    if let Some(dir) = &args.output {
        pictures(dir, args.level)?;
    }
    Ok(())
}

#[cfg(not(feature = "gpu"))]
fn pictures(_dir: &Path, _level: u32) -> anyhow::Result<()> {
    eprintln!("note: no pictures: {}", super::no_gpu("drawing pictures"));
    Ok(())
}

/// Side-by-side pictures of the samples whose silhouettes show the difference best.
#[cfg(feature = "gpu")]
fn pictures(dir: &Path, level: u32) -> anyhow::Result<()> {
    use tessella_view::{render_compare, save_png, RenderOptions};
    let ctx = match super::gpu::render_context() {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("note: no pictures: {e:#}");
            return Ok(());
        }
    };
    let view = RenderOptions {
        // Four 360-pixel panels and their separators.
        size: (4 * 360 + 3 * 2, 360),
        yaw: 20.0,
        pitch: 10.0,
        ..RenderOptions::default()
    };
    let schemes = [Scheme::Flat, Scheme::PHONG, Scheme::Pn, Scheme::Png1];
    for name in ["creature", "tetrahedron", "torus"] {
        let mesh = samples::by_name(name).expect("listed sample");
        let panels: Vec<_> = schemes
            .iter()
            .map(|&s| (s.name().to_string(), RefineOptions::new(s, level)))
            .collect();
        let picture = render_compare(&ctx, &mesh, &panels, &view)?;
        let path = dir.join(format!("compare-{name}.png"));
        save_png(&picture, &path)?;
        println!("{} ({})", path.display(), ctx.adapter_label());
    }
    Ok(())
}
