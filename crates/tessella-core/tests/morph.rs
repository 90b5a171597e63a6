//! Geomorphing grid patterns (docs/formulas.md, "Geomorphing grid patterns"): a fractional grid
//! level `f` draws the grid of `N = ⌈f⌉` segments with every point at
//! `α S(l) + (1 − α) L(l)`, `α = f − (N − 1)`, `S` the surface and `L` the level-`(N − 1)` flat
//! refined triangles.
//!
//! The references are independent of the morph code: `S` and `L` come from ordinary integer-level
//! refinements (the classic path), `L` by locating the point in the level-`(N − 1)` grid here and
//! interpolating that mesh's vertices linearly.

mod reference;

use glam::DVec3;
use reference::corpus::{perturbed_sphere, Lcg};
use reference::{closed_manifold, d3, diagonal};
use std::sync::Arc;
use tessella_core::refine::{Levels, Plan};
use tessella_core::{refine, samples, Mesh, Pattern, RefineOptions, RefinedMesh, Scheme};

fn run(mesh: &Mesh, o: &RefineOptions) -> (Plan, RefinedMesh) {
    let plan = Plan::new(mesh, o).unwrap();
    let frame = plan.frame(mesh).unwrap();
    let mut out = RefinedMesh::default();
    plan.refine_into(&frame, &mut out, &|_| {}).unwrap();
    (plan, out)
}

fn at_level(scheme: Scheme, f: f32, weld: bool) -> RefineOptions {
    RefineOptions::new(scheme, 1)
        .with_weld(weld)
        .with_levels(Levels::Uniform(f))
}

/// A classic soup refinement at integer level `m`: the surface at the level-`m` grid points and
/// the flat triangles between them.
struct Level {
    m: u32,
    positions: Vec<[f32; 3]>,
}

impl Level {
    fn new(mesh: &Mesh, scheme: Scheme, m: u32) -> Level {
        let out = refine(mesh, &RefineOptions::new(scheme, m).with_weld(false)).unwrap();
        Level {
            m,
            positions: out.positions,
        }
    }
    /// Grid point `(i, j)` of face `f`.
    fn at(&self, f: usize, i: u32, j: u32) -> DVec3 {
        let np = Pattern::point_count(self.m) as usize;
        d3(self.positions[f * np + Pattern::index(self.m, i, j) as usize])
    }
    /// The flat refined surface of face `f` at point `(i, j)` of the level-`n` grid.
    fn flat(&self, f: usize, n: u32, i: u32, j: u32) -> DVec3 {
        let m = self.m;
        // x = i m / n = cx + rx / n, exactly.
        let (cx, rx, cy, ry) = ((i * m) / n, (i * m) % n, (j * m) / n, (j * m) % n);
        let (fx, fy) = (rx as f64 / n as f64, ry as f64 / n as f64);
        let corners = if rx + ry <= n {
            [(cx, cy, 1.0 - fx - fy), (cx + 1, cy, fx), (cx, cy + 1, fy)]
        } else {
            [
                (cx + 1, cy, 1.0 - fy),
                (cx + 1, cy + 1, fx + fy - 1.0),
                (cx, cy + 1, 1.0 - fx),
            ]
        };
        corners
            .iter()
            .filter(|c| c.2 != 0.0)
            .map(|&(a, b, w)| self.at(f, a, b) * w)
            .sum()
    }
}

/// Each output vertex's face and level-`n` grid point, from the plan's origins.
fn grid_origins(plan: &Plan, n: u32) -> Vec<(usize, u32, u32)> {
    let (faces, bary) = plan.origin();
    faces
        .iter()
        .zip(&bary)
        .map(|(&f, l)| {
            let (i, j) = (
                (l[1] as f64 * n as f64).round() as u32,
                (l[2] as f64 * n as f64).round() as u32,
            );
            (f as usize, i, j)
        })
        .collect()
}

