//! The per-frame path: a [`Plan`] built once, frames moved by [`Plan::update`] and evaluated
//! into caller memory. Each frame must match an independent f64 evaluation of the deformed
//! mesh (`reference/`), the interleaved buffer must hold the same bits as separate arrays, and
//! bad frames must be refused without touching anything.

mod reference;

use reference::{d3, diagonal, occurrences, RefNormals, RefPatch, RefScheme, Tri};
use tessella_core::refine::{CpuEvaluator, Evaluator, Frame, Plan, VertexFormat, VertexOutput};
use tessella_core::{
    refine, samples, Mesh, MeshError, NormalMode, RefineError, RefineOptions, RefinedMesh, Scheme,
};

/// `mesh`'s positions twisted about Y by up to `degrees` and scaled by `scale`.
fn twisted(mesh: &Mesh, degrees: f32, scale: f32) -> Vec<[f32; 3]> {
    let (lo, hi) = mesh.bounds();
    let height = (hi[1] - lo[1]).max(1e-6);
    mesh.positions()
        .iter()
        .map(|p| {
            let a = degrees.to_radians() * (p[1] - lo[1]) / height;
            let (s, c) = a.sin_cos();
            [
                scale * (c * p[0] + s * p[2]),
                scale * p[1],
                scale * (-s * p[0] + c * p[2]),
            ]
        })
        .collect()
}

/// Evaluates a frame into fresh separate arrays, with the plan's indices.
fn evaluate(plan: &Plan, frame: &Frame) -> RefinedMesh {
    let n = plan.vertex_count();
    let mut out = RefinedMesh {
        positions: vec![[f32::NAN; 3]; n],
        normals: vec![[f32::NAN; 3]; n],
        uvs: None,
        triangles: plan.indices().to_vec(),
    };
    CpuEvaluator
        .evaluate(
            plan,
            frame,
            VertexOutput::Separate {
                positions: &mut out.positions,
                normals: Some(&mut out.normals),
                uvs: None,
            },
        )
        .expect("evaluates");
    out
}

/// Evaluates a frame into one interleaved buffer of `format`, every float `fill` first.
fn evaluate_interleaved(plan: &Plan, frame: &Frame, format: VertexFormat, fill: f32) -> Vec<f32> {
    let mut data = vec![fill; plan.vertex_count() * format.stride];
    plan.evaluate(
        frame,
        VertexOutput::Interleaved {
            data: &mut data,
            format,
        },
    )
    .unwrap();
    data
}

/// Every output vertex of every face against the f64 reference of `mesh` (the deformed
/// frame's own mesh, built independently with `Mesh::new`). Positions must match on every face
/// that uses a vertex; normals on at least one (real normals differ across a coarse edge, where
/// PN is only C0, and a welded vertex takes its owner face's).
fn assert_matches_reference(
    out: &RefinedMesh,
    mesh: &Mesh,
    plan: &Plan,
    scheme: RefScheme,
    normals: RefNormals,
) {
    let tol = 1e-5 * diagonal(mesh);
    let mut best = vec![f64::INFINITY; out.positions.len()];
    for o in occurrences(out, mesh.face_count(), plan.pattern()) {
        let t = mesh.triangles()[o.face];
        let tri = Tri {
            p: t.map(|v| d3(mesh.positions()[v as usize])),
            n: t.map(|v| d3(mesh.normals()[v as usize]).normalize()),
        };
        let patch = RefPatch::new(tri, scheme, normals);
        let l = plan.pattern().points[o.point];
        let err = (d3(out.positions[o.vertex]) - patch.position(l)).length();
        assert!(
            err <= tol,
            "face {} point {}: position off by {err}",
            o.face,
            o.point
        );
        let angle = reference::angle(d3(out.normals[o.vertex]), patch.normal(l));
        best[o.vertex] = best[o.vertex].min(angle);
    }
    let worst = best.iter().cloned().fold(0.0, f64::max);
    assert!(worst <= 1e-4, "a normal is off by {worst} rad");
}

