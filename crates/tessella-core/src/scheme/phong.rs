//! Phong tessellation (Boubekeur & Alexa 2008; the FEM poster's equations (1), (2), with the
//! parenthesis fixed as in docs/formulas.md, Corrections to printed formulas).

use super::{cubic_from_quadratic, Corners};
use crate::scalar::{Real, V3};
use glam::Vec3;

/// `pi_i(q) = q - ((q - Pi) . Ni) Ni`: `q` projected onto the tangent plane at corner `i`.
fn project<T: Real>(q: V3<T>, p: V3<T>, n: V3<T>) -> V3<T> {
    q - n * (q - p).dot(n)
}

/// `p_alpha = (1 - alpha) p_flat + alpha p*`, with
/// `p* = sum li² Pi + sum_{i<j} li lj (pi_i(Pj) + pi_j(Pi))`. Both are quadratics with the same
/// corner terms, so the mid coefficients blend: `m_ij = (1-alpha)(Pi + Pj) + alpha (pi_i(Pj) + pi_j(Pi))`.
pub fn control_points(c: &Corners, alpha: f32) -> [Vec3; 10] {
    points(c.p.map(V3::from), c.n.map(V3::from), alpha).map(Vec3::from)
}

/// [`control_points`] for any [`Real`] (the CPU's `f32`, the shaders' generated code).
pub fn points<T: Real>(p: [V3<T>; 3], n: [V3<T>; 3], alpha: T) -> [V3<T>; 10] {
    let mid = |i: usize, j: usize| {
        let flat = p[i] + p[j];
        let phong = project(p[j], p[i], n[i]) + project(p[i], p[j], n[j]);
        flat + (phong - flat) * alpha
    };
    cubic_from_quadratic(p, [mid(0, 1), mid(1, 2), mid(2, 0)])
}
