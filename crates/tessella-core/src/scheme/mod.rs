//! Surface schemes. A scheme turns each coarse triangle (with its normals, and for some schemes
//! its neighbours or tags) into a *control net*: the points its [`Basis`] combines, plus a
//! quadratic net of control normals. Evaluation never depends on the scheme, only on the basis.
//!
//! | scheme | paper | basis | default normals |
//! |---|---|---|---|
//! | [`Scheme::Flat`] | the input triangle | cubic (degree-elevated) | linear |
//! | [`Scheme::Phong`] | Boubekeur & Alexa 2008; FEM poster | cubic (degree-elevated quadratic) | linear |
//! | [`Scheme::Pn`] | Vlachos et al. 2001; GMR Appendix A | cubic | quadratic |
//! | [`Scheme::Png1`] | Fünfzig et al. 2008 | [`Basis::Png1`] (21 points, rational blends) | section 3.3 smoothed |
//! | [`Scheme::PnAen`] | McDonald & Kilgard 2010 | cubic | quadratic |
//! | [`Scheme::ScalarTagged`] | GMR Appendix B | cubic | quadratic (side normals) |
//! | [`Scheme::Quadratic`] | isoparametric P2 finite elements | cubic (degree-elevated quadratic) | real |
//!
//! PNG1 and PN-AEN look across edges (neighbours by position, [`Topology::neighbors`]); the
//! scalar-tagged scheme reads [`Tags`] by position. The others see one triangle at a time.

pub(crate) mod flat;
pub(crate) mod normal_net;
pub(crate) mod phong;
pub(crate) mod pn;
pub mod pn_aen;
pub mod png1;
mod quadratic;
mod scalar_tagged;

use crate::basis::{Basis, NORMAL_NET_LEN};
use crate::error::RefineError;
use crate::mesh::topology::across_edge;
use crate::mesh::{Mesh, Topology};
use crate::scalar::{Real, V3};
use crate::tags::Tags;
use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

/// Which surface to build over each coarse triangle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "scheme", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Scheme {
    /// The coarse triangle itself.
    Flat,
    /// Phong tessellation with shape factor `alpha` (0 = flat, 1 = full projection; 3/4 is the
    /// paper's default).
    Phong { alpha: f32 },
    /// Curved PN triangles: cubic geometry from positions and normals.
    Pn,
    /// PNG1 triangles: G1 across edges, from each triangle, its normals and its edge
    /// neighbours ([`png1`]).
    Png1,
    /// Crack-free PN triangles (PN-AEN): PN whose edge points average both sides' normals, so
    /// hard edges and UV seams stay closed ([`pn_aen`](self)).
    PnAen,
    /// Scalar-tagged PN (GMR Appendix B): PN shaped by per-vertex tension, sharpness, bias and
    /// crease direction and per-edge crease sharpness from [`Tags`]; zero tags give PN.
    ScalarTagged,
    /// Second-order finite elements: the isoparametric P2 map of faces with mid-edge nodes
    /// ([`Mesh::with_mid_nodes`]), exactly; linear faces stay flat.
    Quadratic,
}

/// Largest |alpha| [`Scheme::Phong`] accepts.
pub const MAX_PHONG_ALPHA: f32 = 16.0;

impl Scheme {
    /// Phong tessellation with the paper's default shape factor 3/4.
    pub const PHONG: Scheme = Scheme::Phong { alpha: 0.75 };

    /// The basis this scheme's control nets are combined with.
    pub fn basis(&self) -> Basis {
        match self {
            Scheme::Png1 => Basis::Png1,
            _ => Basis::Cubic,
        }
    }

    /// True for schemes whose nets depend on the triangles across each edge.
    pub fn needs_topology(&self) -> bool {
        matches!(self, Scheme::Png1 | Scheme::PnAen | Scheme::ScalarTagged)
    }

    /// The normals a scheme uses unless told otherwise.
    pub fn default_normals(&self) -> NormalMode {
        match self {
            Scheme::Flat | Scheme::Phong { .. } => NormalMode::Linear,
            Scheme::Quadratic => NormalMode::Real,
            Scheme::Pn | Scheme::Png1 | Scheme::PnAen | Scheme::ScalarTagged => {
                NormalMode::Quadratic
            }
        }
    }

    /// How far a patch's control points may lie from its flat triangle, in lengths of the
    /// triangle's longest edge, where the net formulas alone bound it: flat 0; PN and PN-AEN
    /// 1/2 (an edge point lies within a third of its edge of the flat point, the centre
    /// within half); Phong `|alpha|` (each projection moves a point by at most an edge).
    /// `None` where the nets need more to bound (PNG1, scalar-tagged, quadratic).
    pub fn control_reach(&self) -> Option<f32> {
        match self {
            Scheme::Flat => Some(0.0),
            Scheme::Pn | Scheme::PnAen => Some(0.5),
            Scheme::Phong { alpha } => Some(alpha.abs()),
            Scheme::Png1 | Scheme::ScalarTagged | Scheme::Quadratic => None,
        }
    }

