//! A mesh file drawn by Bevy with `Tessellate` (or without, `--plain`), framed by the camera
//! `tessella render` uses (`tessella_core::framing`), written to a PNG headless:
//!
//! `cargo run --example view -- FILE --scheme S --level L --yaw Y --pitch P --zoom Z
//!  --size WxH [--clip C --time T] --screenshot OUT.png [--plain] [--draw per-frame|mesh|welded|runs]
//!  [--pose gpu|cpu]
//!  [--crowd N [--stagger S]] [--frames N --stats]`
//!
//! A glTF file is loaded by Bevy's glTF loader (its scene, `Tessellate` added to each of its
//! meshes); with `--clip` Bevy's `AnimationPlayer` plays that clip, held at `--time` for the
//! picture and playing on during `--frames`. `--stats` prints one JSON line a frame with the
//! bytes tessella handed Bevy to upload in it and the welded vertices the per-frame pass has
//! evaluated so far.
//!
//! No window: the camera renders into an image, and Bevy's `Screenshot` of that image is
//! saved once two successive captures agree (pipelines compile synchronously, so the picture
//! settles within a few frames), then the app exits.

// The showcase examples' module, for the ground's look only.
mod showcase;

use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::asset::uuid::Uuid;
use bevy::camera::NormalizedRenderTarget;
use bevy::camera::RenderTarget;
use bevy::gltf::{Gltf, GltfAssetLabel};
use bevy::picking::backend::ray::{RayId, RayMap};
use bevy::picking::hover::HoverMap;
use bevy::picking::mesh_picking::MeshPickingPlugin;
use bevy::picking::pointer::{Location, PointerId, PointerLocation};
use bevy::picking::PickingSystems;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::window::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::view::{Msaa, Tonemapping};
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use bevy::world_serialization::WorldAssetRoot;
use std::path::PathBuf;
use std::time::Duration;
use tessella_bevy::tessella_core::animation::Poser;
use tessella_bevy::tessella_core::names::parse_name;
use tessella_bevy::tessella_core::refine::{Camera as LodCamera, Lod, Spacing};
use tessella_bevy::tessella_core::Scheme;
use tessella_bevy::{
    to_bevy_mesh, EvaluationStats, LodLevels, Patch, TessellaDraw, TessellaPlugin, TessellaPosing,
    Tessellate, UploadStats,
};

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
    /// How the tessellated meshes are drawn (`--draw per-frame|mesh|welded|runs`, the plugin's default when absent).
    draw: TessellaDraw,
    /// Where animated ones are posed (`--pose gpu|cpu`, the plugin's default when absent).
    posing: TessellaPosing,
    /// `--crowd N`: N copies of a glTF scene in a square grid, each playing `--clip` (many
    /// animated characters, as Bevy's `many_foxes` stress test).
    crowd: u32,
    /// After the picture: draw this many frames more, each waited for on the GPU, and print
    /// their mean time as one JSON line.
    frames: u32,
    /// Frames drawn before the first capture.
    warmup: u32,
    /// A glTF animation clip (name or index) Bevy's `AnimationPlayer` plays.
    clip: Option<String>,
    /// Seconds into the clip the picture is taken at.
    time: f32,
    /// `--stagger S`: a crowd's k-th copy is held S x k seconds later into the clip than the
    /// first (each copy its own pose).
    stagger: f32,
    /// One JSON line a frame during `--frames`: the bytes tessella uploaded in it.
    stats: bool,
    /// Per-edge levels from this LOD (`screen:PX`, `tolerance:D`, `distance:NEAR,FAR,MAX`),
    /// seen from the camera, divided with `spacing`.
    lod: Option<String>,
    spacing: Spacing,
    /// A pointer at this pixel: after the picture, one JSON line says what Bevy's picking
    /// found under it.
    pick: Option<Vec2>,
}

