//! A refinement (uniform or adaptive, welded or soup) as a [`MeshSource`]: the plan's
//! [`Piece`]s evaluated one after the other into
//! a few reused buffers, the next piece computed on another thread while the last is written,
//! so memory holds a few pieces whatever the output's size. An output that fits in one piece's
//! budget (a small file) is evaluated on the writer's thread, with no thread started.
//! Per-vertex fields and origins, when asked for, are computed piece by piece too.

use crate::ply::{Origin, VertexScalars};
use crate::stream::{MeshSource, VertexRun, Wanted};
use crate::MeshView;
use std::ops::Range;
use std::sync::mpsc;
use tessella_core::fields::FieldError;
use tessella_core::refine::{Frame, Piece, Plan, VertexOutput};
use tessella_core::{DisplaceError, DisplaceFrame, Displacement, SharedSlots};

/// Bytes of one vertex in the piece buffers (position, normal, uv), before fields and origins.
const VERTEX_BYTES: usize = 32;
/// Bytes of one vertex's origin (face, barycentrics) and of one field value.
const ORIGIN_BYTES: usize = 16;
const FIELD_BYTES: usize = 4;

/// A refinement of `frame` (uniform or adaptive, welded or not), produced piece by piece,
/// displaced when
/// asked ([`RefinedSource::displaced`]), with per-vertex fields
/// ([`RefinedSource::with_fields`]) and origins ([`RefinedSource::with_origin`]) when asked.
pub struct RefinedSource<'a> {
    plan: &'a Plan,
    frame: &'a Frame<'a>,
    budget: u64,
    displace: Option<Displace<'a>>,
    fields: &'a [(String, Vec<f32>)],
    origin: bool,
}

/// A displacement and what it needs of the mesh, built once for every piece.
struct Displace<'a> {
    displacement: &'a Displacement,
    frame: DisplaceFrame,
    shared: SharedSlots,
}

impl<'a> RefinedSource<'a> {
    /// A source whose buffers (three pieces in flight) stay within about `budget` bytes:
    /// uniform and adaptive plans, welded or soup.
    pub fn new(plan: &'a Plan, frame: &'a Frame<'a>, budget: u64) -> RefinedSource<'a> {
        RefinedSource {
            plan,
            frame,
            budget,
            displace: None,
            fields: &[],
            origin: false,
        }
    }

    /// The same source with per-vertex fields of the coarse mesh (`(name, one value per
    /// coarse vertex)`) carried to every refined vertex, linear on each coarse face (quadratic
    /// on second-order faces), as [`tessella_core::fields::interpolate_point_data`] does for
    /// a whole refinement. Errors name a field of the wrong length or with a NaN or infinity.
    pub fn with_fields(
        mut self,
        fields: &'a [(String, Vec<f32>)],
    ) -> Result<RefinedSource<'a>, FieldError> {
        for (name, values) in fields {
            tessella_core::fields::check_point_data(self.frame.mesh(), name, values, 1)?;
        }
        self.fields = fields;
        Ok(self)
    }

