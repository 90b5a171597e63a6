//! Curved PN triangles (Vlachos et al. 2001; GMR Appendix A and van Veen eq. (3), corrected as
//! in docs/formulas.md, Corrections to printed formulas).

use super::Corners;
use crate::scalar::{Real, V3};
use glam::Vec3;

/// The edge point near corner `i` on edge `i -> j`: `(2 Pi + Pj - w_ij Ni) / 3`,
/// `w_ij = (Pj - Pi) . Ni`; it lies in the tangent plane at `Pi`. For any [`Real`].
pub fn edge_point_of<T: Real>(pi: V3<T>, pj: V3<T>, ni: V3<T>) -> V3<T> {
    let w = (pj - pi).dot(ni);
    (pi * T::lit(2.0) + pj - ni * w) / T::lit(3.0)
}

/// The centre `b111 = E + (E - V) / 2`, `E` the mean of the six edge points, `V` of the corners.
pub(crate) fn centre(p: &[Vec3; 3], edge: &[Vec3; 6]) -> Vec3 {
    centre_of(&p.map(V3::from), &edge.map(V3::from)).into()
}

/// [`centre`] for any [`Real`]; the edge points are summed from zero, left to right.
pub fn centre_of<T: Real>(p: &[V3<T>; 3], edge: &[V3<T>; 6]) -> V3<T> {
    let e = edge.iter().fold(V3::zero(), |acc, &x| acc + x) / T::lit(6.0);
    let v = (p[0] + p[1] + p[2]) / T::lit(3.0);
    e + (e - v) * T::lit(0.5)
}

/// The ten cubic control points in [`crate::basis::CUBIC_ORDER`].
pub fn control_points(c: &Corners) -> [Vec3; 10] {
    points(c.p.map(V3::from), c.n.map(V3::from)).map(Vec3::from)
}

/// [`control_points`] for any [`Real`] (the CPU's `f32`, the shaders' generated code).
pub fn points<T: Real>(p: [V3<T>; 3], n: [V3<T>; 3]) -> [V3<T>; 10] {
    let edge = [
        edge_point_of(p[0], p[1], n[0]), // b210
        edge_point_of(p[1], p[0], n[1]), // b120
        edge_point_of(p[1], p[2], n[1]), // b021
        edge_point_of(p[2], p[1], n[2]), // b012
        edge_point_of(p[2], p[0], n[2]), // b102
        edge_point_of(p[0], p[2], n[0]), // b201
    ];
    let b111 = centre_of(&p, &edge);
    [
        p[0], p[1], p[2], edge[0], edge[1], edge[2], edge[3], edge[4], edge[5], b111,
    ]
}