impl Args {
    fn is_gltf(&self) -> bool {
        let ext = self.input.extension().and_then(|e| e.to_str());
        matches!(
            ext.map(str::to_ascii_lowercase).as_deref(),
            Some("glb" | "gltf")
        )
    }
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
        draw: TessellaDraw::default(),
        posing: TessellaPosing::default(),
        crowd: 1,
        frames: 0,
        warmup: 3,
        clip: None,
        time: 0.0,
        stagger: 0.0,
        stats: false,
        pick: None,
        lod: None,
        spacing: Spacing::FractionalOdd,
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
            "--draw" => {
                args.draw = match value()?.as_str() {
                    "per-frame" => TessellaDraw::PerFrame,
                    "welded" => TessellaDraw::Welded,
                    "runs" => TessellaDraw::Runs,
                    "mesh" => TessellaDraw::Mesh,
                    other => {
                        return Err(format!("--draw {other}: per-frame, mesh, welded or runs"))
                    }
                }
            }
            "--pose" => {
                args.posing = match value()?.as_str() {
                    "gpu" => TessellaPosing::Gpu,
                    "cpu" => TessellaPosing::Cpu,
                    other => return Err(format!("--pose {other}: gpu or cpu")),
                }
            }
            "--frames" => args.frames = value()?.parse().map_err(|e| format!("--frames: {e}"))?,
            "--clip" => args.clip = Some(value()?),
            "--time" => args.time = num(value()?)?,
            "--stagger" => args.stagger = num(value()?)?,
            "--stats" => args.stats = true,
            "--crowd" => {
                args.crowd = value()?.parse().map_err(|e| format!("--crowd: {e}"))?;
                if args.crowd == 0 || args.crowd > 10_000 {
                    return Err("--crowd: 1 to 10000 copies".into());
                }
            }
            "--lod" => args.lod = Some(value()?),
            "--spacing" => args.spacing = parse_name(&value()?).map_err(|e| e.to_string())?,
            "--pick" => {
                let v = value()?;
                let (x, y) = v.split_once(',').ok_or(format!("--pick {v}: want X,Y"))?;
                args.pick = Some(Vec2::new(num(x.into())?, num(y.into())?));
            }
            "--then-plain" => args.then_plain = Some(PathBuf::from(value()?)),
            s if !s.starts_with('-') && input.is_none() => input = Some(PathBuf::from(s)),
            s => return Err(format!("unknown argument {s}")),
        }
    }
    args.input = input.ok_or("usage: view FILE [--scheme S --level L ...]")?;
    if let Some(lod) = &args.lod {
        // Checked now; the camera and size are Bevy's, each frame.
        let camera = LodCamera {
            eye: [0.0, 0.0, 1.0],
            target: [0.0; 3],
            fov_y_deg: tessella_view::FOV_Y_DEGREES,
        };
        Lod::parse(lod, Some(camera), Some([1, 1])).map_err(|e| format!("--lod: {e}"))?;
    }
    if args.clip.is_some() && !args.is_gltf() {
        return Err("--clip needs a glTF file".into());
    }
    if args.crowd > 1 && !args.is_gltf() {
        return Err("--crowd needs a glTF file".into());
    }
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
    // Bevy's assets are read below one folder: the input's.
    let folder = args
        .input
        .canonicalize()
        .ok()
        .and_then(|p| p.parent().map(|p| p.display().to_string()))
        .unwrap_or_else(|| ".".into());
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
                .set(AssetPlugin {
                    file_path: folder,
                    ..default()
                })
                .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>(),
        )
        // No winit: this loop runs the frames.
        .add_plugins(ScheduleRunnerPlugin::run_loop(Duration::ZERO))
        .add_plugins((MeshPickingPlugin, TessellaPlugin))
        .add_plugins(WaitForGpu)
        .insert_resource(Capture::default())
        .add_systems(Startup, setup)
        .add_systems(
            PreUpdate,
            image_pointer_rays
                .after(PickingSystems::ProcessInput)
                .before(PickingSystems::Backend),
        )
        .add_systems(
            Update,
            (
                adopt_scene_meshes,
                start_clip,
                exit_on_failed_load,
                capture,
                time_frames.run_if(resource_exists::<Timing>),
            ),
        )
        .run()
}

