//! The refined output agrees with an independent f64 evaluation of the papers' formulas
//! (`reference/`), for flat, Phong and PN, at every level 1..=32, welded and soup; and the
//! reference itself agrees with hand arithmetic and with finite differences.

mod reference;

use glam::DVec3;
use reference::corpus::{closed_meshes, perturbed_sphere};
use reference::{
    angle, d3, diagonal, occurrences, undirected_edges, PnNet, RefNormals, RefPatch, RefScheme, Tri,
};
use tessella_core::{
    refine, Mesh, NormalMode, Pattern, RefineOptions, RefinedMesh, Refiner, Scheme,
};

/// Positions must agree to this fraction of the bounding box diagonal (f32 output: about 1e-7
/// relative rounding, times the few dozen terms of a cubic).
const POSITION_TOLERANCE: f64 = 1e-5;
/// Normals must agree to this angle in radians.
const NORMAL_TOLERANCE: f64 = 1e-4;

#[derive(Debug, Clone, Copy)]
struct Config {
    scheme: Scheme,
    normals: NormalMode,
    ref_scheme: RefScheme,
    ref_normals: RefNormals,
}

/// Checks that the pattern's points are exactly `((N-i-j)/N, i/N, j/N)` for every `i, j ≥ 0`,
/// `i + j ≤ N`, each once: the reference is evaluated at the pattern's points, so they must be
/// the points the issue specifies.
fn check_pattern_points(pattern: &Pattern) {
    let n = pattern.level;
    let nf = n as f64;
    let mut seen = vec![false; ((n + 1) * (n + 1)) as usize];
    assert_eq!(pattern.points.len() as u32, (n + 1) * (n + 2) / 2);
    for &l in &pattern.points {
        let i = (l[1] * nf).round() as u32;
        let j = (l[2] * nf).round() as u32;
        assert!(i + j <= n, "level {n}: point {l:?}");
        let expected = [(n - i - j) as f64 / nf, i as f64 / nf, j as f64 / nf];
        assert_eq!(l, expected, "level {n}: pattern point is not exact");
        let slot = &mut seen[(j * (n + 1) + i) as usize];
        assert!(!*slot, "level {n}: point {l:?} twice");
        *slot = true;
    }
}

/// Largest errors seen, for the log.
#[derive(Default, Debug)]
struct Worst {
    position: f64,
    normal: f64,
}

/// The options of one refinement of a sweep.
fn options(cfg: Config, level: u32, weld: bool) -> RefineOptions {
    RefineOptions::new(cfg.scheme, level)
        .with_normals(cfg.normals)
        .with_weld(weld)
}

/// The reference's (position, normal) at every pattern point of every face:
/// `[f * points + p]` is pattern point `p` on face `f`.
fn expected_values(mesh: &Mesh, cfg: Config, pattern: &Pattern) -> Vec<(DVec3, DVec3)> {
    (0..mesh.face_count())
        .flat_map(|f| {
            let patch = RefPatch::new(Tri::of(mesh, f), cfg.ref_scheme, cfg.ref_normals);
            pattern
                .points
                .iter()
                .map(move |&l| (patch.position(l), patch.normal(l)))
        })
        .collect()
}

