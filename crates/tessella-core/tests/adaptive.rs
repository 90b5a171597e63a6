//! Adaptive refinement: per-face patterns from per-edge levels (grid and tessellator spacings),
//! LOD functions, origins, bad levels. Facts checked against independent references: exact
//! counts from the tessellator and the grid formula, closed-manifold topology of welded output,
//! the f64 reference surface of tests/reference, bit equality between layouts.

mod reference;

use glam::DVec3;
use reference::corpus::Lcg;
use reference::{closed_manifold, d3, RefNormals, RefPatch, RefScheme, Tri};
use std::sync::Arc;
use tessella_core::refine::grid_pattern;
use tessella_core::refine::{Camera, Levels, Lod, Plan, Spacing};
use tessella_core::tessellator::{tessellate, TessLevels};
use tessella_core::Named;
use tessella_core::{refine, samples, Mesh, RefineError, RefineOptions, RefinedMesh, Scheme};

fn run(mesh: &Mesh, o: &RefineOptions) -> (Plan, RefinedMesh) {
    let plan = Plan::new(mesh, o).unwrap();
    let frame = plan.frame(mesh).unwrap();
    let mut out = RefinedMesh::default();
    plan.refine_into(&frame, &mut out, &|_| {}).unwrap();
    (plan, out)
}

fn random_levels(mesh: &Mesh, seed: u64, lo: f64, hi: f64) -> Levels {
    let mut rng = Lcg::new(seed);
    let edges: Vec<f32> = (0..mesh.topology().edges.len())
        .map(|_| rng.range(lo, hi) as f32)
        .collect();
    Levels::PerEdge {
        edges: Arc::from(edges),
        faces: None,
    }
}

const TESS: [Spacing; 3] = [
    Spacing::Equal,
    Spacing::FractionalOdd,
    Spacing::FractionalEven,
];

#[test]
fn uniform_tessellator_levels_give_the_tessellators_pattern_on_every_face() {
    let mesh = samples::icosphere(1);
    for spacing in TESS {
        for level in [1.0f32, 2.0, 3.5, 5.0, 7.25, 64.0, 100.0] {
            let o = RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(Levels::Uniform(level));
            let (plan, out) = run(&mesh, &o);
            let p = tessellate(spacing.tessellator().unwrap(), TessLevels::uniform(level));
            assert_eq!(
                out.triangles.len(),
                80 * p.triangles.len(),
                "{spacing} {level}"
            );
            let m = closed_manifold(out.positions.len(), &out.triangles)
                .unwrap_or_else(|e| panic!("{spacing} {level}: {e}"));
            assert_eq!(m.euler, 2);
            assert_eq!(plan.triangle_count(), out.triangles.len());
        }
    }
}

#[test]
fn integer_uniform_grid_levels_take_the_classic_path_bit_for_bit() {
    let mesh = samples::creature();
    let classic = refine(&mesh, &RefineOptions::new(Scheme::Png1, 6)).unwrap();
    let o = RefineOptions::new(Scheme::Png1, 2).with_levels(Levels::Uniform(6.0));
    assert_eq!(refine(&mesh, &o).unwrap(), classic);
}

#[test]
fn per_edge_levels_welded_output_is_closed_and_equals_soup_bit_for_bit() {
    let meshes = [
        ("icosphere(1)", samples::icosphere(1), 2),
        ("creature", samples::creature(), 2),
        ("torus", samples::torus(1.0, 0.4, 10, 6), 0),
    ];
    for (name, mesh, euler) in &meshes {
        for (i, spacing) in Spacing::ALL.iter().copied().enumerate() {
            for scheme in [Scheme::Pn, Scheme::Png1, Scheme::PHONG] {
                let levels = random_levels(mesh, 11 + i as u64, 0.6, 9.0);
                let o = RefineOptions::new(scheme, 1)
                    .with_spacing(spacing)
                    .with_levels(levels);
                let (_, welded) = run(mesh, &o);
                let (_, soup) = run(mesh, &o.clone().with_weld(false));
                let what = format!("{name} {spacing} {scheme:?}");
                let m = closed_manifold(welded.positions.len(), &welded.triangles)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(m.euler, *euler, "{what}");
                assert_eq!(welded.triangles.len(), soup.triangles.len(), "{what}");
                for (tw, ts) in welded.triangles.iter().zip(&soup.triangles) {
                    for c in 0..3 {
                        assert_eq!(
                            welded.positions[tw[c] as usize].map(f32::to_bits),
                            soup.positions[ts[c] as usize].map(f32::to_bits),
                            "{what}"
                        );
                    }
                }
            }
        }
    }
}

