//! Refinement in pieces on the CPU: the vertices of one piece of a plan's output
//! ([`Plan::pieces`]), the same values [`Plan::evaluate`] puts there.

use super::output::{Sink, VertexOutput};
use crate::error::RefineError;
use crate::refine::plan::pieces::Piece;
use crate::refine::plan::surface::Frame;
use crate::refine::plan::table::Plan;

impl Plan {
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

    fn piece_k<const K: usize>(&self, frame: &Frame, piece: &Piece, sink: Sink) {
        let job = self.job(frame);
        match piece.clone() {
            Piece::Faces(r) => job.soup_faces::<K>(r.start, sink, &|_| {}),
            Piece::Corners(r) => job.corners::<K>(r.start, sink),
            Piece::Edges(r) => job.edges::<K>(r.start, sink),
            Piece::Interiors(r) => job.interiors::<K>(r.start, sink, &|_| {}),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::plan::pieces::Kind;
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
                    let level = format!("{:?}", options.levels);
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
