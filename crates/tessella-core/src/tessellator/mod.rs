//! Hardware tessellator patterns: the triangles the OpenGL 4 / Direct3D 11 / Vulkan tessellation
//! primitive generator makes for a triangle domain, computed on the CPU.
//!
//! This is a reimplementation of the D3D11 reference tessellator (Microsoft's `CHWTessellator`,
//! which Mesa also runs for GL): the same level processing, the same 16.16 fixed-point
//! placement, the same points in the same order and the same triangles. The formulas are written
//! out in docs/formulas.md, "Tessellator patterns".
//!
//! # Domain and orientation
//!
//! GL's tessellation coordinate `(u, v, w)` becomes the barycentric `(l1, l2, l3) = (u, v, w)`:
//! corner `u = 1` is P1, `v = 1` is P2, `w = 1` is P3. Outer levels are in GL order:
//!
//! | level      | edge    | our edge ([`PointClass::Edge`]) | points run |
//! |------------|---------|---------------------------------|------------|
//! | `outer[0]` | `l1 = 0` | 1 (P2 → P3)                     | P2 → P3    |
//! | `outer[1]` | `l2 = 0` | 2 (P3 → P1)                     | P3 → P1    |
//! | `outer[2]` | `l3 = 0` | 0 (P1 → P2)                     | P1 → P2    |
//!
//! Points come in the hardware's order: the outer ring (edge `l1 = 0` from P2, then `l2 = 0`
//! from P3, then `l3 = 0` from P1, each without its end corner), then the inner rings from the
//! outside in, each in the same edge order, then (even inner spacing) the centre. Triangles are
//! counter-clockwise in the `(l2, l3)` plane like [`Pattern::uniform`]'s, which is the vertex
//! order GL emits for `ccw` (its default). Every position is a multiple of 2⁻¹⁶, stored exactly;
//! `l3 = 1 − l1 − l2` is exact too, so the three sum to 1.
//!
//! # Classes
//!
//! Corners are [`PointClass::Corner`]; a point inside an outer edge is
//! [`PointClass::Edge`]` { edge, step }` with `step` its index along the edge (`1..segments`),
//! counted in our edge's direction; segments are not of equal length with fractional spacing.
//! Everything else is [`PointClass::Interior`]. [`Pattern::level`] is the largest outer segment
//! count (0 for a culled patch). Stencils and output layouts still assume the uniform layout.
//!
//! # Bad input
//!
//! Nothing panics. Any outer level ≤ 0 or NaN culls the patch: an empty pattern, as the hardware
//! draws nothing. Other levels are clamped: +∞ and values above the maximum become the maximum
//! (64; 63 for fractional-odd), values below the minimum and a NaN inner level become the minimum.

pub(crate) mod fixed;
pub mod parts;
pub(crate) mod points;
mod stitch;

use crate::pattern::{Pattern, PointClass};
use fixed::{ONE, ONE_HALF, ONE_THIRD, TWO_THIRDS};
use points::Ruler;
use serde::Serialize;

/// How a level divides an edge (GL `layout(equal_spacing / fractional_odd_spacing /
/// fractional_even_spacing)`; D3D11's partitioning `integer / fractional_odd /
/// fractional_even`). The options' [`refine::Spacing`](crate::refine::Spacing) is this or the
/// uniform grid. Exhaustive: GL's tessellator has exactly these three.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Partitioning {
    /// Levels rounded up to an integer in `[1, 64]`; equal segments.
    Equal,
    /// Levels in `[1, 63]`; an odd number of segments, two of them shorter, growing continuously.
    FractionalOdd,
    /// Levels in `[2, 64]`; an even number of segments, two of them shorter.
    FractionalEven,
}

impl Partitioning {
    /// `(minimum, maximum)` level for this spacing.
    pub fn range(self) -> (f32, f32) {
        match self {
            Partitioning::Equal => (1.0, 64.0),
            Partitioning::FractionalOdd => (1.0, 63.0),
            Partitioning::FractionalEven => (2.0, 64.0),
        }
    }
}

/// The four levels of a triangle patch: GL's `gl_TessLevelInner[0]` and `gl_TessLevelOuter[0..3]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TessLevels {
    /// Inner level.
    pub inner: f32,
    /// Outer levels: `outer[k]` is the edge where `l_{k+1} = 0` (opposite corner P_{k+1}).
    pub outer: [f32; 3],
}

impl TessLevels {
    /// All four levels equal to `level`.
    pub fn uniform(level: f32) -> TessLevels {
        TessLevels {
            inner: level,
            outer: [level; 3],
        }
    }
}

