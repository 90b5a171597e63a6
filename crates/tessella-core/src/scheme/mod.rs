//! Surface schemes. A scheme turns each coarse triangle (with its normals, and for some schemes
//! its neighbours or tags) into a *control net*: the points its [`Basis`] combines, plus a
//! quadratic net of control normals. Evaluation never depends on the scheme, only on the basis.
//!
//! | scheme | paper | basis | default normals |
//! |---|---|---|---|
//! | [`Scheme::Flat`] | the input triangle | cubic (degree-elevated) | linear |
//! | [`Scheme::Phong`] | Boubekeur & Alexa 2008; FEM poster | cubic (degree-elevated quadratic) | linear |
//! | [`Scheme::Pn`] | Vlachos et al. 2001; GMR Appendix A | cubic | quadratic |

mod flat;
mod normal_net;
mod phong;
mod pn;

use crate::basis::{Basis, NORMAL_NET_LEN};
use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

/// Which surface to build over each coarse triangle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "scheme", rename_all = "snake_case")]
pub enum Scheme {
    /// The coarse triangle itself.
    Flat,
    /// Phong tessellation with shape factor `alpha` (0 = flat, 1 = full projection; 3/4 is the
    /// paper's default).
    Phong { alpha: f32 },
    /// Curved PN triangles: cubic geometry from positions and normals.
    Pn,
}

impl Scheme {
    /// Phong tessellation with the paper's default shape factor 3/4.
    pub const PHONG: Scheme = Scheme::Phong { alpha: 0.75 };

    /// The basis this scheme's control nets are combined with.
    pub fn basis(&self) -> Basis {
        Basis::Cubic
    }

    /// The normals a scheme uses unless told otherwise.
    pub fn default_normals(&self) -> NormalMode {
        match self {
            Scheme::Flat | Scheme::Phong { .. } => NormalMode::Linear,
            Scheme::Pn => NormalMode::Quadratic,
        }
    }

    /// Short lowercase name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::Flat => "flat",
            Scheme::Phong { .. } => "phong",
            Scheme::Pn => "pn",
        }
    }

    /// Checks the scheme's parameters.
    pub fn validate(&self) -> Result<(), RefineError> {
        match *self {
            Scheme::Phong { alpha } if !alpha.is_finite() => Err(RefineError::BadAlpha(alpha)),
            _ => Ok(()),
        }
    }
}

/// How refined normals are made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalMode {
    /// Vertex normals interpolated linearly (Phong shading), normalised.
    Linear,
    /// Vlachos' quadratic normals: the mid-edge normals reflect the edge's curvature.
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
}

/// What a net builder sees of one coarse triangle.
pub struct Corners {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
}

/// Builds the control nets of every face of `mesh`, in parallel.
///
/// `topology` is for schemes that look across edges; flat, Phong and PN ignore it.
pub fn build_nets(
    mesh: &Mesh,
    _topology: Option<&Topology>,
    scheme: &Scheme,
    normal_mode: NormalMode,
) -> Result<PatchNets, RefineError> {
    scheme.validate()?;
    let basis = scheme.basis();
    let k = basis.len();
    let faces = mesh.face_count();
    let mut points = vec![[0.0f32; 3]; faces * k];
    let mut normals = vec![[0.0f32; 3]; faces * NORMAL_NET_LEN];
    points
        .par_chunks_mut(k)
        .zip(normals.par_chunks_mut(NORMAL_NET_LEN))
        .enumerate()
        .for_each(|(f, (pts, nrm))| {
            let c = Corners {
                p: mesh.corner_positions(f),
                n: mesh.corner_normals(f),
            };
            let net = match *scheme {
                Scheme::Flat => flat::control_points(&c),
                Scheme::Phong { alpha } => phong::control_points(&c, alpha),
                Scheme::Pn => pn::control_points(&c),
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
    Ok(PatchNets {
        basis,
        normal_mode,
        points,
        normals,
    })
}

/// Degree-elevates a quadratic patch `sum li² Pi + sum_{i<j} li lj m_ij` (monomial mid
/// coefficients `m = [m12, m23, m31]`) to the cubic Bernstein net in [`crate::basis::CUBIC_ORDER`].
pub(crate) fn cubic_from_quadratic(p: [Vec3; 3], m: [Vec3; 3]) -> [Vec3; 10] {
    // Bernstein mid coefficients q_ij = m_ij / 2; c_ijk = (i q_(i-1)jk + j q_i(j-1)k + k q_ij(k-1)) / 3.
    let q = m.map(|x| x * 0.5);
    [
        p[0],
        p[1],
        p[2],
        (p[0] + 2.0 * q[0]) / 3.0,
        (p[1] + 2.0 * q[0]) / 3.0,
        (p[1] + 2.0 * q[1]) / 3.0,
        (p[2] + 2.0 * q[1]) / 3.0,
        (p[2] + 2.0 * q[2]) / 3.0,
        (p[0] + 2.0 * q[2]) / 3.0,
        (q[0] + q[1] + q[2]) / 3.0,
    ]
}
