//! A skinned glTF character playing its clip, looped by Bevy's `AnimationPlayer`: each frame
//! the plugin poses the coarse mesh with tessella's skinning (every joint influence set, morph
//! weights) and uploads only its control nets.
//!
//! `cargo run --features window --example skinned [-- FILE.glb --clip wave --level 8]`; with
//! `--screenshot OUT.png` it draws headless and exits.

mod showcase;

use bevy::gltf::Gltf;
use bevy::prelude::*;
use showcase::{GltfStage, NewMesh};
use std::path::PathBuf;
use tessella_bevy::tessella_core::Scheme;
use tessella_bevy::{Tessellate, UploadStats};

#[derive(Resource, Clone)]
struct Options {
    file: PathBuf,
    clip: String,
    level: u32,
}

#[derive(Resource)]
struct File(Handle<Gltf>);

fn options(args: Vec<String>) -> Result<Options, String> {
    let mut clip = String::from("wave");
    let shared = showcase::gltf_args(args, "--clip", |value| {
        clip = value;
        Ok(())
    })?;
    Ok(Options {
        file: shared.file,
        clip,
        level: shared.level,
    })
}

fn main() -> AppExit {
    showcase::run("skinned", |args, output| {
        let o = options(args)?;
        let mut app = output.app(
            "tessella: a skinned character",
            showcase::folder_of(&o.file)?,
        )?;
        app.insert_resource(o)
            .add_systems(Startup, setup)
            .add_systems(Update, (tessellate_meshes, play, report_uploads));
        Ok(app)
    })
}

fn setup(mut stage: GltfStage, options: Res<Options>) {
    let file = stage.spawn(&options.file, Vec3::new(0.3, 0.35, 1.0), 3.4);
    // `play` finds the file's clips through it.
    stage.commands.insert_resource(File(file));
}

fn tessellate_meshes(mut commands: Commands, options: Res<Options>, found: Query<Entity, NewMesh>) {
    for entity in &found {
        commands
            .entity(entity)
            .insert(Tessellate::new(Scheme::Pn, options.level));
    }
}

/// Once the file has loaded, its players loop the clip.
fn play(
    mut commands: Commands,
    options: Res<Options>,
    file: Res<File>,
    gltfs: Res<Assets<Gltf>>,
    mut graphs: ResMut<Assets<AnimationGraph>>,
    mut players: Query<(Entity, &mut AnimationPlayer), Without<AnimationGraphHandle>>,
    mut exit: MessageWriter<AppExit>,
) {
    let Some(gltf) = gltfs.get(&file.0) else {
        return;
    };
    for (entity, mut player) in &mut players {
        let clip = match options.clip.parse::<usize>() {
            Ok(i) => gltf.animations.get(i),
            Err(_) => gltf.named_animations.get(options.clip.as_str()),
        };
        let Some(clip) = clip else {
            eprintln!("skinned: the file has no clip {}", options.clip);
            exit.write(AppExit::error());
            return;
        };
        let (graph, node) = AnimationGraph::from_clip(clip.clone());
        commands
            .entity(entity)
            .insert(AnimationGraphHandle(graphs.add(graph)));
        player.play(node).repeat();
    }
}

/// Prints, once a second, the bytes tessella uploaded in the last frame.
fn report_uploads(stats: Res<UploadStats>, time: Res<Time>, mut last: Local<(u64, f32)>) {
    let total = stats.total();
    let now = time.elapsed_secs();
    if now - last.1 >= 1.0 {
        info!(
            "tessella uploaded {} bytes in the last frame",
            total - last.0
        );
        last.1 = now;
    }
    last.0 = total;
}
