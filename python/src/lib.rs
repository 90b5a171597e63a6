//! `tessella._tessella`: the compiled half of the `tessella` Python package. The pure-Python
//! half (`tessella/__init__.py`) re-exports these functions and adds trimesh/meshio interop.
//!
//! Every function converts its arrays while holding the GIL, then releases it
//! (`Python::detach`) for the work itself, so other Python threads run meanwhile; that includes
//! opening a GPU device and waiting for the GPU (`gpu.rs`).

mod animated;
mod arrays;
mod cpu;
mod displace;
mod errors;
mod fem;
mod gl;
#[cfg(feature = "gpu")]
mod gpu;
// Without the `gpu` feature: the same interface, CPU only (`backend="gpu"` is a ValueError).
#[cfg(not(feature = "gpu"))]
#[path = "cpu_only.rs"]
mod gpu;
mod options;
mod pool;
mod refiner;
mod render;
mod scene;
mod stream;
mod tags;

use errors::bad_option;
use numpy::PyArray2;
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use tessella_core::refine::Ask;
use tessella_core::{Mesh, Pattern, Refiner};
use tessella_io::{MeshView, WriteOptions};

type F32Array<'py> = Bound<'py, PyArray2<f32>>;
type U32Array<'py> = Bound<'py, PyArray2<u32>>;

/// Builds a validated mesh from Python arrays (GIL held only for reading them).
fn mesh_from(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    normals: Option<&Bound<'_, PyAny>>,
) -> PyResult<Mesh> {
    mesh_with_uvs_from(py, vertices, faces, normals, None)
}

/// [`mesh_from`] with texture coordinates (`uvs`: float32 `(n, 2)`, checked by the core).
fn mesh_with_uvs_from(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    normals: Option<&Bound<'_, PyAny>>,
    uvs: Option<numpy::PyReadonlyArray2<'_, f32>>,
) -> PyResult<Mesh> {
    let positions = arrays::points(vertices, "vertices")?;
    let triangles = arrays::triangles(faces, "faces")?;
    let normals = arrays::normals(normals)?;
    let uvs = uvs.map(|u| arrays::uvs(&u)).transpose()?;
    py.detach(|| Mesh::new(positions, normals, uvs, triangles))
        .map_err(errors::mesh_error)
}

/// [`mesh_from`] with second-order faces: `mids` (int64 `(m, 3)`, -1 for a linear face's edges)
/// gives faces their mid-edge nodes.
pub(crate) fn mesh_with_mids_from(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    mids: Option<numpy::PyReadonlyArray2<'_, i64>>,
    normals: Option<&Bound<'_, PyAny>>,
    uvs: Option<numpy::PyReadonlyArray2<'_, f32>>,
) -> PyResult<Mesh> {
    let mesh = mesh_with_uvs_from(py, vertices, faces, normals, uvs)?;
    let Some(mids) = mids else {
        return Ok(mesh);
    };
    let mids = arrays::mid_nodes(&mids, mesh.face_count())?;
    py.detach(|| mesh.with_mid_nodes(mids))
        .map_err(errors::mesh_error)
}

/// A backend's fallback note (the GPU failed, the CPU refined) as a `RuntimeWarning`; `refine`
/// and the FEM refine warn alike. stacklevel 2: the caller of the `tessella.refine` wrapper.
fn warn_fallback(py: Python<'_>, fallback: Option<String>) -> PyResult<()> {
    if let Some(note) = fallback {
        let note = std::ffi::CString::new(note.replace('\0', " "))?;
        PyErr::warn(py, &py.get_type::<PyRuntimeWarning>(), &note, 2)?;
    }
    Ok(())
}

/// The origin's coarse face of each refined vertex as int64, -1 for a coarse vertex no face
/// uses (`u32::MAX` in the core); `origin=True` and the FEM refine return it alike.
fn face_ids(py: Python<'_>, faces: Vec<u32>) -> Bound<'_, numpy::PyArray1<i64>> {
    numpy::PyArray1::from_vec(
        py,
        faces
            .into_iter()
            .map(|x| if x == u32::MAX { -1 } else { x as i64 })
            .collect(),
    )
}

/// What `refine` returns: vertices, faces, normals, the origin (face, bary) when asked for,
/// and the uvs when the input had them.
type RefineArrays<'py> = (
    F32Array<'py>,
    U32Array<'py>,
    F32Array<'py>,
    Option<Bound<'py, numpy::PyArray1<i64>>>,
    Option<F32Array<'py>>,
    Option<F32Array<'py>>,
);