    /// Short lowercase name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::Flat => "flat",
            Scheme::Phong { .. } => "phong",
            Scheme::Pn => "pn",
            Scheme::Png1 => "png1",
            Scheme::PnAen => "pn-aen",
            Scheme::ScalarTagged => "st",
            Scheme::Quadratic => "quadratic",
        }
    }

    /// Checks the scheme's parameters.
    pub fn validate(&self) -> Result<(), RefineError> {
        match *self {
            // The paper's alpha lies in 0..=1; a little outside still makes sense (over- or
            // under-shooting the projection), but a huge one overflows f32 (found by fuzzing).
            Scheme::Phong { alpha } if !(alpha.is_finite() && alpha.abs() <= MAX_PHONG_ALPHA) => {
                Err(RefineError::BadAlpha(alpha))
            }
            _ => Ok(()),
        }
    }
}

/// How refined normals are made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum NormalMode {
    /// Vertex normals interpolated linearly (Phong shading), normalised.
    Linear,
    /// Vlachos' quadratic normals: the mid-edge normals reflect the edge's curvature. For PNG1,
    /// the smoothed normals of its section 3.3 (exact at corners and edge midpoints).
    Quadratic,
    /// The surface's own normal, `Du × Dv` of the patch ("real" normals, van Veen 3.2.2).
    Real,
}

/// The control nets of every coarse triangle, laid out flat so any backend can consume them:
/// patch `f`'s points are `points[f*K..(f+1)*K]` with `K = basis.len()`, in the basis' order, and
/// its normal net is `normals[f*6..(f+1)*6]` (`N1, N2, N3, n110, n011, n101`).
#[derive(Debug, Clone, PartialEq)]
pub struct PatchNets {
    pub basis: Basis,
    pub normal_mode: NormalMode,
    pub points: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
}

impl PatchNets {
    /// Nets of no patches, for a surface to fill ([`build_nets`] builds filled ones).
    pub fn empty(basis: Basis, normal_mode: NormalMode) -> PatchNets {
        PatchNets {
            basis,
            normal_mode,
            points: Vec::new(),
            normals: Vec::new(),
        }
    }
    /// Number of patches.
    pub fn len(&self) -> usize {
        self.normals.len() / NORMAL_NET_LEN
    }
    /// True when there are no patches.
    pub fn is_empty(&self) -> bool {
        self.normals.is_empty()
    }
    /// Control points of patch `f`.
    pub fn patch_points(&self, f: usize) -> &[[f32; 3]] {
        let k = self.basis.len();
        &self.points[f * k..(f + 1) * k]
    }
    /// Control normals of patch `f`.
    pub fn patch_normals(&self, f: usize) -> &[[f32; 3]] {
        &self.normals[f * NORMAL_NET_LEN..(f + 1) * NORMAL_NET_LEN]
    }

    /// Packs the nets as RGBA float texels for a GPU that reads them from a texture (WebGL2's
    /// `TessellatedMesh` and the viewer's fallback): patch `f` takes `texels` texels from
    /// texel `((f % per_row) * texels, f / per_row)` of rows `per_row * texels` texels wide,
    /// holding its control points then its normal net, 3 floats an entry one after the other
    /// (an entry may straddle two texels). Floats past a patch's entries are left as they are.
    ///
    /// Panics when a patch's entries do not fit its texels or `out` is too short (the callers
    /// size both from [`PatchNets::len`] and [`Basis::len`]).
    pub fn pack_texels(&self, per_row: usize, texels: usize, out: &mut [f32]) {
        let width = per_row * texels;
        for f in 0..self.len() {
            let start = ((f / per_row) * width + (f % per_row) * texels) * 4;
            let entries = self.patch_points(f).iter().chain(self.patch_normals(f));
            for (e, v) in entries.enumerate() {
                out[start + 3 * e..start + 3 * e + 3].copy_from_slice(v);
            }
        }
    }
}

/// What a net builder sees of one coarse triangle.
pub struct Corners {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
}

