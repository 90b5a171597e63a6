//! GPU faults give errors, never panics: a destroyed (lost) device, and a device whose buffer
//! limits are far below what the work asks for. Run on the software adapter (lavapipe).
mod common;

use common::PlainShading;

use tessella_core::refine::{Evaluator, Levels, Plan, Spacing};
use tessella_core::{samples, RefineOptions, RefinedMesh, Refiner, Scheme};
use tessella_gpu::{
    gpu_refine_with, AdapterChoice, GpuContext, GpuError, GpuEvaluator, GpuOutput,
    GpuRefineOptions, PatternRenderer, TargetFormats,
};

fn refiner(mesh: &tessella_core::Mesh, level: u32) -> Refiner<'_> {
    Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, level)).unwrap()
}

/// A fresh software device of its own (destroying the shared one would break other tests).
fn own_device(limits: impl FnOnce(wgpu::Limits) -> wgpu::Limits) -> GpuContext {
    let base = common::ctx();
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::PRIMARY))
        .into_iter()
        .find(|a| a.get_info().name == base.info.name)
        .expect("the software adapter again");
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("faults"),
        required_limits: limits(base.limits.clone()),
        ..Default::default()
    }))
    .unwrap();
    GpuContext::from_device(device, queue)
}

#[test]
fn a_lost_device_is_an_error_not_a_panic() {
    let ctx = own_device(|l| l);
    let mesh = samples::by_name("icosphere").unwrap();
    // Works first...
    gpu_refine_with(&ctx, &refiner(&mesh, 4), &GpuRefineOptions::default()).unwrap();
    // ...then the device goes away.
    ctx.device.destroy();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        gpu_refine_with(&ctx, &refiner(&mesh, 4), &GpuRefineOptions::default())
    }));
    let err = result.expect("no panic on a lost device").unwrap_err();
    assert!(
        matches!(err, GpuError::DeviceLost { .. } | GpuError::Validation(_)),
        "{err}"
    );
    let message = err.to_string();
    assert!(!message.is_empty());
}

#[test]
fn work_beyond_the_device_buffer_limits_is_split_or_refused() {
    // 64 KiB bindings and buffers: far below what level 64 needs in one piece.
    let ctx = own_device(|l| wgpu::Limits {
        max_storage_buffer_binding_size: 64 << 10,
        max_buffer_size: 64 << 10,
        ..l
    });
    let mesh = samples::by_name("icosphere").unwrap();
    let refiner = refiner(&mesh, 64);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        gpu_refine_with(&ctx, &refiner, &GpuRefineOptions::default())
    }));
    match result.expect("no panic beyond the limits") {
        Ok(out) => {
            let cpu = refiner.refine();
            common::assert_same(&cpu, &out, &mesh, 0.0, "64 KiB limits");
        }
        Err(err) => {
            assert!(matches!(err, GpuError::TooLarge { .. }), "{err}");
            assert!(err.to_string().contains("CPU backend"), "{err}");
        }
    }
}

#[test]
fn no_adapter_of_a_kind_is_a_clear_error() {
    // Without a hardware adapter (CI), Hardware is refused with what to do; with one, it opens.
    match GpuContext::new(AdapterChoice::Hardware) {
        Ok(ctx) => assert!(!ctx.is_software()),
        Err(e) => {
            assert!(matches!(e, GpuError::NoAdapter { .. }), "{e}");
            assert!(e.to_string().contains("use the CPU backend"), "{e}");
        }
    }
}

fn same_bits(a: &RefinedMesh, b: &RefinedMesh, what: &str) {
    let bits = |m: &RefinedMesh| -> Vec<u32> {
        let mut out: Vec<u32> = m.positions.iter().flatten().map(|x| x.to_bits()).collect();
        out.extend(m.normals.iter().flatten().map(|x| x.to_bits()));
        out
    };
    assert_eq!(bits(a), bits(b), "{what}: vertices");
    assert_eq!(a.triangles, b.triangles, "{what}: triangles");
}

/// Welded and soup, uniform and adaptive (per-edge levels) options on `mesh`.
fn plans(mesh: &tessella_core::Mesh) -> Vec<(String, RefineOptions)> {
    let edges = Plan::new(mesh, &RefineOptions::new(Scheme::Pn, 1))
        .unwrap()
        .topology()
        .edges
        .len();
    let levels = Levels::PerEdge {
        edges: (0..edges).map(|e| 1.0 + (e * 7 % 5) as f32).collect(),
        faces: None,
    };
    let mut out = Vec::new();
    for weld in [true, false] {
        out.push((
            format!("uniform weld {weld}"),
            RefineOptions::new(Scheme::Pn, 3).with_weld(weld),
        ));
        out.push((
            format!("adaptive weld {weld}"),
            RefineOptions::new(Scheme::Pn, 1)
                .with_weld(weld)
                .with_spacing(Spacing::Grid)
                .with_levels(levels.clone()),
        ));
    }
    out
}

