//! `tessella.load_animated` and `tessella.AnimatedMesh`: a glTF file's skins, morph targets and
//! clips (read by `tessella_io::read_animated`, checked once by the core's [`Poser`]), posed at
//! any moment of any clip into numpy arrays ready for `tessella.Refiner.refine`.
//!
//! - Loading reads and checks the whole file with the GIL released; every later `pose` only
//!   samples the clip and deforms the vertices (also with the GIL released).
//! - A file without normals gets normals computed by the core from each pose (`Poser::mesh`,
//!   the same angle-weighted normals `refine` computes), so a pose always carries normals.
//! - The faces are converted once into one read-only uint32 array, returned by every `faces`.
//!
//! Errors (`errors.rs`): the file as `tessella.load` (`OSError`, `FileFormatError`); an
//! animation the core refuses (`AnimationError` from [`Poser::new`]) is a broken file,
//! `FileFormatError` naming it; an unknown clip or a non-finite time is an `OptionError`; a
//! pose whose triangles collapse (normals cannot be computed) is a `MeshError`.

use crate::arrays;
use crate::errors::{bad_file, bad_mesh, bad_option};
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyString};
use std::path::PathBuf;
use tessella_core::animation::Poser;
use tessella_core::AnimationError;

type F32Array<'py> = Bound<'py, PyArray2<f32>>;

/// An animated mesh read from a glTF/GLB file by :func:`load_animated`: one triangle mesh
/// (every skinned, morphing or rigid primitive of the default scene, merged) and its clips,
/// posed at any time of any clip into arrays ready for :class:`Refiner`.
///
/// Attributes
/// ----------
/// faces : numpy.ndarray, uint32 (F, 3), read-only
///     The triangles (the same array object every time; ``faces.copy()`` for a writable one).
/// clips : list of str
///     The clips' names, in the file's order; a clip is named by its name or its index here.
/// vertex_count : int
///     Vertices of every pose.
/// has_normals : bool
///     True when the file has normals (they are posed with the vertices); else ``pose``
///     computes angle-weighted normals from each pose's positions, as :func:`refine` would.
/// path : str
///     The file it was read from.
///
/// Methods
/// -------
/// duration(clip) -> float
///     The clip's duration in seconds (its last key time); ``clip`` a name or an index.
/// pose(clip=None, time=0.0) -> (positions, normals)
///     The mesh at ``time`` seconds of ``clip`` (a name or an index; ``None``: the rest pose,
///     the nodes' stored transforms and weights), following the glTF 2.0 specification
///     (linear blend skinning, morph targets, the node hierarchy). Times before the first key
///     give the first pose, after the last key the last one. Returns float32 ``(V, 3)``
///     positions (in the scene's space) and unit normals, fresh arrays each call, computed
///     with the GIL released. Unknown clips (the message lists the clips), a NaN or infinite
///     time: :class:`OptionError`; a bool or float clip: ``TypeError``; a pose whose
///     triangles collapse when normals must be computed: :class:`MeshError`.
///
/// Examples
/// --------
/// >>> import tessella
/// >>> anim = tessella.load_animated("samples/animated-creature.glb")  # doctest: +SKIP
/// >>> anim.clips, anim.duration("hop")                                 # doctest: +SKIP
/// (['wave', 'hop', 'breathe'], 0.8)
/// >>> r = tessella.Refiner(anim.faces, vertices=anim.pose()[0], level=4)  # doctest: +SKIP
/// >>> v, f, n = r.refine(*anim.pose("wave", 0.5))                     # doctest: +SKIP
#[pyclass(module = "tessella._tessella", name = "AnimatedMesh", frozen)]
pub struct AnimatedMesh {
    poser: Poser,
    /// The file it was read from, named in error messages.
    path: PathBuf,
    /// The triangles as a read-only uint32 `(F, 3)` array, made once.
    faces: Py<PyArray2<u32>>,
}

/// An error posing or naming a clip of the file at `path`.
fn animation_error(e: AnimationError, path: &std::path::Path) -> PyErr {
    let message = format!("{}: {e}", path.display());
    match e {
        AnimationError::Mesh(_) => bad_mesh(message),
        _ => bad_option(message),
    }
}

impl AnimatedMesh {
    /// The clip `clip` names: `None` (the rest pose), a name (or a decimal index, as the core
    /// reads it) or an integer index.
    fn clip(&self, clip: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
        let Some(clip) = clip.filter(|c| !c.is_none()) else {
            return Ok(None);
        };
        if let Ok(name) = clip.cast::<PyString>() {
            let name = name.to_cow()?;
            return self
                .poser
                .clip_index(&name)
                .map(Some)
                .map_err(|e| animation_error(e, &self.path));
        }
        if clip.is_instance_of::<pyo3::types::PyBool>() {
            return Err(pyo3::exceptions::PyTypeError::new_err(
                "clip must be a clip's name (str), an index (int) or None, got bool",
            ));
        }
        let index: i64 = clip.extract().map_err(|_| {
            let kind = clip
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_else(|_| "?".into());
            pyo3::exceptions::PyTypeError::new_err(format!(
                "clip must be a clip's name (str), an index (int) or None, got {kind}"
            ))
        })?;
        match usize::try_from(index) {
            Ok(i) if i < self.poser.clip_count() => Ok(Some(i)),
            // The core's message, which lists the clips, naming the index given.
            _ => Err(animation_error(
                match self.poser.duration(usize::MAX) {
                    Err(AnimationError::UnknownClip { count, names, .. }) => {
                        AnimationError::UnknownClip {
                            clip: index.to_string(),
                            count,
                            names,
                        }
                    }
                    Err(e) => e,
                    Ok(_) => AnimationError::UnknownClip {
                        clip: index.to_string(),
                        count: self.poser.clip_count(),
                        names: String::new(),
                    },
                },
                &self.path,
            )),
        }
    }
}