/// Signed area in the (l2, l3) plane.
fn area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]))
}

#[test]
fn grid_patterns_with_edge_levels_keep_orientation_and_tile_the_triangle() {
    for n0 in 1..=6 {
        for n1 in 1..=6 {
            for n2 in 1..=6 {
                for extra in [0, 1, 3] {
                    let inner = n0.max(n1).max(n2) + extra;
                    let p = grid_pattern([n0, n1, n2], inner);
                    let mut total = 0.0;
                    for t in &p.triangles {
                        let s = area(
                            p.points[t[0] as usize],
                            p.points[t[1] as usize],
                            p.points[t[2] as usize],
                        );
                        assert!(s > 0.0, "{n0},{n1},{n2} inner {inner}: {t:?} area {s}");
                        total += s;
                    }
                    assert!((total - 0.5).abs() < 1e-12, "{n0},{n1},{n2}: {total}");
                    // Each edge carries exactly its own n_k + 1 points.
                    for (k, &n) in [n0, n1, n2].iter().enumerate() {
                        let o = (k + 2) % 3;
                        let on = p.points.iter().filter(|l| l[o] == 0.0).count() as u32;
                        assert_eq!(on, n + 1, "edge {k}");
                    }
                    // Every edge of the pattern is used twice (inside) or once (boundary).
                    let mut half: Vec<(u32, u32)> = p
                        .triangles
                        .iter()
                        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
                        .collect();
                    half.sort_unstable();
                    assert!(half.windows(2).all(|w| w[0] != w[1]));
                }
            }
        }
    }
}

#[test]
fn refined_vertices_lie_on_the_reference_surface_at_their_origin() {
    let mesh = reference::corpus::perturbed_sphere(3);
    let diag = reference::diagonal(&mesh);
    for &spacing in Spacing::ALL {
        for weld in [true, false] {
            let mut levels = random_levels(&mesh, 5, 1.0, 8.0);
            if spacing == Spacing::Grid {
                // Fractional grid levels geomorph: their new points lie between the surface and
                // the coarser level's flat triangles by design (tests/morph.rs). Integer ones
                // lie on the surface.
                if let Levels::PerEdge { edges, .. } = &mut levels {
                    *edges = edges.iter().map(|x| x.ceil()).collect();
                }
            }
            let o = RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(levels)
                .with_weld(weld);
            let (plan, out) = run(&mesh, &o);
            let (faces, bary) = plan.origin();
            assert_eq!(faces.len(), out.positions.len());
            for (v, (&f, l)) in faces.iter().zip(&bary).enumerate() {
                let patch = RefPatch::new(
                    Tri::of(&mesh, f as usize),
                    RefScheme::Pn,
                    RefNormals::Quadratic,
                );
                let s = patch.position(l.map(|x| x as f64));
                let d = (s - d3(out.positions[v])).length();
                assert!(d < 1e-5 * diag, "{spacing} weld {weld} vertex {v}: {d}");
            }
        }
    }
}

/// Largest distance between the flat refined triangles (sampled, 6 per side) and the f64 PN
/// surface at the same parameters (an upper bound of the distance to the surface).
fn max_deviation(mesh: &Mesh, plan: &Plan, out: &RefinedMesh) -> f64 {
    let (faces, bary) = plan.origin();
    let patches: Vec<RefPatch> = (0..mesh.face_count())
        .map(|f| RefPatch::new(Tri::of(mesh, f), RefScheme::Pn, RefNormals::Quadratic))
        .collect();
    let mut worst = 0.0f64;
    const S: usize = 6;
    for t in &out.triangles {
        let f = faces[t[0] as usize] as usize;
        // soup: the three vertices have the same origin face
        let l = t.map(|v| bary[v as usize].map(|x| x as f64));
        let p = t.map(|v| d3(out.positions[v as usize]));
        for i in 0..=S {
            for j in 0..=S - i {
                let m = [
                    (S - i - j) as f64 / S as f64,
                    i as f64 / S as f64,
                    j as f64 / S as f64,
                ];
                let flat: DVec3 = m[0] * p[0] + m[1] * p[1] + m[2] * p[2];
                let lm = [0, 1, 2].map(|c| m[0] * l[0][c] + m[1] * l[1][c] + m[2] * l[2][c]);
                worst = worst.max((patches[f].position(lm) - flat).length());
            }
        }
    }
    worst
}

