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
//! and `b_ijk` has `i` for P1 (docs/formulas.md, Conventions). The paper's `D_u`, `D_v` are our `Du` (P1 → P2) and
//! `Dv` (P1 → P3).

pub use crate::basis::png1::{eval_f64, weights, PNG1_LEN, PNG1_ORDER};

use crate::basis::png1::own_slot;
use crate::basis::NORMAL_NET_LEN;
use crate::scalar::{Noise, Real, V3};
use glam::DVec3;

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

/// One edge's inputs to [`control_points_of`], as numbers a shader can take: where
/// [`Png1Edge`] says `Option`, this says `1` or `0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Png1EdgeOf<T> {
    /// The neighbour's corner opposite the edge; read only where `smooth` is `1`.
    pub opposite: V3<T>,
    /// `1`: a smooth edge with a neighbour, whose plane joins the middle plane; `0`: sharp,
    /// boundary or non-manifold, the triangle's own plane alone.
    pub smooth: T,
    /// `1`: a sharp edge, its cross and centre points moved by `kappa N_T`; `0`: not.
    pub sharp: T,
    pub kappa: T,
}

impl Png1Edge {
    /// This edge as [`control_points_of`] takes it, in `f64`.
    pub fn numbers(&self) -> Png1EdgeOf<f64> {
        let bit = |b: bool| if b { 1.0 } else { 0.0 };
        Png1EdgeOf {
            opposite: self.opposite.unwrap_or(DVec3::ZERO).into(),
            smooth: bit(self.sharp.is_none() && self.opposite.is_some()),
            sharp: bit(self.sharp.is_some()),
            kappa: self.sharp.unwrap_or(0.0),
        }
    }
}

/// A unit vector orthogonal to the unit vector `n` (`glam`'s `any_orthonormal_vector`, Duff et
/// al.'s branchless basis). The sign of `n.z` is read from `1 / n.z`, so `-0.0` counts as
/// negative, as `signum` has it.
fn any_orthonormal<T: Noise>(n: V3<T>) -> V3<T> {
    let (one, zero) = (T::lit(1.0), T::lit(0.0));
    let sign = T::pick_gt(one / n.z, zero, one, -one);
    let a = T::lit(-1.0) / (sign + n.z);
    let b = n.x * n.y * a;
    V3::new(b, sign + n.y * n.y * a, -n.y)
}

/// `x` projected along `n` into the tangent plane at `a`, rescaled to `|x - a|`, a third of the
/// way (section 3.2, Figure 5).
fn tangent_point<T: Noise>(a: V3<T>, n: V3<T>, x: V3<T>) -> V3<T> {
    let d = x - a;
    let proj = d - n * d.dot(n);
    let len = proj.length();
    // `len - 1e-300` is positive and finite exactly where `len > 1e-300` is finite.
    V3::choose_positive_finite(
        len - T::lit(1e-300),
        || a + proj * (d.length() / len / T::lit(3.0)),
        // The edge runs along the normal: any tangent direction is as good as another.
        || a + any_orthonormal(n) * (d.length() / T::lit(3.0)),
    )
}

/// A segment `s0 → s1` in a plane with unit normal `n`, as a frame `(t, n × t / |t|)` at `s0`:
/// the pieces of the similarity [`transfer`] builds, kept so that the four transfers of an
/// edge set up three frames instead of eight (the same operations, so the same bits).
struct SegmentFrame<T> {
    s0: V3<T>,
    t: V3<T>,
    m: V3<T>,
    len: T,
}

impl<T: Noise> SegmentFrame<T> {
    fn new(s0: V3<T>, s1: V3<T>, n: V3<T>) -> SegmentFrame<T> {
        let t = s1 - s0;
        let len = t.length();
        // Unused when the segment is degenerate (`len == 0`): the transfer translates then.
        let m = V3::choose_nonzero(len, || n.cross(t) / len, V3::zero);
        SegmentFrame { s0, t, m, len }
    }

