//! An independent f64 evaluation of the surfaces, written from the papers' formulas (as corrected
//! in docs/formulas.md), plus the helpers the acceptance tests share.
//!
//! Nothing here uses the crate's `Basis`, `Stencil`, `PatchNets` or `eval_point`: the point of
//! this module is to catch a mistake in any of them. From the crate it takes only plain data:
//! a validated `Mesh` (positions, unit normals, triangles), a `Pattern`'s table of barycentric
//! points and small triangles, and the refined output.
//!
//! Convention (docs/formulas.md, Conventions): a point of face `(P1, P2, P3)` is `l1 P1 + l2 P2 + l3 P3`, and the
//! first index of `b_ijk` belongs to `P1`. Derivatives use `l = (1 - u - v, u, v)`, so `Du` runs
//! along `P1 -> P2` and `Dv` along `P1 -> P3`, and `Du × Dv` faces the side a counter-clockwise
//! triangle's normals face.

#![allow(dead_code)]

pub mod corpus;

use glam::DVec3;
use tessella_core::{Mesh, Pattern, RefinedMesh};

/// Which surface the reference evaluates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RefScheme {
    Flat,
    Phong { alpha: f64 },
    Pn,
}

/// Which normals the reference evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RefNormals {
    Linear,
    Quadratic,
    Real,
}

/// One coarse triangle in f64: corners and unit normals.
#[derive(Debug, Clone, Copy)]
pub struct Tri {
    pub p: [DVec3; 3],
    pub n: [DVec3; 3],
}

impl Tri {
    /// Face `f` of `mesh`, widened to f64 (normals re-normalised in f64: the papers assume unit
    /// normals, the f32 ones are unit to about 1e-7).
    pub fn of(mesh: &Mesh, f: usize) -> Tri {
        let t = mesh.triangles()[f];
        Tri {
            p: t.map(|v| d3(mesh.positions()[v as usize])),
            n: t.map(|v| d3(mesh.normals()[v as usize]).normalize()),
        }
    }
}

