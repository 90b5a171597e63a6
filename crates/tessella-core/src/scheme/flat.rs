//! The flat triangle, written as a cubic so it shares the evaluator with every other scheme.

use super::{cubic_from_quadratic, Corners};
use glam::Vec3;

/// `l1 P1 + l2 P2 + l3 P3 = sum li² Pi + sum_{i<j} li lj (Pi + Pj)`, degree-elevated.
pub fn control_points(c: &Corners) -> [Vec3; 10] {
    let p = c.p;
    cubic_from_quadratic(p, [p[0] + p[1], p[1] + p[2], p[2] + p[0]])
}
