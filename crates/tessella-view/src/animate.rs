//! A deforming coarse mesh rendered with the pattern: one [`Plan`] for the whole animation;
//! per frame [`Plan::update`] rebuilds the control nets (O(coarse triangles)) and
//! [`PatternRenderer::update`] uploads them (GMR section 3.1), never a refined vertex buffer.
//! The coarse mesh moves by a twist ([`render_twist`]) or by a glTF clip's skinning and morph
//! targets ([`render_clip`]), posed on the CPU or, uploading only the frame's joint matrices,
//! on the GPU ([`Skinning`]). The fly-in changes the levels every frame instead, drawn by one
//! [`AdaptiveRenderer`].

use crate::appearance::Appearance;
use crate::save_png;
use crate::scene::{scene_uniforms, RenderOptions};
use crate::target::Target;
use std::path::{Path, PathBuf};
use tessella_core::animation::Poser;
use tessella_core::refine::{Frame, Plan, Surface};
use tessella_core::{AnimationError, Mesh, OutputLayout, RefineOptions};
use tessella_gpu::{
    AdaptiveRenderer, GpuContext, GpuError, GpuNetBuilder, GpuSkinner, PatternRenderer,
};

/// What an animation cost on the bus.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationStats {
    pub frames: u32,
    /// Bytes uploaded per frame: the control nets (points and normal nets).
    pub bytes_per_frame: u64,
    /// Bytes a fully refined, welded, indexed mesh at the same level would need per frame.
    pub refined_bytes_per_frame: u64,
    /// The frames written, in order.
    pub paths: Vec<PathBuf>,
}

/// Positions and normals of `mesh` twisted about the vertical (Y) axis: a point at height `y`
/// turns by `angle_degrees × (y - centre) / height`, normals turn with it.
pub fn twist_points(mesh: &Mesh, angle_degrees: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let (lo, hi) = mesh.bounds();
    let height = (hi[1] - lo[1]).max(1e-12);
    let mid = 0.5 * (lo[1] + hi[1]);
    let turn = |v: [f32; 3], y: f32| {
        let a = angle_degrees.to_radians() * (y - mid) / height;
        let (s, c) = a.sin_cos();
        [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]
    };
    let positions = mesh.positions().iter().map(|&p| turn(p, p[1])).collect();
    // Rotating a normal with its point is exact for a rigid turn, approximate under the
    // twist's shear; good enough for shading a demo.
    let normals = mesh
        .normals()
        .iter()
        .zip(mesh.positions())
        .map(|(&n, p)| turn(n, p[1]))
        .collect();
    (positions, normals)
}

/// `mesh` twisted by `angle_degrees` ([`twist_points`]) as a new mesh.
pub fn twist(mesh: &Mesh, angle_degrees: f32) -> Result<Mesh, GpuError> {
    let (positions, normals) = twist_points(mesh, angle_degrees);
    Mesh::new(
        positions,
        Some(normals),
        mesh.uvs().map(|u| u.to_vec()),
        mesh.triangles().to_vec(),
    )
    .map_err(|e| GpuError::Refine(e.into()))
}

/// Renders `frames` pictures of `mesh` twisting back and forth by up to `max_angle_degrees`
/// (frame `k` turns by `max_angle × sin(2πk / frames)`), into `out_dir/frame_000.png`, ...
/// The camera is framed on the rest pose; only the nets change between frames.
pub fn render_twist(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
    frames: u32,
    max_angle_degrees: f32,
    out_dir: &Path,
) -> Result<AnimationStats, GpuError> {
    render_frames(ctx, mesh, refine, options, frames, out_dir, |k, cpu| {
        let phase = k as f32 / frames as f32 * std::f32::consts::TAU;
        let (positions, normals) = twist_points(mesh, max_angle_degrees * phase.sin());
        cpu.plan.update(cpu.frame, &positions, Some(&normals))?;
        cpu.renderer.update(cpu.frame)
    })
}

/// Where a clip's frames are posed and their control nets built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Skinning {
    /// On the CPU: [`Poser::pose_into`], then [`Plan::update`] builds the nets and the renderer
    /// uploads them (the nets' bytes every frame).
    #[default]
    Cpu,
    /// On the GPU: [`GpuSkinner`] poses the coarse mesh from the frame's deform matrices (and
    /// morph weights), [`GpuNetBuilder`] builds the nets from its output into the renderer's
    /// buffers; a frame uploads the matrices and weights alone. Needs a mesh with normals and
    /// a scheme the GPU builds (flat, Phong, PN, PN-AEN).
    Gpu,
}