/// Builds the control nets of every face of `mesh`, in parallel.
///
/// `topology` is for schemes that look across edges ([`Scheme::needs_topology`]); it is computed
/// here when such a scheme gets `None`. Flat, Phong and PN ignore it. `tags` are the shape tags:
/// sharp edges for PNG1, everything for the scalar-tagged scheme (checked against its
/// restrictions first); other schemes ignore them. A deforming mesh's per-frame update reuses
/// its nets' memory through [`crate::refine::Surface::update`] instead.
pub fn build_nets(
    mesh: &Mesh,
    topology: Option<&Topology>,
    scheme: &Scheme,
    normal_mode: NormalMode,
    tags: Option<&Tags>,
) -> Result<PatchNets, RefineError> {
    let owned;
    let topology = match topology {
        Some(t) => Some(t),
        None if scheme.needs_topology() => {
            owned = mesh.topology();
            Some(&owned)
        }
        None => None,
    };
    validate_nets(mesh, topology, scheme, tags)?;
    let mut nets = PatchNets::empty(scheme.basis(), normal_mode);
    fill_nets(mesh, topology, scheme, normal_mode, tags, &mut nets);
    Ok(nets)
}

/// The checks of [`build_nets`]: they depend on the scheme, the tags and the topology only,
/// so a deforming mesh passes them once. `topology` is required for schemes that need it.
pub(crate) fn validate_nets(
    mesh: &Mesh,
    topology: Option<&Topology>,
    scheme: &Scheme,
    tags: Option<&Tags>,
) -> Result<(), RefineError> {
    scheme.validate()?;
    if let (Scheme::ScalarTagged, Some(tags)) = (scheme, tags) {
        let topo = topology.expect("the scalar-tagged scheme needs the topology");
        tags.validate_scalar_tagged(mesh, topo)?;
    }
    Ok(())
}

