//! PNG1 triangles (Fünfzig, Müller, Hansford & Farin 2008): a G1 surface from each triangle,
//! its vertex normals and its three edge neighbours.
//!
//! # Construction (section 3.2), with the steps the paper leaves open
//!
//! For every edge `a → b` of a triangle (`c` the opposite corner) two *versions* of the
//! edge's cross-boundary control row are built, one from the corner triangle at `a`, one from
//! the corner triangle at `b`:
//!
//! - *Tangent points* (Figure 5): `x` projected along `Na` into the tangent plane at `a`, the
//!   vector scaled back to `|x - a|`, a third of the way: `T_a(x) = a + |x-a| proj/|proj| / 3`.
//!   `e_a = T_a(b)`, `e_b = T_b(a)` are the edge's own control points (shared with the
//!   neighbour), `f_a = T_a(c)`, `f_b = T_b(c)` the corner triangles' third points.
//! - *The "affine transformation"* between planes is, here, the **similarity** that carries one
//!   segment onto another and one plane normal onto the other (rotation and uniform scale,
//!   orientation kept: `(t, n × t, n)` frames map to each other). Version `a` is the triangle
//!   `(a, e_a, f_a)` carried from segment `a → e_a` onto `e_a → e_b` in the middle plane (the
//!   centre candidate `b_{ab:a:111}`) and onto `e_b → b` in `b`'s tangent plane (the cross
//!   point next to `b`); version `b` carries `(e_b, b, f_b)` from `e_b → b` onto `e_a → e_b`
//!   and `a → e_a`.
//!
//!   Why this choice is G1: both triangles of an edge map their corner quads by the *same*
//!   similarities (they depend only on `a, b, Na, Nb` and the middle plane), so in each version
//!   the neighbour's cross vectors are one fixed affine combination of the edge tangent and
//!   ours. Within one patch, both versions' cross vectors have the same frame coordinates in
//!   every plane, so version `b`'s row is `κ ×` version `a`'s plus a multiple of the edge
//!   tangent: any blend of them has the same tangent plane along the edge. Hence the blended
//!   patches (equation (6)) have equal tangent planes on both sides of every smooth edge; the
//!   tests check this in f64 on random meshes.
//! - *Middle plane* (equations (3)–(5)): normal `(N_T + N_T12)` made orthogonal to
//!   `e1 = e_b - e_a`. `N_T12` is the unit normal of the neighbour `(b, a, P12)` *oriented by
//!   our edge* (so a neighbour with inconsistent winding is flipped): both sides then compute
//!   the same plane.
//! - *Boundary edges* (no neighbour) and *non-manifold* edges (more than two faces; treated as
//!   boundary): `N_T12 = N_T`, the triangle's own plane, so the patch degrades to a smooth,
//!   PN-like edge. Edges whose two sides disagree on a normal (split normals) are treated as
//!   sharp edges with `κ = 0`: G1 is impossible there.
//! - *Sharp edges* (section 3.4): the middle plane uses `N_T` alone, and the four cross and
//!   centre points of the edge move by `κ N_T`.
//!
//! # Control points (21), see [`PNG1_ORDER`]
//!
//! The blending functions make every control function a fixed rational combination of these
//! points, so for a fixed `(l1, l2, l3)` the patch is linear in them ([`weights`]) and the
//! shared stencil/evaluator machinery works unchanged.
//!
//! # Naming
//!
//! The paper writes `(u, v, w)` with `w ↔ P1`, `u ↔ P2`, `v ↔ P3`; here `(l1, l2, l3) = (w, u, v)`
//! and `b_ijk` has `i` for P1 (ERRATA.md). The paper's `D_u`, `D_v` are our `Du` (P1 → P2) and
//! `Dv` (P1 → P3).

use crate::basis::{BasisWeights, NORMAL_NET_LEN};
use glam::DVec3;
use std::ops::{Add, Div, Mul, Sub};

/// Number of PNG1 control points per patch.
pub const PNG1_LEN: usize = 21;

