//! `tessella samples`: write the bundled sample meshes, and the animated sample as glTF.

use crate::args::SamplesArgs;
use anyhow::Context;
use tessella_core::samples;
use tessella_io::{write_atomic, write_mesh, MeshView, WriteOptions};

/// The animated sample's file: [`samples::animated_creature`] on the creature's icosphere.
pub const ANIMATED: &str = "animated-creature.glb";
/// The sample scene's files ([`tessella_io::sample_scene`]): nodes, materials, a texture,
/// lights, a camera, clips; float and quantised.
pub const SCENE: &str = "scene.glb";
pub const SCENE_QUANTIZED: &str = "scene-quantized.glb";

pub fn run(args: &SamplesArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    for name in samples::NAMES {
        let mesh = samples::by_name(name).expect("every listed sample exists");
        let path = args.output.join(format!("{name}.obj"));
        write_mesh(&path, MeshView::from(&mesh), &WriteOptions::default())?;
        println!(
            "{}: {} vertices, {} triangles",
            path.display(),
            mesh.vertex_count(),
            mesh.face_count()
        );
    }
    let animated = samples::animated_creature(2);
    let path = args.output.join(ANIMATED);
    write_atomic(&path, |out| {
        tessella_io::gltf::write_animated(out, &animated, true)
    })?;
    println!(
        "{}: {} vertices, {} triangles, {} joints, {} clips ({})",
        path.display(),
        animated
            .instances
            .iter()
            .map(|i| i.positions.len())
            .sum::<usize>(),
        animated.triangles.len(),
        animated.skins.iter().map(|s| s.joints.len()).sum::<usize>(),
        animated.clips.len(),
        animated
            .clips
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    for (name, quantized) in [(SCENE, false), (SCENE_QUANTIZED, true)] {
        let path = args.output.join(name);
        let bytes = tessella_io::sample_scene(quantized);
        write_atomic(&path, |out| std::io::Write::write_all(out, &bytes))?;
        println!(
            "{}: the sample scene{}",
            path.display(),
            if quantized { ", quantised" } else { "" }
        );
    }
    Ok(())
}
