//! Quality of a refinement, measured on the patches themselves (f64 evaluation of the control
//! nets a backend would get):
//!
//! - **normal jump** across coarse edges (the G1 defect): along every edge shared by position,
//!   both adjacent patches' surface normals (`Du × Dv`) are compared at
//!   [`SAMPLES_PER_EDGE`] points; largest and mean angle. PNG1 is G1 (≈ 0 up to f32 rounding of
//!   its nets), PN is not.
//! - **watertightness**: the largest distance between the two sides' points along those edges
//!   (PN cracks at split normals, PN-AEN does not).
//! - **distance from the coarse mesh**: the largest distance between a refined point and the flat
//!   triangle's point at the same barycentric coordinates, over the pattern of the given level.
//!
//! ```
//! use tessella_core::{quality, samples, RefineOptions, Scheme};
//! let mesh = samples::icosphere(1);
//! let pn = quality::report(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
//! let png1 = quality::report(&mesh, &RefineOptions::new(Scheme::Png1, 4))?;
//! assert!(png1.normal_jump_max_deg < 0.01 && pn.normal_jump_max_deg > 0.5);
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

use crate::basis::Basis;
use crate::error::RefineError;
use crate::mesh::topology::NO_NEIGHBOR;
use crate::mesh::Mesh;
use crate::pattern::Pattern;
use crate::refine::RefineOptions;
use crate::scheme::{build_nets, NormalMode, PatchNets, Scheme};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use serde::Serialize;

/// Points compared along each coarse edge (evenly spaced, ends excluded).
pub const SAMPLES_PER_EDGE: usize = 9;

/// What [`report`] measured. Angles in degrees, lengths in model units and relative to the
/// bounding-box diagonal.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QualityReport {
    pub scheme: String,
    pub level: u32,
    /// Coarse edges with two faces (by position) that were compared.
    pub edges_checked: usize,
    pub samples_per_edge: usize,
    /// Largest angle between the two sides' surface normals across a coarse edge.
    pub normal_jump_max_deg: f64,
    /// Mean of that angle over all samples.
    pub normal_jump_mean_deg: f64,
    /// Largest distance between the two sides' points along a coarse edge.
    pub gap_max: f64,
    pub gap_max_relative: f64,
    /// Largest distance of a refined point from the flat triangle's point.
    pub distance_max: f64,
    pub distance_max_relative: f64,
    /// Bounding-box diagonal of the coarse mesh.
    pub diagonal: f64,
}

/// Evaluation weights (value, Du, Dv) of one basis at one point.
struct W {
    value: Vec<f64>,
    du: Vec<f64>,
    dv: Vec<f64>,
}

