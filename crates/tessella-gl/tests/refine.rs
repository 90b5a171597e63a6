//! GL output against the CPU refinement with the same scheme, spacing, levels and normals.
//! The tests need an EGL driver with OpenGL 4.3 (CI: Mesa's llvmpipe); without one they fail
//! with the install hint rather than skip.

use tessella_core::refine::{Levels, Lod, Spacing};
use tessella_core::{samples, Mesh, NormalMode, RefineOptions, Scheme};
use tessella_gl::{compare, GlContext, GlTessellator, LevelSource};

const TOL: f32 = 1e-5;
const NORMAL_TOL: f32 = 1e-4;

fn ctx() -> GlContext {
    GlContext::new().unwrap_or_else(|e| panic!("no GL driver for the tests: {e}"))
}

fn check(
    gl: &mut GlTessellator,
    mesh: &Mesh,
    options: &RefineOptions,
    source: Option<LevelSource>,
    what: &str,
) {
    let out = gl
        .refine(mesh, options, source)
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(out.notes.is_empty(), "{what}: {:?}", out.notes);
    let c = compare(mesh, options, &out, TOL, NORMAL_TOL).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(c.triangles > 0, "{what}");
    eprintln!("{what}: {c:?}");
}

fn pn(spacing: Spacing, level: f32) -> RefineOptions {
    RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(spacing)
        .with_levels(Levels::Uniform(level))
}

#[test]
fn context_reports_gl4_with_tessellation() {
    let ctx = ctx();
    let info = ctx.info();
    assert!(info.max_tess_level >= 64, "{info:?}");
    assert!(info.version.starts_with('4'), "{info:?}");
}

#[test]
fn pn_uniform_levels_match_the_cpu() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let mesh = samples::icosphere(1);
    for level in [1.0, 2.0, 3.0, 5.0, 8.0] {
        let o = pn(Spacing::Equal, level);
        check(
            &mut gl,
            &mesh,
            &o,
            Some(LevelSource::Uniform),
            &format!("pn {level}"),
        );
        // The same levels read per face by the TCS.
        check(
            &mut gl,
            &mesh,
            &o,
            Some(LevelSource::PerFace),
            &format!("pn {level} per face"),
        );
    }
}

#[test]
fn schemes_and_normal_modes_match_the_cpu() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let mesh = samples::torus(1.0, 0.35, 10, 7);
    let cases = [
        (Scheme::Flat, NormalMode::Linear),
        (Scheme::PHONG, NormalMode::Linear),
        (Scheme::PHONG, NormalMode::Real),
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
        (Scheme::Pn, NormalMode::Linear),
        (Scheme::Png1, NormalMode::Quadratic),
        (Scheme::Png1, NormalMode::Real),
        (Scheme::PnAen, NormalMode::Quadratic),
    ];
    for (scheme, normals) in cases {
        for level in [2.0, 4.0, 7.0] {
            let o = RefineOptions::new(scheme, 1)
                .with_normals(normals)
                .with_spacing(Spacing::Equal)
                .with_levels(Levels::Uniform(level));
            check(
                &mut gl,
                &mesh,
                &o,
                None,
                &format!("{scheme:?} {normals:?} {level}"),
            );
        }
    }
}

#[test]
fn every_spacing_matches_the_cpu() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let mesh = samples::icosphere(1);
    for spacing in [
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        for level in [1.0, 2.5, 3.7, 6.0, 9.3] {
            for scheme in [Scheme::Pn, Scheme::Png1] {
                let o = RefineOptions::new(scheme, 1)
                    .with_spacing(spacing)
                    .with_levels(Levels::Uniform(level));
                check(
                    &mut gl,
                    &mesh,
                    &o,
                    None,
                    &format!("{scheme:?} {spacing} {level}"),
                );
            }
        }
    }
}

#[test]
fn per_edge_and_lod_levels_match_the_cpu() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let mesh = samples::icosphere(1);
    let ne = mesh.topology().edges.len();
    let edges: Vec<f32> = (0..ne).map(|e| 1.0 + (e * 7 % 11) as f32 * 0.8).collect();
    for spacing in [
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        for scheme in [Scheme::Flat, Scheme::PHONG, Scheme::Pn, Scheme::Png1] {
            let o = RefineOptions::new(scheme, 1)
                .with_spacing(spacing)
                .with_levels(Levels::PerEdge {
                    edges: edges.clone().into(),
                    faces: None,
                });
            check(
                &mut gl,
                &mesh,
                &o,
                Some(LevelSource::PerFace),
                &format!("{scheme:?} {spacing} per edge"),
            );
            let o = o.with_levels(Levels::Lod(Lod::Tolerance {
                max_deviation: 0.002,
            }));
            check(
                &mut gl,
                &mesh,
                &o,
                Some(LevelSource::PerFace),
                &format!("{scheme:?} {spacing} tolerance"),
            );
        }
    }
}

