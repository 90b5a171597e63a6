//! The deformations `animate` plays: the coarse mesh moves, the GPU refines it again from its
//! new control nets alone (GMR Figure 1). The twist is [`tessella_core::samples::twist`]; the
//! bend is here.

use crate::params::Animation;
use tessella_core::Mesh;

/// The twist's largest angle, degrees, top against bottom.
pub const MAX_TWIST_DEGREES: f32 = 60.0;
/// The bend's largest angle, degrees, between the bottom's and the top's tangents.
pub const MAX_BEND_DEGREES: f32 = 45.0;
/// One back-and-forth of an animation, milliseconds.
pub const PERIOD_MS: f64 = 4000.0;

/// `mesh` bent about the Z axis (Barr 1984): its vertical extent curves into an arc of
/// `degrees` towards +X, the bottom (lowest Y) fixed; normals turn with the arc's tangent
/// (exact for the rotation, close under the bend's stretch, as the twist's).
pub fn bend(mesh: &Mesh, degrees: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let (lo, hi) = mesh.bounds();
    let height = (hi[1] - lo[1]).max(f32::MIN_POSITIVE);
    let x0 = 0.5 * (lo[0] + hi[0]);
    let curvature = degrees.to_radians() / height;
    if curvature.abs() < 1e-9 {
        return (mesh.positions().to_vec(), mesh.normals().to_vec());
    }
    let radius = 1.0 / curvature;
    let angle = |y: f32| curvature * (y - lo[1]);
    let positions = mesh
        .positions()
        .iter()
        .map(|&[x, y, z]| {
            let (s, c) = angle(y).sin_cos();
            let r = radius - (x - x0);
            [x0 + radius - r * c, lo[1] + r * s, z]
        })
        .collect();
    let normals = mesh
        .normals()
        .iter()
        .zip(mesh.positions())
        .map(|(&[nx, ny, nz], p)| {
            let (s, c) = angle(p[1]).sin_cos();
            [nx * c + ny * s, -nx * s + ny * c, nz]
        })
        .collect();
    (positions, normals)
}

/// A deformed frame's positions and normals, one each per coarse vertex.
pub type PositionsNormals = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// The positions and normals of `rest` under `animation` at `time_ms`: the angle swings as
/// `max × sin(2π t / PERIOD_MS)`. `None` for [`Animation::None`].
pub fn at(rest: &Mesh, animation: Animation, time_ms: f64) -> Option<PositionsNormals> {
    let swing = (time_ms / PERIOD_MS * std::f64::consts::TAU).sin() as f32;
    match animation {
        Animation::None => None,
        Animation::Twist => Some(tessella_core::samples::twist(
            rest,
            MAX_TWIST_DEGREES * swing,
        )),
        Animation::Bend => Some(bend(rest, MAX_BEND_DEGREES * swing)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::samples;

    #[test]
    fn the_bend_keeps_the_bottom_and_lengths_along_the_axis() {
        let mesh = samples::torus(1.0, 0.4, 12, 8);
        let (p, n) = bend(&mesh, 90.0);
        let (lo, hi) = mesh.bounds();
        let x0 = 0.5 * (lo[0] + hi[0]);
        let height = hi[1] - lo[1];
        for ((q, m), (&orig, &normal)) in p
            .iter()
            .zip(&n)
            .zip(mesh.positions().iter().zip(mesh.normals()))
        {
            // Normals stay unit and a point on the axis stays at its arc length from the
            // bottom: distance from the arc's centre is preserved.
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-4 || normal == [0.0; 3], "{len}");
            let radius = height / 90f32.to_radians();
            let centre = [x0 + radius, lo[1]];
            let before = radius - (orig[0] - x0);
            let after = ((q[0] - centre[0]).powi(2) + (q[1] - centre[1]).powi(2)).sqrt();
            assert!((before - after).abs() < 1e-4, "{before} {after}");
            assert_eq!(q[2], orig[2]);
        }
        // The top of the axis turned by 90 degrees: it points along +X now.
        let (same, _) = bend(&mesh, 0.0);
        assert_eq!(same, mesh.positions());
    }

    #[test]
    fn animations_swing_through_the_rest_pose() {
        let mesh = samples::creature();
        assert!(at(&mesh, Animation::None, 100.0).is_none());
        for a in [Animation::Twist, Animation::Bend] {
            let (p, _) = at(&mesh, a, 0.0).unwrap();
            assert_eq!(p, mesh.positions(), "{a:?} at t = 0");
            let (q, _) = at(&mesh, a, PERIOD_MS / 4.0).unwrap();
            assert_ne!(q, mesh.positions(), "{a:?} at a quarter period");
        }
    }
}