#[test]
fn every_frame_matches_the_reference_of_the_deformed_mesh() {
    let rest = samples::creature();
    for (scheme, mode, rs, rn) in [
        (
            Scheme::Pn,
            NormalMode::Quadratic,
            RefScheme::Pn,
            RefNormals::Quadratic,
        ),
        (
            Scheme::Pn,
            NormalMode::Real,
            RefScheme::Pn,
            RefNormals::Real,
        ),
        (
            Scheme::PHONG,
            NormalMode::Linear,
            RefScheme::Phong { alpha: 0.75 },
            RefNormals::Linear,
        ),
        (
            Scheme::Flat,
            NormalMode::Linear,
            RefScheme::Flat,
            RefNormals::Linear,
        ),
    ] {
        for weld in [true, false] {
            let options = RefineOptions::new(scheme, 5)
                .with_normals(mode)
                .with_weld(weld);
            let plan = Plan::new(&rest, &options).unwrap();
            let mut frame = plan.frame(&rest).unwrap();
            for (degrees, scale) in [(0.0, 1.0), (40.0, 1.0), (-25.0, 1.3)] {
                let moved = twisted(&rest, degrees, scale);
                plan.update(&mut frame, &moved, None).unwrap();
                let out = evaluate(&plan, &frame);
                // The frame's mesh, built from scratch: normals recomputed as Mesh::new does.
                let mesh = Mesh::new(moved, None, None, rest.triangles().to_vec()).unwrap();
                assert_eq!(frame.mesh().normals(), mesh.normals());
                assert_matches_reference(&out, &mesh, &plan, rs, rn);
            }
        }
    }
}

#[test]
fn a_frame_equals_a_one_shot_refine_of_the_same_mesh_bit_for_bit() {
    // The one-shot path builds its own topology, nets and indices: every scheme, welded and soup.
    let rest = samples::half_faceted_icosphere(1);
    for scheme in [
        Scheme::Flat,
        Scheme::PHONG,
        Scheme::Pn,
        Scheme::Png1,
        Scheme::PnAen,
        Scheme::ScalarTagged,
    ] {
        for weld in [true, false] {
            let options = RefineOptions::new(scheme, 6).with_weld(weld);
            let plan = Plan::new(&rest, &options).unwrap();
            let mut frame = plan.frame(&rest).unwrap();
            let moved = twisted(&rest, 30.0, 0.8);
            let normals = rest.normals().to_vec();
            plan.update(&mut frame, &moved, Some(&normals)).unwrap();
            let per_frame = evaluate(&plan, &frame);
            let mesh = Mesh::new(moved, Some(normals), None, rest.triangles().to_vec()).unwrap();
            let one_shot = refine(&mesh, &options).unwrap();
            assert_eq!(per_frame, one_shot, "{} weld={weld}", scheme.name());
        }
    }
}

#[test]
fn interleaved_output_holds_the_same_bits_and_leaves_other_floats_alone() {
    let mut mesh = samples::torus(1.0, 0.3, 12, 8);
    let uvs: Vec<[f32; 2]> = mesh.positions().iter().map(|p| [p[0], p[2]]).collect();
    mesh = Mesh::new(
        mesh.positions().to_vec(),
        Some(mesh.normals().to_vec()),
        Some(uvs),
        mesh.triangles().to_vec(),
    )
    .unwrap();
    for weld in [true, false] {
        let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 7).with_weld(weld)).unwrap();
        let frame = plan.frame(&mesh).unwrap();
        let n = plan.vertex_count();
        let (mut p, mut nr, mut uv) = (
            vec![[0.0f32; 3]; n],
            vec![[0.0f32; 3]; n],
            vec![[0.0f32; 2]; n],
        );
        plan.evaluate(
            &frame,
            VertexOutput::Separate {
                positions: &mut p,
                normals: Some(&mut nr),
                uvs: Some(&mut uv),
            },
        )
        .unwrap();
        // An engine's layout: uv first, a float of its own, position, a float of its own, normal.
        let format = VertexFormat {
            stride: 10,
            position: 3,
            normal: Some(7),
            uv: Some(0),
        };
        let data = evaluate_interleaved(&plan, &frame, format, -7.5);
        for v in 0..n {
            let at = &data[v * 10..(v + 1) * 10];
            assert_eq!(
                at[0..2].iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                uv[v].map(f32::to_bits)
            );
            assert_eq!(
                at[3..6].iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                p[v].map(f32::to_bits)
            );
            assert_eq!(
                at[7..10].iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                nr[v].map(f32::to_bits)
            );
            assert_eq!(
                (at[2], at[6]),
                (-7.5, -7.5),
                "vertex {v}: floats no attribute covers were written"
            );
        }
        // And both equal the one-shot refine.
        let once = refine(&mesh, &RefineOptions::new(Scheme::Pn, 7).with_weld(weld)).unwrap();
        assert_eq!((once.positions, once.normals, once.uvs), (p, nr, Some(uv)));
    }
}