#[cfg(test)]
thread_local! {
    /// How many times this thread called [`fill_nets`]: the unit tests count net builds.
    pub(crate) static NET_BUILDS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Fills `nets` for `mesh`, which passed [`validate_nets`] (with the same topology and tags);
/// `topology` is required for schemes that need it.
pub(crate) fn fill_nets(
    mesh: &Mesh,
    topology: Option<&Topology>,
    scheme: &Scheme,
    normal_mode: NormalMode,
    tags: Option<&Tags>,
    nets: &mut PatchNets,
) {
    #[cfg(test)]
    NET_BUILDS.with(|n| n.set(n.get() + 1));
    let empty = Tags::new();
    let tags = tags.unwrap_or(&empty);
    let mean_normals = match scheme {
        Scheme::ScalarTagged => {
            let topo = topology.expect("the scalar-tagged scheme needs the topology");
            scalar_tagged::position_normals(mesh, topo)
        }
        _ => Vec::new(),
    };
    let basis = scheme.basis();
    let k = basis.len();
    let faces = mesh.face_count();
    nets.basis = basis;
    nets.normal_mode = normal_mode;
    // Reuses the allocations of a previous frame (same face count: no allocation).
    nets.points.resize(faces * k, [0.0; 3]);
    nets.normals.resize(faces * NORMAL_NET_LEN, [0.0; 3]);
    nets.points
        .par_chunks_mut(k)
        .zip(nets.normals.par_chunks_mut(NORMAL_NET_LEN))
        .enumerate()
        .for_each(|(f, (pts, nrm))| {
            let c = Corners {
                p: mesh.corner_positions(f),
                n: mesh.corner_normals(f),
            };
            if *scheme == Scheme::Png1 {
                let topo = topology.expect("PNG1 has its topology");
                let (net, nnet) = png1_face(mesh, topo, tags, f, normal_mode);
                for (dst, src) in pts.iter_mut().zip(net) {
                    *dst = src.as_vec3().into();
                }
                for (dst, src) in nrm.iter_mut().zip(nnet) {
                    *dst = src.into();
                }
                return;
            }
            let (net, c) = match *scheme {
                Scheme::Flat => (flat::control_points(&c), c),
                Scheme::Phong { alpha } => (phong::control_points(&c, alpha), c),
                Scheme::Pn => (pn::control_points(&c), c),
                Scheme::PnAen => {
                    let topo = topology.expect("computed above");
                    (pn_aen::control_points(mesh, topo, f, &c), c)
                }
                Scheme::ScalarTagged => {
                    let topo = topology.expect("computed above");
                    scalar_tagged::control_points(mesh, topo, tags, &mean_normals, f, &c)
                }
                Scheme::Quadratic => (quadratic::control_points(mesh, f, &c), c),
                Scheme::Png1 => unreachable!("handled above"),
            };
            for (dst, src) in pts.iter_mut().zip(net) {
                *dst = src.into();
            }
            let nnet = match normal_mode {
                NormalMode::Quadratic => normal_net::quadratic(&c),
                // Real normals fall back to the linear net where Du × Dv vanishes.
                NormalMode::Linear | NormalMode::Real => normal_net::linear(&c),
            };
            for (dst, src) in nrm.iter_mut().zip(nnet) {
                *dst = src.into();
            }
        });
}

/// The data behind [`png1_edges`], by vertex index: for each edge `k` of face `f`, the
/// neighbour's corner opposite the edge (`None` on boundary and non-manifold edges) and, for a
/// sharp edge, its `κ`. It depends on the topology, the normals' splits and the tags only, so
/// a deforming mesh keeps it (the GL backend uploads it once and builds the nets in its
/// tessellation control shader).
pub fn png1_edge_sources(
    mesh: &Mesh,
    topo: &Topology,
    tags: &Tags,
    f: usize,
) -> [(Option<u32>, Option<f64>); 3] {
    let t = mesh.triangles()[f];
    let pid = |v: u32| topo.position_ids[v as usize];
    std::array::from_fn(|k| match across_edge(mesh, topo, f, k) {
        None => (None, None),
        Some(x) => {
            let nrm = |v: u32| mesh.normals()[v as usize];
            let split = nrm(x.at_a) != nrm(t[k]) || nrm(x.at_b) != nrm(t[(k + 1) % 3]);
            let tag = tags.edge(pid(t[k]), pid(t[(k + 1) % 3]));
            let sharp = if tag.sharpness > 0.0 {
                Some(tag.kappa as f64)
            } else {
                split.then_some(0.0)
            };
            (Some(x.opposite), sharp)
        }
    })
}

/// What PNG1 sees of the edges of face `f`: neighbours' opposite corners, sharp edges from
/// `tags` (sharpness > 0, displaced by their `kappa`), and sharp edges where the two sides
/// disagree on a normal (G1 cannot hold there).
pub fn png1_edges(mesh: &Mesh, topo: &Topology, tags: &Tags, f: usize) -> [png1::Png1Edge; 3] {
    let pos = |v: u32| glam::Vec3::from(mesh.positions()[v as usize]).as_dvec3();
    png1_edge_sources(mesh, topo, tags, f).map(|(opposite, sharp)| match opposite {
        None => png1::Png1Edge::default(),
        Some(v) => png1::Png1Edge {
            opposite: Some(pos(v)),
            sharp,
        },
    })
}

/// The PNG1 net of face `f` in f64 and its normal net for `mode`.
fn png1_face(
    mesh: &Mesh,
    topo: &Topology,
    tags: &Tags,
    f: usize,
    mode: NormalMode,
) -> ([glam::DVec3; png1::PNG1_LEN], [Vec3; NORMAL_NET_LEN]) {
    let p = mesh.corner_positions(f).map(|v| v.as_dvec3());
    let n = mesh.corner_normals(f).map(|v| v.as_dvec3());
    let net = png1::control_points_f64(p, n, png1_edges(mesh, topo, tags, f));
    let nnet = match mode {
        NormalMode::Quadratic => png1::smoothed_normal_net(&net, n).map(|v| v.as_vec3()),
        NormalMode::Linear | NormalMode::Real => normal_net::linear(&Corners {
            p: mesh.corner_positions(f),
            n: mesh.corner_normals(f),
        }),
    };
    (net, nnet)
}

/// PNG1 nets of every face in f64 (what [`build_nets`] rounds to f32): for checking G1 without
/// f32 rounding.
pub fn png1_nets_f64(
    mesh: &Mesh,
    topo: &Topology,
    tags: Option<&Tags>,
) -> Vec<[glam::DVec3; png1::PNG1_LEN]> {
    let empty = Tags::new();
    let tags = tags.unwrap_or(&empty);
    (0..mesh.face_count())
        .map(|f| {
            let p = mesh.corner_positions(f).map(|v| v.as_dvec3());
            let n = mesh.corner_normals(f).map(|v| v.as_dvec3());
            png1::control_points_f64(p, n, png1_edges(mesh, topo, tags, f))
        })
        .collect()
}

/// Degree-elevates a quadratic patch `sum li² Pi + sum_{i<j} li lj m_ij` (monomial mid
/// coefficients `m = [m12, m23, m31]`) to the cubic Bernstein net in [`crate::basis::CUBIC_ORDER`].
pub(crate) fn cubic_from_quadratic<T: Real>(p: [V3<T>; 3], m: [V3<T>; 3]) -> [V3<T>; 10] {
    // Bernstein mid coefficients q_ij = m_ij / 2; c_ijk = (i q_(i-1)jk + j q_i(j-1)k + k q_ij(k-1)) / 3.
    let q = m.map(|x| x * T::lit(0.5));
    let (two, three) = (T::lit(2.0), T::lit(3.0));
    [
        p[0],
        p[1],
        p[2],
        (p[0] + q[0] * two) / three,
        (p[1] + q[0] * two) / three,
        (p[1] + q[1] * two) / three,
        (p[2] + q[1] * two) / three,
        (p[2] + q[2] * two) / three,
        (p[0] + q[2] * two) / three,
        (q[0] + q[1] + q[2]) / three,
    ]
}