/// PNG1 control points in storage order:
///
/// - `0..3`: corners `b300 = P1, b030 = P2, b003 = P3`;
/// - `3..15`: the six edge-adjacent slots of [`crate::basis::CUBIC_ORDER`]
///   (`b210, b120, b021, b012, b102, b201`), each as *own* (built from the edge the slot lies
///   on, in the slot corner's tangent plane; shared with the neighbour) then *cross* (from the
///   other edge through that corner: the far corner's triangle carried into this corner's
///   plane). In the paper's names: `b_{P1:210}, b_{P3:210}, b_{P2:120}, b_{P3:120},
///   b_{P2:021}, b_{P1:021}, b_{P3:012}, b_{P1:012}, b_{P3:102}, b_{P2:102}, b_{P1:201},
///   b_{P2:201}`;
/// - `15..21`: centre candidates `b_{12:P1:111}, b_{12:P2:111}, b_{23:P2:111}, b_{23:P3:111},
///   b_{31:P3:111}, b_{31:P1:111}`.
pub const PNG1_ORDER: [&str; PNG1_LEN] = [
    "b300",
    "b030",
    "b003",
    "b210:P1",
    "b210:P3",
    "b120:P2",
    "b120:P3",
    "b021:P2",
    "b021:P1",
    "b012:P3",
    "b012:P1",
    "b102:P3",
    "b102:P2",
    "b201:P1",
    "b201:P2",
    "b111:12:P1",
    "b111:12:P2",
    "b111:23:P2",
    "b111:23:P3",
    "b111:31:P3",
    "b111:31:P1",
];

/// Own slot of edge `k` near its start corner, in `3..15` (the cross version is `+ 1`).
fn own_slot(k: usize, offset: usize) -> usize {
    3 + (4 * k + offset) % 12
}

// ---------------------------------------------------------------------------------------------
// Weights: cubic Bernstein × the paper's rational blends, with exact derivatives.

/// A number with its two partial derivatives along `u` (P1 → P2) and `v` (P1 → P3): forward-mode
/// differentiation, so the weights' `Du`, `Dv` are exact to rounding.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Dual {
    v: f64,
    du: f64,
    dv: f64,
}

impl Dual {
    const ZERO: Dual = Dual::c(0.0);
    const fn c(v: f64) -> Dual {
        Dual {
            v,
            du: 0.0,
            dv: 0.0,
        }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            du: self.du + o.du,
            dv: self.dv + o.dv,
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            du: self.du - o.du,
            dv: self.dv - o.dv,
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            du: self.du * o.v + self.v * o.du,
            dv: self.dv * o.v + self.v * o.dv,
        }
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        let q = self.v / o.v;
        Dual {
            v: q,
            du: (self.du - q * o.du) / o.v,
            dv: (self.dv - q * o.dv) / o.v,
        }
    }
}
impl Mul<Dual> for f64 {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self * o.v,
            du: self * o.du,
            dv: self * o.dv,
        }
    }
}

/// Weights of the 21 PNG1 control points at barycentric `l` (value, `Du`, `Dv`), in f64.
///
/// `S(l) = Σ B_ijk(l) b_ijk(l)` (equation (6)) with the edge slots blended by
/// `((1-x)² own + x² cross) / ((1-x)² + x²)`, `x` the barycentric coordinate of the corner
/// opposite the slot's edge (never singular), and the centre by Nielson's side-vertex blend.
/// The centre blend's denominators vanish only at the corners, where `B111 = 6 l1 l2 l3` and its
/// gradient vanish while the blend stays bounded (a convex combination): there the centre
/// weights are exactly zero, the limit. No NaN anywhere on the closed triangle.
///
/// ```
/// let w = tessella_core::scheme::png1::weights([0.2, 0.3, 0.5]);
/// assert!((w.value.iter().sum::<f64>() - 1.0).abs() < 1e-14);
/// ```
pub fn weights(l: [f64; 3]) -> BasisWeights {
    let w = weights_dual(l);
    BasisWeights {
        value: w.iter().map(|d| d.v).collect(),
        du: w.iter().map(|d| d.du).collect(),
        dv: w.iter().map(|d| d.dv).collect(),
    }
}

