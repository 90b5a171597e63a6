//! A grid pattern's point as an instanced renderer evaluates it, written once for the CPU and the
//! shaders (docs/formulas.md, "Geomorphing grid patterns").
//!
//! Point `(i, j)` of a face's level-`big` grid (`l = ((big−i−j)/big, i/big, j/big)`) is
//! placed and weighted in three steps:
//!
//! - **The snap** ([`snap_step_of`]): a point inside coarse edge `e` moves to the nearest step of
//!   the edge's own `n`-segment layout, ties up, so neighbours with other levels meet;
//! - **The geomorph sources** ([`edge_sources_of`], [`grid_sources_of`]): at a fractional level
//!   (morph factor `α < 1`) the point's surface is blended with that of the level-`(n − 1)`
//!   points around it;
//! - **The plan** ([`grid_point_of`]: [`edge_plan_of`] inside a coarse edge, [`inner_plan_of`]
//!   elsewhere, as [`grid_edge_of`] says): the point, its coarse edge, the weighted points whose
//!   surfaces are summed and, on an edge, the weighted canonical points whose edge weights are
//!   summed.
//!
//! Every function is generic over [`Noise`] (and its [`Word`]): the CPU runs them with `f64` and
//! `u32` ([`super::morph`]'s stencils, [`super::tiling::grid_pattern`]'s snap,
//! [`super::instanced::grid_point`]), and [`crate::shader::grid_plan_wgsl`] traces
//! [`grid_edge_of`], [`edge_plan_of`] and [`inner_plan_of`] into the adaptive renderer's WGSL.
//! Branches inside them are selections: every side is computed and one kept (a side not taken
//! may divide zero by zero; its weight is zero, and a caller skips a zero weight). Steps are
//! `u32`, exact while the products `i (n − 1)` and `step n` stay below 2³², so for every grid
//! level up to 65,536 (a pattern of 2³¹ points a face).

use crate::scalar::{Noise, Word};
use crate::tessellator::parts::NO_EDGE;

/// Where step `step` of a level-`big` grid edge goes on the edge's own `n`-segment layout: the
/// nearest step, ties up (`⌊step n / big + 1/2⌋`, as the quotient of `step n` by `big` plus one
/// where twice the remainder reaches `big`; monotone in `step`, so the boundary keeps its
/// order).
pub(crate) fn snap_step_of<W: Word>(step: W, n: W, big: W) -> W {
    let x = step.wmul(n);
    let (q, r) = (x.div(big), x.rem(big));
    W::select_ge(r.wadd(r), big, q.wadd(W::lit(1)), q)
}

/// Where step `s` of an `n`-segment edge lies on its `(n − 1)`-segment layout: the two steps
/// around it and their weights (the second may be 0). `n ≥ 1` (for `n = 1` the weights are
/// those of a layout of no segments; a caller with `α = 1` gives them no weight).
pub(crate) fn edge_sources_of<R: Noise>(n: R::W, s: R::W) -> [(R::W, R); 2] {
    let one = R::W::lit(1);
    let x = s.wmul(n.wsub(one));
    let (t, r) = (x.div(n), x.rem(n));
    let nf = R::from_word(n);
    [
        (t, R::from_word(n.wsub(r)) / nf),
        (t.wadd(one), R::from_word(r) / nf),
    ]
}

/// Where point `(i, j)` of the level-`n` grid lies on the level-`(n − 1)` grid: the corners
/// `(I, J)` of the level-`(n − 1)` triangle holding it and its barycentric weights there (exact
/// rationals; a weight may be 0). `n ≥ 1`.
pub(crate) fn grid_sources_of<R: Noise>(n: R::W, i: R::W, j: R::W) -> [([R::W; 2], R); 3] {
    let one = R::W::lit(1);
    let m = n.wsub(one);
    let (x, y) = (i.wmul(m), j.wmul(m));
    let (cx, cy, rx, ry) = (x.div(n), y.div(n), x.rem(n), y.rem(n));
    let nf = R::from_word(n);
    let weight = |w: R::W| R::from_word(w) / nf;
    // The lower triangle of its cell where rx + ry <= n, else the upper one.
    let sum = rx.wadd(ry);
    let corner = |lower: R::W, upper: R::W| R::W::select_ge(n, sum, lower, upper);
    let beta = |lower: R::W, upper: R::W| R::pick_ge(n, sum, weight(lower), weight(upper));
    [
        (
            [corner(cx, cx.wadd(one)), cy],
            beta(n.wsub(sum), n.wsub(ry)),
        ),
        (
            [cx.wadd(one), corner(cy, cy.wadd(one))],
            beta(rx, sum.wsub(n)),
        ),
        ([cx, cy.wadd(one)], beta(ry, n.wsub(rx))),
    ]
}

