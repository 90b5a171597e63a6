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

use super::{pn, Corners};
use crate::mesh::topology::across_edge;
use crate::mesh::{Mesh, Topology};
use glam::Vec3;

/// The ten cubic control points ([`crate::basis::CUBIC_ORDER`]) of face `f`.
pub(crate) fn control_points(mesh: &Mesh, topo: &Topology, f: usize, c: &Corners) -> [Vec3; 10] {
    let Corners { p, n } = c;
    let mut edge = [Vec3::ZERO; 6];
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        let mut near_a = pn::edge_point(p[a], p[b], n[a]);
        let mut near_b = pn::edge_point(p[b], p[a], n[b]);
        if let Some(x) = across_edge(mesh, topo, f, k) {
            let other = |v: u32| Vec3::from(mesh.normals()[v as usize]);
            // (x + y) / 2 is symmetric in IEEE arithmetic: both sides get the same bits.
            near_a = (near_a + pn::edge_point(p[a], p[b], other(x.at_a))) * 0.5;
            near_b = (near_b + pn::edge_point(p[b], p[a], other(x.at_b))) * 0.5;
        }
        edge[2 * k] = near_a;
        edge[2 * k + 1] = near_b;
    }
    let b111 = pn::centre(p, &edge);
    [
        p[0], p[1], p[2], edge[0], edge[1], edge[2], edge[3], edge[4], edge[5], b111,
    ]
}
