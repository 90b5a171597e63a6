//! Where each refined vertex goes.
//!
//! Welded output is laid out in three blocks, so each shared vertex has exactly one slot and
//! is computed once:
//!
//! 1. `V` corner vertices, one per input vertex, in input order (the coarse mesh, exactly);
//! 2. `E × (N-1)` edge vertices, per unique edge `[a, b]` (`a < b`), ordered from `a` to `b`;
//! 3. `F × (N-1)(N-2)/2` interior vertices, per face, in pattern order.
//!
//! Soup output gives every face its own `(N+1)(N+2)/2` vertices in pattern order. Triangles are
//! face by face, in pattern order, in both layouts.

use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;

/// Bytes of one output triangle's three `u32` indices.
pub const BYTES_PER_INDEXED_TRIANGLE: u64 = 12;

/// Sizes and block offsets of a refined mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputLayout {
    pub level: u32,
    pub weld: bool,
    pub vertex_count: u64,
    pub triangle_count: u64,
    /// First edge vertex (welded).
    pub edge_base: u64,
    /// First interior vertex (welded).
    pub interior_base: u64,
}

impl OutputLayout {
    /// Sizes for `mesh` at `level` (sizes saturate rather than overflow); `topology` is
    /// required when `weld` is set.
    pub fn new(
        mesh: &Mesh,
        topology: Option<&Topology>,
        level: u32,
        weld: bool,
    ) -> Result<OutputLayout, RefineError> {
        if level == 0 {
            return Err(RefineError::LevelZero);
        }
        let n = level as u64;
        let faces = mesh.face_count() as u64;
        let triangle_count = faces.saturating_mul(n * n);
        let (vertex_count, edge_base, interior_base) = if weld {
            let edges = topology
                .expect("welded layout needs the topology")
                .edges
                .len() as u64;
            let v = mesh.vertex_count() as u64;
            let edge_base = v;
            let interior_base = edge_base.saturating_add(edges.saturating_mul(n - 1));
            let total =
                interior_base.saturating_add(faces.saturating_mul(Pattern::interior_count(level)));
            (total, edge_base, interior_base)
        } else {
            (faces.saturating_mul(Pattern::point_count(level)), 0, 0)
        };
        Ok(OutputLayout {
            level,
            weld,
            vertex_count,
            triangle_count,
            edge_base,
            interior_base,
        })
    }

    /// Bytes of positions, normals, optional UVs and indices.
    pub fn output_bytes(&self, uvs: bool) -> u64 {
        let per_vertex = 24 + if uvs { 8 } else { 0 };
        self.vertex_count.saturating_mul(per_vertex).saturating_add(
            self.triangle_count
                .saturating_mul(BYTES_PER_INDEXED_TRIANGLE),
        )
    }
}

/// The origin face of a coarse vertex no triangle uses ([`Plan::origin`](crate::refine::Plan::origin)).
pub const NO_FACE: u32 = u32::MAX;
