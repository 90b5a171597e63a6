//! A deforming coarse mesh rendered with the pattern: per frame only the control nets are
//! re-uploaded (GMR section 3.1), never a refined vertex buffer.

use crate::context::GpuContext;
use crate::error::GpuError;
use crate::render::{nets_for, scene_uniforms, PatternScene, RenderOptions, Target};
use crate::save_png;
use std::path::{Path, PathBuf};
use tessella_core::{Mesh, OutputLayout, RefineOptions};

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

/// `mesh` twisted about the vertical (Y) axis: a point at height `y` turns by
/// `angle_degrees × (y - centre) / height`, normals turn with it.
pub fn twist(mesh: &Mesh, angle_degrees: f32) -> Result<Mesh, GpuError> {
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
    // twist's shear; good enough for shading a demo, and renormalised by Mesh::new.
    let normals = mesh
        .normals()
        .iter()
        .zip(mesh.positions())
        .map(|(&n, p)| turn(n, p[1]))
        .collect();
    Mesh::new(
        positions,
        Some(normals),
        mesh.uvs().map(|u| u.to_vec()),
        mesh.triangles().to_vec(),
    )
    .map_err(|e| GpuError::Refine(e.into()))
}

/// Renders `frames` pictures of `mesh` twisting back and forth by up to `max_angle_degrees`,
/// into `out_dir/frame_000.png`, ... Only the nets change between frames.
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
    let scene = PatternScene::new(ctx, mesh, refine, &options.displacement)?;
    let target = Target::new(ctx, options.size);
    // Framed on the rest pose so the camera stays put.
    let uniforms = scene_uniforms(mesh, options, refine.level, &scene.displacement_reach);
    let topology = mesh.topology();
    let layout = OutputLayout::new(mesh, Some(&topology), refine.level, true)?;
    let mut stats = AnimationStats {
        frames,
        bytes_per_frame: 0,
        refined_bytes_per_frame: layout.output_bytes(false),
        paths: Vec::new(),
    };
    for frame in 0..frames {
        let phase = frame as f32 / frames as f32 * std::f32::consts::TAU;
        let deformed = twist(mesh, max_angle_degrees * phase.sin())?;
        let (_, nets) = nets_for(&deformed, refine)?;
        stats.bytes_per_frame = scene.patches.update_nets(ctx, &nets);
        scene.draw(ctx, &target, &uniforms, options.background);
        ctx.check()?;
        let picture = target.read(ctx)?;
        let path = out_dir.join(format!("frame_{frame:03}.png"));
        save_png(&picture, &path)?;
        stats.paths.push(path);
    }
    Ok(stats)
}
