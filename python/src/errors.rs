//! How core errors become Python exceptions, in one place (documented in `tessella/__init__.py`):
//!
//! | Rust error | Python exception |
//! |---|---|
//! | `MeshError`, `RefineError` (bad mesh, level, alpha, too large) | `ValueError` |
//! | `TagSourceError` (bad tags: unknown vertex, not an edge, out of range, malformed JSON, bad crease angle) | `ValueError` |
//! | `IoError::Read`/`Write`, `TagSourceError::Read` (an unreadable tags file: the OS refused) | `OSError` (`FileNotFoundError`, `PermissionError`, ...) |
//! | other `IoError`s (unknown extension, malformed file, no triangles, bad arrays) | `ValueError` |
//! | wrong array dtype or object type | `TypeError` |
//! | `DisplaceError`, `GpuError::BadOption`/`Refine`/`Displace` (bad displacement, bad mesh) | `ValueError` |
//! | other `GpuError`s (no adapter for `backend="gpu"`, device lost, GPU limits) | `RuntimeError` |

#[cfg(feature = "gpu")]
use pyo3::exceptions::PyRuntimeError;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError,
    PyPermissionError, PyValueError,
};
use pyo3::PyErr;
use std::io::ErrorKind;
use tessella_core::{MeshError, RefineError};
#[cfg(feature = "gpu")]
use tessella_gpu::GpuError;
use tessella_io::tags::TagSourceError;
use tessella_io::IoError;

/// A bad mesh is a bad value.
pub fn mesh_error(e: MeshError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A refinement that cannot be honoured (level 0, too large, bad alpha, bad mesh).
pub fn refine_error(e: RefineError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Tags that could not be gathered: an unreadable tags file is the OS's refusal, anything else
/// (bad JSON, tags that do not fit the mesh, a bad crease angle) a bad value. Messages say where
/// the tags came from (`"in tags.json"`, `"in the tags dict"`, `crease_angle=...`).
pub fn tag_source_error(e: TagSourceError, crease_angle: Option<f64>) -> PyErr {
    match &e {
        TagSourceError::Read { error, .. } => os_error(error.kind(), e.to_string()),
        TagSourceError::CreaseAngle(_) => match crease_angle {
            Some(degrees) => PyValueError::new_err(format!("crease_angle={degrees}: {e}")),
            None => PyValueError::new_err(e.to_string()),
        },
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A GPU error (builds with the `gpu` feature): bad options are bad values; the GPU failing (or
/// missing) is a runtime error, whose message says what to install or to use the CPU backend.
#[cfg(feature = "gpu")]
pub fn gpu_error(e: GpuError) -> PyErr {
    match e {
        GpuError::BadOption(_) | GpuError::Refine(_) | GpuError::Displace(_) => {
            PyValueError::new_err(e.to_string())
        }
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

/// A file error: the OS's refusals keep their `OSError` subclass, bad content is a bad value.
pub fn io_error(e: IoError) -> PyErr {
    let message = e.to_string();
    match &e {
        IoError::Read { source, .. } | IoError::Write { source, .. } => {
            os_error(source.kind(), message)
        }
        _ => PyValueError::new_err(message),
    }
}

/// The `OSError` subclass Python itself raises for `kind`.
pub fn os_error(kind: ErrorKind, message: String) -> PyErr {
    match kind {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
        ErrorKind::NotADirectory => PyNotADirectoryError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}