/// Refines a mesh; see `tessella.refine` (the Python wrapper) for the full documentation. Every
/// option of a mesh without fields comes here: the levels (whole, fractional, a tessellator
/// spacing, LOD) through the core's text form, the combinations through the core's
/// [`tessella_core::RefineOptions::conflict`], the backend's choice through the core's.
#[pyfunction]
#[pyo3(signature = (vertices, faces, normals=None, *, scheme="pn", level=8.0, alpha=0.75,
                    normals_mode=None, spacing="grid", lod=None, camera=None, size=None,
                    tags=None, crease_angle=None, backend="auto", weld=true, displace=None,
                    origin=false, uvs=None))]
#[allow(clippy::too_many_arguments)]
fn refine<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    normals: Option<&Bound<'py, PyAny>>,
    scheme: &str,
    level: f64,
    alpha: f64,
    normals_mode: Option<&str>,
    spacing: &str,
    lod: Option<&str>,
    camera: Option<&str>,
    size: Option<(u32, u32)>,
    tags: Option<&Bound<'py, PyAny>>,
    crease_angle: Option<f64>,
    backend: &str,
    weld: bool,
    displace: Option<&Bound<'py, PyAny>>,
    origin: bool,
    uvs: Option<numpy::PyReadonlyArray2<'py, f32>>,
) -> PyResult<RefineArrays<'py>> {
    // A fractional grid level geomorphs (docs/formulas.md, "Geomorphing grid patterns").
    let opts = options::refine_options(options::Given {
        scheme,
        alpha,
        level: level.to_string(),
        spacing,
        lod,
        camera,
        size,
        normals_mode,
        weld,
    })?;
    let backend = options::backend(backend)?;
    let asks = [
        displace.is_some().then_some(Ask::Displace),
        origin.then_some(Ask::Origin),
        uvs.is_some().then_some(Ask::Uvs),
        (backend == options::Backend::Gl).then_some(Ask::GlBackend),
    ];
    options::refuse_conflicts(&opts, asks.into_iter().flatten())?;
    let displacement = displace::parse(displace)?;
    let source = tags::source(tags)?;
    let mesh = mesh_with_uvs_from(py, vertices, faces, normals, uvs)?;
    pool::follow_numpy(py);
    let (out, from) = py.detach(|| -> PyResult<_> {
        let opts = tags::tagged(opts, &mesh, &source, crease_angle)?;
        if backend == options::Backend::Gl {
            let out = cpu::Outcome {
                mesh: gl::refine(&mesh, &opts)?,
                fallback: None,
            };
            return Ok((out, None));
        }
        let refiner = Refiner::new(&mesh, &opts).map_err(errors::refine_error)?;
        let out = gpu::refine(&refiner, backend, &displacement)?;
        Ok((out, origin.then(|| refiner.plan().origin())))
    })?;
    warn_fallback(py, out.fallback)?;
    let (face, bary) = match from {
        Some((f, b)) => (Some(face_ids(py, f)), Some(arrays::to_numpy(py, b))),
        None => (None, None),
    };
    let out = out.mesh;
    Ok((
        pool::to_numpy(py, out.positions)?,
        pool::to_numpy(py, out.triangles)?,
        pool::to_numpy(py, out.normals)?,
        face,
        bary,
        out.uvs.map(|u| pool::to_numpy(py, u)).transpose()?,
    ))
}

