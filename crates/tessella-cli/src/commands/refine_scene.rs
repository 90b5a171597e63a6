//! `tessella refine` with glTF in and glTF out: the scene written back refined
//! (`tessella_io::gltf::scene`), every primitive with its own level and material.

use super::refined::Refined;
use crate::args::RefineArgs;
use anyhow::Context;
use std::time::Instant;
use tessella_core::refine::{Levels, Spacing};
use tessella_io::gltf::scene::{
    JointSets, Scene, SceneLevels, SceneOptions, Tangents, MAX_JOINT_SETS,
};
use tessella_io::{Durability, Format};

/// Whether `args` ask for the scene path: glTF in and out, no `--flatten`, no `--clip`.
pub fn applies(args: &RefineArgs) -> bool {
    let gltf = |p: &std::path::Path| matches!(Format::from_path(p), Ok(Format::Gltf | Format::Glb));
    gltf(&args.input) && gltf(&args.output) && !args.flatten && args.pose.clip.is_none()
}

/// Refuses the options that work on one merged mesh only, naming the way out.
fn check(args: &RefineArgs, options: &tessella_core::RefineOptions) -> anyhow::Result<()> {
    let merged_only = [
        (args.lod.lod.is_some(), "--lod"),
        (options.spacing != Spacing::Grid, "--spacing"),
        (
            !matches!(options.levels, Levels::Uniform(x) if x.fract() == 0.0),
            "a fractional --level",
        ),
        (args.displace.is_some(), "--displace"),
        (args.write_origin, "--write-origin"),
        (
            args.tags.file.is_some() || args.tags.crease_angle.is_some(),
            "--tags and --crease-angle",
        ),
        (args.report, "--report"),
        (args.soup, "--soup"),
        (
            !matches!(
                args.backend,
                tessella_core::Backend::Auto | tessella_core::Backend::Cpu
            ),
            "--backend gpu/gl",
        ),
    ];
    if let Some((_, flag)) = merged_only.iter().find(|(on, _)| *on) {
        anyhow::bail!(
            "{flag} works on one merged mesh; a glTF scene is refined primitive by primitive with \
             --level or --max-edge. Add --flatten to merge the scene into one mesh first (its \
             nodes, materials and animations are then dropped)"
        );
    }
    Ok(())
}

/// Reads the scene once, refines it and writes it once.
pub fn refine(
    args: &RefineArgs,
    options: tessella_core::RefineOptions,
    durability: Durability,
) -> anyhow::Result<Refined> {
    check(args, &options)?;
    let levels = match args.max_edge {
        Some(length) => SceneLevels::MaxEdge(length),
        None => SceneLevels::Uniform(options.uniform_grid_level().unwrap_or(1)),
    };
    let start = Instant::now();
    let scene = Scene::read(&args.input)?;
    let tangents = Tangents::parse(&args.tangents)
        .ok_or_else(|| anyhow::anyhow!("--tangents takes recomputed or carried"))?;
    let joint_sets = JointSets::parse(&args.joint_sets).ok_or_else(|| {
        anyhow::anyhow!(
            "--joint-sets takes input or a number of sets from 1 to {MAX_JOINT_SETS}, got {}",
            args.joint_sets
        )
    })?;
    let refined = scene
        .refine(
            &SceneOptions::new(options.clone(), levels)
                .with_tangents(tangents)
                .with_joint_sets(joint_sets),
        )
        .with_context(|| format!("cannot refine {}", args.input.display()))?;
    for warning in refined.write(&args.output, durability)? {
        eprintln!("note: {warning}");
    }
    for (report, (m, p)) in refined.primitives.iter().zip(&refined.which) {
        for note in &report.notes {
            eprintln!("note: mesh {m} primitive {p}: {note}");
        }
    }
    let levels: std::collections::BTreeSet<u32> =
        refined.primitives.iter().map(|r| r.level).collect();
    let levels: Vec<String> = levels.iter().map(u32::to_string).collect();
    let counts = scene.counts();
    Ok(Refined {
        mesh: None,
        what: format!(
            "{}, level {}, {} primitives of {} meshes",
            options.scheme.name(),
            levels.join("/"),
            refined.primitives.len(),
            counts.meshes
        ),
        input_triangles: refined.primitives.iter().map(|r| r.coarse_triangles).sum(),
        vertices: refined.primitives.iter().map(|r| r.vertices as u64).sum(),
        triangles: refined.primitives.iter().map(|r| r.triangles as u64).sum(),
        refine_seconds: start.elapsed().as_secs_f64(),
        streamed: false,
        options,
    })
}
