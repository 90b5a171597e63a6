//! PNG1's basis (Fünfzig, Müller, Hansford & Farin 2008, equation (6)): the 21 control points'
//! storage order and their weights at a barycentric point, cubic Bernstein polynomials times the
//! paper's rational blends. The scheme that builds the 21 points is `scheme::png1`; this
//! module only knows how they are combined, so the basis needs nothing from the scheme.

use super::BasisWeights;
use crate::scalar::{Dual, Real};
use glam::DVec3;

/// Number of PNG1 control points per patch.
pub const PNG1_LEN: usize = 21;

/// PNG1 control points in storage order:
///
/// - `0..3`: corners `b300 = P1, b030 = P2, b003 = P3`;
/// - `3..15`: the six edge-adjacent slots of [`crate::basis::CUBIC_ORDER`]
///   (`b210, b120, b021, b012, b102, b201`), each as *own* (built from the edge the slot lies
///   on, in the slot corner's tangent plane; shared with the neighbour) then *cross* (from the
///   other edge through that corner: the far corner's triangle carried into this corner's
///   plane). In the paper's names: `b_{P1:210}, b_{P3:210}, b_{P2:120}, b_{P3:120},
///   b_{P2:021}, b_{P1:021}, b_{P3:012}, b_{P1:012}, b_{P3:102}, b_{P2:102}, b_{P1:201},
///   b_{P2:201}`;
/// - `15..21`: centre candidates `b_{12:P1:111}, b_{12:P2:111}, b_{23:P2:111}, b_{23:P3:111},
///   b_{31:P3:111}, b_{31:P1:111}`.
pub const PNG1_ORDER: [&str; PNG1_LEN] = [
    "b300",
    "b030",
    "b003",
    "b210:P1",
    "b210:P3",
    "b120:P2",
    "b120:P3",
    "b021:P2",
    "b021:P1",
    "b012:P3",
    "b012:P1",
    "b102:P3",
    "b102:P2",
    "b201:P1",
    "b201:P2",
    "b111:12:P1",
    "b111:12:P2",
    "b111:23:P2",
    "b111:23:P3",
    "b111:31:P3",
    "b111:31:P1",
];

/// Own slot of edge `k` near its start corner, in `3..15` (the cross version is `+ 1`).
pub(crate) fn own_slot(k: usize, offset: usize) -> usize {
    3 + (4 * k + offset) % 12
}

// ---------------------------------------------------------------------------------------------
// Weights: cubic Bernstein × the paper's rational blends, with exact derivatives.

/// Weights of the 21 PNG1 control points at barycentric `l` (value, `Du`, `Dv`), in f64.
///
/// `S(l) = Σ B_ijk(l) b_ijk(l)` (equation (6)) with the edge slots blended by
/// `((1-x)² own + x² cross) / ((1-x)² + x²)`, `x` the barycentric coordinate of the corner
/// opposite the slot's edge (never singular), and the centre by Nielson's side-vertex blend.
/// The centre blend's denominators vanish only at the corners, where `B111 = 6 l1 l2 l3` and its
/// gradient vanish while the blend stays bounded (a convex combination): there the centre
/// weights are exactly zero, the limit. No NaN anywhere on the closed triangle.
///
/// ```
/// let w = tessella_core::basis::png1::weights([0.2, 0.3, 0.5]);
/// assert!((w.value.iter().sum::<f64>() - 1.0).abs() < 1e-14);
/// ```
pub fn weights(l: [f64; 3]) -> BasisWeights {
    let w = weights_dual(l);
    BasisWeights {
        value: w.iter().map(|d| d.v).collect(),
        du: w.iter().map(|d| d.du).collect(),
        dv: w.iter().map(|d| d.dv).collect(),
    }
}

fn weights_dual(l: [f64; 3]) -> [Dual<f64>; PNG1_LEN] {
    weights_of(l)
}