/// Largest distance of the level-`n` mesh's vertices from the flat level-`coarse.m` surface at
/// the same parameters.
fn jump_to_flat(plan: &Plan, out: &RefinedMesh, n: u32, coarse: &Level) -> f64 {
    grid_origins(plan, n)
        .iter()
        .zip(&out.positions)
        .map(|(&(f, i, j), p)| (d3(*p) - coarse.flat(f, n, i, j)).length())
        .fold(0.0, f64::max)
}

fn vertex_jump(a: &RefinedMesh, b: &RefinedMesh) -> f64 {
    assert_eq!(a.positions.len(), b.positions.len());
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (d3(*p) - d3(*q)).length())
        .fold(0.0, f64::max)
}

/// The morph factor of `f` as the plan sees it (the f32 level in f64).
fn alpha(f: f32) -> f64 {
    f as f64 - (f.ceil() as f64 - 1.0)
}

#[test]
fn morphed_points_are_the_blend_of_the_surface_and_the_coarser_flat_surface() {
    let meshes = [
        ("perturbed sphere", perturbed_sphere(4)),
        ("creature", samples::creature()),
    ];
    for (name, mesh) in &meshes {
        let diag = diagonal(mesh);
        for scheme in [Scheme::Pn, Scheme::Png1] {
            for n in [2u32, 3, 5, 16] {
                let (fine, coarse) = (Level::new(mesh, scheme, n), Level::new(mesh, scheme, n - 1));
                let mut pop = 0.0f64;
                for a in [1.0f32 / 4096.0, 0.25, 0.7, 0.999] {
                    let f = (n - 1) as f32 + a;
                    let a = alpha(f);
                    for weld in [true, false] {
                        let (plan, out) = run(mesh, &at_level(scheme, f, weld));
                        assert!(plan.tiling().unwrap().tiles[0].morph.is_some());
                        let mut worst = 0.0f64;
                        let mut near = 0.0f64;
                        for (&(face, i, j), p) in grid_origins(&plan, n).iter().zip(&out.positions)
                        {
                            let s = fine.at(face, i, j);
                            let l = coarse.flat(face, n, i, j);
                            pop = pop.max((s - l).length());
                            worst = worst.max((d3(*p) - (s * a + l * (1.0 - a))).length());
                            near = near.max((d3(*p) - l).length());
                        }
                        let what = format!("{name} {scheme:?} N {n} f {f} weld {weld}");
                        assert!(worst < 2e-6 * diag, "{what}: off the blend by {worst:.2e}");
                        // Near α = 0 every point lies on the coarser flat triangles.
                        assert!(near <= a * pop + 2e-6 * diag, "{what}: {near:.2e}");
                    }
                }
                // The check has teeth: the surface and the flat level differ visibly.
                assert!(pop > 1e-4 * diag, "{name} {scheme:?} N {n}: pop {pop:.2e}");
            }
        }
    }
}

#[test]
fn integer_levels_are_bit_identical_to_the_classic_refinement() {
    let mesh = samples::creature();
    for n in [1u32, 2, 7] {
        for weld in [true, false] {
            let classic =
                refine(&mesh, &RefineOptions::new(Scheme::Png1, n).with_weld(weld)).unwrap();
            let o = at_level(Scheme::Png1, n as f32, weld);
            assert_eq!(refine(&mesh, &o).unwrap(), classic, "N {n} weld {weld}");
        }
    }
    // Integer per-edge levels: no morph, the plain weights.
    let mesh = perturbed_sphere(2);
    let mut rng = Lcg::new(3);
    let edges: Vec<f32> = (0..mesh.topology().edges.len())
        .map(|_| rng.range(1.0, 7.0).ceil() as f32)
        .collect();
    let o = RefineOptions::new(Scheme::Pn, 1).with_levels(Levels::PerEdge {
        edges: Arc::from(edges),
        faces: None,
    });
    let plan = Plan::new(&mesh, &o).unwrap();
    for t in &plan.tiling().unwrap().tiles {
        assert!(t.morph.is_none());
        assert_eq!(
            t.stencil,
            tessella_core::Stencil::new(&t.pattern, Scheme::Pn.basis())
        );
    }
}

