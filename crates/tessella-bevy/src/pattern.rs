//! What Bevy draws for a tessellated entity: the refinement pattern (one triangle
//! pre-tessellated at the level) repeated for a run of coarse triangles, stored once a level
//! and drawn once per run of the entity's triangles, and
//! the patch buffers its vertex stage reads; and the conversions between Bevy's meshes and
//! tessella's.

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::storage::{ShaderBuffer, ShaderBufferData};
use std::sync::Arc;
use tessella_core::refine::{Frame, Plan};
use tessella_core::{NormalMode, RefineOptions};

/// A tessellated mesh's GPU data: the patch group's buffers and what a deforming mesh rebuilds
/// them with.
pub struct Built {
    /// The patch group's seven bindings (tessella-gpu's
    /// [`patch_bytes`](tessella_gpu::wgsl::patch_bytes)), then the coarse texture coordinates
    /// (binding 107: three `vec2<f32>` a coarse triangle).
    pub bytes: [Vec<u8>; 8],
    pub normal_mode: NormalMode,
    /// Per coarse triangle, a box around its patch: its control points' (a patch lies in its
    /// control net's convex hull).
    pub boxes: Vec<(Vec3, Vec3)>,
    /// What was built once for the mesh's topology: a deforming mesh builds each frame's nets
    /// with it.
    pub plan: Arc<Plan>,
    /// The coarse mesh and its nets as built.
    pub frame: Frame<'static>,
}

/// Reads a Bevy triangle mesh as a tessella mesh (positions, normals if any, triangles).
pub fn to_tessella_mesh(mesh: &Mesh) -> Result<tessella_core::Mesh, String> {
    read_mesh(mesh, true)
}

/// [`to_tessella_mesh`], with the mesh's normals or with tessella's computed ones (smooth
/// across vertices that share a position).
pub(crate) fn read_mesh(mesh: &Mesh, keep_normals: bool) -> Result<tessella_core::Mesh, String> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err("tessella refines triangle lists".into());
    }
    let positions: Vec<[f32; 3]> = match mesh.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) => p.clone(),
        _ => return Err("the mesh has no Float32x3 positions".into()),
    };
    let normals = match mesh.attribute(Mesh::ATTRIBUTE_NORMAL) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(n)) if keep_normals => Some(n.clone()),
        _ => None,
    };
    let indices: Vec<u32> = match mesh.indices() {
        Some(i) => i.iter().map(|i| i as u32).collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    tessella_core::Mesh::new(positions, normals, None, triangles).map_err(|e| e.to_string())
}

/// A Bevy mesh of a tessella mesh (what the examples load files into).
pub fn to_bevy_mesh(mesh: &tessella_core::Mesh) -> Mesh {
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, mesh.positions().to_vec())
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, mesh.normals().to_vec())
    .with_inserted_indices(Indices::U32(
        mesh.triangles().iter().flatten().copied().collect(),
    ))
}

/// Builds the patch buffers of `mesh` refined with `options` (uniform levels: the one
/// pattern all triangles share).
pub fn build(mesh: &tessella_core::Mesh, options: &RefineOptions) -> Result<Built, String> {
    let plan = Plan::new(mesh, options).map_err(|e| e.to_string())?;
    let frame = plan.frame(mesh.clone()).map_err(|e| e.to_string())?;
    let [b0, b1, b2, b3, b4, b5, b6] =
        tessella_gpu::wgsl::patch_bytes(&plan, &frame).map_err(|e| e.to_string())?;
    let uvs = face_uv_bytes(mesh, plan.triangles());
    Ok(Built {
        bytes: [b0, b1, b2, b3, b4, b5, b6, uvs],
        normal_mode: plan.normal_mode(),
        boxes: face_boxes(&frame),
        plan: Arc::new(plan),
        frame,
    })
}

