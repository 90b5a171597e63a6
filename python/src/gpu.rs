//! The backends behind `refine(backend=...)`: the CPU, and the GPU through tessella-gpu with
//! the CLI's rules (`tessella-cli/src/commands/gpu.rs`, `refine.rs`):
//!
//! - `"cpu"`: [`Refiner::refine`], then [`Displacement::apply`] (`cpu.rs`, shared with
//!   `cpu_only.rs`, the backends of a build without the `gpu` feature).
//! - `"gpu"`: any adapter, software (Mesa's lavapipe) included; an error when there is none.
//! - `"auto"`: a hardware adapter when there is one (a software adapter is slower than the
//!   CPU path), else the CPU; when the GPU fails, the CPU, with a note for a Python warning.
//!
//! Opening a device costs tens of milliseconds, so opened devices are kept for the whole
//! process in two slots (hardware, any). Only two outcomes are remembered: an open device, and
//! "no adapter of this kind" (adapters do not appear while a process runs). Any other failure
//! (the driver refused a device) is tried again on the next call, and a device that reports
//! itself lost is dropped from the cache so the next call opens a fresh one.
//!
//! Everything here runs without the GIL (callers wrap it in `Python::detach`).

use crate::cpu::{self, Outcome};
use crate::errors;
use crate::options::Backend;
use pyo3::PyResult;
use std::sync::{Arc, Mutex, MutexGuard};
use tessella_core::names::Device;
use tessella_core::{RefinedMesh, Refiner};
use tessella_gpu::{
    gpu_refine_with, AdapterChoice, Displacement, GpuContext, GpuError, GpuRefineOptions,
};

/// What one cache slot knows about its kind of adapter.
enum Slot {
    Untried,
    Open(Arc<GpuContext>),
    /// There is no adapter of this kind (the error to repeat).
    Missing(GpuError),
}

static HARDWARE: Mutex<Slot> = Mutex::new(Slot::Untried);
static ANY: Mutex<Slot> = Mutex::new(Slot::Untried);

