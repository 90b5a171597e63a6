//! The GPU evaluator against the CPU evaluator, frame by frame, into its own buffer and into
//! the caller's; and errors that must reach the caller.

mod common;

use common::{ctx, dist, torus_with_uvs};
use tessella_core::refine::{CpuEvaluator, Evaluator, Plan, VertexFormat, VertexOutput};
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{GpuError, GpuEvaluator, GpuOutput, GpuRefineOptions, IndexWidth};

/// `mesh` squashed and bent a little, differently for every `t`.
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

fn cpu_interleaved(plan: &Plan, frame: &tessella_core::refine::Frame) -> Vec<f32> {
    let format = if plan.has_uvs() {
        VertexFormat::POSITION_NORMAL_UV
    } else {
        VertexFormat::POSITION_NORMAL
    };
    let mut data = vec![0.0f32; plan.vertex_count() * format.stride];
    CpuEvaluator
        .evaluate(
            plan,
            frame,
            VertexOutput::Interleaved {
                data: &mut data,
                format,
            },
        )
        .unwrap();
    data
}

/// Interleaved vertices equal: positions within `1e-5 × diagonal`, normals within 1e-4,
/// UVs within 1e-6.
fn assert_close(cpu: &[f32], gpu: &[f32], stride: usize, diagonal: f32, what: &str) {
    assert_eq!(cpu.len(), gpu.len(), "{what}: float count");
    for (i, (a, b)) in cpu.chunks(stride).zip(gpu.chunks(stride)).enumerate() {
        let p = dist([a[0], a[1], a[2]], [b[0], b[1], b[2]]);
        let n = dist([a[3], a[4], a[5]], [b[3], b[4], b[5]]);
        assert!(
            p <= 1e-5 * diagonal,
            "{what}: vertex {i} position {a:?} vs {b:?}"
        );
        assert!(n <= 1e-4, "{what}: vertex {i} normal {a:?} vs {b:?}");
        for k in 6..stride {
            assert!(
                (a[k] - b[k]).abs() <= 1e-6,
                "{what}: vertex {i} uv {a:?} vs {b:?}"
            );
        }
    }
}

#[test]
fn own_buffer_follows_a_deforming_mesh_like_the_cpu() {
    for (mesh, scheme, weld) in [
        (samples::icosphere(1), Scheme::Pn, true),
        (torus_with_uvs(), Scheme::Png1, true),
        (samples::creature(), Scheme::Pn, false),
    ] {
        let plan = Plan::new(&mesh, &RefineOptions::new(scheme, 5).with_weld(weld)).unwrap();
        let mut frame = plan.frame(&mesh).unwrap();
        let mut gpu = GpuEvaluator::new(ctx(), &plan).unwrap();
        let stride = gpu.vertex_stride();
        assert_eq!(stride, if mesh.uvs().is_some() { 8 } else { 6 });
        let mut previous: Option<Vec<f32>> = None;
        for t in 0..3 {
            plan.update(&mut frame, &deformed(&mesh, t), None).unwrap();
            gpu.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
            let got = gpu.read_back().unwrap();
            let want = cpu_interleaved(&plan, &frame);
            let what = format!("{scheme:?} weld {weld} frame {t}");
            assert_close(&want, &got, stride, mesh.diagonal() * 1.5, &what);
            // The buffer really follows the frames (kept, not stale).
            if let Some(p) = &previous {
                assert_ne!(p, &got, "{what}: the vertex buffer did not change");
            }
            previous = Some(got);
        }
    }
}

#[test]
fn caller_buffer_at_an_offset_in_many_chunks_leaves_the_rest_alone() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 6)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let options = GpuRefineOptions {
        max_chunk_items: Some(37),
        ..Default::default()
    };
    let mut gpu = GpuEvaluator::with_options(ctx(), &plan, &options).unwrap();
    // An offset that is not a multiple of the binding alignment, and guard words either side.
    let offset = 12u64;
    let size = offset + gpu.vertex_bytes() + 16;
    let sentinel = vec![0x7fu8; size as usize];
    let buffer = ctx().buffer_init(
        "caller",
        &sentinel,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
    );
    gpu.evaluate(
        &plan,
        &frame,
        GpuOutput::Buffer {
            buffer: &buffer,
            offset,
        },
    )
    .unwrap();
    let bytes = ctx().read_buffer(&buffer, 0, size).unwrap();
    let end = (offset + gpu.vertex_bytes()) as usize;
    assert!(
        bytes[..offset as usize].iter().all(|&b| b == 0x7f),
        "bytes before the offset"
    );
    assert!(
        bytes[end..].iter().all(|&b| b == 0x7f),
        "bytes after the vertices"
    );
    let got: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes[offset as usize..end]);
    assert_close(
        &cpu_interleaved(&plan, &frame),
        &got,
        6,
        mesh.diagonal(),
        "caller buffer",
    );
}

