//! Scalar-tagged PN triangles (Boubekeur, Reuter & Schlick 2005; GMR Appendix B, equation (3)).
//!
//! Each edge control point `b_i` next to vertex `V_j` on edge `{V_j, V_k}` becomes
//!
//! ```text
//! b_i = d_i + e_i,   d_i = P_j + (1 - θ_j)/3 (P_k - P_j)
//! e_i = (1 - δ_i) Π(P_j, X_j, d_i) X_j + δ_i Π(P_j, N_j, d_i) Y_j,   Π(p, n, q) = -n.(q - p)
//! X_j = normalize((1 - |σ_j|) N_j + N'_j),   Y_j = normalize(N_j + β_j Δ_j)
//! ```
//!
//! with `δ_i` the edge's crease sharpness and `N'_j = normalize(N_j ± σ_j Δ_j)` the side normal:
//! `+` for triangles on the side `Δ_j` points into (`(centroid - P_j) . Δ_j > 0`), `-` on the
//! other. The centre is PN's. Choices the paper leaves open, written down here:
//!
//! - `N_j` of a vertex with a crease direction, and in the crease term, is the mean of the unit
//!   normals at its position (`N̄`), so split copies of a vertex agree and a creased edge is
//!   watertight; elsewhere it is the corner's own normal, so zero tags give PN exactly.
//! - `σ ∈ [-1, 1]` weighs with `|σ|`; a negative `σ` tilts the `+` side away from `Δ` (a
//!   valley).
//! - Shading uses each corner's side normal `N'_j` (the paper's "sharp normal") in the quadratic
//!   normal net.

use super::{pn, Corners};

use crate::mesh::{Mesh, Topology};
use crate::tags::Tags;
use glam::Vec3;

/// Mean unit normal per position id (indexed like [`Topology::position_ids`]): the normalised
/// sum of the normals of every vertex at the position, each vertex once; a position whose
/// vertices all have one normal keeps it bit for bit.
pub(crate) fn position_normals(mesh: &Mesh, topo: &Topology) -> Vec<Vec3> {
    let n = mesh.vertex_count();
    let mut sum = vec![Vec3::ZERO; n];
    let mut first = vec![None::<Vec3>; n];
    let mut split = vec![false; n];
    for v in 0..n {
        let p = topo.position_ids[v] as usize;
        let nv = Vec3::from(mesh.normals()[v]);
        match first[p] {
            None => first[p] = Some(nv),
            Some(f) if f != nv => split[p] = true,
            Some(_) => {}
        }
        sum[p] += nv;
    }
    (0..n)
        .map(|p| match first[p] {
            Some(f) if !split[p] => f,
            Some(f) => sum[p].try_normalize().unwrap_or(f),
            None => Vec3::Z,
        })
        .collect()
}

/// The ten cubic control points of face `f` and its shading corners (side normals).
pub(crate) fn control_points(
    mesh: &Mesh,
    topo: &Topology,
    tags: &Tags,
    mean_normals: &[Vec3],
    f: usize,
    c: &Corners,
) -> ([Vec3; 10], Corners) {
    let t = mesh.triangles()[f];
    let pid = |k: usize| topo.position_ids[t[k] as usize];
    let centroid = (c.p[0] + c.p[1] + c.p[2]) / 3.0;
    // Per corner: tag, mean normal, X (tangent-plane normal off creases), side normal.
    let corner = |j: usize| {
        let tag = tags.vertex(pid(j));
        let nbar = mean_normals[pid(j) as usize];
        let delta = Vec3::from(tag.crease);
        if tag.has_crease() && tag.sharpness != 0.0 {
            let side = if (centroid - c.p[j]).dot(delta) > 0.0 {
                1.0
            } else {
                -1.0
            };
            let n_side = (nbar + side * tag.sharpness * delta).normalize_or(nbar);
            let x = ((1.0 - tag.sharpness.abs()) * nbar + n_side).normalize_or(nbar);
            (tag, nbar, x, n_side)
        } else {
            (tag, nbar, c.n[j], c.n[j])
        }
    };
    let corners = [corner(0), corner(1), corner(2)];
    let edge_point = |j: usize, k: usize| {
        let (tag, nbar, x, _) = corners[j];
        let (pj, pk) = (c.p[j], c.p[k]);
        let delta = tags.edge(pid(j), pid(k)).sharpness;
        let d = pj + (1.0 - tag.tension) / 3.0 * (pk - pj);
        let proj = |n: Vec3| -n.dot(d - pj);
        let mut e = (1.0 - delta) * proj(x) * x;
        if delta != 0.0 {
            let y = (nbar + tag.bias * Vec3::from(tag.crease)).normalize_or(nbar);
            e += delta * proj(nbar) * y;
        }
        d + e
    };
    let edge = [
        edge_point(0, 1),
        edge_point(1, 0),
        edge_point(1, 2),
        edge_point(2, 1),
        edge_point(2, 0),
        edge_point(0, 2),
    ];
    let b111 = pn::centre(&c.p, &edge);
    let shading = Corners {
        p: c.p,
        n: [corners[0].3, corners[1].3, corners[2].3],
    };
    (
        [
            c.p[0], c.p[1], c.p[2], edge[0], edge[1], edge[2], edge[3], edge[4], edge[5], b111,
        ],
        shading,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four vertices at one position, normals A, A, B, B: every copy counts once, so the mean
    /// is along A + B (it was along A + 2B when copies of the first normal were skipped).
    #[test]
    fn position_normal_weighs_every_copy_once() {
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mut positions = p.clone();
        let mut normals = vec![[0.0, 0.0, 1.0]; 3];
        let mut triangles = vec![[0, 1, 2]];
        let a = [0.0, 0.0, 1.0];
        let b = [1.0, 0.0, 0.0];
        for (k, n) in [a, b, b].into_iter().enumerate() {
            positions.extend(p.iter().copied());
            normals.extend([n, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]);
            let base = 3 * (k as u32 + 1);
            triangles.push([base, base + 1, base + 2]);
        }
        let mesh = Mesh::new(positions, Some(normals), None, triangles).unwrap();
        let topo = mesh.topology();
        let mean = position_normals(&mesh, &topo)[0];
        let expected = (Vec3::from(a) + Vec3::from(b)).normalize();
        assert!(
            (mean - expected).length() < 1e-6,
            "{mean:?} vs {expected:?}"
        );
        // A position with one normal keeps it exactly.
        assert_eq!(position_normals(&mesh, &topo)[1], Vec3::Z);
    }
}
