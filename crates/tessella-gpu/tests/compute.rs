//! The compute path against the CPU evaluator: same vertices (to 1e-5 of the bounding-box
//! diagonal), same normals, same indices, for every scheme, normal mode and layout.

mod common;

use common::{assert_same, ctx, open_edges, torus_with_uvs};
use tessella_core::displace::{DisplaceFrame, Displacement, HeightMap};
use tessella_core::refine::{Evaluator, Plan, Refiner};
use tessella_core::{samples, Mesh, NormalMode, RefineOptions, RefinedMesh, Scheme};
use tessella_gpu::{gpu_refine, gpu_refine_with, GpuEvaluator, GpuOutput, GpuRefineOptions};

const SCHEMES: [Scheme; 4] = [Scheme::Flat, Scheme::PHONG, Scheme::Pn, Scheme::Png1];
const MODES: [NormalMode; 3] = [NormalMode::Linear, NormalMode::Quadratic, NormalMode::Real];

fn check(mesh: &Mesh, opts: &RefineOptions, what: &str) {
    let refiner = Refiner::new(mesh, opts).expect("valid options");
    let cpu = refiner.refine();
    let gpu = gpu_refine(ctx(), &refiner).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_same(&cpu, &gpu, mesh, 0.0, what);
}

#[test]
fn tetrahedron_every_level_every_scheme() {
    let mesh = samples::tetrahedron();
    for scheme in SCHEMES {
        for level in 1..=32 {
            // Soup at a few levels: each GPU call costs a submission wait on lavapipe.
            for weld in [true, false] {
                if !weld && !matches!(level, 1..=4 | 32) {
                    continue;
                }
                let opts = RefineOptions::new(scheme, level).with_weld(weld);
                check(
                    &mesh,
                    &opts,
                    &format!("tetrahedron {scheme:?} level {level} weld {weld}"),
                );
            }
        }
    }
}

#[test]
fn every_normal_mode_on_several_meshes() {
    let meshes = [
        ("icosphere(1)", samples::icosphere(1)),
        ("torus", samples::torus(1.0, 0.4, 10, 6)),
        ("hard_cube", samples::hard_cube()),
        ("creature", samples::creature()),
    ];
    for (name, mesh) in &meshes {
        for scheme in SCHEMES {
            for mode in MODES {
                let opts = RefineOptions::new(scheme, 5).with_normals(mode);
                check(mesh, &opts, &format!("{name} {scheme:?} {mode:?} level 5"));
            }
        }
    }
}

#[test]
fn every_normal_mode_at_level_32() {
    let mesh = samples::icosphere(1);
    for scheme in SCHEMES {
        for mode in MODES {
            let opts = RefineOptions::new(scheme, 32).with_normals(mode);
            check(
                &mesh,
                &opts,
                &format!("icosphere(1) {scheme:?} {mode:?} level 32"),
            );
        }
    }
}

#[test]
fn uvs_are_interpolated_like_the_cpu() {
    let mesh = torus_with_uvs();
    for weld in [true, false] {
        for level in [1, 4, 9] {
            let opts = RefineOptions::new(Scheme::Pn, level).with_weld(weld);
            check(
                &mesh,
                &opts,
                &format!("torus with uvs level {level} weld {weld}"),
            );
        }
    }
}

#[test]
fn chunked_output_equals_unchunked() {
    // Chunk sizes that split both outputs unevenly, and 1 (every item its own dispatch) on a
    // mesh small enough for that to stay quick.
    let cases = [
        (samples::icosphere(1), 7, vec![63, 64, 1000]),
        (samples::tetrahedron(), 3, vec![1, 5]),
    ];
    for (mesh, level, chunks) in &cases {
        for weld in [true, false] {
            let opts = RefineOptions::new(Scheme::Pn, *level).with_weld(weld);
            let refiner = Refiner::new(mesh, &opts).unwrap();
            let whole = gpu_refine(ctx(), &refiner).unwrap();
            for &chunk in chunks {
                let chunked = gpu_refine_with(
                    ctx(),
                    &refiner,
                    &GpuRefineOptions {
                        max_chunk_items: Some(chunk),
                        ..Default::default()
                    },
                )
                .unwrap();
                // Same kernel, same inputs: bit-identical.
                assert_eq!(whole, chunked, "chunk size {chunk}, weld {weld}");
            }
        }
    }
}

