//! The regression suite, after OpenSubdiv's: one check, [`check_backend`], run for every
//! backend that implements `tessella_core::refine::Evaluator` (CPU, GPU compute, GL) over the
//! shared mesh corpus, against the independent f64 reference of `tessella-core/tests/reference`
//! (one copy, included by path).
//!
//! For every mesh, scheme (flat, Phong at two shape factors, PN), normal mode (linear,
//! quadratic, real) and pattern (grid levels, hardware spacings), every vertex a backend
//! outputs is compared, at its coarse face and barycentric point, with the reference's
//! position and unit normal there, within the backend's [`Tolerance`]; and the vertices must
//! cover every point of the plan's pattern on every face. Displacement is checked the same
//! way against the reference displaced in f64. A backend that cannot run a case must refuse
//! it with an error: the suite checks the refusal.

#[path = "../../../tessella-core/tests/reference/mod.rs"]
mod reference;

mod backends;

use backends::{Backend, Cpu, Gl, Gpu, Sample};
use glam::DVec3;
use reference::corpus::{closed_meshes, planar_grid};
use reference::{d3, diagonal, RefNormals, RefPatch, RefScheme, Tri};
use std::collections::HashSet;
use tessella_core::displace::{perlin, permutation, DisplaceFrame, Displacement};
use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::{Mesh, NormalMode, RefineOptions, Scheme};

