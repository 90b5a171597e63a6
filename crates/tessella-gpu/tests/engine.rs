//! The engine walk-through (`examples/engine.rs`) against the CPU: its interleaved vertex
//! buffer, filled in its own encoder, holds the CPU evaluator's vertices in its own format
//! (padding untouched); the exported WGSL module gives the same points in the engine's
//! shaders; the engine's errors reach the engine's handler, tessella's its `Result`s.

#[path = "../examples/engine.rs"]
#[allow(dead_code)]
mod engine;

use engine::{ENGINE_FORMAT, PADDING};
use tessella_core::refine::{CpuEvaluator, Evaluator, VertexOutput};
use tessella_gpu::{GpuContext, GpuError, GpuEvaluator, GpuOutput};

fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn the_engine_frame_matches_the_cpu_and_keeps_its_handler() {
    let (device, queue, errors) = engine::open_engine_device().unwrap();
    assert_eq!(
        device.limits().max_storage_buffers_per_shader_stage,
        8,
        "the engine opened its device with WebGPU's default limits"
    );
    let (mesh, plan) = engine::scene().unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let got = engine::run_frame(&device, &queue, &plan, &frame).unwrap();

    // The vertex buffer: the CPU's vertices in the engine's format; padding as the engine
    // left it.
    let stride = ENGINE_FORMAT.stride;
    let mut cpu = vec![PADDING; plan.vertex_count() * stride];
    CpuEvaluator
        .evaluate(
            &plan,
            &frame,
            VertexOutput::Interleaved {
                data: &mut cpu,
                format: ENGINE_FORMAT,
            },
        )
        .unwrap();
    assert_eq!(got.vertices.len(), cpu.len());
    for (v, (g, c)) in got
        .vertices
        .chunks(stride)
        .zip(cpu.chunks(stride))
        .enumerate()
    {
        assert!(
            close(&g[0..3], &c[0..3], 1e-5),
            "vertex {v}: {g:?} vs {c:?}"
        );
        assert!(
            close(&g[4..7], &c[4..7], 1e-4),
            "normal {v}: {g:?} vs {c:?}"
        );
        assert_eq!([g[3], g[7]], [PADDING; 2], "vertex {v}: padding written");
    }

    // The module: `tessella_point(face, pattern vertex)` is the CPU's vertex the plan's
    // indices put at that corner of that pattern triangle.
    let pattern = plan.pattern();
    let per_face = pattern.points.len();
    let n2 = pattern.triangles.len();
    let indices = plan.indices();
    for f in 0..plan.face_count() {
        for (j, tri) in pattern.triangles.iter().enumerate() {
            for c in 0..3 {
                let p = tri[c] as usize;
                let probe = &got.module_points[(f * per_face + p) * 6..][..6];
                let v = indices[f * n2 + j][c] as usize;
                let c = &cpu[v * stride..][..stride];
                assert!(
                    close(&probe[0..3], &c[0..3], 1e-4),
                    "face {f} point {p}: {probe:?} vs {c:?}"
                );
                assert!(
                    close(&probe[3..6], &c[4..7], 1e-3),
                    "face {f} point {p}: {probe:?} vs {c:?}"
                );
            }
        }
    }

    // The two draws show the same surface, and a surface it is.
    let covered = |px: &[u8]| px.chunks(4).filter(|p| p[0] < 250).count();
    let total = (engine::SIZE * engine::SIZE) as usize;
    assert!(
        covered(&got.buffer_picture) > total / 5,
        "the buffer draw drew little"
    );
    let differ = got
        .buffer_picture
        .chunks(4)
        .zip(got.module_picture.chunks(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(
        differ * 100 < total,
        "{differ} of {total} pixels differ between the draws"
    );
    assert!(
        errors.lock().unwrap().is_empty(),
        "tessella's work raised errors in the engine's handler: {:?}",
        errors.lock().unwrap()
    );

    // An error in the engine's own work reaches the engine's handler, and not tessella.
    let ctx = GpuContext::from_device(device.clone(), queue.clone());
    let mut bad = device.create_command_encoder(&Default::default());
    let small = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("engine small"),
        size: 16,
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    bad.copy_buffer_to_buffer(&small, 0, &small, 0, 64); // past the end
    queue.submit([bad.finish()]);
    let seen = errors.lock().unwrap().len();
    assert!(
        seen >= 1,
        "the engine's own error did not reach its handler"
    );
    assert!(ctx.check().is_ok(), "tessella took the engine's error");

    // An error in tessella's call is that call's `Err`, and not the engine's handler's.
    let mut evaluator = GpuEvaluator::new(&ctx, &plan).unwrap();
    let gone = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("destroyed"),
        size: evaluator.vertex_bytes(),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
        mapped_at_creation: false,
    });
    gone.destroy();
    let mut encoder = device.create_command_encoder(&Default::default());
    let recorded = evaluator.record(
        &mut encoder,
        &plan,
        &frame,
        GpuOutput::Buffer {
            buffer: &gone,
            offset: 0,
        },
    );
    let submitted = recorded.and_then(|()| ctx.submit(encoder).map(|_| ()));
    assert!(
        matches!(submitted, Err(GpuError::Validation(_))),
        "{submitted:?}"
    );
    assert_eq!(
        errors.lock().unwrap().len(),
        seen,
        "tessella's error reached the engine's handler"
    );
}
