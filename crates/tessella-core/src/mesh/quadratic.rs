//! Second-order (6-node, isoparametric P2) triangles: the corners of a face plus one node on
//! each edge, as finite-element meshes give them (gmsh `triangle6`, VTK/meshio `triangle6`,
//! the boundary faces of `tetra10`). Node order: the corners, then the mid-edge nodes of edges
//! 0-1, 1-2, 2-0.
//!
//! Mid-edge nodes are vertices of the mesh (they index its positions) but corners of no
//! triangle: refinement never moves them, welded output keeps them as unused vertices (no
//! refined triangle references them; they lie on the refined surface, at the edge's `l = 1/2`
//! point) and the Python package drops them from its results. The element's own mapping is
//!
//! ```text
//! X(l) = Σ_i l_i (2 l_i − 1) P_i + Σ_{i<j} 4 l_i l_j M_ij
//! ```
//!
//! which [`Scheme::Quadratic`](crate::Scheme::Quadratic) writes as a quadratic Bézier patch
//! (middle control points `Q_ij = 2 M_ij − (P_i + P_j)/2`) degree-elevated to the cubic net.

use super::Mesh;
use crate::error::MeshError;
use crate::scalar::Real;
use glam::DVec3;
use std::collections::HashMap;

/// The mid-edge entry of a linear face in [`Mesh::mid_nodes`].
pub const NO_MID: u32 = u32::MAX;

/// Barycentric points where the Jacobian of a second-order face is checked: its six nodes and
/// its centroid.
const JACOBIAN_POINTS: [[f64; 3]; 7] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.5],
    [0.5, 0.0, 0.5],
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
];

/// Relative distance (to the edge's length) a mid-edge node of a second-order face may lie from
/// the midpoint of an edge it shares with a linear face.
pub const STRAIGHT_EDGE_TOLERANCE: f64 = 1e-5;

impl Mesh {
    /// Makes some or all faces second order: `mids[f]` are the mid-edge nodes of face `f`'s
    /// edges 0-1, 1-2, 2-0 (indices into the positions), or `[NO_MID; 3]` for a linear face.
    ///
    /// Checked: one entry per face; indices in range, none a corner of its own face, all three
    /// given or none; an edge's faces agree on its mid node (the same index or the same
    /// position; a linear face's edge is straight, so a second-order neighbour's node must lie
    /// at its midpoint); no element is inverted or folded (the surface Jacobian `Du × Dv` points
    /// to the side of the corner triangle's normal at the six nodes and the centroid).
    pub fn with_mid_nodes(mut self, mids: Vec<[u32; 3]>) -> Result<Mesh, MeshError> {
        if mids.len() != self.triangles.len() {
            return Err(MeshError::MidNodeCount {
                got: mids.len(),
                expected: self.triangles.len(),
            });
        }
        let count = self.positions.len();
        for (face, m) in mids.iter().enumerate() {
            let given = m.iter().filter(|&&x| x != NO_MID).count();
            if given != 0 && given != 3 {
                return Err(MeshError::BadMidNode {
                    face,
                    reason: format!(
                        "it has {given} of 3 mid-edge nodes ({m:?}); give all three or none"
                    ),
                });
            }
            if given == 0 {
                continue;
            }
            for &index in m {
                if index as usize >= count {
                    return Err(MeshError::BadMidNode {
                        face,
                        reason: format!(
                            "its mid-edge node {index} is out of range (the mesh has {count} vertices)"
                        ),
                    });
                }
                if self.triangles[face].contains(&index) {
                    return Err(MeshError::BadMidNode {
                        face,
                        reason: format!("its mid-edge node {index} is also one of its corners"),
                    });
                }
            }
        }
        check_shared_edges(&self.positions, &self.triangles, &mids)?;
        check_inverted(&self.positions, &self.triangles, &mids)?;
        self.mid_nodes = Some(mids);
        Ok(self)
    }

    /// Per face, its mid-edge nodes ([`NO_MID`] for linear faces); `None` when every face is
    /// linear.
    pub fn mid_nodes(&self) -> Option<&[[u32; 3]]> {
        self.mid_nodes.as_deref()
    }

    /// The mid-edge nodes of face `f` (edges 0-1, 1-2, 2-0) when it is second order.
    pub fn face_mid_nodes(&self, f: usize) -> Option<[u32; 3]> {
        self.mid_nodes
            .as_ref()
            .map(|m| m[f])
            .filter(|m| m[0] != NO_MID)
    }

    /// True when at least one face is second order.
    pub fn is_quadratic(&self) -> bool {
        self.mid_nodes
            .as_ref()
            .is_some_and(|m| m.iter().any(|x| x[0] != NO_MID))
    }
}

fn point(positions: &[[f32; 3]], i: u32) -> DVec3 {
    DVec3::from(positions[i as usize].map(f64::from))
}