/// Control nets split into windows of a few faces (a test cap, and a real binding limit
/// below the nets' size) give the CPU's output, and the unsplit GPU output bit for bit,
/// through `gpu_refine_with` and `GpuEvaluator::evaluate`.
#[test]
fn control_nets_over_one_binding_are_split_by_faces() {
    let mesh = samples::icosphere(1);
    for (what, options) in plans(&mesh) {
        let refiner = Refiner::new(&mesh, &options).unwrap();
        let cpu = refiner.refine();
        let whole = gpu_refine_with(common::ctx(), &refiner, &GpuRefineOptions::default()).unwrap();
        common::assert_same(&cpu, &whole, &mesh, 0.0, &what);
        for cap in [2, 17] {
            let split = GpuRefineOptions {
                max_net_faces: Some(cap),
                max_chunk_items: Some(50),
                ..Default::default()
            };
            let what = format!("{what}, {cap} faces per net window");
            let out = gpu_refine_with(common::ctx(), &refiner, &split).unwrap();
            same_bits(&whole, &out, &what);
            // The frame path (vertex chunks over its own buffer).
            let plan = refiner.plan();
            let mut gpu = GpuEvaluator::with_options(common::ctx(), plan, &split).unwrap();
            gpu.evaluate(plan, refiner.frame(), GpuOutput::Own).unwrap();
            let floats = gpu.read_back().unwrap();
            let expected: Vec<f32> = whole
                .positions
                .iter()
                .zip(&whole.normals)
                .flat_map(|(p, n)| p.iter().chain(n).copied())
                .collect();
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&floats), bits(&expected), "{what}: evaluate");
        }
    }
    // A real limit: 96 KiB bindings, nets of 1280 faces x (10 + 6) x 12 bytes = 240 KiB
    // (uniform plans: the adaptive plans' stencils of every tile exceed 96 KiB themselves).
    let ctx = own_device(|l| wgpu::Limits {
        max_storage_buffer_binding_size: 96 << 10,
        ..l
    });
    let mesh = samples::icosphere(3);
    for (what, options) in plans(&mesh).into_iter().step_by(2) {
        let refiner = Refiner::new(&mesh, &options).unwrap();
        let out = gpu_refine_with(&ctx, &refiner, &GpuRefineOptions::default()).unwrap();
        let whole = gpu_refine_with(common::ctx(), &refiner, &GpuRefineOptions::default()).unwrap();
        same_bits(&whole, &out, &format!("{what}, 96 KiB bindings"));
    }
}

/// The instanced renderer binds all nets at once: nets over one binding are a clear error.
#[test]
fn the_renderer_refuses_nets_over_one_binding() {
    let ctx = own_device(|l| wgpu::Limits {
        max_storage_buffer_binding_size: 96 << 10,
        ..l
    });
    let mesh = samples::icosphere(3);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let formats = TargetFormats {
        color: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth: None,
        samples: 1,
    };
    let plain = PlainShading::new(&ctx, formats);
    let err = PatternRenderer::new(&ctx, &plan, &frame, &plain.shading(), &Default::default())
        .map(|_| ())
        .unwrap_err();
    assert!(
        matches!(err, GpuError::TooLarge { what, .. } if what == "the control nets"),
        "{err}"
    );
    assert!(err.to_string().contains("the control nets"), "{err}");
    assert!(err.to_string().contains("CPU backend"), "{err}");
}

