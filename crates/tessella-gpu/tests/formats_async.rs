//! The GPU output in any `VertexFormat` (against the CPU evaluator in the same format), refused
//! formats, and the non-blocking API driven by an executor and a thread polling the device, as
//! a native engine with its own loop would.
mod common;

use common::ctx;
use std::sync::atomic::{AtomicBool, Ordering};
use tessella_core::refine::{CpuEvaluator, Evaluator, Plan, VertexFormat, VertexOutput};
use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{
    AdapterChoice, GpuContext, GpuError, GpuEvaluator, GpuOutput, GpuRefineOptions,
};

/// uv first, then normal, then position, with a float of padding between each: 11 floats.
const SHUFFLED: VertexFormat = VertexFormat {
    stride: 11,
    position: 7,
    normal: Some(3),
    uv: Some(0),
};

fn cpu_vertices(
    plan: &Plan,
    frame: &tessella_core::refine::Frame,
    format: VertexFormat,
) -> Vec<f32> {
    let mut out = vec![f32::NAN; plan.vertex_count() * format.stride];
    CpuEvaluator
        .evaluate(
            plan,
            frame,
            VertexOutput::Interleaved {
                data: &mut out,
                format,
            },
        )
        .unwrap();
    out
}

#[test]
fn a_shuffled_format_with_uvs_in_small_chunks_matches_the_cpu() {
    let mesh = common::torus_with_uvs();
    assert!(mesh.uvs().is_some());
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 5)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::with_options(
        ctx(),
        &plan,
        &GpuRefineOptions {
            vertex_format: Some(SHUFFLED),
            max_chunk_items: Some(41),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(gpu.vertex_bytes(), plan.vertex_count() as u64 * 44);
    gpu.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
    let got = gpu.read_back().unwrap();
    let want = cpu_vertices(&plan, &frame, SHUFFLED);
    assert_eq!(got.len(), want.len());
    let tol = 1e-5 * mesh.diagonal();
    for (v, (g, c)) in got.chunks(11).zip(want.chunks(11)).enumerate() {
        for (k, range, tol) in [
            ("uv", 0..2, 1e-6),
            ("normal", 3..6, 1e-4),
            ("position", 7..10, tol),
        ] {
            for i in range {
                assert!((g[i] - c[i]).abs() <= tol, "vertex {v} {k}: {g:?} vs {c:?}");
            }
        }
        // The CPU leaves NaN in the padding; the GPU's own buffer starts zeroed.
        for i in [2, 6, 10] {
            assert!(
                c[i].is_nan() && g[i] == 0.0,
                "vertex {v} padding {i}: {g:?}"
            );
        }
    }
}

#[test]
fn formats_the_mesh_or_the_layout_cannot_take_are_refused() {
    let mesh = samples::icosphere(0);
    assert!(mesh.uvs().is_none());
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let refused = |format| {
        GpuEvaluator::with_options(
            ctx(),
            &plan,
            &GpuRefineOptions {
                vertex_format: Some(format),
                ..Default::default()
            },
        )
        .map(|_| ())
        .unwrap_err()
    };
    let e = refused(VertexFormat::POSITION_NORMAL_UV);
    assert!(matches!(e, GpuError::BadOption(_)), "{e}");
    assert!(e.to_string().contains("texture coordinates"), "{e}");
    let overlapping = VertexFormat {
        stride: 5,
        position: 0,
        normal: Some(2),
        uv: None,
    };
    let e = refused(overlapping);
    assert!(matches!(e, GpuError::Refine(_)), "{e}");
}

/// `new_async`, `record` + `submit`, `check_async` and `read_back_async` under an executor,
/// with a thread polling the device meanwhile (native wgpu completes maps only when polled).
#[test]
fn the_async_api_refines_as_the_cpu_does() {
    let ctx = pollster::block_on(GpuContext::new_async(AdapterChoice::Software)).unwrap();
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::new(&ctx, &plan).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    gpu.record(&mut encoder, &plan, &frame, GpuOutput::Own)
        .unwrap();
    ctx.submit(encoder).unwrap();
    let done = AtomicBool::new(false);
    let got = std::thread::scope(|s| {
        s.spawn(|| {
            while !done.load(Ordering::Acquire) {
                if ctx.device.poll(wgpu::PollType::Poll).is_err() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        });
        let got = pollster::block_on(async {
            ctx.check_async().await?;
            gpu.read_back_async().await
        });
        done.store(true, Ordering::Release);
        got
    })
    .unwrap();
    let want = cpu_vertices(&plan, &frame, gpu.vertex_format());
    assert_eq!(got.len(), want.len());
    let tol = 1e-5 * mesh.diagonal();
    for (i, (g, c)) in got.iter().zip(&want).enumerate() {
        assert!((g - c).abs() <= tol.max(1e-4), "float {i}: {g} vs {c}");
    }
}