/// Separate arrays of more than 64 MiB are written with streaming stores (whole cache lines,
/// plain stores at the ends of each run); an interleaved buffer never is. Both must hold the
/// same bits, edges stored against their owner's direction included.
#[test]
fn outputs_past_the_streaming_size_hold_the_same_bits_as_plain_stores() {
    let mesh = samples::icosphere_4k();
    for weld in [true, false] {
        let options = RefineOptions::new(Scheme::Pn, 40).with_weld(weld);
        let plan = Plan::new(&mesh, &options).unwrap();
        let frame = plan.frame(&mesh).unwrap();
        let n = plan.vertex_count();
        assert!(
            n * 24 > 64 << 20,
            "{n} vertices stay under the streaming size"
        );
        let separate = evaluate(&plan, &frame);
        let (p, nr) = (separate.positions, separate.normals);
        let data = evaluate_interleaved(&plan, &frame, VertexFormat::POSITION_NORMAL, f32::NAN);
        for v in 0..n {
            let bits = |a: &[f32]| a.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let at = &data[v * 6..(v + 1) * 6];
            assert_eq!(
                bits(&p[v]),
                bits(&at[..3]),
                "weld {weld} vertex {v} position"
            );
            assert_eq!(
                bits(&nr[v]),
                bits(&at[3..]),
                "weld {weld} vertex {v} normal"
            );
        }
    }
}

#[test]
fn positions_only_output_skips_normals_but_keeps_positions() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Png1, 5)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let mut p = vec![[0.0f32; 3]; plan.vertex_count()];
    plan.evaluate(
        &frame,
        VertexOutput::Separate {
            positions: &mut p,
            normals: None,
            uvs: None,
        },
    )
    .unwrap();
    assert_eq!(
        p,
        refine(&mesh, &RefineOptions::new(Scheme::Png1, 5))
            .unwrap()
            .positions
    );
}

#[test]
fn u16_indices_equal_u32_and_are_refused_when_too_many_vertices() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 8)).unwrap();
    assert!(plan.fits_u16());
    let mut small = vec![[0u16; 3]; plan.triangle_count()];
    plan.write_indices(&mut small).unwrap();
    let wide: Vec<[u32; 3]> = small.iter().map(|t| t.map(u32::from)).collect();
    assert_eq!(wide, plan.indices());
    assert_eq!(
        wide,
        refine(&mesh, &RefineOptions::new(Scheme::Pn, 8))
            .unwrap()
            .triangles
    );

    let big = samples::icosphere_4k();
    let plan = Plan::new(&big, &RefineOptions::new(Scheme::Pn, 8)).unwrap();
    assert!(plan.vertex_count() > 65536 && !plan.fits_u16());
    let mut small = vec![[0u16; 3]; plan.triangle_count()];
    assert!(matches!(
        plan.write_indices(&mut small),
        Err(RefineError::IndicesTooNarrow { index_bits: 16, .. })
    ));
    assert!(
        small.iter().all(|t| *t == [0; 3]),
        "a refused write wrote nothing"
    );
    let mut short = vec![[0u32; 3]; plan.triangle_count() - 1];
    assert!(matches!(
        plan.write_indices(&mut short),
        Err(RefineError::OutputTooSmall { .. })
    ));
}

