//! The text form of [`RefineOptions`]: `key=value` pairs. It is the one spelling every front
//! end parses through [`RefineOptions::from_pairs`]: the CLI's flags (`--level 5.5` is
//! `level=5.5`), Python's keyword arguments, npm's options object, the viewer's controls and
//! its URL (`?scheme=png1&level=5.5`). A value means the same wherever it is written, and a bad
//! one gets the same message.
//!
//! ```
//! use tessella_core::refine::{Levels, Spacing};
//! use tessella_core::{RefineOptions, Scheme};
//! let o: RefineOptions = "scheme=png1 level=5.5 spacing=fractional-odd".parse().unwrap();
//! assert_eq!((o.scheme, o.spacing), (Scheme::Png1, Spacing::FractionalOdd));
//! assert_eq!(o.levels, Levels::Uniform(5.5));
//! // The URL's spelling, and back to text.
//! let o: RefineOptions = "scheme=phong&alpha=0.5&level=4&soup=true".parse().unwrap();
//! assert_eq!(o.to_string(), "scheme=phong alpha=0.5 level=4 spacing=grid soup=true");
//! let err = "level=0.0.1".parse::<RefineOptions>().unwrap_err();
//! assert_eq!(err.key, "level");
//! ```

use super::levels::{Camera, Levels, Lod, Spacing};
use super::options::{RefineOptions, DEFAULT_MAX_OUTPUT_BYTES};
use crate::names::{Named, UnknownName};
use crate::scheme::{NormalMode, Scheme};

/// Every key of the text form with what its value is, in the order text is written.
pub const OPTION_KEYS: &[(&str, &str)] = &[
    (
        "scheme",
        "the surface: flat, phong, pn, png1, pn-aen, st or quadratic",
    ),
    (
        "alpha",
        "Phong's shape factor, a finite number (0 flat, 1 the full projection)",
    ),
    (
        "level",
        "segments per coarse edge, a number above 0: whole on the grid is the classic \
         refinement, fractional geomorphs (grid) or is clamped to a tessellator spacing's range",
    ),
    ("spacing", "grid, equal, fractional-odd or fractional-even"),
    (
        "lod",
        "per-edge levels from a LOD function: tolerance:D, screen:PX (needs camera, size) or \
         distance:NEAR,FAR,MAX (needs camera); replaces level",
    ),
    (
        "camera",
        "EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEG, for lod",
    ),
    ("size", "WIDTHxHEIGHT of the image, for lod screen:PX"),
    (
        "normals",
        "how normals are made (default: the scheme's own)",
    ),
    (
        "soup",
        "true: every coarse triangle gets its own vertices; false (default): welded",
    ),
    (
        "max-memory",
        "refuse outputs over this many bytes: 512MiB, 8GiB, 1000000",
    ),
];

/// A bad option: which key, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OptionError {
    /// The key as the text form spells it (`level`, `lod`, ...).
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for OptionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.key, self.message)
    }
}

impl std::error::Error for OptionError {}

fn error(key: &str, message: impl Into<String>) -> OptionError {
    OptionError {
        key: key.into(),
        message: message.into(),
    }
}

fn named<T: Named + std::str::FromStr<Err = UnknownName>>(
    key: &str,
    value: &str,
) -> Result<T, OptionError> {
    value
        .parse()
        .map_err(|e: UnknownName| error(key, e.to_string()))
}

fn number(key: &str, value: &str) -> Result<f64, OptionError> {
    value
        .trim()
        .parse::<f64>()
        .map_err(|_| error(key, format!("{value:?} is not a number")))
}

/// A level for every edge: a finite number above 0.
pub fn parse_level(value: &str) -> Result<f64, OptionError> {
    let level = number("level", value)?;
    if !(level.is_finite() && level > 0.0) {
        return Err(error(
            "level",
            format!("must be a finite number above 0 (segments per coarse edge), got {value}"),
        ));
    }
    Ok(level)
}

/// `true`/`false` (ASCII case ignored, so Python's `True` too), `1`/`0`.
fn boolean(key: &str, value: &str) -> Result<bool, OptionError> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        _ => Err(error(key, format!("{value:?} is not true or false"))),
    }
}

/// `WIDTHxHEIGHT`, both at least 1.
pub fn parse_size(value: &str) -> Result<[u32; 2], OptionError> {
    let bad = || error("size", format!("{value:?} is not a size like 800x600"));
    let (w, h) = value.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if w == 0 || h == 0 {
        return Err(error(
            "size",
            format!("{value:?}: width and height must be at least 1"),
        ));
    }
    Ok([w, h])
}

