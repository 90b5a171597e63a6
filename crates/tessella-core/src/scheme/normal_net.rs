//! Quadratic nets of control normals, weighted by `l1², l2², l3², l1 l2, l2 l3, l3 l1`.

use super::Corners;
use crate::scalar::{Real, V3};
use glam::Vec3;

/// Linear interpolation `sum li Ni = sum li² Ni + sum_{i<j} li lj (Ni + Nj)`.
pub fn linear(c: &Corners) -> [Vec3; 6] {
    linear_of(c.n.map(V3::from)).map(Vec3::from)
}

/// [`linear`] for any [`Real`].
pub fn linear_of<T: Real>(n: [V3<T>; 3]) -> [V3<T>; 6] {
    [n[0], n[1], n[2], n[0] + n[1], n[1] + n[2], n[2] + n[0]]
}

/// Vlachos' quadratic normals: `n_ij = normalize(Ni + Nj - v_ij (Pj - Pi))`,
/// `v_ij = 2 (Pj - Pi) . (Ni + Nj) / |Pj - Pi|²`: the average normal reflected across the plane
/// perpendicular to the edge, so an inflected edge gets an inflected normal.
pub fn quadratic(c: &Corners) -> [Vec3; 6] {
    quadratic_of(c.p.map(V3::from), c.n.map(V3::from)).map(Vec3::from)
}

/// [`quadratic`] for any [`Real`].
pub fn quadratic_of<T: Real>(p: [V3<T>; 3], n: [V3<T>; 3]) -> [V3<T>; 6] {
    let mid = |i: usize, j: usize| {
        let d = p[j] - p[i];
        let v = T::lit(2.0) * d.dot(n[i] + n[j]) / d.length_squared();
        (n[i] + n[j] - d * v).normalize_or_zero()
    };
    [n[0], n[1], n[2], mid(0, 1), mid(1, 2), mid(2, 0)]
}
