//! Crack-free PN triangles, PN-AEN (McDonald & Kilgard 2010, "Crack-free point-normal triangles
//! using adjacent edge normals"; meshoptimizer's `meshopt_generateTessellationIndexBuffer` builds
//! the same adjacency for GPUs).
//!
//! Where two triangles meet at the same positions but with different vertices (split normals at
//! hard edges, UV seams), PN builds each side's edge from its own normals and the sides part.
//! PN-AEN builds each edge control point as the mean of the two computed from either side's
//! normal at that corner, so both sides get the same edge curve: watertight. The centre follows
//! from the (averaged) edge points as in PN; shading keeps each side's own normals. With shared
//! normals the mean of two equal points is that point, bit for bit: PN exactly.
//!
//! The adjacency is fixed per topology ([`across_vertices`], [`across_table`]); the net itself
//! ([`points`]) is generic over [`Real`], so the GPU runs the code the CPU runs
//! ([`crate::shader::NetBuilder::PnAenPoints`]).

use super::{pn, Corners};
use crate::mesh::topology::across_edge_in;
use crate::mesh::{Mesh, Topology};
use crate::scalar::{Real, V3};
use glam::Vec3;

/// The ten cubic control points ([`crate::basis::CUBIC_ORDER`]) of face `f`.
pub(crate) fn control_points(mesh: &Mesh, topo: &Topology, f: usize, c: &Corners) -> [Vec3; 10] {
    let across = across_vertices(mesh.triangles(), topo, f)
        .map(|v| V3::from(Vec3::from(mesh.normals()[v as usize])));
    points(c.p.map(V3::from), c.n.map(V3::from), across).map(Vec3::from)
}

/// For each local edge `k` of face `f` (corner `k` to `k + 1`), the vertices whose normals the
/// other side uses at the edge's start and end (`[a0, b0, a1, b1, a2, b2]`): the neighbour's
/// vertices at those positions (`mesh::topology` neighbours by position), or the face's own
/// corners on boundary and non-manifold edges.
pub fn across_vertices(triangles: &[[u32; 3]], topo: &Topology, f: usize) -> [u32; 6] {
    let t = triangles[f];
    let mut out = [0; 6];
    for k in 0..3 {
        let (a, b) = match across_edge_in(triangles, topo, f, k) {
            Some(x) => (x.at_a, x.at_b),
            None => (t[k], t[(k + 1) % 3]),
        };
        out[2 * k] = a;
        out[2 * k + 1] = b;
    }
    out
}

/// [`across_vertices`] of every face, in face order: fixed per topology, so a deforming mesh
/// (or a GPU that builds the nets from its own coarse vertices) keeps it.
pub fn across_table(triangles: &[[u32; 3]], topo: &Topology) -> Vec<[u32; 6]> {
    (0..triangles.len())
        .map(|f| across_vertices(triangles, topo, f))
        .collect()
}

/// The ten cubic control points from the corners `p`, `n` and the other side's normals
/// `across` at each edge's start and end (`[a0, b0, a1, b1, a2, b2]`, as [`across_vertices`]
/// orders them). Where an edge has no other side pass the face's own corner normals: the mean
/// `(x + x) * 0.5` is `x` exactly in IEEE arithmetic (a finite edge point is at most a third of
/// the largest float, so `x + x` cannot overflow), which is PN's edge point.
pub fn points<T: Real>(p: [V3<T>; 3], n: [V3<T>; 3], across: [V3<T>; 6]) -> [V3<T>; 10] {
    let half = T::lit(0.5);
    let mut edge = [V3::zero(); 6];
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        let own_a = pn::edge_point_of(p[a], p[b], n[a]);
        let own_b = pn::edge_point_of(p[b], p[a], n[b]);
        // (x + y) / 2 is symmetric in IEEE arithmetic: both sides get the same bits.
        edge[2 * k] = (own_a + pn::edge_point_of(p[a], p[b], across[2 * k])) * half;
        edge[2 * k + 1] = (own_b + pn::edge_point_of(p[b], p[a], across[2 * k + 1])) * half;
    }
    let b111 = pn::centre_of(&p, &edge);
    [
        p[0], p[1], p[2], edge[0], edge[1], edge[2], edge[3], edge[4], edge[5], b111,
    ]
}
