//! The steps of the evaluation glue that every backend takes after its sums, written once: the
//! "real" normal's test, the unit normal and the corner triangle's normal where that vanishes.
//! The CPU's kernels run them in `f32` ([`crate::refine::eval_point`]), as does the canonical
//! edge's normal; [`crate::shader::surface_normal`] traces them into the WGSL and GLSL that
//! the wgpu, OpenGL, wasm and Bevy evaluations call. What stays with each caller is its own:
//! where its weights and control points come from, and the normal net it sums where the real
//! normal fails.

use crate::scalar::{Noise, Real};

// `inline(always)` throughout: the SIMD kernels' target-feature copies call these in their
// vector loops, and a call there would not vectorise.

/// `a × b` in `glam::Vec3::cross`'s order of operations (so the `f32` bits are glam's).
#[inline(always)]
fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - b[1] * a[2],
        a[2] * b[0] - b[2] * a[0],
        a[0] * b[1] - b[0] * a[1],
    ]
}

/// `a · b`, summed left to right as `glam::Vec3::dot`.
#[inline(always)]
fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2])
}

/// `v / |v|` where `1 / |v|` is finite and positive, else `fallback` (`glam::Vec3::normalize_or`).
#[inline(always)]
fn normalize_or<T: Real>(v: [T; 3], fallback: [T; 3]) -> [T; 3] {
    let rcp = T::lit(1.0) / dot(v, v).sqrt();
    std::array::from_fn(|i| T::select_positive_finite(rcp, v[i] * rcp, fallback[i]))
}

/// The "real" normal `Du × Dv` of a patch point, or zero where the derivatives are (nearly)
/// parallel: `|Du × Dv|² > 10⁻¹² |Du|² |Dv|²` keeps it, so a degenerate corner (a cubic patch's
/// derivatives vanish or align there) takes the normal net instead of rounding noise.
#[inline(always)]
pub fn real_normal_of<T: Noise>(du: [T; 3], dv: [T; 3]) -> [T; 3] {
    let c = cross(du, dv);
    let c2 = dot(c, c);
    let bound = T::lit(1e-12) * dot(du, du) * dot(dv, dv);
    let zero = T::lit(0.0);
    [
        T::pick_gt(c2, bound, c[0], zero),
        T::pick_gt(c2, bound, c[1], zero),
        T::pick_gt(c2, bound, c[2], zero),
    ]
}

/// `n / |n|`, or zero where `1 / |n|` is not finite and positive (`glam::Vec3::normalize_or_zero`):
/// a patch point's unit normal from its real or normal-net normal, zero where that vanishes and
/// the caller takes [`corner_normal_of`].
#[inline(always)]
pub fn unit_or_zero_of<T: Real>(n: [T; 3]) -> [T; 3] {
    let zero = T::lit(0.0);
    normalize_or(n, [zero, zero, zero])
}

/// The unit normal of a patch's corner triangle `corners` (its first three control points, the
/// coarse triangle's corners), else `+Z`: the normal of a point whose own normal vanished.
#[inline(always)]
pub fn corner_normal_of<T: Real>(corners: [[T; 3]; 3]) -> [T; 3] {
    let [a, b, c] = corners;
    let sub = |p: [T; 3], q: [T; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let z = [T::lit(0.0), T::lit(0.0), T::lit(1.0)];
    normalize_or(cross(sub(b, a), sub(c, a)), z)
}

/// One step of a patch point's unit normal. Every evaluation takes [`NORMAL_STEPS`] in order:
/// the CPU's scalar kernel through [`normal_of`] (the SIMD kernels take the first steps in
/// vectors and hand it every point whose normal did not stand), the shaders through the glue
/// [`crate::shader::normal_glue`] prints from the same list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalStep {
    /// `Du × Dv` ([`real_normal_of`]) where the normal mode is `Real`; the normal starts zero.
    Real,
    /// The normal net's sum, where the normal is still zero (every mode but `Real`, and a
    /// `Real` point whose derivatives are parallel).
    NetWhereZero,
    /// The unit normal, or zero ([`unit_or_zero_of`]).
    Unit,
    /// The corner triangle's normal ([`corner_normal_of`]), where the unit normal is zero.
    CornerWhereZero,
}

/// The order of a patch point's normal fallbacks, written once.
pub const NORMAL_STEPS: [NormalStep; 4] = [
    NormalStep::Real,
    NormalStep::NetWhereZero,
    NormalStep::Unit,
    NormalStep::CornerWhereZero,
];

