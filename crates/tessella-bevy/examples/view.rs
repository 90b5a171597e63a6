//! A mesh file drawn by Bevy with `Tessellate` (or without, `--plain`), framed by the camera
//! `tessella render` uses (crates/tessella-view/src/camera.rs), written to a PNG headless:
//!
//! `cargo run --example view -- FILE --scheme S --level L --yaw Y --pitch P --zoom Z
//!  --size WxH --screenshot OUT.png [--plain]`
//!
//! No window: the camera renders into an image, and Bevy's `Screenshot` of that image is
//! saved once two successive captures agree (pipelines compile synchronously, so the picture
//! settles within a few frames), then the app exits.

use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::window::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::view::{Msaa, Tonemapping};
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use std::path::PathBuf;
use std::time::Duration;
use tessella_bevy::tessella_core::names::parse_name;
use tessella_bevy::tessella_core::Scheme;
use tessella_bevy::{to_bevy_mesh, TessellaPlugin, Tessellate};

/// `tessella render`'s vertical field of view (tessella-view's `FOV_Y_DEGREES`).
const FOV_Y_DEGREES: f32 = 30.0;

#[derive(Resource, Clone, Debug)]
struct Args {
    input: PathBuf,
    scheme: Scheme,
    level: u32,
    alpha: f32,
    yaw: f32,
    pitch: f32,
    zoom: f32,
    size: (u32, u32),
    screenshot: PathBuf,
    plain: bool,
    /// After the picture: remove `Tessellate` and write the plain mesh's picture here.
    then_plain: Option<PathBuf>,
    /// Frame the camera on this file's mesh instead of FILE's (to view an offline-refined
    /// mesh with the camera its coarse mesh gets).
    frame: Option<PathBuf>,
    /// A ground plane under the mesh, to receive its shadow.
    ground: bool,
    /// The light casts no shadows.
    no_shadows: bool,
    /// After the picture: draw this many frames more, each waited for on the GPU, and print
    /// their mean time as one JSON line.
    frames: u32,
    /// Frames drawn before the first capture.
    warmup: u32,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        input: PathBuf::new(),
        scheme: Scheme::Pn,
        level: 16,
        alpha: 0.75,
        yaw: 30.0,
        pitch: 20.0,
        zoom: 1.0,
        size: (512, 512),
        screenshot: PathBuf::from("view.png"),
        plain: false,
        then_plain: None,
        frame: None,
        ground: false,
        no_shadows: false,
        frames: 0,
        warmup: 3,
    };
    let mut it = std::env::args().skip(1);
    let mut input = None;
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        let num = |s: String| s.parse::<f32>().map_err(|e| format!("{a}: {e}"));
        match a.as_str() {
            "--scheme" => args.scheme = parse_name(&value()?).map_err(|e| e.to_string())?,
            "--level" => args.level = value()?.parse().map_err(|e| format!("--level: {e}"))?,
            "--alpha" => args.alpha = num(value()?)?,
            "--yaw" => args.yaw = num(value()?)?,
            "--pitch" => args.pitch = num(value()?)?,
            "--zoom" => args.zoom = num(value()?)?,
            "--warmup" => args.warmup = value()?.parse().map_err(|e| format!("--warmup: {e}"))?,
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').ok_or(format!("--size {v}: want WxH"))?;
                args.size = (
                    w.parse().map_err(|e| format!("--size: {e}"))?,
                    h.parse().map_err(|e| format!("--size: {e}"))?,
                );
            }
            "--screenshot" => args.screenshot = PathBuf::from(value()?),
            "--plain" => args.plain = true,
            "--frame" => args.frame = Some(PathBuf::from(value()?)),
            "--ground" => args.ground = true,
            "--no-shadows" => args.no_shadows = true,
            "--frames" => args.frames = value()?.parse().map_err(|e| format!("--frames: {e}"))?,
            "--then-plain" => args.then_plain = Some(PathBuf::from(value()?)),
            s if !s.starts_with('-') && input.is_none() => input = Some(PathBuf::from(s)),
            s => return Err(format!("unknown argument {s}")),
        }
    }
    args.input = input.ok_or("usage: view FILE [--scheme S --level L ...]")?;
    args.scheme = args.scheme.with_alpha(args.alpha);
    Ok(args)
}

