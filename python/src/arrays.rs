//! numpy arrays in and out.
//!
//! Inputs: any array-like (lists too; they go through `numpy.asarray`), of shape `(n, 3)`,
//! C or Fortran order or any other strides (read element by element, no copy of the array
//! first). Points: float32 as is, float64 rounded to float32, integers converted. Indices: int32, int64, uint32,
//! uint64 (also int8/16, uint8/16), checked to be non-negative and below 2³².
//! Outputs: fresh C-ordered float32 `(n, 3)` and uint32 `(m, 3)` arrays that own their memory.

use crate::errors::bad_mesh;
use numpy::ndarray::{Array2, ArrayView2};
use numpy::{Element, PyArray2, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

/// `obj` as a numpy array (`numpy.asarray` for anything else).
fn as_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        return Ok(a.clone());
    }
    let np = obj.py().import("numpy")?;
    let converted = np.call_method1("asarray", (obj,)).map_err(|e| {
        PyTypeError::new_err(format!(
            "{what} must be an array of shape (n, 3); numpy.asarray failed: {e}"
        ))
    })?;
    Ok(converted.cast_into::<PyUntypedArray>()?)
}

/// Checks the shape is `(n, 3)` and returns `n`.
fn check_n_by_3(a: &Bound<'_, PyUntypedArray>, what: &str) -> PyResult<usize> {
    let shape = a.shape();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(bad_mesh(format!(
            "{what} must have shape (n, 3), got {}; reshape it with .reshape(-1, 3)",
            py_shape(shape)
        )));
    }
    Ok(shape[0])
}

/// A shape as Python prints it: `(3,)`, `(3, 2)`.
fn py_shape(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => {
            let parts: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
            format!("({})", parts.join(", "))
        }
    }
}

fn dtype_name(a: &Bound<'_, PyUntypedArray>) -> String {
    a.dtype()
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "?".into())
}

fn rows<T: Element + Copy, U>(
    a: &Bound<'_, PyUntypedArray>,
    f: impl Fn(usize, usize, T) -> PyResult<U>,
) -> Option<PyResult<Vec<[U; 3]>>> {
    let arr = a.extract::<PyReadonlyArray2<T>>().ok()?;
    let view: ArrayView2<T> = arr.as_array();
    Some(
        view.outer_iter()
            .enumerate()
            .map(|(i, r)| Ok([f(i, 0, r[0])?, f(i, 1, r[1])?, f(i, 2, r[2])?]))
            .collect(),
    )
}

/// An `(n, 3)` array of points or normals as float32 rows.
pub fn points(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f32; 3]>> {
    let a = as_array(obj, what)?;
    check_n_by_3(&a, what)?;
    if let Some(r) = rows::<f32, f32>(&a, |_, _, x| Ok(x)) {
        return r;
    }
    // float64 is rounded to the nearest float32; integers (lists like [[0, 0, 1]]) convert too.
    macro_rules! try_dtypes {
        ($($t:ty),*) => {$(
            if let Some(r) = rows::<$t, f32>(&a, |_, _, x| Ok(x as f32)) {
                return r;
            }
        )*};
    }
    try_dtypes!(f64, i64, i32, u32, u64, i16, u16, i8, u8);
    Err(PyTypeError::new_err(format!(
        "{what} must be float32 or float64 (or integers), got dtype {}; convert with .astype(numpy.float64)",
        dtype_name(&a)
    )))
}

/// The `normals=` argument as [`points`], or `None` when it is left out or Python's `None`
/// (the core then computes normals); every function that takes normals reads them here.
pub fn normals(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Vec<[f32; 3]>>> {
    match obj {
        Some(n) if !n.is_none() => Ok(Some(points(n, "normals")?)),
        _ => Ok(None),
    }
}

fn index<T: TryInto<u32> + Copy + std::fmt::Display>(
    what: &str,
) -> impl Fn(usize, usize, T) -> PyResult<u32> + '_ {
    move |i, j, x| {
        x.try_into().map_err(|_| {
            bad_mesh(format!(
                "{what}[{i}, {j}] = {x} is not a vertex index (indices are 0 .. 2**32-1)"
            ))
        })
    }
}

/// An `(m, 3)` array of vertex indices as u32 rows.
pub fn triangles(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[u32; 3]>> {
    let a = as_array(obj, what)?;
    check_n_by_3(&a, what)?;
    // Tried in turn; the first dtype that matches reads the array.
    macro_rules! try_dtypes {
        ($($t:ty),*) => {$(
            if let Some(r) = rows::<$t, u32>(&a, index(what)) {
                return r;
            }
        )*};
    }
    try_dtypes!(i32, i64, u32, u64, i16, u16, i8, u8);
    Err(PyTypeError::new_err(format!(
        "{what} must hold integers (int32, int64, uint32, ...), got dtype {}",
        dtype_name(&a)
    )))
}

/// A named field as it comes in: `(name, float32 (count, width) C-ordered array)`.
pub type FieldIn<'py> = (String, numpy::PyReadonlyArray2<'py, f32>);

/// Rows as a C-ordered `(n, K)` numpy array, moving the buffer (no copy).
pub fn to_numpy<'py, T: Element, const K: usize>(
    py: Python<'py>,
    rows: Vec<[T; K]>,
) -> Bound<'py, PyArray2<T>> {
    let n = rows.len();
    let flat: Vec<T> = rows.into_flattened();
    let array = Array2::from_shape_vec((n, K), flat).expect("n*K elements make an (n, K) array");
    PyArray2::from_owned_array(py, array)
}

/// Mid-edge node rows of second-order faces, `(faces, 3)` (edges 0-1, 1-2, 2-0); a negative
/// entry (or one past `u32`) marks a linear face's edge as [`tessella_core::mesh::NO_MID`].
pub fn mid_nodes(m: &PyReadonlyArray2<'_, i64>, faces: usize) -> PyResult<Vec<[u32; 3]>> {
    let a = m.as_array();
    if a.ncols() != 3 || a.nrows() != faces {
        return Err(bad_mesh(format!(
            "mid-edge nodes must have shape ({faces}, 3), got {:?}",
            a.shape()
        )));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| {
            std::array::from_fn(|k| u32::try_from(r[k]).unwrap_or(tessella_core::mesh::NO_MID))
        })
        .collect())
}

/// Texture coordinates, a float32 `(n, 2)` array (the Python wrapper converts dtypes).
pub fn uvs(a: &PyReadonlyArray2<'_, f32>) -> PyResult<Vec<[f32; 2]>> {
    let view = a.as_array();
    if view.ncols() != 2 {
        return Err(bad_mesh(format!(
            "uvs must have shape (n, 2), got {}",
            py_shape(view.shape())
        )));
    }
    Ok(view.outer_iter().map(|r| [r[0], r[1]]).collect())
}