    /// The same source with each vertex's origin (its coarse face and barycentrics,
    /// [`Plan::origin`]) in the vertex runs: PLY's `face`, `bary1..3` properties.
    pub fn with_origin(mut self) -> RefinedSource<'a> {
        self.origin = true;
        self
    }

    /// The same source with every vertex displaced by `displacement`: the positions
    /// [`Displacement::apply`] gives the whole refinement, piece by piece. Errors when the
    /// displacement needs texture coordinates the mesh lacks, and for adaptive plans.
    pub fn displaced(
        mut self,
        displacement: &'a Displacement,
    ) -> Result<RefinedSource<'a>, DisplaceError> {
        if self.plan.tiling().is_some() {
            return Err(DisplaceError::Adaptive);
        }
        displacement.validate(self.plan.has_uvs())?;
        let frame = DisplaceFrame::new(self.frame.mesh(), self.plan.topology(), self.plan.layout());
        let shared = frame.shared();
        self.displace = Some(Displace {
            displacement,
            frame,
            shared,
        });
        Ok(self)
    }

    /// Bytes of one vertex in the piece buffers, with this source's fields and origins.
    fn vertex_bytes(&self) -> usize {
        VERTEX_BYTES + FIELD_BYTES * self.fields.len() + if self.origin { ORIGIN_BYTES } else { 0 }
    }

    /// Vertices per piece: three pieces in flight and the encoders' blocks, an eighth of the
    /// budget each.
    fn piece_vertices(&self) -> usize {
        (self.budget / 8 / self.vertex_bytes() as u64).clamp(1024, 1 << 24) as usize
    }

    /// The refined triangles in runs of whole coarse faces (about a piece's worth of bytes
    /// each): `each(faces, their triangles)`, in output order.
    fn face_runs(&self, each: &mut FaceRun<'_>) -> std::io::Result<()> {
        let mut run = Vec::new();
        for faces in self
            .plan
            .face_runs(self.piece_vertices() * VERTEX_BYTES / 12)
        {
            run.resize(self.plan.face_triangles(faces.clone()).len(), [0u32; 3]);
            self.plan
                .write_face_indices(faces.clone(), &mut run)
                .map_err(std::io::Error::other)?;
            each(faces, &run)?;
        }
        Ok(())
    }
}

/// What [`RefinedSource::face_runs`] hands each run to: the faces and their triangles.
type FaceRun<'a> = dyn FnMut(Range<usize>, &[[u32; 3]]) -> std::io::Result<()> + 'a;

/// One evaluated piece: positions, and normals, uvs, origins and fields when asked for.
#[derive(Default)]
struct Buffers {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    faces: Vec<u32>,
    bary: Vec<[f32; 3]>,
    fields: Vec<Vec<f32>>,
}

impl Buffers {
    /// Evaluates `piece` of `source` (displaced when the source displaces: that needs the
    /// normals, and the uvs when the mesh has them, whatever `want` says).
    fn fill(&mut self, source: &RefinedSource, piece: &Piece, want: Wanted) -> std::io::Result<()> {
        let (plan, frame, displace) = (source.plan, source.frame, source.displace.as_ref());
        if want.extras {
            self.fill_extras(source, piece)?;
        }
        let want = match displace {
            Some(_) => Wanted {
                normals: true,
                uvs: plan.has_uvs(),
                extras: want.extras,
            },
            None => want,
        };
        let range = plan.piece_vertices(piece);
        let n = range.len();
        self.positions.resize(n, [0.0; 3]);
        self.normals
            .resize(if want.normals { n } else { 0 }, [0.0; 3]);
        self.uvs.resize(if want.uvs { n } else { 0 }, [0.0; 2]);
        plan.evaluate_piece(
            frame,
            piece,
            VertexOutput::Separate {
                positions: &mut self.positions,
                normals: want.normals.then_some(&mut self.normals[..]),
                uvs: want.uvs.then_some(&mut self.uvs[..]),
            },
        )
        .map_err(std::io::Error::other)?;
        if let Some(d) = displace {
            d.displacement
                .apply_range(
                    range.start,
                    &mut self.positions,
                    &self.normals,
                    want.uvs.then_some(&self.uvs[..]),
                    &d.frame,
                    &d.shared,
                )
                .map_err(std::io::Error::other)?;
        }
        Ok(())
    }

    /// The origins of `piece`'s vertices, and its fields interpolated there.
    fn fill_extras(&mut self, source: &RefinedSource, piece: &Piece) -> std::io::Result<()> {
        if !source.origin && source.fields.is_empty() {
            return Ok(());
        }
        let plan = source.plan;
        let range = plan.piece_vertices(piece);
        let n = range.len();
        self.faces.resize(n, 0);
        self.bary.resize(n, [0.0; 3]);
        plan.write_piece_origin(piece, &mut self.faces, &mut self.bary)
            .map_err(std::io::Error::other)?;
        self.fields.resize_with(source.fields.len(), Vec::new);
        for ((_, values), out) in source.fields.iter().zip(&mut self.fields) {
            out.resize(n, 0.0);
            tessella_core::fields::interpolate_into(
                source.frame.mesh(),
                range.start,
                &self.faces,
                &self.bary,
                values,
                1,
                out,
            );
        }
        Ok(())
    }

