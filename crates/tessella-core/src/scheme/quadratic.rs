//! Second-order (isoparametric P2) triangles: the finite-element solver's own curved geometry
//! ([`crate::mesh::quadratic`]). The 6-node map `Σ l_i (2 l_i − 1) P_i + Σ 4 l_i l_j M_ij` is the
//! quadratic Bézier patch with middle control points `Q_ij = 2 M_ij − (P_i + P_j)/2`; its
//! monomial mid coefficients (what [`super::cubic_from_quadratic`] takes) are
//! `m_ij = 2 Q_ij = 4 M_ij − (P_i + P_j)`. A linear face (no mid-edge nodes) is the flat
//! triangle.

use super::{flat, Corners};
use crate::mesh::Mesh;
use glam::Vec3;

/// The cubic net of face `f`: its P2 map when it has mid-edge nodes, else the flat triangle.
pub fn control_points(mesh: &Mesh, f: usize, c: &Corners) -> [Vec3; 10] {
    let Some(m) = mesh.face_mid_nodes(f) else {
        return flat::control_points(c);
    };
    // `cubic_from_quadratic` in f64, so the net is the element's map up to one rounding.
    let p = c.p.map(|x| x.as_dvec3());
    let mid = m.map(|i| Vec3::from(mesh.positions()[i as usize]).as_dvec3());
    let coef = |i: usize, j: usize, k: usize| 4.0 * mid[k] - (p[i] + p[j]);
    let m = [coef(0, 1, 0), coef(1, 2, 1), coef(2, 0, 2)];
    let q = m.map(|x| x * 0.5);
    let net = [
        p[0],
        p[1],
        p[2],
        (p[0] + 2.0 * q[0]) / 3.0,
        (p[1] + 2.0 * q[0]) / 3.0,
        (p[1] + 2.0 * q[1]) / 3.0,
        (p[2] + 2.0 * q[1]) / 3.0,
        (p[2] + 2.0 * q[2]) / 3.0,
        (p[0] + 2.0 * q[2]) / 3.0,
        (q[0] + q[1] + q[2]) / 3.0,
    ];
    net.map(|x| x.as_vec3())
}
