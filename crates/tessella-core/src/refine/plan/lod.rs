//! Level-of-detail functions: each coarse edge's level from that edge's data (docs/formulas.md,
//! "LOD functions"). Levels are computed once per unique edge, so both faces use the same one.

use super::canonical;
use super::levels::{Camera, Lod, Spacing, MAX_LOD_GRID_LEVEL};
use crate::basis::Basis;
use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::scheme::PatchNets;
use glam::DVec3;

fn bad(msg: String) -> RefineError {
    RefineError::BadLevels(msg)
}

fn finite3(p: [f32; 3]) -> bool {
    p.iter().all(|x| x.is_finite())
}

/// Checks a LOD function's parameters.
pub fn validate(lod: &Lod) -> Result<(), RefineError> {
    match lod {
        Lod::Tolerance { max_deviation } => {
            if !(max_deviation.is_finite() && *max_deviation > 0.0) {
                return Err(bad(format!(
                    "tolerance {max_deviation}: the largest deviation must be a finite distance above 0"
                )));
            }
        }
        Lod::Screen {
            pixels,
            camera,
            size,
        } => {
            if !(pixels.is_finite() && *pixels > 0.0) {
                return Err(bad(format!(
                    "screen:{pixels}: pixels per edge must be a finite number above 0"
                )));
            }
            validate_camera(camera)?;
            if size[0] == 0 || size[1] == 0 {
                return Err(bad(format!(
                    "image size {}x{}: both must be at least 1 pixel",
                    size[0], size[1]
                )));
            }
        }
        Lod::Distance {
            near,
            far,
            max,
            eye,
        } => {
            if !(near.is_finite() && far.is_finite() && *near >= 0.0 && far > near) {
                return Err(bad(format!(
                    "distance:{near},{far}: need 0 <= NEAR < FAR, both finite"
                )));
            }
            if !(max.is_finite() && *max >= 1.0) {
                return Err(bad(format!(
                    "distance level {max}: the largest level must be finite and at least 1"
                )));
            }
            if !finite3(*eye) {
                return Err(bad(format!("camera eye {eye:?} is not finite")));
            }
        }
    }
    Ok(())
}

/// Checks a camera: finite, eye ≠ target, field of view in `(0, 180)` degrees.
pub fn validate_camera(c: &Camera) -> Result<(), RefineError> {
    if !finite3(c.eye) || !finite3(c.target) {
        return Err(bad(format!(
            "camera {:?} -> {:?} is not finite",
            c.eye, c.target
        )));
    }
    if c.eye == c.target {
        return Err(bad("camera eye and target are the same point".into()));
    }
    if !(c.fov_y_deg.is_finite() && c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) {
        return Err(bad(format!(
            "field of view {} degrees: it must be above 0 and below 180",
            c.fov_y_deg
        )));
    }
    Ok(())
}