/// A clip played into pictures: which, how many frames at what rate, and where they are posed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipFrames {
    pub clip: usize,
    pub frames: u32,
    /// Frames per second of the clip's time: frame `k` shows `k / fps` seconds.
    pub fps: f32,
    pub skinning: Skinning,
}

/// Renders the frames of an animation clip played from its start (frame `k` at `k / fps`
/// seconds; past the clip's end its last pose holds) into `out_dir/frame_000.png`, ...: per
/// frame the coarse mesh is posed (morph targets, skinning) and its nets rebuilt, on the CPU
/// or the GPU ([`Skinning`]), and the pattern renderer draws them. The camera is framed on the
/// rest pose. [`AnimationStats::bytes_per_frame`] is what the last frame uploaded.
pub fn render_clip(
    ctx: &GpuContext,
    poser: &Poser,
    refine: &RefineOptions,
    options: &RenderOptions,
    play: &ClipFrames,
    out_dir: &Path,
) -> Result<AnimationStats, GpuError> {
    let bad = |e: AnimationError| GpuError::BadOption(e.to_string());
    let fps = play.fps;
    if !(fps.is_finite() && fps > 0.0) {
        return Err(GpuError::BadOption(format!(
            "frames per second must be positive, got {fps}"
        )));
    }
    let clip = Some(play.clip);
    poser.duration(play.clip).map_err(bad)?;
    let rest = poser.mesh(None, 0.0).map_err(bad)?;
    let time = |k: u32| k as f32 / fps;
    // Both skinnings draw through the same loop; only their frame step differs.
    let render = |step: &mut dyn FnMut(u32, FrameStep<'_>) -> Result<u64, GpuError>| {
        render_frames(ctx, &rest, refine, options, play.frames, out_dir, step)
    };
    match play.skinning {
        Skinning::Cpu => {
            let mut positions = vec![[0.0; 3]; poser.vertex_count()];
            let mut normals = poser
                .has_normals()
                .then(|| vec![[0.0; 3]; poser.vertex_count()]);
            render(&mut |k, cpu| {
                poser
                    .pose_into(clip, time(k), &mut positions, normals.as_deref_mut())
                    .map_err(bad)?;
                cpu.plan.update(cpu.frame, &positions, normals.as_deref())?;
                cpu.renderer.update(cpu.frame)
            })
        }
        Skinning::Gpu => {
            let mut skinner = GpuSkinner::new(ctx, poser)?;
            // Made on the first frame, from the plan's own surface (topology computed once).
            let mut builder: Option<GpuNetBuilder> = None;
            render(&mut |k, gpu| {
                let builder = match &mut builder {
                    Some(b) => b,
                    None => builder.insert(GpuNetBuilder::new(ctx, gpu.plan.surface())?),
                };
                let mut bytes = skinner.update(poser, clip, time(k))?;
                let mut encoder = ctx.device.create_command_encoder(&Default::default());
                skinner.record(&mut encoder)?;
                bytes +=
                    builder.record(&mut encoder, skinner.output(), gpu.renderer.nets_target()?)?;
                ctx.submit(encoder)?;
                Ok(bytes)
            })
        }
    }
}

/// What a frame step may move: the plan's frame and the renderer's nets.
struct FrameStep<'a> {
    plan: &'a Plan,
    frame: &'a mut Frame<'static>,
    renderer: &'a PatternRenderer,
}