/// The 21 weights (value, `Du`, `Dv`) at `l` for any [`Real`]: the `f64` of [`weights`] and
/// the shaders' generated code ([`crate::shader`]) come from this one function. The centre
/// weights' two guards (`σ = 0` at the corners, a vanishing side-vertex denominator) are
/// selections, not branches, so a shader can run them as straight-line code.
pub fn weights_of<T: Real>(l: [T; 3]) -> [Dual<T>; PNG1_LEN] {
    let l = Dual::barycentric(l);
    let one = Dual::c(1.0);
    let zero = Dual::c(0.0);
    let mut w = [zero; PNG1_LEN];
    for i in 0..3 {
        w[i] = l[i] * l[i] * l[i];
    }
    for k in 0..3 {
        let (a, b, c) = (l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
        // Blend of the two versions of the slots on edge k, by the opposite coordinate.
        let own = (one - c) * (one - c);
        let cross = c * c;
        let den = own + cross;
        let (own, cross) = (own / den, cross / den);
        let near_a = (a * a * b).scale(3.0);
        let near_b = (a * b * b).scale(3.0);
        let (sa, sb) = (own_slot(k, 0), own_slot(k, 2));
        w[sa] = near_a * own;
        w[sa + 1] = near_a * cross;
        w[sb] = near_b * own;
        w[sb + 1] = near_b * cross;
    }
    // σ vanishes only at the corners, and the side-vertex denominator only where a = b = 0,
    // i.e. at a corner too: there the centre weights are exactly zero, the limit.
    let sigma = l[0] * l[1] + l[1] * l[2] + l[2] * l[0];
    let b111 = (l[0] * l[1] * l[2]).scale(6.0);
    for k in 0..3 {
        let (a, b) = (l[k], l[(k + 1) % 3]);
        let den = a + b - (a * b).scale(2.0);
        let t = b111 * (a * b) / sigma / den;
        let keep =
            |x: Dual<T>| Dual::select_nonzero(sigma.v, Dual::select_nonzero(den.v, x, zero), zero);
        w[15 + 2 * k] = keep(t * ((one - b) * a));
        w[16 + 2 * k] = keep(t * ((one - a) * b));
    }
    w
}

/// Evaluates a PNG1 net in f64 at `l`: `(position, Du, Dv)`.
pub fn eval_f64(net: &[DVec3; PNG1_LEN], l: [f64; 3]) -> (DVec3, DVec3, DVec3) {
    eval_with(net, &weights_dual(l))
}

/// The weights (value and derivatives) at the edge midpoints `(½, ½, 0)`, `(0, ½, ½)`,
/// `(½, 0, ½)`, computed once: every net's smoothed normals evaluate there
/// (`scheme::png1::smoothed_normal_net_of` through [`mid_weights`], [`eval_f64_at_mid`]), and
/// the rational weights cost more than the sum.
static MID_WEIGHTS: std::sync::LazyLock<[[Dual<f64>; PNG1_LEN]; 3]> =
    std::sync::LazyLock::new(|| {
        [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]].map(weights_dual)
    });

/// [`eval_f64`] at the midpoint of edge `k` (`k` to `k + 1`), with weights computed once: the
/// same bits as `eval_f64(net, mid)`.
pub fn eval_f64_at_mid(net: &[DVec3; PNG1_LEN], k: usize) -> (DVec3, DVec3, DVec3) {
    eval_with(net, &MID_WEIGHTS[k])
}

/// The weights (value, `Du`, `Dv`) at the midpoint of edge `k`, computed once.
pub(crate) fn mid_weights(k: usize) -> &'static [Dual<f64>; PNG1_LEN] {
    &MID_WEIGHTS[k]
}

