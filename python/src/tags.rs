//! The `tags=` and `crease_angle=` arguments: what Python may pass. The layering is
//! `tessella_io::tags::gather`'s, the CLI's too: for the scalar-tagged scheme the mesh's split
//! normals first, then the crease angle, then the given tags, later ones overriding earlier ones.
//!
//! `tags` is `None`, a dict in the sidecar-JSON structure (`tessella_io::tags` docs), that JSON
//! as a string, or the path of such a file (`str` or `os.PathLike`). A string whose first
//! non-blank character is `{` is JSON text; any other string is a path.

use crate::errors;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyCFunction, PyDict, PyString, PyTuple};
use std::path::PathBuf;
use tessella_core::{Mesh, RefineOptions, Scheme, Tags};
use tessella_io::tags::{JsonSource, TagSources};

/// Where the given tags come from, read while the GIL is held.
pub enum TagSource {
    None,
    /// JSON text, and how messages name it (`"in the tags dict"`).
    Json {
        text: String,
        origin: String,
    },
    /// A sidecar JSON file, read without the GIL.
    File(PathBuf),
}

/// Classifies the `tags` argument.
pub fn source(tags: Option<&Bound<'_, PyAny>>) -> PyResult<TagSource> {
    let Some(obj) = tags.filter(|t| !t.is_none()) else {
        return Ok(TagSource::None);
    };
    if let Ok(s) = obj.cast::<PyString>() {
        let s: String = s.extract()?;
        if s.trim_start().starts_with('{') {
            return Ok(TagSource::Json {
                text: s,
                origin: "in the tags string".into(),
            });
        }
        return Ok(TagSource::File(PathBuf::from(s)));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        return Ok(TagSource::Json {
            text: dict_to_json(d)?,
            origin: "in the tags dict".into(),
        });
    }
    if obj.hasattr("__fspath__")? {
        return Ok(TagSource::File(obj.extract::<PathBuf>()?));
    }
    Err(PyTypeError::new_err(format!(
        "tags must be None, a dict like {{\"edges\": [...], \"vertices\": [...]}}, a JSON string \
         or the path of a JSON file, got {}",
        obj.get_type().name()?
    )))
}

/// `json.dumps(d)`, with numpy scalars and arrays turned into numbers and lists.
fn dict_to_json(d: &Bound<'_, PyDict>) -> PyResult<String> {
    let py = d.py();
    let default = PyCFunction::new_closure(
        py,
        Some(c"tags_json_default"),
        None,
        |args: &Bound<'_, PyTuple>, _kwargs: Option<&Bound<'_, PyDict>>| -> PyResult<Py<PyAny>> {
            let obj = args.get_item(0)?;
            if obj.hasattr("tolist")? {
                return Ok(obj.call_method0("tolist")?.unbind());
            }
            Err(PyTypeError::new_err(format!(
                "tags hold {} of type {}; use numbers, lists and dicts",
                obj.repr()?,
                obj.get_type().name()?
            )))
        },
    )?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("default", default)?;
    kwargs.set_item("allow_nan", false)?;
    let json = py.import("json")?;
    match json.call_method("dumps", (d,), Some(&kwargs)) {
        Ok(text) => text.extract(),
        // allow_nan=False: NaN or infinity somewhere; JSON cannot carry it.
        Err(e) if e.is_instance_of::<PyValueError>(py) => Err(crate::errors::bad_option(format!(
            "bad tags in the tags dict: {e}; tags must be finite numbers"
        ))),
        Err(e) => Err(e),
    }
}

/// `opts` with the tags its scheme gets on `mesh` ([`gather`]), unchanged when nothing is
/// tagged: the one way `refine`, `quality` and `Refiner` tag their options. Runs without the GIL.
pub fn tagged(
    opts: RefineOptions,
    mesh: &Mesh,
    source: &TagSource,
    crease_angle: Option<f64>,
) -> PyResult<RefineOptions> {
    Ok(match gather(mesh, opts.scheme, source, crease_angle)? {
        Some(t) => opts.with_tags(t),
        None => opts,
    })
}

/// The tags `scheme` gets on `mesh` (layered by [`tessella_io::tags::gather`], as the CLI does),
/// or `None` when nothing is tagged. Runs without the GIL.
fn gather(
    mesh: &Mesh,
    scheme: Scheme,
    source: &TagSource,
    crease_angle: Option<f64>,
) -> PyResult<Option<Tags>> {
    let json = match source {
        TagSource::None => None,
        TagSource::Json { text, origin } => Some(JsonSource::Text { text, origin }),
        TagSource::File(path) => Some(JsonSource::File(path)),
    };
    let sources = TagSources {
        crease_angle: crease_angle.map(|d| d as f32),
        file: None,
        json,
    };
    tessella_io::tags::gather(mesh, scheme, &sources)
        .map_err(|e| errors::tag_source_error(e, crease_angle))
}
