//! The refined triangles' vertex indices. They depend on the topology, the layout and the
//! pattern only, never on positions, so a [`super::Plan`] writes them once for every frame.

use super::layout::OutputLayout;
use crate::mesh::Topology;
use crate::pattern::Pattern;
use crate::stencil::Stencil;
use rayon::prelude::*;

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
