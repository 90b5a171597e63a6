//! A pattern's basis weights, computed once: for every pattern point, the weights of the patch's
//! control points (value, `Du`, `Dv`) and of its control normals. With them, refining a patch is
//! a small matrix product — the same table serves every coarse triangle and every backend
//! (OpenSubdiv's stencil tables play this role for subdivision surfaces).

use crate::basis::{normal_weights, Basis, NORMAL_NET_LEN};
use crate::pattern::{Pattern, PointClass};

/// Weights of one pattern point, stored as `f32` rows of [`Stencil::stride`] floats:
/// `value[K] | du[K] | dv[K] | normal[6] | l[3]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Stencil {
    pub basis: Basis,
    pub level: u32,
    /// Row-major weights, `points × stride`.
    pub weights: Vec<f32>,
    /// Pattern point index of each edge point: `edge_points[e][s - 1]` is step `s` of edge `e`.
    pub edge_points: [Vec<u32>; 3],
    /// Pattern point index of each interior point, in interior order.
    pub interior_points: Vec<u32>,
}

impl Stencil {
    /// Floats per pattern point for a basis of `k` control points.
    pub const fn stride_for(k: usize) -> usize {
        3 * k + NORMAL_NET_LEN + 3
    }
    /// Floats per pattern point.
    pub fn stride(&self) -> usize {
        Self::stride_for(self.basis.len())
    }
    /// Number of pattern points.
    pub fn len(&self) -> usize {
        self.weights.len() / self.stride()
    }
    /// True when the table is empty (never for a valid pattern).
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
    /// The weights row of pattern point `p`.
    #[inline]
    pub fn row(&self, p: usize) -> &[f32] {
        let s = self.stride();
        &self.weights[p * s..(p + 1) * s]
    }

    /// Computes the table for `pattern` and `basis` (weights in f64, stored as f32).
    pub fn new(pattern: &Pattern, basis: Basis) -> Stencil {
        let k = basis.len();
        let stride = Self::stride_for(k);
        let mut weights = Vec::with_capacity(pattern.points.len() * stride);
        for &l in &pattern.points {
            let w = basis.weights(l);
            weights.extend(w.value.iter().chain(&w.du).chain(&w.dv).map(|&x| x as f32));
            weights.extend(normal_weights(l).iter().map(|&x| x as f32));
            weights.extend(l.iter().map(|&x| x as f32));
        }
        let n = pattern.level as usize;
        let mut edge_points = [vec![0; n - 1], vec![0; n - 1], vec![0; n - 1]];
        let mut interior_points =
            Vec::with_capacity(Pattern::interior_count(pattern.level) as usize);
        for (p, class) in pattern.classes.iter().enumerate() {
            match *class {
                PointClass::Edge { edge, step } => {
                    edge_points[edge as usize][step as usize - 1] = p as u32
                }
                PointClass::Interior { .. } => interior_points.push(p as u32),
                PointClass::Corner { .. } => {}
            }
        }
        Stencil {
            basis,
            level: pattern.level,
            weights,
            edge_points,
            interior_points,
        }
    }

    /// Pattern point index of corner `c`.
    pub fn corner_point(&self, c: usize) -> u32 {
        let n = self.level;
        [
            Pattern::index(n, 0, 0),
            Pattern::index(n, n, 0),
            Pattern::index(n, 0, n),
        ][c]
    }
}