/// The loop every deforming animation shares: one plan and renderer; per frame `step(k)` moves
/// the nets (posing the coarse mesh, rebuilding and uploading its nets, returning the bytes
/// uploaded), then the picture is drawn and saved.
fn render_frames(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
    frames: u32,
    out_dir: &Path,
    mut step: impl FnMut(u32, FrameStep<'_>) -> Result<u64, GpuError>,
) -> Result<AnimationStats, GpuError> {
    if frames == 0 {
        return Err(GpuError::BadOption(
            "an animation needs at least one frame".into(),
        ));
    }
    options.validate()?;
    let (plan, frame) = Plan::with_frame(mesh, refine)?;
    let mut frame = frame.into_owned();
    let look = Appearance::new(ctx, Target::FORMATS);
    let renderer =
        PatternRenderer::new(ctx, &plan, &frame, &look.shading(), &options.displacement)?;
    let target = Target::new(ctx, options.size)?;
    look.set_uniforms(&scene_uniforms(
        mesh,
        options,
        renderer.displacement_reach(),
    ));
    let welded = OutputLayout::new(mesh, Some(plan.topology()), plan.layout().level, true)?;
    let mut stats = AnimationStats {
        frames,
        bytes_per_frame: 0,
        refined_bytes_per_frame: welded.output_bytes(false),
        paths: Vec::new(),
    };
    for k in 0..frames {
        stats.bytes_per_frame = step(
            k,
            FrameStep {
                plan: &plan,
                frame: &mut frame,
                renderer: &renderer,
            },
        )?;
        target.draw(ctx, options.background, |pass| look.draw(pass, &renderer))?;
        let picture = target.read(ctx)?;
        let path = out_dir.join(format!("frame_{k:03}.png"));
        save_png(&picture, &path)?;
        stats.paths.push(path);
    }
    Ok(stats)
}

/// What a fly-in rendered.
#[derive(Debug, Clone, PartialEq)]
pub struct FlyInStats {
    /// Per frame: the camera's zoom, the largest edge level, the refined triangle count, and
    /// the bytes uploaded for its levels (one record per face and one instance per face and
    /// part: coarse data, whatever the levels).
    pub zooms: Vec<f32>,
    pub max_levels: Vec<f32>,
    pub triangles: Vec<u64>,
    pub upload_bytes: Vec<u64>,
    /// The frames written, in order.
    pub paths: Vec<PathBuf>,
}

/// Renders `frames` pictures of `mesh` with the camera moving towards it, from `zoom.0` to
/// `zoom.1` (geometrically, the eye's distance shrinking by the same factor every frame),
/// with view-dependent levels: `refine`'s spacing (fractional-odd or fractional-even make
/// levels, and so points, move continuously) and `Lod::Screen` at `pixels` per refined edge
/// seen from each frame's own camera. The levels change every frame; one
/// [`AdaptiveRenderer`] draws them all, uploading only per-face level data per frame. Frames go
/// to `out_dir/frame_000.png`, ...; `options.zoom` is ignored, and displacement is refused (the
/// adaptive renderer draws none).
#[allow(clippy::too_many_arguments)]
pub fn render_fly_in(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
    frames: u32,
    zoom: (f32, f32),
    pixels: f32,
    out_dir: &Path,
) -> Result<FlyInStats, GpuError> {
    use tessella_core::refine::Lod;
    if frames == 0 {
        return Err(GpuError::BadOption(
            "an animation needs at least one frame".into(),
        ));
    }
    if !(zoom.0 > 0.0 && zoom.1 > 0.0 && zoom.0.is_finite() && zoom.1.is_finite()) {
        return Err(GpuError::BadOption(format!(
            "fly-in zooms must be positive, got {} and {}",
            zoom.0, zoom.1
        )));
    }
    if options.displacement != tessella_gpu::Displacement::None {
        return Err(GpuError::BadOption(
            "the fly-in's adaptive renderer draws no displacement".into(),
        ));
    }
    options.validate()?;
    let target = Target::new(ctx, options.size)?;
    // The surface alone: the levels come from the screen-space LOD every frame.
    let surface = Surface::new(mesh, &refine.surface_options())?;
    let frame = surface.frame(mesh)?;
    let look = Appearance::new(ctx, Target::FORMATS);
    let mut renderer =
        AdaptiveRenderer::new(ctx, &surface, &frame, &look.shading(), refine.spacing)?;
    let mut stats = FlyInStats {
        zooms: Vec::new(),
        max_levels: Vec::new(),
        triangles: Vec::new(),
        upload_bytes: Vec::new(),
        paths: Vec::new(),
    };
    for k in 0..frames {
        let t = if frames > 1 {
            k as f32 / (frames - 1) as f32
        } else {
            0.0
        };
        let view = RenderOptions {
            zoom: zoom.0 * (zoom.1 / zoom.0).powf(t),
            ..options.clone()
        };
        let (w, h) = view.size;
        let screen = Lod::Screen {
            pixels,
            camera: crate::lod_camera(mesh, &view),
            size: [w, h],
        };
        let bytes = renderer.set_lod(&frame, &screen)?;
        look.set_uniforms(&scene_uniforms(mesh, &view, 0.0));
        target.draw(ctx, view.background, |pass| look.draw(pass, &renderer))?;
        let picture = target.read(ctx)?;
        let path = out_dir.join(format!("frame_{k:03}.png"));
        save_png(&picture, &path)?;
        stats.zooms.push(view.zoom);
        stats
            .max_levels
            .push(renderer.edge_levels().iter().copied().fold(1.0, f32::max));
        stats.triangles.push(renderer.triangle_count());
        stats.upload_bytes.push(bytes);
        stats.paths.push(path);
    }
    Ok(stats)
}
