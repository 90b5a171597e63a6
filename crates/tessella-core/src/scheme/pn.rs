//! Curved PN triangles (Vlachos et al. 2001; GMR Appendix A and van Veen eq. (3), corrected as
//! in docs/formulas.md, Corrections to printed formulas).

use super::Corners;
use glam::Vec3;

/// The edge point near corner `i` on edge `i -> j`: `(2 Pi + Pj - w_ij Ni) / 3`,
/// `w_ij = (Pj - Pi) . Ni`; it lies in the tangent plane at `Pi`.
pub(crate) fn edge_point(pi: Vec3, pj: Vec3, ni: Vec3) -> Vec3 {
    let w = (pj - pi).dot(ni);
    (2.0 * pi + pj - w * ni) / 3.0
}

/// The centre `b111 = E + (E - V) / 2`, `E` the mean of the six edge points, `V` of the corners.
pub(crate) fn centre(p: &[Vec3; 3], edge: &[Vec3; 6]) -> Vec3 {
    let e = edge.iter().copied().sum::<Vec3>() / 6.0;
    let v = (p[0] + p[1] + p[2]) / 3.0;
    e + (e - v) * 0.5
}

/// The ten cubic control points in [`crate::basis::CUBIC_ORDER`].
pub fn control_points(c: &Corners) -> [Vec3; 10] {
    let Corners { p, n } = c;
    let edge = [
        edge_point(p[0], p[1], n[0]), // b210
        edge_point(p[1], p[0], n[1]), // b120
        edge_point(p[1], p[2], n[1]), // b021
        edge_point(p[2], p[1], n[2]), // b012
        edge_point(p[2], p[0], n[2]), // b102
        edge_point(p[0], p[2], n[0]), // b201
    ];
    let b111 = centre(p, &edge);
    [
        p[0], p[1], p[2], edge[0], edge[1], edge[2], edge[3], edge[4], edge[5], b111,
    ]
}
