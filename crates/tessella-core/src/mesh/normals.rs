//! Vertex normals: normalising given ones, computing missing ones.

use crate::error::MeshError;
use glam::DVec3;

/// Normalises given normals; a zero-length or non-finite normal is an error naming its vertex.
pub fn normalized(normals: Vec<[f32; 3]>) -> Result<Vec<[f32; 3]>, MeshError> {
    normals
        .into_iter()
        .enumerate()
        .map(|(vertex, n)| {
            if !n.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFiniteNormal { vertex, value: n });
            }
            let v = DVec3::from(n.map(f64::from));
            let len = v.length();
            if len == 0.0 || !len.is_finite() {
                return Err(MeshError::ZeroNormal { vertex });
            }
            Ok((v / len).as_vec3().into())
        })
        .collect()
}

/// Angle-weighted vertex normals (Thürmer & Wüthrich 1998): each face adds its unit normal times
/// the angle of its corner at the vertex. The weights do not depend on how a region is split into
/// triangles, unlike area or uniform weights. Computed in f64.
///
/// Normals are summed per *position*: vertices that share a position (split for UVs, say) get
/// the same smooth normal, so computed normals never open a seam. A vertex no triangle uses, or
/// whose faces cancel, gets +Z.
pub fn angle_weighted(positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> Vec<[f32; 3]> {
    let position_id = super::topology::position_ids(positions);
    let mut sum = vec![DVec3::ZERO; positions.len()];
    let p = |i: u32| DVec3::from(positions[i as usize].map(f64::from));
    for t in triangles {
        let [a, b, c] = t.map(p);
        let n = (b - a).cross(c - a).normalize_or_zero();
        for (k, &v) in t.iter().enumerate() {
            let here = [a, b, c][k];
            let e1 = [b, c, a][k] - here;
            let e2 = [c, a, b][k] - here;
            let angle = e1.angle_between(e2);
            if angle.is_finite() {
                sum[position_id[v as usize] as usize] += n * angle;
            }
        }
    }
    (0..positions.len())
        .map(|v| {
            let n = sum[position_id[v] as usize].normalize_or_zero();
            if n == DVec3::ZERO {
                [0.0, 0.0, 1.0]
            } else {
                n.as_vec3().into()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_corner_normal_points_along_diagonal() {
        // Three faces of a cube meeting at the origin, each split into two triangles with
        // different corner angles: angle weighting still gives the symmetric diagonal.
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 1.0],
            [1.0, 0.0, 1.0],
        ];
        // Outward normals -x, -y, -z (the corner is the cube's min corner).
        let triangles = vec![
            [0, 2, 4],
            [0, 4, 1],
            [0, 3, 5],
            [0, 5, 2],
            [0, 1, 6],
            [0, 6, 3],
        ];
        let n = angle_weighted(&positions, &triangles)[0];
        let expected = -1.0 / 3f32.sqrt();
        for c in n {
            assert!((c - expected).abs() < 1e-6, "{n:?}");
        }
    }
}