fn eval_with(net: &[DVec3; PNG1_LEN], w: &[Dual<f64>; PNG1_LEN]) -> (DVec3, DVec3, DVec3) {
    let (mut p, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (wk, c) in w.iter().zip(net) {
        p += wk.v * *c;
        du += wk.du * *c;
        dv += wk.dv * *c;
    }
    (p, du, dv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::Basis;

    #[test]
    fn midpoint_evaluation_with_weights_kept_equals_eval_f64_bit_for_bit() {
        let net: [DVec3; PNG1_LEN] =
            std::array::from_fn(|i| DVec3::new(i as f64 * 0.37, (i * i) as f64 * 0.011, -0.5));
        let mids = [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]];
        let bits = |(p, du, dv): (DVec3, DVec3, DVec3)| {
            [p, du, dv].map(|v| v.to_array().map(f64::to_bits))
        };
        for (k, mid) in mids.into_iter().enumerate() {
            assert_eq!(
                bits(eval_f64_at_mid(&net, k)),
                bits(eval_f64(&net, mid)),
                "edge {k}"
            );
        }
    }

    #[test]
    fn weights_sum_to_one_and_match_finite_differences() {
        for l in [
            [0.2, 0.3, 0.5],
            [0.6, 0.3, 0.1],
            [0.01, 0.98, 0.01],
            [0.5, 0.5, 0.0],
        ] {
            let w = weights(l);
            assert!((w.value.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(w.du.iter().sum::<f64>().abs() < 1e-12);
            assert!(w.dv.iter().sum::<f64>().abs() < 1e-12);
            let h = 1e-6;
            // Central differences along u (l2 up, l1 down) and v (l3 up, l1 down).
            let fu = weights([l[0] - h, l[1] + h, l[2]]);
            let bu = weights([l[0] + h, l[1] - h, l[2]]);
            let fv = weights([l[0] - h, l[1], l[2] + h]);
            let bv = weights([l[0] + h, l[1], l[2] - h]);
            for k in 0..PNG1_LEN {
                let du = (fu.value[k] - bu.value[k]) / (2.0 * h);
                let dv = (fv.value[k] - bv.value[k]) / (2.0 * h);
                assert!(
                    (du - w.du[k]).abs() < 1e-7,
                    "{l:?} k={k}: {du} vs {}",
                    w.du[k]
                );
                assert!(
                    (dv - w.dv[k]).abs() < 1e-7,
                    "{l:?} k={k}: {dv} vs {}",
                    w.dv[k]
                );
            }
        }
    }

    #[test]
    fn collapsed_versions_give_the_cubic_bernstein_weights() {
        // When both versions of every slot coincide, PNG1 is the cubic patch.
        let map = [
            0, 1, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 9, 9, 9, 9,
        ];
        for l in [
            [1.0, 0.0, 0.0],
            [0.2, 0.3, 0.5],
            [0.0, 0.25, 0.75],
            [0.5, 0.5, 0.0],
        ] {
            let p = weights(l);
            let c = Basis::Cubic.weights(l);
            let mut sum = [[0.0; 3]; 10];
            for k in 0..PNG1_LEN {
                sum[map[k]][0] += p.value[k];
                sum[map[k]][1] += p.du[k];
                sum[map[k]][2] += p.dv[k];
            }
            for (j, s) in sum.iter().enumerate() {
                assert!((s[0] - c.value[j]).abs() < 1e-14, "{l:?} {j}");
                assert!((s[1] - c.du[j]).abs() < 1e-13, "{l:?} {j}");
                assert!((s[2] - c.dv[j]).abs() < 1e-13, "{l:?} {j}");
            }
        }
    }

    #[test]
    fn corner_limits_are_exact() {
        for c in 0..3 {
            let mut l = [0.0; 3];
            l[c] = 1.0;
            let w = weights(l);
            assert!(w
                .value
                .iter()
                .chain(&w.du)
                .chain(&w.dv)
                .all(|x| x.is_finite()));
            assert_eq!(w.value[c], 1.0);
            for k in 15..21 {
                assert_eq!((w.value[k], w.du[k], w.dv[k]), (0.0, 0.0, 0.0));
            }
        }
    }
}
