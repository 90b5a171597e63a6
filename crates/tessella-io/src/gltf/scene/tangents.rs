//! Tangents of the refined vertices: MikkTSpace (the algorithm glTF 2.0 names for tangents a
//! file leaves out; [`super::mikktspace`]) from the refined positions, normals and the normal
//! map's texture coordinates; without texture coordinates, the corners' tangents interpolated
//! and made orthogonal to the refined normal.

use super::carry::Origins;
use glam::Vec3;

/// Per-vertex tangents (xyz, handedness w) by MikkTSpace ([`super::mikktspace`]); a vertex no
/// triangle gives one keeps a unit tangent orthogonal to its normal.
pub(super) fn mikktspace(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[f32],
    triangles: &[[u32; 3]],
) -> Vec<[f32; 4]> {
    let uvs: &[[f32; 2]] = bytemuck::cast_slice(uvs);
    let tangents = super::mikktspace::generate(positions, normals, uvs, triangles)
        .into_iter()
        .map(|t| t.unwrap_or([1.0, 0.0, 0.0, 1.0]))
        .collect();
    orthonormal(tangents, normals)
}

/// The corners' tangents interpolated, their handedness from the nearest corner.
pub(super) fn interpolated(
    origins: &Origins,
    tangents: &[f32],
    normals: &[[f32; 3]],
) -> Vec<[f32; 4]> {
    let xyzw = origins.interpolate(tangents, 4);
    let nearest = origins.nearest();
    let out = xyzw
        .chunks_exact(4)
        .zip(nearest)
        .map(|(t, v)| {
            let w = tangents[v as usize * 4 + 3];
            [t[0], t[1], t[2], if w < 0.0 { -1.0 } else { 1.0 }]
        })
        .collect();
    orthonormal(out, normals)
}

/// Gram-Schmidt against the normal; any unit vector orthogonal to it where that leaves zero.
fn orthonormal(tangents: Vec<[f32; 4]>, normals: &[[f32; 3]]) -> Vec<[f32; 4]> {
    tangents
        .into_iter()
        .zip(normals)
        .map(|(t, n)| {
            let n = Vec3::from(*n);
            let v = Vec3::new(t[0], t[1], t[2]);
            let v = (v - n * n.dot(v))
                .try_normalize()
                .unwrap_or_else(|| n.any_orthonormal_vector());
            [v.x, v.y, v.z, if t[3] < 0.0 { -1.0 } else { 1.0 }]
        })
        .collect()
}
