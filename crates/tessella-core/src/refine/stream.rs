//! Refinement in pieces, for outputs larger than memory: the welded layout (corners | edges |
//! interiors) cut into runs of whole corners, edges or faces, or the unwelded one into runs of
//! whole faces, each evaluated on its own into a small buffer, and the triangles of any range
//! of faces; uniform plans and adaptive ones (whose elements differ in size: the tiling's
//! offsets say where each starts). Concatenated in order, the pieces are exactly
//! [`Plan::evaluate`]'s vertices and [`Plan::indices`]'s triangles, bit for bit: each vertex
//! is computed by the same evaluation on the same owning face.

use super::output::{Sink, VertexOutput};
use super::plan::{Frame, Plan, NO_FACE};
use crate::error::RefineError;
use crate::pattern::Pattern;
use rayon::prelude::*;
use std::ops::Range;

/// Faces per parallel task when writing a piece's triangles.
const FACES_PER_TASK: usize = 32;

/// A run of consecutive output vertices made of whole elements of the layout.
#[derive(Debug, Clone, PartialEq, Eq)]
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
enum Kind {
    Corners,
    Edges,
    Interiors,
    Faces,
}

impl Kind {
    fn of(piece: &Piece) -> (Kind, &Range<usize>) {
        match piece {
            Piece::Corners(r) => (Kind::Corners, r),
            Piece::Edges(r) => (Kind::Edges, r),
            Piece::Interiors(r) => (Kind::Interiors, r),
            Piece::Faces(r) => (Kind::Faces, r),
        }
    }

    fn piece(self, r: Range<usize>) -> Piece {
        match self {
            Kind::Corners => Piece::Corners(r),
            Kind::Edges => Piece::Edges(r),
            Kind::Interiors => Piece::Interiors(r),
            Kind::Faces => Piece::Faces(r),
        }
    }
}

impl Plan {
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