/// A grid point's evaluation plan ([`grid_point_of`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridPointOf<W, R> {
    /// The point, barycentric in the coarse triangle (edge points snapped).
    pub l: [R; 3],
    /// The coarse edge whose inside it lies in, or [`NO_EDGE`] (corners, snapped onto a corner,
    /// and interior points).
    pub edge: W,
    /// The points whose surfaces are summed, with their weights: the point itself first, then
    /// its geomorph sources; a weight of zero is no term.
    pub points: [([R; 3], R); 4],
    /// On an edge, the canonical points `(a, b)` (`a` the canonical start corner's weight)
    /// whose edge weights are summed, with their weights: the point itself, then its two
    /// sources; zero weights elsewhere.
    pub edge_points: [([R; 2], R); 3],
}

/// The coarse edge whose inside point `(i, j)` (`i + j ≤ big`) of the level-`big` grid lies
/// in, or [`NO_EDGE`] (corners and interior points): edge 0 where `j = 0`, edge 1 where
/// `i + j = big`, edge 2 where `i = 0`.
pub(crate) fn grid_edge_of<W: Word>(big: W, i: W, j: W) -> W {
    let (zero, one) = (W::lit(0), W::lit(1));
    let k = big.wsub(i).wsub(j);
    // Flags are words 0 or 1; a product is their "and".
    let is_zero = |x: W| W::select_eq(x, zero, one, zero);
    let not_zero = |x: W| W::select_eq(x, zero, zero, one);
    let e0 = is_zero(j).wmul(not_zero(i)).wmul(not_zero(k));
    let e1 = is_zero(k).wmul(not_zero(i)).wmul(not_zero(j));
    let e2 = is_zero(i).wmul(not_zero(j)).wmul(not_zero(k));
    let on = |flag: W, e: u32, rest: W| W::select_eq(flag, one, W::lit(e), rest);
    on(e0, 0, on(e1, 1, on(e2, 2, W::lit(NO_EDGE))))
}

