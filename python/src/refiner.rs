//! `tessella.Refiner`: one mesh topology refined frame after frame (a deforming mesh), on the
//! core's [`Plan`] (built once) and [`Frame`] (moved every frame).
//!
//! - The plan is built from a mesh, because which vertices share a position (what PNG1, PN-AEN
//!   and the scalar-tagged scheme look across) and the tags (split-normal creases,
//!   `crease_angle`, vertex indices) are decided from one: at construction when `vertices=` is
//!   given, else on the first `refine(vertices, ...)` call. Every later call only moves the
//!   frame ([`Plan::update`], O(coarse)) and evaluates into memory.
//! - `backend="gpu"` (or `"auto"` on a hardware GPU, for an output large enough to gain from
//!   it) evaluates on a [`crate::gpu::FrameGpu`]:
//!   the kernels and the plan's tables are uploaded once, each frame uploads its nets and reads
//!   the vertices back.
//! - `out=(v, n)` writes into the caller's float32 C-contiguous writable `(N, 3)` arrays with
//!   the GIL released; without it, fresh arrays are returned.
//! - A bad frame (wrong vertex count, NaN positions, zero normals, a degenerate triangle) raises
//!   `MeshError` and changes nothing: the frame stays where it was and `out` is not written.
//! - The refined faces are computed once ([`Plan::indices`]) into one read-only uint32 array,
//!   returned by every call and by the `faces` property.
//! - Pickling (`tessella.Refiner.__reduce__`, in Python) stores `_state()`: the arguments and
//!   the mesh the plan was built from, so unpickling rebuilds the same plan.
//!
//! The same error mapping as `tessella.refine` (`errors.rs`).

use crate::arrays;
use crate::errors;
use crate::errors::{bad_mesh, bad_option};
use crate::options::{self, Backend};
use crate::tags::{self, TagSource};
use numpy::{PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict};
use tessella_core::refine::{Frame, Plan, VertexOutput};
use tessella_core::{Mesh, RefineOptions, Scheme};

type F32Array<'py> = Bound<'py, PyArray2<f32>>;
type U32Array<'py> = Bound<'py, PyArray2<u32>>;

/// What pickling stores: the faces, the keyword arguments, and the mesh the plan was built from.
type State<'py> = (
    U32Array<'py>,
    Bound<'py, PyDict>,
    Option<(F32Array<'py>, Option<F32Array<'py>>)>,
);

/// What the first frame builds: the plan, the current frame and the faces array.
struct Built {
    plan: Plan,
    /// Owns the first frame's mesh (moved in, not copied), which it moves every frame.
    frame: Frame<'static>,
    /// `plan.indices()` as a read-only numpy array, made once.
    faces: Py<PyArray2<u32>>,
    /// The GPU evaluating the frames (`None`: the CPU).
    gpu: Option<crate::gpu::FrameGpu>,
    /// The mesh the plan was built from (positions, normals), so a pickled refiner rebuilds
    /// the same plan.
    planned: (Vec<[f32; 3]>, Option<Vec<[f32; 3]>>),
}

/// Refines one mesh topology frame after frame; see `tessella.Refiner` (the Python docs).
#[pyclass(module = "tessella._tessella", name = "Refiner", subclass)]
pub struct Refiner {
    /// The coarse triangles, fixed at construction.
    triangles: Vec<[u32; 3]>,
    scheme: Scheme,
    /// Options without tags (they are gathered from the first mesh).
    options: RefineOptions,
    tag_source: TagSource,
    crease_angle: Option<f64>,
    backend: Backend,
    /// The arguments as given, for pickling: alpha, normals_mode, tags, backend.
    given: (f64, Option<String>, Option<Py<PyAny>>, String),
    built: Option<Built>,
}