/// `512MiB`, `8GiB`, `1.5G`, `1000000` (bytes; powers of 1024).
pub fn parse_bytes(value: &str) -> Result<u64, OptionError> {
    let t = value.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (digits, unit) = t.split_at(split);
    let bad = || {
        error(
            "max-memory",
            format!("{value:?} is not a size like 512MiB or 8GiB"),
        )
    };
    let amount: f64 = digits.parse().map_err(|_| bad())?;
    let scale: f64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kb" | "kib" => 1024.0,
        "m" | "mb" | "mib" => 1024.0 * 1024.0,
        "g" | "gb" | "gib" => 1024.0f64.powi(3),
        "t" | "tb" | "tib" => 1024.0f64.powi(4),
        other => {
            return Err(error(
                "max-memory",
                format!("unknown unit {other:?} in {value:?}; use B, KiB, MiB, GiB or TiB"),
            ))
        }
    };
    Ok((amount * scale) as u64)
}

impl RefineOptions {
    /// Options from `key=value` pairs ([`OPTION_KEYS`]); keys left out keep their defaults
    /// (`scheme=pn level=8 spacing=grid`, welded, the scheme's normals, 8 GiB). Keys are
    /// spelt as in the table (`_` for `-` is accepted); a key given twice, an unknown key or a
    /// bad value is an [`OptionError`] naming it. `camera` and `size` serve `lod` alone.
    pub fn from_pairs<K: AsRef<str>, V: AsRef<str>>(
        pairs: impl IntoIterator<Item = (K, V)>,
    ) -> Result<RefineOptions, OptionError> {
        let mut given: [Option<String>; 10] = Default::default();
        for (key, value) in pairs {
            let key = key.as_ref().trim().replace('_', "-");
            let Some(slot) = OPTION_KEYS.iter().position(|(k, _)| *k == key) else {
                let known: Vec<&str> = OPTION_KEYS.iter().map(|(k, _)| *k).collect();
                return Err(error(
                    &key,
                    format!("unknown option; the options are {}", known.join(", ")),
                ));
            };
            if given[slot].is_some() {
                return Err(error(&key, "given twice"));
            }
            given[slot] = Some(value.as_ref().trim().to_string());
        }
        let [scheme, alpha, level, spacing, lod, camera, size, normals, soup, max_memory] = given;
        let mut scheme = match scheme {
            Some(v) => named::<Scheme>("scheme", &v)?,
            None => Scheme::Pn,
        };
        if let Some(v) = alpha {
            let a = number("alpha", &v)?;
            if !a.is_finite() {
                return Err(error(
                    "alpha",
                    format!("must be finite (usually within 0..=1), got {v}"),
                ));
            }
            scheme = scheme.with_alpha(a as f32);
        }
        let spacing = match spacing {
            Some(v) => named::<Spacing>("spacing", &v)?,
            None => Spacing::Grid,
        };
        let levels = match (lod, level) {
            (Some(_), Some(_)) => {
                return Err(error("lod", "replaces level; give one of them"));
            }
            (Some(spec), None) => {
                let camera = camera
                    .as_deref()
                    .map(Camera::parse)
                    .transpose()
                    .map_err(|e| error("camera", e.to_string()))?;
                let size = size.as_deref().map(parse_size).transpose()?;
                let lod =
                    Lod::parse(&spec, camera, size).map_err(|e| error("lod", e.to_string()))?;
                Levels::Lod(lod)
            }
            (None, level) => {
                if camera.is_some() || size.is_some() {
                    let key = if camera.is_some() { "camera" } else { "size" };
                    return Err(error(
                        key,
                        "serves lod=screen:PX and lod=distance:NEAR,FAR,MAX; add a lod",
                    ));
                }
                Levels::Uniform(level.as_deref().map_or(Ok(8.0), parse_level)? as f32)
            }
        };
        let mut options = RefineOptions::new(scheme, 1)
            .with_spacing(spacing)
            .with_levels(levels);
        if let Some(v) = normals {
            options = options.with_normals(named::<NormalMode>("normals", &v)?);
        }
        if let Some(v) = soup {
            options = options.with_weld(!boolean("soup", &v)?);
        }
        if let Some(v) = max_memory {
            options = options.with_max_output_bytes(parse_bytes(&v)?);
        }
        Ok(options)
    }
}