/// Compares every vertex of `out` (`mesh` refined with `cfg` at `level`, welded or not), at
/// every (face, pattern point) it stands for, with the reference values `expected`
/// (see [`expected_values`]).
#[allow(clippy::too_many_arguments)]
fn compare_layout(
    name: &str,
    mesh: &Mesh,
    cfg: Config,
    level: u32,
    weld: bool,
    out: &RefinedMesh,
    expected: &[(DVec3, DVec3)],
    worst: &mut Worst,
) {
    let pattern = &Pattern::uniform(level);
    let tol = POSITION_TOLERANCE * diagonal(mesh);
    let what = format!("{name}, {cfg:?}, level {level}, weld {weld}");
    let (v, f, n) = (mesh.vertex_count(), mesh.face_count(), level as usize);
    let e = undirected_edges(mesh.triangles());
    let vertex_count = if weld {
        // V + E(N-1) + F(N-1)(N-2)/2
        v + e * (n - 1) + f * (n - 1) * n.saturating_sub(2) / 2
    } else {
        f * (n + 1) * (n + 2) / 2
    };
    assert_eq!(out.positions.len(), vertex_count, "{what}: vertex count");
    assert_eq!(out.normals.len(), vertex_count, "{what}: normal count");
    assert_eq!(out.triangles.len(), f * n * n, "{what}: triangle count");
    assert!(out.uvs.is_none(), "{what}: UVs appeared from nowhere");

    let np = pattern.points.len();
    // Real normals differ across a coarse edge (PN is only C0 there), and a welded vertex on a
    // shared edge or corner was evaluated on one face (its owner): it must match the reference
    // on *some* face containing it, so keep the best angle per vertex. Every other normal is
    // the same on every face containing the vertex, so each occurrence must match.
    let per_vertex_best = cfg.ref_normals == RefNormals::Real && weld;
    let mut best = vec![f64::INFINITY; vertex_count];
    let mut covered = vec![false; vertex_count];
    for occ in occurrences(out, f, pattern) {
        covered[occ.vertex] = true;
        let (p_ref, n_ref) = expected[occ.face * np + occ.point];
        let p = out.positions[occ.vertex];
        let err = (d3(p) - p_ref).length();
        worst.position = worst.position.max(err);
        assert!(
            err <= tol,
            "{what}: face {} point {:?}: position {p:?}, reference {p_ref}, error {err:e} > {tol:e}",
            occ.face,
            pattern.points[occ.point]
        );
        let a = angle(d3(out.normals[occ.vertex]), n_ref);
        if per_vertex_best {
            best[occ.vertex] = best[occ.vertex].min(a);
        } else {
            worst.normal = worst.normal.max(a);
            assert!(
                a <= NORMAL_TOLERANCE,
                "{what}: face {} point {:?}: normal {:?}, reference {n_ref}, angle {a:e}",
                occ.face,
                pattern.points[occ.point],
                out.normals[occ.vertex]
            );
        }
        // Coarse corners are the input positions, bit for bit.
        if let Some(c) = pattern.points[occ.point].iter().position(|&l| l == 1.0) {
            let input = mesh.triangles()[occ.face][c];
            let bits = |q: [f32; 3]| q.map(f32::to_bits);
            assert_eq!(
                bits(p),
                bits(mesh.positions()[input as usize]),
                "{what}: corner {c} of face {} is not the input position",
                occ.face
            );
            if weld {
                // Welded output keeps the input vertices first, in input order.
                assert_eq!(occ.vertex, input as usize, "{what}: corner vertex index");
            }
        }
    }
    if let Some(v) = covered.iter().position(|c| !c) {
        panic!("{what}: output vertex {v} is in no triangle, so it was never checked");
    }
    if per_vertex_best {
        for (vertex, &a) in best.iter().enumerate() {
            worst.normal = worst.normal.max(a);
            assert!(
                a <= NORMAL_TOLERANCE,
                "{what}: vertex {vertex}: real normal {:?} is {a:e} rad from the reference on \
                 every face containing it",
                out.normals[vertex]
            );
        }
    }
}

/// Every mesh of the corpus, every level 1..=32, welded and soup. (The workspace builds
/// tessella-core optimised in test builds, so the whole sweep takes seconds.)
fn sweep(cfg: Config) {
    for (name, mesh, _) in closed_meshes() {
        let levels: Vec<u32> = (1..=32).collect();
        sweep_mesh(name, &mesh, cfg, &levels);
    }
}

