//! PNG1's generic net builder (`scheme::png1::control_points_of`, which the OpenGL control
//! shader's doubles are traced from) keeps the bits of the `glam` builder it replaced: that
//! builder, kept here as it was, is the oracle.

use glam::DVec3;
use tessella_core::basis::NORMAL_NET_LEN;
use tessella_core::scheme::png1::{control_points_f64, smoothed_normal_net, Png1Edge};

/// The builder as it was written on `glam` before `control_points_of`.
mod glam_oracle {
    use glam::DVec3;
    use tessella_core::basis::NORMAL_NET_LEN;
    use tessella_core::scheme::png1::{Png1Edge, PNG1_LEN};

    /// Own slot of edge `k` near its start corner (the net's order, `PNG1_ORDER`).
    fn own_slot(k: usize, offset: usize) -> usize {
        3 + (4 * k + offset) % 12
    }

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

    struct SegmentFrame {
        s0: DVec3,
        t: DVec3,
        m: DVec3,
        len: f64,
    }

    impl SegmentFrame {
        fn new(s0: DVec3, s1: DVec3, n: DVec3) -> SegmentFrame {
            let t = s1 - s0;
            let len = t.length();
            // Unused when the segment is degenerate (`len == 0`): the transfer translates then.
            let m = if len == 0.0 {
                DVec3::ZERO
            } else {
                n.cross(t) / len
            };
            SegmentFrame { s0, t, m, len }
        }

        /// `x` in this frame: its offset from `s0` and its coordinates `(ξ, η)` along `t` and `m`,
        /// in units of the segment's length.
        fn coords(&self, x: DVec3) -> (DVec3, f64, f64) {
            let r = x - self.s0;
            if self.len == 0.0 {
                return (r, 0.0, 0.0);
            }
            (
                r,
                r.dot(self.t) / (self.len * self.len),
                r.dot(self.m) / self.len,
            )
        }

        /// The point with coordinates `coords` (from `from`) in this frame: the similarity carrying
        /// `from`'s segment onto this one, or a translation when either segment is degenerate.
        fn place(&self, from: &SegmentFrame, (r, xi, eta): (DVec3, f64, f64)) -> DVec3 {
            if from.len == 0.0 || self.len == 0.0 {
                return self.s0 + r;
            }
            self.s0 + xi * self.t + (eta * self.len) * self.m
        }
    }

    fn tri_normal(a: DVec3, b: DVec3, o: DVec3) -> DVec3 {
        (b - a).cross(o - a).normalize_or_zero()
    }

    pub fn control_points(p: [DVec3; 3], n: [DVec3; 3], edges: [Png1Edge; 3]) -> [DVec3; 21] {
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

            // Version a maps from a → e_a (a's plane), version b from e_b → b (b's plane); each
            // onto the middle segment and onto the other end's segment.
            let at_a = SegmentFrame::new(pa, e_a, na);
            let at_b = SegmentFrame::new(e_b, pb, nb);
            let middle = SegmentFrame::new(e_a, e_b, nm);
            let (in_a, in_b) = (at_a.coords(f_a), at_b.coords(f_b));
            let mut centre_a = middle.place(&at_a, in_a);
            let mut cross_a = at_b.place(&at_a, in_a);
            let mut centre_b = middle.place(&at_b, in_b);
            let mut cross_b = at_a.place(&at_b, in_b);
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

    pub fn smoothed_normals(net: &[DVec3; PNG1_LEN], n: [DVec3; 3]) -> [DVec3; NORMAL_NET_LEN] {
        let mut out = [n[0], n[1], n[2], DVec3::ZERO, DVec3::ZERO, DVec3::ZERO];
        for k in 0..3 {
            let (_, du, dv) = tessella_core::basis::png1::eval_f64_at_mid(net, k);
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
}

/// The generic builder gives the `glam` builder's bits, on random triangles and on the
/// degenerate ones its branches are for: an edge along a normal, a zero-length edge,
/// folded neighbours, sharp edges, boundaries and a normal with `z = -0.0`.
#[test]
fn generic_builder_keeps_the_glam_builders_bits() {
    let mut seed = 5u32;
    let mut r = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f64 / (1u32 << 24) as f64 * 2.0 - 1.0
    };
    let bits = |net: [DVec3; 21]| net.map(|v| v.to_array().map(f64::to_bits));
    for case in 0..3000 {
        let mut v = || DVec3::new(r(), r(), r());
        let mut p = [v(), v(), v()];
        let mut n = [v(), v(), v()];
        let q = [v(), v(), v()];
        match case % 9 {
            // The edge 0 → 1 along corner 0's normal.
            1 => n[0] = (p[1] - p[0]).normalize(),
            // A zero-length edge.
            2 => p[1] = p[0],
            // A neighbour folded onto the triangle.
            3 => {}
            // Normals with z = -0.0 and +0.0, edges along them (their tangent points
            // take any orthonormal direction, whose sign is z's).
            4 => {
                n[0] = DVec3::new(0.6, 0.8, -0.0);
                n[1] = DVec3::new(-0.8, 0.6, 0.0);
                p[1] = p[0] + n[0] * 0.7;
                p[2] = p[1] + n[1] * 0.4;
            }
            // A zero normal (falls back on +Z).
            5 => n[2] = DVec3::ZERO,
            _ => {}
        }
        let edges: [Png1Edge; 3] = std::array::from_fn(|k| Png1Edge {
            opposite: match (case + k) % 4 {
                0 => None,
                _ if case % 9 == 3 => Some(p[(k + 2) % 3]),
                _ => Some(q[k]),
            },
            sharp: match (case / 3 + k) % 5 {
                0 => Some(0.0),
                1 => Some(r() * 0.2),
                _ => None,
            },
        });
        let net = control_points_f64(p, n, edges);
        assert_eq!(
            bits(net),
            bits(glam_oracle::control_points(p, n, edges)),
            "case {case}"
        );
        let normals = |m: [DVec3; NORMAL_NET_LEN]| m.map(|v| v.to_array().map(f64::to_bits));
        assert_eq!(
            normals(smoothed_normal_net(&net, n)),
            normals(glam_oracle::smoothed_normals(&net, n)),
            "case {case}"
        );
    }
}