#[test]
fn the_comparison_catches_a_moved_vertex_a_wrong_normal_and_a_flipped_triangle() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let mesh = samples::icosphere(1);
    let o = pn(Spacing::FractionalOdd, 4.5);
    let good = gl.refine(&mesh, &o, None).unwrap();
    compare(&mesh, &o, &good, TOL, NORMAL_TOL).unwrap();
    let mut moved = good.clone();
    moved.positions[7][0] += 1e-3 * mesh.diagonal();
    assert!(compare(&mesh, &o, &moved, TOL, NORMAL_TOL).is_err());
    let mut bent = good.clone();
    bent.normals[5] = [0.0, 0.0, 1.0];
    assert!(compare(&mesh, &o, &bent, TOL, NORMAL_TOL).is_err());
    let mut flipped = good.clone();
    flipped.positions.swap(0, 1);
    flipped.normals.swap(0, 1);
    flipped.coords.swap(0, 1);
    assert!(compare(&mesh, &o, &flipped, TOL, NORMAL_TOL).is_err());
    // Other options' CPU output is not this output.
    assert!(compare(
        &mesh,
        &pn(Spacing::FractionalEven, 4.5),
        &good,
        TOL,
        NORMAL_TOL
    )
    .is_err());
}

#[test]
fn grid_spacing_is_refused_with_a_message() {
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let err = gl
        .refine(
            &samples::icosphere(0),
            &RefineOptions::new(Scheme::Pn, 3),
            None,
        )
        .unwrap_err();
    assert!(err.to_string().contains("fractional-odd"), "{err}");
}

#[test]
fn a_missing_driver_is_a_clear_error() {
    let err = match GlContext::with_library("libEGL-that-does-not-exist.so.1") {
        Ok(_) => panic!("a context from a missing library"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("libEGL-that-does-not-exist.so.1"), "{err}");
    assert!(err.contains(tessella_gl::DRIVER_PACKAGES), "{err}");
    assert!(err.contains("--backend cpu"), "{err}");
}

#[test]
fn the_control_shader_builds_the_nets_and_they_match_the_cpu() {
    use tessella_core::tags::{EdgeTag, Tags};
    use tessella_gl::NetSource;
    let ctx = ctx();
    let mut gl = GlTessellator::new(&ctx).unwrap();
    let level = |o: RefineOptions| {
        o.with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::Uniform(4.5))
    };
    // Which schemes build their nets in the shader, and which take the CPU's.
    let torus = samples::torus(1.0, 0.35, 8, 6);
    for (scheme, shader) in [
        (Scheme::Flat, true),
        (Scheme::Phong { alpha: 0.3 }, true),
        (Scheme::Pn, true),
        (Scheme::Png1, true),
        (Scheme::PnAen, false),
        (Scheme::ScalarTagged, false),
    ] {
        let o = level(RefineOptions::new(scheme, 1));
        let p = gl.prepare(&torus, &o, None).unwrap();
        assert_eq!(matches!(p.nets, NetSource::Shader(_)), shader, "{scheme:?}");
        check(
            &mut gl,
            &torus,
            &o,
            None,
            &format!("{scheme:?} on the torus"),
        );
    }
    // PNG1's edge cases, built in the shader: boundary edges (an open patch), split normals
    // (sharp, κ = 0: the hard cube, half a faceted sphere) and tagged sharp edges with κ.
    let sphere = samples::icosphere(1);
    let open = samples::first_faces(&sphere, 30);
    let mut tags = Tags::new();
    let t = sphere.triangles()[0];
    let crease = EdgeTag {
        sharpness: 1.0,
        kappa: 0.05,
    };
    tags.set_edge(&sphere, [t[0], t[1]], crease).unwrap();
    let cases = [
        ("open patch", open, None),
        ("hard cube", samples::hard_cube(), None),
        (
            "half-faceted sphere",
            samples::half_faceted_icosphere(1),
            None,
        ),
        ("tagged crease", sphere, Some(tags)),
    ];
    for (name, mesh, tags) in cases {
        for normals in [NormalMode::Quadratic, NormalMode::Real] {
            let mut o = level(RefineOptions::new(Scheme::Png1, 1)).with_normals(normals);
            if let Some(t) = &tags {
                o = o.with_tags(t.clone());
            }
            let p = gl.prepare(&mesh, &o, None).unwrap();
            let NetSource::Shader(s) = &p.nets else {
                panic!("{name}: PNG1 nets should come from the shader");
            };
            assert_eq!(s.patch_vertices, 6);
            check(
                &mut gl,
                &mesh,
                &o,
                None,
                &format!("PNG1 {normals:?}, {name}"),
            );
        }
    }
}

/// `mesh` with its positions scaled and bent a little, differently for every `t`.
fn deformed(mesh: &Mesh, t: usize) -> Vec<[f32; 3]> {
    let s = 0.15 * t as f32;
    mesh.positions()
        .iter()
        .map(|p| {
            [
                p[0] * (1.0 + s),
                p[1] + s * p[0] * p[0],
                p[2] * (1.0 - 0.5 * s),
            ]
        })
        .collect()
}

