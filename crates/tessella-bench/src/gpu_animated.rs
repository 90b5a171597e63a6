//! An animated mesh's frame on the three paths a frame can take to the pattern renderer, timed
//! on one device in one run, with the bytes each uploads:
//!
//! 1. **CPU nets**: the CPU poses the coarse mesh (`Poser::pose_into`), builds its nets
//!    (`Plan::update`) and uploads them (`PatternRenderer::update`);
//! 2. **GPU nets from the caller's buffer**: the caller's coarse vertices are already on the
//!    GPU (here the CPU's pose, written as an engine's skinning would leave them: its own
//!    upload, counted apart); `GpuNetBuilder` builds the nets from that buffer;
//! 3. **GPU skinning**: `GpuSkinner` poses the mesh from the frame's deform matrices and
//!    morph weights (its only upload), `GpuNetBuilder` builds the nets from its output.
//!
//! Each frame is drawn and awaited; the median of the frames after a warm-up is reported.

use tessella_core::animation::Poser;
use tessella_core::refine::Plan;
use tessella_core::{RefineOptions, Scheme};
use tessella_gpu::{
    CoarseInput, CoarseStream, GpuContext, GpuError, GpuNetBuilder, GpuSkinner, PatternRenderer,
};
use tessella_view::{scene_uniforms, Appearance, RenderOptions, Target};
use web_time::Instant;

/// The three paths.
pub const PATHS: [&str; 3] = [
    "CPU nets",
    "GPU nets from the caller's buffer",
    "GPU skinning",
];

/// One path at one level.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimatedPathRow {
    pub adapter: String,
    pub path: &'static str,
    pub level: u32,
    pub coarse_triangles: usize,
    /// Median milliseconds a frame: pose, nets, upload and the draw, awaited.
    pub frame_ms: f64,
    /// Bytes tessella uploads a frame (the last frame's).
    pub tessella_bytes: u64,
    /// Bytes the caller itself uploads a frame for the path (its coarse vertices, on path 2).
    pub caller_bytes: u64,
}

/// The three paths for `clip` of `poser`, at each of `levels`, `frames` frames of 1/30 s
/// each, drawn at `size`, PN triangles.
pub fn animated_paths(
    ctx: &GpuContext,
    poser: &Poser,
    clip: usize,
    levels: &[u32],
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<AnimatedPathRow>, GpuError> {
    let bad = |e: tessella_core::AnimationError| GpuError::BadOption(e.to_string());
    let rest = poser.mesh(None, 0.0).map_err(bad)?;
    let options = RenderOptions {
        size,
        ..Default::default()
    };
    let target = Target::new(ctx, size)?;
    let look = Appearance::new(ctx, Target::FORMATS);
    let vertices = poser.vertex_count();
    // The caller's buffer on path 2: position xyz, normal xyz a vertex (24 bytes).
    let caller = ctx.buffer_init(
        "caller's coarse vertices",
        &vec![0; vertices * 24],
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    );
    let caller_input = CoarseInput {
        positions: CoarseStream {
            buffer: &caller,
            offset: 0,
            stride: 24,
            first: 0,
        },
        normals: CoarseStream {
            buffer: &caller,
            offset: 0,
            stride: 24,
            first: 12,
        },
    };
    let mut skinner = GpuSkinner::new(ctx, poser)?;
    let mut positions = vec![[0.0; 3]; vertices];
    let mut normals = vec![[0.0; 3]; vertices];
    let mut interleaved: Vec<[f32; 6]> = vec![[0.0; 6]; vertices];
    let mut rows = Vec::new();
    for &level in levels {
        let (plan, mut frame) = Plan::with_frame(&rest, &RefineOptions::new(Scheme::Pn, level))?;
        let renderer =
            PatternRenderer::new(ctx, &plan, &frame, &look.shading(), &options.displacement)?;
        look.set_uniforms(&scene_uniforms(&rest, &options, 0.0));
        let builder = GpuNetBuilder::new(ctx, plan.surface())?;
        for path in PATHS {
            let (mut times, mut tessella_bytes, mut caller_bytes) = (Vec::new(), 0, 0);
            for k in 0..=frames {
                let time = k as f32 / 30.0;
                let start = Instant::now();
                let mut encoder = ctx.device.create_command_encoder(&Default::default());
                tessella_bytes = match path {
                    "CPU nets" => {
                        poser
                            .pose_into(Some(clip), time, &mut positions, Some(&mut normals))
                            .map_err(bad)?;
                        plan.update(&mut frame, &positions, Some(&normals))?;
                        renderer.update(&frame)?
                    }
                    "GPU nets from the caller's buffer" => {
                        poser
                            .pose_into(Some(clip), time, &mut positions, Some(&mut normals))
                            .map_err(bad)?;
                        for ((out, p), n) in interleaved.iter_mut().zip(&positions).zip(&normals) {
                            *out = [p[0], p[1], p[2], n[0], n[1], n[2]];
                        }
                        let bytes: &[u8] = bytemuck::cast_slice(&interleaved);
                        ctx.queue.write_buffer(&caller, 0, bytes);
                        caller_bytes = bytes.len() as u64;
                        builder.record(&mut encoder, caller_input, renderer.nets_target()?)?
                    }
                    _ => {
                        let bytes = skinner.update(poser, Some(clip), time)?;
                        skinner.record(&mut encoder)?;
                        bytes
                            + builder.record(
                                &mut encoder,
                                skinner.output(),
                                renderer.nets_target()?,
                            )?
                    }
                };
                ctx.submit(encoder)?;
                target.draw(ctx, options.background, |pass| look.draw(pass, &renderer))?;
                if k > 0 {
                    times.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
            times.sort_by(f64::total_cmp);
            rows.push(AnimatedPathRow {
                adapter: ctx.adapter_label(),
                path,
                level,
                coarse_triangles: rest.face_count(),
                frame_ms: times[times.len() / 2],
                tessella_bytes,
                caller_bytes,
            });
        }
    }
    Ok(rows)
}

/// Markdown table of [`animated_paths`] rows.
pub fn animated_paths_table(rows: &[AnimatedPathRow]) -> String {
    let mut s = String::from(
        "| adapter | path | level | coarse triangles | frame ms | bytes uploaded by tessella | by the caller |\n|---|---|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.2} | {} | {} |\n",
            r.adapter,
            r.path,
            r.level,
            r.coarse_triangles,
            r.frame_ms,
            r.tessella_bytes,
            r.caller_bytes
        );
    }
    s
}
