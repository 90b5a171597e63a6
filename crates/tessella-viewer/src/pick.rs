//! Picking: the coarse vertex and edge under a pixel, by a ray cast against the coarse mesh on
//! the CPU with the view's own camera matrix (so what is picked is what is drawn there, up to
//! the curved surface's bulge over its coarse triangle).

use glam::{Mat4, Vec3, Vec4};

/// What [`Viewer::pick`](crate::Viewer::pick) found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Picked {
    /// The hit triangle's corner nearest the hit point (a vertex index of the mesh).
    pub vertex: u32,
    /// The hit triangle's edge nearest the hit point, its two vertex indices.
    pub edge: [u32; 2],
    /// The coarse triangle hit.
    pub face: u32,
}

/// The ray through `ndc` (x, y in -1..1, y up) of the camera `view_proj` (wgpu's 0..1
/// depth): its origin on the near plane and unit direction; `None` for a singular matrix.
pub fn ray(view_proj: &Mat4, ndc: [f32; 2]) -> Option<(Vec3, Vec3)> {
    let inverse = view_proj.inverse();
    let unproject = |z: f32| {
        let p = inverse * Vec4::new(ndc[0], ndc[1], z, 1.0);
        (p.w.abs() > f32::EPSILON).then(|| p.truncate() / p.w)
    };
    let (near, far) = (unproject(0.0)?, unproject(1.0)?);
    let dir = (far - near).try_normalize()?;
    near.is_finite().then_some((near, dir))
}

/// The nearest triangle of `positions`/`triangles` the ray `(origin, dir)` hits in front of
/// its origin (either side facing: a click on a back face still picks), with its corner and
/// edge nearest the hit (Möller-Trumbore, in f64 so thin triangles far away still hit).
pub fn pick(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    origin: Vec3,
    dir: Vec3,
) -> Option<Picked> {
    let (o, d) = (origin.as_dvec3(), dir.as_dvec3());
    let mut best: Option<(f64, usize, [f64; 3])> = None;
    for (f, t) in triangles.iter().enumerate() {
        let [a, b, c] = t.map(|v| Vec3::from(positions[v as usize]).as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-14 {
            continue;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let distance = e2.dot(q) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || distance <= 0.0 {
            continue;
        }
        if best.is_none_or(|(nearest, _, _)| distance < nearest) {
            best = Some((distance, f, [1.0 - u - v, u, v]));
        }
    }
    let (_, f, l) = best?;
    let t = triangles[f];
    // The nearest corner has the largest barycentric weight; the nearest edge is the one
    // opposite the smallest.
    let corner = (0..3).max_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap_or(0);
    let opposite = (0..3).min_by(|&i, &j| l[i].total_cmp(&l[j])).unwrap_or(0);
    Some(Picked {
        vertex: t[corner],
        edge: [t[(opposite + 1) % 3], t[(opposite + 2) % 3]],
        face: f as u32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_through_a_triangle_picks_its_nearest_corner_and_edge() {
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, -5.0],
        ];
        let triangles = [[0, 1, 2], [3, 1, 2]];
        // Near corner 1, near the edge 1-2 (x + y close to 1).
        let hit = pick(
            &positions,
            &triangles,
            Vec3::new(0.7, 0.25, 3.0),
            Vec3::NEG_Z,
        )
        .unwrap();
        assert_eq!((hit.face, hit.vertex, hit.edge), (0, 1, [1, 2]));
        // Pointing away: nothing.
        assert!(pick(&positions, &triangles, Vec3::new(0.2, 0.2, 3.0), Vec3::Z).is_none());
        // Outside both triangles.
        assert!(pick(
            &positions,
            &triangles,
            Vec3::new(2.0, 2.0, 3.0),
            Vec3::NEG_Z
        )
        .is_none());
    }

    #[test]
    fn rays_unproject_through_the_projected_point() {
        // The camera the viewer draws with (tessella render's), turned and zoomed.
        let options = tessella_view::RenderOptions {
            size: (300, 200),
            yaw: 40.0,
            pitch: 20.0,
            zoom: 1.3,
            ..Default::default()
        };
        let uniforms =
            tessella_view::scene_uniforms(&tessella_core::samples::icosphere(1), &options, 0.0);
        let m = Mat4::from_cols_array_2d(&uniforms.view_proj);
        let point = Vec3::new(0.3, -0.2, 0.4);
        let clip = m * point.extend(1.0);
        let (o, d) = ray(&m, [clip.x / clip.w, clip.y / clip.w]).unwrap();
        let closest = o + d * (point - o).dot(d);
        assert!(closest.distance(point) < 1e-4);
    }
}
