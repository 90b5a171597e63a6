//! How core errors become Python exceptions, in one place (documented in `tessella/__init__.py`):
//!
//! | Rust error | Python exception |
//! |---|---|
//! | `MeshError`, `RefineError` (bad mesh, level, alpha, too large) | `ValueError` |
//! | `TagError` (bad tags: unknown vertex, not an edge, out of range, malformed JSON) | `ValueError` |
//! | `IoError::Read`/`Write`, an unreadable tags file (the OS refused) | `OSError` (`FileNotFoundError`, `PermissionError`, ...) |
//! | other `IoError`s (unknown extension, malformed file, no triangles, bad arrays) | `ValueError` |
//! | wrong array dtype or object type | `TypeError` |
//! | `GpuError::BadOption`/`Refine` (bad displacement, bad mesh) | `ValueError` |
//! | other `GpuError`s (no adapter for `backend="gpu"`, device lost, GPU limits) | `RuntimeError` |

use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError,
    PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::PyErr;
use std::io::ErrorKind;
use tessella_core::{MeshError, RefineError, TagError};
use tessella_gpu::GpuError;
use tessella_io::IoError;

/// A bad mesh is a bad value.
pub fn mesh_error(e: MeshError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A refinement that cannot be honoured (level 0, too large, bad alpha, bad mesh).
pub fn refine_error(e: RefineError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Bad tags, with where they came from (`"in tags.json"`, `"in the tags dict"`).
pub fn tag_error(origin: &str, e: TagError) -> PyErr {
    PyValueError::new_err(format!("bad tags {origin}: {e}"))
}

/// A GPU error: bad options are bad values; the GPU failing (or missing) is a runtime error,
/// whose message says what to install or to use the CPU backend.
pub fn gpu_error(e: GpuError) -> PyErr {
    match e {
        GpuError::BadOption(_) | GpuError::Refine(_) => PyValueError::new_err(e.to_string()),
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
