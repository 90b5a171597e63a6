//! Refinement in pieces, for outputs larger than memory: the welded layout (corners | edges |
//! interiors) cut into runs of whole corners, edges or faces, or the unwelded one into runs of
//! whole faces, each evaluated on its own into a small buffer, and the triangles of any range
//! of faces; uniform plans and adaptive ones (whose elements differ in size: the tiling's
//! offsets say where each starts). Concatenated in order, the pieces are exactly
//! [`Plan::evaluate`]'s vertices and [`Plan::indices`]'s triangles, bit for bit: each vertex
//! is computed by the same evaluation on the same owning face.
//!
//! This file holds what is built from the plan alone (the pieces, their triangles and
//! origins); the CPU evaluation of a piece is `cpu::stream`'s.

use super::layout::NO_FACE;
use super::pieces::{greedy_runs, Kind, Piece};
use super::table::Plan;
use crate::error::RefineError;
use crate::pattern::Pattern;
use rayon::prelude::*;
use std::ops::Range;

/// Faces per parallel task when writing a piece's triangles.
const FACES_PER_TASK: usize = 32;

impl Plan {
    /// Where each refined vertex comes from: the coarse face it was evaluated on and its
    /// barycentric coordinates `(l1, l2, l3)` in that face's corner order. A vertex shared by
    /// several faces (welded output) names the face that owns it; a coarse vertex no face uses
    /// gets [`NO_FACE`] and `(1, 0, 0)`. Depends on the plan only, like the indices.
    ///
    /// ```
    /// use tessella_core::refine::Plan;
    /// use tessella_core::{samples, RefineOptions, Scheme};
    /// let mesh = samples::icosphere(0);
    /// let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
    /// let (faces, bary) = plan.origin();
    /// assert_eq!((faces.len(), bary.len()), (plan.vertex_count(), plan.vertex_count()));
    /// // the first V vertices are the coarse corners
    /// let (f, c) = (faces[0] as usize, mesh.triangles()[faces[0] as usize].iter().position(|&v| v == 0).unwrap());
    /// assert_eq!(bary[0][c], 1.0);
    /// # Ok::<(), tessella_core::RefineError>(())
    /// ```
    pub fn origin(&self) -> (Vec<u32>, Vec<[f32; 3]>) {
        let n = self.vertex_count();
        let (mut faces, mut bary) = (vec![NO_FACE; n], vec![[1.0, 0.0, 0.0]; n]);
        self.write_origin(&mut faces, &mut bary)
            .expect("arrays of the plan's size");
        (faces, bary)
    }

    /// [`Plan::origin`] into caller memory (each at least [`Plan::vertex_count`] long).
    pub fn write_origin(
        &self,
        faces: &mut [u32],
        bary: &mut [[f32; 3]],
    ) -> Result<(), RefineError> {
        let n = self.vertex_count();
        for (what, got) in [("origin faces", faces.len()), ("barycentrics", bary.len())] {
            if got < n {
                return Err(RefineError::OutputTooSmall {
                    what: what.into(),
                    got,
                    need: n,
                });
            }
        }
        // The whole layout as pieces: one code path for the whole and for streamed pieces.
        for piece in &self.pieces(usize::MAX) {
            let r = self.piece_vertices(piece);
            self.write_piece_origin(piece, &mut faces[r.clone()], &mut bary[r])?;
        }
        Ok(())
    }

