//! A glTF scene loaded by Bevy's glTF loader, `Tessellate` added to each of its meshes as the
//! scene spawns them: Bevy's PBR, its lights and shadows, on tessella's curved surfaces.
//!
//! `cargo run --features window --example gltf_scene [-- FILE.glb --scheme pn --level 8]`; with
//! `--screenshot OUT.png` it draws headless (no window, no `window` feature needed) and exits.

mod showcase;

use bevy::prelude::*;
use showcase::{GltfStage, NewMesh};
use std::path::PathBuf;
use tessella_bevy::tessella_core::names::parse_name;
use tessella_bevy::tessella_core::Scheme;
use tessella_bevy::Tessellate;

/// The scene's file and how its meshes are tessellated.
#[derive(Resource, Clone)]
struct Options {
    file: PathBuf,
    scheme: Scheme,
    level: u32,
}

fn options(args: Vec<String>) -> Result<Options, String> {
    let mut scheme = Scheme::Pn;
    let shared = showcase::gltf_args(args, "--scheme", |value| {
        scheme = parse_name(&value).map_err(|e| e.to_string())?;
        Ok(())
    })?;
    Ok(Options {
        file: shared.file,
        scheme,
        level: shared.level,
    })
}

fn main() -> AppExit {
    showcase::run("gltf_scene", |args, output| {
        let o = options(args)?;
        let mut app = output.app("tessella: a glTF scene", showcase::folder_of(&o.file)?)?;
        app.insert_resource(o)
            .add_systems(Startup, setup)
            .add_systems(Update, tessellate_scene_meshes);
        Ok(app)
    })
}

fn setup(mut stage: GltfStage, options: Res<Options>) {
    // This example plays no clips: it needs no handle on the file.
    stage.spawn(&options.file, Vec3::new(0.6, 0.45, 1.0), 3.2);
}

/// Every mesh the scene spawns gets `Tessellate`.
fn tessellate_scene_meshes(
    mut commands: Commands,
    options: Res<Options>,
    found: Query<Entity, NewMesh>,
) {
    for entity in &found {
        commands
            .entity(entity)
            .insert(Tessellate::new(options.scheme, options.level));
    }
}
