//! A tessellator pattern cut into parts that depend on few levels, so that fixed index buffers,
//! built once, draw every pattern: the instanced renderer whose levels change every frame
//! (tessella-gpu's `AdaptiveRenderer`) uploads only per-face level data.
//!
//! A pattern ([`super::tessellate`]) is its outer ring stitched to the first inner ring — three
//! *strips*, strip `k` a function of outer level `k`'s layout and the inner layout only — and the
//! *interior*: the inner rings from the first one inwards, a function of the inner layout only.
//! A layout's topology is its [`Shape`] (the ruler's half-row length and parity): 32 × 2 shapes,
//! so 64 interiors and 64 × 64 strips cover every level of every spacing.
//!
//! The parts' triangles hold *point codes*, not indices: ring (0 the outer ring), side (GL's
//! outer-level order) and index along that side. [`FaceRulers::locate`] turns a code into the
//! point's 16.16 `(u, v)` with one face's rulers, by the arithmetic of [`super::tessellate`];
//! drawing the parts with a face's rulers reproduces its pattern point for point and triangle for
//! triangle (tested). Strip codes are side-local: the instance drawing strip `k` adds `k` to the
//! side. The last point of a side is the first of the next side.

use super::fixed::{self, ONE, ONE_HALF, ONE_THIRD, TWO_THIRDS};
use super::points::{place_of, Ruler, RULER_PACKED_WORD, RULER_POINTS_SHIFT, RULER_WORDS};
use super::{stitch, ProcessedLevels};
use crate::scalar::Word;

/// The topology of one level's 1D layout: points per half-row and parity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shape {
    /// `Ruler::half_points`, 1..=32.
    pub half_points: u32,
    pub odd: bool,
}

impl Shape {
    /// Number of shapes; [`Shape::id`] is below it.
    pub const COUNT: u32 = 64;

    /// `0..COUNT`.
    pub fn id(self) -> u32 {
        (self.half_points - 1) * 2 + u32::from(self.odd)
    }

    /// The shape of id `id`.
    pub fn from_id(id: u32) -> Shape {
        Shape {
            half_points: id / 2 + 1,
            odd: id % 2 == 1,
        }
    }

    /// Points of an outer edge of this shape, both ends included.
    pub fn points(self) -> u32 {
        2 * self.half_points + u32::from(!self.odd)
    }

    /// Points of the inner level's layout: at least 3 (even) or 4 (odd), as
    /// [`super::process_levels`] makes them.
    pub fn inner_points(self) -> u32 {
        self.points().max(if self.odd { 4 } else { 3 })
    }
}

/// Point code: ring, side, index along the side.
pub const fn code(ring: u32, side: u32, index: u32) -> u32 {
    index | side << 8 | ring << 10
}

/// The triangles of the strip between an outer edge of shape `outer` and the first inner ring of
/// the inner shape `inner`, as side-local codes (side 0).
pub fn strip(inner: Shape, outer: Shape) -> Vec<[u32; 3]> {
    let mut tris = Vec::new();
    stitch::transition(
        &mut tris,
        |i| code(1, 0, i),
        inner.half_points,
        inner.odd,
        |o| code(0, 0, o),
        outer.half_points,
        outer.odd,
    );
    tris
}

/// The triangles inside the first inner ring of the inner shape `inner`.
pub fn interior(inner: Shape) -> Vec<[u32; 3]> {
    let n = inner.inner_points();
    let mut tris = Vec::new();
    for ring in 2..n.div_ceil(2) {
        let inside_len = n - 2 * ring;
        for k in 0..3 {
            stitch::regular(
                &mut tris,
                |i| code(ring, k, i),
                |o| code(ring - 1, k, o),
                inside_len,
            );
        }
    }
    if inner.odd {
        // The innermost ring of an odd level is one triangle.
        let r = n / 2 - 1;
        tris.push([code(r, 0, 0), code(r, 1, 0), code(r, 2, 0)]);
    }
    tris
}

/// The pattern of levels that are all 1: one triangle of the three corners.
pub fn single() -> [u32; 3] {
    [code(0, 0, 0), code(0, 1, 0), code(0, 2, 0)]
}

/// One face's layouts: what [`FaceRulers::locate`] needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceRulers {
    /// Outer levels in GL order.
    pub outer: [Ruler; 3],
    pub inner: Ruler,
    pub outer_points: [u32; 3],
    pub inner_points: u32,
    pub single_triangle: bool,
}

