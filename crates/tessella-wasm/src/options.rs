//! `refine`'s options, as the JS wrapper passes them (a JSON object of plain values), to
//! [`RefineOptions`] through the core's text form ([`tessella_core::refine::OPTION_KEYS`]):
//! `{ level: 5.5 }` is `level=5.5`, parsed by the same code as the CLI's `--level 5.5`, Python's
//! `level=5.5` and the viewer's `?level=5.5`. Unknown keys are refused, so a misspelt option is
//! an error rather than ignored.

use serde_json::{Map, Value};
use tessella_core::RefineOptions;

/// The largest output `refine` accepts in wasm: 32-bit wasm has 4 GiB of memory in all, and the
/// output is copied once into JS arrays, so refuse (with the core's message) what could not be
/// allocated, rather than trap on a failed allocation. A smaller `maxMemory` is taken.
pub const MAX_OUTPUT_BYTES: u64 = 1 << 30;

/// The options of one refinement, and what this package adds to them.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub refine: RefineOptions,
    /// Also return each refined vertex's coarse face and barycentric coordinates (what
    /// `tessella/three` interpolates other attributes with).
    pub origin: bool,
}

/// A JSON value as option text: strings as they are (the JS side spells non-finite numbers
/// `"NaN"`, `"Infinity"`), numbers and booleans as JSON writes them, `size: [W, H]` as `WxH`.
fn text(key: &str, value: &Value) -> Result<String, String> {
    Ok(match value {
        Value::String(s) => s.clone(),
        Value::Number(_) | Value::Bool(_) => value.to_string(),
        Value::Array(items) if key == "size" && items.len() == 2 => {
            format!("{}x{}", items[0], items[1])
        }
        other => return Err(format!("{key}: {other} is not a string, number or boolean")),
    })
}

/// JS's camelCase keys (`maxMemory`) as the text form's (`max-memory`).
fn key(name: &str) -> String {
    let mut out = String::new();
    for c in name.chars() {
        if c.is_ascii_uppercase() {
            out.push('-');
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// The options object the JS wrapper sends, as a JSON map.
pub fn parse(json: &str) -> Result<Map<String, Value>, String> {
    serde_json::from_str(json).map_err(|e| format!("bad options: {e}"))
}

impl Options {
    /// Parses and validates the JSON the JS wrapper sends; the messages say which option was
    /// wrong.
    pub fn from_json(json: &str) -> Result<Options, String> {
        Options::from_map(&parse(json)?)
    }

    /// [`Options::from_json`] on options already parsed (`refineGltf` takes its own keys out
    /// first).
    pub fn from_map(map: &Map<String, Value>) -> Result<Options, String> {
        let mut origin = false;
        let mut pairs = Vec::new();
        // `null` is an option left out, as `undefined` is.
        for (name, value) in map.iter().filter(|(_, v)| !v.is_null()) {
            match name.as_str() {
                "origin" => {
                    origin = value
                        .as_bool()
                        .ok_or_else(|| format!("origin: {value} is not true or false"))?
                }
                _ => pairs.push((key(name), text(name, value)?)),
            }
        }
        let mut refine = RefineOptions::from_pairs(pairs).map_err(|e| {
            let hint = if e.key == "scheme" {
                " (see schemes())"
            } else {
                ""
            };
            format!("{e}{hint}")
        })?;
        // The text form read `maxMemory`; wasm's own cap bounds it, and is the default.
        refine.max_output_bytes = match map.get("maxMemory") {
            Some(_) => refine.max_output_bytes.min(MAX_OUTPUT_BYTES),
            None => MAX_OUTPUT_BYTES,
        };
        Ok(Options { refine, origin })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::refine::{Levels, Lod};
    use tessella_core::{NormalMode, Scheme};

    #[test]
    fn good_options_reach_the_core_types() {
        let o = Options::from_json(r#"{"scheme":"PNG1","level":5,"soup":true,"normals":"real"}"#)
            .unwrap();
        assert_eq!(o.refine.scheme, Scheme::Png1);
        assert!(!o.refine.weld);
        assert_eq!(o.refine.normals, Some(NormalMode::Real));
        assert_eq!(o.refine.uniform_grid_level(), Some(5));
        assert_eq!(o.refine.max_output_bytes, MAX_OUTPUT_BYTES);
        let o = Options::from_json(r#"{"level":2.5,"origin":true,"maxMemory":"1MiB"}"#).unwrap();
        assert_eq!(o.refine.levels, Levels::Uniform(2.5));
        assert!(o.origin);
        assert_eq!(o.refine.max_output_bytes, 1 << 20);
        let o = Options::from_json(r#"{"lod":"tolerance:0.01","camera":null}"#).unwrap();
        assert_eq!(
            o.refine.levels,
            Levels::Lod(Lod::Tolerance {
                max_deviation: 0.01
            })
        );
        let o =
            Options::from_json(r#"{"lod":"screen:8","camera":"0,0,5,0,0,0,45","size":[640,480]}"#)
                .unwrap();
        assert!(matches!(
            o.refine.levels,
            Levels::Lod(Lod::Screen {
                size: [640, 480],
                ..
            })
        ));
    }

    #[test]
    fn bad_options_say_which_one_is_wrong() {
        for (json, expected) in [
            (r#"{"scheme":"loop"}"#, "see schemes()"),
            (r#"{"level":0}"#, "level: must be a finite number above 0"),
            (
                r#"{"level":"NaN"}"#,
                "level: must be a finite number above 0",
            ),
            (r#"{"alpha":"Infinity"}"#, "alpha: must be finite"),
            (r#"{"spacing":"odd"}"#, "unknown spacing"),
            (r#"{"normals":"cubic"}"#, "unknown normal mode"),
            (r#"{"camera":"0,0,5,0,0,0,45"}"#, "camera: serves lod"),
            (r#"{"levle":3}"#, "levle: unknown option"),
            (
                r#"{"origin":"yes"}"#,
                "origin: \"yes\" is not true or false",
            ),
            (r#"[1]"#, "bad options"),
        ] {
            let err = Options::from_json(json).unwrap_err();
            assert!(err.contains(expected), "{json}: {err:?} lacks {expected:?}");
        }
    }
}