fn weights_dual(l: [f64; 3]) -> [Dual; PNG1_LEN] {
    // l1 = 1 - u - v, l2 = u, l3 = v; keep the given values (exact zeros stay exact).
    let l = [
        Dual {
            v: l[0],
            du: -1.0,
            dv: -1.0,
        },
        Dual {
            v: l[1],
            du: 1.0,
            dv: 0.0,
        },
        Dual {
            v: l[2],
            du: 0.0,
            dv: 1.0,
        },
    ];
    let one = Dual::c(1.0);
    let mut w = [Dual::ZERO; PNG1_LEN];
    for i in 0..3 {
        w[i] = l[i] * l[i] * l[i];
    }
    for k in 0..3 {
        let (a, b, c) = (l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
        // Blend of the two versions of the slots on edge k, by the opposite coordinate.
        let own = (one - c) * (one - c);
        let cross = c * c;
        let den = own + cross;
        let (own, cross) = (own / den, cross / den);
        let near_a = 3.0 * (a * a * b);
        let near_b = 3.0 * (a * b * b);
        let (sa, sb) = (own_slot(k, 0), own_slot(k, 2));
        w[sa] = near_a * own;
        w[sa + 1] = near_a * cross;
        w[sb] = near_b * own;
        w[sb + 1] = near_b * cross;
    }
    let sigma = l[0] * l[1] + l[1] * l[2] + l[2] * l[0];
    if sigma.v != 0.0 {
        let b111 = 6.0 * (l[0] * l[1] * l[2]);
        for k in 0..3 {
            let (a, b) = (l[k], l[(k + 1) % 3]);
            let den = a + b - 2.0 * (a * b);
            if den.v == 0.0 {
                // Only where a = b = 0, i.e. at a corner, excluded above.
                continue;
            }
            let t = b111 * (a * b) / sigma / den;
            w[15 + 2 * k] = t * ((one - b) * a);
            w[16 + 2 * k] = t * ((one - a) * b);
        }
    }
    w
}

// ---------------------------------------------------------------------------------------------
// Control net, built in f64.

/// What the net builder knows about one edge of a triangle (edge `k` runs from corner `k` to
/// corner `k + 1`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Png1Edge {
    /// The neighbour's corner opposite the edge (`P12` in the paper); `None` on boundary and
    /// non-manifold edges.
    pub opposite: Option<DVec3>,
    /// `Some(κ)`: a sharp edge (section 3.4), creased by moving its cross and centre points by
    /// `κ N_T` (`κ = 0`: sharp, not displaced).
    pub sharp: Option<f64>,
}

/// `x` projected along `n` into the tangent plane at `a`, rescaled to `|x - a|`, a third of the
/// way (section 3.2, Figure 5).
fn tangent_point(a: DVec3, n: DVec3, x: DVec3) -> DVec3 {
    let d = x - a;
    let proj = d - d.dot(n) * n;
    let len = proj.length();
    if len > 1e-300 && len.is_finite() {
        a + proj * (d.length() / len / 3.0)
    } else {
        // The edge runs along the normal: any tangent direction is as good as another.
        a + n.any_orthonormal_vector() * (d.length() / 3.0)
    }
}

/// The similarity carrying segment `s0 → s1` (in the plane with unit normal `ns`) onto
/// `d0 → d1` (in the plane with unit normal `nd`), frames `(t, n × t, n)` onto each other,
/// applied to `x`.
fn transfer(x: DVec3, s0: DVec3, s1: DVec3, ns: DVec3, d0: DVec3, d1: DVec3, nd: DVec3) -> DVec3 {
    let ts = s1 - s0;
    let td = d1 - d0;
    let (ls, ld) = (ts.length(), td.length());
    if ls == 0.0 || ld == 0.0 {
        return d0 + (x - s0);
    }
    let ms = ns.cross(ts) / ls;
    let md = nd.cross(td) / ld;
    let r = x - s0;
    let xi = r.dot(ts) / (ls * ls);
    let eta = r.dot(ms) / ls;
    d0 + xi * td + (eta * ld) * md
}