fn d3(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// The four canonical control points of unique edge `e` (on its owner face), in f64.
fn edge_curve(mesh: &Mesh, topology: &Topology, nets: &PatchNets, e: usize) -> [DVec3; 4] {
    let (f, k) = topology.edge_owner[e];
    let t = mesh.triangles()[f as usize];
    let fwd = canonical::forward(t, k as usize, &topology.position_ids);
    canonical::canonical_points(nets.basis, nets.patch_points(f as usize), k as usize, fwd).map(d3)
}

/// Largest second difference of a cubic Bézier's control polygon.
fn curve_second_difference(c: &[DVec3; 4]) -> f64 {
    (c[0] - 2.0 * c[1] + c[2])
        .length()
        .max((c[1] - 2.0 * c[2] + c[3]).length())
}

/// Segments so that a uniform chord of a cubic with second differences ≤ `m` stays within
/// `d`: the chord error is at most `h² max|C''| / 8 = 6 m / (8 n²)`.
fn edge_level_for(m: f64, d: f64) -> f64 {
    (0.75 * m / d).sqrt().ceil().max(1.0)
}

/// The face's interior level: the grid's small triangles stay within `d` when
/// `5 M / (3 N²) ≤ d`, `M` the net's largest second difference (cubic), or an estimate from
/// sampled second differences of the surface with a 1.5 safety factor (PNG1).
fn interior_level(nets: &PatchNets, f: usize, d: f64) -> f64 {
    let m = match nets.basis {
        Basis::Cubic => cubic_second_difference(nets.patch_points(f)),
        Basis::Png1 => 1.5 * sampled_second_difference(nets, f),
    };
    (5.0 * m / (3.0 * d)).sqrt().ceil().max(1.0)
}

/// Largest second difference of a cubic net along the three edge directions.
fn cubic_second_difference(points: &[[f32; 3]]) -> f64 {
    let order = crate::basis::CUBIC_ORDER;
    let at = |i: u8, j: u8, k: u8| -> DVec3 {
        let idx = order
            .iter()
            .position(|&e| e == [i, j, k])
            .expect("cubic index");
        d3(points[idx])
    };
    let mut m = 0.0f64;
    for (i, j, k) in [(1u8, 0u8, 0u8), (0, 1, 0), (0, 0, 1)] {
        // along P1 -> P2, P2 -> P3, P3 -> P1 from the quadratic sub-net (i, j, k)
        let a = at(i + 2, j, k) - 2.0 * at(i + 1, j + 1, k) + at(i, j + 2, k);
        let b = at(i, j + 2, k) - 2.0 * at(i, j + 1, k + 1) + at(i, j, k + 2);
        let c = at(i, j, k + 2) - 2.0 * at(i + 1, j, k + 1) + at(i + 2, j, k);
        m = m.max(a.length()).max(b.length()).max(c.length());
    }
    // Any direction's second derivative is at most 10/6 of the edge directions' bound.
    m * 10.0 / 6.0
}

/// PNG1: second differences of the surface sampled on a grid of 12 (as a net's second
/// difference, i.e. scaled by 1/6 of the derivative bound).
fn sampled_second_difference(nets: &PatchNets, f: usize) -> f64 {
    const S: usize = 12;
    let pts: Vec<DVec3> = nets.patch_points(f).iter().map(|&p| d3(p)).collect();
    let eval = |i: usize, j: usize| -> DVec3 {
        let l = [
            (S - i - j) as f64 / S as f64,
            i as f64 / S as f64,
            j as f64 / S as f64,
        ];
        let w = nets.basis.weights(l);
        w.value
            .iter()
            .zip(&pts)
            .fold(DVec3::ZERO, |acc, (&w, &p)| acc + w * p)
    };
    let mut m = 0.0f64;
    let h2 = 1.0 / (S * S) as f64;
    for j in 0..=S {
        for i in 0..=S - j {
            if i + j + 2 <= S {
                let a = eval(i, j) - 2.0 * eval(i + 1, j) + eval(i + 2, j);
                let b = eval(i, j) - 2.0 * eval(i, j + 1) + eval(i, j + 2);
                let c = eval(i + 2, j) - 2.0 * eval(i + 1, j + 1) + eval(i, j + 2);
                m = m.max(a.length()).max(b.length()).max(c.length());
            }
        }
    }
    // second derivative ≈ m / h²; a net's second difference is the derivative / 6
    m / h2 / 6.0 * 10.0 / 6.0
}

/// The smallest integer ≥ `x` of the spacing's parity (the tessellator's fractional spacings
/// are uniform at integers of their parity).
pub fn with_parity(spacing: Spacing, x: f64) -> f64 {
    let n = x.ceil().max(1.0);
    match spacing {
        Spacing::FractionalOdd if n % 2.0 == 0.0 => n + 1.0,
        Spacing::FractionalEven if n % 2.0 == 1.0 => n + 1.0,
        _ => n,
    }
}

/// Per-edge levels and per-face minimum inner levels of `lod` on `mesh`.
pub fn levels(
    mesh: &Mesh,
    topology: &Topology,
    nets: &PatchNets,
    lod: &Lod,
) -> Result<(Vec<f32>, Option<Vec<f32>>), RefineError> {
    validate(lod)?;
    let ne = topology.edges.len();
    let cap = |x: f64| x.min(MAX_LOD_GRID_LEVEL as f64) as f32;
    match lod {
        Lod::Tolerance { max_deviation } => {
            let d = *max_deviation as f64;
            let faces: Vec<f32> = (0..mesh.face_count())
                .map(|f| cap(interior_level(nets, f, d)))
                .collect();
            // An edge also takes the smaller interior level of the faces beside it: triangles
            // along it span its segments, so the edge curve alone does not bound them.
            let mut beside = vec![f32::INFINITY; ne];
            for (f, fe) in topology.face_edges.iter().enumerate() {
                for &e in fe {
                    beside[e as usize] = beside[e as usize].min(faces[f]);
                }
            }
            let edges = (0..ne)
                .map(|e| {
                    let c = edge_curve(mesh, topology, nets, e);
                    cap(edge_level_for(curve_second_difference(&c), d))
                        .max(beside[e].min(MAX_LOD_GRID_LEVEL))
                })
                .collect();
            Ok((edges, Some(faces)))
        }
        Lod::Screen {
            pixels,
            camera,
            size,
        } => {
            let eye = d3(camera.eye);
            let focal = size[1] as f64 / 2.0 / (camera.fov_y_deg as f64 / 2.0).to_radians().tan();
            let edges = (0..ne)
                .map(|e| {
                    let c = edge_curve(mesh, topology, nets, e);
                    let length =
                        (c[1] - c[0]).length() + (c[2] - c[1]).length() + (c[3] - c[2]).length();
                    let mid = (c[0] + 3.0 * c[1] + 3.0 * c[2] + c[3]) / 8.0;
                    let dist = (mid - eye).length().max(1e-9 * length.max(1e-30));
                    cap((length * focal / dist / *pixels as f64).max(1.0))
                })
                .collect();
            Ok((edges, None))
        }
        Lod::Distance {
            near,
            far,
            max,
            eye,
        } => {
            let eye = d3(*eye);
            let (near, far, max) = (*near as f64, *far as f64, *max as f64);
            let edges = (0..ne)
                .map(|e| {
                    let c = edge_curve(mesh, topology, nets, e);
                    let mid = (c[0] + 3.0 * c[1] + 3.0 * c[2] + c[3]) / 8.0;
                    let d = (mid - eye).length();
                    let s = ((d - near) / (far - near)).clamp(0.0, 1.0);
                    cap(max + (1.0 - max) * s)
                })
                .collect();
            Ok((edges, None))
        }
    }
}

fn numbers(what: &str, text: &str) -> Result<Vec<f32>, RefineError> {
    text.split(',')
        .map(|x| {
            x.trim()
                .parse::<f32>()
                .map_err(|_| bad(format!("{what}: {x:?} is not a number")))
        })
        .collect()
}

impl Camera {
    /// Parses `EX,EY,EZ,TX,TY,TZ,FOV_DEG` (eye, target, vertical field of view in degrees),
    /// as the CLI's `--camera` and Python's `camera=` take it, and validates it.
    ///
    /// ```
    /// use tessella_core::refine::Camera;
    /// let c: Camera = Camera::parse("0,0,5,0,0,0,45").unwrap();
    /// assert_eq!((c.eye, c.fov_y_deg), ([0.0, 0.0, 5.0], 45.0));
    /// assert!(Camera::parse("0,0,5,0,0,0,0").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Camera, RefineError> {
        let v = numbers("camera", text)?;
        if v.len() != 7 {
            return Err(bad(format!(
                "camera {text:?}: expected 7 numbers EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEG"
            )));
        }
        let c = Camera {
            eye: [v[0], v[1], v[2]],
            target: [v[3], v[4], v[5]],
            fov_y_deg: v[6],
        };
        validate_camera(&c)?;
        Ok(c)
    }
}

