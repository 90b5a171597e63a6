//! What the showcase examples (`gltf_scene`, `skinned`, `lod_scene`) share: where they draw (a
//! window, built with the `window` feature; or, with `--screenshot OUT.png`, no window at all:
//! the camera draws into an image, saved once the scene has been tessellated and drawn a few
//! frames, and the app exits) and their stage (a light with shadows, a ground, a camera).
//! `view` takes only the ground's look from here ([`ground_plane`]).
//!
//! Flags: `--screenshot OUT.png` (headless), `--size WxH`, `--frames N` (exit N frames after the
//! first tessellated entity appears; in a window, `--window-shot OUT.png` saves that frame).

// Each example compiles this module and uses part of it.
#![allow(dead_code)]

use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::camera::RenderTarget;
use bevy::ecs::system::SystemParam;
use bevy::gltf::Gltf;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::window::screenshot::{save_to_disk, Screenshot, ScreenshotCaptured};
use bevy::render::view::Tonemapping;
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use std::path::{Path, PathBuf};
use std::time::Duration;
use tessella_bevy::{Patch, Patches, TessellaPlugin, Tessellate};

/// Runs the app `build` makes from the example's own arguments (the output flags taken out) and
/// `Output`; an error is printed with the example's `name`.
pub fn run(name: &str, build: impl FnOnce(Vec<String>, Output) -> Result<App, String>) -> AppExit {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    match Output::take(&mut args).and_then(|output| build(args, output)) {
        Ok(mut app) => app.run(),
        Err(e) => {
            eprintln!("{name}: {e}");
            AppExit::error()
        }
    }
}

/// The arguments the glTF examples (`gltf_scene`, `skinned`) share.
pub struct GltfArgs {
    /// A bare argument; the animated creature by default.
    pub file: PathBuf,
    /// `--level N`; 8 by default.
    pub level: u32,
}

/// Reads a glTF example's own arguments: the shared ones ([`GltfArgs`]), and the example's own
/// flag `own`, whose values go to `set` in the order given; any other flag is an error.
pub fn gltf_args(
    args: Vec<String>,
    own: &str,
    mut set: impl FnMut(String) -> Result<(), String>,
) -> Result<GltfArgs, String> {
    let samples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    let mut shared = GltfArgs {
        file: samples.join("animated-creature.glb"),
        level: 8,
    };
    let mut it = args.into_iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--level" => shared.level = value()?.parse().map_err(|e| format!("--level: {e}"))?,
            s if s == own => set(value()?)?,
            s if !s.starts_with('-') => shared.file = PathBuf::from(s),
            s => return Err(format!("unknown argument {s}")),
        }
    }
    Ok(shared)
}

/// The folder a file lies in (Bevy reads assets below one folder).
pub fn folder_of(file: &Path) -> Result<String, String> {
    let file = file
        .canonicalize()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    Ok(file
        .parent()
        .map(|p| p.display().to_string())
        .unwrap_or_default())
}

/// Spawns scene 0 of the glTF `file` (read from the asset folder, [`folder_of`]) and returns
/// the file's handle (its clips), and the box of its mesh as tessella reads it (to frame it).
pub fn spawn_gltf(
    commands: &mut Commands,
    assets: &AssetServer,
    file: &Path,
) -> (Handle<Gltf>, (Vec3, Vec3)) {
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let scene = bevy::gltf::GltfAssetLabel::Scene(0).from_asset(name.clone());
    commands.spawn(bevy::world_serialization::WorldAssetRoot(
        assets.load(scene),
    ));
    let (lo, hi) = match tessella_io::read_mesh(file) {
        Ok(m) => m.bounds(),
        Err(_) => ([-1.0; 3], [1.0; 3]),
    };
    (assets.load(name), (Vec3::from(lo), Vec3::from(hi)))
}

/// What a startup system needs to put a glTF scene on the stage ([`GltfStage::spawn`]).
#[derive(SystemParam)]
pub struct GltfStage<'w, 's> {
    pub commands: Commands<'w, 's>,
    assets: Res<'w, AssetServer>,
    meshes: ResMut<'w, Assets<Mesh>>,
    materials: ResMut<'w, Assets<StandardMaterial>>,
}

impl GltfStage<'_, '_> {
    /// Spawns the glTF `file` ([`spawn_gltf`]) on the [`stage`], the camera looking at it from
    /// `direction`, `distance` radii away ([`orbit`]); returns the file's handle (its clips).
    pub fn spawn(&mut self, file: &Path, direction: Vec3, distance: f32) -> Handle<Gltf> {
        let (gltf, bounds) = spawn_gltf(&mut self.commands, &self.assets, file);
        let camera = orbit(bounds, direction, distance);
        stage(
            &mut self.commands,
            &mut self.meshes,
            &mut self.materials,
            bounds,
            camera,
        );
        gltf
    }
}