#[test]
fn displacement_on_gpu_matches_cpu_and_keeps_shared_vertices_shared() {
    let mesh = torus_with_uvs();
    let map = HeightMap {
        width: 3,
        height: 2,
        heights: vec![0.0, 0.5, 1.0, 0.25, 0.75, 0.1],
    };
    let cases = [
        Displacement::Sine {
            amplitude: 0.05,
            frequency: 12.0,
        },
        Displacement::Perlin {
            amplitude: 0.1,
            frequency: 3.0,
            seed: 42,
        },
        Displacement::HeightMap {
            amplitude: 0.08,
            map,
        },
    ];
    for d in cases {
        let opts = RefineOptions::new(Scheme::Pn, 6);
        let refiner = Refiner::new(&mesh, &opts).unwrap();
        let mut cpu = refiner.refine();
        let undisplaced = cpu.clone();
        d.apply(&mut cpu, &displace_frame(&refiner)).unwrap();
        let gpu = gpu_refine_with(
            ctx(),
            &refiner,
            &GpuRefineOptions {
                displacement: d.clone(),
                ..Default::default()
            },
        )
        .unwrap();
        // sin/noise on GPU and CPU differ in the last bits; allow 1e-5 of the amplitude more.
        assert_same(&cpu, &gpu, &mesh, 1e-5, &format!("{d:?}"));
        // The displacement really moved vertices (not a no-op passing trivially).
        let moved = undisplaced
            .positions
            .iter()
            .zip(&gpu.positions)
            .filter(|(a, b)| common::dist(**a, **b) > 1e-3)
            .count();
        assert!(
            moved > cpu.positions.len() / 4,
            "{d:?}: only {moved} vertices moved"
        );
        // Shared vertices stay shared: the soup evaluates every coarse edge once per face
        // and displaces each copy on its own; each copy must land on the welded vertex (one
        // slot per edge point), or the displaced surface has cracks.
        let soup = gpu_refine_with(
            ctx(),
            &Refiner::new(&mesh, &opts.clone().with_weld(false)).unwrap(),
            &GpuRefineOptions {
                displacement: d.clone(),
                ..Default::default()
            },
        )
        .unwrap();
        let tol = 1e-5 * mesh.diagonal() + 1e-5;
        for (s, w) in soup.triangles.iter().zip(&gpu.triangles) {
            for c in 0..3 {
                let (a, b) = (soup.positions[s[c] as usize], gpu.positions[w[c] as usize]);
                assert!(
                    common::dist(a, b) <= tol,
                    "{d:?}: soup {a:?} vs welded {b:?}"
                );
            }
        }
    }
}

#[test]
fn height_map_without_uvs_is_a_clear_error() {
    let mesh = samples::icosphere(0);
    let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, 2)).unwrap();
    let d = Displacement::HeightMap {
        amplitude: 1.0,
        map: HeightMap {
            width: 1,
            height: 1,
            heights: vec![1.0],
        },
    };
    let err = gpu_refine_with(
        ctx(),
        &refiner,
        &GpuRefineOptions {
            displacement: d,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("texture coordinates"), "{err}");
}

fn displace_frame(refiner: &Refiner) -> DisplaceFrame {
    DisplaceFrame::new(refiner.mesh(), refiner.topology(), refiner.layout())
}

/// Refines and displaces on the CPU: (undisplaced, displaced).
fn cpu_displaced(refiner: &Refiner, d: &Displacement) -> (RefinedMesh, RefinedMesh) {
    let plain = refiner.refine();
    let mut out = plain.clone();
    d.apply(&mut out, &displace_frame(refiner)).unwrap();
    (plain, out)
}

