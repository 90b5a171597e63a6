//! One frame's vertices on a uniform plan. Work is split into disjoint output blocks (corners,
//! edges, interiors, triangles) so threads never share a slot.

use super::edge_groups::eval_edges;
use super::kernels::{eval_block, eval_point, BlockRun, Scratch};
use super::output::Sink;
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::refine::plan::canonical::{self, EdgeWeights};
use crate::refine::plan::layout::OutputLayout;
use crate::scheme::{NormalMode, PatchNets};
use crate::stencil::{Block, Stencil};
use rayon::prelude::*;
use smallvec::SmallVec;

/// Faces per parallel task: large enough to amortise scheduling, small enough to balance.
const FACES_PER_TASK: usize = 32;
/// Corner vertices per parallel task (each is one point evaluation).
const CORNERS_PER_TASK: usize = 1024;
/// Coarse edges per parallel task.
const EDGES_PER_TASK: usize = 64;

/// Barycentric interpolation of the face's UVs at `l` (a block's contiguous `barycentric`, not
/// the strided stencil rows).
#[inline(always)]
fn interpolate_uv(l: [f32; 3], uv: &[[f32; 2]; 3]) -> [f32; 2] {
    [
        l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0],
        l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1],
    ]
}

/// One frame's vertices: the frame's mesh and nets with the plan's tables.
pub(crate) struct Job<'a> {
    /// The frame's mesh (positions and normals of this frame; the plan's triangles).
    pub mesh: &'a Mesh,
    pub topology: &'a Topology,
    pub layout: &'a OutputLayout,
    pub stencil: &'a Stencil,
    pub nets: &'a PatchNets,
}

