//! The refined triangles' vertex indices. They depend on the topology, the layout and the
//! pattern only, never on positions, so a [`super::Plan`] writes them once for every frame.

use super::layout::OutputLayout;
use crate::mesh::Topology;
use crate::pattern::Pattern;
use crate::stencil::Stencil;
use rayon::prelude::*;

/// Coarse faces per parallel task.
const FACES_PER_TASK: usize = 32;

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
        out.par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                // Pattern point -> output vertex, rebuilt for each face.
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
                    let base = self.layout.interior_base as usize + f * ni;
                    for (i, &p) in self.stencil.interior_points.iter().enumerate() {
                        map[p as usize] = (base + i) as u32;
                    }
                    for (dst, src) in face_tris.iter_mut().zip(&self.pattern.triangles) {
                        *dst = src.map(|p| I::from_index(map[p as usize]));
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