/// Unit normal of the triangle `(a, b, o)` (counter-clockwise), zero when degenerate.
fn tri_normal(a: DVec3, b: DVec3, o: DVec3) -> DVec3 {
    (b - a).cross(o - a).normalize_or_zero()
}

/// The 21 control points ([`PNG1_ORDER`]) of one triangle from its corners `p`, unit normals `n`
/// and edges, in f64. The middle plane of edge `k` uses the triangle `(p[k], p[k+1], p[k+2])`'s
/// normal and the neighbour's, both computed so that the two sides of an edge get the same plane.
pub fn control_points_f64(p: [DVec3; 3], n: [DVec3; 3], edges: [Png1Edge; 3]) -> [DVec3; 21] {
    // f32 unit normals are unit only to f32 rounding; the construction needs exact tangent planes.
    let n = n.map(|v| v.normalize_or(DVec3::Z));
    let mut net = [DVec3::ZERO; PNG1_LEN];
    net[..3].copy_from_slice(&p);
    for (k, edge) in edges.iter().enumerate() {
        let (a, b, c) = (k, (k + 1) % 3, (k + 2) % 3);
        let (pa, pb, pc) = (p[a], p[b], p[c]);
        let (na, nb) = (n[a], n[b]);
        let e_a = tangent_point(pa, na, pb);
        let e_b = tangent_point(pb, nb, pa);
        let f_a = tangent_point(pa, na, pc);
        let f_b = tangent_point(pb, nb, pc);

        // Middle plane, equations (3)-(5); sharp and boundary edges use the own plane only.
        let n_t = tri_normal(pa, pb, pc);
        let n_sum = match (edge.sharp, edge.opposite) {
            (None, Some(q)) => n_t + tri_normal(pb, pa, q),
            _ => n_t,
        };
        let e1 = e_b - e_a;
        let t = e1.normalize_or_zero();
        let mut nm = (n_sum - n_sum.dot(t) * t).normalize_or_zero();
        if nm == DVec3::ZERO {
            // Folded neighbours cancel: fall back on the corner normals, then on anything.
            let s = na + nb;
            nm = (s - s.dot(t) * t).normalize_or_zero();
            if nm == DVec3::ZERO {
                nm = t.any_orthonormal_vector();
            }
        }

        let mut centre_a = transfer(f_a, pa, e_a, na, e_a, e_b, nm);
        let mut cross_a = transfer(f_a, pa, e_a, na, e_b, pb, nb);
        let mut centre_b = transfer(f_b, e_b, pb, nb, e_a, e_b, nm);
        let mut cross_b = transfer(f_b, e_b, pb, nb, pa, e_a, na);
        if let Some(kappa) = edge.sharp {
            let shift = kappa * n_t;
            centre_a += shift;
            cross_a += shift;
            centre_b += shift;
            cross_b += shift;
        }
        net[own_slot(k, 0)] = e_a;
        net[own_slot(k, 2)] = e_b;
        // cross_a sits next to b in the slot whose own point is f_b; cross_b next to a.
        net[own_slot(k, 4) + 1] = cross_a;
        net[own_slot(k, 10) + 1] = cross_b;
        net[15 + 2 * k] = centre_a;
        net[16 + 2 * k] = centre_b;
    }
    net
}