fn eval(nets: &PatchNets, f: usize, w: &W) -> (DVec3, DVec3) {
    let (mut p, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (k, c) in nets.patch_points(f).iter().enumerate() {
        let c = Vec3::from(*c).as_dvec3();
        p += w.value[k] * c;
        du += w.du[k] * c;
        dv += w.dv[k] * c;
    }
    (p, du.cross(dv))
}

fn weights(basis: Basis, l: [f64; 3]) -> W {
    let b = basis.weights(l);
    W {
        value: b.value,
        du: b.du,
        dv: b.dv,
    }
}

/// Measures `options.scheme` (with `options.tags`) on `mesh`; the level sets the pattern for the
/// distance from the coarse mesh.
pub fn report(mesh: &Mesh, options: &RefineOptions) -> Result<QualityReport, RefineError> {
    let level = match options.uniform_grid_level() {
        Some(0) => return Err(RefineError::LevelZero),
        Some(level) => level,
        None => {
            return Err(RefineError::BadLevels(
                "the quality report samples a whole, uniform grid level".into(),
            ))
        }
    };
    let scheme = options.scheme;
    let topo = mesh.topology();
    let nets = build_nets(
        mesh,
        Some(&topo),
        &scheme,
        NormalMode::Real,
        options.tags.as_deref(),
    )?;
    let basis = nets.basis;
    // Weights along the edge from corner a to corner b, for every ordered pair of corners.
    let ts: Vec<f64> = (1..=SAMPLES_PER_EDGE)
        .map(|i| i as f64 / (SAMPLES_PER_EDGE + 1) as f64)
        .collect();
    let along: Vec<Vec<W>> = (0..9)
        .map(|ab| {
            let (a, b) = (ab / 3, ab % 3);
            ts.iter()
                .map(|&t| {
                    let mut l = [0.0; 3];
                    if a != b {
                        l[a] = 1.0 - t;
                        l[b] = t;
                    }
                    weights(basis, l)
                })
                .collect()
        })
        .collect();
    let pid = |v: u32| topo.position_ids[v as usize];

    // Per face: (largest jump, sum of jumps, samples, largest gap, edges).
    let edge_stats = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let mut s = (0.0f64, 0.0f64, 0usize, 0.0f64, 0usize);
            let tf = mesh.triangles()[f];
            for k in 0..3 {
                let g = topo.neighbors[f][k];
                if g == NO_NEIGHBOR || (g as usize) < f {
                    continue;
                }
                let g = g as usize;
                let tg = mesh.triangles()[g];
                let find = |p: u32| (0..3).find(|&c| pid(tg[c]) == p);
                let (Some(ca), Some(cb)) = (find(pid(tf[k])), find(pid(tf[(k + 1) % 3]))) else {
                    continue;
                };
                s.4 += 1;
                let wf = &along[k * 3 + (k + 1) % 3];
                let wg = &along[ca * 3 + cb];
                for (a, b) in wf.iter().zip(wg) {
                    let (pf, nf) = eval(&nets, f, a);
                    let (pg, ng) = eval(&nets, g, b);
                    s.3 = s.3.max((pf - pg).length());
                    if nf == DVec3::ZERO || ng == DVec3::ZERO {
                        continue;
                    }
                    let angle = nf.cross(ng).length().atan2(nf.dot(ng));
                    s.0 = s.0.max(angle);
                    s.1 += angle;
                    s.2 += 1;
                }
            }
            s
        })
        .reduce(
            || (0.0, 0.0, 0, 0.0, 0),
            |x, y| (x.0.max(y.0), x.1 + y.1, x.2 + y.2, x.3.max(y.3), x.4 + y.4),
        );

    let pattern = Pattern::uniform(level);
    let table: Vec<(W, [f64; 3])> = pattern
        .points
        .iter()
        .map(|&l| (weights(basis, l), l))
        .collect();
    let distance = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let c = mesh.corner_positions(f).map(|v| v.as_dvec3());
            table
                .iter()
                .map(|(w, l)| {
                    let flat = l[0] * c[0] + l[1] * c[1] + l[2] * c[2];
                    (eval(&nets, f, w).0 - flat).length()
                })
                .fold(0.0, f64::max)
        })
        .reduce(|| 0.0, f64::max);

    let diagonal = mesh.diagonal() as f64;
    let rel = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
    Ok(QualityReport {
        scheme: scheme.name().to_string(),
        level,
        edges_checked: edge_stats.4,
        samples_per_edge: SAMPLES_PER_EDGE,
        normal_jump_max_deg: edge_stats.0.to_degrees(),
        normal_jump_mean_deg: if edge_stats.2 > 0 {
            (edge_stats.1 / edge_stats.2 as f64).to_degrees()
        } else {
            0.0
        },
        gap_max: edge_stats.3,
        gap_max_relative: rel(edge_stats.3),
        distance_max: distance,
        distance_max_relative: rel(distance),
        diagonal,
    })
}

/// [`report`] for each of `schemes` with the rest of `options`: the comparison table the CLI
/// prints.
pub fn compare(
    mesh: &Mesh,
    options: &RefineOptions,
    schemes: &[Scheme],
) -> Result<Vec<QualityReport>, RefineError> {
    schemes
        .iter()
        .map(|&scheme| {
            let mut o = options.clone();
            o.scheme = scheme;
            report(mesh, &o)
        })
        .collect()
}
