//! Patch bases: for fixed barycentric coordinates, the weights that combine a patch's control
//! points into a point of the surface, and the weights of its two directional derivatives.
//!
//! Every scheme is such a linear combination, so a refinement pattern can hold the weights of
//! each of its points once ([`crate::Stencil`]) and every backend evaluates a patch as a
//! weighted sum of its control points.
//!
//! Derivatives are taken along `u` (from P1 towards P2) and `v` (from P1 towards P3), with
//! barycentric `(l1, l2, l3) = (1-u-v, u, v)`; `Du × Dv` points to the side a
//! counter-clockwise triangle faces.

pub mod png1;
pub mod surface_normal;

use crate::scalar::{Dual, Real};
use serde::Serialize;

/// Cubic control points in storage order: corners, then two points per edge walking
/// P1 → P2 → P3 → P1, then the centre. Index `i` of `b_ijk` belongs to P1 (docs/formulas.md, Conventions).
pub const CUBIC_ORDER: [[u8; 3]; 10] = [
    [3, 0, 0], // b300 = P1
    [0, 3, 0], // b030 = P2
    [0, 0, 3], // b003 = P3
    [2, 1, 0], // b210, edge P1P2 near P1
    [1, 2, 0], // b120, edge P1P2 near P2
    [0, 2, 1], // b021, edge P2P3 near P2
    [0, 1, 2], // b012, edge P2P3 near P3
    [1, 0, 2], // b102, edge P3P1 near P3
    [2, 0, 1], // b201, edge P3P1 near P1
    [1, 1, 1], // b111
];

/// Number of control normals of the quadratic normal net: `N1, N2, N3, n110, n011, n101`.
pub const NORMAL_NET_LEN: usize = 6;

/// The family of functions a scheme's control points are combined with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Basis {
    /// The cubic Bernstein basis of a Bézier triangle, 10 control points ([`CUBIC_ORDER`]).
    /// Flat and Phong patches are degree-elevated into it.
    Cubic,
    /// PNG1's 21 control points ([`png1::PNG1_ORDER`]): cubic Bernstein
    /// polynomials times the paper's rational blends of two versions of each edge slot and six
    /// centre candidates (Fünfzig et al. 2008, equation (6)).
    Png1,
}

/// Weights of one parameter point: value, `Du` and `Dv`, one entry per control point.
#[derive(Debug, Clone, PartialEq)]
pub struct BasisWeights {
    pub value: Vec<f64>,
    pub du: Vec<f64>,
    pub dv: Vec<f64>,
}

#[allow(clippy::len_without_is_empty)] // a basis always has control points
impl Basis {
    /// Number of control points per patch.
    pub const fn len(self) -> usize {
        match self {
            Basis::Cubic => 10,
            Basis::Png1 => png1::PNG1_LEN,
        }
    }

    /// Weights at barycentric `l = (l1, l2, l3)`, `l1 + l2 + l3 = 1`, computed in f64.
    pub fn weights(self, l: [f64; 3]) -> BasisWeights {
        let w = self.weights_of(l);
        BasisWeights {
            value: w.iter().map(|d| d.v).collect(),
            du: w.iter().map(|d| d.du).collect(),
            dv: w.iter().map(|d| d.dv).collect(),
        }
    }

    /// The weights at `l` for any [`Real`], one [`Dual`] (value, `Du`, `Dv`) per control
    /// point: what [`Basis::weights`] computes in `f64` and the shaders' generated code
    /// ([`crate::shader`]) computes per vertex.
    pub fn weights_of<T: Real>(self, l: [T; 3]) -> Vec<Dual<T>> {
        match self {
            Basis::Cubic => cubic_weights(l).to_vec(),
            Basis::Png1 => png1::weights_of(l).to_vec(),
        }
    }
}

fn factorial(n: u8) -> f64 {
    (1..=n as u32).product::<u32>() as f64
}

/// Cubic Bernstein polynomials `3!/(i!j!k!) l1^i l2^j l3^k` of [`CUBIC_ORDER`] with their `Du`,
/// `Dv` (`Du = ∂/∂l2 − ∂/∂l1`, `Dv = ∂/∂l3 − ∂/∂l1`), for any [`Real`]: the CPU's stencils
/// (`f64`) and the shaders' weights ([`crate::shader`]) come from this one function.
pub fn cubic_weights<T: Real>(l: [T; 3]) -> [Dual<T>; 10] {
    CUBIC_ORDER.map(|e| {
        let c = 6.0 / (factorial(e[0]) * factorial(e[1]) * factorial(e[2]));
        let pow = |x: T, n: u8| if n == 0 { T::lit(1.0) } else { x.powi(n) };
        // Partial derivative along barycentric coordinate `m`.
        let partial = |m: usize| {
            if e[m] == 0 {
                return T::lit(0.0);
            }
            let mut p = T::lit(c * e[m] as f64);
            for (k, &lk) in l.iter().enumerate() {
                p = p * pow(lk, if k == m { e[k] - 1 } else { e[k] });
            }
            p
        };
        let d1 = partial(0);
        Dual {
            v: T::lit(c) * pow(l[0], e[0]) * pow(l[1], e[1]) * pow(l[2], e[2]),
            du: partial(1) - d1,
            dv: partial(2) - d1,
        }
    })
}

/// Weights of the quadratic normal net `N1, N2, N3, n110, n011, n101` at `l`:
/// `l1², l2², l3², l1 l2, l2 l3, l3 l1` (Vlachos et al., with the mid coefficients carrying
/// their factor; docs/formulas.md, Normal nets). Generic for the shaders, as
/// [`cubic_weights`].
pub fn normal_weights<T: Real>(l: [T; 3]) -> [T; NORMAL_NET_LEN] {
    let [a, b, c] = l;
    [a * a, b * b, c * c, a * b, b * c, c * a]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_partition_of_unity_and_derivatives() {
        for &l in &[
            [1.0, 0.0, 0.0],
            [0.2, 0.3, 0.5],
            [1.0 / 3.0; 3],
            [0.0, 0.25, 0.75],
        ] {
            let w = Basis::Cubic.weights(l);
            assert!((w.value.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(w.du.iter().sum::<f64>().abs() < 1e-13);
            assert!(w.dv.iter().sum::<f64>().abs() < 1e-13);
            // Finite differences agree with the analytic derivatives.
            let h = 1e-6;
            let fu = Basis::Cubic.weights([l[0] - h, l[1] + h, l[2]]);
            let bu = Basis::Cubic.weights([l[0] + h, l[1] - h, l[2]]);
            for k in 0..10 {
                let fd = (fu.value[k] - bu.value[k]) / (2.0 * h);
                assert!((fd - w.du[k]).abs() < 1e-8, "k={k} {fd} {}", w.du[k]);
            }
        }
    }

    #[test]
    fn corner_weights_select_corner_points() {
        let w = Basis::Cubic.weights([0.0, 1.0, 0.0]);
        assert_eq!(w.value[1], 1.0);
        assert_eq!(w.value.iter().filter(|&&x| x != 0.0).count(), 1);
    }
}
