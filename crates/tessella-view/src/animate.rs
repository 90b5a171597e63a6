//! A deforming coarse mesh rendered with the pattern: one [`Plan`] for the whole animation;
//! per frame [`Plan::update`] rebuilds the control nets (O(coarse triangles)) and
//! [`PatternRenderer::update`] uploads them (GMR section 3.1), never a refined vertex buffer.

use crate::render::{scene_uniforms, RenderOptions, Target};
use crate::save_png;
use std::path::{Path, PathBuf};
use tessella_core::refine::Plan;
use tessella_core::{Mesh, OutputLayout, RefineOptions};
use tessella_gpu::{GpuContext, GpuError, PatternRenderer};

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
    if frames == 0 {
        return Err(GpuError::BadOption(
            "an animation needs at least one frame".into(),
        ));
    }
    options.validate()?;
    let plan = Plan::new(mesh, refine)?;
    let mut frame = plan.frame(mesh)?;
    let renderer =
        PatternRenderer::new(ctx, &plan, &frame, &Target::FORMATS, &options.displacement)?;
    let target = Target::new(ctx, options.size)?;
    renderer.set_uniforms(&scene_uniforms(
        mesh,
        options,
        renderer.displacement_reach(),
    ));
    let welded = OutputLayout::new(mesh, Some(plan.topology()), refine.level, true)?;
    let mut stats = AnimationStats {
        frames,
        bytes_per_frame: 0,
        refined_bytes_per_frame: welded.output_bytes(false),
        paths: Vec::new(),
    };
    for k in 0..frames {
        let phase = k as f32 / frames as f32 * std::f32::consts::TAU;
        let (positions, normals) = twist_points(mesh, max_angle_degrees * phase.sin());
        plan.update(&mut frame, &positions, Some(&normals))?;
        stats.bytes_per_frame = renderer.update(&frame)?;
        target.draw(ctx, options.background, |pass| renderer.draw(pass))?;
        let picture = target.read(ctx)?;
        let path = out_dir.join(format!("frame_{k:03}.png"));
        save_png(&picture, &path)?;
        stats.paths.push(path);
    }
    Ok(stats)
}