/// WebGPU's default of 8 storage buffers per stage is enough for every path (the CPU gives the
/// same mesh); a device allowing fewer is refused with the limit named, before any GPU call.
#[test]
fn webgpu_default_storage_buffers_suffice_and_fewer_are_refused_clearly() {
    let ctx = own_device(|l| wgpu::Limits {
        max_storage_buffers_per_shader_stage: 8,
        ..l
    });
    let mesh = samples::icosphere(1);
    let refiner = refiner(&mesh, 3);
    let gpu = gpu_refine_with(&ctx, &refiner, &GpuRefineOptions::default()).unwrap();
    let cpu = refiner.refine();
    assert_eq!(gpu.triangles, cpu.triangles);
    for (g, c) in gpu.positions.iter().zip(&cpu.positions) {
        for k in 0..3 {
            assert!((g[k] - c[k]).abs() < 1e-5, "{g:?} vs {c:?}");
        }
    }
    let plan = refiner.plan();
    let frame = plan.frame(&mesh).unwrap();
    let formats = TargetFormats {
        color: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth: None,
        samples: 1,
    };
    let plain = PlainShading::new(&ctx, formats);
    // Both renderers' pipelines (validated when made) fit the 8 storage buffers too.
    PatternRenderer::new(&ctx, plan, &frame, &plain.shading(), &Default::default()).unwrap();
    tessella_gpu::AdaptiveRenderer::new(
        &ctx,
        plan.surface(),
        &frame,
        &plain.shading(),
        Spacing::FractionalOdd,
    )
    .unwrap();
    assert!(ctx.check().is_ok());

    let ctx = own_device(|l| wgpu::Limits {
        max_storage_buffers_per_shader_stage: 4,
        ..l
    });
    let Err(e) = GpuEvaluator::new(&ctx, plan) else {
        panic!("a device with 4 storage buffers per stage was accepted");
    };
    assert!(
        matches!(
            e,
            GpuError::Limit {
                needed: 8,
                allowed: 4,
                ..
            }
        ),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("max_storage_buffers_per_shader_stage"),
        "{e}"
    );
    let Err(e) = PatternRenderer::new(&ctx, plan, &frame, &plain.shading(), &Default::default())
    else {
        panic!("the renderer took a device with 4 storage buffers per stage");
    };
    assert!(e.to_string().contains("vertex stage"), "{e}");
    assert!(ctx.check().is_ok(), "the refusals came before any GPU call");
}

/// A device without storage buffers in the vertex stage (WebGL2, GL ES 3.0: its adapter lacks
/// `DownlevelFlags::VERTEX_STORAGE`) has every vertex-stage reader refused up front, by name and
/// with what still works; the compute path still gives the CPU's mesh on it.
#[test]
fn a_device_without_vertex_storage_refuses_the_renderers_and_keeps_the_compute_path() {
    // lavapipe stores in the vertex stage; the capabilities below are a GL ES 3.0 adapter's.
    let caps = wgpu::DownlevelCapabilities {
        flags: wgpu::DownlevelFlags::all() - wgpu::DownlevelFlags::VERTEX_STORAGE,
        ..Default::default()
    };
    let ctx = own_device(|l| l).with_downlevel(caps);
    let mesh = samples::icosphere(1);
    let refiner = refiner(&mesh, 3);
    let plan = refiner.plan();
    let frame = plan.frame(&mesh).unwrap();
    let formats = TargetFormats {
        color: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth: None,
        samples: 1,
    };
    let plain = PlainShading::new(&ctx, formats);
    let refusals = [
        (
            "the pattern renderer",
            PatternRenderer::new(&ctx, plan, &frame, &plain.shading(), &Default::default())
                .map(|_| ()),
        ),
        (
            "the adaptive renderer",
            tessella_gpu::AdaptiveRenderer::new(
                &ctx,
                plan.surface(),
                &frame,
                &plain.shading(),
                Spacing::FractionalOdd,
            )
            .map(|_| ()),
        ),
        (
            "the exported patch group",
            tessella_gpu::PatchBindings::new(&ctx, plan, &frame, 0, wgpu::ShaderStages::VERTEX)
                .map(|_| ()),
        ),
    ];
    for (name, result) in refusals {
        let Err(e) = result else {
            panic!("{name} was made on a device without vertex-stage storage buffers");
        };
        assert!(
            matches!(e, GpuError::NoVertexStorage { what } if what == name),
            "{name}: {e}"
        );
        let message = e.to_string();
        for needle in ["VERTEX_STORAGE", "vertex stage", "compute path still works"] {
            assert!(message.contains(needle), "{name}: {message}");
        }
    }
    assert!(ctx.check().is_ok(), "the refusals came before any GPU call");

    // The compute path binds no storage buffer in the vertex stage: it still works there, and
    // so does the exported group bound for an engine's compute shader.
    tessella_gpu::PatchBindings::new(&ctx, plan, &frame, 0, wgpu::ShaderStages::COMPUTE).unwrap();
    let gpu = gpu_refine_with(&ctx, &refiner, &GpuRefineOptions::default()).unwrap();
    let cpu = refiner.refine();
    assert_eq!(gpu.triangles, cpu.triangles);
    for (g, c) in gpu.positions.iter().zip(&cpu.positions) {
        for k in 0..3 {
            assert!((g[k] - c[k]).abs() < 1e-5, "{g:?} vs {c:?}");
        }
    }
    assert!(ctx.check().is_ok());

    // A context tessella opens knows its adapter's capabilities (lavapipe: with the flag).
    let own = common::ctx().downlevel().expect("read from the adapter");
    assert!(own.flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE));
}