    /// Writes the vertices of `piece` (from [`Plan::pieces`]) into `out`, which holds
    /// [`Plan::piece_vertices`]`.len()` slots; the same values [`Plan::evaluate`] puts there.
    pub fn evaluate_piece(
        &self,
        frame: &Frame,
        piece: &Piece,
        out: VertexOutput<'_>,
    ) -> Result<(), RefineError> {
        self.check_frame(frame)?;
        self.check_piece(piece)?;
        let sink = out.sink(self.piece_vertices(piece).len(), self.has_uvs())?;
        if let Some(job) = self.adaptive_job(frame) {
            job.piece(piece, sink);
            return Ok(());
        }
        match frame.nets().basis.len() {
            10 => self.piece_k::<10>(frame, piece, sink),
            21 => self.piece_k::<21>(frame, piece, sink),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
        Ok(())
    }

    /// Errors unless `piece` is one of this plan's: a uniform plan, the layout's kind of
    /// piece, a range within the mesh.
    fn check_piece(&self, piece: &Piece) -> Result<(), RefineError> {
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

    fn piece_k<const K: usize>(&self, frame: &Frame, piece: &Piece, sink: Sink) {
        let job = self.job(frame);
        match piece.clone() {
            Piece::Faces(r) => job.soup_faces::<K>(r.start, sink, &|_| {}),
            Piece::Corners(r) => job.corners::<K>(r.start, sink),
            Piece::Edges(r) => job.edges::<K>(r.start, sink),
            Piece::Interiors(r) => job.interiors::<K>(r.start, sink, &|_| {}),
        }
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

/// `0..count` cut into consecutive runs whose span `at(end) - at(start)` stays within `max`
/// (a run of one element may be larger), `at` being non-decreasing.
fn greedy_runs(count: usize, max: usize, at: impl Fn(usize) -> usize) -> Vec<Range<usize>> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::{Levels, Spacing};
    use crate::{samples, RefineOptions, Scheme};

    /// Pieces of every size, concatenated, against the whole evaluation and the whole index
    /// table, for a cubic and a 21-point basis, with and without UVs.
    #[test]
    fn pieces_concatenate_to_the_whole_evaluation() {
        let meshes = [samples::icosphere(1), samples::tetrahedron()];
        for mesh in &meshes {
            for (scheme, weld) in [
                (Scheme::Pn, true),
                (Scheme::Png1, true),
                (Scheme::Pn, false),
                (Scheme::Png1, false),
            ] {
                // Uniform levels, then adaptive plans: a fractional level on a tessellator
                // spacing, and a level per edge (edges of different lengths in one piece).
                let ne = crate::mesh::Topology::new(mesh).edges.len();
                let per_edge = Levels::PerEdge {
                    edges: (0..ne).map(|e| 1.0 + (e % 4) as f32).collect(),
                    faces: None,
                };
                let adaptive = [
                    RefineOptions::new(scheme, 1)
                        .with_spacing(Spacing::FractionalOdd)
                        .with_uniform_level(3.4),
                    RefineOptions::new(scheme, 1).with_levels(per_edge),
                ];
                let uniform = [1, 2, 5].map(|level| RefineOptions::new(scheme, level));
                for options in uniform.into_iter().chain(adaptive) {
                    let options = options.with_weld(weld);
                    let level = options.level;
                    let plan = Plan::new(mesh, &options).unwrap();
                    let frame = plan.frame(mesh).unwrap();
                    let n = plan.vertex_count();
                    let (mut pos, mut nrm) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
                    plan.evaluate(
                        &frame,
                        VertexOutput::Separate {
                            positions: &mut pos,
                            normals: Some(&mut nrm),
                            uvs: None,
                        },
                    )
                    .unwrap();
                    let (faces, bary) = plan.origin();
                    for max in [1, 7, 1000] {
                        let (mut p2, mut n2) = (Vec::new(), Vec::new());
                        let (mut f2, mut b2) = (Vec::new(), Vec::new());
                        for piece in plan.pieces(max) {
                            let len = plan.piece_vertices(&piece).len();
                            // One element may be larger: an edge, or a face's pattern.
                            let (_, r) = Kind::of(&piece);
                            assert!(len <= max || r.len() == 1, "{piece:?}: {len}");
                            let (mut p, mut q) = (vec![[0.0f32; 3]; len], vec![[0.0f32; 3]; len]);
                            plan.evaluate_piece(
                                &frame,
                                &piece,
                                VertexOutput::Separate {
                                    positions: &mut p,
                                    normals: Some(&mut q),
                                    uvs: None,
                                },
                            )
                            .unwrap();
                            p2.extend(p);
                            n2.extend(q);
                            let (mut f, mut b) = (vec![0u32; len], vec![[0.0f32; 3]; len]);
                            plan.write_piece_origin(&piece, &mut f, &mut b).unwrap();
                            f2.extend(f);
                            b2.extend(b);
                        }
                        let bits = |v: &[[f32; 3]]| -> Vec<[u32; 3]> {
                            v.iter().map(|p| p.map(f32::to_bits)).collect()
                        };
                        let what = format!("{scheme:?} weld {weld} level {level} max {max}");
                        assert_eq!(bits(&p2), bits(&pos), "{what}");
                        assert_eq!(bits(&n2), bits(&nrm), "{what}");
                        assert_eq!((&f2, bits(&b2)), (&faces, bits(&bary)), "{what}");
                    }
                    for max in [1, 50, usize::MAX] {
                        let mut tris = Vec::new();
                        for run in plan.face_runs(max) {
                            let mut t = vec![[0u32; 3]; plan.face_triangles(run.clone()).len()];
                            assert!(t.len() <= max || run.len() == 1);
                            plan.write_face_indices(run, &mut t).unwrap();
                            tris.extend(t);
                        }
                        assert_eq!(tris, plan.indices());
                    }
                }
            }
        }
    }

    #[test]
    fn bad_pieces_are_refused() {
        let mesh = samples::tetrahedron();
        let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
        let frame = plan.frame(&mesh).unwrap();
        let mut p = vec![[0.0f32; 3]; 100];
        let out = VertexOutput::Separate {
            positions: &mut p,
            normals: None,
            uvs: None,
        };
        assert!(plan
            .evaluate_piece(&frame, &Piece::Interiors(0..99), out)
            .is_err());
        let mut t = vec![[0u32; 3]; 16];
        assert!(plan.write_face_indices(3..5, &mut t).is_err());
        // Origins: one slot per vertex of the piece, neither more nor fewer.
        let edges = Piece::Edges(0..2);
        let (mut f, mut b) = (vec![0u32; 6], vec![[0.0f32; 3]; 6]);
        assert!(plan.write_piece_origin(&edges, &mut f, &mut b).is_ok());
        assert!(plan
            .write_piece_origin(&edges, &mut f[..5], &mut b[..5])
            .is_err());
        assert!(plan
            .write_piece_origin(&Piece::Edges(5..7), &mut f, &mut b)
            .is_err());
        // Pieces of the other layout: faces of a welded plan, interiors of a soup.
        let mut p = vec![[0.0f32; 3]; 15];
        fn positions(p: &mut [[f32; 3]]) -> VertexOutput<'_> {
            VertexOutput::Separate {
                positions: p,
                normals: None,
                uvs: None,
            }
        }
        assert!(plan
            .evaluate_piece(&frame, &Piece::Faces(0..1), positions(&mut p))
            .is_err());
        let soup = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4).with_weld(false)).unwrap();
        let soup_frame = soup.frame(&mesh).unwrap();
        assert!(soup
            .pieces(100)
            .iter()
            .all(|p| matches!(p, Piece::Faces(_))));
        assert!(soup
            .evaluate_piece(&soup_frame, &Piece::Interiors(0..1), positions(&mut p))
            .is_err());
        assert!(soup
            .evaluate_piece(&soup_frame, &Piece::Faces(3..5), positions(&mut p))
            .is_err());
        // An adaptive plan's pieces are checked against its own element counts.
        let spaced = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalOdd)
            .with_uniform_level(4.0);
        let adaptive = Plan::new(&mesh, &spaced).unwrap();
        assert!(adaptive.tiling().is_some() && !adaptive.pieces(100).is_empty());
        let frame = adaptive.frame(&mesh).unwrap();
        assert!(adaptive
            .evaluate_piece(&frame, &Piece::Interiors(3..5), positions(&mut p))
            .is_err());
    }
}