/// How an example shows its scene.
#[derive(Resource, Clone, Debug)]
pub struct Output {
    /// Headless: the picture's file.
    pub screenshot: Option<PathBuf>,
    /// In a window: the last frame's file.
    pub window_shot: Option<PathBuf>,
    pub size: UVec2,
    /// Exit after this many frames.
    pub frames: Option<u32>,
}

impl Output {
    /// Takes the output flags out of `args`, leaving the example's own.
    pub fn take(args: &mut Vec<String>) -> Result<Output, String> {
        let mut out = Output {
            screenshot: None,
            window_shot: None,
            size: UVec2::new(640, 480),
            frames: None,
        };
        let mut rest = Vec::new();
        let mut it = std::mem::take(args).into_iter();
        while let Some(a) = it.next() {
            let mut value = || it.next().ok_or(format!("{a} needs a value"));
            match a.as_str() {
                "--screenshot" => out.screenshot = Some(PathBuf::from(value()?)),
                "--window-shot" => out.window_shot = Some(PathBuf::from(value()?)),
                "--frames" => {
                    out.frames = Some(value()?.parse().map_err(|e| format!("--frames: {e}"))?)
                }
                "--size" => {
                    let v = value()?;
                    let (w, h) = v.split_once('x').ok_or(format!("--size {v}: want WxH"))?;
                    let num = |s: &str| s.parse::<u32>().map_err(|e| format!("--size: {e}"));
                    out.size = UVec2::new(num(w)?, num(h)?);
                }
                _ => rest.push(a),
            }
        }
        *args = rest;
        Ok(out)
    }

    /// The app: Bevy's default plugins set for a window or for no window, assets read from
    /// `assets`, the tessella plugin, and the systems that capture or count frames.
    pub fn app(self, title: &str, assets: String) -> Result<App, String> {
        let mut app = App::new();
        let render = RenderPlugin {
            // A pipeline is ready the frame it is first asked for.
            synchronous_pipeline_compilation: self.screenshot.is_some(),
            ..default()
        };
        let asset = AssetPlugin {
            file_path: assets,
            ..default()
        };
        if self.screenshot.is_some() {
            app.add_plugins(
                DefaultPlugins
                    .set(WindowPlugin {
                        primary_window: None,
                        exit_condition: ExitCondition::DontExit,
                        ..default()
                    })
                    .set(render)
                    .set(asset)
                    .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>(),
            )
            .add_plugins(ScheduleRunnerPlugin::run_loop(Duration::ZERO))
            .add_systems(PostStartup, draw_into_image)
            .add_systems(Update, capture_image);
        } else {
            window_plugins(&mut app, title, self.size, render, asset)?;
            app.add_systems(Update, count_window_frames);
        }
        app.add_systems(Update, exit_on_failed_load)
            .insert_resource(self)
            .insert_resource(Frames::default())
            .insert_resource(ClearColor(Color::srgb(0.93, 0.94, 0.96)))
            .add_plugins(TessellaPlugin);
        Ok(app)
    }
}

#[cfg(feature = "window")]
fn window_plugins(
    app: &mut App,
    title: &str,
    size: UVec2,
    render: RenderPlugin,
    asset: AssetPlugin,
) -> Result<(), String> {
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: title.into(),
                    resolution: (size.x, size.y).into(),
                    ..default()
                }),
                ..default()
            })
            .set(render)
            .set(asset),
    );
    Ok(())
}

#[cfg(not(feature = "window"))]
fn window_plugins(
    _app: &mut App,
    _title: &str,
    _size: UVec2,
    _render: RenderPlugin,
    _asset: AssetPlugin,
) -> Result<(), String> {
    Err("built without a window: add `--features window`, or pass --screenshot OUT.png".into())
}

/// Frames drawn, and since when the scene has been tessellated.
#[derive(Resource, Default)]
struct Frames {
    drawn: u32,
    tessellated_since: Option<u32>,
    pending: bool,
}

/// Headless: every 3D camera draws into one image of the asked size.
fn draw_into_image(
    mut commands: Commands,
    output: Res<Output>,
    cameras: Query<Entity, With<Camera3d>>,
    mut images: ResMut<Assets<Image>>,
) {
    let mut target = Image::new_target_texture(
        output.size.x,
        output.size.y,
        TextureFormat::Rgba8UnormSrgb,
        None,
    );
    target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = images.add(target);
    for camera in &cameras {
        commands
            .entity(camera)
            .insert(RenderTarget::Image(target.clone().into()));
    }
    commands.insert_resource(CaptureTarget(target));
}

#[derive(Resource)]
struct CaptureTarget(Handle<Image>);

/// Frames drawn after the scene's first tessellated entity before the picture.
const SETTLE_FRAMES: u32 = 5;

