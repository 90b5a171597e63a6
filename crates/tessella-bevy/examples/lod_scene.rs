//! Screen-space LOD: sixteen creatures in a row going away from the camera, each with
//! `Tessellate::lod(Pn, screen:6, fractional-odd)`: per-edge levels from Bevy's camera every
//! frame, fine near the camera and coarse far away, crack-free.
//!
//! `cargo run --features window --example lod_scene`; with `--screenshot OUT.png` it draws
//! headless and exits, printing the triangles drawn.

mod showcase;

use bevy::prelude::*;
use showcase::stage;
use std::path::PathBuf;
use tessella_bevy::tessella_core::refine::{Camera as LodCamera, Lod, Spacing};
use tessella_bevy::tessella_core::Scheme;
use tessella_bevy::{to_bevy_mesh, LodLevels, TessellaSystems, Tessellate};

fn main() -> AppExit {
    let samples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    showcase::run("lod_scene", |args, output| {
        if let Some(a) = args.first() {
            return Err(format!("unknown argument {a}"));
        }
        let mut app = output.app("tessella: screen-space LOD", samples.display().to_string())?;
        app.add_systems(Startup, setup)
            // After tessella's systems: this frame's levels.
            .add_systems(PostUpdate, report_triangles.after(TessellaSystems))
            .add_systems(Last, report_on_exit);
        Ok(app)
    })
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples/creature.obj");
    let coarse = match tessella_io::read_mesh(&file) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("lod_scene: {}: {e}", file.display());
            return;
        }
    };
    let (lo, hi) = coarse.bounds();
    let (lo, hi) = (Vec3::from(lo), Vec3::from(hi));
    let step = (hi - lo).length();
    let mesh = meshes.add(to_bevy_mesh(&coarse));
    let material = materials.add(StandardMaterial {
        base_color: Color::srgb_u8(120, 160, 215),
        perceptual_roughness: 0.6,
        ..default()
    });
    // The screen LOD's camera and size are Bevy's; these stand in until the first frame.
    let lod = Lod::Screen {
        pixels: 6.0,
        camera: LodCamera {
            eye: [0.0, 0.0, 1.0],
            target: [0.0; 3],
            fov_y_deg: 45.0,
        },
        size: [1, 1],
    };
    for i in 0..16 {
        let x = if i % 2 == 0 { -0.6 } else { 0.6 } * step;
        commands.spawn((
            Mesh3d(mesh.clone()),
            MeshMaterial3d(material.clone()),
            Transform::from_xyz(x, 0.0, -(i as f32) * step),
            Tessellate::lod(Scheme::Pn, lod.clone(), Spacing::FractionalOdd),
        ));
    }
    // The row from the camera's feet into the distance.
    let far = Vec3::new(0.0, 0.0, -15.0 * step);
    let eye = Vec3::new(0.0, 0.6 * step, 1.6 * step);
    let target = Vec3::new(0.0, 0.0, -3.0 * step);
    stage(
        &mut commands,
        &mut meshes,
        &mut materials,
        (lo.min(far + lo) - Vec3::X * step, hi + Vec3::X * step),
        (eye, target),
    );
}

/// Logs the triangles drawn whenever they change.
fn report_triangles(levels: Query<&LodLevels>, mut last: Local<u64>) {
    let total: u64 = levels.iter().map(|l| l.triangles).sum();
    if total != *last {
        info!("{total} triangles");
        *last = total;
    }
}

fn report_on_exit(levels: Query<&LodLevels>, mut exits: MessageReader<AppExit>) {
    if exits.read().next().is_some() {
        let per: Vec<u64> = levels.iter().map(|l| l.triangles).collect();
        println!("{{\"triangles\":{per:?}}}");
    }
}
