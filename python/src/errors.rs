//! How core errors become Python exceptions, in one place. The classes are defined in Python
//! (`tessella/_errors.py`, all subclasses of `TessellaError(ValueError)`) and imported lazily
//! when an error is raised:
//!
//! | Rust error | Python exception |
//! |---|---|
//! | `MeshError`, `RefineError::{Mesh, TopologyMismatch, ForeignFrame}`, bad array shapes or indices, bad fields | `MeshError` |
//! | other `RefineError`s (level, alpha, too large), `TagError`, `TagSourceError` (bad tags, bad crease angle), `DisplaceError`, bad or conflicting options | `OptionError` |
//! | `IoError::{UnknownExtension, Parse, Unsupported, NoTriangles, IndexOutOfRange}` | `FileFormatError` |
//! | `IoError::{Mesh, BadMesh}` (a file's mesh failed validation, arrays a writer refused) | `MeshError` |
//! | `IoError::Refine` (a glTF primitive that cannot be refined): its `RefineError`, as above | `MeshError` or `OptionError` |
//! | `IoError::Read` of a file the opened one refers to (a glTF's missing buffer) | `FileFormatError` |
//! | `AnimationError` from `Poser::new` (a glTF animation the core refuses, `animated.rs`) | `FileFormatError` naming the file |
//! | `AnimationError` posing: an unknown clip, a non-finite time; `AnimationError::Mesh` (a pose's triangles collapse) | `OptionError`; `MeshError` |
//! | `IoError::Read`/`Write`, `TagSourceError::Read` (the OS refused) | `OSError` (`FileNotFoundError`, `PermissionError`, ...) |
//! | `GpuError::BadOption`/`Displace` | `OptionError`; `GpuError::Refine(e)`: as `e` |
//! | other `GpuError`s, `GlError`s but `Unsupported` (no adapter, device lost, GPU limits) | `GpuError` (also a `RuntimeError`) |
//! | wrong array dtype or object type | `TypeError` |

use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError,
    PyPermissionError,
};
use pyo3::PyErr;
use std::io::ErrorKind;
use tessella_core::{MeshError, RefineError};
#[cfg(feature = "gpu")]
use tessella_gpu::GpuError;
use tessella_io::tags::TagSourceError;
use tessella_io::IoError;

/// The Python classes, resolved from `tessella._errors` the first time one is raised.
mod py {
    pyo3::import_exception!(tessella._errors, MeshError);
    pyo3::import_exception!(tessella._errors, OptionError);
    pyo3::import_exception!(tessella._errors, FileFormatError);
    #[cfg(any(feature = "gpu", feature = "gl"))]
    pyo3::import_exception!(tessella._errors, GpuError);
}

/// A bad mesh (positions, indices, shapes, fields).
pub fn bad_mesh(message: impl Into<String>) -> PyErr {
    py::MeshError::new_err(message.into())
}

/// A bad option, or options that conflict.
pub fn bad_option(message: impl Into<String>) -> PyErr {
    py::OptionError::new_err(message.into())
}

/// A broken or unsupported file.
pub fn bad_file(message: impl Into<String>) -> PyErr {
    py::FileFormatError::new_err(message.into())
}

/// The GPU is missing or failed (builds with a GPU or GL backend).
#[cfg(any(feature = "gpu", feature = "gl"))]
pub fn gpu_failure(message: impl Into<String>) -> PyErr {
    py::GpuError::new_err(message.into())
}

/// A bad mesh is a [`bad_mesh`].
pub fn mesh_error(e: MeshError) -> PyErr {
    bad_mesh(e.to_string())
}

/// A refinement that cannot be honoured: the mesh's fault, or the options'.
pub fn refine_error(e: RefineError) -> PyErr {
    match e {
        RefineError::Mesh(_) | RefineError::TopologyMismatch { .. } | RefineError::ForeignFrame => {
            bad_mesh(e.to_string())
        }
        _ => bad_option(e.to_string()),
    }
}

/// Tags that could not be gathered: an unreadable tags file is the OS's refusal, anything else
/// (bad JSON, tags that do not fit the mesh, a bad crease angle) a bad option. Messages say where
/// the tags came from (`"in tags.json"`, `"in the tags dict"`, `crease_angle=...`).
pub fn tag_source_error(e: TagSourceError, crease_angle: Option<f64>) -> PyErr {
    match &e {
        TagSourceError::Read { error, .. } => os_error(error.kind(), e.to_string()),
        TagSourceError::CreaseAngle(_) => match crease_angle {
            Some(degrees) => bad_option(format!("crease_angle={degrees}: {e}")),
            None => bad_option(e.to_string()),
        },
        _ => bad_option(e.to_string()),
    }
}

/// A GPU error (builds with the `gpu` feature): bad options are option errors, a refinement
/// error is mapped as on the CPU; the GPU failing (or missing) is a [`gpu_failure`], whose
/// message says what to install or to use the CPU backend.
#[cfg(feature = "gpu")]
pub fn gpu_error(e: GpuError) -> PyErr {
    match e {
        GpuError::Refine(e) => refine_error(e),
        GpuError::BadOption(_) | GpuError::Displace(_) => bad_option(e.to_string()),
        _ => gpu_failure(e.to_string()),
    }
}

/// A file error: the OS's refusals keep their `OSError` subclass, a mesh that fails validation
/// is a bad mesh, any other bad content a bad file.
pub fn io_error(e: IoError) -> PyErr {
    let message = e.to_string();
    match &e {
        IoError::Read { source, .. } | IoError::Write { source, .. } => {
            os_error(source.kind(), message)
        }
        IoError::Mesh { .. } | IoError::BadMesh { .. } => bad_mesh(message),
        // A part of a file (a glTF primitive) that cannot be refined: as `refine_error`, with
        // the file and the part named.
        IoError::Refine { source, .. } => match source.as_ref() {
            RefineError::Mesh(_)
            | RefineError::TopologyMismatch { .. }
            | RefineError::ForeignFrame => bad_mesh(message),
            _ => bad_option(message),
        },
        _ => bad_file(message),
    }
}

/// An error reading `path`: as [`io_error`], except that the OS refusing a file `path` refers
/// to (a glTF's external buffer) makes `path` a broken file, not an `OSError` about `path`.
pub fn read_error(e: IoError, path: &std::path::Path) -> PyErr {
    match &e {
        IoError::Read { path: other, .. } if other != path => bad_file(e.to_string()),
        _ => io_error(e),
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