/// The levels as the hardware uses them, after culling, clamping and rounding.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProcessedLevels {
    pub spacing: Partitioning,
    /// Clamped (and, for equal spacing, rounded up) levels, as `f32` before fixed point.
    pub levels: TessLevels,
    /// The same in 16.16 fixed point, as placement uses them.
    pub outer_fixed: [u32; 3],
    pub inner_fixed: u32,
    /// Parities: odd levels have a middle segment, even ones a middle point. Fractional spacings
    /// fix the parity; equal spacing takes each level's own (an inner level of 1 counts as even).
    pub outer_odd: [bool; 3],
    pub inner_odd: bool,
    /// Segments along each outer edge.
    pub outer_segments: [u32; 3],
    /// Segments of the inner level's 1D layout (at least 2, or 3 when odd); each side of the
    /// first inner ring has two fewer.
    pub inner_segments: u32,
    /// All four levels are 1 (equal or fractional-odd spacing): the pattern is the one triangle.
    pub single_triangle: bool,
}

/// Culls, clamps and rounds `levels` as the hardware does; `None` when the patch is culled (an
/// outer level ≤ 0 or NaN).
pub fn process_levels(spacing: Partitioning, levels: TessLevels) -> Option<ProcessedLevels> {
    // Culled unless every outer level is a number above 0 (NaN is not).
    if levels.outer.iter().any(|&x| x.is_nan() || x <= 0.0) {
        return None;
    }
    let (lo, hi) = spacing.range();
    // The reference's IEEE-754R min/max: a NaN operand yields the other one.
    let clamp = |x: f32, lo: f32| if x.is_nan() { lo } else { x.max(lo).min(hi) };
    let equal = spacing == Partitioning::Equal;
    let round = |x: f32| if equal { x.ceil() } else { x };
    let outer = levels.outer.map(|x| round(clamp(x, lo)));
    // Fractional-odd: when an outer level will be above 1 in fixed point, the inner level is
    // kept a hair above 1, so there is an inner ring to stitch the edges to.
    let mut inner_lo = lo;
    if spacing == Partitioning::FractionalOdd && outer.iter().any(|&x| x > 1.0 + 2f32.powi(-17)) {
        inner_lo = 1.0 + 2f32.powi(-16);
    }
    let inner = round(clamp(levels.inner, inner_lo));
    let (outer_odd, inner_odd) = match spacing {
        Partitioning::Equal => (
            outer.map(|x| (x as i32) & 1 == 1),
            (inner as i32) & 1 == 1 && inner != 1.0,
        ),
        Partitioning::FractionalOdd => ([true; 3], true),
        Partitioning::FractionalEven => ([false; 3], false),
    };
    let outer_fixed = outer.map(fixed::from_f32);
    let inner_fixed = fixed::from_f32(inner);
    let single_triangle = spacing != Partitioning::FractionalEven
        && inner_fixed == ONE
        && outer_fixed.iter().all(|&x| x == ONE);
    let outer_segments = [0, 1, 2].map(|e| points::point_count(outer_fixed[e], outer_odd[e]) - 1);
    let min_inner_points = if inner_odd { 4 } else { 3 };
    let inner_segments = points::point_count(inner_fixed, inner_odd).max(min_inner_points) - 1;
    Some(ProcessedLevels {
        spacing,
        levels: TessLevels { inner, outer },
        outer_fixed,
        inner_fixed,
        outer_odd,
        inner_odd,
        outer_segments,
        inner_segments,
        single_triangle,
    })
}

/// Our edge index ([`PointClass::Edge`]) of outer level `k`'s edge.
pub const fn edge_of_outer(k: usize) -> u8 {
    [1, 2, 0][k]
}

/// The pattern the hardware tessellator makes for `levels` (see the module docs for the
/// mapping). A culled patch gives an empty pattern with level 0.
///
/// ```
/// use tessella_core::tessellator::{tessellate, Partitioning, TessLevels};
/// let p = tessellate(Partitioning::Equal, TessLevels::uniform(2.0));
/// assert_eq!((p.points.len(), p.triangles.len()), (7, 6));
/// ```
pub fn tessellate(spacing: Partitioning, levels: TessLevels) -> Pattern {
    match process_levels(spacing, levels) {
        None => Pattern {
            level: 0,
            points: Vec::new(),
            triangles: Vec::new(),
            classes: Vec::new(),
        },
        Some(p) => build(&p),
    }
}