/// The uniform refinement pattern of ``level`` segments per edge.
///
/// Returns ``(barycentric, triangles)``: ``barycentric`` is float64 ``((level+1)(level+2)/2, 3)``,
/// the weights ``(l1, l2, l3)`` of the coarse corners ``(P1, P2, P3)``, row by row:
/// point ``(i, j)`` (``j`` outer, ``i`` inner) is ``((N-i-j)/N, i/N, j/N)``. ``triangles`` is
/// uint32 ``(level**2, 3)``, counter-clockwise like the coarse triangle. This is the table every
/// coarse triangle is mapped through; ``weld=False`` output follows its order per face.
///
/// Raises ``ValueError`` for ``level < 1`` or a pattern too large to allocate.
#[pyfunction]
fn pattern<'py>(
    py: Python<'py>,
    level: i64,
) -> PyResult<(Bound<'py, PyArray2<f64>>, U32Array<'py>)> {
    let level = options::level(level)?;
    // A pattern has (N+1)(N+2)/2 points; refuse sizes that cannot be allocated sensibly.
    if Pattern::point_count(level) > 1 << 28 {
        return Err(bad_option(format!(
            "level {level} makes a pattern of {} points; choose a level of 23000 or less",
            Pattern::point_count(level)
        )));
    }
    let p = py.detach(|| Pattern::uniform(level));
    Ok((
        arrays::to_numpy(py, p.points),
        arrays::to_numpy(py, p.triangles),
    ))
}

/// A topology report of a mesh, as a dict.
///
/// Keys: ``vertices``, ``faces``, ``positions`` (distinct positions used by faces), ``edges``
/// (between positions), ``boundary_edges`` (one face), ``non_manifold_edges`` (more than two),
/// ``inconsistent_edges`` (two faces running the same way), ``seam_edges`` (faces meeting at one
/// position through different vertices), ``split_normal_positions``,
/// ``unreferenced_vertices``, ``euler_characteristic`` (V - E + F over positions),
/// ``closed_manifold`` (bool), ``normals_computed`` (bool: no normals given), ``bounds_min``,
/// ``bounds_max`` (lists of 3 floats) and ``diagonal`` (float).
///
/// The arrays are read and validated like ``refine``'s (same exceptions).
#[pyfunction]
#[pyo3(signature = (vertices, faces, normals=None))]
fn info<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    normals: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = mesh_from(py, vertices, faces, normals)?;
    let (report, (lo, hi), diagonal) =
        py.detach(|| (mesh.topology().report, mesh.bounds(), mesh.diagonal()));
    let d = PyDict::new(py);
    d.set_item("vertices", report.vertices)?;
    d.set_item("faces", report.faces)?;
    d.set_item("positions", report.positions)?;
    d.set_item("edges", report.edges)?;
    d.set_item("boundary_edges", report.boundary_edges)?;
    d.set_item("non_manifold_edges", report.non_manifold_edges)?;
    d.set_item("inconsistent_edges", report.inconsistent_edges)?;
    d.set_item("seam_edges", report.seam_edges)?;
    d.set_item("split_normal_positions", report.split_normal_positions)?;
    d.set_item("unreferenced_vertices", report.unreferenced_vertices)?;
    d.set_item("euler_characteristic", report.euler_characteristic)?;
    d.set_item("closed_manifold", report.is_closed_manifold())?;
    d.set_item("normals_computed", mesh.normals_computed())?;
    d.set_item("bounds_min", lo.to_vec())?;
    d.set_item("bounds_max", hi.to_vec())?;
    d.set_item("diagonal", diagonal)?;
    Ok(d)
}

/// Measures a scheme's surface on a mesh; see `tessella.quality` (the Python wrapper) for the
/// full documentation. Returns the core's `QualityReport` as a dict.
#[pyfunction]
#[pyo3(signature = (vertices, faces, normals=None, *, scheme="pn", level=8, alpha=0.75,
                    tags=None, crease_angle=None))]