    fn view(&self, want: Wanted) -> MeshView<'_> {
        MeshView {
            positions: &self.positions,
            normals: want.normals.then_some(&self.normals[..]),
            uvs: want.uvs.then_some(&self.uvs[..]),
            triangles: &[],
        }
    }

    /// The fields of the last piece filled with extras, named as `source` names them.
    fn scalars<'b>(&'b self, source: &'b RefinedSource, want: Wanted) -> Vec<(&'b str, &'b [f32])> {
        match want.extras {
            true => source
                .fields
                .iter()
                .zip(&self.fields)
                .map(|((name, _), values)| (name.as_str(), values.as_slice()))
                .collect(),
            false => Vec::new(),
        }
    }

    /// The run `each` gets: the piece's view, and its extras when asked for.
    fn run<'b>(
        &'b self,
        source: &RefinedSource,
        want: Wanted,
        scalars: &'b VertexScalars<'b>,
    ) -> VertexRun<'b> {
        VertexRun {
            mesh: self.view(want),
            scalars,
            origin: (want.extras && source.origin).then_some(Origin {
                faces: &self.faces,
                bary: &self.bary,
            }),
        }
    }
}

impl MeshSource for RefinedSource<'_> {
    fn vertex_count(&self) -> u64 {
        self.plan.vertex_count() as u64
    }
    fn triangle_count(&self) -> u64 {
        self.plan.triangle_count() as u64
    }
    fn has_normals(&self) -> bool {
        true
    }
    fn has_uvs(&self) -> bool {
        self.plan.has_uvs()
    }
    fn scalar_names(&self) -> Vec<&str> {
        self.fields.iter().map(|(name, _)| name.as_str()).collect()
    }
    fn has_origin(&self) -> bool {
        self.origin
    }

    fn vertices(
        &self,
        want: Wanted,
        each: &mut dyn FnMut(VertexRun<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let want = Wanted {
            normals: want.normals,
            uvs: want.uvs && self.plan.has_uvs(),
            extras: want.extras,
        };
        let pieces = self.plan.pieces(self.piece_vertices());
        // The whole output within one piece's budget (a small file, as in a batch of many):
        // its few pieces (corners, edges, interiors) are evaluated here in turn, with no
        // thread to start and one buffer reused.
        if self.plan.vertex_count() <= self.piece_vertices() {
            let mut buffers = Buffers::default();
            for piece in &pieces {
                buffers.fill(self, piece, want)?;
                let scalars = buffers.scalars(self, want);
                each(buffers.run(self, want, &scalars))?;
            }
            return Ok(());
        }
        // Full buffers go to the writer, empty ones come back; three exist in all.
        let (full_tx, full_rx) = mpsc::sync_channel::<std::io::Result<Buffers>>(1);
        let (empty_tx, empty_rx) = mpsc::channel::<Buffers>();
        for _ in 0..3 {
            empty_tx
                .send(Buffers::default())
                .map_err(std::io::Error::other)?;
        }
        // `move`: the writer's ends of both channels drop when it returns (early, on an
        // error, too), which stops the evaluating thread before the scope joins it.
        std::thread::scope(move |scope| {
            scope.spawn(move || {
                for piece in &pieces {
                    // The writer hung up (it failed): stop.
                    let Ok(mut buffers) = empty_rx.recv() else {
                        return;
                    };
                    let filled = buffers.fill(self, piece, want);
                    if full_tx.send(filled.map(|()| buffers)).is_err() {
                        return;
                    }
                }
            });
            // Ends when the evaluating thread has sent every piece and hung up.
            for filled in full_rx.iter() {
                let buffers = filled?;
                let scalars = buffers.scalars(self, want);
                each(buffers.run(self, want, &scalars))?;
                // Refused once the evaluator has sent its last piece and gone: the buffer is
                // then dropped, and the pieces still queued are written all the same.
                if let Err(mpsc::SendError(unused)) = empty_tx.send(buffers) {
                    drop(unused);
                }
            }
            Ok(())
        })
    }

    fn triangles(
        &self,
        each: &mut dyn FnMut(&[[u32; 3]]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        self.face_runs(&mut |_, run| each(run))
    }

    fn triangle_corners(
        &self,
        each: &mut dyn FnMut(&[crate::stream::Corners]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let plan = self.plan;
        let layout = plan.layout();
        let topology = plan.topology();
        let positions_only = Wanted {
            normals: false,
            uvs: false,
            extras: false,
        };
        let (mut interiors, mut edges) = (Buffers::default(), Buffers::default());
        let mut out = Vec::new();
        if !layout.weld {
            // Unwelded: a run of faces' patterns holds every corner of its triangles.
            return self.face_runs(&mut |faces, triangles| {
                let piece = Piece::Faces(faces);
                interiors.fill(self, &piece, positions_only)?;
                let first = plan.piece_vertices(&piece).start;
                out.clear();
                out.extend(
                    triangles
                        .iter()
                        .map(|t| t.map(|v| interiors.positions[v as usize - first])),
                );
                each(&out)
            });
        }
        // The coarse vertices' output positions (displaced, when displacing), a few per
        // coarse vertex.
        let mut corners = Buffers::default();
        let coarse = Piece::Corners(0..plan.coarse_vertex_count());
        corners.fill(self, &coarse, positions_only)?;
        let corners = corners.positions;
        // Where the edges' and the interiors' vertices start in the output.
        let edge_first = plan.coarse_vertex_count();
        let interior_start = plan.piece_vertices(&Piece::Interiors(0..0)).start;
        self.face_runs(&mut |faces, triangles| {
            let Range { start, end } = faces;
            let interior_piece = Piece::Interiors(start..end);
            interiors.fill(self, &interior_piece, positions_only)?;
            let interior_first = plan.piece_vertices(&interior_piece).start;
            // The run's edges, evaluated in runs of consecutive edge numbers.
            let mut unique: Vec<usize> = topology.face_edges[start..end]
                .iter()
                .flatten()
                .map(|&e| e as usize)
                .collect();
            unique.sort_unstable();
            unique.dedup();
            // Each run of consecutive edges is one piece: its output vertices, consecutive
            // too, sit at `offset..` of `edge_positions` (sorted by first vertex).
            let mut spans: Vec<(usize, usize)> = Vec::new();
            let mut edge_positions: Vec<[f32; 3]> = Vec::new();
            let mut i = 0;
            while i < unique.len() {
                let mut j = i + 1;
                while j < unique.len() && unique[j] == unique[j - 1] + 1 {
                    j += 1;
                }
                let piece = Piece::Edges(unique[i]..unique[j - 1] + 1);
                edges.fill(self, &piece, positions_only)?;
                spans.push((plan.piece_vertices(&piece).start, edge_positions.len()));
                edge_positions.extend_from_slice(&edges.positions);
                i = j;
            }
            let at = |v: u32| -> [f32; 3] {
                let v = v as usize;
                if v < edge_first {
                    corners[v]
                } else if v < interior_start {
                    let (first, offset) = spans[spans.partition_point(|&(f, _)| f <= v) - 1];
                    edge_positions[offset + v - first]
                } else {
                    interiors.positions[v - interior_first]
                }
            };
            out.clear();
            out.extend(triangles.iter().map(|t| t.map(at)));
            each(&out)
        })
    }
}