/// Headless: once something is tessellated and a few frames have been drawn (or at
/// `--frames`), saves the image and exits.
fn capture_image(
    mut commands: Commands,
    mut frames: ResMut<Frames>,
    output: Res<Output>,
    target: Option<Res<CaptureTarget>>,
    tessellated: Query<(), With<Patches>>,
    mut exit: MessageWriter<AppExit>,
) {
    frames.drawn += 1;
    if frames.tessellated_since.is_none() && !tessellated.is_empty() {
        frames.tessellated_since = Some(frames.drawn);
    }
    let settled = frames
        .tessellated_since
        .is_some_and(|t| frames.drawn >= t + SETTLE_FRAMES);
    let forced = output.frames.is_some_and(|n| frames.drawn >= n);
    if frames.drawn > 600 {
        eprintln!("nothing was tessellated in 600 frames");
        exit.write(AppExit::error());
        return;
    }
    let (Some(target), Some(path)) = (target, output.screenshot.clone()) else {
        return;
    };
    if frames.pending || !(settled || forced) {
        return;
    }
    frames.pending = true;
    commands.spawn(Screenshot::image(target.0.clone())).observe(
        move |captured: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
            let saved = captured
                .image
                .clone()
                .try_into_dynamic()
                .map_err(|e| e.to_string())
                .and_then(|d| d.to_rgba8().save(&path).map_err(|e| e.to_string()));
            match saved {
                Ok(()) => {
                    eprintln!("wrote {}", path.display());
                    exit.write(AppExit::Success);
                }
                Err(e) => {
                    eprintln!("cannot write {}: {e}", path.display());
                    exit.write(AppExit::error());
                }
            }
        },
    );
}

/// In a window: exits `--frames` frames after the first tessellated entity appeared (the
/// scene loads and its pipelines compile in the background first), saving the window first
/// with `--window-shot`.
fn count_window_frames(
    mut commands: Commands,
    mut frames: ResMut<Frames>,
    output: Res<Output>,
    tessellated: Query<(), With<Patches>>,
    mut exit: MessageWriter<AppExit>,
) {
    frames.drawn += 1;
    if frames.tessellated_since.is_none() && !tessellated.is_empty() {
        frames.tessellated_since = Some(frames.drawn);
    }
    let (Some(n), Some(since)) = (output.frames, frames.tessellated_since) else {
        return;
    };
    let d = frames.drawn - since;
    match &output.window_shot {
        Some(path) if d == n => {
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path.clone()));
        }
        // A few frames for the screenshot to be written.
        Some(_) if d >= n + 10 => {
            exit.write(AppExit::Success);
        }
        None if d >= n => {
            exit.write(AppExit::Success);
        }
        _ => {}
    }
}

/// A file that fails to load (the glTF, one of its images) ends the app with an error: a
/// blank picture and exit 0 would hide it.
pub fn exit_on_failed_load(
    mut failed: MessageReader<bevy::asset::UntypedAssetLoadFailedEvent>,
    mut exit: MessageWriter<AppExit>,
) {
    for e in failed.read() {
        eprintln!("cannot load {}: {}", e.path, e.error);
        exit.write(AppExit::error());
    }
}

/// The ground plane (not tessellated).
#[derive(Component)]
pub struct Ground;

/// A mesh entity a scene spawned that is not tessellated yet (not the ground, not one of the
/// plugin's patches).
pub type NewMesh = (
    With<Mesh3d>,
    Without<Tessellate>,
    Without<Patch>,
    Without<Ground>,
);

/// A subject's box, `lo..hi`, and the camera looking at its centre from `direction`,
/// `distance` radii away.
pub fn orbit((lo, hi): (Vec3, Vec3), direction: Vec3, distance: f32) -> (Vec3, Vec3) {
    let center = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    (center + direction.normalize() * radius * distance, center)
}

/// A light with shadows from above left, a ground under the subjects' box `lo..hi`, and a
/// camera at `eye` looking at `target`.
pub fn stage(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    (lo, hi): (Vec3, Vec3),
    (eye, target): (Vec3, Vec3),
) {
    let center = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let size = radius * 12.0;
    commands.spawn((
        ground_plane(meshes, materials, size),
        Transform::from_xyz(center.x, lo.y - 0.01 * radius, center.z),
        Ground,
    ));
    commands.spawn((
        DirectionalLight {
            shadow_maps_enabled: true,
            illuminance: 3000.0,
            ..default()
        },
        Transform::from_xyz(-1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.insert_resource(GlobalAmbientLight {
        brightness: 400.0,
        ..default()
    });
    commands.spawn((
        Camera3d::default(),
        // Bevy's default tonemapper needs the `tonemapping_luts` feature (it draws magenta
        // without it).
        Tonemapping::None,
        Transform::from_translation(eye).looking_at(target, Vec3::Y),
    ));
}

/// The ground's mesh and material: a plane `size` wide facing up, matte and warm (the tests
/// tell the subjects from the ground by its colour, red above blue).
pub fn ground_plane(
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    size: f32,
) -> (Mesh3d, MeshMaterial3d<StandardMaterial>) {
    (
        Mesh3d(meshes.add(Plane3d::new(Vec3::Y, Vec2::splat(size * 0.5)))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb_u8(200, 190, 170),
            perceptual_roughness: 1.0,
            ..default()
        })),
    )
}