#[test]
fn evaluator_follows_a_deforming_mesh_like_the_tessellator_and_the_cpu() {
    use tessella_core::refine::{Evaluator, Plan};
    use tessella_gl::{GlEvaluator, GlRefined};
    let ctx = ctx();
    let mut tessellator = GlTessellator::new(&ctx).unwrap();
    // Shader-built nets (PN, PNG1: coarse vertices uploaded) and CPU nets (PN-AEN: the nets).
    for (scheme, spacing) in [
        (Scheme::Pn, Spacing::Equal),
        (Scheme::Png1, Spacing::FractionalOdd),
        (Scheme::PnAen, Spacing::Equal),
    ] {
        let mesh = samples::icosphere(1);
        let options = RefineOptions::new(scheme, 1)
            .with_spacing(spacing)
            .with_levels(Levels::Uniform(4.5));
        let plan = Plan::new(&mesh, &options).unwrap();
        let mut frame = plan.frame(&mesh).unwrap();
        let mut gl = GlEvaluator::new(&ctx, &plan, &frame).unwrap();
        let mut out = GlRefined::default();
        for t in 0..3 {
            let moved = deformed(&mesh, t);
            plan.update(&mut frame, &moved, None).unwrap();
            gl.evaluate(&plan, &frame, &mut out).unwrap();
            let what = format!("{scheme:?} {spacing:?} frame {t}");
            // The same draw as the one-shot path on the deformed mesh, and the CPU's surface.
            let deformed_mesh = frame.mesh().clone();
            let once = tessellator.refine(&deformed_mesh, &options, None).unwrap();
            assert_eq!(out.positions, once.positions, "{what}");
            assert_eq!(out.faces, once.faces, "{what}");
            let c = compare(&deformed_mesh, &options, &out, TOL, NORMAL_TOL)
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(c.triangles, plan.triangle_count(), "{what}");
            // Only the frame's coarse data crossed the bus: no levels, no indices.
            let nets = frame.nets();
            let coarse = match scheme {
                Scheme::PnAen => (nets.points.len() + nets.normals.len()) * 12,
                _ => mesh.vertex_count() * 24,
            };
            assert_eq!(gl.uploaded_bytes(), coarse as u64, "{what}");
        }
    }
    // One program per spacing, shared by the tessellator and every evaluator.
    assert_eq!(ctx.linked_programs(), 2);
}

#[test]
fn evaluator_refuses_other_plans_grids_and_displacement() {
    use tessella_core::displace::Displacement;
    use tessella_core::refine::{Evaluator, Plan};
    use tessella_gl::{GlError, GlEvaluator, GlRefined};
    let ctx = ctx();
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &pn(Spacing::Equal, 3.0)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let other = Plan::new(&mesh, &pn(Spacing::Equal, 5.0)).unwrap();
    let other_frame = other.frame(&mesh).unwrap();
    let mut gl = GlEvaluator::new(&ctx, &plan, &frame).unwrap();
    let mut out = GlRefined::default();
    gl.evaluate(&plan, &frame, &mut out).unwrap();
    let good = out.clone();
    let err = gl.evaluate(&other, &other_frame, &mut out).unwrap_err();
    assert!(err.to_string().contains("another plan"), "{err}");
    // A plan with the same counts and another shape (Phong's shape factor is per plan).
    let phong = |alpha| {
        RefineOptions::new(Scheme::Phong { alpha }, 1)
            .with_spacing(Spacing::Equal)
            .with_levels(Levels::Uniform(3.0))
    };
    let (soft, full) = (
        Plan::new(&mesh, &phong(0.5)).unwrap(),
        Plan::new(&mesh, &phong(1.0)).unwrap(),
    );
    let (soft_frame, full_frame) = (soft.frame(&mesh).unwrap(), full.frame(&mesh).unwrap());
    let mut soft_gl = GlEvaluator::new(&ctx, &soft, &soft_frame).unwrap();
    let err = soft_gl.evaluate(&full, &full_frame, &mut out).unwrap_err();
    assert!(err.to_string().contains("another plan"), "{err}");
    // A frame of another plan with the same counts.
    let twin = Plan::new(&mesh, &pn(Spacing::Equal, 3.0)).unwrap();
    let twin_frame = twin.frame(&mesh).unwrap();
    let err = gl.evaluate(&plan, &twin_frame, &mut out).unwrap_err();
    assert!(matches!(err, GlError::Refine(_)), "{err}");
    assert_eq!(out, good, "a refused evaluation writes nothing");
    // The grid pattern is not the hardware's.
    let grid = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let grid_frame = grid.frame(&mesh).unwrap();
    let err = GlEvaluator::new(&ctx, &grid, &grid_frame).unwrap_err();
    assert!(err.to_string().contains("spacing equal"), "{err}");
    // No displacement stage: refused with the reason, not ignored.
    let sine = Displacement::Sine {
        amplitude: 0.1,
        frequency: 3.0,
    };
    let err = GlEvaluator::with_displacement(&ctx, &plan, &frame, &sine).unwrap_err();
    assert!(err.to_string().contains("does not displace"), "{err}");
    GlEvaluator::with_displacement(&ctx, &plan, &frame, &Displacement::None).unwrap();
}