#[test]
fn bad_frames_are_refused_and_leave_frame_and_output_untouched() {
    let rest = samples::icosphere(1);
    let plan = Plan::new(&rest, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let mut frame = plan.frame(&rest).unwrap();
    plan.update(&mut frame, &twisted(&rest, 20.0, 1.0), None)
        .unwrap();
    let good = evaluate(&plan, &frame);
    let before = frame.clone();

    let mut nan = twisted(&rest, 50.0, 1.0);
    nan[5][1] = f32::NAN;
    let mut collapsed = twisted(&rest, 50.0, 1.0);
    let t = rest.triangles()[3];
    collapsed[t[1] as usize] = collapsed[t[0] as usize];
    collapsed[t[2] as usize] = collapsed[t[0] as usize];
    let mut zero = rest.normals().to_vec();
    zero[2] = [0.0; 3];
    let moved = twisted(&rest, 50.0, 1.0);
    let cases: Vec<(&str, Result<(), RefineError>)> = vec![
        ("too few", plan.update(&mut frame, &moved[1..], None)),
        ("NaN", plan.update(&mut frame, &nan, None)),
        ("collapsed", plan.update(&mut frame, &collapsed, None)),
        ("zero normal", plan.update(&mut frame, &moved, Some(&zero))),
        (
            "short normals",
            plan.update(&mut frame, &moved, Some(&zero[1..])),
        ),
    ];
    for (what, result) in cases {
        let e = result.expect_err(what);
        assert!(
            matches!(
                (what, &e),
                (
                    "too few",
                    RefineError::Mesh(MeshError::AttributeCount {
                        what: "positions",
                        ..
                    })
                ) | (
                    "NaN",
                    RefineError::Mesh(MeshError::NonFinitePosition { vertex: 5, .. })
                ) | ("collapsed", RefineError::Mesh(MeshError::ZeroArea { .. }))
                    | (
                        "zero normal",
                        RefineError::Mesh(MeshError::ZeroNormal { vertex: 2 })
                    )
                    | (
                        "short normals",
                        RefineError::Mesh(MeshError::AttributeCount {
                            what: "normals",
                            ..
                        })
                    )
            ),
            "{what}: {e}"
        );
        assert!(!e.to_string().is_empty());
        assert_eq!(frame.mesh(), before.mesh(), "{what}: the frame moved");
        assert_eq!(frame.nets(), before.nets(), "{what}: the nets changed");
    }
    assert_eq!(evaluate(&plan, &frame), good);

    // Output too small: refused before anything is written.
    let mut p = vec![[1.0f32; 3]; plan.vertex_count() - 1];
    let e = plan.evaluate(
        &frame,
        VertexOutput::Separate {
            positions: &mut p,
            normals: None,
            uvs: None,
        },
    );
    assert!(matches!(e, Err(RefineError::OutputTooSmall { .. })));
    assert!(p.iter().all(|x| *x == [1.0; 3]));
    // UVs asked of a mesh without them.
    let n = plan.vertex_count();
    let (mut p, mut uv) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 2]; n]);
    let e = plan.evaluate(
        &frame,
        VertexOutput::Separate {
            positions: &mut p,
            normals: None,
            uvs: Some(&mut uv),
        },
    );
    assert!(matches!(e, Err(RefineError::NoUvs)));
    // Overlapping interleaved attributes.
    let mut data = vec![0.0f32; n * 6];
    let format = VertexFormat {
        stride: 6,
        position: 0,
        normal: Some(2),
        uv: None,
    };
    let e = plan.evaluate(
        &frame,
        VertexOutput::Interleaved {
            data: &mut data,
            format,
        },
    );
    assert!(matches!(e, Err(RefineError::BadVertexFormat(_))));
    assert!(data.iter().all(|&x| x == 0.0));
}

#[test]
fn a_plan_refuses_frames_and_meshes_of_another_topology() {
    let a = samples::icosphere(1);
    let b = samples::torus(1.0, 0.3, 8, 6);
    let options = RefineOptions::new(Scheme::Pn, 3);
    let plan_a = Plan::new(&a, &options).unwrap();
    let plan_b = Plan::new(&b, &options).unwrap();
    let mut frame_b = plan_b.frame(&b).unwrap();
    assert!(matches!(
        plan_a.frame(&b),
        Err(RefineError::TopologyMismatch { .. })
    ));
    assert!(matches!(
        plan_a.update(&mut frame_b, a.positions(), None),
        Err(RefineError::ForeignFrame)
    ));
    let n = plan_a.vertex_count();
    let mut p = vec![[0.0f32; 3]; n];
    let e = plan_a.evaluate(
        &frame_b,
        VertexOutput::Separate {
            positions: &mut p,
            normals: None,
            uvs: None,
        },
    );
    assert!(matches!(e, Err(RefineError::ForeignFrame)));
    // Same counts, other triangles: a flipped face.
    let mut t = a.triangles().to_vec();
    t[0].swap(1, 2);
    let flipped = Mesh::new(a.positions().to_vec(), None, None, t).unwrap();
    let e = plan_a.frame(&flipped).unwrap_err();
    assert!(e.to_string().contains("triangle 0"), "{e}");
    // A plan made from one frame serves another frame of the same plan only.
    let mut frame_a = plan_a.frame(&a).unwrap();
    assert!(plan_a.update_from_mesh(&mut frame_a, &flipped).is_err());
    assert!(plan_a.update_from_mesh(&mut frame_a, &a).is_ok());
}