/// The mesh the camera frames: `--frame`'s file, else FILE posed at `--clip`/`--time` (as
/// `tessella render` poses it), else FILE.
fn framed_mesh(args: &Args) -> Result<tessella_bevy::tessella_core::Mesh, String> {
    let read = |path: &std::path::Path| {
        tessella_io::read_mesh(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    if let Some(path) = &args.frame {
        return read(path);
    }
    let Some(clip) = &args.clip else {
        return read(&args.input);
    };
    let model = tessella_io::read_animated(&args.input).map_err(|e| e.to_string())?;
    let poser = Poser::new(model).map_err(|e| e.to_string())?;
    let index = poser.clip_index(clip).map_err(|e| e.to_string())?;
    poser
        .mesh(Some(index), args.time)
        .map_err(|e| e.to_string())
}

impl Args {
    /// The `Tessellate` the options ask for.
    fn tessellate(&self) -> Tessellate {
        let lod = self.lod.as_ref().and_then(|text| {
            let camera = LodCamera {
                eye: [0.0, 0.0, 1.0],
                target: [0.0; 3],
                fov_y_deg: tessella_view::FOV_Y_DEGREES,
            };
            Lod::parse(text, Some(camera), Some([1, 1])).ok()
        });
        match lod {
            Some(lod) => Tessellate::lod(self.scheme, lod, self.spacing),
            None => Tessellate::new(self.scheme, self.level),
        }
    }
}

/// Where the `count` copies of a crowd stand: a square grid on the ground plane (x, z), a
/// copy's box diagonal apart, centred on the origin. One copy stands at the origin.
fn crowd_offsets(count: u32, (lo, hi): ([f32; 3], [f32; 3])) -> Vec<Vec3> {
    if count <= 1 {
        return vec![Vec3::ZERO];
    }
    let side = (count as f32).sqrt().ceil() as u32;
    let step = (Vec3::from(hi) - Vec3::from(lo)).length();
    let half = (side - 1) as f32 * 0.5;
    (0..count)
        .map(|i| {
            let (col, row) = ((i % side) as f32 - half, (i / side) as f32 - half);
            Vec3::new(col * step, 0.0, row * step)
        })
        .collect()
}

/// The colour every subject is drawn in: `tessella render`'s default, rough so no highlight
/// reaches the background's white.
#[derive(Resource)]
struct SubjectMaterial(Handle<StandardMaterial>);

/// A mesh entity the picture is of (FILE's mesh, or each mesh of its glTF scene).
#[derive(Component)]
struct Subject;

/// The glTF file being shown, for its animation clips.
#[derive(Resource)]
struct GltfFile(Handle<Gltf>);

#[allow(clippy::too_many_arguments)]
fn setup(
    mut commands: Commands,
    args: Res<Args>,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut images: ResMut<Assets<Image>>,
    mut exit: MessageWriter<AppExit>,
) {
    let framed = match framed_mesh(&args) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("view: {e}");
            exit.write(AppExit::error());
            return;
        }
    };
    let (w, h) = args.size;
    // The copies of a crowd, and the points the camera and the ground take in: each copy's box.
    let offsets = crowd_offsets(args.crowd, framed.bounds());
    let (lo, hi) = framed.bounds();
    let framed_points: Vec<[f32; 3]> = if args.crowd > 1 {
        offsets
            .iter()
            .flat_map(|o| {
                (0..8).map(move |k| {
                    let corner = Vec3::new(
                        if k & 1 == 0 { lo[0] } else { hi[0] },
                        if k & 2 == 0 { lo[1] } else { hi[1] },
                        if k & 4 == 0 { lo[2] } else { hi[2] },
                    );
                    (corner + *o).to_array()
                })
            })
            .collect()
    } else {
        framed.positions().to_vec()
    };
    // tessella render's framing and key light (tessella-view's, the one definition).
    let framing = tessella_view::frame_points(
        &framed_points,
        args.yaw,
        args.pitch,
        args.zoom,
        w as f32 / h as f32,
    );
    let (eye, center, up) = (
        Vec3::from(framing.eye),
        Vec3::from(framing.target),
        Vec3::from(framing.up),
    );
    let material = materials.add(StandardMaterial {
        base_color: Color::srgb_u8(120, 160, 215),
        perceptual_roughness: 0.8,
        ..default()
    });
    commands.insert_resource(SubjectMaterial(material.clone()));
    if args.is_gltf() {
        // Bevy's glTF loader spawns the scene; `adopt_scene_meshes` tessellates its meshes.
        let name = args
            .input
            .file_name()
            .map(|n| n.to_string_lossy().to_string());
        let name = name.unwrap_or_default();
        let scene = assets.load(GltfAssetLabel::Scene(0).from_asset(name.clone()));
        for (k, offset) in offsets.iter().enumerate() {
            commands.spawn((
                WorldAssetRoot(scene.clone()),
                Transform::from_translation(*offset),
                CrowdCopy(k as u32),
            ));
        }
        commands.insert_resource(GltfFile(assets.load(name)));
    } else {
        let mesh = match tessella_io::read_mesh(&args.input) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("view: cannot read {}: {e}", args.input.display());
                exit.write(AppExit::error());
                return;
            }
        };
        let mut entity = commands.spawn((
            Mesh3d(meshes.add(to_bevy_mesh(&mesh))),
            MeshMaterial3d(material),
            Subject,
        ));
        if !args.plain {
            entity.insert((args.tessellate(), args.draw, args.posing));
        }
    }
    if args.ground {
        // A floor just under the framed mesh, facing up, wide enough to hold its shadow.
        let (lo, hi) = tessella_bevy::tessella_core::mesh::bounds(&framed_points);
        let size = (Vec3::from(hi) - Vec3::from(lo)).length() * 3.0;
        commands.spawn((
            showcase::ground_plane(&mut meshes, &mut materials, size),
            Transform::from_translation(Vec3::new(
                (lo[0] + hi[0]) * 0.5,
                lo[1] - 0.02 * size,
                (lo[2] + hi[2]) * 0.5,
            )),
            Ground,
        ));
    }
    let mut target = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = images.add(target);
    commands.insert_resource(Target(target.clone()));
    if let Some(position) = args.pick {
        commands.spawn((
            PICK_POINTER,
            PointerLocation::new(Location {
                target: NormalizedRenderTarget::Image(target.clone().into()),
                position,
            }),
        ));
    }
    let light_dir = Vec3::from(framing.light_dir);
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
            fov: tessella_view::FOV_Y_DEGREES.to_radians(),
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
                let wait = bevy::render::render_resource::PollType::wait_indefinitely();
                if let Err(e) = device.poll(wait) {
                    error!("view: waiting for the GPU failed: {e}");
                }
            })
            .in_set(RenderSystems::Cleanup),
        );
    }
}

