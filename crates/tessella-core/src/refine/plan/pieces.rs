//! Pieces of a plan's output: runs of whole elements of its layout (corners, edges, interiors
//! or faces), for refinement in pieces ([`super::stream`]).

use std::ops::Range;

/// A run of consecutive output vertices made of whole elements of the layout.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Piece {
    /// Coarse vertices (one output vertex each). Welded.
    Corners(Range<usize>),
    /// Unique edges (`level - 1` output vertices each; adaptive: segments - 1). Welded.
    Edges(Range<usize>),
    /// Faces' interior points (`(N-1)(N-2)/2` output vertices each; adaptive: the face's
    /// tile's). Welded.
    Interiors(Range<usize>),
    /// Faces' whole patterns (`(N+1)(N+2)/2` output vertices each; adaptive: the face's
    /// tile's). Unwelded (soup).
    Faces(Range<usize>),
}

/// The kinds of element a layout is made of, in output order.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Corners,
    Edges,
    Interiors,
    Faces,
}

impl Kind {
    pub(crate) fn of(piece: &Piece) -> (Kind, &Range<usize>) {
        match piece {
            Piece::Corners(r) => (Kind::Corners, r),
            Piece::Edges(r) => (Kind::Edges, r),
            Piece::Interiors(r) => (Kind::Interiors, r),
            Piece::Faces(r) => (Kind::Faces, r),
        }
    }

    pub(super) fn piece(self, r: Range<usize>) -> Piece {
        match self {
            Kind::Corners => Piece::Corners(r),
            Kind::Edges => Piece::Edges(r),
            Kind::Interiors => Piece::Interiors(r),
            Kind::Faces => Piece::Faces(r),
        }
    }
}

/// `0..count` cut into consecutive runs whose span `at(end) - at(start)` stays within `max`
/// (a run of one element may be larger), `at` being non-decreasing.
pub(super) fn greedy_runs(
    count: usize,
    max: usize,
    at: impl Fn(usize) -> usize,
) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < count {
        let mut end = start + 1;
        // Doubling, then halving: long runs of small elements in O(log) steps.
        let mut step = 1;
        while end + step <= count && at(end + step) - at(start) <= max {
            end += step;
            step *= 2;
        }
        while step > 0 {
            if end + step <= count && at(end + step) - at(start) <= max {
                end += step;
            }
            step /= 2;
        }
        out.push(start..end);
        start = end;
    }
    out
}