#[test]
fn origin_names_a_face_and_barycentrics_that_evaluate_to_the_vertex() {
    let mesh = samples::creature();
    for weld in [true, false] {
        let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 6).with_weld(weld)).unwrap();
        let out = refine(&mesh, plan.options()).unwrap();
        let (faces, bary) = plan.origin();
        let tol = 1e-5 * diagonal(&mesh);
        for v in 0..plan.vertex_count() {
            let f = faces[v] as usize;
            assert!(f < mesh.face_count(), "vertex {v}: face {f}");
            let l = bary[v].map(f64::from);
            assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-6 && l.iter().all(|&x| x >= 0.0));
            let patch = RefPatch::new(Tri::of(&mesh, f), RefScheme::Pn, RefNormals::Quadratic);
            let err = (d3(out.positions[v]) - patch.position(l)).length();
            assert!(
                err <= tol,
                "vertex {v} (face {f}, {l:?}) is {err} from its origin"
            );
        }
    }
    let mut short = vec![0u32; 3];
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 2)).unwrap();
    let mut bary = vec![[0.0f32; 3]; plan.vertex_count()];
    assert!(plan.write_origin(&mut short, &mut bary).is_err());
}

#[test]
fn a_frame_borrows_its_mesh_until_it_moves_and_owns_a_mesh_given_by_value() {
    let mesh = samples::creature();
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::PnAen, 4)).unwrap();
    let mut borrowed = plan.frame(&mesh).unwrap();
    assert!(std::ptr::eq(borrowed.mesh(), &mesh) && !borrowed.owns_mesh());
    let owned = plan.frame(mesh.clone()).unwrap();
    assert!(owned.owns_mesh());
    let want = evaluate(&plan, &borrowed);
    assert_eq!(evaluate(&plan, &owned), want);
    assert_eq!(evaluate(&plan, &borrowed.clone().into_owned()), want);
    // A refused update leaves the frame borrowing; the first good one gives it its own copy,
    // and the borrowed mesh stays as it was.
    let nan = vec![[f32::NAN; 3]; mesh.vertex_count()];
    assert!(plan.update(&mut borrowed, &nan, None).is_err());
    assert!(!borrowed.owns_mesh());
    let moved = twisted(&mesh, 30.0, 1.2);
    plan.update(&mut borrowed, &moved, None).unwrap();
    assert!(borrowed.owns_mesh());
    assert_eq!(borrowed.mesh().positions(), &moved[..]);
    assert_eq!(mesh.positions(), samples::creature().positions());
    let mut from_owned = owned;
    plan.update(&mut from_owned, &moved, None).unwrap();
    assert_eq!(evaluate(&plan, &from_owned), evaluate(&plan, &borrowed));
}

#[test]
fn a_lod_plan_keeps_the_levels_of_the_mesh_it_was_made_from() {
    use tessella_core::refine::{Levels, Lod};
    let mesh = samples::creature();
    let mut options = RefineOptions::new(Scheme::Pn, 1);
    options.levels = Levels::Lod(Lod::Tolerance {
        max_deviation: 0.01,
    });
    let (plan, mut frame) = Plan::with_frame(&mesh, &options).unwrap();
    let triangles = plan.triangle_count();
    // Twice the size deviates twice as far: a plan made from it refines more ...
    let big: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|p| p.map(|c| 2.0 * c))
        .collect();
    let big_mesh = Mesh::new(big.clone(), None, None, mesh.triangles().to_vec()).unwrap();
    assert!(Plan::new(&big_mesh, &options).unwrap().triangle_count() > triangles);
    // ... while the first plan's frames, moved or made from it, keep the first mesh's levels.
    plan.update(&mut frame, &big, None).unwrap();
    let moved = evaluate(&plan, &frame);
    assert_eq!(moved.triangles.len(), triangles);
    assert_eq!(moved, evaluate(&plan, &plan.frame(&big_mesh).unwrap()));
}
