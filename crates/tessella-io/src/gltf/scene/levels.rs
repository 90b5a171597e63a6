//! The level of each primitive: one for all, or from a target edge length in world space.

use super::accessor::read_f32;
use super::{is_triangles, Scene};
use glam::{Mat4, Vec3};
use tessella_core::mesh::is_degenerate;

/// The largest level a target edge length may ask for (a level-64 primitive has 4096 times
/// its coarse triangles).
pub const MAX_SCENE_LEVEL: u32 = 64;

/// How each primitive's level is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum SceneLevels {
    /// The same level everywhere.
    Uniform(u32),
    /// Refined edges about this long in world space: each primitive gets
    /// `ceil(mean coarse edge × scale / length)`, clamped to `1..=MAX_SCENE_LEVEL`, where
    /// `scale` is the largest scale of the nodes that show its mesh (1 for a mesh no node
    /// shows). Scenes whose parts differ in size get levels that differ with them.
    MaxEdge(f32),
}

/// What a triangle primitive holds, and the level it gets.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PrimitiveSummary {
    pub id: super::PrimitiveId,
    pub triangles: usize,
    /// Zero-area triangles (a repeated corner, or corners on one line), refined flat.
    pub degenerate: usize,
    /// Mean coarse edge length in the mesh's own space.
    pub mean_edge: f64,
    pub level: u32,
}

/// Every triangle primitive, in order, with its level.
pub(super) fn summaries(
    scene: &Scene,
    levels: &SceneLevels,
) -> Result<Vec<PrimitiveSummary>, String> {
    let mut out = Vec::new();
    let scales = match levels {
        SceneLevels::MaxEdge(length) if !(length.is_finite() && *length > 0.0) => {
            return Err(format!(
                "the target edge length {length} is not a positive number"
            ));
        }
        SceneLevels::MaxEdge(_) => Some(mesh_scales(&scene.document)),
        SceneLevels::Uniform(0) => {
            return Err("level 0 is not a refinement; give 1 or more".into());
        }
        SceneLevels::Uniform(_) => None,
    };
    for mesh in scene.document.meshes() {
        for primitive in mesh.primitives() {
            if !is_triangles(primitive.mode()) {
                continue;
            }
            let id = (mesh.index(), primitive.index());
            let (triangles, degenerate, mean_edge) = shape(scene, &primitive)
                .map_err(|m| format!("mesh {} primitive {}: {m}", id.0, id.1))?;
            let level = match (levels, &scales) {
                (SceneLevels::MaxEdge(length), Some(scales)) => {
                    let world = mean_edge * scales[mesh.index()] as f64;
                    ((world / *length as f64).ceil() as u32).clamp(1, MAX_SCENE_LEVEL)
                }
                (SceneLevels::Uniform(n), _) => *n,
                _ => 1,
            };
            out.push(PrimitiveSummary {
                id,
                triangles,
                degenerate,
                mean_edge,
                level,
            });
        }
    }
    Ok(out)
}

/// Per mesh, the largest scale of the nodes that show it (1 where none does).
fn mesh_scales(document: &gltf::Document) -> Vec<f32> {
    let mut scales = vec![0.0f32; document.meshes().len()];
    let mut seen = vec![false; document.nodes().len()];
    let mut stack: Vec<(gltf::Node, Mat4)> = document
        .scenes()
        .flat_map(|s| s.nodes())
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            continue; // a node reached twice (a malformed hierarchy) counts once
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let scale = [world.x_axis, world.y_axis, world.z_axis]
                .iter()
                .map(|c| c.truncate().length())
                .fold(0.0f32, f32::max);
            scales[mesh.index()] = scales[mesh.index()].max(scale);
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    scales
        .into_iter()
        .map(|s| if s > 0.0 && s.is_finite() { s } else { 1.0 })
        .collect()
}

/// The primitive's triangle count, its degenerate triangles and the mean length of its edges
/// (each triangle's three, in its own space; degenerate ones too).
fn shape(scene: &Scene, primitive: &gltf::Primitive) -> Result<(usize, usize, f64), String> {
    let position = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or("no POSITION attribute")?;
    let p = read_f32(&position, &scene.buffers)?;
    let n = p.len() / 3;
    let corners: Vec<u32> = match primitive.indices() {
        Some(a) => super::accessor::read_u32(&a, &scene.buffers)?,
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = corners.iter().find(|&&i| i as usize >= n) {
        return Err(format!("uses vertex {bad} but has only {n} vertices"));
    }
    let triangles = super::super::data::assemble(primitive.mode(), &corners)?;
    let positions: Vec<[f32; 3]> = p.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let (mut sum, mut count, mut degenerate) = (0.0f64, 0usize, 0usize);
    for t in &triangles {
        let [a, b, c] = t.map(|i| Vec3::from(positions[i as usize]));
        if is_degenerate(&positions, *t) {
            degenerate += 1;
        }
        for (u, v) in [(a, b), (b, c), (c, a)] {
            let d = u.distance(v) as f64;
            if d.is_finite() {
                sum += d;
                count += 1;
            }
        }
    }
    let mean = if count == 0 { 0.0 } else { sum / count as f64 };
    Ok((triangles.len(), degenerate, mean))
}