/// The corpus: the reference's closed meshes and an open planar grid (boundary edges).
fn corpus() -> Vec<(&'static str, Mesh)> {
    let mut meshes: Vec<(&'static str, Mesh)> = closed_meshes()
        .into_iter()
        .map(|(name, mesh, _)| (name, mesh))
        .collect();
    meshes.push(("planar grid", planar_grid(4, 3, 11)));
    meshes
}

const SCHEMES: [(Scheme, RefScheme); 4] = [
    (Scheme::Flat, RefScheme::Flat),
    (
        Scheme::Phong { alpha: 0.75 },
        RefScheme::Phong { alpha: 0.75 },
    ),
    (
        Scheme::Phong { alpha: 1.0 },
        RefScheme::Phong { alpha: 1.0 },
    ),
    (Scheme::Pn, RefScheme::Pn),
];

const NORMALS: [(NormalMode, RefNormals); 3] = [
    (NormalMode::Linear, RefNormals::Linear),
    (NormalMode::Quadratic, RefNormals::Quadratic),
    (NormalMode::Real, RefNormals::Real),
];

/// The patterns: grid levels, and the hardware tessellator's spacings (integer and fractional),
/// soup and welded.
fn patterns() -> Vec<(String, RefineOptions)> {
    let mut out: Vec<(String, RefineOptions)> = [(1, false), (3, false), (8, false), (3, true)]
        .into_iter()
        .map(|(n, weld)| {
            let name = format!("grid {n}{}", if weld { " welded" } else { "" });
            (name, RefineOptions::new(Scheme::Flat, n).with_weld(weld))
        })
        .collect();
    for (spacing, level, weld) in [
        (Spacing::Equal, 2.0, false),
        (Spacing::Equal, 5.0, false),
        (Spacing::FractionalOdd, 3.5, false),
        (Spacing::FractionalOdd, 3.5, true),
    ] {
        out.push((
            format!("{spacing} {level}{}", if weld { " welded" } else { "" }),
            RefineOptions::new(Scheme::Flat, 1)
                .with_spacing(spacing)
                .with_levels(Levels::Uniform(level))
                .with_weld(weld),
        ));
    }
    out
}

/// A vertex's place: face and barycentric point (tessellator coordinates are multiples of
/// 2^-16; pattern points are rounded the same way).
fn key(face: u32, l: [f32; 3]) -> (u32, [i64; 3]) {
    (face, l.map(|x| (x as f64 * 65536.0).round() as i64))
}

/// What the backend must have made at one sample: the reference's position and unit normal.
type Expected<'a> = dyn Fn(&RefPatch, [f64; 3]) -> (DVec3, DVec3) + 'a;

/// Largest errors seen.
#[derive(Debug, Default, Clone, Copy)]
struct Worst {
    position: f64,
    normal: f64,
    samples: usize,
}

/// The one check: `samples` (a backend's refinement of `plan` on `mesh`) against `expected`
/// at each sample's face and point, within `backend`'s tolerance; every sample is a point of
/// the plan's pattern on its face, and the samples cover the plan's vertices: every
/// (face, point) `Plan::origin` names (each pattern point of each face in a soup; one owning
/// face per vertex when welded, so a welded vertex is checked on the face that made it).
fn check_samples(
    backend: &dyn Backend,
    mesh: &Mesh,
    plan: &Plan,
    (scheme, normals): (RefScheme, RefNormals),
    samples: &[Sample],
    expected: &Expected<'_>,
    what: &str,
) -> Worst {
    let tol = backend.tolerance();
    let diag = diagonal(mesh);
    let patches: Vec<RefPatch> = (0..mesh.face_count())
        .map(|f| RefPatch::new(Tri::of(mesh, f), scheme, normals))
        .collect();
    let keys = |plan: &Plan| -> HashSet<_> {
        let (faces, bary) = plan.origin();
        faces.iter().zip(&bary).map(|(&f, &l)| key(f, l)).collect()
    };
    let origins = keys(plan);
    let pattern = if plan.layout().weld {
        let soup = plan.options().clone().with_weld(false);
        keys(&Plan::new(mesh, &soup).unwrap_or_else(|e| panic!("{what}: {e}")))
    } else {
        origins.clone()
    };
    let mut seen = HashSet::with_capacity(pattern.len());
    let mut worst = Worst {
        samples: samples.len(),
        ..Worst::default()
    };
    for (i, s) in samples.iter().enumerate() {
        let k = key(s.face, s.l);
        assert!(
            pattern.contains(&k),
            "{what}: vertex {i} at face {}, l = {:?} is no point of the plan's pattern",
            s.face,
            s.l
        );
        seen.insert(k);
        let (p, n) = expected(&patches[s.face as usize], s.l.map(f64::from));
        let dp = (d3(s.position) - p).length() / diag;
        let dn = (d3(s.normal) - n).length();
        assert!(
            dp <= tol.position,
            "{what}: vertex {i} (face {}, l = {:?}) at {:?}, reference {p}: {dp:e} diagonals \
             apart, tolerance {:e}",
            s.face,
            s.l,
            s.position,
            tol.position
        );
        assert!(
            dn <= tol.normal,
            "{what}: vertex {i} (face {}, l = {:?}) normal {:?}, reference {n}: |d| = {dn:e}, \
             tolerance {:e}",
            s.face,
            s.l,
            s.normal,
            tol.normal
        );
        worst.position = worst.position.max(dp);
        worst.normal = worst.normal.max(dn);
    }
    let missing = origins.difference(&seen).count();
    assert_eq!(
        missing,
        0,
        "{what}: {missing} of the plan's {} vertices' (face, point) places are not in the output",
        origins.len()
    );
    worst
}

/// The reference, undisplaced.
fn plain(patch: &RefPatch, l: [f64; 3]) -> (DVec3, DVec3) {
    (patch.position(l), patch.normal(l))
}

/// Runs the whole corpus on `backend`: every case it runs is checked against the reference,
/// every case it does not is checked to be refused.
fn check_backend(backend: &mut dyn Backend) {
    let start = std::time::Instant::now();
    let (mut worst, mut cases, mut refused) = (Worst::default(), 0, 0);
    for (name, mesh) in corpus() {
        for (scheme, ref_scheme) in SCHEMES {
            for (normals, ref_normals) in NORMALS {
                for (pattern, base) in patterns() {
                    let mut options = base.with_normals(normals);
                    options.scheme = scheme;
                    let what = format!(
                        "{}: {name}, {scheme:?}, {normals:?} normals, {pattern}",
                        backend.name()
                    );
                    let plan = Plan::new(&mesh, &options).unwrap_or_else(|e| panic!("{what}: {e}"));
                    let frame = plan.frame(&mesh).unwrap_or_else(|e| panic!("{what}: {e}"));
                    let result = backend.refine(&plan, &frame, &Displacement::None);
                    if !backend.runs(&options) {
                        assert!(result.is_err(), "{what}: ran a case it documents it cannot");
                        refused += 1;
                        continue;
                    }
                    let samples = result.unwrap_or_else(|e| panic!("{what}: {e}"));
                    let w = check_samples(
                        backend,
                        &mesh,
                        &plan,
                        (ref_scheme, ref_normals),
                        &samples,
                        &plain,
                        &what,
                    );
                    worst.position = worst.position.max(w.position);
                    worst.normal = worst.normal.max(w.normal);
                    worst.samples += w.samples;
                    cases += 1;
                }
            }
        }
    }
    assert!(cases > 0, "{}: no case ran", backend.name());
    eprintln!(
        "{}: {cases} cases ({} vertices) within tolerance, {refused} refused as documented; \
         worst position {:.2e} diagonals, worst normal {:.2e}; {:.1} s",
        backend.name(),
        worst.samples,
        worst.position,
        worst.normal,
        start.elapsed().as_secs_f64()
    );
}

/// The displacements every displacing backend must apply alike.
fn displacements() -> [Displacement; 2] {
    [
        Displacement::Sine {
            amplitude: 0.05,
            frequency: 12.0,
        },
        Displacement::Perlin {
            amplitude: 0.08,
            frequency: 3.0,
            seed: 42,
        },
    ]
}

/// The reference displaced by `d`: each point moves along its unit normal (the corpus has no
/// split normals, so no vertex takes a shared direction) by the displacement's offset at the
/// reference point: `a sin(f |p|)` in f64 for the sine; for Perlin noise `a noise(f p)` with
/// the core's noise function (its definition: a permutation table and fades) at the point
/// rounded to f32. Normals are kept.
fn displaced(d: &Displacement) -> impl Fn(&RefPatch, [f64; 3]) -> (DVec3, DVec3) + '_ {
    let perm = match d {
        Displacement::Perlin { seed, .. } => permutation(*seed),
        _ => [0; 512],
    };
    move |patch, l| {
        let (p, n) = plain(patch, l);
        let offset = match *d {
            Displacement::Sine {
                amplitude,
                frequency,
            } => amplitude as f64 * (frequency as f64 * p.length()).sin(),
            Displacement::Perlin {
                amplitude,
                frequency,
                ..
            } => {
                let q = [p.x, p.y, p.z].map(|c| frequency * c as f32);
                amplitude as f64 * perlin(&perm, q) as f64
            }
            _ => panic!("no reference for {d:?}"),
        };
        (p + offset * n, n)
    }
}