/// An array `out=` names, checked: float32, `(vertices, 3)`, C-contiguous (writable is checked
/// when it is borrowed for writing, [`borrow_error`]).
fn check_out<'py>(obj: &Bound<'py, PyAny>, what: &str, vertices: usize) -> PyResult<F32Array<'py>> {
    let a = obj.cast::<PyArray2<f32>>().map_err(|_| {
        let got = match obj.cast::<numpy::PyUntypedArray>() {
            Ok(u) => format!(
                "a {}-dimensional array of dtype {}",
                u.ndim(),
                u.dtype()
                    .str()
                    .map(|s| s.to_string())
                    .unwrap_or_else(|_| "?".into())
            ),
            Err(_) => obj
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_else(|_| "?".into()),
        };
        bad_option(format!(
            "out {what} must be a float32 numpy array of shape ({vertices}, 3), got {got}; \
             make it with numpy.empty(({vertices}, 3), dtype=numpy.float32)"
        ))
    })?;
    let shape = a.shape();
    if shape != [vertices, 3] {
        return Err(bad_option(format!(
            "out {what} must have shape ({vertices}, 3) (the refined vertex count), got ({}, {})",
            shape[0], shape[1]
        )));
    }
    if !a.is_c_contiguous() {
        return Err(bad_option(format!(
            "out {what} must be C-contiguous (a view with strides cannot be written in place); \
             use numpy.ascontiguousarray or numpy.empty(({vertices}, 3), dtype=numpy.float32)"
        )));
    }
    Ok(a.clone())
}

/// Why an `out` array cannot be written: read-only, or sharing memory with the other one (or
/// borrowed elsewhere).
fn borrow_error(what: &str, e: numpy::BorrowError) -> PyErr {
    match e {
        numpy::BorrowError::NotWriteable => bad_option(format!(
            "out {what} is read-only (its WRITEABLE flag is off); pass a writable array"
        )),
        _ => bad_option(format!(
            "out {what} cannot be written: it shares memory with the other out array (out[0] \
             and out[1] must be two separate arrays) or is being written elsewhere"
        )),
    }
}

/// A validated mesh of one frame: `triangles` at `vertices` (GIL held only for reading them).
fn frame_mesh(
    py: Python<'_>,
    triangles: &[[u32; 3]],
    vertices: &Bound<'_, PyAny>,
    normals: Option<&Bound<'_, PyAny>>,
) -> PyResult<Mesh> {
    let positions = arrays::points(vertices, "vertices")?;
    let normals = arrays::normals(normals)?;
    let triangles = triangles.to_vec();
    py.detach(|| Mesh::new(positions, normals, None, triangles))
        .map_err(errors::mesh_error)
}

/// `&mut [f32]` of `3k` floats as `k` rows.
fn as_rows(flat: &mut [f32]) -> &mut [[f32; 3]] {
    let rows = flat.len() / 3;
    // SAFETY: `[f32; 3]` has the size of three `f32`s and their alignment, and `rows * 3`
    // floats lie inside `flat`, which stays mutably borrowed for the result's lifetime.
    unsafe { std::slice::from_raw_parts_mut(flat.as_mut_ptr().cast::<[f32; 3]>(), rows) }
}

impl Refiner {
    /// The uniform grid level (a `Refiner` takes a whole `level=`).
    fn grid_level(&self) -> u32 {
        self.options.uniform_grid_level().unwrap_or(1)
    }

    /// Builds the plan and the first frame from `mesh` (the first call), which the frame keeps.
    fn build(&self, py: Python<'_>, mesh: Mesh) -> PyResult<Built> {
        let backend = self.backend;
        let planned = (
            mesh.positions().to_vec(),
            (!mesh.normals_computed()).then(|| mesh.normals().to_vec()),
        );
        let (plan, frame, gpu) = py.detach(|| -> PyResult<_> {
            let opts = tags::tagged(
                self.options.clone(),
                &mesh,
                &self.tag_source,
                self.crease_angle,
            )?;
            let (plan, frame) = Plan::with_frame(mesh, &opts).map_err(errors::refine_error)?;
            plan.indices();
            let gpu = crate::gpu::frame_gpu(backend, &plan)?;
            Ok((plan, frame, gpu))
        })?;
        let faces = arrays::to_numpy(py, plan.indices().to_vec());
        faces.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
        Ok(Built {
            plan,
            frame,
            faces: faces.unbind(),
            gpu,
            planned,
        })
    }
}