impl FaceRulers {
    /// The rulers of processed levels (see [`super::process_levels`]).
    pub fn new(p: &ProcessedLevels) -> FaceRulers {
        FaceRulers {
            outer: [0, 1, 2].map(|k| Ruler::new(p.outer_fixed[k], p.outer_odd[k])),
            inner: Ruler::new(p.inner_fixed, p.inner_odd),
            outer_points: p.outer_segments.map(|s| s + 1),
            inner_points: p.inner_segments + 1,
            single_triangle: p.single_triangle,
        }
    }

    /// Shapes of the outer levels (GL order) and of the inner level.
    pub fn shapes(&self) -> ([Shape; 3], Shape) {
        let shape = |r: &Ruler| Shape {
            half_points: r.half_points,
            odd: r.odd,
        };
        (self.outer.each_ref().map(shape), shape(&self.inner))
    }

    /// The 20 words the GPU reads: the outer rulers (GL order), then the inner one
    /// (`Ruler::words`).
    pub fn words(&self) -> [u32; 4 * RULER_WORDS] {
        let mut w = [0u32; 20];
        for k in 0..3 {
            w[RULER_WORDS * k..RULER_WORDS * (k + 1)]
                .copy_from_slice(&self.outer[k].words(self.outer_points[k]));
        }
        w[3 * RULER_WORDS..].copy_from_slice(&self.inner.words(self.inner_points));
        w
    }

    /// The 16.16 `(u, v)` of the point `code` names, its side turned by `side_offset` (a
    /// strip's instance side): `locate_of` on this face's words.
    pub fn locate(&self, code: u32, side_offset: u32) -> (u32, u32) {
        let words = self.words();
        let [u, v, _] = locate_of(
            |r: u32, k| words[RULER_WORDS * r as usize + k],
            code,
            side_offset,
        );
        (u, v)
    }
}

/// Off the coarse edges: the edge `locate_of` names for interior points and corners.
pub const NO_EDGE: u32 = 3;