/// Text: pairs separated by whitespace or `&` (a URL's query string without its `?`).
impl std::str::FromStr for RefineOptions {
    type Err = OptionError;
    fn from_str(text: &str) -> Result<RefineOptions, OptionError> {
        let pairs = text
            .split(|c: char| c == '&' || c.is_whitespace())
            .filter(|p| !p.is_empty())
            .map(|p| {
                p.split_once('=')
                    .ok_or_else(|| error(p, "expected key=value"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        RefineOptions::from_pairs(pairs)
    }
}

/// The text form, one space between pairs: scheme, Phong's alpha, the levels, spacing, then
/// what differs from the defaults. Tags and per-edge levels have no text form and are left
/// out; a distance LOD keeps only its eye, written as a camera looking down −Z with a 45°
/// field of view.
impl std::fmt::Display for RefineOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "scheme={}", self.scheme.name())?;
        if let Scheme::Phong { alpha } = self.scheme {
            write!(f, " alpha={alpha}")?;
        }
        match &self.levels {
            Levels::Uniform(level) => write!(f, " level={level}")?,
            Levels::Lod(Lod::Tolerance { max_deviation }) => {
                write!(f, " lod=tolerance:{max_deviation}")?
            }
            Levels::Lod(Lod::Screen {
                pixels,
                camera: c,
                size,
            }) => {
                write!(
                    f,
                    " lod=screen:{pixels} camera={c} size={}x{}",
                    size[0], size[1]
                )?;
            }
            Levels::Lod(Lod::Distance {
                near,
                far,
                max,
                eye,
            }) => {
                let camera = Camera {
                    eye: *eye,
                    target: [eye[0], eye[1], eye[2] - 1.0],
                    fov_y_deg: 45.0,
                };
                write!(f, " lod=distance:{near},{far},{max} camera={camera}")?;
            }
            // Per-edge levels have no text form.
            _ => {}
        }
        write!(f, " spacing={}", self.spacing)?;
        if let Some(normals) = self.normals {
            write!(f, " normals={}", normals.name())?;
        }
        if !self.weld {
            f.write_str(" soup=true")?;
        }
        if self.max_output_bytes != DEFAULT_MAX_OUTPUT_BYTES {
            write!(f, " max-memory={}", self.max_output_bytes)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<RefineOptions, OptionError> {
        text.parse()
    }

    #[test]
    fn defaults_are_the_documented_ones() {
        let o = parse("").unwrap();
        assert_eq!(o, RefineOptions::new(Scheme::Pn, 8));
        assert_eq!(o.uniform_grid_level(), Some(8));
    }

    #[test]
    fn every_key_reaches_its_field() {
        let o = parse(
            "scheme=phong alpha=0.25 level=3.5 spacing=fractional-even normals=real \
             soup=True max_memory=2MiB",
        )
        .unwrap();
        assert_eq!(o.scheme, Scheme::Phong { alpha: 0.25 });
        assert_eq!(o.levels, Levels::Uniform(3.5));
        assert_eq!(o.spacing, Spacing::FractionalEven);
        assert_eq!(o.normals, Some(NormalMode::Real));
        assert!(!o.weld);
        assert_eq!(o.max_output_bytes, 2 << 20);
        let o = parse("lod=screen:12&camera=0,0,5,0,0,0,45&size=640x480").unwrap();
        let Levels::Lod(Lod::Screen {
            pixels,
            camera,
            size,
        }) = o.levels
        else {
            panic!("{:?}", o.levels)
        };
        assert_eq!(
            (pixels, camera.eye, camera.fov_y_deg, size),
            (12.0, [0.0, 0.0, 5.0], 45.0, [640, 480])
        );
    }

    #[test]
    fn text_round_trips() {
        for text in [
            "scheme=pn level=8 spacing=grid",
            "scheme=phong alpha=0.3 level=5.25 spacing=fractional-odd normals=quadratic soup=true",
            "scheme=png1 lod=tolerance:0.01 spacing=equal max-memory=1048576",
            "scheme=st lod=screen:18 camera=1,2,3,0,0,0,50 size=800x600 spacing=grid",
            "scheme=pn-aen lod=distance:1,10,8 camera=0,0,5,0,0,4,45 spacing=grid",
        ] {
            let o = parse(text).unwrap();
            assert_eq!(o.to_string(), text);
            assert_eq!(parse(&o.to_string()).unwrap(), o);
        }
    }

    #[test]
    fn bad_options_name_their_key() {
        for (text, key, says) in [
            ("levle=3", "levle", "unknown option"),
            ("level=3 level=4", "level", "given twice"),
            ("level", "level", "expected key=value"),
            ("scheme=loop", "scheme", "unknown scheme"),
            ("alpha=inf", "alpha", "must be finite"),
            ("level=0", "level", "above 0"),
            ("level=NaN", "level", "above 0"),
            ("level=-2", "level", "above 0"),
            ("level=x", "level", "not a number"),
            ("spacing=odd", "spacing", "unknown spacing"),
            ("lod=screen:4", "lod", "needs a camera"),
            ("lod=tolerance:0", "lod", "above 0"),
            ("lod=tolerance:1 level=3", "lod", "replaces level"),
            ("camera=0,0,5,0,0,0,45", "camera", "add a lod"),
            ("lod=distance:1,2,3 camera=1,2", "camera", "7 numbers"),
            (
                "lod=screen:4 camera=0,0,5,0,0,0,45 size=0x4",
                "size",
                "at least 1",
            ),
            ("normals=cubic", "normals", "unknown"),
            ("soup=maybe", "soup", "true or false"),
            ("max-memory=3parsecs", "max-memory", "unknown unit"),
        ] {
            let e = parse(text).unwrap_err();
            assert_eq!(e.key, key, "{text}: {e}");
            assert!(e.message.contains(says), "{text}: {e} lacks {says:?}");
        }
    }

    #[test]
    fn byte_sizes_parse() {
        assert_eq!(parse_bytes("8GiB"), Ok(8 << 30));
        assert_eq!(parse_bytes("512 MiB"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5k"), Ok(1536));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("lots").is_err());
        assert_eq!(parse_size("640X480"), Ok([640, 480]));
        assert!(parse_size("640").is_err());
    }
}