#[test]
fn morphing_output_is_watertight_welded_and_bit_for_bit_in_soup() {
    let meshes = [
        ("perturbed sphere", perturbed_sphere(7), 2),
        ("torus", samples::torus(1.0, 0.4, 10, 6), 0),
    ];
    for (name, mesh, euler) in &meshes {
        let mut rng = Lcg::new(9);
        let per_edge: Vec<f32> = (0..mesh.topology().edges.len())
            .map(|_| rng.range(0.7, 9.0) as f32)
            .collect();
        let levels = [
            Levels::Uniform(3.3),
            Levels::Uniform(6.01),
            Levels::PerEdge {
                edges: Arc::from(per_edge),
                faces: None,
            },
        ];
        for levels in levels {
            for scheme in [Scheme::Pn, Scheme::Png1, Scheme::PHONG] {
                let o = RefineOptions::new(scheme, 1).with_levels(levels.clone());
                let (plan, welded) = run(mesh, &o);
                assert!(plan
                    .tiling()
                    .unwrap()
                    .tiles
                    .iter()
                    .any(|t| t.morph.is_some()));
                let (_, soup) = run(mesh, &o.clone().with_weld(false));
                let what = format!("{name} {levels:?} {scheme:?}");
                let m = closed_manifold(welded.positions.len(), &welded.triangles)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(m.euler, *euler, "{what}");
                // Soup vertices equal the one welded vertex bit for bit, so the copies of a
                // shared edge point from its two faces are equal too.
                assert_eq!(welded.triangles.len(), soup.triangles.len(), "{what}");
                for (tw, ts) in welded.triangles.iter().zip(&soup.triangles) {
                    for c in 0..3 {
                        assert_eq!(
                            welded.positions[tw[c] as usize].map(f32::to_bits),
                            soup.positions[ts[c] as usize].map(f32::to_bits),
                            "{what}"
                        );
                        // PN's normal-net normals are canonical too (PNG1's are not
                        // everywhere, with or without morphing: the torus differs at level 3).
                        if scheme == Scheme::Pn {
                            assert_eq!(
                                welded.normals[tw[c] as usize].map(f32::to_bits),
                                soup.normals[ts[c] as usize].map(f32::to_bits),
                                "{what}"
                            );
                        }
                    }
                }
            }
        }
    }
}

/// Largest jumps over a sweep of uniform levels `1..=top`: `(morph, pop)`, the morph's
/// largest vertex move between `f` and `f + eps` (same grid: vertex to vertex; across an
/// integer: the new grid against the old one's flat surface) and the integer pop (level `N`
/// against the flat level `N − 1`), each also per `N` through `each`.
fn sweep(
    mesh: &Mesh,
    top: u32,
    fractions: &[f32],
    eps: f32,
    mut each: impl FnMut(u32, f64, f64),
) -> (f64, f64) {
    let scheme = Scheme::Pn;
    let (mut morph, mut pop) = (0.0f64, 0.0f64);
    let mut coarse = Level::new(mesh, scheme, 1);
    for n in 2..=top {
        let (plan_n, int_n) = run(mesh, &RefineOptions::new(scheme, n).with_weld(false));
        let pop_n = jump_to_flat(&plan_n, &int_n, n, &coarse);
        // Across the integer N − 1: level N − 1 exactly, then N − 1 + eps on the grid N.
        let f = (n - 1) as f32 + eps;
        let (plan, out) = run(mesh, &at_level(scheme, f, false));
        let mut jump_n = jump_to_flat(&plan, &out, n, &coarse);
        // Inside (N − 1, N]: f against f + eps, the last step landing on N exactly.
        for &x in fractions {
            let f = (n - 1) as f32 + x;
            let g = if x + eps >= 1.0 { n as f32 } else { f + eps };
            assert_eq!(f.ceil() as u32, n);
            let a = run(mesh, &at_level(scheme, f, false)).1;
            let b = run(mesh, &at_level(scheme, g, false)).1;
            jump_n = jump_n.max(vertex_jump(&a, &b));
        }
        each(n, jump_n, pop_n);
        morph = morph.max(jump_n);
        pop = pop.max(pop_n);
        coarse = Level {
            m: n,
            positions: int_n.positions,
        };
    }
    (morph, pop)
}

