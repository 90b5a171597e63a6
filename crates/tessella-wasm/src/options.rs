//! `refine`'s options, as the JS wrapper passes them (plain values), to [`RefineOptions`]. Names
//! are parsed by the core types, as the CLI and Python parse them.

use tessella_core::refine::{Camera, Levels, Lod, Spacing};
use tessella_core::{NormalMode, RefineOptions, Scheme};

/// The largest output `refine` accepts in wasm: 32-bit wasm has 4 GiB of memory in all, and the
/// output is copied once into JS arrays, so refuse (with the core's message) what could not be
/// allocated, rather than trap on a failed allocation.
pub const MAX_OUTPUT_BYTES: u64 = 1 << 30;

/// The options of one refinement, as JS gives them (a JSON object; unknown keys are refused,
/// so a misspelt option is an error rather than ignored).
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Options {
    pub scheme: String,
    /// A number, or `"NaN"`/`"Infinity"` (JSON has no such numbers; the JS side spells them).
    #[serde(deserialize_with = "number")]
    pub level: f64,
    pub normals: Option<String>,
    #[serde(deserialize_with = "number")]
    pub alpha: f64,
    pub spacing: String,
    pub lod: Option<String>,
    /// `EX,EY,EZ,TX,TY,TZ,FOV_DEG` for `lod: "screen:PX"` and `"distance:..."`.
    pub camera: Option<String>,
    pub size: Option<[u32; 2]>,
    pub soup: bool,
    /// Also return each refined vertex's coarse face and barycentric coordinates (what
    /// `tessella/three` interpolates other attributes with).
    pub origin: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scheme: "pn".into(),
            level: 8.0,
            normals: None,
            alpha: 0.75,
            spacing: "grid".into(),
            lod: None,
            camera: None,
            size: None,
            soup: false,
            origin: false,
        }
    }
}

/// A JSON number or the JS spelling of a non-finite one.
fn number<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    #[derive(serde::Deserialize)]
    #[serde(untagged)]
    enum Number {
        Finite(f64),
        Named(String),
    }
    match Number::deserialize(d)? {
        Number::Finite(x) => Ok(x),
        Number::Named(name) => match name.as_str() {
            "NaN" => Ok(f64::NAN),
            "Infinity" => Ok(f64::INFINITY),
            "-Infinity" => Ok(f64::NEG_INFINITY),
            _ => Err(serde::de::Error::custom(format!(
                "expected a number, got {name:?}"
            ))),
        },
    }
}

use serde::Deserialize;

impl Options {
    /// Parses the JSON the JS wrapper sends.
    pub fn from_json(text: &str) -> Result<Options, String> {
        serde_json::from_str(text).map_err(|e| format!("bad options: {e}"))
    }

    /// Validates and converts; the messages say which option was wrong.
    pub fn to_core(&self) -> Result<RefineOptions, String> {
        if !self.alpha.is_finite() {
            return Err(format!(
                "alpha must be finite (usually within 0..=1), got {}",
                self.alpha
            ));
        }
        let scheme: Scheme = self
            .scheme
            .parse()
            .map_err(|e| format!("{e} (see schemes())"))?;
        let scheme = scheme.with_alpha(self.alpha as f32);
        let spacing: Spacing = self.spacing.parse()?;
        let level = self.level;
        if level.is_nan() || level < 1.0 {
            return Err(format!(
                "level must be 1 or more (segments per coarse edge), got {level}"
            ));
        }
        let whole = level.fract() == 0.0 && level <= u32::MAX as f64;
        let mut options = RefineOptions::new(scheme, if whole { level as u32 } else { 1 })
            .with_weld(!self.soup)
            .with_spacing(spacing)
            .with_max_output_bytes(MAX_OUTPUT_BYTES);
        if let Some(name) = &self.normals {
            let mode: NormalMode = name.parse().map_err(|e: tessella_core::UnknownName| {
                format!(
                    "unknown normals {name:?}; use one of {:?} or leave it out for the scheme's default",
                    e.valid
                )
            })?;
            options = options.with_normals(mode);
        }
        if let Some(spec) = &self.lod {
            let camera = self
                .camera
                .as_deref()
                .map(Camera::parse)
                .transpose()
                .map_err(|e| e.to_string())?;
            let lod = Lod::parse(spec, camera, self.size).map_err(|e| e.to_string())?;
            options = options.with_levels(Levels::Lod(lod));
        } else if self.camera.is_some() || self.size.is_some() {
            return Err(
                "camera and size serve lod: \"screen:PX\" and lod: \"distance:NEAR,FAR,MAX\""
                    .into(),
            );
        } else if !whole || spacing != Spacing::Grid {
            // A fractional grid level geomorphs, as in the CLI and Python.
            options = options.with_levels(Levels::Uniform(level as f32));
        }
        Ok(options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(f: impl FnOnce(&mut Options)) -> Result<RefineOptions, String> {
        let mut o = Options::default();
        f(&mut o);
        o.to_core()
    }

    #[test]
    fn good_options_reach_the_core_types() {
        let o = with(|o| {
            o.scheme = "PNG1".into();
            o.level = 5.0;
            o.soup = true;
            o.normals = Some("real".into());
        })
        .unwrap();
        assert_eq!(o.scheme, Scheme::Png1);
        assert_eq!((o.level, o.weld), (5, false));
        assert_eq!(o.normals, Some(NormalMode::Real));
        assert_eq!(o.uniform_grid_level(), Some(5));
        let o = with(|o| o.level = 2.5).unwrap();
        assert_eq!(o.levels, Some(Levels::Uniform(2.5)));
        let o = with(|o| o.lod = Some("tolerance:0.01".into())).unwrap();
        assert_eq!(
            o.levels,
            Some(Levels::Lod(Lod::Tolerance {
                max_deviation: 0.01
            }))
        );
    }

    #[test]
    fn options_come_as_json_with_non_finite_numbers_spelt_out() {
        let o = Options::from_json(r#"{"scheme":"phong","level":"NaN","alpha":0.5}"#).unwrap();
        assert!(o.level.is_nan());
        assert_eq!((o.scheme.as_str(), o.alpha), ("phong", 0.5));
        let err = Options::from_json(r#"{"levle":3}"#).unwrap_err();
        assert!(err.contains("unknown field `levle`"), "{err}");
        let o =
            Options::from_json(r#"{"lod":"screen:8","camera":"0,0,5,0,0,0,45","size":[640,480]}"#)
                .unwrap();
        assert!(matches!(
            o.to_core().unwrap().levels,
            Some(Levels::Lod(Lod::Screen { .. }))
        ));
    }

    #[test]
    fn bad_options_say_which_one_is_wrong() {
        type Case = (fn(&mut Options), &'static str);
        let cases: [Case; 7] = [
            (|o| o.scheme = "loop".into(), "see schemes()"),
            (|o| o.level = 0.0, "level must be 1 or more"),
            (|o| o.level = f64::NAN, "level must be 1 or more"),
            (|o| o.alpha = f64::INFINITY, "alpha must be finite"),
            (|o| o.spacing = "odd".into(), "unknown spacing"),
            (|o| o.normals = Some("cubic".into()), "unknown normals"),
            (
                |o| o.camera = Some("0,0,5,0,0,0,45".into()),
                "camera and size serve lod",
            ),
        ];
        for (change, expected) in cases {
            let err = with(change).unwrap_err();
            assert!(err.contains(expected), "{err:?} lacks {expected:?}");
        }
    }
}
