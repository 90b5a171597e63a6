//! The refined triangles' vertex indices. They depend on the topology, the layout and the
//! pattern only, never on positions, so a [`Plan`](super::table::Plan) writes them once for every frame.

#![allow(clippy::needless_range_loop)] // corners and edges index several tables

use super::layout::{OutputLayout, NO_FACE};
use super::pieces::Piece;
use super::tiling::Tiling;
use crate::mesh::Topology;
use crate::pattern::Pattern;
use crate::stencil::Stencil;
use rayon::prelude::*;
use std::ops::Range;

/// Coarse faces per parallel task.
const FACES_PER_TASK: usize = 32;

/// A pattern point that is not inside the face (a corner or an edge point).
const NOT_INTERIOR: u32 = u32::MAX;

/// An index type of the output: `u32`, or `u16` when every vertex index fits.
pub trait IndexInt: Copy + Default + Send + Sync + 'static {
    /// The largest vertex count this type can address.
    const MAX_VERTICES: u64;
    /// Converts an index known to be in range.
    fn from_index(i: u32) -> Self;
}

impl IndexInt for u32 {
    const MAX_VERTICES: u64 = u32::MAX as u64 + 1;
    #[inline(always)]
    fn from_index(i: u32) -> u32 {
        i
    }
}

impl IndexInt for u16 {
    const MAX_VERTICES: u64 = u16::MAX as u64 + 1;
    #[inline(always)]
    fn from_index(i: u32) -> u16 {
        i as u16
    }
}

/// The tables the index pass reads.
pub(crate) struct IndexJob<'a> {
    pub triangles: &'a [[u32; 3]],
    pub topology: &'a Topology,
    pub layout: &'a OutputLayout,
    pub pattern: &'a Pattern,
    pub stencil: &'a Stencil,
}

impl IndexJob<'_> {
    /// Writes all `layout.triangle_count` triangles into `out` (exactly that long; the caller
    /// checked that every index fits `I`). `progress` receives faces done.
    pub fn write<I: IndexInt>(&self, out: &mut [[I; 3]], progress: &(dyn Fn(u64) + Sync)) {
        debug_assert_eq!(out.len() as u64, self.layout.triangle_count);
        debug_assert!(self.layout.vertex_count <= I::MAX_VERTICES);
        if self.layout.weld {
            self.welded(out, progress)
        } else {
            self.soup(out, progress)
        }
    }

    fn welded<I: IndexInt>(&self, out: &mut [[I; 3]], progress: &(dyn Fn(u64) + Sync)) {
        let topo = self.topology;
        let n = self.layout.level as usize;
        let m = n - 1;
        let ni = Pattern::interior_count(self.layout.level) as usize;
        let per_face = n * n;
        let points = self.pattern.points.len();
        // Most triangles (nine in ten at level 32) have interior points only, whose vertices
        // are the face's interior base plus a fixed offset: those are one add per index, which
        // vectorises. The others (touching a corner or an edge) look their points up in a map
        // of the face's corner and edge vertices.
        let mut interior_of = vec![NOT_INTERIOR; points];
        for (i, &p) in self.stencil.interior_points.iter().enumerate() {
            interior_of[p as usize] = i as u32;
        }
        let template: Vec<[u32; 3]> = (self.pattern.triangles.iter())
            .map(|t| {
                [
                    interior_of[t[0] as usize],
                    interior_of[t[1] as usize],
                    interior_of[t[2] as usize],
                ]
            })
            .collect();
        let boundary: Vec<usize> = (0..template.len())
            .filter(|&t| template[t].contains(&NOT_INTERIOR))
            .collect();
        out.par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                // Pattern point -> output vertex of the face's corners and edges.
                let mut map = vec![0u32; points];
                for (lf, face_tris) in tris.chunks_mut(per_face).enumerate() {
                    let f = task * FACES_PER_TASK + lf;
                    let t = self.triangles[f];
                    for (c, &v) in t.iter().enumerate() {
                        map[self.stencil.corner_point(c) as usize] = v;
                    }
                    #[allow(clippy::needless_range_loop)] // k indexes four tables
                    for k in 0..3 {
                        let e = topo.face_edges[f][k] as usize;
                        let forward = t[k] == topo.edges[e][0];
                        let base = self.layout.edge_base as usize + e * m;
                        for (s, &p) in self.stencil.edge_points[k].iter().enumerate() {
                            map[p as usize] = (base + if forward { s } else { m - 1 - s }) as u32;
                        }
                    }
                    let base = (self.layout.interior_base as usize + f * ni) as u32;
                    // Every triangle as if interior (the others' values are overwritten next).
                    for (dst, tm) in face_tris.iter_mut().zip(&template) {
                        *dst = [
                            I::from_index(base.wrapping_add(tm[0])),
                            I::from_index(base.wrapping_add(tm[1])),
                            I::from_index(base.wrapping_add(tm[2])),
                        ];
                    }
                    for &b in &boundary {
                        let (src, tm) = (self.pattern.triangles[b], template[b]);
                        let vertex = |j: usize| {
                            if tm[j] == NOT_INTERIOR {
                                map[src[j] as usize]
                            } else {
                                base + tm[j]
                            }
                        };
                        face_tris[b] = [
                            I::from_index(vertex(0)),
                            I::from_index(vertex(1)),
                            I::from_index(vertex(2)),
                        ];
                    }
                }
                progress((tris.len() / per_face) as u64);
            });
    }

    fn soup<I: IndexInt>(&self, out: &mut [[I; 3]], progress: &(dyn Fn(u64) + Sync)) {
        let np = self.pattern.points.len();
        let per_face = self.pattern.triangles.len();
        out.par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                for (lf, face_tris) in tris.chunks_mut(per_face).enumerate() {
                    let base = ((task * FACES_PER_TASK + lf) * np) as u32;
                    for (dst, src) in face_tris.iter_mut().zip(&self.pattern.triangles) {
                        *dst = src.map(|p| I::from_index(base + p));
                    }
                }
                progress((tris.len() / per_face) as u64);
            });
    }
}