/// The 6-node shape functions at `l`: corners `l_i (2 l_i − 1)`, then mid nodes `4 l_i l_j` of
/// edges 0-1, 1-2, 2-0. Generic over [`Real`], so the shaders that colour a P2 field get this
/// very formula ([`crate::shader::p2_weights_wgsl`]).
pub fn shape_functions<T: Real>(l: [T; 3]) -> [T; 6] {
    let (one, two, four) = (T::lit(1.0), T::lit(2.0), T::lit(4.0));
    [
        l[0] * (two * l[0] - one),
        l[1] * (two * l[1] - one),
        l[2] * (two * l[2] - one),
        four * l[0] * l[1],
        four * l[1] * l[2],
        four * l[2] * l[0],
    ]
}

/// `Du` (towards corner 2) and `Dv` (towards corner 3) of the 6-node map at `l`.
pub fn derivatives(nodes: &[DVec3; 6], l: [f64; 3]) -> (DVec3, DVec3) {
    let [p1, p2, p3, m12, m23, m31] = *nodes;
    let g1 = (4.0 * l[0] - 1.0) * p1 + 4.0 * l[1] * m12 + 4.0 * l[2] * m31;
    let g2 = (4.0 * l[1] - 1.0) * p2 + 4.0 * l[0] * m12 + 4.0 * l[2] * m23;
    let g3 = (4.0 * l[2] - 1.0) * p3 + 4.0 * l[1] * m23 + 4.0 * l[0] * m31;
    (g2 - g1, g3 - g1)
}

/// Refuses second-order faces whose Jacobian does not point to the side of their corner
/// triangle's normal at one of [`JACOBIAN_POINTS`].
pub(crate) fn check_inverted(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    mids: &[[u32; 3]],
) -> Result<(), MeshError> {
    for (face, (t, m)) in triangles.iter().zip(mids).enumerate() {
        if m[0] == NO_MID {
            continue;
        }
        let nodes = [t[0], t[1], t[2], m[0], m[1], m[2]].map(|i| point(positions, i));
        let flat = (nodes[1] - nodes[0]).cross(nodes[2] - nodes[0]);
        for l in JACOBIAN_POINTS {
            let (du, dv) = derivatives(&nodes, l);
            let j = du.cross(dv).dot(flat);
            if j.is_nan() || j <= 0.0 {
                return Err(MeshError::InvertedElement {
                    face,
                    at: l.map(|x| x as f32),
                });
            }
        }
    }
    Ok(())
}

/// Refuses edges whose faces disagree on the mid-edge node (see [`Mesh::with_mid_nodes`]).
/// Edges are keyed by corner position, so split vertices (hard edges) still meet.
fn check_shared_edges(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    mids: &[[u32; 3]],
) -> Result<(), MeshError> {
    let pid = super::topology::position_ids(positions);
    // edge (lower position id, higher) → (first face, its mid node or NO_MID, corner a, corner b)
    let mut seen: HashMap<(u32, u32), (usize, u32, u32, u32)> = HashMap::new();
    for (face, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (pa, pb) = (pid[a as usize], pid[b as usize]);
            let key = (pa.min(pb), pa.max(pb));
            let mid = mids[face][k];
            let Some(&(other, other_mid, oa, ob)) = seen.get(&key) else {
                seen.insert(key, (face, mid, a, b));
                continue;
            };
            let mismatch = match (mid == NO_MID, other_mid == NO_MID) {
                (true, true) => None,
                (false, false) => (pid[mid as usize] != pid[other_mid as usize]).then(|| {
                    format!(
                        "face {other} gives it mid-edge node {other_mid} at {:?}, face {face} gives node {mid} at {:?}",
                        positions[other_mid as usize], positions[mid as usize]
                    )
                }),
                (lin, _) => {
                    let (q, m, qa, qb) = if lin {
                        (other, other_mid, oa, ob)
                    } else {
                        (face, mid, a, b)
                    };
                    let (pa, pb) = (point(positions, qa), point(positions, qb));
                    let off = (point(positions, m) - 0.5 * (pa + pb)).length();
                    let linear = if lin { face } else { other };
                    (off > STRAIGHT_EDGE_TOLERANCE * (pb - pa).length()).then(|| {
                        format!(
                            "face {linear} is linear (a straight edge) but face {q}'s mid-edge node {m} lies {off:.3e} off the edge's midpoint; give face {linear} that mid-edge node too"
                        )
                    })
                }
            };
            if let Some(detail) = mismatch {
                return Err(MeshError::MidNodeMismatch {
                    faces: [other, face],
                    edge: [oa, ob],
                    detail,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_nodal() {
        for l in JACOBIAN_POINTS {
            let s: f64 = shape_functions(l).iter().sum();
            assert!((s - 1.0).abs() < 1e-15);
        }
        for (node, l) in JACOBIAN_POINTS[..6].iter().enumerate() {
            let n = shape_functions(*l);
            for (k, &x) in n.iter().enumerate() {
                assert_eq!(x, if k == node { 1.0 } else { 0.0 });
            }
        }
    }
}