#[test]
fn tolerance_lod_keeps_the_flat_triangles_within_the_deviation() {
    let meshes = [
        ("creature", samples::creature()),
        ("perturbed sphere", reference::corpus::perturbed_sphere(9)),
        ("icosphere(1)", samples::icosphere(1)),
    ];
    for (name, mesh) in &meshes {
        let diag = reference::diagonal(mesh);
        for rel in [1e-2, 2e-3] {
            let d = (rel * diag) as f32;
            for spacing in [Spacing::Grid, Spacing::FractionalOdd, Spacing::Equal] {
                let o = RefineOptions::new(Scheme::Pn, 1)
                    .with_spacing(spacing)
                    .with_weld(false)
                    .with_levels(Levels::Lod(Lod::Tolerance { max_deviation: d }));
                let (plan, out) = run(mesh, &o);
                let dev = max_deviation(mesh, &plan, &out);
                assert!(dev <= d as f64, "{name} {spacing} D {d}: deviation {dev}");
                if spacing != Spacing::Grid {
                    continue;
                }
                // An upper bound, not wildly conservative: a third of the levels exceed D.
                let tiling = plan.tiling().unwrap();
                let half: Vec<f32> = tiling
                    .edge_levels
                    .iter()
                    .map(|&x| (x / 3.0).max(1.0))
                    .collect();
                let lower = o
                    .clone()
                    .with_spacing(Spacing::Grid)
                    .with_levels(Levels::PerEdge {
                        edges: Arc::from(half),
                        faces: None,
                    });
                let (plan2, out2) = run(mesh, &lower);
                let dev2 = max_deviation(mesh, &plan2, &out2);
                assert!(
                    dev2 > d as f64,
                    "{name} {spacing} D {d}: half levels {dev2}"
                );
            }
        }
    }
}

#[test]
fn view_lods_give_more_segments_near_the_camera() {
    let mesh = samples::icosphere(2);
    let camera = Camera {
        eye: [0.0, 0.0, 3.0],
        target: [0.0; 3],
        fov_y_deg: 45.0,
    };
    for lod in [
        Lod::Screen {
            pixels: 8.0,
            camera,
            size: [800, 600],
        },
        Lod::Distance {
            near: 2.0,
            far: 4.0,
            max: 16.0,
            eye: camera.eye,
        },
    ] {
        let o = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalEven)
            .with_levels(Levels::Lod(lod.clone()));
        let plan = Plan::new(&mesh, &o).unwrap();
        let t = plan.topology();
        let levels = &plan.tiling().unwrap().edge_levels;
        let z = |e: usize| {
            let [a, b] = t.edges[e];
            mesh.positions()[a as usize][2] + mesh.positions()[b as usize][2]
        };
        let near = (0..t.edges.len())
            .max_by(|&a, &b| z(a).total_cmp(&z(b)))
            .unwrap();
        let far = (0..t.edges.len())
            .min_by(|&a, &b| z(a).total_cmp(&z(b)))
            .unwrap();
        assert!(
            levels[near] > levels[far],
            "{lod:?}: {} vs {}",
            levels[near],
            levels[far]
        );
        // A camera inside the mesh works too (distance-based, no division by a depth).
        let inside = match lod {
            Lod::Screen { pixels, size, .. } => Lod::Screen {
                pixels,
                size,
                camera: Camera {
                    eye: [0.0; 3],
                    target: [0.0, 0.0, -1.0],
                    fov_y_deg: 60.0,
                },
            },
            other => other,
        };
        assert!(Plan::new(&mesh, &o.clone().with_levels(Levels::Lod(inside))).is_ok());
    }
}