/// Evaluates a PNG1 net in f64 at `l`: `(position, Du, Dv)`.
pub fn eval_f64(net: &[DVec3; PNG1_LEN], l: [f64; 3]) -> (DVec3, DVec3, DVec3) {
    let w = weights_dual(l);
    let (mut p, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (wk, c) in w.iter().zip(net) {
        p += wk.v * *c;
        du += wk.du * *c;
        dv += wk.dv * *c;
    }
    (p, du, dv)
}

/// The smoothed normals of section 3.3 as the crate's 6-entry quadratic normal net
/// (weights `l1², l2², l3², l1 l2, l2 l3, l3 l1`): corners `N_i`, mid-edge monomial coefficients
/// `2 n_e = 4 M_e - (Na + Nb)` with `M_e` the unit surface normal at the edge's midpoint, so the
/// net reproduces the surface normal exactly at corners and edge midpoints.
pub fn smoothed_normal_net(net: &[DVec3; PNG1_LEN], n: [DVec3; 3]) -> [DVec3; NORMAL_NET_LEN] {
    let mids = [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]];
    let mut out = [n[0], n[1], n[2], DVec3::ZERO, DVec3::ZERO, DVec3::ZERO];
    for k in 0..3 {
        let (_, du, dv) = eval_f64(net, mids[k]);
        let (a, b) = (n[k], n[(k + 1) % 3]);
        // A degenerate midpoint (Du ∥ Dv) falls back on the mean of the end normals.
        let m = du
            .cross(dv)
            .try_normalize()
            .unwrap_or_else(|| (a + b).normalize_or_zero());
        out[3 + k] = 4.0 * m - (a + b);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::Basis;

    #[test]
    fn weights_sum_to_one_and_match_finite_differences() {
        for l in [
            [0.2, 0.3, 0.5],
            [0.6, 0.3, 0.1],
            [0.01, 0.98, 0.01],
            [0.5, 0.5, 0.0],
        ] {
            let w = weights(l);
            assert!((w.value.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(w.du.iter().sum::<f64>().abs() < 1e-12);
            assert!(w.dv.iter().sum::<f64>().abs() < 1e-12);
            let h = 1e-6;
            // Central differences along u (l2 up, l1 down) and v (l3 up, l1 down).
            let fu = weights([l[0] - h, l[1] + h, l[2]]);
            let bu = weights([l[0] + h, l[1] - h, l[2]]);
            let fv = weights([l[0] - h, l[1], l[2] + h]);
            let bv = weights([l[0] + h, l[1], l[2] - h]);
            for k in 0..PNG1_LEN {
                let du = (fu.value[k] - bu.value[k]) / (2.0 * h);
                let dv = (fv.value[k] - bv.value[k]) / (2.0 * h);
                assert!(
                    (du - w.du[k]).abs() < 1e-7,
                    "{l:?} k={k}: {du} vs {}",
                    w.du[k]
                );
                assert!(
                    (dv - w.dv[k]).abs() < 1e-7,
                    "{l:?} k={k}: {dv} vs {}",
                    w.dv[k]
                );
            }
        }
    }

    #[test]
    fn collapsed_versions_give_the_cubic_bernstein_weights() {
        // When both versions of every slot coincide, PNG1 is the cubic patch.
        let map = [
            0, 1, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 9, 9, 9, 9,
        ];
        for l in [
            [1.0, 0.0, 0.0],
            [0.2, 0.3, 0.5],
            [0.0, 0.25, 0.75],
            [0.5, 0.5, 0.0],
        ] {
            let p = weights(l);
            let c = Basis::Cubic.weights(l);
            let mut sum = [[0.0; 3]; 10];
            for k in 0..PNG1_LEN {
                sum[map[k]][0] += p.value[k];
                sum[map[k]][1] += p.du[k];
                sum[map[k]][2] += p.dv[k];
            }
            for (j, s) in sum.iter().enumerate() {
                assert!((s[0] - c.value[j]).abs() < 1e-14, "{l:?} {j}");
                assert!((s[1] - c.du[j]).abs() < 1e-13, "{l:?} {j}");
                assert!((s[2] - c.dv[j]).abs() < 1e-13, "{l:?} {j}");
            }
        }
    }

    #[test]
    fn corner_limits_are_exact() {
        for c in 0..3 {
            let mut l = [0.0; 3];
            l[c] = 1.0;
            let w = weights(l);
            assert!(w
                .value
                .iter()
                .chain(&w.du)
                .chain(&w.dv)
                .all(|x| x.is_finite()));
            assert_eq!(w.value[c], 1.0);
            for k in 15..21 {
                assert_eq!((w.value[k], w.du[k], w.dv[k]), (0.0, 0.0, 0.0));
            }
        }
    }
}