/// Per coarse triangle, its corners' texture coordinates (the barycentric corners (0, 0),
/// (1, 0), (0, 1) for a mesh without them): the vertex stage interpolates them linearly at
/// each pattern point.
fn face_uv_bytes(mesh: &tessella_core::Mesh, triangles: &[[u32; 3]]) -> Vec<u8> {
    let mut uvs: Vec<[f32; 2]> = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        match mesh.uvs() {
            Some(uv) => uvs.extend(t.map(|i| uv[i as usize])),
            None => uvs.extend([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        }
    }
    bytemuck::cast_slice(&uvs).to_vec()
}

/// Vertices a run's mesh holds at most (when one triangle's pattern has fewer): large enough
/// that a draw's fixed costs vanish beside its vertices, small enough that the one mesh of a
/// full run is a few MB shared by every tessellated entity at that level.
pub const RUN_VERTICES: usize = 1 << 16;

/// Coarse triangles a run draws at most with a pattern of `points` vertices: as many as fit in
/// [`RUN_VERTICES`], at least one.
pub fn run_faces(points: usize) -> usize {
    (RUN_VERTICES / points.max(1)).max(1)
}

/// The refinement pattern repeated for `faces` consecutive coarse triangles, as a Bevy mesh: a
/// child entity draws it with its first triangle in its `MeshTag`. Each vertex's `UV_0` is its
/// barycentric `(l2, l3)` and its `UV_1` is `(pattern vertex, triangle in the run)` (exact in
/// `f32`); position and normal are the unit triangle's (unused by the shaders, which evaluate
/// the patch; kept so the mesh is an ordinary Bevy mesh).
pub fn pattern_mesh(pattern: &tessella_core::Pattern, faces: usize) -> Result<Mesh, String> {
    let n = pattern.points.len();
    let total = n.checked_mul(faces).filter(|&t| t < 1 << 24 && faces > 0);
    let Some(total) = total else {
        return Err(format!(
            "{faces} triangles of {n} pattern vertices: a run holds 1 to 2^24 vertices"
        ));
    };
    let mut uvs = Vec::with_capacity(total);
    let mut ids = Vec::with_capacity(total);
    for face in 0..faces {
        for (v, l) in pattern.points.iter().enumerate() {
            uvs.push([l[1] as f32, l[2] as f32]);
            ids.push([v as f32, face as f32]);
        }
    }
    let indices = (0..faces as u32)
        .flat_map(|face| {
            pattern
                .triangles
                .iter()
                .flatten()
                .map(move |&i| i + face * n as u32)
        })
        .collect();
    Ok(patch_point_mesh(uvs, ids, indices))
}

/// A mesh of patch points: per vertex its barycentric `(l2, l3)` (`UV_0`) and its `(pattern
/// vertex, triangle)` (`UV_1`); position and normal are the unit triangle's at that
/// barycentric (placeholders the shaders do not read, kept so the mesh is an ordinary Bevy
/// mesh).
fn patch_point_mesh(uvs: Vec<[f32; 2]>, ids: Vec<[f32; 2]>, indices: Vec<u32>) -> Mesh {
    let positions: Vec<[f32; 3]> = uvs.iter().map(|u| [u[0], u[1], 0.0]).collect();
    let normals = vec![[0.0f32, 0.0, 1.0]; uvs.len()];
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
    // StandardMaterial's shaders read UV_0 whenever a mesh has UV channels.
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_1, ids)
    .with_inserted_indices(Indices::U32(indices))
}

/// Vertices a welded mesh holds at most: at 40 bytes a vertex, 160 MB, inside the 256 MiB a
/// WebGPU buffer may hold by default. A mesh with more is drawn in runs.
pub const WELDED_VERTICES: usize = 1 << 22;

/// The refined surface's welded topology as a Bevy mesh, drawn by one child entity with
/// `MeshTag` 0: one vertex per refined vertex (each shared edge and corner point once, as
/// [`Plan::write_indices`] weld them), its `UV_1` the pattern vertex and the coarse triangle that
/// owns it ([`Plan::origin`]), its `UV_0` that pattern vertex's barycentric. The vertex stage
/// evaluates each refined vertex once, as it would read a static mesh's.
pub fn welded_mesh(plan: &Plan) -> Result<Mesh, String> {
    welded_mesh_of(plan, welded_points(plan)?)
}

/// The refined surface as a Bevy mesh of its own for [`crate::TessellaDraw::Mesh`]: the welded
/// topology with `POSITION` and `NORMAL` (placeholders, which the per-frame compute pass
/// overwrites in Bevy's vertex buffer) and `UV_0` the coarse texture coordinates interpolated at
/// each vertex (as `coarse_uv` does in the vertex stages: `face_uvs` three a coarse triangle);
/// 32 bytes a vertex, in Bevy's order (position, normal, uv). Also each vertex's
/// `(pattern vertex, owning triangle)`, for the compute pass's origins.
pub(crate) fn vertex_mesh(
    plan: &Plan,
    face_uvs: &[[f32; 2]],
) -> Result<(Mesh, Vec<[f32; 2]>), String> {
    let (bary, ids) = welded_points(plan)?;
    let uvs: Vec<[f32; 2]> = bary
        .iter()
        .zip(&ids)
        .map(|(&[l2, l3], &[_, face])| {
            let corner = |k: usize| {
                let uv = face_uvs.get(3 * face as usize + k).copied();
                Vec2::from(uv.unwrap_or_default())
            };
            let uv = corner(0) * (1.0 - l2 - l3) + corner(1) * l2 + corner(2) * l3;
            uv.to_array()
        })
        .collect();
    let mut indices = vec![[0u32; 3]; plan.triangle_count()];
    plan.write_indices(&mut indices)
        .map_err(|e| e.to_string())?;
    let n = uvs.len();
    let mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; n])
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; n])
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_indices(Indices::U32(indices.into_iter().flatten().collect()));
    Ok((mesh, ids))
}

