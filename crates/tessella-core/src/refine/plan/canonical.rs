//! Canonical evaluation of points on a coarse edge, so that the two faces sharing the edge
//! compute them bit for bit alike (docs/formulas.md, "Canonical edges").
//!
//! On its boundary every patch reduces to a cubic Bézier curve of four of its control points:
//! the edge's two corners and the edge's two *own* control points (cubic basis: `b210, b120`
//! for edge 0 and so on; PNG1: the own versions, whose cross versions and the centre have zero
//! weight there). Neighbouring faces hold these four points bit for bit alike (every scheme
//! builds them from the edge's own data; PN where the two sides share the normals). Evaluating
//! them in one canonical order — from the corner with the lower position id to the higher — at
//! the same parameter, with the same f64 weights rounded to f32 and summed in the same order,
//! therefore gives identical bits on both faces, which summing a face's whole stencil row does
//! not (its order and its weights' rounding follow the face's corner order).
//!
//! Normals from the normal net use its edge restriction `(N_a, n_ab, N_b)` with weights
//! `(a², a b, b²)` the same way; "real" normals (`Du × Dv`) look across the edge and stay the
//! face's own.

#![allow(clippy::needless_range_loop)] // corners, edges and axes index several tables

use crate::basis::png1::own_slot;
use crate::basis::Basis;
use crate::scalar::{Noise, Real, Word};

/// Control point indices of edge `k`'s boundary curve: start corner, its own control point
/// near the start, near the end, end corner (edge `k` runs from corner `k` to `k + 1 mod 3`).
pub fn edge_controls(basis: Basis, k: usize) -> [usize; 4] {
    let (c0, c1) = (k, (k + 1) % 3);
    match basis {
        Basis::Cubic => [c0, 3 + 2 * k, 4 + 2 * k, c1],
        Basis::Png1 => [c0, own_slot(k, 0), own_slot(k, 2), c1],
    }
}

/// Normal-net indices of edge `k`: start corner normal, edge normal, end corner normal.
pub fn edge_normal_controls(k: usize) -> [usize; 3] {
    [k, 3 + k, (k + 1) % 3]
}

/// Weights of a point of a canonical edge: `a` the barycentric weight of the canonical start
/// corner, `b` of the end corner (both exact pattern coordinates, `a + b = 1` up to rounding).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeWeights {
    /// Cubic Bernstein weights `a³, 3a²b, 3ab², b³`, computed in f64, rounded to f32.
    pub value: [f32; 4],
    /// Quadratic normal-net weights `a², a b, b²`.
    pub normal: [f32; 3],
}

impl EdgeWeights {
    /// The weights at `(a, b)`.
    pub fn new(a: f64, b: f64) -> EdgeWeights {
        let (value, normal) = Self::new_f64(a, b);
        Self::from_f64(value, normal)
    }
    /// The same weights in f64, before rounding.
    pub fn new_f64(a: f64, b: f64) -> ([f64; 4], [f64; 3]) {
        Self::new_of(a, b)
    }
    /// The weights for any [`Real`]: `f64` here, traced for the shaders
    /// ([`crate::shader::edge_weights_wgsl`]).
    pub fn new_of<T: Real>(a: T, b: T) -> ([T; 4], [T; 3]) {
        let three = T::lit(3.0);
        (
            [a * a * a, three * a * a * b, three * a * b * b, b * b * b],
            [a * a, a * b, b * b],
        )
    }
    /// Rounds f64 weights to f32.
    pub fn from_f64(value: [f64; 4], normal: [f64; 3]) -> EdgeWeights {
        EdgeWeights {
            value: value.map(|x| x as f32),
            normal: normal.map(|x| x as f32),
        }
    }
}

