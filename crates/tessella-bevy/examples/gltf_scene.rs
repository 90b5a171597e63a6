//! A glTF scene loaded by Bevy's glTF loader, `Tessellate` added to each of its meshes as the
//! scene spawns them: Bevy's PBR, its lights and shadows, on tessella's curved surfaces.
//!
//! `cargo run --features window --example gltf_scene [-- FILE.glb --scheme pn --level 8]`; with
//! `--screenshot OUT.png` it draws headless (no window, no `window` feature needed) and exits.

mod showcase;

use bevy::gltf::GltfAssetLabel;
use bevy::prelude::*;
use bevy::world_serialization::WorldAssetRoot;
use showcase::{orbit, stage, NewMesh, Output};
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
    let samples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    let mut o = Options {
        file: samples.join("animated-creature.glb"),
        scheme: Scheme::Pn,
        level: 8,
    };
    let mut it = args.into_iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--scheme" => o.scheme = parse_name(&value()?).map_err(|e| e.to_string())?,
            "--level" => o.level = value()?.parse().map_err(|e| format!("--level: {e}"))?,
            s if !s.starts_with('-') => o.file = PathBuf::from(s),
            s => return Err(format!("unknown argument {s}")),
        }
    }
    Ok(o)
}

fn main() -> AppExit {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let built = Output::take(&mut args).and_then(|output| {
        let o = options(args)?;
        let file = o
            .file
            .canonicalize()
            .map_err(|e| format!("{}: {e}", o.file.display()))?;
        let folder = file
            .parent()
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        let mut app = output.app("tessella: a glTF scene", folder)?;
        app.insert_resource(o)
            .add_systems(Startup, setup)
            .add_systems(Update, tessellate_scene_meshes);
        Ok(app)
    });
    match built {
        Ok(mut app) => app.run(),
        Err(e) => {
            eprintln!("gltf_scene: {e}");
            AppExit::error()
        }
    }
}

fn setup(
    mut commands: Commands,
    options: Res<Options>,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let name = options
        .file
        .file_name()
        .map(|n| n.to_string_lossy().to_string());
    let scene = GltfAssetLabel::Scene(0).from_asset(name.unwrap_or_default());
    commands.spawn(WorldAssetRoot(assets.load(scene)));
    // The stage is framed on the file's mesh as tessella reads it.
    let (lo, hi) = match tessella_io::read_mesh(&options.file) {
        Ok(m) => m.bounds(),
        Err(_) => ([-1.0; 3], [1.0; 3]),
    };
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let camera = orbit(bounds, Vec3::new(0.6, 0.45, 1.0), 3.2);
    stage(&mut commands, &mut meshes, &mut materials, bounds, camera);
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
