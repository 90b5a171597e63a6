//! Names the Python API accepts, mapped to core types in this one place. A scheme or backend
//! that lands in the Rust crates is added here and nowhere else; `schemes()` and `backends()`
//! report what this build has, so scripts can adapt.

use pyo3::exceptions::PyValueError;
use pyo3::PyResult;
use tessella_core::{NormalMode, Scheme};

/// Scheme names, in the order `tessella.schemes()` lists them.
pub const SCHEMES: &[&str] = &["flat", "phong", "pn", "png1", "pn-aen", "st"];

/// Backend names `refine` accepts (`tessella.backends()` lists those that work on this machine).
pub const BACKEND_NAMES: &[&str] = &["auto", "cpu", "gpu"];

/// Normal mode names.
pub const NORMAL_MODES: &[&str] = &["linear", "quadratic", "real"];

/// The scheme called `name` (the core's [`Scheme::name`]s, case-insensitive); `alpha` is
/// Phong's shape factor (ignored by other schemes).
pub fn scheme(name: &str, alpha: f64) -> PyResult<Scheme> {
    match name.to_ascii_lowercase().as_str() {
        "flat" => Ok(Scheme::Flat),
        "phong" => Ok(Scheme::Phong {
            alpha: alpha as f32,
        }),
        "pn" => Ok(Scheme::Pn),
        "png1" => Ok(Scheme::Png1),
        // "pn_aen" too: Python keyword-style spelling of the CLI's name.
        "pn-aen" | "pn_aen" => Ok(Scheme::PnAen),
        "st" => Ok(Scheme::ScalarTagged),
        _ => Err(PyValueError::new_err(format!(
            "unknown scheme {name:?}; this build has {SCHEMES:?} (see tessella.schemes())"
        ))),
    }
}

/// The normal mode called `name`; `None` means the scheme's default.
pub fn normal_mode(name: Option<&str>) -> PyResult<Option<NormalMode>> {
    let Some(name) = name else { return Ok(None) };
    match name.to_ascii_lowercase().as_str() {
        "linear" => Ok(Some(NormalMode::Linear)),
        "quadratic" => Ok(Some(NormalMode::Quadratic)),
        "real" => Ok(Some(NormalMode::Real)),
        _ => Err(PyValueError::new_err(format!(
            "unknown normals_mode {name:?}; use one of {NORMAL_MODES:?} or None for the scheme's default"
        ))),
    }
}

/// Which backend runs the work.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// A hardware GPU when there is one (a software adapter is slower than the CPU path),
    /// otherwise the CPU; the CPU also when the GPU fails.
    Auto,
    Cpu,
    /// Any GPU adapter, software (lavapipe) included; an error when there is none.
    Gpu,
}

/// The backend called `name` (case-insensitive).
pub fn backend(name: &str) -> PyResult<Backend> {
    match name.to_ascii_lowercase().as_str() {
        "auto" => Ok(Backend::Auto),
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        _ => Err(PyValueError::new_err(format!(
            "unknown backend {name:?}; use one of {BACKEND_NAMES:?} (tessella.backends() lists \
             those that work here)"
        ))),
    }
}

/// A refinement level from a Python int: 1 or more.
pub fn level(level: i64) -> PyResult<u32> {
    if level < 1 || level > u32::MAX as i64 {
        return Err(PyValueError::new_err(format!(
            "level must be 1 or more (segments per coarse edge), got {level}"
        )));
    }
    Ok(level as u32)
}

/// The largest level [`quality_level`] accepts: its pattern samples the distance from the coarse
/// mesh, and a finer one adds time and memory (about 500 B a point) but no insight.
pub const MAX_QUALITY_LEVEL: u32 = 256;

/// A level for the quality report: 1 to [`MAX_QUALITY_LEVEL`].
pub fn quality_level(value: i64) -> PyResult<u32> {
    let l = level(value)?;
    if l > MAX_QUALITY_LEVEL {
        return Err(PyValueError::new_err(format!(
            "level {l} is too fine for the quality report (it samples every pattern point of every \
             triangle); use a level of {MAX_QUALITY_LEVEL} or less"
        )));
    }
    Ok(l)
}

/// Phong's shape factor must be finite.
pub fn alpha(alpha: f64) -> PyResult<f64> {
    if !alpha.is_finite() {
        return Err(PyValueError::new_err(format!(
            "alpha must be finite (usually within 0..=1), got {alpha}"
        )));
    }
    Ok(alpha)
}