/// Bytes a vertex of [`vertex_mesh`] takes in Bevy's vertex buffer: position (3 floats), then
/// normal (3), as the compute pass writes them, then uv (2), which it leaves alone.
pub(crate) const VERTEX_MESH_STRIDE: u64 = 32;

/// [`welded_mesh`] with its vertex attributes already found ([`welded_points`]).
pub(crate) fn welded_mesh_of(plan: &Plan, (uvs, ids): WeldedPoints) -> Result<Mesh, String> {
    // Written here, not `Plan::indices` (which the plan would keep for its lifetime).
    let mut indices = vec![[0u32; 3]; plan.triangle_count()];
    plan.write_indices(&mut indices)
        .map_err(|e| e.to_string())?;
    let indices = indices.into_iter().flatten().collect();
    Ok(patch_point_mesh(uvs, ids, indices))
}

/// The welded mesh's vertex attributes: per refined vertex, its barycentric `(l2, l3)` and its
/// `(pattern vertex, owning triangle)`, as `f32` pairs.
pub(crate) type WeldedPoints = (Vec<[f32; 2]>, Vec<[f32; 2]>);

/// [`welded_mesh`]'s `UV_0` and `UV_1`, in the plan's vertex order.
pub(crate) fn welded_points(plan: &Plan) -> Result<WeldedPoints, String> {
    let pattern = plan.pattern();
    let n = plan.vertex_count();
    if n > WELDED_VERTICES || plan.face_count() >= 1 << 24 {
        return Err(format!(
            "{n} refined vertices of {} triangles: over the {WELDED_VERTICES} a welded mesh holds",
            plan.face_count()
        ));
    }
    // Each pattern point by its barycentric's f32 bits: the origin's barycentrics are the
    // pattern's points in their owner's corner order.
    let key = |l1: f32, l2: f32| (l1.to_bits(), l2.to_bits());
    let points: std::collections::HashMap<(u32, u32), u32> = pattern
        .points
        .iter()
        .enumerate()
        .map(|(v, l)| (key(l[1] as f32, l[2] as f32), v as u32))
        .collect();
    let (faces, bary) = plan.origin();
    let mut uvs = Vec::with_capacity(n);
    let mut ids = Vec::with_capacity(n);
    for (face, l) in faces.iter().zip(&bary) {
        let Some(&v) = points.get(&key(l[1], l[2])) else {
            return Err(format!(
                "a refined vertex at {l:?} of triangle {face} is no point of the pattern"
            ));
        };
        uvs.push([l[1], l[2]]);
        ids.push([v as f32, *face as f32]);
    }
    Ok((uvs, ids))
}

/// The box around a run of coarse triangles, from each triangle's box (its net's).
pub fn run_box(boxes: &[(Vec3, Vec3)]) -> (Vec3, Vec3) {
    boxes.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), (l, h)| (lo.min(*l), hi.max(*h)),
    )
}

/// Per coarse triangle, the box of its control points, which holds its patch.
pub fn face_boxes(frame: &Frame) -> Vec<(Vec3, Vec3)> {
    let nets = frame.nets();
    let per_face = nets.points.len() / nets.len().max(1);
    nets.points
        .chunks_exact(per_face.max(1))
        .map(|points| {
            points.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
            )
        })
        .collect()
}

/// The bytes a storage binding holds: `bytes`, grown to at least 16 and to a multiple of 4 (an
/// empty binding is invalid; the shader never reads past the data).
pub(crate) fn padded(bytes: &[u8]) -> Vec<u8> {
    let mut data = bytes.to_vec();
    data.resize(data.len().max(16).next_multiple_of(4), 0);
    data
}

/// Replaces a storage buffer's contents by `bytes` of the same padded size: Bevy then writes
/// them into the buffer it has (no new buffer, no new bind group). Returns the bytes handed
/// over.
pub(crate) fn rewrite(buffer: &mut ShaderBuffer, bytes: &[u8]) -> u64 {
    let data = padded(bytes);
    let len = data.len() as u64;
    buffer.data = ShaderBufferData::Initialized {
        data: data.into(),
        buffer_size: len,
    };
    len
}

pub(crate) fn storage(buffers: &mut Assets<ShaderBuffer>, bytes: &[u8]) -> Handle<ShaderBuffer> {
    buffers.add(ShaderBuffer::new(
        padded(bytes),
        RenderAssetUsages::RENDER_WORLD,
    ))
}