#[allow(clippy::too_many_arguments)]
fn quality<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    normals: Option<&Bound<'py, PyAny>>,
    scheme: &str,
    level: i64,
    alpha: f64,
    tags: Option<&Bound<'py, PyAny>>,
    crease_angle: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let level = options::quality_level(level)?;
    let opts = options::refine_options(options::Given {
        scheme,
        alpha,
        level: level.to_string(),
        ..Default::default()
    })?;
    let source = tags::source(tags)?;
    let mesh = mesh_from(py, vertices, faces, normals)?;
    let r = py.detach(|| -> PyResult<_> {
        let opts = tags::tagged(opts, &mesh, &source, crease_angle)?;
        tessella_core::quality::report(&mesh, &opts).map_err(errors::refine_error)
    })?;
    // Field by field, in the report's order (tests check the keys against the docs).
    let d = PyDict::new(py);
    d.set_item("scheme", r.scheme)?;
    d.set_item("level", r.level)?;
    d.set_item("edges_checked", r.edges_checked)?;
    d.set_item("samples_per_edge", r.samples_per_edge)?;
    d.set_item("normal_jump_max_deg", r.normal_jump_max_deg)?;
    d.set_item("normal_jump_mean_deg", r.normal_jump_mean_deg)?;
    d.set_item("gap_max", r.gap_max)?;
    d.set_item("gap_max_relative", r.gap_max_relative)?;
    d.set_item("distance_max", r.distance_max)?;
    d.set_item("distance_max_relative", r.distance_max_relative)?;
    d.set_item("diagonal", r.diagonal)?;
    Ok(d)
}

/// Reads a mesh file: ``.obj``, ``.ply`` (ascii or binary), ``.gltf``/``.glb`` or ``.stl``.
///
/// Returns ``(vertices, faces, normals)``: float32 ``(n, 3)``, uint32 ``(m, 3)`` and float32
/// ``(n, 3)`` normals as stored in the file, or ``None`` when it has none (``refine`` then
/// computes them). Polygons are fan-triangulated; texture coordinates are not returned.
///
/// Raises ``OSError`` (``FileNotFoundError``, ``PermissionError``, ...) when the file cannot be
/// read, ``FileFormatError`` when its extension is unknown, its content is malformed or holds
/// no triangles, or a file it refers to (a glTF's buffer) cannot be read.
#[pyfunction]
fn load<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(F32Array<'py>, U32Array<'py>, Option<F32Array<'py>>)> {
    let raw = py
        .detach(|| tessella_io::read_raw(&path))
        .map_err(|e| errors::read_error(e, &path))?;
    Ok((
        arrays::to_numpy(py, raw.positions),
        arrays::to_numpy(py, raw.triangles),
        raw.normals.map(|n| arrays::to_numpy(py, n)),
    ))
}

/// Writes a mesh file; the format follows the extension: ``.obj``, ``.ply`` (binary
/// little-endian, or ascii with ``ply_ascii=True``), ``.gltf``, ``.glb``, ``.stl``.
///
/// ``vertices``/``normals`` are ``(n, 3)`` float arrays, ``faces`` ``(m, 3)`` integers (as for
/// ``refine``). The file is written to a temporary file in the same folder and renamed, so a
/// failure never leaves half a file. STL keeps no normals. ``uvs`` (float32 ``(n, 2)``) are
/// written as texture coordinates where the format has them.
///
/// Raises ``ValueError`` for bad arrays (shapes, indices out of range, non-finite positions,
/// no triangles) or an unknown extension, ``TypeError`` for unsupported dtypes and ``OSError``
/// when the file cannot be written.
#[pyfunction]
#[pyo3(signature = (path, vertices, faces, normals=None, *, ply_ascii=false, uvs=None))]
fn save(
    py: Python<'_>,
    path: PathBuf,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    normals: Option<&Bound<'_, PyAny>>,
    ply_ascii: bool,
    uvs: Option<numpy::PyReadonlyArray2<'_, f32>>,
) -> PyResult<()> {
    let positions = arrays::points(vertices, "vertices")?;
    let triangles = arrays::triangles(faces, "faces")?;
    let normals = arrays::normals(normals)?;
    let uvs = uvs.map(|u| arrays::uvs(&u)).transpose()?;
    if let Some(u) = &uvs {
        if u.len() != positions.len() {
            return Err(errors::bad_mesh(format!(
                "uvs has {} rows, but there are {} vertices",
                u.len(),
                positions.len()
            )));
        }
    }
    let view = MeshView {
        positions: &positions,
        normals: normals.as_deref(),
        uvs: uvs.as_deref(),
        triangles: &triangles,
    };
    py.detach(|| {
        tessella_io::write_mesh(
            &path,
            view,
            &WriteOptions {
                ply_ascii,
                ..Default::default()
            },
        )
    })
    .map_err(errors::io_error)
}

/// Names of the schemes this build has: ``["flat", "phong", "pn", "png1", "pn-aen", "st"]``.
#[pyfunction]
fn schemes() -> Vec<&'static str> {
    options::SCHEMES.to_vec()
}