    /// `x` in this frame: its offset from `s0` and its coordinates `(ξ, η)` along `t` and `m`,
    /// in units of the segment's length (`0` on a degenerate segment).
    fn coords(&self, x: V3<T>) -> (V3<T>, T, T) {
        let r = x - self.s0;
        let zero = T::lit(0.0);
        // ξ and η as a vector's first two parts, to choose them at once.
        let along = V3::choose_nonzero(
            self.len,
            || {
                let xi = r.dot(self.t) / (self.len * self.len);
                V3::new(xi, r.dot(self.m) / self.len, zero)
            },
            V3::zero,
        );
        (r, along.x, along.y)
    }

    /// The point with coordinates `coords` (from `from`) in this frame: the similarity carrying
    /// `from`'s segment onto this one, or a translation when either segment is degenerate.
    fn place(&self, from: &SegmentFrame<T>, (r, xi, eta): (V3<T>, T, T)) -> V3<T> {
        let similar = || self.s0 + self.t * xi + self.m * (eta * self.len);
        let translated = || self.s0 + r;
        V3::choose_nonzero(
            from.len,
            || V3::choose_nonzero(self.len, similar, translated),
            translated,
        )
    }
}

/// The similarity carrying segment `s0 → s1` (in the plane with unit normal `ns`) onto
/// `d0 → d1` (in the plane with unit normal `nd`), frames `(t, n × t, n)` onto each other,
/// applied to `x`. The plain form of what [`SegmentFrame`] computes in parts.
#[cfg(test)]
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
fn tri_normal<T: Real>(a: V3<T>, b: V3<T>, o: V3<T>) -> V3<T> {
    (b - a).cross(o - a).normalize_or_zero()
}

/// The 21 control points ([`PNG1_ORDER`]) of one triangle from its corners `p`, unit normals `n`
/// and edges, in f64. The middle plane of edge `k` uses the triangle `(p[k], p[k+1], p[k+2])`'s
/// normal and the neighbour's, both computed so that the two sides of an edge get the same plane.
pub fn control_points_f64(p: [DVec3; 3], n: [DVec3; 3], edges: [Png1Edge; 3]) -> [DVec3; 21] {
    control_points_of(p.map(V3::from), n.map(V3::from), edges.map(|e| e.numbers())).map(DVec3::from)
}

