//! One frame's vertices on an adaptive tiling (`refine::plan::tiling`): each face's own
//! pattern and stencil, edge points evaluated canonically so shared points keep their bits.

#![allow(clippy::needless_range_loop)] // corners, edges and axes index several tables

use super::kernels::eval_point;
use super::output::Sink;
use crate::mesh::{Mesh, Topology};
use crate::refine::plan::canonical;
use crate::refine::plan::pieces::Piece;
use crate::refine::plan::tiling::{Tile, Tiling};
use crate::scheme::{NormalMode, PatchNets};
use rayon::prelude::*;
use std::ops::Range;

/// One frame's vertices on an adaptive tiling.
pub(crate) struct AdaptiveJob<'a> {
    pub mesh: &'a Mesh,
    pub topology: &'a Topology,
    pub tiling: &'a Tiling,
    pub nets: &'a PatchNets,
    pub weld: bool,
}

/// Splits `sink` into consecutive runs of the given lengths.
fn runs<'a>(mut sink: Sink<'a>, lens: impl Iterator<Item = usize>) -> Vec<Sink<'a>> {
    let mut out = Vec::new();
    for len in lens {
        let (head, tail) = sink.split_at(len);
        out.push(head);
        sink = tail;
    }
    out
}

impl AdaptiveJob<'_> {
    pub fn vertices(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        match self.nets.basis.len() {
            10 => self.vertices_k::<10>(sink, progress),
            21 => self.vertices_k::<21>(sink, progress),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
    }

    fn point<const K: usize>(&self, tile: &Tile, f: usize, p: u32) -> ([f32; 3], [f32; 3]) {
        eval_point::<K>(
            tile.stencil.row(p as usize),
            self.nets.patch_points(f),
            self.nets.patch_normals(f),
            self.nets.normal_mode,
        )
    }

    fn uv(&self, tile: &Tile, f: usize, p: u32) -> Option<[f32; 2]> {
        let uv = self.mesh.uvs()?;
        let t = self.mesh.triangles()[f];
        let l = tile.pattern.points[p as usize].map(|x| x as f32);
        let c = t.map(|v| uv[v as usize]);
        Some([
            l[0] * c[0][0] + l[1] * c[1][0] + l[2] * c[2][0],
            l[0] * c[0][1] + l[1] * c[1][1] + l[2] * c[2][1],
        ])
    }

    /// Writes pattern point `p` (step `step` from corner `k` of edge `k`) of face `f`
    /// canonically into `slot`.
    #[allow(clippy::too_many_arguments)]
    fn edge_point<const K: usize>(
        &self,
        tile: &Tile,
        f: usize,
        k: usize,
        fwd: bool,
        (step, p): (usize, u32),
        sink: &mut Sink,
        slot: usize,
    ) {
        let w = tile.edge_weights(k, step as u32, fwd);
        let points = self.nets.patch_points(f);
        let c = canonical::canonical_points(self.nets.basis, points, k, fwd);
        sink.set_position(slot, canonical::position(&w, &c));
        if sink.wants_normals() {
            let net = (self.nets.normal_mode != NormalMode::Real)
                .then(|| {
                    let cn = canonical::canonical_normals(self.nets.patch_normals(f), k, fwd);
                    canonical::net_normal(&w, &cn)
                })
                .flatten();
            sink.set_normal(slot, net.unwrap_or_else(|| self.point::<K>(tile, f, p).1));
        }
        if sink.wants_uvs() {
            if let Some(uv) = self.uv(tile, f, p) {
                sink.set_uv(slot, uv);
            }
        }
    }

    fn full_point<const K: usize>(
        &self,
        tile: &Tile,
        f: usize,
        p: u32,
        sink: &mut Sink,
        slot: usize,
    ) {
        let (pos, n) = self.point::<K>(tile, f, p);
        sink.set_position(slot, pos);
        if sink.wants_normals() {
            sink.set_normal(slot, n);
        }
        if sink.wants_uvs() {
            if let Some(uv) = self.uv(tile, f, p) {
                sink.set_uv(slot, uv);
            }
        }
    }

    fn vertices_k<const K: usize>(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        let (nv, ne, nf) = (
            self.mesh.vertex_count(),
            self.topology.edges.len(),
            self.mesh.face_count(),
        );
        if !self.weld {
            return self.faces_k::<K>(0..nf, sink, progress);
        }
        let (corners, rest) = sink.split_at(nv);
        let edge_total = (self.tiling.face_offset[0] - nv as u64) as usize;
        let (edges, interiors) = rest.split_at(edge_total);
        self.corners_k::<K>(0..nv, corners);
        self.edges_k::<K>(0..ne, edges);
        self.interiors_k::<K>(0..nf, interiors, progress);
    }

    /// The vertices of one piece of the layout (`sink` holds just that piece's slots).
    pub fn piece(&self, piece: &Piece, sink: Sink) {
        match self.nets.basis.len() {
            10 => self.piece_k::<10>(piece, sink),
            21 => self.piece_k::<21>(piece, sink),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
    }

    fn piece_k<const K: usize>(&self, piece: &Piece, sink: Sink) {
        match piece.clone() {
            Piece::Corners(r) => self.corners_k::<K>(r, sink),
            Piece::Edges(r) => self.edges_k::<K>(r, sink),
            Piece::Interiors(r) => self.interiors_k::<K>(r, sink, &|_| {}),
            Piece::Faces(r) => self.faces_k::<K>(r, sink, &|_| {}),
        }
    }

    /// Soup: the whole patterns of faces `r`, one after the other.
    fn faces_k<const K: usize>(
        &self,
        r: Range<usize>,
        sink: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let (tiling, mesh, pid) = (self.tiling, self.mesh, &self.topology.position_ids);
        let lens = r.clone().map(|f| tiling.tile(f).pattern.points.len());
        runs(sink, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let f = r.start + i;
                let tile = tiling.tile(f);
                let t = mesh.triangles()[f];
                for p in 0..tile.pattern.points.len() as u32 {
                    self.full_point::<K>(tile, f, p, &mut sink, p as usize);
                }
                for c in 0..3 {
                    sink.set_position(tile.corners[c] as usize, mesh.positions()[t[c] as usize]);
                }
                for k in 0..3 {
                    let fwd = canonical::forward(t, k, pid);
                    for (s, &p) in tile.edges[k].iter().enumerate() {
                        let at = (s + 1, p);
                        self.edge_point::<K>(tile, f, k, fwd, at, &mut sink, p as usize);
                    }
                }
                progress(1);
            });
    }

    /// Welded: coarse vertices `r`, evaluated on their owner faces.
    fn corners_k<const K: usize>(&self, r: Range<usize>, mut corners: Sink) {
        let (tiling, mesh, topo) = (self.tiling, self.mesh, self.topology);
        for (i, v) in r.enumerate() {
            match topo.vertex_owner[v] {
                Some((f, c)) => {
                    let tile = tiling.tile(f as usize);
                    let p = tile.corners[c as usize];
                    self.full_point::<K>(tile, f as usize, p, &mut corners, i);
                }
                None => {
                    if corners.wants_normals() {
                        corners.set_normal(i, mesh.normals()[v]);
                    }
                    if let (true, Some(uv)) = (corners.wants_uvs(), mesh.uvs()) {
                        corners.set_uv(i, uv[v]);
                    }
                }
            }
            corners.set_position(i, mesh.positions()[v]);
        }
    }

    /// Welded: the inner points of unique edges `r`, from their lower vertex index.
    fn edges_k<const K: usize>(&self, r: Range<usize>, edges: Sink) {
        let (tiling, mesh, topo) = (self.tiling, self.mesh, self.topology);
        let lens = r
            .clone()
            .map(|e| tiling.edge_segments[e].max(1) as usize - 1);
        runs(edges, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let e = r.start + i;
                let (f, k) = topo.edge_owner[e];
                let (f, k) = (f as usize, k as usize);
                let tile = tiling.tile(f);
                let t = mesh.triangles()[f];
                let fwd = canonical::forward(t, k, &topo.position_ids);
                let by_index = t[k] == topo.edges[e][0];
                let m = tile.edges[k].len();
                for (s, &p) in tile.edges[k].iter().enumerate() {
                    let slot = if by_index { s } else { m - 1 - s };
                    self.edge_point::<K>(tile, f, k, fwd, (s + 1, p), &mut sink, slot);
                }
            });
    }

    /// Welded: the interior points of faces `r`.
    fn interiors_k<const K: usize>(
        &self,
        r: Range<usize>,
        interiors: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let tiling = self.tiling;
        let lens = r.clone().map(|f| tiling.tile(f).interior.len());
        runs(interiors, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let f = r.start + i;
                let tile = tiling.tile(f);
                for (i, &p) in tile.interior.iter().enumerate() {
                    self.full_point::<K>(tile, f, p, &mut sink, i);
                }
                progress(1);
            });
    }
}