#[pymethods]
impl Refiner {
    #[new]
    #[pyo3(signature = (faces, *, vertices=None, normals=None, scheme="pn", level=8, alpha=0.75,
                        normals_mode=None, tags=None, crease_angle=None, backend="auto",
                        weld=true))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        faces: &Bound<'_, PyAny>,
        vertices: Option<&Bound<'_, PyAny>>,
        normals: Option<&Bound<'_, PyAny>>,
        scheme: &str,
        level: i64,
        alpha: f64,
        normals_mode: Option<&str>,
        tags: Option<&Bound<'_, PyAny>>,
        crease_angle: Option<f64>,
        backend: &str,
        weld: bool,
    ) -> PyResult<Self> {
        let opts = options::grid_options(scheme, alpha, level, normals_mode, weld)?;
        let scheme = opts.scheme;
        scheme.validate().map_err(errors::refine_error)?;
        let backend_choice = options::backend(backend)?;
        if backend_choice == Backend::Gl {
            return Err(bad_option(
                "Refiner runs on the CPU or the GPU (backend=\"gl\" is not supported by \
                 Refiner); use tessella.refine(..., backend=\"gl\", spacing=\"equal\") for the GL \
                 tessellator",
            ));
        }
        #[cfg(not(feature = "gpu"))]
        if backend_choice == Backend::Gpu {
            return Err(bad_option(crate::gpu::NO_GPU));
        }
        if let Some(degrees) = crease_angle {
            if !(0.0..=180.0).contains(&degrees) {
                return Err(bad_option(format!(
                    "crease_angle={degrees}: the angle must lie in 0..180 degrees"
                )));
            }
        }
        let tag_source = tags::source(tags)?;
        let triangles = arrays::triangles(faces, "faces")?;
        if triangles.is_empty() {
            return Err(bad_mesh("faces holds no triangles"));
        }
        let mut refiner = Refiner {
            triangles,
            scheme,
            options: opts,
            tag_source,
            crease_angle,
            backend: backend_choice,
            given: (
                alpha,
                normals_mode.map(str::to_owned),
                tags.filter(|t| !t.is_none()).map(|t| t.clone().unbind()),
                backend.to_owned(),
            ),
            built: None,
        };
        // With a first frame the plan is built now (its errors raised here).
        if let Some(vertices) = vertices.filter(|v| !v.is_none()) {
            let mesh = frame_mesh(py, &refiner.triangles, vertices, normals)?;
            refiner.built = Some(refiner.build(py, mesh)?);
        }
        Ok(refiner)
    }

    /// Refines one frame; see `tessella.Refiner.refine` (the Python docs).
    #[pyo3(signature = (vertices, normals=None, *, out=None))]
    fn refine<'py>(
        &mut self,
        py: Python<'py>,
        vertices: &Bound<'py, PyAny>,
        normals: Option<&Bound<'py, PyAny>>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(F32Array<'py>, U32Array<'py>, F32Array<'py>)> {
        let positions = arrays::points(vertices, "vertices")?;
        let normals = arrays::normals(normals)?;
        // `out` is read before the frame moves, so a bad `out` changes nothing either.
        let out_pair = match out.filter(|o| !o.is_none()) {
            None => None,
            Some(o) => {
                let pair: (Bound<'py, PyAny>, Bound<'py, PyAny>) = o.extract().map_err(|_| {
                    bad_option(
                        "out must be a tuple (vertices, normals) of two float32 (N, 3) arrays",
                    )
                })?;
                Some(pair)
            }
        };
        // The first frame builds the plan from its mesh (already at this frame's positions);
        // later frames move it. `update` is `Some` for those.
        let update = match self.built {
            Some(_) => Some((positions, normals)),
            None => {
                let triangles = self.triangles.clone();
                let mesh = py
                    .detach(|| Mesh::new(positions, normals, None, triangles))
                    .map_err(errors::mesh_error)?;
                let built = self.build(py, mesh)?;
                self.built = Some(built);
                None
            }
        };
        let built = self.built.as_mut().expect("built above");
        let count = built.plan.vertex_count();
        let faces = built.faces.bind(py).clone();
        // Both paths write into numpy arrays: the caller's, or fresh ones (numpy's allocator, so
        // tracemalloc and numpy's memory accounting see them).
        let (v, n) = match out_pair {
            Some((v_obj, n_obj)) => (
                check_out(&v_obj, "vertices (out[0])", count)?,
                check_out(&n_obj, "normals (out[1])", count)?,
            ),
            None => (
                PyArray2::<f32>::zeros(py, [count, 3], false),
                PyArray2::<f32>::zeros(py, [count, 3], false),
            ),
        };
        let mut v_rw = v
            .try_readwrite()
            .map_err(|e| borrow_error("vertices (out[0])", e))?;
        let mut n_rw = n
            .try_readwrite()
            .map_err(|e| borrow_error("normals (out[1])", e))?;
        let v_flat = v_rw.as_slice_mut().map_err(|e| bad_option(e.to_string()))?;
        let n_flat = n_rw.as_slice_mut().map_err(|e| bad_option(e.to_string()))?;
        let (plan, frame, gpu) = (&built.plan, &mut built.frame, &mut built.gpu);
        py.detach(|| -> PyResult<()> {
            // On error the frame is unchanged and nothing below runs: `out` is not written.
            if let Some((positions, normals)) = &update {
                plan.update(frame, positions, normals.as_deref())
                    .map_err(errors::refine_error)?;
            }
            if let Some(gpu) = gpu {
                return gpu.evaluate(plan, frame, as_rows(v_flat), as_rows(n_flat));
            }
            plan.evaluate(
                frame,
                VertexOutput::Separate {
                    positions: as_rows(v_flat),
                    normals: Some(as_rows(n_flat)),
                    uvs: None,
                },
            )
            .map_err(errors::refine_error)
        })?;
        drop((v_rw, n_rw));
        Ok((v, faces, n))
    }

    /// Refined vertices per frame, or `None` before the first `refine`.
    #[getter]
    fn vertex_count(&self) -> Option<usize> {
        self.built.as_ref().map(|b| b.plan.vertex_count())
    }

    /// Refined triangles per frame: coarse faces × level².
    #[getter]
    fn triangle_count(&self) -> usize {
        self.triangles.len() * (self.grid_level() as usize).pow(2)
    }

    /// The refined triangles (the read-only array `refine` returns), or `None` before the
    /// first `refine`.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Option<U32Array<'py>> {
        self.built.as_ref().map(|b| b.faces.bind(py).clone())
    }

    /// Segments per coarse edge.
    #[getter]
    fn level(&self) -> u32 {
        self.grid_level()
    }

    /// The scheme's name (`tessella.schemes()` spelling).
    #[getter]
    fn scheme(&self) -> &'static str {
        self.scheme.name()
    }

    /// Whether output is welded.
    #[getter]
    fn weld(&self) -> bool {
        self.options.weld
    }

    /// Where frames are refined: `"gpu"` or `"cpu"` once planned; before, the backend asked for.
    #[getter]
    fn backend(&self) -> String {
        match &self.built {
            Some(b) if b.gpu.is_some() => "gpu".into(),
            Some(_) => "cpu".into(),
            None => self.given.3.clone(),
        }
    }

    /// The arguments this refiner was made with, `(faces, kwargs)`, and the mesh its plan was
    /// built from (`(vertices, normals or None)`, or `None` before the first frame): what
    /// pickling stores (`tessella.Refiner.__reduce__`).
    fn _state<'py>(&self, py: Python<'py>) -> PyResult<State<'py>> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("scheme", self.scheme.name())?;
        kwargs.set_item("level", self.grid_level())?;
        kwargs.set_item("alpha", self.given.0)?;
        kwargs.set_item("normals_mode", self.given.1.as_deref())?;
        kwargs.set_item("tags", self.given.2.as_ref().map(|t| t.bind(py)))?;
        kwargs.set_item("crease_angle", self.crease_angle)?;
        kwargs.set_item("backend", &self.given.3)?;
        kwargs.set_item("weld", self.options.weld)?;
        let planned = self.built.as_ref().map(|b| {
            (
                arrays::to_numpy(py, b.planned.0.clone()),
                b.planned.1.clone().map(|n| arrays::to_numpy(py, n)),
            )
        });
        Ok((
            arrays::to_numpy(py, self.triangles.clone()),
            kwargs,
            planned,
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "tessella.Refiner(scheme={:?}, level={}, faces={}, weld={}, backend={:?}, vertex_count={})",
            self.scheme.name(),
            self.grid_level(),
            self.triangles.len(),
            if self.options.weld { "True" } else { "False" },
            self.backend(),
            match self.vertex_count() {
                Some(n) => n.to_string(),
                None => "None".into(),
            }
        )
    }
}