#[test]
fn levels_moving_by_a_little_move_vertices_by_a_little() {
    let mesh = perturbed_sphere(5);
    let diag = diagonal(&mesh);
    let eps = 1e-3;
    let (morph, pop) = sweep(&mesh, 64, &[1e-4, 0.5, 1.0 - 1e-3], eps, |n, jump, pop| {
        assert!(
            jump <= 1e-2 * pop + 1e-6 * diag,
            "N {n}: morph jump {jump:.2e}, integer pop {pop:.2e}"
        );
    });
    eprintln!("perturbed sphere: morph jump {morph:.2e}, integer pop {pop:.2e}");
    assert!(morph <= 1e-2 * pop, "morph {morph:.2e} pop {pop:.2e}");
    assert!(pop > 1e-3 * diag);
}

#[test]
fn per_edge_levels_moving_continuously_move_vertices_continuously() {
    let mesh = perturbed_sphere(6);
    let diag = diagonal(&mesh);
    let mut rng = Lcg::new(1);
    let base: Vec<f32> = (0..mesh.topology().edges.len())
        .map(|_| rng.range(1.0, 3.0) as f32)
        .collect();
    let at = |s: f32| {
        let edges: Vec<f32> = base.iter().map(|&x| x * s).collect();
        run(
            &mesh,
            &RefineOptions::new(Scheme::Pn, 1)
                .with_weld(false)
                .with_levels(Levels::PerEdge {
                    edges: Arc::from(edges),
                    faces: None,
                }),
        )
    };
    let shape = |p: &Plan| {
        let t = p.tiling().unwrap();
        let levels: Vec<u32> = (0..p.face_count())
            .map(|f| t.tile(f).pattern.level)
            .collect();
        (t.edge_segments.clone(), levels)
    };
    let eps = 1e-4;
    let (mut worst, mut compared) = (0.0f64, 0);
    let mut s = 1.0f32;
    while s < 4.0 {
        let ((pa, a), (pb, b)) = (at(s), at(s + eps));
        if shape(&pa) == shape(&pb) {
            worst = worst.max(vertex_jump(&a, &b));
            compared += 1;
        }
        s += 0.0371;
    }
    assert!(compared > 50, "{compared}");
    // Edge levels move by at most 3 eps: the points by at most 3 eps times the pop, which is
    // below the diagonal.
    assert!(worst <= 3.0 * eps as f64 * diag, "{worst:.2e}");
}

/// Measurements for the report (`cargo test --release -p tessella-core --test morph --
/// --ignored --nocapture`): the largest vertex jump between `f` and `f + 10⁻³` over a sweep of
/// `1..64`, with geomorphing, against the integer pop (what the grid did before: fractional
/// levels rounded up, so crossing an integer popped by this much).
#[test]
#[ignore]
fn measure() {
    let mesh = samples::creature();
    let fractions: Vec<f32> = (0..20).map(|k| k as f32 / 20.0 + 1e-4).collect();
    let (morph, pop) = sweep(&mesh, 64, &fractions, 1e-3, |n, jump, pop| {
        eprintln!("N {n:2}: morph jump {jump:.2e}, integer pop {pop:.2e}");
    });
    eprintln!(
        "creature ({} triangles, diagonal {:.3}), PN soup, levels 1..64, f -> f + 1e-3 at 20 fractions per level and across each integer: morph max jump {morph:.2e}, integer pop max {pop:.2e} (ratio {:.1e})",
        mesh.face_count(),
        diagonal(&mesh),
        morph / pop
    );
}