/// The plan of grid point `(i, j)` inside coarse edge `edge` ([`grid_edge_of`], not
/// [`NO_EDGE`]) of a face whose grid has level `big`, whose edge `k` has `segments[k]`
/// segments (each at least 1, at most `big`) and geomorph factor `alpha[k]`, and whose edge
/// `k` runs canonically where bit `k` of `forward` is set: step `s` of the edge's own layout
/// ([`snap_step_of`]); where `s` is 0 or `n` the point is that corner (weight 1 alone, no
/// edge). Else the point, weight `α` (1 where `α ≥ 1`), and its two level-`(n − 1)` steps
/// weighted `(1 − α) β` where `α < 1`; the same in canonical direction for the edge weights,
/// computed from the canonical step alone so both faces get the same bits.
pub(crate) fn edge_plan_of<R: Noise>(
    edge: R::W,
    big: R::W,
    i: R::W,
    j: R::W,
    segments: [R::W; 3],
    alpha: [R; 3],
    forward: R::W,
) -> GridPointOf<R::W, R> {
    let w = R::W::lit;
    let (zero, one) = (w(0), w(1));
    let (r0, r1) = (R::lit(0.0), R::lit(1.0));
    // Edge `edge`'s entry of a per-edge triple.
    let of_edge =
        |v: [R::W; 3]| R::W::select_eq(edge, w(1), v[1], R::W::select_eq(edge, w(2), v[2], v[0]));
    let of_edge_r = |v: [R; 3]| R::pick_eq(edge, w(1), v[1], R::pick_eq(edge, w(2), v[2], v[0]));
    let n = of_edge(segments);
    let s = snap_step_of(of_edge([i, j, big.wsub(j)]), n, big);
    let snapped = R::W::select_eq(s, zero, one, R::W::select_eq(s, n, one, zero));
    // Barycentrics of step `t` of an `m`-segment layout of edge `edge` (corner `edge` to
    // `edge + 1`): component `c` is the start weight where `c == edge`, the end weight where
    // `c == edge + 1`.
    let step_point = |m: R::W, t: R::W| {
        let mf = R::from_word(m);
        let (start, end) = (R::from_word(m.wsub(t)) / mf, R::from_word(t) / mf);
        [0u32, 1, 2]
            .map(|c| R::pick_eq(edge, w(c), start, R::pick_eq(edge, w((c + 2) % 3), end, r0)))
    };
    let l = step_point(n, s);
    let a = of_edge_r(alpha);
    // `yes` where `α < 1` (a geomorph) and the point is not a corner, else `no`.
    let morphing = |yes: R, no: R| R::pick_eq(snapped, one, no, R::pick_gt(r1, a, yes, no));
    let own = R::pick_eq(snapped, one, r1, R::pick_gt(r1, a, a, r1));
    let bit = |b: u32| forward.shr(b).and(one);
    let sc = R::W::select_eq(of_edge([bit(0), bit(1), bit(2)]), one, s, n.wsub(s));
    let m = n.wsub(one);
    let source = |(t, beta): (R::W, R)| (step_point(m, t), morphing((r1 - a) * beta, r0));
    let [p1, p2] = edge_sources_of::<R>(n, s).map(source);
    let canonical = |steps: R::W, t: R::W| {
        let f = R::from_word(steps);
        [R::from_word(steps.wsub(t)) / f, R::from_word(t) / f]
    };
    let canonical_source = |(t, beta): (R::W, R)| (canonical(m, t), morphing((r1 - a) * beta, r0));
    let [e1, e2] = edge_sources_of::<R>(n, sc).map(canonical_source);
    let on_edge = |weight: R| R::pick_eq(snapped, one, r0, weight);
    GridPointOf {
        l,
        edge: R::W::select_eq(snapped, one, w(NO_EDGE), edge),
        points: [(l, own), p1, p2, ([r0; 3], r0)],
        edge_points: [
            (canonical(n, sc), on_edge(own)),
            (e1.0, on_edge(e1.1)),
            (e2.0, on_edge(e2.1)),
        ],
    }
}

/// The plan of interior point or corner `(i, j)` of a face whose grid has level `big` and
/// whose interior has geomorph factor `alpha_inner`: `l = (big−i−j, i, j) / big`, weight
/// `α_inner`, and the three corners of the level-`(big − 1)` triangle holding it weighted
/// `(1 − α_inner) β`; weight 1 alone at a corner or where `α_inner ≥ 1`. No edge points.
pub(crate) fn inner_plan_of<R: Noise>(
    big: R::W,
    i: R::W,
    j: R::W,
    alpha_inner: R,
) -> GridPointOf<R::W, R> {
    let w = R::W::lit;
    let (zero, one) = (w(0), w(1));
    let (r0, r1) = (R::lit(0.0), R::lit(1.0));
    let a = alpha_inner;
    let bigf = R::from_word(big);
    let l = [big.wsub(i).wsub(j), i, j].map(|x| R::from_word(x) / bigf);
    let corner = R::W::select_eq(
        i.wadd(j),
        zero,
        one,
        R::W::select_eq(i, big, one, R::W::select_eq(j, big, one, zero)),
    );
    let plain = |yes: R, no: R| R::pick_eq(corner, one, yes, no);
    let mb = big.wsub(one);
    let [p1, p2, p3] = grid_sources_of::<R>(big, i, j).map(|([ci, cj], beta)| {
        let mbf = R::from_word(mb);
        let l = [mb.wsub(ci).wsub(cj), ci, cj].map(|x| R::from_word(x) / mbf);
        (l, plain(r0, R::pick_gt(r1, a, (r1 - a) * beta, r0)))
    });
    GridPointOf {
        l,
        edge: w(NO_EDGE),
        points: [(l, plain(r1, R::pick_gt(r1, a, a, r1))), p1, p2, p3],
        edge_points: [([r0; 2], r0); 3],
    }
}

