//! Geomorphing grid patterns (docs/formulas.md, "Geomorphing grid patterns").
//!
//! A fractional grid level `f` uses the grid of `N = ⌈f⌉` segments and the morph factor
//! `α = f − (N − 1) ∈ (0, 1]`. Pattern point `l` is evaluated at
//! `P(l) = α S(l) + (1 − α) L(l)`, `L` the level-`(N − 1)` refined flat surface: `S`
//! interpolated linearly over the level-`(N − 1)` grid triangle that holds `l`. `S` is a
//! weighted sum of the control points, so `P` is too: the morphed stencil row is
//! `α w(l) + (1 − α) Σ β_t w(l_t)` (values, derivatives and normal-net weights alike), built
//! once per pattern; evaluation and every backend are unchanged. At `α → 0` the level-`N` points
//! lie on the level-`(N − 1)` flat triangles, so nothing pops when `N` steps up; at `α = 1`
//! (integer levels) the plain stencil is used, bit for bit.
//!
//! Along a coarse edge `L` depends only on the edge's own points, so both faces agree; the
//! canonical edge weights ([`edge_weights`]) get the same blend, computed from the point's step
//! in canonical direction, so shared edge points keep identical bits.

use super::canonical::EdgeWeights;
use crate::basis::Basis;
use crate::pattern::{Pattern, PointClass};
use crate::stencil::Stencil;

/// The morph factor of grid level `x` drawn on `n = ⌈x⌉` segments: `x − (n − 1)`, in
/// `(0, 1]`; 1 for `n = 1` (the coarse triangle has no coarser level) and integer `x`.
pub fn factor(x: f32, n: u32) -> f64 {
    if n <= 1 {
        return 1.0;
    }
    (x as f64 - (n - 1) as f64).clamp(0.0, 1.0)
}

/// Where point `(i, j)` of the level-`n` grid (`l = ((n−i−j)/n, i/n, j/n)`) lies on the
/// level-`(n − 1)` grid: the corners `(I, J)` of the level-`(n − 1)` triangle holding it and its
/// barycentric weights there (exact rationals; a weight may be 0). `n ≥ 2`.
pub fn grid_sources(n: u32, i: u32, j: u32) -> [([u32; 2], f64); 3] {
    super::grid_point::grid_sources_of::<f64>(n, i, j)
}

/// Where step `s` of an `n`-segment edge lies on its `(n − 1)`-segment layout: the two steps
/// around it and their weights (the second may be 0). `n ≥ 2`.
pub fn edge_sources(n: u32, s: u32) -> [(u32, f64); 2] {
    super::grid_point::edge_sources_of::<f64>(n, s)
}

/// `α row(l) + (1 − α) Σ β_t row(l_t)` in f64.
fn blend(basis: Basis, alpha: f64, l: [f64; 3], sources: &[([f64; 3], f64)]) -> Vec<f64> {
    let mut row = Stencil::row_f64(basis, l);
    row.iter_mut().for_each(|x| *x *= alpha);
    for &(lt, beta) in sources {
        if beta == 0.0 {
            continue;
        }
        let w = (1.0 - alpha) * beta;
        for (o, x) in row.iter_mut().zip(Stencil::row_f64(basis, lt)) {
            *o += w * x;
        }
    }
    row
}

/// Barycentrics of step `t` of an `m`-segment layout of edge `k` (corner `k` to `k + 1`).
fn edge_l(k: usize, m: u32, t: u32) -> [f64; 3] {
    let mut l = [0.0; 3];
    l[k] = (m - t) as f64 / m as f64;
    l[(k + 1) % 3] = t as f64 / m as f64;
    l
}

/// The stencil of a grid pattern ([`super::tiling::grid_pattern`]) whose edge `k` has
/// `segments[k]` segments and morph factor `alpha[k]`, and whose interior (the uniform grid of
/// `pattern.level`) has `alpha_inner`. Points with a factor of 1 get the plain weights.
pub fn grid_stencil(
    pattern: &Pattern,
    basis: Basis,
    segments: [u32; 3],
    alpha: [f64; 3],
    alpha_inner: f64,
) -> Stencil {
    let big = pattern.level;
    Stencil::from_rows(pattern, basis, |p| {
        let l = pattern.points[p];
        match pattern.classes[p] {
            PointClass::Edge { edge, step } if alpha[edge as usize] < 1.0 => {
                let k = edge as usize;
                let n = segments[k];
                let src = edge_sources(n, step).map(|(t, b)| (edge_l(k, n - 1, t), b));
                blend(basis, alpha[k], l, &src)
            }
            PointClass::Interior { .. } if alpha_inner < 1.0 => {
                let (i, j) = (
                    (l[1] * big as f64).round() as u32,
                    (l[2] * big as f64).round() as u32,
                );
                let m = (big - 1) as f64;
                let src = grid_sources(big, i, j).map(|([ci, cj], b)| {
                    (
                        [(big - 1 - ci - cj) as f64 / m, ci as f64 / m, cj as f64 / m],
                        b,
                    )
                });
                blend(basis, alpha_inner, l, &src)
            }
            _ => Stencil::row_f64(basis, l),
        }
    })
}

/// Canonical weights ([`EdgeWeights`]) of step `s` (from the canonical start) of an
/// `n`-segment edge with morph factor `alpha < 1`: the plain weights at `((n−s)/n, s/n)` blended
/// with those of the two level-`(n − 1)` points around it, in f64, then rounded. A function of
/// `(n, s, alpha)` only, so both faces of the edge get the same bits.
pub fn edge_weights(n: u32, s: u32, alpha: f64) -> EdgeWeights {
    let nf = n as f64;
    let (mut value, mut normal) = EdgeWeights::new_f64((n - s) as f64 / nf, s as f64 / nf);
    value.iter_mut().for_each(|x| *x *= alpha);
    normal.iter_mut().for_each(|x| *x *= alpha);
    let m = n - 1;
    for (t, beta) in edge_sources(n, s) {
        if beta == 0.0 {
            continue;
        }
        let w = (1.0 - alpha) * beta;
        let (v, nw) = EdgeWeights::new_f64((m - t) as f64 / m as f64, t as f64 / m as f64);
        for i in 0..4 {
            value[i] += w * v[i];
        }
        for i in 0..3 {
            normal[i] += w * nw[i];
        }
    }
    EdgeWeights::from_f64(value, normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sources_reproduce_the_point() {
        for n in 2..12u32 {
            let m = (n - 1) as f64;
            for j in 0..=n {
                for i in 0..=n - j {
                    let src = grid_sources(n, i, j);
                    let (mut x, mut y, mut sum) = (0.0, 0.0, 0.0);
                    for ([ci, cj], b) in src {
                        assert!(b >= 0.0);
                        if b > 0.0 {
                            assert!(ci + cj < n, "corner inside the level-(n-1) grid");
                        }
                        x += b * ci as f64 / m;
                        y += b * cj as f64 / m;
                        sum += b;
                    }
                    assert!((sum - 1.0).abs() < 1e-12);
                    assert!((x - i as f64 / n as f64).abs() < 1e-12, "{n} {i} {j}");
                    assert!((y - j as f64 / n as f64).abs() < 1e-12, "{n} {i} {j}");
                }
            }
            for s in 0..=n {
                let [(t0, b0), (t1, b1)] = edge_sources(n, s);
                assert!(t0 < n && (b1 == 0.0 || t1 < n));
                let t = b0 * t0 as f64 / m + b1 * t1 as f64 / m;
                assert!((t - s as f64 / n as f64).abs() < 1e-12);
            }
        }
    }
}
