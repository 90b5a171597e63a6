//! How core errors become Python exceptions, in one place (documented in `tessella/__init__.py`):
//!
//! | Rust error | Python exception |
//! |---|---|
//! | `MeshError`, `RefineError` (bad mesh, level, alpha, too large) | `ValueError` |
//! | wrong array dtype or object type | `TypeError` |
//! | a backend this build does not have | `NotImplementedError` |

use pyo3::exceptions::PyValueError;
use pyo3::PyErr;
use tessella_core::{MeshError, RefineError};

/// A bad mesh is a bad value.
pub fn mesh_error(e: MeshError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A refinement that cannot be honoured (level 0, too large, bad alpha, bad mesh).
pub fn refine_error(e: RefineError) -> PyErr {
    PyValueError::new_err(e.to_string())
}