/// [`control_points_f64`] over any [`Noise`] number: the one source of the CPU's nets (in
/// `f64`) and of the OpenGL control shader's (`shader::png1_net_glsl`, traced in doubles).
/// Every branch is a choice ([`V3::choose_nonzero`]): the CPU computes the side it takes, a
/// traced number records both sides and a selection.
pub fn control_points_of<T: Noise>(
    p: [V3<T>; 3],
    n: [V3<T>; 3],
    edges: [Png1EdgeOf<T>; 3],
) -> [V3<T>; 21] {
    // f32 unit normals are unit only to f32 rounding; the construction needs exact tangent planes.
    let z = V3::new(T::lit(0.0), T::lit(0.0), T::lit(1.0));
    let n = n.map(|v| v.normalize_or(z));
    let mut net = [V3::zero(); PNG1_LEN];
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
        let n_sum = V3::choose_nonzero(
            edge.smooth,
            || n_t + tri_normal(pb, pa, edge.opposite),
            || n_t,
        );
        let e1 = e_b - e_a;
        let t = e1.normalize_or_zero();
        let nm = (n_sum - t * n_sum.dot(t)).normalize_or_zero();
        // Folded neighbours cancel: fall back on the corner normals, then on anything.
        let fallback = || {
            let s = na + nb;
            let from_corners = (s - t * s.dot(t)).normalize_or_zero();
            V3::choose_nonzero(
                from_corners.length_squared(),
                || from_corners,
                || any_orthonormal(t),
            )
        };
        let nm = V3::choose_nonzero(nm.length_squared(), || nm, fallback);

        // Version a maps from a → e_a (a's plane), version b from e_b → b (b's plane); each
        // onto the middle segment and onto the other end's segment.
        let at_a = SegmentFrame::new(pa, e_a, na);
        let at_b = SegmentFrame::new(e_b, pb, nb);
        let middle = SegmentFrame::new(e_a, e_b, nm);
        let (in_a, in_b) = (at_a.coords(f_a), at_b.coords(f_b));
        let sharpen = |x: V3<T>| V3::choose_nonzero(edge.sharp, || x + n_t * edge.kappa, || x);
        let centre_a = sharpen(middle.place(&at_a, in_a));
        let cross_a = sharpen(at_b.place(&at_a, in_a));
        let centre_b = sharpen(middle.place(&at_b, in_b));
        let cross_b = sharpen(at_a.place(&at_b, in_b));
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

/// The smoothed normals of section 3.3 as the crate's 6-entry quadratic normal net
/// (weights `l1², l2², l3², l1 l2, l2 l3, l3 l1`): corners `N_i`, mid-edge monomial coefficients
/// `2 n_e = 4 M_e - (Na + Nb)` with `M_e` the unit surface normal at the edge's midpoint, so the
/// net reproduces the surface normal exactly at corners and edge midpoints.
pub fn smoothed_normal_net(net: &[DVec3; PNG1_LEN], n: [DVec3; 3]) -> [DVec3; NORMAL_NET_LEN] {
    smoothed_normal_net_of(&net.map(V3::from), n.map(V3::from)).map(DVec3::from)
}

/// [`smoothed_normal_net`] over any [`Real`]: the CPU runs it in `f64`, the OpenGL control
/// shader in doubles (`shader::png1_normals_glsl`).
pub fn smoothed_normal_net_of<T: Real>(
    net: &[V3<T>; PNG1_LEN],
    n: [V3<T>; 3],
) -> [V3<T>; NORMAL_NET_LEN] {
    let mut out = [n[0], n[1], n[2], V3::zero(), V3::zero(), V3::zero()];
    for k in 0..3 {
        let (mut du, mut dv) = (V3::zero(), V3::zero());
        for (w, c) in crate::basis::png1::mid_weights(k).iter().zip(net) {
            du = du + *c * T::lit(w.du);
            dv = dv + *c * T::lit(w.dv);
        }
        let (a, b) = (n[k], n[(k + 1) % 3]);
        // A degenerate midpoint (Du ∥ Dv) falls back on the mean of the end normals.
        let m = du.cross(dv).normalize_or((a + b).normalize_or_zero());
        out[3 + k] = m * T::lit(4.0) - (a + b);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frames give the plain similarity's bits, degenerate segments (a translation)
    /// included.
    #[test]
    fn segment_frames_give_the_plain_transfer_bit_for_bit() {
        let mut seed = 11u32;
        let mut r = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f64 / (1u32 << 24) as f64 * 2.0 - 1.0
        };
        for case in 0..200 {
            let mut v = || DVec3::new(r(), r(), r());
            let (x, s0, d0) = (v(), v(), v());
            let mut s1 = v();
            let mut d1 = v();
            if case % 7 == 0 {
                s1 = s0;
            }
            if case % 11 == 0 {
                d1 = d0;
            }
            let (ns, nd) = (v().normalize(), v().normalize());
            let from = SegmentFrame::new(s0.into(), s1.into(), ns.into());
            let to = SegmentFrame::new(d0.into(), d1.into(), nd.into());
            let got = DVec3::from(to.place(&from, from.coords(x.into())));
            let want = transfer(x, s0, s1, ns, d0, d1, nd);
            let bits = |p: DVec3| p.to_array().map(f64::to_bits);
            assert_eq!(bits(got), bits(want), "case {case}");
        }
    }
}