#[test]
fn bad_levels_are_refused_or_clamped_never_a_panic() {
    let mesh = samples::icosphere(1);
    let ne = mesh.topology().edges.len();
    let bad = |o: RefineOptions| match Plan::new(&mesh, &o) {
        Err(RefineError::BadLevels(m)) => m,
        other => panic!("expected BadLevels, got {:?}", other.map(|_| ())),
    };
    for &spacing in Spacing::ALL {
        let base = RefineOptions::new(Scheme::Pn, 1).with_spacing(spacing);
        for x in [f32::NAN, -1.0, 0.0, f32::INFINITY, f32::NEG_INFINITY] {
            let o = base.clone().with_levels(Levels::Uniform(x));
            if (spacing, x) == (Spacing::Grid, 0.0) {
                // A whole grid level: the classic refinement's own error.
                assert!(matches!(Plan::new(&mesh, &o), Err(RefineError::LevelZero)));
                continue;
            }
            let m = bad(o);
            assert!(m.contains("finite numbers above 0"), "{m}");
        }
        let mut edges = vec![2.0f32; ne];
        edges[7] = f32::NAN;
        let m = bad(base.clone().with_levels(Levels::PerEdge {
            edges: Arc::from(edges),
            faces: None,
        }));
        assert!(m.contains("edge 7"), "{m}");
        let m = bad(base.clone().with_levels(Levels::PerEdge {
            edges: Arc::from(vec![2.0f32; 3]),
            faces: None,
        }));
        assert!(m.contains("unique edges"), "{m}");
        for d in [0.0, -1.0, f32::NAN] {
            bad(base
                .clone()
                .with_levels(Levels::Lod(Lod::Tolerance { max_deviation: d })));
        }
        for (fov, eye) in [
            (0.0, [0.0, 0.0, 3.0]),
            (180.0, [0.0, 0.0, 3.0]),
            (45.0, [0.0; 3]),
        ] {
            let m = bad(base.clone().with_levels(Levels::Lod(Lod::Screen {
                pixels: 4.0,
                camera: Camera {
                    eye,
                    target: [0.0; 3],
                    fov_y_deg: fov,
                },
                size: [100, 100],
            })));
            assert!(m.contains("camera") || m.contains("field of view"), "{m}");
        }
    }
    // Above the tessellator's maximum: clamped as the hardware does.
    let o = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_levels(Levels::Uniform(1000.0));
    let plan = Plan::new(&mesh, &o).unwrap();
    assert!(plan
        .tiling()
        .unwrap()
        .edge_levels
        .iter()
        .all(|&x| x == 63.0));
    // Over the size cap: refused before anything is allocated.
    let o = RefineOptions::new(Scheme::Pn, 1)
        .with_levels(Levels::Uniform(1e9))
        .with_max_output_bytes(1 << 30);
    assert!(matches!(
        Plan::new(&mesh, &o),
        Err(RefineError::TooLarge { .. })
    ));
}