/// A patch point's unit normal by [`NORMAL_STEPS`]: `real` holds its derivatives where the
/// normal mode is `Real` (else `None`); `net` sums the normal net and `corners` gives the
/// corner triangle, each called only where its step needs it.
#[inline(always)]
pub fn normal_of(
    real: Option<([f32; 3], [f32; 3])>,
    net: impl FnOnce() -> [f32; 3],
    corners: impl FnOnce() -> [[f32; 3]; 3],
) -> [f32; 3] {
    let (mut net, mut corners) = (Some(net), Some(corners));
    let mut n = [0.0f32; 3];
    for step in NORMAL_STEPS {
        match step {
            NormalStep::Real => {
                if let Some((du, dv)) = real {
                    n = real_normal_of(du, dv);
                }
            }
            NormalStep::NetWhereZero => {
                if let (true, Some(net)) = (n == [0.0; 3], net.take()) {
                    n = net();
                }
            }
            NormalStep::Unit => n = unit_or_zero_of(n),
            NormalStep::CornerWhereZero => {
                if let (true, Some(corners)) = (n == [0.0; 3], corners.take()) {
                    n = corner_normal_of(corners());
                }
            }
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn vectors() -> Vec<[f32; 3]> {
        let mut v = vec![
            [0.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
            [1.0, 2.0, 3.0],
            [1e-22, 0.0, 0.0],
            [1e-30, 1e-30, 0.0],
            [3e38, 3e38, 0.0],
            [f32::NAN, 1.0, 0.0],
            [f32::INFINITY, 0.0, 0.0],
        ];
        let mut s = 0x2545_f491u32;
        for _ in 0..200 {
            let mut r = || {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                (s as f32 / u32::MAX as f32 - 0.5) * 4.0
            };
            v.push([r(), r(), r()]);
        }
        v
    }

    /// The test and the fallbacks as the kernel wrote them with glam before they were shared.
    #[test]
    fn the_shared_glue_gives_glams_bits() {
        let vs = vectors();
        for (i, &du) in vs.iter().enumerate() {
            let dv = vs[(i * 7 + 3) % vs.len()];
            let (a, b) = (Vec3::from(du), Vec3::from(dv));
            let c = a.cross(b);
            let glam_real = if c.length_squared() > 1e-12 * a.length_squared() * b.length_squared()
            {
                c
            } else {
                Vec3::ZERO
            };
            let ours = Vec3::from(real_normal_of(du, dv));
            assert_eq!(
                ours.to_array().map(f32::to_bits),
                glam_real.to_array().map(f32::to_bits)
            );
            // Parallel derivatives take no real normal.
            assert_eq!(real_normal_of(du, du.map(|x| 2.0 * x)), [0.0; 3]);

            let corners = [du, dv, vs[(i * 13 + 5) % vs.len()]];
            let [p, q, r] = corners.map(Vec3::from);
            let n = Vec3::from(vs[(i * 3 + 1) % vs.len()]);
            let unit = n.normalize_or_zero();
            let glam_unit = if unit == Vec3::ZERO {
                (q - p).cross(r - p).normalize_or(Vec3::Z)
            } else {
                unit
            };
            let unit_of = unit_or_zero_of(n.to_array());
            let ours = if unit_of == [0.0; 3] {
                corner_normal_of(corners)
            } else {
                unit_of
            };
            assert_eq!(
                ours.map(f32::to_bits),
                glam_unit.to_array().map(f32::to_bits)
            );
        }
    }

    /// `normal_of` takes the steps as the kernels spelled them, and asks for the net and the
    /// corners only where they are used.
    #[test]
    fn normal_of_takes_the_steps_in_order() {
        let vs = vectors();
        for (i, &du) in vs.iter().enumerate() {
            let dv = vs[(i * 7 + 3) % vs.len()];
            let net = vs[(i * 5 + 2) % vs.len()];
            let corners = [vs[(i * 3 + 1) % vs.len()], du, dv];
            for real in [None, Some((du, dv)), Some((du, du))] {
                let mut n = real.map_or([0.0; 3], |(a, b)| real_normal_of(a, b));
                let net_used = n == [0.0; 3];
                if net_used {
                    n = net;
                }
                let mut unit = unit_or_zero_of(n);
                let corner_used = unit == [0.0; 3];
                if corner_used {
                    unit = corner_normal_of(corners);
                }
                let (mut asked_net, mut asked_corners) = (false, false);
                let ours = normal_of(
                    real,
                    || {
                        asked_net = true;
                        net
                    },
                    || {
                        asked_corners = true;
                        corners
                    },
                );
                assert_eq!(ours.map(f32::to_bits), unit.map(f32::to_bits));
                assert_eq!((asked_net, asked_corners), (net_used, corner_used));
            }
        }
    }

    #[test]
    fn a_vanishing_normal_falls_back_to_the_corner_triangle_then_to_z() {
        let corners: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0]];
        assert_eq!(unit_or_zero_of([0.0f32; 3]), [0.0; 3]);
        assert_eq!(unit_or_zero_of([f32::NAN, 0.0, 0.0]), [0.0; 3]);
        assert_eq!(corner_normal_of(corners), [0.0, -1.0, 0.0]);
        assert_eq!(corner_normal_of([[1.0f32; 3]; 3]), [0.0, 0.0, 1.0]);
        let [x, y, z] = unit_or_zero_of([0.0f32, 3.0, 4.0]);
        assert!(x == 0.0 && (y - 0.6).abs() < 1e-7 && (z - 0.8).abs() < 1e-7);
    }
}
