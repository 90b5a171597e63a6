//! `tessella._tessella._refine_to_file` (wrapped by `tessella.refine_to_file` and
//! `tessella.refine_file`, in `tessella/_batch.py`): refinements written straight
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

/// The options `_refine_to_file` takes.
struct Options {
    refine: RefineOptions,
    write: WriteOptions,
    max_memory: u64,
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

/// What `_refine_to_file` refines: a mesh file (its per-vertex fields go where the output
/// holds them, as `tessella refine` does), or arrays `(vertices, faces, normals, point_data)`
/// with one value per coarse vertex in each field.
#[derive(FromPyObject)]
enum Source<'py> {
    File(PathBuf),
    Arrays(
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Option<Bound<'py, PyAny>>,
        Vec<(String, numpy::PyReadonlyArray1<'py, f32>)>,
    ),
}

/// Refines `source` (a mesh file's path, or arrays: see [`Source`]) into the file `output`
/// (format by extension); returns the counts. See `tessella.refine_to_file` and
/// `tessella.refine_file` (`tessella/_batch.py`) for the options.
#[pyfunction]
#[pyo3(name = "_refine_to_file", signature = (source, output, *, scheme="pn", level=8.0, alpha=0.75,
                    normals_mode=None, weld=true, ply_ascii=false, max_memory=1 << 30, sync=true, origin=false,
                    spacing="grid", lod=None))]
#[allow(clippy::too_many_arguments)]
fn refine_to_file(
    py: Python<'_>,
    source: Source<'_>,
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
    let o = Options {
        refine,
        write: WriteOptions {
            ply_ascii,
            durability: tessella_io::Durability::synced_if(sync),
        },
        max_memory,
    };
    let (mesh, fields) = match source {
        Source::File(input) => {
            let (mesh, fields) = py
                .detach(|| tessella_io::read_mesh_with_fields(&input))
                .map_err(|e| crate::errors::read_error(e, &input))?;
            // The file's fields go where the output holds them, as `tessella refine` does.
            let fields = match tessella_io::holds_vertex_scalars(&output) {
                true => fields.into_iter().collect(),
                false => Vec::new(),
            };
            (mesh, fields)
        }
        Source::Arrays(vertices, faces, normals, point_data) => {
            // mesh_from raises the package's own classes already (MeshError, TypeError for
            // dtypes).
            let mesh = crate::mesh_from(py, &vertices, &faces, normals.as_ref())?;
            let fields = point_data
                .iter()
                .map(|(name, values)| Ok((name.clone(), values.as_slice()?.to_vec())))
                .collect::<PyResult<_>>()?;
            (mesh, fields)
        }
    };
    write(py, &mesh, &output, &o, &Extras { fields, origin })
}
