//! Tangents of the refined vertices: MikkTSpace (the `bevy_mikktspace` crate, Bevy's maintained port, the algorithm glTF 2.0
//! names for tangents a file leaves out) from the refined positions, normals and the normal
//! map's texture coordinates; without texture coordinates, the corners' tangents interpolated
//! and made orthogonal to the refined normal.

use super::carry::Origins;
use glam::Vec3;

struct Geometry<'a> {
    positions: &'a [[f32; 3]],
    normals: &'a [[f32; 3]],
    uvs: &'a [f32],
    triangles: &'a [[u32; 3]],
    out: Vec<[f32; 4]>,
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.triangles[face][vert] as usize]
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.triangles[face][vert] as usize]
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let i = self.triangles[face][vert] as usize;
        [self.uvs[i * 2], self.uvs[i * 2 + 1]]
    }
    fn set_tangent(
        &mut self,
        tangent: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        // A vertex no face gives a tangent keeps its default (made orthogonal below).
        if let Some(t) = tangent {
            self.out[self.triangles[face][vert] as usize] = t.tangent_encoded();
        }
    }
}

/// Per-vertex tangents (xyz, handedness w) by MikkTSpace; `None` when it fails (no usable
/// triangle).
pub(super) fn mikktspace(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[f32],
    triangles: &[[u32; 3]],
) -> Option<Vec<[f32; 4]>> {
    let mut geometry = Geometry {
        positions,
        normals,
        uvs,
        triangles,
        out: vec![[1.0, 0.0, 0.0, 1.0]; positions.len()],
    };
    bevy_mikktspace::generate_tangents(&mut geometry).ok()?;
    // A vertex no triangle uses keeps a unit tangent orthogonal to its normal.
    Some(orthonormal(geometry.out, normals))
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