/// The k-th copy of a crowd: the root of its scene.
#[derive(Component)]
struct CrowdCopy(u32);

/// Frame timing after the picture (`--frames`).
#[derive(Resource)]
struct Timing {
    left: u32,
    start: Option<std::time::Instant>,
    /// The process's CPU seconds (all threads: lavapipe's rasterizer too) at `start`.
    cpu_start: Option<f64>,
    /// The previous frame's end and tessella's upload total then.
    last: Option<(std::time::Instant, u64)>,
}

fn time_frames(
    mut timing: ResMut<Timing>,
    args: Res<Args>,
    stats: Res<UploadStats>,
    evaluations: Res<EvaluationStats>,
    materials: Res<Assets<tessella_bevy::TessellaMaterial>>,
    mut exit: MessageWriter<AppExit>,
) {
    let now = std::time::Instant::now();
    // This frame's main-world work is done; its render (and upload) follows, so a frame's
    // bytes are the total's growth from one Update to the next.
    let total = stats.total();
    if args.stats {
        if let Some((then, before)) = timing.last {
            let frame = args.frames - timing.left;
            println!(
                "{{\"frame\":{frame},\"uploaded_bytes\":{},\"evaluated_vertices\":{},\"bind_groups\":{},\"frame_ms\":{:.3}}}",
                total - before,
                evaluations.evaluated_vertices(),
                evaluations.bind_groups_made(),
                now.duration_since(then).as_secs_f64() * 1000.0
            );
        }
    }
    timing.last = Some((now, total));
    let Some(start) = timing.start else {
        timing.start = Some(now);
        timing.cpu_start = cpu_seconds();
        return;
    };
    timing.left -= 1;
    if timing.left == 0 {
        let ms = now.duration_since(start).as_secs_f64() * 1000.0 / args.frames as f64;
        // CPU time a frame: on a software rasterizer the GPU's work too, and less swayed than
        // the wall clock by other processes on a shared machine.
        let cpu = match (timing.cpu_start, cpu_seconds()) {
            (Some(a), Some(b)) => format!("{:.3}", (b - a) * 1000.0 / args.frames as f64),
            _ => "null".to_string(),
        };
        println!(
            "{{\"file\":{:?},\"plain\":{},\"level\":{},\"frames\":{},\"mean_frame_ms\":{ms:.3},\"mean_frame_cpu_ms\":{cpu},\"tessella_materials\":{}}}",
            args.input.display().to_string(),
            args.plain,
            args.level,
            args.frames,
            materials.len()
        );
        exit.write(AppExit::Success);
    }
}