impl Job<'_> {
    /// Writes every vertex of the layout into `sink` (exactly `layout.vertex_count` slots).
    /// `progress` receives the number of faces done, adding up to the face count.
    pub fn vertices(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        debug_assert_eq!(sink.len() as u64, self.layout.vertex_count);
        // Enter the thread pool once a frame: called from outside it, each of the frame's
        // parallel passes (corners, edges, interiors) would hand its work to the pool and put
        // this thread to sleep until done. From inside, they run on the pool's own threads.
        rayon::scope(|_| match self.nets.basis.len() {
            10 => self.vertices_k::<10>(sink, progress),
            21 => self.vertices_k::<21>(sink, progress),
            k => unreachable!("no evaluator for a basis of {k} points"),
        })
    }

    fn vertices_k<const K: usize>(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        if self.layout.weld {
            self.welded::<K>(sink, progress);
        } else {
            self.soup::<K>(sink, progress);
        }
    }

    fn face_uvs(&self, f: usize) -> Option<[[f32; 2]; 3]> {
        self.mesh
            .uvs()
            .map(|uv| self.mesh.triangles()[f].map(|v| uv[v as usize]))
    }

    /// Runs a block of patch `f` into `sink` at `base`, see [`eval_block`].
    #[inline(always)]
    fn block<const K: usize>(
        &self,
        block: &Block,
        f: usize,
        sink: &mut Sink,
        base: usize,
        reverse: bool,
        scratch: &mut Scratch,
    ) {
        let run = BlockRun {
            block,
            points: self.nets.patch_points(f),
            normals: self.nets.patch_normals(f),
            base,
            reverse,
        };
        eval_block::<K>(&run, self.stencil, self.nets.normal_mode, sink, scratch);
    }

    fn welded<const K: usize>(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        let m = self.layout.level as usize - 1;
        let nv = self.mesh.vertex_count();
        let ne = self.topology.edges.len();
        let (corners, rest) = sink.split_at(nv);
        let (edges, interiors) = rest.split_at(ne * m);
        self.corners::<K>(0, corners);
        self.edges::<K>(0, edges);
        self.interiors::<K>(0, interiors, progress);
    }

    /// The welded layout's corner vertices `first..` (as many as `sink` holds): the input
    /// position exactly; the normal of the owning patch.
    pub fn corners<const K: usize>(&self, first: usize, sink: Sink) {
        let (mesh, topo) = (self.mesh, self.topology);
        let want_normals = sink.wants_normals();
        let want_uvs = sink.wants_uvs();
        sink.chunks(CORNERS_PER_TASK)
            .into_par_iter()
            .enumerate()
            .for_each(|(task, mut sink)| {
                for i in 0..sink.len() {
                    let v = first + task * CORNERS_PER_TASK + i;
                    sink.set_position(i, mesh.positions()[v]);
                    if want_normals {
                        let normal = match topo.vertex_owner[v] {
                            Some((f, c)) => {
                                let row = self
                                    .stencil
                                    .row(self.stencil.corner_point(c as usize) as usize);
                                eval_point::<K>(
                                    row,
                                    self.nets.patch_points(f as usize),
                                    self.nets.patch_normals(f as usize),
                                    self.nets.normal_mode,
                                )
                                .1
                            }
                            None => mesh.normals()[v],
                        };
                        sink.set_normal(i, normal);
                    }
                    if want_uvs {
                        sink.set_uv(i, mesh.uvs().expect("checked: the mesh has uvs")[v]);
                    }
                }
            });
    }

    /// The welded layout's edge points of coarse edges `first..` (as many as `sink` holds
    /// whole edges for): evaluated on the owning face, stored from the lower vertex index to
    /// the higher, several edges at a time ([`eval_edges`]).
    pub fn edges<const K: usize>(&self, first: usize, sink: Sink) {
        let (mesh, topo) = (self.mesh, self.topology);
        let m = self.layout.level as usize - 1;
        if m == 0 {
            return;
        }
        let want_uvs = sink.wants_uvs();
        sink.chunks(m * EDGES_PER_TASK)
            .into_par_iter()
            .enumerate()
            .for_each(|(task, mut sink)| {
                let mut scratch = Scratch::take();
                let edge = |le: usize| first + task * EDGES_PER_TASK + le;
                // On the stack: a `Vec` per task was 2% of a level-16 frame.
                let runs: SmallVec<[BlockRun; EDGES_PER_TASK]> = (0..sink.len() / m)
                    .map(|le| {
                        let e = edge(le);
                        let (f, k) = topo.edge_owner[e];
                        let (f, k) = (f as usize, k as usize);
                        BlockRun {
                            block: &self.stencil.blocks.edges[k],
                            points: self.nets.patch_points(f),
                            normals: self.nets.patch_normals(f),
                            base: le * m,
                            reverse: mesh.triangles()[f][k] != topo.edges[e][0],
                        }
                    })
                    .collect();
                eval_edges::<K>(
                    &runs,
                    self.stencil,
                    self.nets.normal_mode,
                    &mut sink,
                    &mut scratch,
                );
                if want_uvs {
                    for (le, run) in runs.iter().enumerate() {
                        let f = topo.edge_owner[edge(le)].0 as usize;
                        let Some(face_uv) = self.face_uvs(f) else {
                            continue;
                        };
                        let l = &run.block.barycentric;
                        for s in 0..m {
                            let i = if run.reverse { m - 1 - s } else { s };
                            sink.set_uv(le * m + s, interpolate_uv(l[i], &face_uv));
                        }
                    }
                }
            });
    }

    /// The welded layout's interior points of faces `first..` (as many as `sink` holds whole
    /// interiors for), per face in pattern order. `progress` receives the faces done.
    pub fn interiors<const K: usize>(
        &self,
        first: usize,
        sink: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let ni = Pattern::interior_count(self.layout.level) as usize;
        if ni == 0 {
            progress(self.mesh.face_count() as u64);
            return;
        }
        let want_uvs = sink.wants_uvs();
        sink.chunks(ni * FACES_PER_TASK)
            .into_par_iter()
            .enumerate()
            .for_each(|(task, mut sink)| {
                let mut scratch = Scratch::take();
                let faces = sink.len() / ni;
                for lf in 0..faces {
                    let f = first + task * FACES_PER_TASK + lf;
                    self.block::<K>(
                        &self.stencil.blocks.interior,
                        f,
                        &mut sink,
                        lf * ni,
                        false,
                        &mut scratch,
                    );
                    if let (true, Some(face_uv)) = (want_uvs, self.face_uvs(f)) {
                        for (i, &l) in self.stencil.blocks.interior.barycentric.iter().enumerate() {
                            sink.set_uv(lf * ni + i, interpolate_uv(l, &face_uv));
                        }
                    }
                }
                progress(faces as u64);
            });
    }

    /// Overwrites the edge points of face `f`'s soup block at `base` with their canonical
    /// evaluation (see [`canonical`]): `weights[s - 1]` are the weights of step `s` from
    /// the canonical start.
    fn canonical_edges(&self, f: usize, weights: &[EdgeWeights], sink: &mut Sink, base: usize) {
        let t = self.mesh.triangles()[f];
        let basis = self.nets.basis;
        let points = self.nets.patch_points(f);
        let normals = self.nets.patch_normals(f);
        let want_normals = sink.wants_normals() && self.nets.normal_mode != NormalMode::Real;
        let m = weights.len();
        for k in 0..3 {
            let fwd = canonical::forward(t, k, &self.topology.position_ids);
            let c = canonical::canonical_points(basis, points, k, fwd);
            let cn = canonical::canonical_normals(normals, k, fwd);
            for (s, &p) in self.stencil.edge_points[k].iter().enumerate() {
                // Step s + 1 from corner k is step m - s from corner k + 1.
                let w = &weights[if fwd { s } else { m - 1 - s }];
                let slot = base + p as usize;
                sink.set_position(slot, canonical::position(w, &c));
                if want_normals {
                    if let Some(normal) = canonical::net_normal(w, &cn) {
                        sink.set_normal(slot, normal);
                    }
                }
            }
        }
    }

    fn soup<const K: usize>(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        self.soup_faces::<K>(0, sink, progress);
    }

    /// The unwelded vertices of faces `first..` (as many as `sink` holds whole patterns for)
    /// into `sink`: each face's whole pattern, corners and edge points exact as in the welded
    /// layout. [`Job::soup`] is the run from face 0; a streamed soup's pieces are the others.
    pub fn soup_faces<const K: usize>(
        &self,
        first: usize,
        sink: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let mesh = self.mesh;
        let np = self.stencil.len();
        let want_uvs = sink.wants_uvs();
        // Edge points from the edge's own data, in canonical order (bitwise watertight soup).
        let n = self.layout.level as usize;
        let edge_weights: Vec<EdgeWeights> = (1..n)
            .map(|s| EdgeWeights::new((n - s) as f64 / n as f64, s as f64 / n as f64))
            .collect();
        sink.chunks(np * FACES_PER_TASK)
            .into_par_iter()
            .enumerate()
            .for_each(|(task, mut sink)| {
                let mut scratch = Scratch::take();
                let faces = sink.len() / np;
                for lf in 0..faces {
                    let f = first + task * FACES_PER_TASK + lf;
                    let base = lf * np;
                    self.block::<K>(
                        &self.stencil.blocks.all,
                        f,
                        &mut sink,
                        base,
                        false,
                        &mut scratch,
                    );
                    for (c, &v) in mesh.triangles()[f].iter().enumerate() {
                        let p = self.stencil.corner_point(c) as usize;
                        sink.set_position(base + p, mesh.positions()[v as usize]);
                    }
                    self.canonical_edges(f, &edge_weights, &mut sink, base);
                    if let (true, Some(face_uv)) = (want_uvs, self.face_uvs(f)) {
                        for (p, &l) in self.stencil.blocks.all.barycentric.iter().enumerate() {
                            sink.set_uv(base + p, interpolate_uv(l, &face_uv));
                        }
                    }
                }
                progress(faces as u64);
            });
    }
}