/// `mesh` with `cfg` at `levels`, welded and soup, against the reference.
fn sweep_mesh(name: &str, mesh: &Mesh, cfg: Config, levels: &[u32]) {
    let mut worst = Worst::default();
    for &level in levels {
        let pattern = Pattern::uniform(level);
        check_pattern_points(&pattern);
        let expected = expected_values(mesh, cfg, &pattern);
        for weld in [true, false] {
            let out = refine(mesh, &options(cfg, level, weld)).expect("refine");
            compare_layout(name, mesh, cfg, level, weld, &out, &expected, &mut worst);
        }
    }
    println!(
        "{:?} {:?} on {name}: worst position error {:.2e} (diagonal {:.2}), worst normal angle \
         {:.2e} rad",
        cfg.scheme,
        cfg.normals,
        worst.position,
        diagonal(mesh),
        worst.normal
    );
}

#[test]
fn flat_agrees_with_reference_at_levels_1_to_32() {
    sweep(Config {
        scheme: Scheme::Flat,
        normals: NormalMode::Linear,
        ref_scheme: RefScheme::Flat,
        ref_normals: RefNormals::Linear,
    });
}

#[test]
fn phong_default_alpha_agrees_with_reference_at_levels_1_to_32() {
    sweep(Config {
        scheme: Scheme::Phong { alpha: 0.75 },
        normals: NormalMode::Linear,
        ref_scheme: RefScheme::Phong { alpha: 0.75 },
        ref_normals: RefNormals::Linear,
    });
}

#[test]
fn phong_full_projection_agrees_with_reference_at_levels_1_to_32() {
    sweep(Config {
        scheme: Scheme::Phong { alpha: 1.0 },
        normals: NormalMode::Linear,
        ref_scheme: RefScheme::Phong { alpha: 1.0 },
        ref_normals: RefNormals::Linear,
    });
}

#[test]
fn pn_quadratic_normals_agree_with_reference_at_levels_1_to_32() {
    sweep(Config {
        scheme: Scheme::Pn,
        normals: NormalMode::Quadratic,
        ref_scheme: RefScheme::Pn,
        ref_normals: RefNormals::Quadratic,
    });
}

#[test]
fn pn_real_normals_agree_with_reference_at_levels_1_to_32() {
    sweep(Config {
        scheme: Scheme::Pn,
        normals: NormalMode::Real,
        ref_scheme: RefScheme::Pn,
        ref_normals: RefNormals::Real,
    });
}

#[test]
fn pn_is_the_default_normal_mode_quadratic() {
    // `RefineOptions::new` without normals must give PN's quadratic normals (the scheme table's
    // default), checked against the reference at one level.
    let mesh = perturbed_sphere(11);
    let level = 5;
    let out = refine(&mesh, &RefineOptions::new(Scheme::Pn, level)).unwrap();
    let pattern = Pattern::uniform(level);
    for occ in occurrences(&out, mesh.face_count(), &pattern) {
        let patch = RefPatch::new(
            Tri::of(&mesh, occ.face),
            RefScheme::Pn,
            RefNormals::Quadratic,
        );
        let l = pattern.points[occ.point];
        let a = angle(d3(out.normals[occ.vertex]), patch.normal(l));
        assert!(a <= NORMAL_TOLERANCE, "angle {a:e} at {l:?}");
    }
}