/// The process's user and system CPU seconds, all threads (Linux's `/proc/self/stat`, in
/// its fixed 100 ticks a second); `None` elsewhere.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command name (which may hold spaces, inside parentheses): utime
    // and stime are the 12th and 13th of them.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// The `--pick` pointer.
const PICK_POINTER: PointerId =
    PointerId::Custom(Uuid::from_u128(0x7e55_e11a_0000_0000_0000_0000_0000_0001));

/// The rays of pointers on the cameras' image targets. Bevy 0.20.1 makes a pointer's ray only
/// when there is a primary window (`Location::is_in_viewport`), even for a camera drawing into
/// an image; `RayMap` takes rays added by hand for such cameras, as its documentation says.
fn image_pointer_rays(
    mut rays: ResMut<RayMap>,
    cameras: Query<(Entity, &Camera, &RenderTarget, &GlobalTransform)>,
    pointers: Query<(&PointerId, &PointerLocation)>,
) {
    for (entity, camera, target, transform) in &cameras {
        let RenderTarget::Image(image) = target else {
            continue;
        };
        for (&id, location) in &pointers {
            let Some(location) = location.location() else {
                continue;
            };
            if location.target != NormalizedRenderTarget::Image(image.clone()) {
                continue;
            }
            if let Ok(ray) = camera.viewport_to_world(transform, location.position) {
                rays.map.insert(RayId::new(entity, id), ray);
            }
        }
    }
}

/// What Bevy's picking has under the `--pick` pointer, nearest first: one JSON line.
fn report_pick(hovers: &HoverMap, subjects: &Query<Entity, With<Subject>>) {
    let mut hits: Vec<_> = hovers
        .get(&PICK_POINTER)
        .map(|h| h.iter().collect())
        .unwrap_or_default();
    hits.sort_by(|a, b| a.1.depth.total_cmp(&b.1.depth));
    match hits.first() {
        None => println!("{{\"pick\":{{\"hit\":false}}}}"),
        Some((entity, hit)) => {
            let p = hit.position.unwrap_or(Vec3::NAN);
            println!(
                "{{\"pick\":{{\"hit\":true,\"subject\":{},\"depth\":{},\"position\":[{},{},{}]}}}}",
                subjects.contains(**entity),
                hit.depth,
                p.x,
                p.y,
                p.z
            );
        }
    }
}

/// The triangles the subjects' LOD draws, and the LOD as the plugin evaluated it (Bevy's
/// camera, the target's size): one JSON line, for `tessella refine --lod --camera --size`.
fn report_lod(levels: &Query<&LodLevels>) {
    let triangles: u64 = levels.iter().map(|l| l.triangles).sum();
    let seen = levels.iter().find_map(|l| match &l.lod {
        Some(Lod::Screen { camera, size, .. }) => Some((*camera, *size)),
        _ => None,
    });
    match seen {
        Some((c, [w, h])) => println!(
            "{{\"lod\":{{\"triangles\":{triangles},\"camera\":\"{},{},{},{},{},{},{}\",\"size\":\"{w}x{h}\"}}}}",
            c.eye[0], c.eye[1], c.eye[2], c.target[0], c.target[1], c.target[2], c.fov_y_deg
        ),
        None => println!("{{\"lod\":{{\"triangles\":{triangles}}}}}"),
    }
}

