//! `tessella._tessella._refine_to_file` and `_refine_file` (wrapped by `tessella.refine_to_file`
//! and `tessella.refine_file`, in `tessella/_batch.py`): refinements written straight
//! to a file, piece by piece where the plan allows (welded uniform levels), so the output may
//! be far larger than memory; `max_memory` is then the working set, not a cap on the output.
//! Errors are mapped by `crate::errors`, as everywhere in the package: `MeshError`,
//! `OptionError`, `FileFormatError`, and `OSError` for what the system refused (a full disk,
//! a read-only folder, a missing file).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tessella_core::refine::Plan;
use tessella_core::{Mesh, RefineOptions};
use tessella_io::{RefinedSource, WriteOptions};

/// Adds this module's functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(refine_file, m)?)?;
    m.add_function(wrap_pyfunction!(refine_to_file, m)?)?;
    m.add_function(wrap_pyfunction!(sync_folder, m)?)?;
    Ok(())
}

/// Flushes every file of the file system holding `path` to the disk (`syncfs`): the one flush
/// after a batch of files written with `sync=False`.
#[pyfunction]
#[pyo3(name = "_sync_folder")]
fn sync_folder(py: Python<'_>, path: PathBuf) -> PyResult<()> {
    py.detach(|| tessella_io::sync_folder(&path))
        .map_err(crate::errors::io_error)
}

/// The options both functions take.
struct Options {
    refine: RefineOptions,
    write: WriteOptions,
    max_memory: u64,
}

#[allow(clippy::too_many_arguments)]
fn options(
    scheme: &str,
    (level, spacing, lod): (f64, &str, Option<&str>),
    alpha: f64,
    normals_mode: Option<&str>,
    weld: bool,
    ply_ascii: bool,
    max_memory: i64,
    sync: bool,
) -> PyResult<Options> {
    let option = |m: String| crate::errors::bad_option(m);
    let max_memory = u64::try_from(max_memory)
        .ok()
        .filter(|&b| b >= 1 << 20)
        .ok_or_else(|| {
            option(format!(
                "max_memory={max_memory}: give at least 1 MiB (in bytes)"
            ))
        })?;
    // Whole grid levels are the classic refinement; a fractional level or a tessellator
    // spacing makes an adaptive plan, as `tessella.refine` does; `lod` sets a level per edge.
    let refine = crate::options::refine_options(crate::options::Given {
        scheme,
        alpha,
        level: level.to_string(),
        spacing,
        lod,
        normals_mode,
        weld,
        ..Default::default()
    })?;
    Ok(Options {
        refine,
        write: WriteOptions {
            ply_ascii,
            durability: tessella_io::Durability::synced_if(sync),
        },
        max_memory,
    })
}

/// What goes into the file beside the refined mesh: per-vertex fields of the coarse mesh
/// (one value per coarse vertex each) and, with `origin`, each vertex's coarse face and
/// barycentrics (PLY only).
struct Extras {
    fields: Vec<(String, Vec<f32>)>,
    origin: bool,
}

/// Refines `mesh` into `output`, piece by piece, so `max_memory` is the working set, not a
/// cap on the output.
fn write(
    py: Python<'_>,
    mesh: &Mesh,
    output: &Path,
    o: &Options,
    extras: &Extras,
) -> PyResult<Py<PyDict>> {
    tessella_io::Format::from_path(output).map_err(crate::errors::io_error)?;
    let start = Instant::now();
    let mut refine = o.refine.clone();
    refine.max_output_bytes = u64::MAX;
    let (vertices, triangles) = py.detach(|| -> Result<_, PyErr> {
        let (plan, frame) = Plan::with_frame(mesh, &refine).map_err(crate::errors::refine_error)?;
        let mut source = RefinedSource::new(&plan, &frame, o.max_memory)
            .with_fields(&extras.fields)
            .map_err(|e| crate::errors::bad_mesh(e.to_string()))?;
        if extras.origin {
            source = source.with_origin();
        }
        tessella_io::write_streamed(output, &source, &o.write, &|_| {})
            .map_err(crate::errors::io_error)?;
        Ok((plan.vertex_count(), plan.triangle_count()))
    })?;
    let streamed = true;
    let row = PyDict::new(py);
    row.set_item("output", output)?;
    row.set_item("input_triangles", mesh.face_count())?;
    row.set_item("vertices", vertices)?;
    row.set_item("triangles", triangles)?;
    row.set_item("streamed", streamed)?;
    row.set_item("seconds", start.elapsed().as_secs_f64())?;
    Ok(row.unbind())
}

/// Refines the mesh file `input` into the file `output` (format by extension); returns the
/// counts. See `tessella.refine_to_file` for the options.
#[pyfunction]
#[pyo3(name = "_refine_file", signature = (input, output, *, scheme="pn", level=8.0, alpha=0.75, normals_mode=None,
                    weld=true, ply_ascii=false, max_memory=1 << 30, sync=true, origin=false, spacing="grid", lod=None))]
#[allow(clippy::too_many_arguments)]
fn refine_file(
    py: Python<'_>,
    input: PathBuf,
    output: PathBuf,
    scheme: &str,
    level: f64,
    alpha: f64,
    normals_mode: Option<&str>,
    weld: bool,
    ply_ascii: bool,
    max_memory: i64,
    sync: bool,
    origin: bool,
    spacing: &str,
    lod: Option<&str>,
) -> PyResult<Py<PyDict>> {
    let o = options(
        scheme,
        (level, spacing, lod),
        alpha,
        normals_mode,
        weld,
        ply_ascii,
        max_memory,
        sync,
    )?;
    let (mesh, fields) = py
        .detach(|| tessella_io::read_mesh_with_fields(&input))
        .map_err(|e| crate::errors::read_error(e, &input))?;
    // The file's fields go where the output holds them, as `tessella refine` does.
    let fields = match tessella_io::holds_vertex_scalars(&output) {
        true => fields.into_iter().collect(),
        false => Vec::new(),
    };
    write(py, &mesh, &output, &o, &Extras { fields, origin })
}

/// Refines arrays into the file `output`; see `tessella.refine_to_file`.
#[pyfunction]
#[pyo3(name = "_refine_to_file", signature = (vertices, faces, output, normals=None, *, scheme="pn", level=8.0, alpha=0.75,
                    normals_mode=None, weld=true, ply_ascii=false, max_memory=1 << 30, sync=true, origin=false,
                    spacing="grid", lod=None, point_data=Vec::new()))]
#[allow(clippy::too_many_arguments)]
fn refine_to_file(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    output: PathBuf,
    normals: Option<&Bound<'_, PyAny>>,
    scheme: &str,
    level: f64,
    alpha: f64,
    normals_mode: Option<&str>,
    weld: bool,
    ply_ascii: bool,
    max_memory: i64,
    sync: bool,
    origin: bool,
    spacing: &str,
    lod: Option<&str>,
    point_data: Vec<(String, numpy::PyReadonlyArray1<'_, f32>)>,
) -> PyResult<Py<PyDict>> {
    let o = options(
        scheme,
        (level, spacing, lod),
        alpha,
        normals_mode,
        weld,
        ply_ascii,
        max_memory,
        sync,
    )?;
    // mesh_from raises the package's own classes already (MeshError, TypeError for dtypes).
    let mesh = crate::mesh_from(py, vertices, faces, normals)?;
    let fields = point_data
        .iter()
        .map(|(name, values)| Ok((name.clone(), values.as_slice()?.to_vec())))
        .collect::<PyResult<_>>()?;
    write(py, &mesh, &output, &o, &Extras { fields, origin })
}