    /// The kinds of element this plan's layout is made of, in output order.
    fn kinds(&self) -> &'static [Kind] {
        match self.layout().weld {
            true => &[Kind::Corners, Kind::Edges, Kind::Interiors],
            false => &[Kind::Faces],
        }
    }

    /// How many elements of `kind` there are.
    fn element_count(&self, kind: Kind) -> usize {
        match kind {
            Kind::Corners => self.coarse_vertex_count(),
            Kind::Edges => self.topology().edges.len(),
            Kind::Interiors | Kind::Faces => self.face_count(),
        }
    }

    /// The first output vertex of element `i` of `kind` (`i` = the count: the end of them
    /// all). Uniform plans: a base and a fixed size; adaptive ones: the tiling's offsets.
    fn element_start(&self, kind: Kind, i: usize) -> usize {
        let layout = self.layout();
        if let Some(tiling) = self.tiling() {
            return match kind {
                Kind::Corners => i,
                Kind::Edges => match tiling.edge_offset.get(i) {
                    Some(&at) => at as usize,
                    None => tiling.face_offset[0] as usize,
                },
                Kind::Interiors | Kind::Faces => tiling.face_offset[i] as usize,
            };
        }
        let (base, per) = match kind {
            Kind::Corners => (0, 1),
            Kind::Edges => (layout.edge_base as usize, layout.level as usize - 1),
            Kind::Interiors => (
                layout.interior_base as usize,
                Pattern::interior_count(layout.level) as usize,
            ),
            Kind::Faces => (0, self.pattern().points.len()),
        };
        base + i * per
    }

    /// The output cut into pieces of at most `max_vertices` vertices (or one element, when an
    /// element alone is larger), in output order; uniform and adaptive plans, welded or soup.
    pub fn pieces(&self, max_vertices: usize) -> Vec<Piece> {
        let max = max_vertices.max(1);
        let mut out = Vec::new();
        for &kind in self.kinds() {
            let count = self.element_count(kind);
            let at = |i: usize| self.element_start(kind, i);
            if at(count) == at(0) {
                continue; // no vertices of this kind (edges at level 1)
            }
            out.extend(
                greedy_runs(count, max, at)
                    .into_iter()
                    .map(|r| kind.piece(r)),
            );
        }
        out
    }

    /// Runs of whole coarse faces with at most `max_triangles` refined triangles each (or
    /// one face, when a face alone has more), in order: how a writer takes the triangles.
    pub fn face_runs(&self, max_triangles: usize) -> Vec<Range<usize>> {
        let per = self.pattern().triangles.len();
        let at = |f: usize| match self.tiling() {
            Some(tiling) => tiling.triangle_offset[f] as usize,
            None => f * per,
        };
        greedy_runs(self.face_count(), max_triangles.max(1), at)
    }

    /// The output vertices `piece` covers.
    pub fn piece_vertices(&self, piece: &Piece) -> Range<usize> {
        let (kind, r) = Kind::of(piece);
        self.element_start(kind, r.start)..self.element_start(kind, r.end)
    }

    /// The refined triangles of faces `faces`, in output order.
    pub fn face_triangles(&self, faces: Range<usize>) -> Range<usize> {
        let at = |f: usize| match self.tiling() {
            Some(tiling) => tiling.triangle_offset[f] as usize,
            None => f * self.pattern().triangles.len(),
        };
        at(faces.start)..at(faces.end)
    }

    /// Errors unless `piece` is one of this plan's: a uniform plan, the layout's kind of
    /// piece, a range within the mesh.
    pub(crate) fn check_piece(&self, piece: &Piece) -> Result<(), RefineError> {
        let (kind, range) = Kind::of(piece);
        let limit = self.element_count(kind);
        if !self.kinds().contains(&kind) || range.start > range.end || range.end > limit {
            return Err(RefineError::BadLevels(format!(
                "{piece:?} is not a piece of this plan (corners, edges and interiors when \
                 welded, faces when not; ranges within the mesh)"
            )));
        }
        Ok(())
    }

    /// [`Plan::origin`] for the vertices of `piece` only: `faces` and `bary` hold
    /// [`Plan::piece_vertices`]`.len()` slots each, and get the values `origin` has there.
    pub fn write_piece_origin(
        &self,
        piece: &Piece,
        faces: &mut [u32],
        bary: &mut [[f32; 3]],
    ) -> Result<(), RefineError> {
        self.check_piece(piece)?;
        let n = self.piece_vertices(piece).len();
        for (what, got) in [("origin faces", faces.len()), ("barycentrics", bary.len())] {
            if got != n {
                return Err(RefineError::OutputTooSmall {
                    what: what.into(),
                    got,
                    need: n,
                });
            }
        }
        if let Some(tiling) = self.tiling() {
            self.adaptive_index(tiling).piece_origin(piece, faces, bary);
            return Ok(());
        }
        let (stencil, topo) = (self.stencil(), self.topology());
        let l = |p: u32| self.pattern().points[p as usize].map(|x| x as f32);
        let slots = faces.iter_mut().zip(bary.iter_mut());
        match piece.clone() {
            Piece::Faces(r) => {
                let np = self.pattern().points.len();
                for (i, (f, b)) in slots.enumerate() {
                    (*f, *b) = ((r.start + i / np) as u32, l((i % np) as u32));
                }
            }
            Piece::Corners(r) => {
                for (v, (f, b)) in r.zip(slots) {
                    (*f, *b) = match topo.vertex_owner[v] {
                        Some((face, c)) => (face, l(stencil.corner_point(c as usize))),
                        None => (NO_FACE, [1.0, 0.0, 0.0]),
                    };
                }
            }
            Piece::Edges(r) => {
                let m = self.layout().level as usize - 1;
                let mut slots = slots;
                for e in r {
                    let (face, k) = topo.edge_owner[e];
                    let forward = self.triangles()[face as usize][k as usize] == topo.edges[e][0];
                    for s in 0..m {
                        let p =
                            stencil.edge_points[k as usize][if forward { s } else { m - 1 - s }];
                        let (f, b) = slots.next().expect("m slots an edge");
                        (*f, *b) = (face, l(p));
                    }
                }
            }
            Piece::Interiors(r) => {
                let interior = &stencil.interior_points;
                let mut slots = slots;
                for face in r {
                    for &p in interior {
                        let (f, b) = slots.next().expect("the interior's slots");
                        (*f, *b) = (face as u32, l(p));
                    }
                }
            }
        }
        Ok(())
    }

    /// Writes the refined triangles of coarse faces `faces` ([`Plan::face_triangles`], in the
    /// order of [`Plan::indices`]) into `out`, exactly that long.
    pub fn write_face_indices(
        &self,
        faces: Range<usize>,
        out: &mut [[u32; 3]],
    ) -> Result<(), RefineError> {
        let per_face = self.pattern().triangles.len();
        if faces.start > faces.end || faces.end > self.face_count() {
            return Err(RefineError::BadLevels(format!(
                "faces {faces:?}: not a range of the mesh's {} faces",
                self.face_count()
            )));
        }
        let need = self.face_triangles(faces.clone()).len();
        if out.len() != need {
            return Err(RefineError::OutputTooSmall {
                what: "triangles".into(),
                got: out.len(),
                need,
            });
        }
        if let Some(tiling) = self.tiling() {
            self.adaptive_index(tiling)
                .face_indices(faces, out, &|_| {});
            return Ok(());
        }
        let (topo, stencil, pattern, layout) = (
            self.topology(),
            self.stencil(),
            self.pattern(),
            self.layout(),
        );
        let n = layout.level as usize;
        let m = n - 1;
        let ni = Pattern::interior_count(layout.level) as usize;
        let np = pattern.points.len();
        out.par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                // Pattern point -> output vertex, rebuilt for each face.
                let mut map = vec![0u32; np];
                for (lf, face_tris) in tris.chunks_mut(per_face).enumerate() {
                    let f = faces.start + task * FACES_PER_TASK + lf;
                    if layout.weld {
                        let t = self.triangles()[f];
                        for (c, &v) in t.iter().enumerate() {
                            map[stencil.corner_point(c) as usize] = v;
                        }
                        #[allow(clippy::needless_range_loop)] // k indexes four tables
                        for k in 0..3 {
                            let e = topo.face_edges[f][k] as usize;
                            let forward = t[k] == topo.edges[e][0];
                            let base = layout.edge_base as usize + e * m;
                            for (s, &p) in stencil.edge_points[k].iter().enumerate() {
                                map[p as usize] =
                                    (base + if forward { s } else { m - 1 - s }) as u32;
                            }
                        }
                        let base = layout.interior_base as usize + f * ni;
                        for (i, &p) in stencil.interior_points.iter().enumerate() {
                            map[p as usize] = (base + i) as u32;
                        }
                    } else {
                        for (p, slot) in map.iter_mut().enumerate() {
                            *slot = (f * np + p) as u32;
                        }
                    }
                    for (dst, src) in face_tris.iter_mut().zip(&pattern.triangles) {
                        *dst = src.map(|p| map[p as usize]);
                    }
                }
            });
        Ok(())
    }
}
