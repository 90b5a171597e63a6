//! Tessellator spacings and adaptive per-edge levels on the GPU compute path: the same vertex
//! order, indices and (to float rounding) vertices as the CPU's refinement of the same plan,
//! welded and soup, through `gpu_refine` and frame by frame through `GpuEvaluator`, whose
//! per-frame upload stays the size of the coarse data.

mod common;

use common::{assert_same, ctx, torus_with_uvs};
use std::sync::Arc;
use tessella_core::refine::{Evaluator, Levels, Plan, Spacing};
use tessella_core::Named;
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme};
use tessella_gpu::{gpu_refine, gpu_refine_with, GpuEvaluator, GpuOutput, GpuRefineOptions};

/// Pseudo-random per-edge levels in `[1, max]`, integers for the grid (fractional grid levels
/// geomorph), fractional for the tessellator spacings.
fn random_levels(mesh: &Mesh, spacing: Spacing, max: f32, seed: u64) -> Levels {
    let edges = Plan::new(mesh, &RefineOptions::new(Scheme::Pn, 1))
        .unwrap()
        .topology()
        .edges
        .len();
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let levels: Arc<[f32]> = (0..edges)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (state >> 40) as f32 / (1u64 << 24) as f32;
            let x = 1.0 + u * (max - 1.0);
            if spacing == Spacing::Grid {
                x.round()
            } else {
                x
            }
        })
        .collect();
    Levels::PerEdge {
        edges: levels,
        faces: None,
    }
}

fn cases(mesh: &Mesh) -> Vec<(String, RefineOptions)> {
    let mut out = Vec::new();
    for &spacing in Spacing::ALL {
        let uniform = if spacing == Spacing::Grid { 3.0 } else { 4.3 };
        for (name, levels) in [
            ("uniform", Levels::Uniform(uniform)),
            ("per-edge", random_levels(mesh, spacing, 9.0, 7)),
        ] {
            if spacing == Spacing::Grid && name == "uniform" {
                continue; // an integer grid level is the uniform path
            }
            let options = RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(levels);
            out.push((format!("{spacing} {name}"), options));
        }
    }
    // Fractional grid levels geomorph: morphed tile stencils and morphed canonical edge weights.
    let mut fractional = random_levels(mesh, Spacing::FractionalOdd, 9.0, 5);
    if let Levels::PerEdge { edges, .. } = &mut fractional {
        *edges = edges.iter().map(|x| x.max(1.0)).collect();
    }
    for (name, levels) in [
        ("geomorph uniform", Levels::Uniform(3.4)),
        ("geomorph per-edge", fractional),
    ] {
        let options = RefineOptions::new(Scheme::Pn, 1).with_levels(levels);
        out.push((format!("grid {name}"), options));
    }
    out
}

#[test]
fn gpu_refine_equals_the_cpu_for_every_spacing_and_per_edge_levels() {
    for (mesh, scheme) in [
        (samples::icosphere(1), Scheme::Pn),
        (torus_with_uvs(), Scheme::Png1),
        (samples::creature(), Scheme::Pn),
    ] {
        for (name, options) in cases(&mesh) {
            for weld in [true, false] {
                let mut options = options.clone().with_weld(weld);
                options.scheme = scheme;
                let refiner = Refiner::new(&mesh, &options).unwrap();
                assert!(refiner.plan().tiling().is_some(), "{name}: not adaptive");
                let cpu = refiner.refine();
                let gpu = gpu_refine(ctx(), &refiner).unwrap();
                let what = format!("{} {name} weld {weld}", scheme.name());
                assert_eq!(gpu.positions.len(), refiner.plan().vertex_count(), "{what}");
                assert_same(&cpu, &gpu, &mesh, 0.0, &what);
            }
        }
    }
}

#[test]
fn small_chunks_give_the_same_adaptive_output() {
    let mesh = samples::icosphere(1);
    let options = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalEven)
        .with_levels(random_levels(&mesh, Spacing::FractionalEven, 12.0, 3));
    let refiner = Refiner::new(&mesh, &options).unwrap();
    let chunked = GpuRefineOptions {
        max_chunk_items: Some(97),
        ..Default::default()
    };
    let gpu = gpu_refine_with(ctx(), &refiner, &chunked).unwrap();
    assert_same(&refiner.refine(), &gpu, &mesh, 0.0, "chunks of 97");
}

/// Per frame of a fixed adaptive plan only the coarse data travels: the control nets
/// (faces × (K + 6) × 12 bytes) and the coarse positions and normals (V × 24), counted here
/// from the mesh, not from the evaluator; and the frame's vertices equal the CPU's.
#[test]
fn a_deforming_adaptive_frame_uploads_only_the_coarse_data() {
    let mesh = samples::creature();
    let options = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_levels(random_levels(&mesh, Spacing::FractionalOdd, 20.0, 11));
    let plan = Plan::new(&mesh, &options).unwrap();
    let mut frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::new(ctx(), &plan).unwrap();
    let k = 10; // the cubic basis of PN
    let nets = mesh.face_count() as u64 * (k + 6) * 12;
    let coarse = mesh.vertex_count() as u64 * 24;
    let refined = plan.vertex_count() as u64 * 24;
    assert!(
        refined > 10 * (nets + coarse),
        "the output should dwarf the upload"
    );
    for t in 0..3 {
        let s = 1.0 + 0.2 * t as f32;
        let moved: Vec<[f32; 3]> = mesh
            .positions()
            .iter()
            .map(|p| [p[0] * s, p[1], p[2] / s])
            .collect();
        plan.update(&mut frame, &moved, None).unwrap();
        gpu.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
        assert_eq!(gpu.uploaded_bytes(), nets + coarse, "frame {t}");
        let data = gpu.read_back().unwrap();
        let cpu = Refiner::new(frame.mesh(), &options).unwrap().refine();
        for (i, (v, p)) in data.chunks(6).zip(&cpu.positions).enumerate() {
            let d = common::dist([v[0], v[1], v[2]], *p);
            assert!(
                d <= 1e-5 * frame.mesh().diagonal(),
                "frame {t} vertex {i}: {v:?} vs {p:?}"
            );
        }
    }
}

#[test]
fn displacement_of_adaptive_plans_is_refused_with_a_message() {
    let mesh = samples::icosphere(0);
    let options = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_levels(Levels::Uniform(3.5));
    let plan = Plan::new(&mesh, &options).unwrap();
    let displaced = GpuRefineOptions {
        displacement: tessella_gpu::Displacement::Sine {
            amplitude: 0.1,
            frequency: 3.0,
        },
        ..Default::default()
    };
    let err = GpuEvaluator::with_options(ctx(), &plan, &displaced).unwrap_err();
    assert!(err.to_string().contains("displacement"), "{err}");
}