/// Which way edge `k` of triangle `t` runs canonically: `true` when its start corner has the
/// lower position id (ties: the lower vertex index), so the canonical start is corner `k`.
#[inline]
pub fn forward(t: [u32; 3], k: usize, position_ids: &[u32]) -> bool {
    let (v0, v1) = (t[k], t[(k + 1) % 3]);
    let (p0, p1) = (position_ids[v0 as usize], position_ids[v1 as usize]);
    (p0, v0) < (p1, v1)
}

/// A tessellator point as the adaptive shaders place it (`crate::shader::tessellator_point`),
/// from its 16.16 `u`, `v` and coarse edge `edge` (`tessellator::parts::NO_EDGE` off the
/// edges) on a face whose edge `k` runs canonically where bit `k` of `forward` is set: its
/// barycentric point (`tessellator::fixed::barycentric_of`) and, on an edge, the
/// canonical parameter `[a, b]` of [`EdgeWeights::new`]: the canonical start corner's weight
/// and the end corner's, `a + b = 1` exactly (off the edges it means nothing). The CPU takes
/// the same `a`, `b` from its f64 pattern points ([`super::tiling::Tile::edge_weights`]).
pub fn fixed_point_of<R: Noise>(u: R::W, v: R::W, edge: R::W, forward: R::W) -> ([R; 3], [R; 2]) {
    let w = R::W::lit;
    let one = w(crate::tessellator::fixed::ONE);
    // Edge `edge`'s entry of a per-edge triple.
    let of_edge =
        |v: [R::W; 3]| R::W::select_eq(edge, w(1), v[1], R::W::select_eq(edge, w(2), v[2], v[0]));
    let start = of_edge([u, v, one.wsub(u).wsub(v)]);
    let bit = |b: u32| forward.shr(b).and(w(1));
    let a = R::W::select_eq(
        of_edge([bit(0), bit(1), bit(2)]),
        w(1),
        start,
        one.wsub(start),
    );
    let scale = R::lit(f64::from(crate::tessellator::fixed::ONE));
    (
        crate::tessellator::fixed::barycentric_of(u, v),
        [a, one.wsub(a)].map(|x| R::from_word(x) / scale),
    )
}

/// The four control points of edge `k` of a patch, in canonical order.
#[inline]
pub fn canonical_points(
    basis: Basis,
    points: &[[f32; 3]],
    k: usize,
    forward: bool,
) -> [[f32; 3]; 4] {
    let mut c = edge_controls(basis, k).map(|i| points[i]);
    if !forward {
        c.reverse();
    }
    c
}

/// The three normal-net entries of edge `k`, in canonical order.
#[inline]
pub fn canonical_normals(normals: &[[f32; 3]], k: usize, forward: bool) -> [[f32; 3]; 3] {
    let mut c = edge_normal_controls(k).map(|i| normals[i]);
    if !forward {
        c.reverse();
    }
    c
}

/// `Σ w_i c_i` in index order from zero, for any [`Real`]: the sums of a canonical edge point
/// ([`position`] and [`net_normal`] on the CPU in `f32`; traced into the shaders'
/// `tessella_canonical_edge`, `crate::shader::canonical_edge`), the same operations on every
/// face.
#[inline]
pub fn edge_sum_of<T: Real, const N: usize>(w: [T; N], c: [[T; 3]; N]) -> [T; 3] {
    std::array::from_fn(|x| {
        let mut s = T::lit(0.0);
        for i in 0..N {
            s = s + w[i] * c[i][x];
        }
        s
    })
}

/// `Σ w_i c_i` in index order, in f32, the same on every face.
#[inline]
pub fn position(w: &EdgeWeights, c: &[[f32; 3]; 4]) -> [f32; 3] {
    edge_sum_of(w.value, *c)
}

/// The unit normal of the normal net's edge restriction, or `None` when it vanishes.
#[inline]
pub fn net_normal(w: &EdgeWeights, c: &[[f32; 3]; 3]) -> Option<[f32; 3]> {
    let unit = crate::basis::surface_normal::unit_or_zero_of(edge_sum_of(w.normal, *c));
    (unit != [0.0; 3]).then_some(unit)
}
