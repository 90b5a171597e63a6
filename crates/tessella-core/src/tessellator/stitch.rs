//! Connectivity: strips of triangles between two rows of points.
//!
//! A strip joins an *outside* row (an outer edge, or the previous inner ring's side) to an
//! *inside* row (the next ring's side). Rows are addressed by local indices; the caller maps them
//! to pattern indices (which lets the third side of a ring wrap back to the ring's first point).
//! Every triangle is emitted in the order the reference passes to its `DefineClockwiseTriangle`,
//! which is counter-clockwise in our `(l2, l3)` plane, and the order GL's default `ccw` produces.

/// Where the ruler function has put the half-edge's `i`-th point once a half-level reaches 32
/// points: point `i` joins the row when the half-level exceeds `FINAL_POSITION[i]`. Both rows of a
/// transition strip are walked in this order, which decides whether the next triangle takes a
/// point from the inside or the outside row. (The reference tessellator's table.)
const FINAL_POSITION: [u32; 33] = [
    0, 32, 16, 8, 17, 4, 18, 9, 19, 2, 20, 10, 21, 5, 22, 11, 23, 1, 24, 12, 25, 6, 26, 13, 27, 3,
    28, 14, 29, 7, 30, 15, 31,
];

/// A point of a strip: local index on the inside or the outside row.
#[derive(Clone, Copy)]
enum Row {
    In(u32),
    Out(u32),
}

/// Collects triangles of one strip, translating local indices.
struct Strip<'a, I: Fn(u32) -> u32, O: Fn(u32) -> u32> {
    inside: I,
    outside: O,
    out: &'a mut Vec<[u32; 3]>,
}

impl<I: Fn(u32) -> u32, O: Fn(u32) -> u32> Strip<'_, I, O> {
    fn tri(&mut self, corners: [Row; 3]) {
        let index = |r: Row| match r {
            Row::In(i) => (self.inside)(i),
            Row::Out(o) => (self.outside)(o),
        };
        let t = corners.map(index);
        self.out.push(t);
    }
}

/// The strip between an outer edge and the first inner ring, for any two levels: each side walks
/// its half-row in ruler order, then the middle (a quad, or one triangle when the parities
/// differ), then the mirrored half. `*_half` are the rows' `Ruler::half_points`.
#[allow(clippy::too_many_arguments)]
pub fn transition(
    out: &mut Vec<[u32; 3]>,
    inside: impl Fn(u32) -> u32,
    inside_half: u32,
    inside_odd: bool,
    outside: impl Fn(u32) -> u32,
    outside_half: u32,
    outside_odd: bool,
) {
    let mut s = Strip {
        inside,
        outside,
        out,
    };
    // An odd row's middle segment is stitched separately, so it has one point fewer per half.
    let in_half = inside_half - u32::from(inside_odd);
    let out_half = outside_half - u32::from(outside_odd);
    let (mut i, mut o) = (0, 0);
    // Entry 0 is the row's first point: only the outside row advances on it (the inside row's
    // first point is where the strip starts).
    for (k, &pos) in FINAL_POSITION.iter().enumerate() {
        if k > 0 && pos < in_half {
            s.tri([Row::In(i), Row::Out(o), Row::In(i + 1)]);
            i += 1;
        }
        if pos < out_half {
            s.tri([Row::Out(o), Row::Out(o + 1), Row::In(i)]);
            o += 1;
        }
    }
    if inside_odd != outside_odd || inside_odd {
        if inside_odd == outside_odd {
            // Both odd: the two middle segments make a quad.
            s.tri([Row::In(i), Row::Out(o), Row::In(i + 1)]);
            s.tri([Row::In(i + 1), Row::Out(o), Row::Out(o + 1)]);
            i += 1;
            o += 1;
        } else if !inside_odd {
            // Only the outside has a middle segment: one triangle pointing inward.
            s.tri([Row::In(i), Row::Out(o), Row::Out(o + 1)]);
            o += 1;
        } else {
            // Only the inside has one: a triangle pointing outward.
            s.tri([Row::In(i), Row::Out(o), Row::In(i + 1)]);
            i += 1;
        }
    }
    for (k, &pos) in FINAL_POSITION.iter().enumerate().rev() {
        if pos < out_half {
            s.tri([Row::Out(o), Row::Out(o + 1), Row::In(i)]);
            o += 1;
        }
        if k > 0 && pos < in_half {
            s.tri([Row::In(i), Row::Out(o), Row::In(i + 1)]);
            i += 1;
        }
    }
}

/// The strip between two inner rings: the outside row has two points more than the inside row
/// (`inside_points`), so a triangle at each end and quads between, their diagonals mirrored about
/// the middle so the strip is symmetric.
pub fn regular(
    out: &mut Vec<[u32; 3]>,
    inside: impl Fn(u32) -> u32,
    outside: impl Fn(u32) -> u32,
    inside_points: u32,
) {
    let mut s = Strip {
        inside,
        outside,
        out,
    };
    s.tri([Row::Out(0), Row::Out(1), Row::In(0)]);
    let (mut i, mut o) = (0, 1);
    for p in 0..inside_points.saturating_sub(1) {
        if p < inside_points / 2 {
            // First half: diagonals from the outside row's earlier point to the inside's later.
            s.tri([Row::Out(o), Row::In(i + 1), Row::In(i)]);
            s.tri([Row::Out(o), Row::Out(o + 1), Row::In(i + 1)]);
        } else {
            // Second half: the mirror image.
            s.tri([Row::In(i), Row::Out(o), Row::Out(o + 1)]);
            s.tri([Row::In(i), Row::Out(o + 1), Row::In(i + 1)]);
        }
        i += 1;
        o += 1;
    }
    s.tri([Row::Out(o), Row::Out(o + 1), Row::In(i)]);
}