#[pymethods]
impl AnimatedMesh {
    /// The triangles, uint32 `(F, 3)`, read-only (the same array every time).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u32>> {
        self.faces.bind(py).clone()
    }

    /// The clips' names, in the file's order (an index into this list names a clip too).
    #[getter]
    fn clips(&self) -> Vec<String> {
        self.poser.clip_names().map(String::from).collect()
    }

    /// Vertices of every pose.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.poser.vertex_count()
    }

    /// True when the file has normals (posed with the vertices); otherwise `pose` computes
    /// them from each pose's positions.
    #[getter]
    fn has_normals(&self) -> bool {
        self.poser.has_normals()
    }

    /// The file it was read from.
    #[getter]
    fn path(&self) -> String {
        self.path.to_string_lossy().into_owned()
    }

    /// A clip's duration in seconds (its last key time, as the shortest decimal of the
    /// float32 value).
    fn duration(&self, clip: &Bound<'_, PyAny>) -> PyResult<f64> {
        let Some(index) = self.clip(Some(clip))? else {
            return Err(bad_option(format!(
                "{}: duration needs a clip (a name or an index), got None",
                self.path.display()
            )));
        };
        let seconds = self
            .poser
            .duration(index)
            .map_err(|e| animation_error(e, &self.path))?;
        // The float32 key time as the shortest decimal that reads back as it (0.8, not
        // 0.800000011920929), so that durations written in a file compare equal in Python.
        Ok(seconds
            .to_string()
            .parse()
            .unwrap_or_else(|_| f64::from(seconds)))
    }

    /// `(positions, normals)` at `time` seconds of `clip` (`None`: the rest pose).
    #[pyo3(signature = (clip=None, time=0.0))]
    fn pose<'py>(
        &self,
        py: Python<'py>,
        clip: Option<&Bound<'py, PyAny>>,
        time: f64,
    ) -> PyResult<(F32Array<'py>, F32Array<'py>)> {
        let clip = self.clip(clip)?;
        if !time.is_finite() {
            return Err(animation_error(
                AnimationError::BadTime(time as f32),
                &self.path,
            ));
        }
        let poser = &self.poser;
        let (positions, normals) = py
            .detach(|| -> Result<_, AnimationError> {
                if poser.has_normals() {
                    let (p, n) = poser.pose(clip, time as f32)?;
                    Ok((p, n.unwrap_or_default()))
                } else {
                    let mesh = poser.mesh(clip, time as f32)?;
                    Ok((mesh.positions().to_vec(), mesh.normals().to_vec()))
                }
            })
            .map_err(|e| animation_error(e, &self.path))?;
        Ok((
            arrays::to_numpy(py, positions),
            arrays::to_numpy(py, normals),
        ))
    }

    fn __repr__(&self) -> String {
        let clips: Vec<String> = self
            .poser
            .model()
            .clips
            .iter()
            .map(|c| format!("{:?}", c.name))
            .collect();
        format!(
            "tessella.AnimatedMesh(path={:?}, vertex_count={}, faces={}, clips=[{}], normals={:?})",
            self.path.display().to_string(),
            self.poser.vertex_count(),
            self.poser.model().triangles.len(),
            clips.join(", "),
            if self.poser.has_normals() {
                "file"
            } else {
                "computed"
            },
        )
    }
}

/// Reads an animated glTF (``.gltf``, buffers embedded or beside it) or ``.glb`` file:
/// its meshes, nodes, skins, morph targets and clips, checked once.
///
/// Returns an :class:`AnimatedMesh`; ``anim.pose(clip, time)`` gives ``(positions, normals)``
/// for :meth:`Refiner.refine`, ``anim.faces`` the triangles.
///
/// Raises ``OSError`` (``FileNotFoundError``, ...) when the file cannot be read,
/// ``FileFormatError`` when it is not glTF/GLB, is malformed, refers to a buffer that cannot
/// be read, or holds an animation tessella refuses (a channel on a node with a matrix, bad key
/// times, a skin without weights, ...): the message names the file and the problem.
#[pyfunction]
pub fn load_animated(py: Python<'_>, path: PathBuf) -> PyResult<AnimatedMesh> {
    let poser = py.detach(|| -> Result<_, PyErr> {
        let model =
            tessella_io::read_animated(&path).map_err(|e| crate::errors::read_error(e, &path))?;
        Poser::new(model).map_err(|e| bad_file(format!("{}: {e}", path.display())))
    })?;
    let faces = arrays::to_numpy(py, poser.model().triangles.clone());
    faces.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
    Ok(AnimatedMesh {
        poser,
        path,
        faces: faces.unbind(),
    })
}
