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
    /// The same weights transposed (weight-major) for runs of points that are evaluated
    /// together: the interior points, each edge's points, and all points (soup output).
    pub blocks: StencilBlocks,
}

/// Points a [`Block`]'s weight rows are padded to a multiple of: the evaluator's vector width.
pub const BLOCK_LANES: usize = 16;

/// Transposed weight tables, see [`Block`].
#[derive(Debug, Clone, PartialEq)]
pub struct StencilBlocks {
    pub interior: Block,
    pub edges: [Block; 3],
    pub all: Block,
}

/// Weights of a run of pattern points, weight-major: `value[k * stride + i]` is control point
/// `k`'s weight at the run's point `i`. Summing `weight × control point` over `k` for many points
/// at once is then a run of independent multiply-adds the compiler vectorises. Each control
/// point's weights are padded with zeros to [`Block::stride`] (a multiple of [`BLOCK_LANES`])
/// so the evaluator sums whole vectors, also for runs shorter than one.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Pattern point index of each point of the run.
    pub points: Vec<u32>,
    /// Floats between one control point's weights and the next's: the run's length rounded
    /// up to a multiple of [`BLOCK_LANES`].
    pub stride: usize,
    pub value: Vec<f32>,
    pub du: Vec<f32>,
    pub dv: Vec<f32>,
    /// Weights of the six control normals, `normal[k * stride + i]`.
    pub normal: Vec<f32>,
    /// Each point's barycentric `l` (the rows' last three floats), contiguous, for texture
    /// coordinates.
    pub barycentric: Vec<[f32; 3]>,
}

impl Block {
    fn new(points: Vec<u32>, rows: &[f32], k: usize) -> Block {
        let row_len = Stencil::stride_for(k);
        let stride = points.len().next_multiple_of(BLOCK_LANES);
        let column = |offset: usize, count: usize| {
            let mut out = vec![0.0f32; count * stride];
            for (i, &p) in points.iter().enumerate() {
                let row = &rows[p as usize * row_len..];
                for c in 0..count {
                    out[c * stride + i] = row[offset + c];
                }
            }
            out
        };
        Block {
            stride,
            value: column(0, k),
            du: column(k, k),
            dv: column(2 * k, k),
            normal: column(3 * k, NORMAL_NET_LEN),
            barycentric: points
                .iter()
                .map(|&p| {
                    let end = (p as usize + 1) * row_len;
                    [rows[end - 3], rows[end - 2], rows[end - 1]]
                })
                .collect(),
            points,
        }
    }
    /// Number of points in the run.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// True when the run is empty.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
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
        Self::from_rows(pattern, basis, |p| Self::row_f64(basis, pattern.points[p]))
    }

    /// The f64 weights at `l`, `value[K] | du[K] | dv[K] | normal[6]` (a row without its `l`).
    pub fn row_f64(basis: Basis, l: [f64; 3]) -> Vec<f64> {
        let w = basis.weights(l);
        let mut row = Vec::with_capacity(3 * basis.len() + NORMAL_NET_LEN);
        row.extend(w.value.iter().chain(&w.du).chain(&w.dv));
        row.extend(normal_weights(l));
        row
    }

    /// The table for `pattern` with pattern point `p`'s f64 weights given by `row(p)`
    /// (`value[K] | du[K] | dv[K] | normal[6]`, as [`Stencil::row_f64`]), stored as f32 with
    /// the point's `l` appended. [`Stencil::new`] is this with the basis' own weights; the
    /// geomorphing grid tiles pass blended rows (see `refine::morph`).
    pub fn from_rows(
        pattern: &Pattern,
        basis: Basis,
        mut row: impl FnMut(usize) -> Vec<f64>,
    ) -> Stencil {
        let k = basis.len();
        let stride = Self::stride_for(k);
        let mut weights = Vec::with_capacity(pattern.points.len() * stride);
        for (p, &l) in pattern.points.iter().enumerate() {
            let r = row(p);
            assert_eq!(r.len(), stride - 3, "a stencil row of the basis' length");
            weights.extend(r.iter().map(|&x| x as f32));
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
        let blocks = StencilBlocks {
            interior: Block::new(interior_points.clone(), &weights, k),
            edges: edge_points.clone().map(|e| Block::new(e, &weights, k)),
            all: Block::new((0..pattern.points.len() as u32).collect(), &weights, k),
        };
        Stencil {
            basis,
            level: pattern.level,
            weights,
            edge_points,
            interior_points,
            blocks,
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
