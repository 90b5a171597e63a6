//! The `displace=` argument of `refine`: moves refined vertices along their normals
//! (tessella-core's [`Displacement`], GMR section 4; hard edges along one shared direction so
//! they stay closed), on the CPU or the GPU like the refinement.
//!
//! Accepted, read while the GIL is held:
//! - `None`: no displacement;
//! - a dict `{"kind": "sine", "amplitude": a, "frequency": f}` (offset `a·sin(f·‖P‖)`) or
//!   `{"kind": "perlin", "amplitude": a, "frequency": f, "seed": s}` (offset `a·noise(f·P)`,
//!   Perlin's improved noise; `seed` optional, 0 by default);
//! - a tuple or list `("sine", a, f)` / `("perlin", a, f[, s])`.
//!
//! Height maps need texture coordinates, which `refine` does not take, so they are refused.

use crate::errors::bad_option;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use tessella_core::displace::Displacement;

const KINDS: &str = "\"sine\" or \"perlin\"";
const DICT_KEYS: &[&str] = &["kind", "amplitude", "frequency", "seed"];

/// The displacement `displace` asks for.
pub fn parse(displace: Option<&Bound<'_, PyAny>>) -> PyResult<Displacement> {
    let Some(obj) = displace.filter(|d| !d.is_none()) else {
        return Ok(Displacement::None);
    };
    let fields = if let Ok(d) = obj.cast::<PyDict>() {
        from_dict(d)?
    } else if obj.cast::<PyTuple>().is_ok() || obj.cast::<PyList>().is_ok() {
        from_sequence(obj)?
    } else {
        return Err(PyTypeError::new_err(format!(
            "displace must be None, a dict like {{\"kind\": \"sine\", \"amplitude\": 0.05, \
             \"frequency\": 10.0}} or a tuple like (\"perlin\", 0.05, 4.0, 7), got {}",
            obj.get_type().name()?
        )));
    };
    build(fields)
}

/// The fields of either spelling, not yet checked.
struct Fields<'py> {
    kind: Bound<'py, PyAny>,
    amplitude: Option<Bound<'py, PyAny>>,
    frequency: Option<Bound<'py, PyAny>>,
    seed: Option<Bound<'py, PyAny>>,
}

fn from_dict<'py>(d: &Bound<'py, PyDict>) -> PyResult<Fields<'py>> {
    for key in d.keys() {
        let known = key.is_instance_of::<PyString>()
            && DICT_KEYS.contains(&key.extract::<String>()?.as_str());
        if !known {
            return Err(bad_option(format!(
                "displace has an unknown key {}; the keys are {DICT_KEYS:?}",
                key.repr()?
            )));
        }
    }
    let kind = d
        .get_item("kind")?
        .ok_or_else(|| bad_option(format!("displace needs a \"kind\": {KINDS}")))?;
    Ok(Fields {
        kind,
        amplitude: d.get_item("amplitude")?,
        frequency: d.get_item("frequency")?,
        seed: d.get_item("seed")?,
    })
}

fn from_sequence<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Fields<'py>> {
    let items: Vec<Bound<'py, PyAny>> = obj.try_iter()?.collect::<PyResult<_>>()?;
    if !(3..=4).contains(&items.len()) {
        return Err(bad_option(format!(
            "displace as a tuple is (kind, amplitude, frequency) or, for perlin, (kind, \
             amplitude, frequency, seed); got {} items",
            items.len()
        )));
    }
    let mut items = items.into_iter();
    Ok(Fields {
        kind: items.next().expect("length checked"),
        amplitude: items.next(),
        frequency: items.next(),
        seed: items.next(),
    })
}

/// A finite number that fits an f32.
fn number(value: Option<Bound<'_, PyAny>>, kind: &str, what: &str) -> PyResult<f32> {
    let value = value
        .ok_or_else(|| bad_option(format!("displace kind {kind:?} needs a value for {what}")))?;
    let x: f64 = value.extract().map_err(|_| {
        bad_option(format!(
            "displace {what} must be a number, got {}",
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })?;
    let x32 = x as f32;
    if !x32.is_finite() {
        return Err(bad_option(format!(
            "displace {what} must be finite (and within float32 range), got {x}"
        )));
    }
    Ok(x32)
}

/// A seed: a whole number in 0..2³².
fn seed(value: Option<Bound<'_, PyAny>>) -> PyResult<u32> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(0);
    };
    // Floats are refused rather than truncated: 7.5 is not a seed.
    let s: Option<i64> = if value.is_instance_of::<pyo3::types::PyFloat>() {
        None
    } else {
        value.extract().ok()
    };
    s.and_then(|s| u32::try_from(s).ok()).ok_or_else(|| {
        bad_option(format!(
            "displace seed must be a whole number from 0 to {}, got {}",
            u32::MAX,
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

fn build(fields: Fields<'_>) -> PyResult<Displacement> {
    let kind: String = fields
        .kind
        .extract()
        .map_err(|_| bad_option(format!("displace kind must be a string: {KINDS}")))?;
    let lower = kind.to_ascii_lowercase();
    let displacement = match lower.as_str() {
        "sine" => {
            if fields.seed.as_ref().is_some_and(|s| !s.is_none()) {
                return Err(bad_option(
                    "displace kind \"sine\" takes no seed (only \"perlin\" does)",
                ));
            }
            Displacement::Sine {
                amplitude: number(fields.amplitude, &lower, "amplitude")?,
                frequency: number(fields.frequency, &lower, "frequency")?,
            }
        }
        "perlin" => Displacement::Perlin {
            amplitude: number(fields.amplitude, &lower, "amplitude")?,
            frequency: number(fields.frequency, &lower, "frequency")?,
            seed: seed(fields.seed)?,
        },
        "heightmap" | "height_map" | "height-map" => {
            return Err(bad_option(
                "displace kind \"heightmap\" needs texture coordinates, which refine does not \
                 take; use \"sine\" or \"perlin\" (or the CLI's refine --displace heightmap:...)",
            ))
        }
        _ => {
            return Err(bad_option(format!(
                "unknown displace kind {kind:?}; use {KINDS}"
            )))
        }
    };
    // The core's own checks, so both backends refuse the same values.
    displacement
        .validate(false)
        .map_err(|e| bad_option(e.to_string()))?;
    Ok(displacement)
}
