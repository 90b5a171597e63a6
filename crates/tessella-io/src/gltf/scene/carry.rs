//! Where each output vertex of a primitive comes from, and the attributes carried there.
//!
//! The output holds the refined mesh's vertices (coarse corners first, then what
//! [`tessella_core::refine::Plan::origin`] places on faces), then one flat pattern per
//! degenerate triangle. Every vertex is a barycentric combination of one coarse triangle's
//! corners, so texture coordinates, colours and any other float attribute are the corners'
//! values interpolated with those weights, in f64 and rounded once — the linear interpolation
//! a rasteriser does across the coarse triangle.

use tessella_core::refine::NO_FACE;

/// The corners and weights of every output vertex.
pub(super) struct Origins {
    /// Per output vertex: its coarse triangle's corners (all three the same vertex for a
    /// coarse corner itself) and barycentric weights.
    pub corners: Vec<[u32; 3]>,
    pub weights: Vec<[f64; 3]>,
}

impl Origins {
    /// From the refinement's origin (`faces`, `bary` over `triangles`, the refined mesh's
    /// faces), then `level`-pattern points on each of `flat` (degenerate) triangles.
    pub fn new(
        faces: &[u32],
        bary: &[[f32; 3]],
        triangles: &[[u32; 3]],
        flat: &[[u32; 3]],
        pattern: &[[f64; 3]],
    ) -> Origins {
        let n = faces.len() + flat.len() * pattern.len();
        let (mut corners, mut weights) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for (v, (&f, l)) in faces.iter().zip(bary).enumerate() {
            if f == NO_FACE {
                corners.push([v as u32; 3]);
                weights.push([1.0, 0.0, 0.0]);
            } else {
                corners.push(triangles[f as usize]);
                weights.push(l.map(f64::from));
            }
        }
        for t in flat {
            for l in pattern {
                corners.push(*t);
                weights.push(*l);
            }
        }
        Origins { corners, weights }
    }

    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// `values` (`width` per coarse vertex) interpolated at every output vertex.
    pub fn interpolate(&self, values: &[f32], width: usize) -> Vec<f32> {
        use rayon::prelude::*;
        let mut out = vec![0.0f32; self.len() * width];
        // Each vertex on its own: the same bits in any order, on any number of threads.
        out.par_chunks_mut(width * 4096)
            .zip(
                self.corners
                    .par_chunks(4096)
                    .zip(self.weights.par_chunks(4096)),
            )
            .for_each(|(out, (corners, weights))| {
                for ((dst, t), l) in out.chunks_exact_mut(width).zip(corners).zip(weights) {
                    for (c, d) in dst.iter_mut().enumerate() {
                        let v = |k: usize| values[t[k] as usize * width + c] as f64;
                        *d = (l[0] * v(0) + l[1] * v(1) + l[2] * v(2)) as f32;
                    }
                }
            });
        out
    }

    /// The corner with the largest weight (the first of equals), for values that cannot be
    /// blended (integer ids).
    pub fn nearest(&self) -> Vec<u32> {
        self.corners
            .iter()
            .zip(&self.weights)
            .map(|(t, l)| {
                let k = (0..3).fold(0, |best, k| if l[k] > l[best] { k } else { best });
                t[k]
            })
            .collect()
    }
}
