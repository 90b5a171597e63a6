//! GPU faults give errors, never panics: a destroyed (lost) device, and a device whose buffer
//! limits are far below what the work asks for. Run on the software adapter (lavapipe).
mod common;

use tessella_core::{samples, RefineOptions, Refiner, Scheme};
use tessella_gpu::{gpu_refine_with, AdapterChoice, GpuContext, GpuError, GpuRefineOptions};

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