#[test]
fn other_scheme_and_normal_combinations_agree_with_reference() {
    // The options allow any normal mode with any scheme; the sweeps above cover each scheme's
    // usual pairing at every level, this covers the rest at a few levels.
    let combos = [
        (
            Scheme::Flat,
            NormalMode::Real,
            RefScheme::Flat,
            RefNormals::Real,
        ),
        (
            Scheme::Flat,
            NormalMode::Quadratic,
            RefScheme::Flat,
            RefNormals::Quadratic,
        ),
        (
            Scheme::PHONG,
            NormalMode::Real,
            RefScheme::Phong { alpha: 0.75 },
            RefNormals::Real,
        ),
        (
            Scheme::PHONG,
            NormalMode::Quadratic,
            RefScheme::Phong { alpha: 0.75 },
            RefNormals::Quadratic,
        ),
        (
            Scheme::Phong { alpha: 0.0 },
            NormalMode::Linear,
            RefScheme::Flat,
            RefNormals::Linear,
        ),
        (
            Scheme::Phong { alpha: 1.0 },
            NormalMode::Real,
            RefScheme::Phong { alpha: 1.0 },
            RefNormals::Real,
        ),
        (
            Scheme::Pn,
            NormalMode::Linear,
            RefScheme::Pn,
            RefNormals::Linear,
        ),
    ];
    let meshes = [
        ("tetrahedron", tessella_core::samples::tetrahedron()),
        ("perturbed sphere", perturbed_sphere(5)),
    ];
    for (scheme, normals, ref_scheme, ref_normals) in combos {
        let cfg = Config {
            scheme,
            normals,
            ref_scheme,
            ref_normals,
        };
        for (name, mesh) in &meshes {
            sweep_mesh(name, mesh, cfg, &[1, 2, 3, 5, 8]);
        }
    }
}

#[test]
fn reused_output_buffers_agree_with_reference() {
    // `refine_into` reuses the caller's buffers: after a larger or a different-layout output,
    // every slot of the next one must still be the reference's.
    let cfg = Config {
        scheme: Scheme::Pn,
        normals: NormalMode::Real,
        ref_scheme: RefScheme::Pn,
        ref_normals: RefNormals::Real,
    };
    let meshes = [
        ("perturbed sphere", perturbed_sphere(13)),
        ("tetrahedron", tessella_core::samples::tetrahedron()),
    ];
    let mut out = RefinedMesh::default();
    let mut worst = Worst::default();
    for (level, weld, m) in [
        (9, true, 0),
        (4, false, 0),
        (6, true, 1),
        (2, true, 0),
        (7, false, 1),
        (3, false, 0),
    ] {
        let (name, mesh) = &meshes[m];
        let refiner = Refiner::new(mesh, &options(cfg, level, weld)).unwrap();
        let total = std::sync::atomic::AtomicU64::new(0);
        refiner.refine_into(&mut out, &|done| {
            total.fetch_add(done, std::sync::atomic::Ordering::Relaxed);
        });
        assert_eq!(
            total.into_inner(),
            refiner.progress_total(),
            "progress adds up"
        );
        let expected = expected_values(mesh, cfg, &Pattern::uniform(level));
        compare_layout(name, mesh, cfg, level, weld, &out, &expected, &mut worst);
    }
}

