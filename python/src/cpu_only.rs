//! The backends of a build without the `gpu` feature (`cargo build --no-default-features`):
//! the same interface as `gpu.rs`, CPU only. `backend="auto"` is the CPU; `backend="gpu"` is a
//! `ValueError` saying the package was built without GPU support.

use crate::cpu::{self, Outcome};
use crate::errors::bad_option;
use crate::options::Backend;
use pyo3::PyResult;
use tessella_core::{Displacement, Refiner};

/// What `backend="gpu"` raises in this build.
pub const NO_GPU: &str = "this tessella package was built without GPU support (the \"gpu\" cargo \
     feature is off); use backend=\"cpu\" or \"auto\", or rebuild with the default features";

/// Refines and displaces on the CPU; `"gpu"` is refused.
pub fn refine(
    refiner: &Refiner,
    backend: Backend,
    displacement: &Displacement,
) -> PyResult<Outcome> {
    if backend == Backend::Gpu {
        return Err(bad_option(NO_GPU));
    }
    if backend == Backend::Gl {
        return Err(bad_option(crate::options::NO_GL));
    }
    let mesh = cpu::refine(refiner, displacement).map_err(|e| bad_option(e.to_string()))?;
    Ok(Outcome {
        mesh,
        fallback: None,
    })
}

/// A plan's kernels on a GPU: none in this build (the type has no values).
pub enum FrameGpu {}

/// `tessella.Refiner`'s GPU: none; `"gpu"` is refused, `"auto"` is the CPU.
pub fn frame_gpu(
    backend: Backend,
    _plan: &tessella_core::refine::Plan,
) -> PyResult<Option<FrameGpu>> {
    match backend {
        Backend::Gpu => Err(bad_option(NO_GPU)),
        Backend::Gl => Err(bad_option(crate::options::NO_GL)),
        Backend::Auto | Backend::Cpu => Ok(None),
        other => Err(crate::options::unsupported_backend(other)),
    }
}

impl FrameGpu {
    /// Never called: no `FrameGpu` exists in this build.
    pub fn evaluate(
        &mut self,
        _plan: &tessella_core::refine::Plan,
        _frame: &tessella_core::refine::Frame,
        _positions: &mut [[f32; 3]],
        _normals: &mut [[f32; 3]],
    ) -> PyResult<()> {
        match *self {}
    }
}