/// Displacement means the same on every backend: each backend that displaces matches the
/// reference displaced in f64; one that does not refuses a displaced request.
fn check_displacement(backend: &mut dyn Backend) {
    let start = std::time::Instant::now();
    let (mut worst, mut cases, mut refused) = (Worst::default(), 0, 0);
    let patterns = [
        ("grid 6", RefineOptions::new(Scheme::Pn, 6)),
        (
            "equal 4",
            RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(Spacing::Equal)
                .with_levels(Levels::Uniform(4.0)),
        ),
    ];
    for (name, mesh) in corpus() {
        for (scheme, ref_scheme) in [SCHEMES[1], SCHEMES[3]] {
            for (normals, ref_normals) in [NORMALS[1], NORMALS[2]] {
                for (pattern, base) in &patterns {
                    for d in displacements() {
                        let mut options = base.clone().with_weld(false).with_normals(normals);
                        options.scheme = scheme;
                        let what = format!(
                            "{}: {name}, {scheme:?}, {normals:?} normals, {pattern}, {d:?}",
                            backend.name()
                        );
                        let plan =
                            Plan::new(&mesh, &options).unwrap_or_else(|e| panic!("{what}: {e}"));
                        let frame = plan.frame(&mesh).unwrap_or_else(|e| panic!("{what}: {e}"));
                        let frames = DisplaceFrame::new(&mesh, plan.topology(), plan.layout());
                        assert!(
                            !frames.has_splits(),
                            "{what}: the reference assumes no splits"
                        );
                        if !backend.runs(&options) {
                            continue;
                        }
                        let result = backend.refine(&plan, &frame, &d);
                        if !backend.displaces(&options) {
                            let err = result.err().unwrap_or_else(|| {
                                panic!("{what}: displaced, which it documents it cannot")
                            });
                            assert!(err.contains("displac"), "{what}: {err}");
                            refused += 1;
                            continue;
                        }
                        let samples = result.unwrap_or_else(|e| panic!("{what}: {e}"));
                        let expected = displaced(&d);
                        let w = check_samples(
                            backend,
                            &mesh,
                            &plan,
                            (ref_scheme, ref_normals),
                            &samples,
                            &expected,
                            &what,
                        );
                        // The displacement moved the surface (the check is not of a no-op).
                        let moved = samples.iter().any(|s| {
                            let p = plain(
                                &RefPatch::new(
                                    Tri::of(&mesh, s.face as usize),
                                    ref_scheme,
                                    ref_normals,
                                ),
                                s.l.map(f64::from),
                            )
                            .0;
                            (d3(s.position) - p).length() > 1e-3
                        });
                        assert!(moved, "{what}: nothing moved");
                        worst.position = worst.position.max(w.position);
                        worst.normal = worst.normal.max(w.normal);
                        cases += 1;
                    }
                }
            }
        }
    }
    assert!(
        cases + refused > 0,
        "{}: no displacement case",
        backend.name()
    );
    eprintln!(
        "{} displaced: {cases} cases within tolerance, {refused} refused as documented; worst \
         position {:.2e} diagonals; {:.1} s",
        backend.name(),
        worst.position,
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn cpu_evaluator_agrees_with_the_f64_reference() {
    check_backend(&mut Cpu);
}

#[test]
fn gpu_compute_evaluator_agrees_with_the_f64_reference() {
    check_backend(&mut Gpu);
}

#[test]
fn gl_evaluator_agrees_with_the_f64_reference() {
    check_backend(&mut Gl::new());
}

#[test]
fn cpu_displacement_agrees_with_the_f64_reference() {
    check_displacement(&mut Cpu);
}

#[test]
fn gpu_compute_displacement_agrees_with_the_f64_reference() {
    check_displacement(&mut Gpu);
}

#[test]
fn gl_refuses_displacement() {
    check_displacement(&mut Gl::new());
}

/// The check is not vacuous: the CPU's PN output checked as if it were Phong's fails it.
#[test]
#[should_panic(expected = "diagonals apart")]
fn the_check_fails_a_backend_that_evaluates_another_surface() {
    let mesh = reference::corpus::perturbed_sphere(7);
    let options = RefineOptions::new(Scheme::Pn, 4).with_weld(false);
    let plan = Plan::new(&mesh, &options).expect("valid options");
    let frame = plan.frame(&mesh).expect("a frame of the plan's mesh");
    let samples = Cpu
        .refine(&plan, &frame, &Displacement::None)
        .expect("the CPU refines");
    let phong = RefScheme::Phong { alpha: 0.75 };
    check_samples(
        &Cpu,
        &mesh,
        &plan,
        (phong, RefNormals::Quadratic),
        &samples,
        &plain,
        "PN as Phong",
    );
}