pub fn d3(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// The cubic PN control net (Vlachos et al. 2001; GMR Appendix A with the fixes in docs/formulas.md, Corrections to printed formulas),
/// indexed by `(i, j, k)`.
#[derive(Debug, Clone, Copy)]
pub struct PnNet {
    /// `net[i][j]` is `b_ij(3-i-j)`.
    net: [[DVec3; 4]; 4],
}

impl PnNet {
    pub fn new(t: &Tri) -> PnNet {
        let [p1, p2, p3] = t.p;
        let [n1, n2, n3] = t.n;
        // b_ij = (2 Pi + Pj - w_ij Ni) / 3,  w_ij = (Pj - Pi) . Ni
        let edge = |pi: DVec3, pj: DVec3, ni: DVec3| (2.0 * pi + pj - (pj - pi).dot(ni) * ni) / 3.0;
        let b210 = edge(p1, p2, n1);
        let b120 = edge(p2, p1, n2);
        let b021 = edge(p2, p3, n2);
        let b012 = edge(p3, p2, n3);
        let b102 = edge(p3, p1, n3);
        let b201 = edge(p1, p3, n1);
        // b111 = E + (E - V) / 2
        let e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
        let v = (p1 + p2 + p3) / 3.0;
        let b111 = e + (e - v) / 2.0;
        let mut net = [[DVec3::NAN; 4]; 4];
        let mut set = |i: usize, j: usize, b: DVec3| net[i][j] = b;
        set(3, 0, p1);
        set(0, 3, p2);
        set(0, 0, p3);
        set(2, 1, b210);
        set(1, 2, b120);
        set(0, 2, b021);
        set(0, 1, b012);
        set(1, 0, b102);
        set(2, 0, b201);
        set(1, 1, b111);
        PnNet { net }
    }

    /// `b_ijk`.
    pub fn b(&self, i: usize, j: usize, k: usize) -> DVec3 {
        debug_assert_eq!(i + j + k, 3);
        self.net[i][j]
    }

    /// `b(l) = Σ 3!/(i!j!k!) b_ijk l1^i l2^j l3^k`, written out term by term.
    pub fn value(&self, l: [f64; 3]) -> DVec3 {
        let [l1, l2, l3] = l;
        let b = |i, j, k| self.b(i, j, k);
        l1 * l1 * l1 * b(3, 0, 0)
            + l2 * l2 * l2 * b(0, 3, 0)
            + l3 * l3 * l3 * b(0, 0, 3)
            + 3.0 * l1 * l1 * l2 * b(2, 1, 0)
            + 3.0 * l1 * l2 * l2 * b(1, 2, 0)
            + 3.0 * l2 * l2 * l3 * b(0, 2, 1)
            + 3.0 * l2 * l3 * l3 * b(0, 1, 2)
            + 3.0 * l3 * l3 * l1 * b(1, 0, 2)
            + 3.0 * l3 * l1 * l1 * b(2, 0, 1)
            + 6.0 * l1 * l2 * l3 * b(1, 1, 1)
    }

    /// Partial derivatives `∂b/∂l1, ∂b/∂l2, ∂b/∂l3` of [`PnNet::value`], differentiated by hand
    /// term by term (e.g. `3 l1² l2 b210` gives `6 l1 l2 b210` to `∂/∂l1` and `3 l1² b210` to
    /// `∂/∂l2`):
    /// - `∂/∂l1 = 3 [l1² b300 + l2² b120 + l3² b102 + 2 l1 l2 b210 + 2 l2 l3 b111 + 2 l3 l1 b201]`
    /// - `∂/∂l2 = 3 [l1² b210 + l2² b030 + l3² b012 + 2 l1 l2 b120 + 2 l2 l3 b021 + 2 l3 l1 b111]`
    /// - `∂/∂l3 = 3 [l1² b201 + l2² b021 + l3² b003 + 2 l1 l2 b111 + 2 l2 l3 b012 + 2 l3 l1 b102]`
    pub fn partials(&self, l: [f64; 3]) -> [DVec3; 3] {
        let [l1, l2, l3] = l;
        let b = |i, j, k| self.b(i, j, k);
        let (q1, q2, q3) = (l1 * l1, l2 * l2, l3 * l3);
        let (m12, m23, m31) = (2.0 * l1 * l2, 2.0 * l2 * l3, 2.0 * l3 * l1);
        [
            3.0 * (q1 * b(3, 0, 0)
                + q2 * b(1, 2, 0)
                + q3 * b(1, 0, 2)
                + m12 * b(2, 1, 0)
                + m23 * b(1, 1, 1)
                + m31 * b(2, 0, 1)),
            3.0 * (q1 * b(2, 1, 0)
                + q2 * b(0, 3, 0)
                + q3 * b(0, 1, 2)
                + m12 * b(1, 2, 0)
                + m23 * b(0, 2, 1)
                + m31 * b(1, 1, 1)),
            3.0 * (q1 * b(2, 0, 1)
                + q2 * b(0, 2, 1)
                + q3 * b(0, 0, 3)
                + m12 * b(1, 1, 1)
                + m23 * b(0, 1, 2)
                + m31 * b(1, 0, 2)),
        ]
    }
}

/// Phong tessellation's projection onto the tangent plane at `p` (normal `n`):
/// `pi(q) = q - ((q - p) . n) n`.
pub fn project(q: DVec3, p: DVec3, n: DVec3) -> DVec3 {
    q - (q - p).dot(n) * n
}

/// Phong tessellation (Boubekeur & Alexa 2008): `p*(l) = Σ li² Pi + Σ_{i<j} li lj (pi_i(Pj) +
/// pi_j(Pi))`, `p_alpha = (1 - alpha) p_flat + alpha p*`.
pub fn phong(t: &Tri, alpha: f64, l: [f64; 3]) -> DVec3 {
    let flat = flat(t, l);
    let mut star = l[0] * l[0] * t.p[0] + l[1] * l[1] * t.p[1] + l[2] * l[2] * t.p[2];
    for (i, j) in [(0, 1), (1, 2), (0, 2)] {
        star += l[i] * l[j] * (project(t.p[j], t.p[i], t.n[i]) + project(t.p[i], t.p[j], t.n[j]));
    }
    (1.0 - alpha) * flat + alpha * star
}

/// Partial derivatives of [`phong`] with respect to `l1, l2, l3`:
/// `∂p*/∂li = 2 li Pi + Σ_{j≠i} lj (pi_i(Pj) + pi_j(Pi))`, `∂p_flat/∂li = Pi`.
pub fn phong_partials(t: &Tri, alpha: f64, l: [f64; 3]) -> [DVec3; 3] {
    let mut d = [0, 1, 2].map(|i| 2.0 * l[i] * t.p[i]);
    for (i, j) in [(0, 1), (1, 2), (0, 2)] {
        let m = project(t.p[j], t.p[i], t.n[i]) + project(t.p[i], t.p[j], t.n[j]);
        d[i] += l[j] * m;
        d[j] += l[i] * m;
    }
    [0, 1, 2].map(|i| (1.0 - alpha) * t.p[i] + alpha * d[i])
}

/// The flat triangle `l1 P1 + l2 P2 + l3 P3`.
pub fn flat(t: &Tri, l: [f64; 3]) -> DVec3 {
    l[0] * t.p[0] + l[1] * t.p[1] + l[2] * t.p[2]
}

/// Vlachos' mid-edge normal `n_ij = normalize(Ni + Nj - v_ij (Pj - Pi))`,
/// `v_ij = 2 (Pj - Pi).(Ni + Nj) / |Pj - Pi|²`.
pub fn mid_normal(t: &Tri, i: usize, j: usize) -> DVec3 {
    let d = t.p[j] - t.p[i];
    let s = t.n[i] + t.n[j];
    let v = 2.0 * d.dot(s) / d.length_squared();
    (s - v * d).normalize()
}

/// A reference patch: one face's surface and normals, with the per-face work done once.
#[derive(Debug, Clone, Copy)]
pub struct RefPatch {
    pub tri: Tri,
    pub scheme: RefScheme,
    pub normals: RefNormals,
    pn: Option<PnNet>,
    mids: [DVec3; 3],
}

impl RefPatch {
    pub fn new(tri: Tri, scheme: RefScheme, normals: RefNormals) -> RefPatch {
        RefPatch {
            tri,
            scheme,
            normals,
            pn: (scheme == RefScheme::Pn).then(|| PnNet::new(&tri)),
            mids: [
                mid_normal(&tri, 0, 1),
                mid_normal(&tri, 1, 2),
                mid_normal(&tri, 2, 0),
            ],
        }
    }

    /// The surface point at `l`.
    pub fn position(&self, l: [f64; 3]) -> DVec3 {
        match self.scheme {
            RefScheme::Flat => flat(&self.tri, l),
            RefScheme::Phong { alpha } => phong(&self.tri, alpha, l),
            RefScheme::Pn => self.pn.unwrap().value(l),
        }
    }

    /// `∂/∂l1, ∂/∂l2, ∂/∂l3` of the surface.
    pub fn partials(&self, l: [f64; 3]) -> [DVec3; 3] {
        match self.scheme {
            RefScheme::Flat => self.tri.p,
            RefScheme::Phong { alpha } => phong_partials(&self.tri, alpha, l),
            RefScheme::Pn => self.pn.unwrap().partials(l),
        }
    }

    /// `(Du, Dv)` with `l = (1 - u - v, u, v)`: `Du = ∂/∂l2 - ∂/∂l1`, `Dv = ∂/∂l3 - ∂/∂l1`.
    pub fn du_dv(&self, l: [f64; 3]) -> (DVec3, DVec3) {
        let d = self.partials(l);
        (d[1] - d[0], d[2] - d[0])
    }

    /// The unit normal at `l`.
    pub fn normal(&self, l: [f64; 3]) -> DVec3 {
        let t = &self.tri;
        match self.normals {
            RefNormals::Linear => (l[0] * t.n[0] + l[1] * t.n[1] + l[2] * t.n[2]).normalize(),
            RefNormals::Quadratic => (t.n[0] * l[0] * l[0]
                + t.n[1] * l[1] * l[1]
                + t.n[2] * l[2] * l[2]
                + self.mids[0] * l[0] * l[1]
                + self.mids[1] * l[1] * l[2]
                + self.mids[2] * l[2] * l[0])
                .normalize(),
            RefNormals::Real => {
                let (du, dv) = self.du_dv(l);
                du.cross(dv).normalize()
            }
        }
    }
}

/// Angle between two directions in radians, accurate near zero (`acos` of a dot product is not:
/// it cannot resolve angles below about 1e-8 rad and amplifies rounding near 1).
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Length of the bounding box diagonal of `mesh`, in f64.
pub fn diagonal(mesh: &Mesh) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for &p in mesh.positions() {
        lo = lo.min(d3(p));
        hi = hi.max(d3(p));
    }
    (hi - lo).length()
}