/// Measurements for the report (`cargo test --release --test adaptive measure -- --ignored
/// --nocapture`): adaptive against uniform at the same deviation, and vertex jumps.
#[test]
#[ignore]
fn measure() {
    use std::time::Instant;
    let mut bunny = samples::icosphere_4k();
    {
        // perturbed like a scanned shape: low-frequency bumps
        let p: Vec<[f32; 3]> = bunny
            .positions()
            .iter()
            .map(|q| {
                let s =
                    1.0 + 0.25 * (3.0 * q[0]).sin() * (2.0 * q[1]).cos() + 0.1 * (5.0 * q[2]).sin();
                q.map(|x| x * s)
            })
            .collect();
        bunny = Mesh::new(p, None, None, bunny.triangles().to_vec()).unwrap();
    }
    for (name, mesh) in [
        ("bumpy icosphere", bunny),
        ("creature", samples::creature()),
    ] {
        let diag = reference::diagonal(&mesh);
        for rel in [1e-3, 1e-4] {
            let d = (rel * diag) as f32;
            let o = RefineOptions::new(Scheme::Pn, 1)
                .with_weld(false)
                .with_levels(Levels::Lod(Lod::Tolerance { max_deviation: d }));
            let t = Instant::now();
            let (plan, out) = run(&mesh, &o);
            let ta = t.elapsed().as_secs_f64() * 1e3;
            let dev = max_deviation(&mesh, &plan, &out);
            // smallest uniform level reaching the same deviation
            let mut n = 1;
            let (tu, tris_u, dev_u) = loop {
                let o = RefineOptions::new(Scheme::Pn, n).with_weld(false);
                let t = Instant::now();
                let (p, u) = run(&mesh, &o);
                let tu = t.elapsed().as_secs_f64() * 1e3;
                let du = max_deviation(&mesh, &p, &u);
                if du <= dev {
                    break (tu, u.triangles.len(), du);
                }
                n += 1;
            };
            eprintln!(
                "{name} ({} tri) D={d:.2e}: adaptive {} triangles, {ta:.1} ms, deviation {dev:.2e}; uniform level {n}: {tris_u} triangles, {tu:.1} ms, deviation {dev_u:.2e}",
                mesh.face_count(),
                out.triangles.len()
            );
        }
    }
    // Geomorphing: largest vertex jump between level f and f + 1e-3 (fractional-odd, soup,
    // same vertex count), over f in 1..63; the grid's pop from N to N+1 (each new vertex
    // against the level-N flat surface at its parameter).
    let mesh = samples::creature();
    let at = |f: f32| {
        let o = RefineOptions::new(Scheme::Pn, 1)
            .with_weld(false)
            .with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::Uniform(f));
        run(&mesh, &o).1
    };
    let mut worst = (0.0f64, 0.0f32);
    let mut f = 1.0f32;
    while f < 63.0 {
        let (a, b) = (at(f), at(f + 1e-3));
        if a.positions.len() == b.positions.len() {
            let j = a
                .positions
                .iter()
                .zip(&b.positions)
                .map(|(p, q)| (d3(*p) - d3(*q)).length())
                .fold(0.0, f64::max);
            if j > worst.0 {
                worst = (j, f);
            }
        }
        f += 0.37;
    }
    let mut pop = (0.0f64, 0);
    for n in 1..64u32 {
        let (_, a) = run(&mesh, &RefineOptions::new(Scheme::Pn, n).with_weld(false));
        let (pb, b) = run(
            &mesh,
            &RefineOptions::new(Scheme::Pn, n + 1).with_weld(false),
        );
        let (fb, lb) = pb.origin();
        let np = (n as usize + 1) * (n as usize + 2) / 2;
        for (v, l) in lb.iter().enumerate() {
            let face = fb[v] as usize;
            // level-n cell of parameter (l2, l3)
            let (x, y) = (l[1] as f64 * n as f64, l[2] as f64 * n as f64);
            let (i, j) = ((x.floor() as u32).min(n - 1), (y.floor() as u32).min(n - 1));
            let (i, j) = if i + j >= n {
                (i.min(n - 1 - j.min(n - 1)), j.min(n - 1))
            } else {
                (i, j)
            };
            let (fx, fy) = (x - i as f64, y - j as f64);
            let idx = |i: u32, j: u32| tessella_core::Pattern::index(n, i, j) as usize + face * np;
            let p = |k: usize| d3(a.positions[k]);
            let flat = if fx + fy <= 1.0 || i + j + 1 >= n {
                p(idx(i, j)) * (1.0 - fx - fy) + p(idx(i + 1, j)) * fx + p(idx(i, j + 1)) * fy
            } else {
                let (gx, gy) = (1.0 - fx, 1.0 - fy);
                p(idx(i + 1, j + 1)) * (1.0 - gx - gy)
                    + p(idx(i, j + 1)) * gx
                    + p(idx(i + 1, j)) * gy
            };
            let jump = (d3(b.positions[v]) - flat).length();
            if jump > pop.0 {
                pop = (jump, n);
            }
        }
    }
    eprintln!(
        "creature diag {:.3}: fractional-odd largest jump f -> f+1e-3 over 1..63: {:.2e} (at f = {:.2}); grid integer pop N -> N+1 over 1..64: {:.2e} (at N = {})",
        reference::diagonal(&mesh),
        worst.0,
        worst.1,
        pop.0,
        pop.1
    );
}

/// Each part of each spacing's table as an indexed mesh: distinct codes, and indices that give
/// back the table's triangles code for code, corner for corner; a part id past the table
/// gives nothing.
#[test]
fn part_vertices_index_each_parts_triangles() {
    use tessella_core::refine::instanced::PartTable;
    for spacing in [
        Spacing::Grid,
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        let table = PartTable::new(spacing);
        let mut drawn = 0;
        for (part, range) in table.ranges.iter().enumerate() {
            let (codes, indices) = table.part_vertices(part as u32);
            let triangles = &table.triangles[range.start as usize..range.end as usize];
            assert_eq!(indices.len(), 3 * triangles.len());
            let distinct: std::collections::HashSet<_> = codes.iter().collect();
            assert_eq!(distinct.len(), codes.len(), "{spacing:?} part {part}");
            let back: Vec<u32> = indices.iter().map(|&i| codes[i as usize]).collect();
            let want: Vec<u32> = triangles.iter().flatten().copied().collect();
            assert_eq!(back, want, "{spacing:?} part {part}");
            drawn += usize::from(!triangles.is_empty());
        }
        assert!(drawn > 0, "{spacing:?}");
        let past = table.ranges.len() as u32;
        assert_eq!(table.part_vertices(past), (Vec::new(), Vec::new()));
    }
}