fn main() -> AppExit {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("view: {e}");
            return AppExit::error();
        }
    };
    App::new()
        .insert_resource(args)
        .insert_resource(ClearColor(Color::WHITE))
        .add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    ..default()
                })
                .set(RenderPlugin {
                    // A pipeline is ready the frame it is first asked for, so the picture
                    // settles in a few frames.
                    synchronous_pipeline_compilation: true,
                    ..default()
                })
                .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>(),
        )
        // No winit: this loop runs the frames.
        .add_plugins(ScheduleRunnerPlugin::run_loop(Duration::ZERO))
        .add_plugins(TessellaPlugin)
        .add_plugins(WaitForGpu)
        .insert_resource(Capture::default())
        .add_systems(Startup, setup)
        .add_systems(
            Update,
            (capture, time_frames.run_if(resource_exists::<Timing>)),
        )
        .run()
}

/// The camera `tessella render` frames a mesh with: the bounding box's centre, the farthest
/// vertex's distance grown by 1.2 (curved patches bulge past the coarse hull), 30 degrees
/// vertical field of view, yaw about +Y, pitch raising the eye, zoom moving closer.
fn framing(
    positions: &[[f32; 3]],
    yaw: f32,
    pitch: f32,
    zoom: f32,
    aspect: f32,
) -> (Vec3, Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in positions {
        lo = lo.min(Vec3::from(*p));
        hi = hi.max(Vec3::from(*p));
    }
    let center = (lo + hi) * 0.5;
    let radius = positions
        .iter()
        .map(|p| Vec3::from(*p).distance(center))
        .fold(0.0f32, f32::max)
        .max(1e-6)
        * 1.2;
    let fov_y = FOV_Y_DEGREES.to_radians();
    let half_x = ((fov_y * 0.5).tan() * aspect).atan();
    let half = (fov_y * 0.5).min(half_x);
    let distance = radius / half.sin() / zoom;
    let (yaw, pitch) = (yaw.to_radians(), pitch.to_radians());
    let dir = Vec3::new(
        pitch.cos() * yaw.sin(),
        pitch.sin(),
        pitch.cos() * yaw.cos(),
    );
    let up = if dir.y.abs() > 0.999 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    (center + dir * distance, center, up)
}

fn setup(
    mut commands: Commands,
    args: Res<Args>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut images: ResMut<Assets<Image>>,
    mut exit: MessageWriter<AppExit>,
) {
    let mesh = match tessella_io::read_mesh(&args.input) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("view: cannot read {}: {e}", args.input.display());
            exit.write(AppExit::error());
            return;
        }
    };
    let framed = match &args.frame {
        None => mesh.clone(),
        Some(path) => match tessella_io::read_mesh(path) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("view: cannot read {}: {e}", path.display());
                exit.write(AppExit::error());
                return;
            }
        },
    };
    let (w, h) = args.size;
    let (eye, center, up) = framing(
        framed.positions(),
        args.yaw,
        args.pitch,
        args.zoom,
        w as f32 / h as f32,
    );
    let mut entity = commands.spawn((
        Mesh3d(meshes.add(to_bevy_mesh(&mesh))),
        MeshMaterial3d(materials.add(StandardMaterial {
            // tessella render's default colour, rough so no highlight reaches the background's
            // white.
            base_color: Color::srgb_u8(120, 160, 215),
            perceptual_roughness: 0.8,
            ..default()
        })),
    ));
    if !args.plain {
        entity.insert(Tessellate::new(args.scheme, args.level));
    }
    let subject = entity.id();
    if args.ground {
        // A floor just under the framed mesh, facing up, wide enough to hold its shadow.
        let (lo, hi) = framed.bounds();
        let size = (Vec3::from(hi) - Vec3::from(lo)).length() * 3.0;
        commands.spawn((
            Mesh3d(meshes.add(Plane3d::new(Vec3::Y, Vec2::splat(size * 0.5)))),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: Color::srgb_u8(200, 190, 170),
                perceptual_roughness: 1.0,
                ..default()
            })),
            Transform::from_translation(Vec3::new(
                (lo[0] + hi[0]) * 0.5,
                lo[1] - 0.02 * size,
                (lo[2] + hi[2]) * 0.5,
            )),
        ));
    }
    commands.insert_resource(Subject(subject));
    let mut target = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = images.add(target);
    commands.insert_resource(Target(target.clone()));
    let forward = (center - eye).normalize();
    let right = forward.cross(up).normalize();
    let cam_up = right.cross(forward);
    // tessella render's key light: above-left of the viewer.
    let light_dir = (-0.45 * right + 0.6 * cam_up - 0.65 * forward).normalize();
    commands.spawn((
        DirectionalLight {
            shadow_maps_enabled: !args.no_shadows,
            illuminance: 4000.0,
            ..default()
        },
        Transform::from_translation(center + light_dir).looking_at(center, up),
    ));
    commands.insert_resource(GlobalAmbientLight {
        brightness: 300.0,
        ..default()
    });
    commands.spawn((
        Camera3d::default(),
        RenderTarget::Image(target.into()),
        Tonemapping::None,
        Msaa::Off,
        Projection::Perspective(PerspectiveProjection {
            fov: FOV_Y_DEGREES.to_radians(),
            ..default()
        }),
        Transform::from_translation(eye).looking_at(center, up),
    ));
}