#[test]
fn index_buffers_hold_the_plans_indices() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let mut gpu = GpuEvaluator::new(ctx(), &plan).unwrap();
    let want: Vec<u32> = plan.indices().iter().flatten().copied().collect();
    let (buffer, format) = gpu.index_buffer(&plan).unwrap();
    assert_eq!(format, wgpu::IndexFormat::Uint16, "a small plan fits u16");
    let bytes = ctx().read_buffer(buffer, 0, buffer.size()).unwrap();
    let got: Vec<u16> = bytemuck::pod_collect_to_vec(&bytes[..want.len() * 2]);
    assert_eq!(got.iter().map(|&i| i as u32).collect::<Vec<_>>(), want);
    // u32 into a caller's buffer.
    let usage =
        wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
    let mine = ctx().buffer_init("mine", &vec![0u8; want.len() * 4 + 8], usage);
    gpu.write_indices(&plan, &mine, 8, IndexWidth::U32).unwrap();
    let bytes = ctx().read_buffer(&mine, 8, want.len() as u64 * 4).unwrap();
    assert_eq!(bytemuck::pod_collect_to_vec::<u8, u32>(&bytes), want);
}

#[test]
fn unusable_output_buffers_are_errors_not_panics() {
    let mesh = samples::icosphere(0);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::new(ctx(), &plan).unwrap();
    let need = gpu.vertex_bytes();
    let make = |size, usage| {
        ctx().device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bad"),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let no_storage = make(
        need,
        wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
    );
    let small = make(need - 4, wgpu::BufferUsages::STORAGE);
    let fine = make(need + 4, wgpu::BufferUsages::STORAGE);
    for (buffer, offset, what) in [
        (&no_storage, 0, "STORAGE"),
        (&small, 0, "do not fit"),
        (&fine, 8, "do not fit"),
        (&fine, 2, "multiple of 4"),
    ] {
        let err = gpu
            .evaluate(&plan, &frame, GpuOutput::Buffer { buffer, offset })
            .unwrap_err();
        assert!(matches!(err, GpuError::BadOutput(_)), "{err:?}");
        assert!(err.to_string().contains(what), "{err}");
    }
    // A frame of another plan, and another plan.
    let other = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let other_frame = other.frame(&mesh).unwrap();
    assert!(gpu.evaluate(&plan, &other_frame, GpuOutput::Own).is_err());
    assert!(gpu.evaluate(&other, &other_frame, GpuOutput::Own).is_err());
    // The evaluator still works after refusing.
    gpu.evaluate(
        &plan,
        &frame,
        GpuOutput::Buffer {
            buffer: &fine,
            offset: 4,
        },
    )
    .unwrap();
}

#[test]
fn work_wgpu_rejects_is_an_error_that_reaches_the_caller() {
    let mesh = samples::icosphere(0);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let mut gpu = GpuEvaluator::new(ctx(), &plan).unwrap();
    // Passes every check tessella can make, but is destroyed: wgpu rejects the submission.
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let gone = ctx().buffer_init("gone", &vec![0u8; gpu.vertex_bytes() as usize], usage);
    gone.destroy();
    let err = gpu
        .evaluate(
            &plan,
            &frame,
            GpuOutput::Buffer {
                buffer: &gone,
                offset: 0,
            },
        )
        .unwrap_err();
    assert!(matches!(err, GpuError::Validation(_)), "{err:?}");
    assert!(err.to_string().contains("destroyed"), "{err}");
    // Reading it back is refused too, by submit_and_wait.
    let err = ctx().read_buffer(&gone, 0, 16).unwrap_err();
    assert!(matches!(err, GpuError::Validation(_)), "{err:?}");
    // The error was reported once, to the caller, not left behind for the next user.
    ctx().check().unwrap();
    gpu.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
}