// ---------------------------------------------------------------------------------------------
// The reference against hand arithmetic.
//
// Triangle P1 = (0,0,0), P2 = (1,0,0), P3 = (0,1,0); normals N1 = (0,0,1), N2 = (0.6,0,0.8),
// N3 = (0,0.6,0.8) (unit: 0.36 + 0.64 = 1).
//
// Edge points b_ij = (2 Pi + Pj - w_ij Ni) / 3, w_ij = (Pj - Pi) . Ni:
//   w12 = (1,0,0).(0,0,1)      = 0     b210 = (2P1 + P2)/3            = (1/3, 0, 0)
//   w21 = (-1,0,0).(0.6,0,0.8) = -0.6  b120 = (2P2 + P1 + 0.6 N2)/3   = (2.36/3, 0, 0.16)
//   w23 = (-1,1,0).(0.6,0,0.8) = -0.6  b021 = (2P2 + P3 + 0.6 N2)/3   = (2.36/3, 1/3, 0.16)
//   w32 = (1,-1,0).(0,0.6,0.8) = -0.6  b012 = (2P3 + P2 + 0.6 N3)/3   = (1/3, 2.36/3, 0.16)
//   w31 = (0,-1,0).(0,0.6,0.8) = -0.6  b102 = (2P3 + P1 + 0.6 N3)/3   = (0, 2.36/3, 0.16)
//   w13 = (0,1,0).(0,0,1)      = 0     b201 = (2P1 + P3)/3            = (0, 1/3, 0)
// Sum of the six = (6.72/3, 6.72/3, 0.64) = (2.24, 2.24, 0.64); E = (0.37333.., 0.37333.., 0.10666..)
// V = (1/3, 1/3, 0); b111 = E + (E - V)/2 = 1.5 E - 0.5 V = (0.56 - 1/6, 0.56 - 1/6, 0.16)
//   = (0.393333.., 0.393333.., 0.16).
//
// Centre l = (1/3, 1/3, 1/3): b = (1/27) [Σ corners + 3 Σ six edges + 6 b111]
//   = (1/27) [(1,1,0) + (6.72, 6.72, 1.92) + (2.36, 2.36, 0.96)] = (10.08, 10.08, 2.88) / 27
//   = (0.373333.., 0.373333.., 0.106666..).
// Midpoint of P1P2, l = (1/2, 1/2, 0): b = (b300 + 3 b210 + 3 b120 + b030) / 8
//   = ((0,0,0) + (1,0,0) + (2.36,0,0.48) + (1,0,0)) / 8 = (4.36, 0, 0.48)/8 = (0.545, 0, 0.06).
// Midpoint of P2P3, l = (0, 1/2, 1/2): b = (b030 + 3 b021 + 3 b012 + b003) / 8
//   = ((1,0,0) + (2.36,1,0.48) + (1,2.36,0.48) + (0,1,0)) / 8 = (0.545, 0.545, 0.12).
//
// Quadratic normal at the midpoint of P1P2: N1 + N2 = (0.6, 0, 1.8), v12 = 2 (1,0,0).(0.6,0,1.8)
// / 1 = 1.2, n110 = normalize((0.6,0,1.8) - 1.2 (1,0,0)) = (-0.6, 0, 1.8)/sqrt(3.6)
// = (-1, 0, 3)/sqrt(10). n(1/2,1/2,0) = (N1 + N2 + n110)/4 ∝ (0.6 - 1/sqrt(10), 0, 1.8 + 3/sqrt(10)).

fn hand_triangle() -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    (
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8]],
    )
}

const HAND_CENTRE: [f64; 3] = [10.08 / 27.0, 10.08 / 27.0, 2.88 / 27.0];
const HAND_MID_12: [f64; 3] = [0.545, 0.0, 0.06];
const HAND_MID_23: [f64; 3] = [0.545, 0.545, 0.12];

fn hand_normal_mid_12() -> DVec3 {
    let s = 10f64.sqrt();
    DVec3::new(0.6 - 1.0 / s, 0.0, 1.8 + 3.0 / s).normalize()
}

fn close(a: DVec3, b: [f64; 3], tol: f64) -> bool {
    (a - DVec3::from(b)).length() <= tol
}

#[test]
fn reference_pn_matches_hand_computed_control_points() {
    let (p, n) = hand_triangle();
    let tri = Tri {
        p: [0, 1, 2].map(|i| d3(p[i])),
        n: [0, 1, 2].map(|i| d3(n[i]).normalize()),
    };
    let net = PnNet::new(&tri);
    let third = 1.0 / 3.0;
    let expect = [
        ((2, 1, 0), [third, 0.0, 0.0]),
        ((1, 2, 0), [2.36 / 3.0, 0.0, 0.16]),
        ((0, 2, 1), [2.36 / 3.0, third, 0.16]),
        ((0, 1, 2), [third, 2.36 / 3.0, 0.16]),
        ((1, 0, 2), [0.0, 2.36 / 3.0, 0.16]),
        ((2, 0, 1), [0.0, third, 0.0]),
        ((1, 1, 1), [0.56 - 1.0 / 6.0, 0.56 - 1.0 / 6.0, 0.16]),
        ((3, 0, 0), [0.0, 0.0, 0.0]),
        ((0, 3, 0), [1.0, 0.0, 0.0]),
        ((0, 0, 3), [0.0, 1.0, 0.0]),
    ];
    // The inputs are f32 (0.6 and 0.8 are not exact), so allow f32 rounding.
    for ((i, j, k), b) in expect {
        assert!(
            close(net.b(i, j, k), b, 1e-7),
            "b{i}{j}{k} = {} != {b:?}",
            net.b(i, j, k)
        );
    }
    assert!(close(net.value([third; 3]), HAND_CENTRE, 1e-7));
    assert!(close(net.value([0.5, 0.5, 0.0]), HAND_MID_12, 1e-7));
    assert!(close(net.value([0.0, 0.5, 0.5]), HAND_MID_23, 1e-7));
    let patch = RefPatch::new(tri, RefScheme::Pn, RefNormals::Quadratic);
    assert!(angle(patch.normal([0.5, 0.5, 0.0]), hand_normal_mid_12()) < 1e-7);
}