/// Names of the backends that work on this machine: ``"cpu"``; ``"gpu"`` when a GPU adapter
/// (hardware, or a software one such as Mesa's lavapipe) opens; ``"gl"`` when an OpenGL 4.3
/// context with tessellation shaders opens through EGL (a hardware driver or Mesa's
/// llvmpipe). A package built without the ``gpu`` or ``gl`` cargo feature never lists it.
///
/// The first call opens the GPU device (kept for the process, so ``refine`` reuses it).
/// ``refine(backend="auto")`` picks the GPU only when it is a hardware one; see
/// :func:`gpu_info`.
#[pyfunction]
fn backends(py: Python<'_>) -> Vec<&'static str> {
    #[cfg(feature = "gpu")]
    let gpu = py.detach(|| gpu::any().is_ok());
    #[cfg(not(feature = "gpu"))]
    let gpu = {
        let _ = py;
        false
    };
    let mut names = vec!["cpu"];
    if gpu {
        names.push("gpu");
    }
    if py.detach(gl::available) {
        names.push("gl");
    }
    names
}

/// The GPU adapter ``backend="gpu"`` uses, as a dict, or ``None`` when there is none.
///
/// Keys: ``name`` (the adapter's), ``backend`` (graphics API: ``"Vulkan"``, ``"Metal"``,
/// ``"Dx12"``), ``device_type`` (``"DiscreteGpu"``, ``"IntegratedGpu"``, ``"VirtualGpu"``,
/// ``"Cpu"``, ``"Other"``), ``driver`` and ``driver_info`` (strings, possibly empty) and
/// ``software`` (``True`` for a CPU adapter such as lavapipe: correct but slower than the CPU
/// backend, so ``backend="auto"`` does not use it).
/// Always ``None`` in a package built without the ``gpu`` cargo feature.
#[cfg(not(feature = "gpu"))]
#[pyfunction]
fn gpu_info(_py: Python<'_>) -> PyResult<Option<Bound<'_, PyDict>>> {
    Ok(None)
}

/// The GPU adapter ``backend="gpu"`` uses, as a dict, or ``None`` when there is none.
///
/// Keys: ``name`` (the adapter's), ``backend`` (graphics API: ``"Vulkan"``, ``"Metal"``,
/// ``"Dx12"``), ``device_type`` (``"DiscreteGpu"``, ``"IntegratedGpu"``, ``"VirtualGpu"``,
/// ``"Cpu"``, ``"Other"``), ``driver`` and ``driver_info`` (strings, possibly empty) and
/// ``software`` (``True`` for a CPU adapter such as lavapipe: correct but slower than the CPU
/// backend, so ``backend="auto"`` does not use it).
#[cfg(feature = "gpu")]
#[pyfunction]
fn gpu_info(py: Python<'_>) -> PyResult<Option<Bound<'_, PyDict>>> {
    let Ok(ctx) = py.detach(gpu::any) else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("name", &ctx.info.name)?;
    d.set_item("backend", format!("{:?}", ctx.info.backend))?;
    d.set_item("device_type", format!("{:?}", ctx.info.device_type))?;
    d.set_item("driver", &ctx.info.driver)?;
    d.set_item("driver_info", &ctx.info.driver_info)?;
    d.set_item("software", ctx.is_software())?;
    Ok(Some(d))
}

#[pymodule]
fn _tessella(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(refine, m)?)?;
    m.add_function(wrap_pyfunction!(fem::refine_fem, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(pattern, m)?)?;
    m.add_function(wrap_pyfunction!(info, m)?)?;
    m.add_function(wrap_pyfunction!(quality, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(save, m)?)?;
    stream::register(m)?;
    scene::register(m)?;
    pool::register(m)?;
    m.add_function(wrap_pyfunction!(schemes, m)?)?;
    m.add_function(wrap_pyfunction!(backends, m)?)?;
    m.add_function(wrap_pyfunction!(gpu_info, m)?)?;
    m.add_class::<refiner::Refiner>()?;
    m.add_function(wrap_pyfunction!(animated::load_animated, m)?)?;
    m.add_class::<animated::AnimatedMesh>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
