//! `tessella._tessella._refine_gltf` (wrapped by `tessella.refine_gltf` and
//! `tessella.refine_gltf_bytes`, in `tessella/_gltf.py`): a whole glTF scene read once, every
//! triangle primitive refined with its own level, material, attributes and morph targets, and
//! written back with everything else the document held (`tessella_io::gltf::scene`, the
//! CLI's `tessella refine` with glTF in and out). The scene is read, refined and written with
//! the GIL released.
//!
//! The options are parsed by [`crate::options::refine_options`], as every other function's;
//! the options that work on one merged mesh only (`lod`, `spacing`, `displace`, tags, ...)
//! never reach this function: `tessella/_options.py` refuses them with the CLI's message.
//! Errors are mapped by `crate::errors`: `FileFormatError` for a broken file, `OptionError`
//! for bad options, `MeshError` for a primitive whose mesh cannot be refined, `OSError` for
//! what the system refused.

use crate::errors::{bad_file, bad_option, io_error, read_error};
use crate::options;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::{Path, PathBuf};
use tessella_io::gltf::scene::{
    JointSets, Scene, SceneLevels, SceneOptions, Tangents, MAX_JOINT_SETS,
};
use tessella_io::gltf::Buffers;
use tessella_io::{Durability, Format};

/// Adds this module's functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(refine_gltf, m)?)?;
    Ok(())
}

/// What `_refine_gltf` reads: the bytes of a file (named by `name=`), or a file's path.
#[derive(FromPyObject)]
enum Source<'py> {
    Bytes(Bound<'py, PyBytes>),
    Path(PathBuf),
}

/// One refined primitive: `(mesh, primitive, level, coarse_triangles, degenerate, vertices,
/// triangles, notes)`.
type Report = (usize, usize, u32, usize, usize, usize, usize, Vec<String>);

/// `(reports, warnings, glb)`: one report per triangle primitive, the writer's warnings, and
/// the GLB bytes when no output path was given.
type Outcome<'py> = (Vec<Report>, Vec<String>, Option<Bound<'py, PyBytes>>);

/// Refuses a path whose extension is not glTF's before anything is read (`what`: which
/// argument it is).
fn gltf_path(path: &Path, what: &str) -> PyResult<()> {
    match Format::from_path(path).map_err(io_error)? {
        Format::Gltf | Format::Glb => Ok(()),
        other => Err(bad_file(format!(
            "{what} {}: refine_gltf reads and writes .gltf and .glb scenes, not {} files; \
             tessella.refine_file refines other formats (a glTF file merged into one mesh)",
            path.display(),
            other.name()
        ))),
    }
}

/// Refines the glTF scene `source` (a path, or the bytes of a file called `name` whose
/// external buffers are `buffers`) and writes it to `output` (`.glb` or `.gltf`), or returns
/// it as GLB bytes when `output` is `None`. `level` (default 8) or `max_edge` (a target edge
/// length in world space) chooses each primitive's level; `scheme` is PN by default. See
/// `tessella.refine_gltf`.
#[pyfunction]
#[pyo3(name = "_refine_gltf", signature = (source, output=None, *, name="scene.glb", buffers=Vec::new(),
                    scheme=None, level=None, max_edge=None, alpha=0.75, normals_mode=None,
                    tangents="recomputed", joint_sets=None, sync=true))]
#[allow(clippy::too_many_arguments)]
fn refine_gltf<'py>(
    py: Python<'py>,
    source: Source<'py>,
    output: Option<PathBuf>,
    name: &str,
    buffers: Vec<(String, Bound<'py, PyBytes>)>,
    scheme: Option<&str>,
    level: Option<i64>,
    max_edge: Option<f64>,
    alpha: f64,
    normals_mode: Option<&str>,
    tangents: &str,
    joint_sets: Option<i64>,
    sync: bool,
) -> PyResult<Outcome<'py>> {
    let tangents = Tangents::parse(tangents).ok_or_else(|| {
        bad_option(format!(
            "tangents={tangents:?}: give \"recomputed\" (MikkTSpace on the refined mesh) or \
             \"carried\" (the file's tangents, interpolated)"
        ))
    })?;
    let joint_sets = match joint_sets {
        None => JointSets::AsInput,
        Some(n) => JointSets::parse(&n.to_string()).ok_or_else(|| {
            bad_option(format!(
                "joint_sets={n}: give None (as many sets as the file has) or a number of sets \
                 from 1 to {MAX_JOINT_SETS}"
            ))
        })?,
    };
    let levels = match (level, max_edge) {
        (Some(_), Some(_)) => {
            // `tessella/_options.py` refuses this first, naming the Python function.
            return Err(bad_option(
                "level= cannot be combined with max_edge= (max_edge= chooses each \
                 primitive's level from its edges; pass one of them)",
            ));
        }
        (_, Some(length)) => SceneLevels::MaxEdge(options::max_edge(length)?),
        (level, None) => SceneLevels::Uniform(options::level(level.unwrap_or(8))?),
    };
    // The scheme, alpha and normals as every other function reads them (the level is replaced
    // per primitive by `levels`).
    let refine = options::refine_options(options::Given {
        scheme: scheme.unwrap_or("pn"),
        alpha,
        level: "1".into(),
        normals_mode,
        ..Default::default()
    })?;
    if let Some(output) = &output {
        gltf_path(output, "dst")?;
    }
    let path = match &source {
        Source::Path(path) => {
            gltf_path(path, "src")?;
            Some(path.clone())
        }
        Source::Bytes(_) => {
            gltf_path(Path::new(name), "name=")?;
            None
        }
    };
    let data: Option<&[u8]> = match &source {
        Source::Bytes(bytes) => Some(bytes.as_bytes()),
        Source::Path(_) => None,
    };
    let given: Vec<(&str, &[u8])> = buffers
        .iter()
        .map(|(uri, bytes)| (uri.as_str(), bytes.as_bytes()))
        .collect();
    let options = SceneOptions::new(refine, levels)
        .with_tangents(tangents)
        .with_joint_sets(joint_sets);
    let durability = Durability::synced_if(sync);
    let (reports, warnings, glb) = py.detach(|| -> PyResult<_> {
        let scene = match (&path, data) {
            (Some(path), _) => Scene::read(path).map_err(|e| read_error(e, path))?,
            (None, Some(bytes)) => {
                Scene::from_bytes(name, bytes, Buffers::Given(&given)).map_err(io_error)?
            }
            (None, None) => unreachable!("a source is a path or bytes"),
        };
        let refined = scene.refine(&options).map_err(io_error)?;
        let (warnings, glb) = match &output {
            Some(output) => (refined.write(output, durability).map_err(io_error)?, None),
            None => (Vec::new(), Some(refined.to_glb().map_err(io_error)?)),
        };
        let reports: Vec<Report> = refined
            .primitives
            .iter()
            .zip(&refined.which)
            .map(|(r, &(mesh, primitive))| {
                (
                    mesh,
                    primitive,
                    r.level,
                    r.coarse_triangles,
                    r.degenerate,
                    r.vertices,
                    r.triangles,
                    r.notes.clone(),
                )
            })
            .collect();
        Ok((reports, warnings, glb))
    })?;
    Ok((reports, warnings, glb.map(|b| PyBytes::new(py, &b))))
}