/// The 16.16 `u`, `v` of the point `code` names on a face whose ruler words
/// ([`FaceRulers::words`]) `word(r, k)` reads (ruler `r`: 0..2 the outer levels in GL order, 3
/// the inner level), its side turned by `side_offset`, and the coarse edge (ours) whose inside
/// it lies in, or [`NO_EDGE`]. For any [`Word`]: the CPU's `u32` and the adaptive renderer's
/// generated shader (`tessella_core::shader`) run this one function. The ring-0 and inner-ring
/// cases are both computed and one is selected.
pub(crate) fn locate_of<W: Word>(word: impl Fn(W, usize) -> W, code: W, side_offset: W) -> [W; 3] {
    let lit = W::lit;
    let three = lit(3);
    let ruler = |r: W| std::array::from_fn(|k| word(r, k));
    let points = |r: W| word(r, RULER_PACKED_WORD).shr(RULER_POINTS_SHIFT);
    let ring = code.shr(10);
    let side = code.shr(8).and(lit(3)).wadd(side_offset).rem(three);
    let i = code.and(lit(0xff));
    // A side's last point is the next side's first.
    let next = |side: W, i: W, last: W| {
        (
            W::select_eq(i, last, side.wadd(lit(1)).rem(three), side),
            W::select_eq(i, last, lit(0), i),
        )
    };
    let on_side = |side: W, t: W, zero: W, third: W| {
        (
            W::select_eq(side, lit(0), zero, t),
            W::select_eq(side, lit(0), t, W::select_eq(side, lit(1), zero, third)),
        )
    };

    // Ring 0: the outer edges, each from its own ruler.
    let (o_side, o_i) = next(side, i, points(side).wsub(lit(1)));
    let last = points(o_side).wsub(lit(1));
    let q = W::select_eq(o_side, lit(1), o_i, last.wsub(o_i));
    let t = place_of(ruler(o_side), q);
    let (o_u, o_v) = on_side(o_side, t, lit(0), lit(ONE).wsub(t));
    // GL's outer[k] is our edge k + 1.
    let o_edge = W::select_gt(o_i, lit(0), o_side.wadd(lit(1)).rem(three), lit(NO_EDGE));

    // Inner rings: the inner ruler's points pushed towards the middle.
    let inner = ruler(lit(3));
    let inner_points = points(lit(3));
    let len = inner_points.wsub(ring.wadd(ring));
    let (n_side, n_i) = next(side, i, len.wsub(lit(1)));
    let end = inner_points.wsub(lit(1)).wsub(ring);
    let perp = place_of(inner, ring)
        .wmul(lit(TWO_THIRDS))
        .wadd(lit(ONE_HALF))
        .shr(fixed::FRACTION_BITS);
    let slide = perp.wadd(lit(1)).div(lit(2));
    let q = W::select_eq(n_side, lit(1), ring.wadd(n_i), end.wsub(n_i));
    let t = place_of(inner, q).wsub(slide);
    let (n_u, n_v) = on_side(n_side, t, perp, lit(ONE).wsub(t).wsub(perp));
    // A ring of one point is the centre.
    let n_u = W::select_eq(len, lit(1), lit(ONE_THIRD), n_u);
    let n_v = W::select_eq(len, lit(1), lit(ONE_THIRD), n_v);

    let outer_ring = |a: W, b: W| W::select_eq(ring, lit(0), a, b);
    [
        outer_ring(o_u, n_u),
        outer_ring(o_v, n_v),
        outer_ring(o_edge, lit(NO_EDGE)),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::{process_levels, tessellate, Partitioning, TessLevels};
    use super::*;

    /// The pattern the parts draw for `levels`, as (u, v) triangles.
    fn drawn(spacing: Partitioning, levels: TessLevels) -> Vec<[(u32, u32); 3]> {
        let Some(p) = process_levels(spacing, levels) else {
            return vec![];
        };
        let r = FaceRulers::new(&p);
        let at = |t: [u32; 3], side| t.map(|c| r.locate(c, side));
        if r.single_triangle {
            return vec![at(single(), 0)];
        }
        let (outer, inner) = r.shapes();
        let mut out = Vec::new();
        for (k, &o) in outer.iter().enumerate() {
            out.extend(strip(inner, o).into_iter().map(|t| at(t, k as u32)));
        }
        out.extend(interior(inner).into_iter().map(|t| at(t, 0)));
        out
    }

    fn expected(spacing: Partitioning, levels: TessLevels) -> Vec<[(u32, u32); 3]> {
        let p = tessellate(spacing, levels);
        let uv = |i: u32| {
            let l = p.points[i as usize];
            let fix = |x: f64| (x * f64::from(ONE)).round() as u32;
            (fix(l[0]), fix(l[1]))
        };
        p.triangles.iter().map(|t| t.map(uv)).collect()
    }

    #[test]
    fn the_parts_draw_the_tessellators_patterns() {
        let mut cases = 0;
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as f32 / (1u64 << 31) as f32
        };
        for spacing in [
            Partitioning::Equal,
            Partitioning::FractionalOdd,
            Partitioning::FractionalEven,
        ] {
            let mut levels: Vec<TessLevels> = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 7.3, 33.0, 63.5, 64.0]
                .iter()
                .map(|&x| TessLevels::uniform(x))
                .collect();
            levels.push(TessLevels {
                inner: 1.0,
                outer: [1.0, 1.0, 1.0],
            });
            levels.push(TessLevels {
                inner: 1.0,
                outer: [5.0, 1.0, 2.0],
            });
            for _ in 0..300 {
                let mut l = || 1.0 + next() * next() * 66.0;
                levels.push(TessLevels {
                    inner: l(),
                    outer: [l(), l(), l()],
                });
            }
            for lv in levels {
                let (a, b) = (drawn(spacing, lv), expected(spacing, lv));
                assert!(!b.is_empty());
                assert_eq!(a, b, "{spacing:?} {lv:?}");
                cases += 1;
            }
        }
        assert!(cases > 900);
    }

    #[test]
    fn every_shape_round_trips_and_its_points_match_the_layout() {
        for id in 0..Shape::COUNT {
            let s = Shape::from_id(id);
            assert_eq!(s.id(), id);
            assert!((1..=32).contains(&s.half_points));
        }
        // The shapes the levels give are the ones `FaceRulers` reports.
        for x in [1.0f32, 2.0, 2.2, 3.0, 9.9, 64.0] {
            for spacing in [Partitioning::Equal, Partitioning::FractionalEven] {
                let p = process_levels(spacing, TessLevels::uniform(x)).unwrap();
                let r = FaceRulers::new(&p);
                let (outer, inner) = r.shapes();
                assert_eq!(outer[0].points(), r.outer_points[0], "{x}");
                assert_eq!(inner.inner_points(), r.inner_points, "{x}");
            }
        }
    }
}
