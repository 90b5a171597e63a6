//! Finite-element refinement: second-order (6-node) faces and solution fields carried to the
//! refined mesh (`tessella.refine(..., point_data=, cell_data=)` and 6-column faces; the
//! Python wrapper in `tessella/_fields.py` prepares the arrays).

use crate::errors::bad_mesh;
use crate::{arrays, displace, errors, gpu, options, F32Array, U32Array};
use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use tessella_core::fields::{copy_cell_data, interpolate_point_data};
use tessella_core::Refiner;

use arrays::FieldIn;
/// A named field as it goes out.
type FieldOut<'py> = (String, Bound<'py, PyArray2<f32>>);

/// `(vertices, faces, normals, face, bary, point_data, cell_data, uvs)`.
type FemArrays<'py> = (
    F32Array<'py>,
    U32Array<'py>,
    F32Array<'py>,
    Bound<'py, PyArray1<i64>>,
    F32Array<'py>,
    Vec<FieldOut<'py>>,
    Vec<FieldOut<'py>>,
    Option<F32Array<'py>>,
);

fn flat_field(name: String, a: PyReadonlyArray2<'_, f32>) -> PyResult<(String, Vec<f32>, usize)> {
    let width = a.as_array().ncols();
    let data = a
        .as_slice()
        .map_err(|_| bad_mesh(format!("field {name:?} must be C-contiguous")))?
        .to_vec();
    Ok((name, data, width))
}

fn field_out(py: Python<'_>, name: String, data: Vec<f32>, width: usize) -> PyResult<FieldOut<'_>> {
    let rows = data.len() / width.max(1);
    let a = Array2::from_shape_vec((rows, width), data)
        .map_err(|e| bad_mesh(format!("field {name:?}: {e}")))?;
    Ok((name, PyArray2::from_owned_array(py, a)))
}

/// Refines a mesh whose faces may carry mid-edge nodes (`mids`: int64 `(m, 3)`, -1 for linear
/// faces) and carries point and cell data through; see `tessella.refine`.
#[pyfunction]
#[pyo3(signature = (vertices, faces, mids=None, normals=None, *, scheme="quadratic", level=8,
                    alpha=0.75, normals_mode=None, backend="auto", weld=true,
                    point_data=Vec::new(), cell_data=Vec::new(), uvs=None))]
#[allow(clippy::too_many_arguments)]
pub fn refine_fem<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    mids: Option<PyReadonlyArray2<'py, i64>>,
    normals: Option<&Bound<'py, PyAny>>,
    scheme: &str,
    level: i64,
    alpha: f64,
    normals_mode: Option<&str>,
    backend: &str,
    weld: bool,
    point_data: Vec<FieldIn<'py>>,
    cell_data: Vec<FieldIn<'py>>,
    uvs: Option<PyReadonlyArray2<'py, f32>>,
) -> PyResult<FemArrays<'py>> {
    let opts = options::grid_options(scheme, alpha, level, normals_mode, weld)?;
    let backend = options::backend(backend)?;
    let mesh = crate::mesh_with_mids_from(py, vertices, faces, mids, normals, uvs)?;
    let point_data = point_data
        .into_iter()
        .map(|(n, a)| flat_field(n, a))
        .collect::<PyResult<Vec<_>>>()?;
    let cell_data = cell_data
        .into_iter()
        .map(|(n, a)| flat_field(n, a))
        .collect::<PyResult<Vec<_>>>()?;
    let displacement = displace::parse(None)?;
    let value = |e: tessella_core::fields::FieldError| bad_mesh(e.to_string());
    let (out, faces_of, bary, pd, cd) = py.detach(|| -> PyResult<_> {
        let refiner = Refiner::new(&mesh, &opts).map_err(errors::refine_error)?;
        let plan = refiner.plan();
        // Fields are checked before the refinement runs.
        let pd = point_data
            .iter()
            .map(|(n, d, w)| {
                Ok((
                    n.clone(),
                    interpolate_point_data(&mesh, plan, n, d, *w).map_err(value)?,
                    *w,
                ))
            })
            .collect::<PyResult<Vec<_>>>()?;
        let cd = cell_data
            .iter()
            .map(|(n, d, w)| {
                Ok((
                    n.clone(),
                    copy_cell_data(plan, n, d, *w).map_err(value)?,
                    *w,
                ))
            })
            .collect::<PyResult<Vec<_>>>()?;
        let out = gpu::refine(&refiner, backend, &displacement)?;
        let (f, b) = plan.origin();
        Ok((out, f, b, pd, cd))
    })?;
    crate::warn_fallback(py, out.fallback)?;
    let out = out.mesh;
    let face = crate::face_ids(py, faces_of);
    let pd = pd
        .into_iter()
        .map(|(n, d, w)| field_out(py, n, d, w))
        .collect::<PyResult<Vec<_>>>()?;
    let cd = cd
        .into_iter()
        .map(|(n, d, w)| field_out(py, n, d, w))
        .collect::<PyResult<Vec<_>>>()?;
    Ok((
        arrays::to_numpy(py, out.positions),
        arrays::to_numpy(py, out.triangles),
        arrays::to_numpy(py, out.normals),
        face,
        arrays::to_numpy(py, bary),
        pd,
        cd,
        out.uvs.map(|u| arrays::to_numpy(py, u)),
    ))
}
