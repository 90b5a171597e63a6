//! Names the Python API accepts, mapped to core types in this one place. The names themselves,
//! their spellings (ASCII case ignored, `_` for `-`) and the lists of valid ones are the core's
//! (`tessella_core::names`), shared with the CLI; this module only turns a bad name into a
//! `ValueError` that says which Python argument was wrong. `schemes()` and `backends()` report
//! what this build has, so scripts can adapt.

use crate::errors::bad_option;
use pyo3::{PyErr, PyResult};
use tessella_core::refine::Ask;
pub use tessella_core::Backend;
use tessella_core::{Named, Scheme};

/// Scheme names, in the order `tessella.schemes()` lists them (the core's list).
pub const SCHEMES: &[&str] = Scheme::NAMES;

/// The backend called `name`.
pub fn backend(name: &str) -> PyResult<Backend> {
    name.parse::<Backend>().map_err(|e| {
        bad_option(format!(
            "{e} (tessella.backends() lists those that work here)"
        ))
    })
}

/// A backend this package does not run (one added to the core after this package was
/// written): an option error naming it.
pub fn unsupported_backend(backend: Backend) -> PyErr {
    bad_option(format!(
        "backend=\"{}\" is not supported by this package (tessella.backends() lists those that work here)",
        backend.name()
    ))
}

/// A refinement level from a Python int: 1 or more.
pub fn level(level: i64) -> PyResult<u32> {
    if level < 1 || level > u32::MAX as i64 {
        return Err(bad_option(format!(
            "level must be 1 or more (segments per coarse edge), got {level}"
        )));
    }
    Ok(level as u32)
}

/// A target edge length for a glTF scene's levels (`max_edge=`): a positive, finite number
/// (world units), as `tessella refine --max-edge` takes.
pub fn max_edge(length: f64) -> PyResult<f32> {
    let l = length as f32;
    if !(l.is_finite() && l > 0.0) {
        return Err(bad_option(format!(
            "max_edge must be a positive length (refined edges about that long in world space), \
             got {length}"
        )));
    }
    Ok(l)
}

/// The largest level [`quality_level`] accepts: its pattern samples the distance from the coarse
/// mesh, and a finer one adds time and memory (about 500 B a point) but no insight.
pub const MAX_QUALITY_LEVEL: u32 = 256;

/// A level for the quality report: 1 to [`MAX_QUALITY_LEVEL`].
pub fn quality_level(value: i64) -> PyResult<u32> {
    let l = level(value)?;
    if l > MAX_QUALITY_LEVEL {
        return Err(bad_option(format!(
            "level {l} is too fine for the quality report (it samples every pattern point of every \
             triangle); use a level of {MAX_QUALITY_LEVEL} or less"
        )));
    }
    Ok(l)
}

/// `backend="gl"` where the grid pattern is asked for (see `gl.rs`).
pub const NO_GL: &str = crate::gl::GL_NEEDS_SPACING;

/// Python's refinement keyword arguments, as given.
pub struct Given<'a> {
    pub scheme: &'a str,
    pub alpha: f64,
    /// An int or a float, as its text.
    pub level: String,
    pub spacing: &'a str,
    pub lod: Option<&'a str>,
    pub camera: Option<&'a str>,
    pub size: Option<(u32, u32)>,
    pub normals_mode: Option<&'a str>,
    pub weld: bool,
}

impl Default for Given<'_> {
    fn default() -> Self {
        Given {
            scheme: "pn",
            alpha: 0.75,
            level: "8".into(),
            spacing: "grid",
            lod: None,
            camera: None,
            size: None,
            normals_mode: None,
            weld: true,
        }
    }
}

/// The refinement options the keyword arguments ask for, parsed by the core's text form
/// ([`tessella_core::refine::OPTION_KEYS`]) as the CLI's flags, npm's options and the viewer's
/// URL are: `level=5.5` here is `--level 5.5` there. Python's `normals_mode` is the text form's
/// `normals` and `weld` its `soup` negated; an error names the Python argument.
pub fn refine_options(given: Given<'_>) -> PyResult<tessella_core::RefineOptions> {
    let mut pairs = vec![
        ("scheme", given.scheme.to_string()),
        ("alpha", given.alpha.to_string()),
        ("spacing", given.spacing.to_string()),
        ("soup", (!given.weld).to_string()),
    ];
    match given.lod {
        Some(lod) => pairs.push(("lod", lod.to_string())),
        None => pairs.push(("level", given.level)),
    }
    pairs.extend(given.camera.map(|c| ("camera", c.to_string())));
    pairs.extend(given.size.map(|(w, h)| ("size", format!("{w}x{h}"))));
    pairs.extend(given.normals_mode.map(|n| ("normals", n.to_string())));
    tessella_core::RefineOptions::from_pairs(pairs).map_err(|e| {
        let (argument, hint) = match e.key.as_str() {
            "normals" => ("normals_mode", " or None for the scheme's default"),
            "soup" => ("weld", ""),
            "scheme" => ("scheme", " (see tessella.schemes())"),
            key => (key, ""),
        };
        let argument = argument.replace('-', "_");
        bad_option(format!("{argument}: {}{hint}", e.message))
    })
}

/// The options of a whole grid level with the shape's arguments, the rest as `refine`'s
/// defaults: what the FEM refinement and the `Refiner` take.
pub fn grid_options(
    scheme: &str,
    alpha: f64,
    level: i64,
    normals_mode: Option<&str>,
    weld: bool,
) -> PyResult<tessella_core::RefineOptions> {
    refine_options(Given {
        scheme,
        alpha,
        level: level.to_string(),
        normals_mode,
        weld,
        ..Default::default()
    })
}

/// An ask as `tessella.refine`'s keyword arguments spell it, for a conflict's message.
fn keyword(ask: Ask) -> String {
    match ask {
        Ask::FractionalLevel => "a fractional level=".into(),
        Ask::PerEdgeLevels => "per-edge levels".into(),
        Ask::Origin => "origin=True".into(),
        Ask::GlBackend => "backend='gl'".into(),
        other => format!("{}=", other.key()),
    }
}

/// Refuses `asks` with these options where the core's rules say they cannot go together
/// ([`tessella_core::RefineOptions::conflict`]): `refine(): A cannot be combined with B (why)`.
pub fn refuse_conflicts(
    options: &tessella_core::RefineOptions,
    asks: impl IntoIterator<Item = Ask>,
) -> PyResult<()> {
    options
        .conflict(asks)
        .map_err(|c| bad_option(format!("refine(): {}", c.message(keyword))))
}