/// The plan of any grid point `(i, j)` (`i + j ≤ big`) on the CPU: [`edge_plan_of`] inside a
/// coarse edge ([`grid_edge_of`]), else [`inner_plan_of`]; the arguments are theirs. The shader
/// makes the same choice with a branch on its traced edge.
pub(crate) fn grid_point_of<R: Noise<W = u32>>(
    big: u32,
    i: u32,
    j: u32,
    segments: [u32; 3],
    alpha: [R; 3],
    alpha_inner: R,
    forward: u32,
) -> GridPointOf<u32, R> {
    match grid_edge_of(big, i, j) {
        NO_EDGE => inner_plan_of::<R>(big, i, j, alpha_inner),
        edge => edge_plan_of::<R>(edge, big, i, j, segments, alpha, forward),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formulas these replaced, in `u64` (the oracle for the CPU's bits).
    fn old_snap_step(step: u32, n: u32, big: u32) -> u32 {
        ((2 * step as u64 * n as u64 + big as u64) / (2 * big as u64)) as u32
    }

    fn old_edge_sources(n: u32, s: u32) -> [(u32, f64); 2] {
        let (n64, m) = (n as u64, n as u64 - 1);
        let x = s as u64 * m;
        let (t, r) = ((x / n64) as u32, x % n64);
        [
            (t, (n64 - r) as f64 / n as f64),
            (t + 1, r as f64 / n as f64),
        ]
    }

    fn old_grid_sources(n: u32, i: u32, j: u32) -> [([u32; 2], f64); 3] {
        let (n64, m) = (n as u64, n as u64 - 1);
        let (x, y) = (i as u64 * m, j as u64 * m);
        let (cx, cy, rx, ry) = ((x / n64) as u32, (y / n64) as u32, x % n64, y % n64);
        let nf = n as f64;
        if rx + ry <= n64 {
            [
                ([cx, cy], (n64 - rx - ry) as f64 / nf),
                ([cx + 1, cy], rx as f64 / nf),
                ([cx, cy + 1], ry as f64 / nf),
            ]
        } else {
            [
                ([cx + 1, cy], (n64 - ry) as f64 / nf),
                ([cx + 1, cy + 1], (rx + ry - n64) as f64 / nf),
                ([cx, cy + 1], (n64 - rx) as f64 / nf),
            ]
        }
    }

    #[test]
    fn the_generic_snap_and_sources_give_the_old_bits() {
        for big in 1..=80u32 {
            for n in 1..=big {
                for step in 0..=big {
                    assert_eq!(snap_step_of(step, n, big), old_snap_step(step, n, big));
                }
            }
        }
        // Near the largest level the steps are exact for.
        for (step, n, big) in [(65_535, 65_536, 65_536), (40_000, 65_535, 65_536)] {
            assert_eq!(snap_step_of(step, n, big), old_snap_step(step, n, big));
        }
        for n in 2..=80u32 {
            for s in 0..=n {
                let new = edge_sources_of::<f64>(n, s);
                let old = old_edge_sources(n, s);
                for (a, b) in new.iter().zip(&old) {
                    assert_eq!((a.0, a.1.to_bits()), (b.0, b.1.to_bits()), "{n} {s}");
                }
            }
            for j in 0..=n {
                for i in 0..=n - j {
                    let new = grid_sources_of::<f64>(n, i, j);
                    let old = old_grid_sources(n, i, j);
                    for (a, b) in new.iter().zip(&old) {
                        assert_eq!((a.0, a.1.to_bits()), (b.0, b.1.to_bits()), "{n} {i} {j}");
                    }
                }
            }
        }
    }
}