/// The triangles of an adaptive tiling (they depend on the plan only).
pub(crate) struct AdaptiveIndex<'a> {
    pub triangles: &'a [[u32; 3]],
    pub topology: &'a Topology,
    pub tiling: &'a Tiling,
    pub weld: bool,
}

impl AdaptiveIndex<'_> {
    /// Output slot of each pattern point of face `f`.
    pub fn slots(&self, f: usize, out: &mut Vec<u32>) {
        let tile = self.tiling.tile(f);
        out.clear();
        out.resize(tile.pattern.points.len(), 0);
        let base = self.tiling.face_offset[f] as u32;
        if !self.weld {
            for (p, o) in out.iter_mut().enumerate() {
                *o = base + p as u32;
            }
            return;
        }
        let t = self.triangles[f];
        for c in 0..3 {
            out[tile.corners[c] as usize] = t[c];
        }
        for k in 0..3 {
            let e = self.topology.face_edges[f][k] as usize;
            let by_index = t[k] == self.topology.edges[e][0];
            let m = tile.edges[k].len();
            let eb = self.tiling.edge_offset[e] as u32;
            for (s, &p) in tile.edges[k].iter().enumerate() {
                out[p as usize] = eb + if by_index { s } else { m - 1 - s } as u32;
            }
        }
        for (i, &p) in tile.interior.iter().enumerate() {
            out[p as usize] = base + i as u32;
        }
    }

    /// Writes every refined triangle.
    pub fn indices<I: IndexInt>(&self, out: &mut [[I; 3]], progress: &(dyn Fn(u64) + Sync)) {
        self.face_indices(0..self.triangles.len(), out, progress);
    }

    /// Writes the refined triangles of faces `faces` (from `triangle_offset[faces.start]` to
    /// `triangle_offset[faces.end]`) into `out`, exactly that long.
    pub fn face_indices<I: IndexInt>(
        &self,
        faces: Range<usize>,
        out: &mut [[I; 3]],
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let tiling = self.tiling;
        let mut chunks = Vec::with_capacity(faces.len());
        let mut rest = out;
        for f in faces.clone() {
            let n = tiling.tile(f).pattern.triangles.len();
            let (head, tail) = rest.split_at_mut(n);
            chunks.push(head);
            rest = tail;
        }
        chunks
            .into_par_iter()
            .enumerate()
            .for_each_init(Vec::new, |map, (i, tris)| {
                let f = faces.start + i;
                self.slots(f, map);
                for (dst, src) in tris.iter_mut().zip(&tiling.tile(f).pattern.triangles) {
                    *dst = src.map(|p| I::from_index(map[p as usize]));
                }
                progress(1);
            });
    }

    /// Each output vertex of `piece`'s face and barycentrics (see `Plan::origin`): a shared
    /// (welded) vertex is named by the face that owns (evaluates) it, as in the uniform layout.
    pub fn piece_origin(&self, piece: &Piece, faces: &mut [u32], bary: &mut [[f32; 3]]) {
        let (topo, tiling) = (self.topology, self.tiling);
        let l = |f: usize, p: u32| tiling.tile(f).pattern.points[p as usize].map(|x| x as f32);
        let mut slots = faces.iter_mut().zip(bary.iter_mut());
        let mut put = |face: u32, b: [f32; 3]| {
            let (f, slot) = slots.next().expect("a slot for each vertex of the piece");
            (*f, *slot) = (face, b);
        };
        match piece.clone() {
            Piece::Corners(r) => {
                for v in r {
                    match topo.vertex_owner[v] {
                        Some((f, c)) => put(
                            f,
                            l(f as usize, tiling.tile(f as usize).corners[c as usize]),
                        ),
                        None => put(NO_FACE, [1.0, 0.0, 0.0]),
                    }
                }
            }
            Piece::Edges(r) => {
                for e in r {
                    let (f, k) = topo.edge_owner[e];
                    let (fu, k) = (f as usize, k as usize);
                    let points = &tiling.tile(fu).edges[k];
                    let by_index = self.triangles[fu][k] == topo.edges[e][0];
                    let m = points.len();
                    for j in 0..m {
                        let s = if by_index { j } else { m - 1 - j };
                        put(f, l(fu, points[s]));
                    }
                }
            }
            Piece::Interiors(r) => {
                for f in r {
                    for &p in &tiling.tile(f).interior {
                        put(f as u32, l(f, p));
                    }
                }
            }
            Piece::Faces(r) => {
                for f in r {
                    for p in 0..tiling.tile(f).pattern.points.len() as u32 {
                        put(f as u32, l(f, p));
                    }
                }
            }
        }
    }
}