/// One place an output vertex appears: corner `corner` of output triangle `triangle`, which is
/// pattern point `point` of coarse face `face`.
#[derive(Debug, Clone, Copy)]
pub struct Occurrence {
    pub vertex: usize,
    pub face: usize,
    pub point: usize,
}

/// Every (output vertex, coarse face, pattern point) the output's triangles name, once per
/// (face, point) pair. Output triangles are face-major in pattern order in both layouts: output
/// triangle `f·N² + t` has, at corner `c`, the vertex of pattern point `pattern.triangles[t][c]`
/// of face `f`. Panics when a (face, point) pair is given two different vertices.
pub fn occurrences(out: &RefinedMesh, faces: usize, pattern: &Pattern) -> Vec<Occurrence> {
    let per_face = pattern.triangles.len();
    assert_eq!(out.triangles.len(), faces * per_face, "triangle count");
    let np = pattern.points.len();
    let mut result = Vec::with_capacity(faces * np);
    let mut seen = vec![u32::MAX; np];
    for f in 0..faces {
        seen.fill(u32::MAX);
        for (t, small) in pattern.triangles.iter().enumerate() {
            let tri = out.triangles[f * per_face + t];
            for c in 0..3 {
                let p = small[c] as usize;
                let v = tri[c];
                if seen[p] == u32::MAX {
                    seen[p] = v;
                    result.push(Occurrence {
                        vertex: v as usize,
                        face: f,
                        point: p,
                    });
                } else {
                    assert_eq!(
                        seen[p], v,
                        "face {f}: pattern point {p} has two output vertices"
                    );
                }
            }
        }
        assert!(
            seen.iter().all(|&v| v != u32::MAX),
            "face {f}: some pattern point is in no output triangle"
        );
    }
    result
}