/// A poisoned lock only means another thread panicked while opening; the slot is still valid.
fn lock(slot: &'static Mutex<Slot>) -> MutexGuard<'static, Slot> {
    slot.lock().unwrap_or_else(|p| p.into_inner())
}

/// The cached device of `choice`, opened on first use.
fn cached(slot: &'static Mutex<Slot>, choice: AdapterChoice) -> Result<Arc<GpuContext>, GpuError> {
    // Held while opening, so two threads never open the same kind of device twice.
    let mut slot = lock(slot);
    match &*slot {
        Slot::Open(ctx) => return Ok(ctx.clone()),
        Slot::Missing(e) => return Err(e.clone()),
        Slot::Untried => {}
    }
    match GpuContext::new(choice) {
        Ok(ctx) => {
            let ctx = Arc::new(ctx);
            *slot = Slot::Open(ctx.clone());
            Ok(ctx)
        }
        Err(e @ GpuError::NoAdapter { .. }) => {
            *slot = Slot::Missing(e.clone());
            Err(e)
        }
        // Not remembered: the next call tries again.
        Err(e) => Err(e),
    }
}

/// A hardware adapter's device (what `"auto"` uses).
pub fn hardware() -> Result<Arc<GpuContext>, GpuError> {
    cached(&HARDWARE, AdapterChoice::Hardware)
}

/// Any adapter's device, a hardware one first (what `"gpu"` uses). Shares the hardware device
/// with `"auto"` rather than opening the same adapter twice.
pub fn any() -> Result<Arc<GpuContext>, GpuError> {
    hardware().or_else(|_| cached(&ANY, AdapterChoice::Auto))
}

/// Drops `ctx` from the cache after it was lost, so the next call reopens a device.
fn forget(ctx: &Arc<GpuContext>) {
    for slot in [&HARDWARE, &ANY] {
        let mut slot = lock(slot);
        if matches!(&*slot, Slot::Open(c) if Arc::ptr_eq(c, ctx)) {
            *slot = Slot::Untried;
        }
    }
}

/// Refines and displaces on `ctx`.
fn on_gpu(
    ctx: &Arc<GpuContext>,
    refiner: &Refiner,
    displacement: &Displacement,
) -> Result<RefinedMesh, GpuError> {
    let options = GpuRefineOptions {
        displacement: displacement.clone(),
        ..Default::default()
    };
    let result = gpu_refine_with(ctx, refiner, &options);
    if matches!(result, Err(GpuError::DeviceLost { .. })) {
        forget(ctx);
    }
    result
}

/// Refines and displaces on the CPU (the reference the GPU path is tested against).
fn on_cpu(refiner: &Refiner, displacement: &Displacement) -> PyResult<RefinedMesh> {
    cpu::refine(refiner, displacement).map_err(|e| errors::gpu_error(e.into()))
}

/// Refines on `backend`.
pub fn refine(
    refiner: &Refiner,
    backend: Backend,
    displacement: &Displacement,
) -> PyResult<Outcome> {
    let done = |mesh| Outcome {
        mesh,
        fallback: None,
    };
    // The core's one choice, on the plan's vertex count (small outputs: the CPU is faster
    // than opening a device, so no probe at all).
    let vertices = refiner.plan().vertex_count() as u64;
    match backend.device(vertices) {
        Device::Cpu => on_cpu(refiner, displacement).map(done),
        Device::Gl => Err(errors::bad_option(crate::options::NO_GL)),
        Device::AnyGpu => {
            let ctx = any().map_err(|e| {
                errors::gpu_failure(format!("backend=\"gpu\" needs a GPU adapter: {e}"))
            })?;
            on_gpu(&ctx, refiner, displacement)
                .map(done)
                .map_err(errors::gpu_error)
        }
        Device::HardwareGpu => {
            // No hardware adapter is the normal case on many machines: the CPU, silently.
            let Ok(ctx) = hardware() else {
                return on_cpu(refiner, displacement).map(done);
            };
            match on_gpu(&ctx, refiner, displacement) {
                Ok(mesh) => Ok(done(mesh)),
                Err(e) if backend.falls_back() => Ok(Outcome {
                    mesh: on_cpu(refiner, displacement)?,
                    fallback: Some(format!(
                        "tessella: the GPU ({}) failed, refined on the CPU instead: {e}",
                        ctx.adapter_label()
                    )),
                }),
                Err(e) => Err(errors::gpu_error(e)),
            }
        }
        _ => Err(crate::options::unsupported_backend(backend)),
    }
}

/// A [`tessella_core::refine::Plan`]'s kernels on a GPU, for `tessella.Refiner`'s frames:
/// compiled and uploaded once, then each frame uploads its coarse nets and reads back.
pub struct FrameGpu {
    evaluator: tessella_gpu::GpuEvaluator,
}

/// The GPU a `Refiner` runs its frames on, by the core's one choice on the plan's vertex
/// count ([`Backend::device`]): `"gpu"` any adapter (an error without one), `"auto"` a
/// hardware one for outputs large enough to gain from it (else, or without one, none: the
/// CPU); `"cpu"` none.
pub fn frame_gpu(
    backend: Backend,
    plan: &tessella_core::refine::Plan,
) -> PyResult<Option<FrameGpu>> {
    let ctx = match backend.device(plan.vertex_count() as u64) {
        Device::Cpu => return Ok(None),
        Device::Gl => return Err(errors::bad_option(crate::options::NO_GL)),
        Device::AnyGpu => any().map_err(|e| {
            errors::gpu_failure(format!("backend=\"gpu\" needs a GPU adapter: {e}"))
        })?,
        Device::HardwareGpu => match hardware() {
            Ok(ctx) => ctx,
            Err(_) => return Ok(None),
        },
        _ => return Err(crate::options::unsupported_backend(backend)),
    };
    let evaluator = tessella_gpu::GpuEvaluator::new(&ctx, plan).map_err(errors::gpu_error)?;
    Ok(Some(FrameGpu { evaluator }))
}

impl FrameGpu {
    /// Evaluates `frame` on the GPU and copies the vertices into `positions` and `normals`
    /// (waits for the GPU).
    pub fn evaluate(
        &mut self,
        plan: &tessella_core::refine::Plan,
        frame: &tessella_core::refine::Frame,
        positions: &mut [[f32; 3]],
        normals: &mut [[f32; 3]],
    ) -> PyResult<()> {
        use tessella_core::refine::Evaluator;
        self.evaluator
            .evaluate(plan, frame, tessella_gpu::GpuOutput::Own)
            .map_err(errors::gpu_error)?;
        let floats = self.evaluator.read_back().map_err(errors::gpu_error)?;
        let stride = self.evaluator.vertex_stride();
        if floats.len() < positions.len() * stride || normals.len() != positions.len() {
            return Err(errors::gpu_failure(format!(
                "the GPU returned {} floats for {} vertices of {stride}",
                floats.len(),
                positions.len()
            )));
        }
        for ((p, n), v) in positions
            .iter_mut()
            .zip(normals.iter_mut())
            .zip(floats.chunks_exact(stride))
        {
            *p = [v[0], v[1], v[2]];
            *n = [v[3], v[4], v[5]];
        }
        Ok(())
    }
}