/// Points (fixed-point `(u, v)`) and triangles for processed levels.
fn build(p: &ProcessedLevels) -> Pattern {
    let level = p.outer_segments.into_iter().max().unwrap_or(1);
    if p.single_triangle {
        // P2, P3, P1: each outer edge's first point, as the hardware lists them.
        let uv = [(0, ONE), (0, 0), (ONE, 0)];
        return Pattern {
            level: 1,
            points: uv.iter().map(|&(u, v)| barycentric(u, v)).collect(),
            triangles: vec![[0, 1, 2]],
            classes: [1, 2, 0].map(|c| PointClass::Corner { corner: c }).to_vec(),
        };
    }
    let outer: [Ruler; 3] = [0, 1, 2].map(|e| Ruler::new(p.outer_fixed[e], p.outer_odd[e]));
    let inner = Ruler::new(p.inner_fixed, p.inner_odd);
    let outer_points = p.outer_segments.map(|s| s + 1);
    let inner_points = p.inner_segments + 1;

    let mut uv: Vec<(u32, u32)> = Vec::new();
    let mut classes = Vec::new();
    // Outer ring: edge k runs from its first corner, in our edge's direction; the position
    // along it (from its first corner) is `place(p)` for point p, by the layout's symmetry.
    for k in 0..3 {
        let last = outer_points[k] - 1;
        for i in 0..last {
            let q = if k == 1 { i } else { last - i };
            let t = outer[k].place(q);
            uv.push(match k {
                0 => (0, t),
                1 => (t, 0),
                _ => (t, ONE - t),
            });
            classes.push(if i == 0 {
                PointClass::Corner {
                    corner: [1, 2, 0][k],
                }
            } else {
                PointClass::Edge {
                    edge: edge_of_outer(k),
                    step: i,
                }
            });
        }
    }
    let inner_start = uv.len() as u32;
    // Inner rings: ring r's sides are the inner layout's points r..=n-1-r, pushed towards the
    // middle; the perpendicular distance is place(r) scaled by 2/3 (barycentric units), and a
    // point slides back along its side by half that distance, so the ring is a smaller similar
    // triangle.
    for ring in 1..(inner_points / 2) {
        let (start, end) = (ring, inner_points - 1 - ring);
        let perp = inner.place(ring).wrapping_mul(TWO_THIRDS);
        let perp = perp.wrapping_add(ONE_HALF) >> fixed::FRACTION_BITS;
        // Half the distance, rounded up (the reference's `(perp + 1) / 2`).
        let slide = perp.div_ceil(2);
        for k in 0..3 {
            for i in start..end {
                let q = if k == 1 { i } else { end - (i - start) };
                let t = inner.place(q).wrapping_sub(slide);
                uv.push(match k {
                    0 => (perp, t),
                    1 => (t, perp),
                    _ => (t, ONE.wrapping_sub(t).wrapping_sub(perp)),
                });
            }
        }
    }
    if !p.inner_odd {
        uv.push((ONE_THIRD, ONE_THIRD));
    }
    let interior = uv.len() - classes.len();
    classes.extend((0..interior as u32).map(|index| PointClass::Interior { index }));

    let triangles = connect(p, &outer, &inner, outer_points, inner_points, inner_start);
    Pattern {
        level,
        points: uv.iter().map(|&(u, v)| barycentric(u, v)).collect(),
        triangles,
        classes,
    }
}

/// `(l1, l2, l3) = (u, v, 1 − u − v)`, exact.
fn barycentric(u: u32, v: u32) -> [f64; 3] {
    // Every placed point is in the triangle: the third weight's u32 subtraction cannot wrap.
    debug_assert!(u64::from(u) + u64::from(v) <= u64::from(ONE), "({u}, {v})");
    fixed::barycentric_of(u, v)
}

/// Triangles, ring by ring from the outside in, each ring side by side.
fn connect(
    p: &ProcessedLevels,
    outer: &[Ruler; 3],
    inner: &Ruler,
    outer_points: [u32; 3],
    inner_points: u32,
    inner_start: u32,
) -> Vec<[u32; 3]> {
    let mut tris = Vec::new();
    let mut outside_points = outer_points;
    let mut outside_base = 0u32;
    let mut inside_base = inner_start;
    // Even inner levels count the centre as a last ring of one point.
    for ring in 1..inner_points.div_ceil(2) {
        let inside_len = inner_points - 2 * ring;
        let (ring_inside_start, ring_outside_start) = (inside_base, outside_base);
        for k in 0..3 {
            let (ib, ob, out_len) = (inside_base, outside_base, outside_points[k]);
            // The third side's last point is the ring's first point.
            let last_side = k == 2;
            let inside = move |i: u32| {
                if last_side && i == inside_len - 1 {
                    ring_inside_start
                } else {
                    ib + i
                }
            };
            let outside = move |o: u32| {
                if last_side && o == out_len - 1 {
                    ring_outside_start
                } else {
                    ob + o
                }
            };
            if ring == 1 {
                stitch::transition(
                    &mut tris,
                    inside,
                    inner.half_points,
                    p.inner_odd,
                    outside,
                    outer[k].half_points,
                    p.outer_odd[k],
                );
            } else {
                stitch::regular(&mut tris, inside, outside, inside_len);
            }
            outside_base += out_len - 1;
            inside_base += inside_len - 1;
            outside_points[k] = inside_len;
        }
    }
    if p.inner_odd {
        // The innermost ring of an odd level is a single triangle.
        tris.push([outside_base, outside_base + 1, outside_base + 2]);
    }
    tris
}