/// Unique undirected edges of a triangle list, by vertex index.
pub fn undirected_edges(triangles: &[[u32; 3]]) -> usize {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges.len()
}

/// What [`closed_manifold`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Manifold {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub euler: i64,
}

/// Checks that `triangles` over `vertex_count` vertices form a closed, consistently oriented
/// manifold surface: every vertex used, no degenerate index triple, every directed edge used
/// exactly once and its reverse exactly once. Returns the counts and `V - E + F`.
pub fn closed_manifold(vertex_count: usize, triangles: &[[u32; 3]]) -> Result<Manifold, String> {
    let mut used = vec![false; vertex_count];
    let mut directed: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for (f, t) in triangles.iter().enumerate() {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return Err(format!("triangle {f} repeats a vertex: {t:?}"));
        }
        for k in 0..3 {
            let v = t[k] as usize;
            if v >= vertex_count {
                return Err(format!("triangle {f} uses vertex {v} of {vertex_count}"));
            }
            used[v] = true;
            directed.push((t[k], t[(k + 1) % 3]));
        }
    }
    if let Some(v) = used.iter().position(|u| !u) {
        return Err(format!("vertex {v} is in no triangle"));
    }
    directed.sort_unstable();
    if let Some(w) = directed.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!(
            "directed edge {:?} is used twice (inconsistent winding or non-manifold)",
            w[0]
        ));
    }
    for &(a, b) in &directed {
        if directed.binary_search(&(b, a)).is_err() {
            return Err(format!(
                "edge ({a}, {b}) has no opposite half-edge (a hole)"
            ));
        }
    }
    let edges = directed.len() / 2;
    Ok(Manifold {
        vertices: vertex_count,
        edges,
        faces: triangles.len(),
        euler: vertex_count as i64 - edges as i64 + triangles.len() as i64,
    })
}