#[test]
fn refined_pn_matches_hand_computed_points() {
    let (p, n) = hand_triangle();
    let mesh = Mesh::new(p, Some(n), None, vec![[0, 1, 2]]).unwrap();
    // Level 6 has both the centre (i = j = 2) and the edge midpoints (i = 3 or j = 3).
    let level = 6;
    let pattern = Pattern::uniform(level);
    for weld in [true, false] {
        let out = refine(
            &mesh,
            &RefineOptions::new(Scheme::Pn, level)
                .with_normals(NormalMode::Quadratic)
                .with_weld(weld),
        )
        .unwrap();
        let mut found = 0;
        for occ in occurrences(&out, 1, &pattern) {
            let l = pattern.points[occ.point];
            let at = |m: [f64; 3]| l.iter().zip(m).all(|(a, b)| (a - b).abs() < 1e-12);
            let got = d3(out.positions[occ.vertex]);
            let hand = if at([1.0 / 3.0; 3]) {
                HAND_CENTRE
            } else if at([0.5, 0.5, 0.0]) {
                let a = angle(d3(out.normals[occ.vertex]), hand_normal_mid_12());
                assert!(
                    a < 1e-5,
                    "quadratic normal at the P1P2 midpoint: {a:e} rad off"
                );
                HAND_MID_12
            } else if at([0.0, 0.5, 0.5]) {
                HAND_MID_23
            } else {
                continue;
            };
            found += 1;
            assert!(
                close(got, hand, 1e-6),
                "weld {weld}: at {l:?} got {got}, by hand {hand:?}"
            );
        }
        assert_eq!(
            found, 3,
            "the pattern must contain the three hand-computed points"
        );
    }
}

#[test]
fn reference_derivatives_match_central_differences() {
    // The hand-derived partials of the reference (used for real normals) against central
    // differences of its own positions, on random triangles of the perturbed sphere.
    let mesh = perturbed_sphere(3);
    let h = 1e-5;
    for f in (0..mesh.face_count()).step_by(7) {
        for scheme in [
            RefScheme::Flat,
            RefScheme::Phong { alpha: 0.75 },
            RefScheme::Pn,
        ] {
            let patch = RefPatch::new(Tri::of(&mesh, f), scheme, RefNormals::Real);
            for l in [
                [0.2, 0.3, 0.5],
                [1.0, 0.0, 0.0],
                [0.0, 0.6, 0.4],
                [0.1, 0.1, 0.8],
            ] {
                let shift = |du: f64, dv: f64| [l[0] - du - dv, l[1] + du, l[2] + dv];
                let fd_u =
                    (patch.position(shift(h, 0.0)) - patch.position(shift(-h, 0.0))) / (2.0 * h);
                let fd_v =
                    (patch.position(shift(0.0, h)) - patch.position(shift(0.0, -h))) / (2.0 * h);
                let (du, dv) = patch.du_dv(l);
                // Central differences of a cubic err by h² · (third derivative) / 6.
                assert!((du - fd_u).length() < 1e-8, "{scheme:?} Du at {l:?}");
                assert!((dv - fd_v).length() < 1e-8, "{scheme:?} Dv at {l:?}");
            }
        }
    }
}