/// The ground plane (not a subject).
#[derive(Component)]
struct Ground;

/// A mesh entity not yet seen: not a subject, the ground, or one of the plugin's patches.
type Unadopted = (
    With<Mesh3d>,
    Without<Subject>,
    Without<Ground>,
    Without<Patch>,
);

/// Each mesh the glTF scene spawned becomes a subject: the subjects' material, and
/// `Tessellate` unless `--plain`.
fn adopt_scene_meshes(
    mut commands: Commands,
    args: Res<Args>,
    material: Option<Res<SubjectMaterial>>,
    found: Query<Entity, Unadopted>,
) {
    let Some(material) = material else { return };
    for entity in &found {
        let mut entity = commands.entity(entity);
        entity.insert((MeshMaterial3d(material.0.clone()), Subject));
        if !args.plain {
            entity.insert((args.tessellate(), args.draw, args.posing));
        }
    }
}

/// A file that fails to load (the glTF, one of its images) ends the app with an error: a
/// blank picture and exit 0 would hide it.
fn exit_on_failed_load(
    mut failed: MessageReader<bevy::asset::UntypedAssetLoadFailedEvent>,
    mut exit: MessageWriter<AppExit>,
) {
    for e in failed.read() {
        eprintln!("view: cannot load {}: {}", e.path, e.error);
        exit.write(AppExit::error());
    }
}

/// Once the glTF file has loaded, each `AnimationPlayer` its scene spawned plays `--clip`,
/// held at `--time` (the timed frames resume it).
fn start_clip(
    mut commands: Commands,
    args: Res<Args>,
    (file, gltfs): (Option<Res<GltfFile>>, Res<Assets<Gltf>>),
    mut graphs: ResMut<Assets<AnimationGraph>>,
    mut players: Query<(Entity, &mut AnimationPlayer), Without<AnimationGraphHandle>>,
    // A player's ancestors, up to its crowd copy's scene root.
    (parents, copies): (Query<&ChildOf>, Query<&CrowdCopy>),
    mut exit: MessageWriter<AppExit>,
) {
    let (Some(clip), Some(file)) = (&args.clip, file) else {
        return;
    };
    let Some(gltf) = gltfs.get(&file.0) else {
        return;
    };
    for (entity, mut player) in &mut players {
        let handle = match clip.parse::<usize>() {
            Ok(i) => gltf.animations.get(i).cloned(),
            Err(_) => gltf.named_animations.get(clip.as_str()).cloned(),
        };
        let Some(handle) = handle else {
            eprintln!("view: the file has no clip {clip}");
            exit.write(AppExit::error());
            return;
        };
        let (graph, node) = AnimationGraph::from_clip(handle);
        commands
            .entity(entity)
            .insert(AnimationGraphHandle(graphs.add(graph)));
        // The copy's number, from its scene root (scenes may load in different frames).
        let k = parents
            .iter_ancestors(entity)
            .find_map(|a| copies.get(a).ok())
            .map_or(0, |c| c.0);
        let time = args.time + args.stagger * k as f32;
        player.play(node).seek_to(time).pause();
    }
}

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
         subjects: Query<Entity, With<Subject>>,
         mut players: Query<&mut AnimationPlayer>,
         hovers: Res<HoverMap>,
         levels: Query<&LodLevels>,
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
            if args.pick.is_some() {
                report_pick(&hovers, &subjects);
            }
            if args.lod.is_some() {
                report_lod(&levels);
            }
            if let Some(next) = args.then_plain.take() {
                // The same entity without Tessellate: the plugin gives its mesh back.
                for subject in &subjects {
                    commands.entity(subject).remove::<Tessellate>();
                }
                args.screenshot = next;
                *state = Capture::default();
                return;
            }
            state.done = true;
            if args.frames > 0 {
                // The clip plays on while the frames are timed.
                for mut player in &mut players {
                    player.resume_all();
                }
                commands.insert_resource(Timing {
                    left: args.frames,
                    start: None,
                    cpu_start: None,
                    last: None,
                });
                return;
            }
            exit.write(AppExit::Success);
        },
    );
}