/// The text [`Camera::parse`] reads: `EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEG`.
impl std::fmt::Display for Camera {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [e, t] = [self.eye, self.target];
        write!(
            f,
            "{},{},{},{},{},{},{}",
            e[0], e[1], e[2], t[0], t[1], t[2], self.fov_y_deg
        )
    }
}

impl Lod {
    /// Parses a LOD function as the CLI's `--lod` and Python's `lod=` take it:
    /// `tolerance:D`, `screen:PX` (needs `camera` and `size`), `distance:NEAR,FAR,MAX` (needs
    /// `camera`, whose eye it uses), and validates it.
    ///
    /// ```
    /// use tessella_core::refine::{Camera, Lod};
    /// assert_eq!(Lod::parse("tolerance:0.01", None, None).unwrap(),
    ///            Lod::Tolerance { max_deviation: 0.01 });
    /// assert!(Lod::parse("tolerance:0", None, None).is_err());
    /// assert!(Lod::parse("screen:4", None, None).is_err()); // needs a camera
    /// ```
    pub fn parse(
        text: &str,
        camera: Option<Camera>,
        size: Option<[u32; 2]>,
    ) -> Result<Lod, RefineError> {
        let (kind, args) = text.split_once(':').ok_or_else(|| {
            bad(format!(
                "LOD {text:?}: expected tolerance:D, screen:PX or distance:NEAR,FAR,MAX"
            ))
        })?;
        let v = numbers(kind, args)?;
        let need_camera = || {
            camera.ok_or_else(|| {
                bad(format!(
                    "{kind}: needs a camera (--camera EX,EY,EZ,TX,TY,TZ,FOV_DEG)"
                ))
            })
        };
        let lod = match (kind, v.as_slice()) {
            ("tolerance", &[d]) => Lod::Tolerance { max_deviation: d },
            ("screen", &[pixels]) => Lod::Screen {
                pixels,
                camera: need_camera()?,
                size: size
                    .ok_or_else(|| bad("screen: needs the image size (--size WxH)".into()))?,
            },
            ("distance", &[near, far, max]) => Lod::Distance {
                near,
                far,
                max,
                eye: need_camera()?.eye,
            },
            _ => {
                return Err(bad(format!(
                    "LOD {text:?}: expected tolerance:D, screen:PX or distance:NEAR,FAR,MAX"
                )))
            }
        };
        validate(&lod)?;
        Ok(lod)
    }
}