#[derive(Resource)]
struct Target(Handle<Image>);

/// Each frame waits for its GPU work, so frame times count the GPU's (lavapipe's) drawing.
struct WaitForGpu;

impl Plugin for WaitForGpu {
    fn build(&self, app: &mut App) {
        use bevy::render::renderer::RenderDevice;
        use bevy::render::{Render, RenderApp, RenderSystems};
        app.sub_app_mut(RenderApp).add_systems(
            Render,
            (|device: Res<RenderDevice>| {
                let _ = device.poll(bevy::render::render_resource::PollType::wait_indefinitely());
            })
            .in_set(RenderSystems::Cleanup),
        );
    }
}

/// Frame timing after the picture (`--frames`).
#[derive(Resource)]
struct Timing {
    left: u32,
    start: Option<std::time::Instant>,
}

fn time_frames(mut timing: ResMut<Timing>, args: Res<Args>, mut exit: MessageWriter<AppExit>) {
    let now = std::time::Instant::now();
    let Some(start) = timing.start else {
        timing.start = Some(now);
        return;
    };
    timing.left -= 1;
    if timing.left == 0 {
        let ms = now.duration_since(start).as_secs_f64() * 1000.0 / args.frames as f64;
        println!(
            "{{\"file\":{:?},\"plain\":{},\"level\":{},\"frames\":{},\"mean_frame_ms\":{ms:.3}}}",
            args.input.display().to_string(),
            args.plain,
            args.level,
            args.frames
        );
        exit.write(AppExit::Success);
    }
}

/// The mesh entity.
#[derive(Resource)]
struct Subject(Entity);

#[derive(Resource, Default)]
struct Capture {
    frames: u32,
    pending: bool,
    last: Option<Vec<u8>>,
    done: bool,
}

fn capture(
    mut commands: Commands,
    mut state: ResMut<Capture>,
    args: Res<Args>,
    target: Option<Res<Target>>,
) {
    state.frames += 1;
    let Some(target) = target else { return };
    if state.done || state.pending || state.frames < args.warmup {
        return;
    }
    state.pending = true;
    commands.spawn(Screenshot::image(target.0.clone())).observe(
        |captured: On<ScreenshotCaptured>,
         mut state: ResMut<Capture>,
         mut args: ResMut<Args>,
         subject: Res<Subject>,
         mut commands: Commands,
         mut exit: MessageWriter<AppExit>| {
            state.pending = false;
            let rgba = match captured.image.clone().try_into_dynamic() {
                Ok(d) => d.to_rgba8(),
                Err(e) => {
                    eprintln!("view: cannot read the capture: {e}");
                    exit.write(AppExit::error());
                    return;
                }
            };
            let bytes = rgba.as_raw().clone();
            if state.last.as_ref() != Some(&bytes) {
                state.last = Some(bytes);
                if state.frames > 600 {
                    eprintln!("view: the picture did not settle in 600 frames");
                    exit.write(AppExit::error());
                }
                return;
            }
            if let Err(e) = rgba.save(&args.screenshot) {
                eprintln!("view: cannot write {}: {e}", args.screenshot.display());
                exit.write(AppExit::error());
                return;
            }
            eprintln!(
                "view: wrote {} after {} frames",
                args.screenshot.display(),
                state.frames
            );
            if let Some(next) = args.then_plain.take() {
                // The same entity without Tessellate: the plugin gives its mesh back.
                commands.entity(subject.0).remove::<Tessellate>();
                args.screenshot = next;
                *state = Capture::default();
                return;
            }
            state.done = true;
            if args.frames > 0 {
                commands.insert_resource(Timing {
                    left: args.frames,
                    start: None,
                });
                return;
            }
            exit.write(AppExit::Success);
        },
    );
}