#[test]
fn displaced_hard_edges_stay_closed_on_the_gpu_as_on_the_cpu() {
    // Split normals: each copy of a hard-edge vertex used to move along its own side's normal
    // and every displaced hard edge opened (192 open edges on the cube at level 8). The shared
    // direction (displace.wgsl's displace_direction, core's FaceFrame::direction) closes them.
    let meshes = [
        ("hard cube", samples::hard_cube()),
        ("half-faceted icosphere", samples::half_faceted_icosphere(1)),
    ];
    let displacements = [
        Displacement::Sine {
            amplitude: 0.08,
            frequency: 7.0,
        },
        Displacement::Perlin {
            amplitude: 0.1,
            frequency: 3.0,
            seed: 5,
        },
    ];
    for (name, mesh) in &meshes {
        let tol = 1e-5 * mesh.diagonal();
        for scheme in [Scheme::Flat, Scheme::PnAen, Scheme::Png1] {
            for weld in [true, false] {
                let opts = RefineOptions::new(scheme, 8).with_weld(weld);
                let refiner = Refiner::new(mesh, &opts).unwrap();
                for d in &displacements {
                    let what = format!("{name} {scheme:?} weld {weld} {d:?}");
                    let (plain, cpu) = cpu_displaced(&refiner, d);
                    let gpu = gpu_refine_with(
                        ctx(),
                        &refiner,
                        &GpuRefineOptions {
                            displacement: d.clone(),
                            ..Default::default()
                        },
                    )
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert_same(&cpu, &gpu, mesh, 1e-5, &what);
                    // PNG1 builds each side's edge curve from that side's normals, so a curved
                    // hard edge is open before displacement; displacement must open no more.
                    let before = open_edges(&plain.positions, &plain.triangles, tol);
                    let scheme_cracks = scheme == Scheme::Png1 && *name != "hard cube";
                    assert_eq!(before == 0, !scheme_cracks, "{what}: {before} open before");
                    let after = open_edges(&gpu.positions, &gpu.triangles, tol);
                    assert_eq!(
                        after, before,
                        "{what}: {after} open on the GPU, {before} before"
                    );
                }
            }
        }
    }
}

#[test]
fn a_deforming_displaced_hard_cube_follows_the_cpu_frame_by_frame() {
    // The evaluator uploads the face records (position means) with every frame: a twisted
    // cube's means turn with it, and stale ones would move the hard edges elsewhere.
    let mesh = samples::hard_cube();
    let d = Displacement::Sine {
        amplitude: 0.1,
        frequency: 5.0,
    };
    let opts = RefineOptions::new(Scheme::PnAen, 6);
    let plan = Plan::new(&mesh, &opts).unwrap();
    let mut frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::with_options(
        ctx(),
        &plan,
        &GpuRefineOptions {
            displacement: d.clone(),
            ..Default::default()
        },
    )
    .unwrap();
    let mut displace = DisplaceFrame::new(&mesh, plan.topology(), plan.layout());
    let tol = 1e-5 * mesh.diagonal();
    for t in 0..3 {
        let (positions, normals) = samples::twist(&mesh, 40.0 * t as f32);
        plan.update(&mut frame, &positions, Some(&normals)).unwrap();
        gpu.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
        let got: Vec<[f32; 3]> = gpu
            .read_back()
            .unwrap()
            .chunks(gpu.vertex_stride())
            .map(|v| [v[0], v[1], v[2]])
            .collect();
        let mut cpu = Refiner::new(frame.mesh(), &opts).unwrap().refine();
        displace.update(frame.mesh());
        d.apply(&mut cpu, &displace).unwrap();
        assert_eq!(got.len(), cpu.positions.len());
        for (i, (a, b)) in cpu.positions.iter().zip(&got).enumerate() {
            let e = common::dist(*a, *b);
            assert!(e <= tol + 1e-5, "frame {t} vertex {i}: cpu {a:?} gpu {b:?}");
        }
        let open = open_edges(&got, plan.indices(), tol);
        assert_eq!(open, 0, "frame {t}: {open} open edges");
    }
}
