//! The flat triangle, written as a cubic so it shares the evaluator with every other scheme.

use super::{cubic_from_quadratic, Corners};
use crate::scalar::{Real, V3};
use glam::Vec3;

/// `l1 P1 + l2 P2 + l3 P3 = sum li² Pi + sum_{i<j} li lj (Pi + Pj)`, degree-elevated.
pub fn control_points(c: &Corners) -> [Vec3; 10] {
    points(c.p.map(V3::from)).map(Vec3::from)
}

/// [`control_points`] for any [`Real`] (the CPU's `f32`, the shaders' generated code).
pub fn points<T: Real>(p: [V3<T>; 3]) -> [V3<T>; 10] {
    cubic_from_quadratic(p, [p[0] + p[1], p[1] + p[2], p[2] + p[0]])
}
