//! The viewer's parameters, with `tessella render`'s names and meanings, parsed from JSON values
//! (what the web page's URL or controls give: strings, or typed numbers, booleans, arrays).
//!
//! Names are parsed by the same code the CLI uses: schemes and normal modes by the core's
//! [`tessella_core::names`], spacings by [`Spacing`]'s `FromStr`, LODs by [`Lod::parse`],
//! displacement by [`Displacement::parse`], the level by
//! [`tessella_core::RefineOptions::with_uniform_level`] (in `panel.rs`). [`Params::apply`]
//! validates every change before it takes any, so a bad value leaves the parameters as they
//! were.

use crate::error::ViewerError;
use serde_json::{json, Map, Value};
use tessella_core::displace::Displacement;
use tessella_core::refine::{Ask, Camera, Lod, Spacing};
use tessella_core::{Named, NormalMode, RefineOptions, Scheme};

/// The deformation `frame(timeMs)` plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Animation {
    #[default]
    None,
    /// [`tessella_core::samples::twist`], up to 60 degrees (`deform.rs`).
    Twist,
    /// A bend about the Z axis, the bottom fixed, up to 45 degrees (`deform.rs`).
    Bend,
}

impl Animation {
    const NAMES: [&'static str; 3] = ["none", "twist", "bend"];
    fn name(self) -> &'static str {
        match self {
            Animation::None => "none",
            Animation::Twist => "twist",
            Animation::Bend => "bend",
        }
    }
}

/// Every parameter of a view (the table in `CONTRACT.md`).
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// The scheme drawn when `panels` is empty (Phong's alpha is `alpha`).
    pub scheme: Scheme,
    /// Segments per coarse edge (`lod: fixed`): whole on the grid, or fractional.
    pub level: f64,
    pub spacing: Spacing,
    /// `None`: fixed levels. `Some(spec)`: `screen:PX`, `distance:NEAR,FAR,MAX`, `tolerance:D`,
    /// evaluated every frame with the current camera.
    pub lod: Option<String>,
    pub alpha: f32,
    /// `None`: the scheme's own normals.
    pub normals: Option<NormalMode>,
    pub wireframe: bool,
    /// The spec as given (`None` for no displacement) and its parsed form.
    pub displace: Option<String>,
    pub displacement: Displacement,
    pub yaw: f32,
    pub pitch: f32,
    pub zoom: f32,
    pub pan: [f32; 2],
    /// Grid spacing with fractional levels: morph (`true`) or round the levels up.
    pub geomorph: bool,
    pub animate: Animation,
    /// One panel per scheme, side by side; empty: `scheme` alone.
    pub panels: Vec<Scheme>,
    /// Tags JSON text (the CLI's `--tags` format); empty: none.
    pub tags: String,
    /// The loaded file's animation clip played, by name or index as given (checked against
    /// the file's clips by the viewer); `None`: the rest pose. A clip overrides `animate`.
    pub clip: Option<String>,
    /// Seconds into the clip: where it is paused, or where it plays from.
    pub time: f32,
    /// The clip plays (its time advances with the frames, looping) or stays at `time`.
    pub playing: bool,
}

impl Default for Params {
    fn default() -> Self {
        let view = tessella_view::RenderOptions::default();
        Params {
            scheme: Scheme::Pn,
            level: 8.0,
            spacing: Spacing::Grid,
            lod: None,
            alpha: 0.75,
            normals: None,
            wireframe: false,
            displace: None,
            displacement: Displacement::None,
            yaw: view.yaw,
            pitch: view.pitch,
            zoom: view.zoom,
            pan: view.pan,
            geomorph: true,
            animate: Animation::None,
            panels: Vec::new(),
            tags: String::new(),
            clip: None,
            time: 0.0,
            playing: true,
        }
    }
}

/// The keys [`Params::apply`] takes, in `CONTRACT.md`'s order.
pub const KEYS: [&str; 20] = [
    "scheme",
    "level",
    "spacing",
    "lod",
    "alpha",
    "normals",
    "wireframe",
    "displace",
    "yaw",
    "pitch",
    "zoom",
    "pan",
    "geomorph",
    "animate",
    "panels",
    "tags",
    "clip",
    "time",
    "playing",
    // Accepted for the URL's sake (`?mesh=...`): the page loads meshes itself, so it is
    // ignored here.
    "mesh",
];

/// Keys whose change only moves the camera or the per-frame work: no surface rebuild.
const VIEW_ONLY: [&str; 10] = [
    "wireframe",
    "yaw",
    "pitch",
    "zoom",
    "pan",
    "animate",
    "clip",
    "time",
    "playing",
    "mesh",
];

fn bad(name: &'static str, message: impl Into<String>) -> ViewerError {
    ViewerError::Param {
        name,
        message: message.into(),
    }
}

/// A number given as a JSON number or a numeric string, finite.
fn number(name: &'static str, value: &Value) -> Result<f64, ViewerError> {
    let x = match value {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => s.trim().parse::<f64>().ok(),
        _ => None,
    }
    .ok_or_else(|| bad(name, format!("{value} is not a number")))?;
    if !x.is_finite() {
        return Err(bad(name, format!("must be finite, got {x}")));
    }
    Ok(x)
}

/// A finite number that fits an `f32`.
fn float(name: &'static str, value: &Value) -> Result<f32, ViewerError> {
    let x = number(name, value)?;
    if x.abs() > f32::MAX as f64 {
        return Err(bad(name, format!("{x} is out of range")));
    }
    Ok(x as f32)
}

fn boolean(name: &'static str, value: &Value) -> Result<bool, ViewerError> {
    match value {
        Value::Bool(b) => Ok(*b),
        Value::Number(n) if n.as_f64() == Some(0.0) => Ok(false),
        Value::Number(n) if n.as_f64() == Some(1.0) => Ok(true),
        Value::String(s) => match s.trim().to_ascii_lowercase().as_str() {
            "true" | "1" | "on" | "yes" => Ok(true),
            "false" | "0" | "off" | "no" => Ok(false),
            _ => Err(bad(name, format!("{s:?} is not true or false"))),
        },
        _ => Err(bad(name, format!("{value} is not true or false"))),
    }
}

fn text<'v>(name: &'static str, value: &'v Value) -> Result<&'v str, ViewerError> {
    value
        .as_str()
        .ok_or_else(|| bad(name, format!("{value} is not a string")))
}

/// A list given as a JSON array of strings or one comma-separated string.
fn list(name: &'static str, value: &Value) -> Result<Vec<String>, ViewerError> {
    match value {
        Value::Array(items) => items
            .iter()
            .map(|v| text(name, v).map(|s| s.trim().to_string()))
            .collect(),
        Value::String(s) => Ok(s
            .split(',')
            .map(str::trim)
            .filter(|p| !p.is_empty())
            .map(String::from)
            .collect()),
        _ => Err(bad(name, format!("{value} is not a list"))),
    }
}

fn scheme(name: &'static str, text: &str) -> Result<Scheme, ViewerError> {
    text.trim()
        .parse::<Scheme>()
        .map_err(|e| bad(name, e.to_string()))
}

/// Checks a LOD spec as [`Lod::parse`] does, with a stand-in camera and size (the real ones
/// come every frame).
fn check_lod(spec: &str) -> Result<(), ViewerError> {
    let camera = Camera {
        eye: [0.0, 0.0, 5.0],
        target: [0.0; 3],
        fov_y_deg: 30.0,
    };
    Lod::parse(spec, Some(camera), Some([512, 512]))
        .map(|_| ())
        .map_err(|e| bad("lod", e.to_string()))
}

impl Params {
    /// The refinement options of `scheme` in the core's text form
    /// ([`tessella_core::refine::OPTION_KEYS`]), which `panel::refine_options` parses:
    /// the URL's `level`, `spacing`, `alpha` and `normals` mean what `tessella refine`'s flags
    /// and Python's arguments of those names mean. A LOD's levels follow the camera every frame
    /// (`Panel::follow_camera`), so it is not among them.
    pub fn refine_pairs(&self, scheme: Scheme) -> Vec<(&'static str, String)> {
        let mut pairs = vec![
            ("scheme", scheme.name().to_string()),
            ("alpha", self.alpha.to_string()),
            ("level", self.level.to_string()),
            ("spacing", self.spacing.to_string()),
        ];
        if let Some(normals) = self.normals {
            pairs.push(("normals", normals.name().to_string()));
        }
        pairs
    }

    /// These parameters with `changes` (a JSON object of any subset of [`KEYS`]) applied, all
    /// validated first; an error names the parameter and nothing changes.
    pub fn apply(&self, changes: &Map<String, Value>) -> Result<Params, ViewerError> {
        let mut p = self.clone();
        for (key, value) in changes {
            match key.as_str() {
                "scheme" => p.scheme = scheme("scheme", text("scheme", value)?)?,
                "level" => {
                    let level = match value {
                        Value::String(s) => s.clone(),
                        other => other.to_string(),
                    };
                    p.level = tessella_core::refine::parse_level(&level)
                        .map_err(|e| bad("level", e.message))?;
                }
                "spacing" => {
                    p.spacing = text("spacing", value)?
                        .trim()
                        .parse()
                        .map_err(|e: tessella_core::UnknownName| bad("spacing", e.to_string()))?
                }
                "lod" => {
                    let spec = text("lod", value)?.trim();
                    p.lod = if spec == "fixed" || spec.is_empty() {
                        None
                    } else {
                        check_lod(spec)?;
                        Some(spec.to_string())
                    };
                }
                "alpha" => p.alpha = float("alpha", value)?,
                "normals" => {
                    let name = text("normals", value)?.trim();
                    p.normals = if name == "default" || name.is_empty() {
                        None
                    } else {
                        Some(name.parse().map_err(|e: tessella_core::UnknownName| {
                            bad(
                                "normals",
                                format!("{e} (or \"default\" for the scheme's own)"),
                            )
                        })?)
                    };
                }
                "wireframe" => p.wireframe = boolean("wireframe", value)?,
                "displace" => {
                    let spec = text("displace", value)?.trim();
                    if spec == "none" || spec.is_empty() {
                        p.displace = None;
                        p.displacement = Displacement::None;
                    } else {
                        let no_files = |_: &str| {
                            Err(
                                "height maps need an image file; the viewer takes sine and perlin"
                                    .to_string(),
                            )
                        };
                        let d = Displacement::parse(spec, no_files)
                            .map_err(|e| bad("displace", e.to_string()))?;
                        d.validate(true)
                            .map_err(|e| bad("displace", e.to_string()))?;
                        p.displace = Some(spec.to_string());
                        p.displacement = d;
                    }
                }
                "yaw" => p.yaw = float("yaw", value)?,
                "pitch" => p.pitch = float("pitch", value)?,
                "zoom" => {
                    let zoom = float("zoom", value)?;
                    if zoom <= 0.0 {
                        return Err(bad("zoom", format!("must be above 0, got {zoom}")));
                    }
                    p.zoom = zoom;
                }
                "pan" => {
                    let parts: Vec<f32> = match value {
                        Value::Array(items) => items
                            .iter()
                            .map(|v| float("pan", v))
                            .collect::<Result<_, _>>()?,
                        _ => list("pan", value)?
                            .iter()
                            .map(|s| float("pan", &Value::String(s.clone())))
                            .collect::<Result<_, _>>()?,
                    };
                    match parts.as_slice() {
                        &[x, y] => p.pan = [x, y],
                        _ => return Err(bad("pan", format!("needs two numbers x,y, got {value}"))),
                    }
                }
                "geomorph" => p.geomorph = boolean("geomorph", value)?,
                "animate" => {
                    let name = text("animate", value)?.trim();
                    p.animate = [Animation::None, Animation::Twist, Animation::Bend]
                        .into_iter()
                        .find(|a| a.name() == name)
                        .ok_or_else(|| {
                            bad(
                                "animate",
                                format!(
                                    "unknown animation {name:?}; use one of {:?}",
                                    Animation::NAMES
                                ),
                            )
                        })?;
                }
                "panels" => {
                    p.panels = list("panels", value)?
                        .iter()
                        .map(|s| scheme("panels", s))
                        .collect::<Result<_, _>>()?;
                }
                "tags" => {
                    let json = text("tags", value)?;
                    if !json.trim().is_empty() {
                        tessella_io::tags::TagFile::parse(json)
                            .map_err(|e| bad("tags", e.to_string()))?;
                    }
                    p.tags = json.to_string();
                }
                "clip" => {
                    let clip = text("clip", value)?.trim();
                    p.clip = (!clip.is_empty() && clip != "none").then(|| clip.to_string());
                }
                "time" => {
                    let time = float("time", value)?;
                    if time < 0.0 {
                        return Err(bad(
                            "time",
                            format!("must be 0 or more seconds, got {time}"),
                        ));
                    }
                    p.time = time;
                }
                "playing" => p.playing = boolean("playing", value)?,
                "mesh" => {}
                other => {
                    return Err(ViewerError::Param {
                        name: "params",
                        message: format!("unknown parameter {other:?}; use one of {KEYS:?}"),
                    })
                }
            }
        }
        p.check()?;
        Ok(p)
    }

    /// Checks what depends on several parameters at once: the core's rules
    /// ([`RefineOptions::conflict`]), the asks spelt as the parameters are.
    fn check(&self) -> Result<(), ViewerError> {
        if !self.displacement.is_some() {
            return Ok(());
        }
        let options = RefineOptions::from_pairs(self.refine_pairs(self.scheme))
            .map_err(|e| bad("options", e.to_string()))?;
        // The viewer's LOD is chosen per frame, outside the options.
        let lod = self.lod.is_some().then_some(Ask::Lod);
        options
            .conflict([Some(Ask::Displace), lod].into_iter().flatten())
            .map_err(|c| {
                let spell = |ask: Ask| match ask {
                    Ask::FractionalLevel => "a fractional level".to_string(),
                    other => other.key().to_string(),
                };
                bad("displace", c.message(spell))
            })
    }

    /// Whether the levels are one whole number on the grid: the pattern renderer draws them.
    pub fn is_uniform_grid(&self) -> bool {
        self.lod.is_none() && self.spacing == Spacing::Grid && self.level.fract() == 0.0
    }

    /// The schemes drawn, one per panel, Phong with `alpha`.
    pub fn schemes(&self) -> Vec<Scheme> {
        let list = if self.panels.is_empty() {
            vec![self.scheme]
        } else {
            self.panels.clone()
        };
        list.into_iter().map(|s| s.with_alpha(self.alpha)).collect()
    }

    /// Whether going from `self` to `next` needs the surfaces rebuilt (anything but the view).
    pub fn needs_rebuild(&self, next: &Params) -> bool {
        let view_only = |p: &Params| Params {
            wireframe: false,
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.0,
            pan: [0.0; 2],
            animate: Animation::None,
            clip: None,
            time: 0.0,
            playing: true,
            ..p.clone()
        };
        debug_assert!(VIEW_ONLY.iter().all(|k| KEYS.contains(k)));
        view_only(self) != view_only(next)
    }

    /// Every parameter as a JSON object, typed (what `get()` returns).
    pub fn to_json(&self) -> Value {
        json!({
            "scheme": self.scheme.name(),
            "level": self.level,
            "spacing": self.spacing.name(),
            "lod": self.lod.as_deref().unwrap_or("fixed"),
            "alpha": self.alpha,
            "normals": self.normals.map_or("default", |n| n.name()),
            "wireframe": self.wireframe,
            "displace": self.displace.as_deref().unwrap_or("none"),
            "yaw": self.yaw,
            "pitch": self.pitch,
            "zoom": self.zoom,
            "pan": self.pan,
            "geomorph": self.geomorph,
            "animate": self.animate.name(),
            "panels": self.panels.iter().map(|s| s.name()).collect::<Vec<_>>(),
            "tags": self.tags,
            "clip": self.clip.as_deref().unwrap_or("none"),
            "time": self.time,
            "playing": self.playing,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Displacement with levels the pattern renderer cannot draw is refused with the core's
    /// rule, the asks spelt as the parameters; a whole level on the grid takes it.
    #[test]
    fn displacement_needs_a_whole_grid_level_by_the_cores_rule() {
        let with = |pairs: Value| -> Result<Params, ViewerError> {
            let mut changes = pairs.as_object().expect("an object").clone();
            changes.insert("displace".into(), json!("sine:0.1,5"));
            Params::default().apply(&changes)
        };
        let why = "(displacement follows the uniform grid's output layout, a whole level on the \
                   grid pattern)";
        for (pairs, named) in [
            (json!({ "lod": "screen:4" }), "lod"),
            (json!({ "spacing": "equal" }), "spacing"),
            (json!({ "level": 2.5 }), "a fractional level"),
        ] {
            let err = with(pairs.clone()).expect_err("refused").to_string();
            let want = format!("displace: displace cannot be combined with {named} {why}");
            assert_eq!(err, want, "{pairs}");
        }
        assert!(with(json!({ "level": 3 })).is_ok());
    }

    /// The page's own copy of the names and defaults (`web/src/params.js`, which the page, its
    /// WebGL2 fallback and the Node tests read without the wasm) is pinned to the core's names
    /// and to these defaults: the `const NAME = [...]` arrays and the `DEFAULTS` object, read
    /// out of the file as JSON.
    #[test]
    fn the_web_pages_names_and_defaults_are_these() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../web/src/params.js");
        let text = std::fs::read_to_string(path).expect("web/src/params.js");
        let json = |literal: &str| -> Value {
            // JS literals to JSON: single quotes, bare keys, trailing commas.
            let mut out = String::new();
            for line in literal.lines() {
                let line = line.trim().replace('\'', "\"");
                let line = match line.split_once(": ") {
                    Some((key, rest)) if key.chars().all(|c| c.is_ascii_alphanumeric()) => {
                        format!("\"{key}\": {rest}")
                    }
                    _ => line,
                };
                out.push_str(&line);
            }
            let out = out.replace(",}", "}").replace(",]", "]");
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
        };
        let array = |name: &str| -> Vec<String> {
            let head = format!("export const {name} = ");
            let at = text.find(&head).expect(name) + head.len();
            let end = at + text[at..].find(';').expect("the array's end");
            serde_json::from_value(json(&text[at..end])).expect("names")
        };
        assert_eq!(array("SCHEMES"), Scheme::NAMES);
        assert_eq!(array("SPACINGS"), Spacing::NAMES);
        let mut normals = vec!["default"];
        normals.extend(NormalMode::NAMES);
        assert_eq!(array("NORMALS"), normals);
        assert_eq!(array("ANIMATIONS"), Animation::NAMES);
        let head = "export const DEFAULTS = Object.freeze(";
        let at = text.find(head).expect("DEFAULTS") + head.len();
        let end = at + text[at..].find("});").expect("the defaults' end") + 1;
        let page = json(&text[at..end]);
        let page = page.as_object().expect("an object");
        let ours = Params::default().to_json();
        let ours = ours.as_object().expect("an object");
        let keys = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
        let mut sorted = KEYS.map(String::from).to_vec();
        sorted.sort();
        assert_eq!(keys(page), sorted, "the page's keys are the engine's");
        // Numbers as numbers (the page writes 0 where the engine's f32 is 0.0), in arrays too.
        fn same(a: &Value, b: &Value) -> bool {
            match (a, b) {
                (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
                (Value::Array(x), Value::Array(y)) => {
                    x.len() == y.len() && x.iter().zip(y).all(|(p, q)| same(p, q))
                }
                _ => a == b,
            }
        }
        for (key, value) in ours {
            let page = &page[key];
            assert!(
                same(page, value),
                "{key}: the page's default {page}, the engine's {value}"
            );
        }
    }

    fn apply(p: &Params, v: Value) -> Result<Params, ViewerError> {
        p.apply(v.as_object().expect("an object"))
    }

    #[test]
    fn strings_and_typed_values_mean_the_same() {
        let p = Params::default();
        let a = apply(
            &p,
            json!({"scheme": "PNG1", "level": "5", "wireframe": "true", "pan": "0.5,-1",
                   "panels": "flat,pn", "yaw": "-30", "normals": "real", "lod": "screen:4"}),
        )
        .unwrap();
        let b = apply(
            &p,
            json!({"scheme": "png1", "level": 5, "wireframe": true, "pan": [0.5, -1],
                   "panels": ["flat", "pn"], "yaw": -30, "normals": "real", "lod": "screen:4"}),
        )
        .unwrap();
        assert_eq!(a, b);
        assert_eq!(a.scheme, Scheme::Png1);
        assert_eq!(a.panels, vec![Scheme::Flat, Scheme::Pn]);
        assert_eq!(a.pan, [0.5, -1.0]);
        // get() gives back what set() takes.
        let back = apply(&Params::default(), a.to_json()).unwrap();
        assert_eq!(back, a);
    }

    #[test]
    fn bad_values_name_the_parameter_and_change_nothing() {
        let p = Params::default();
        for (change, name) in [
            (json!({"level": "NaN"}), "level"),
            (json!({"level": 0}), "level"),
            (json!({"level": 4, "zoom": -1}), "zoom"),
            (json!({"scheme": "loop"}), "scheme"),
            (json!({"spacing": "odd"}), "spacing"),
            (json!({"lod": "screen:-1"}), "lod"),
            (json!({"lod": "fast"}), "lod"),
            (json!({"displace": "wobble:1"}), "displace"),
            (
                json!({"displace": "sine:0.1,10", "spacing": "fractional-odd"}),
                "displace",
            ),
            (json!({"displace": "sine:NaN,10"}), "displace"),
            (json!({"pan": [1]}), "pan"),
            (json!({"wireframe": "maybe"}), "wireframe"),
            (json!({"animate": "spin"}), "animate"),
            (json!({"panels": ["pn", "nurbs"]}), "panels"),
            (json!({"tags": "{not json"}), "tags"),
            (json!({"normals": "smooth"}), "normals"),
            (json!({"yaw": 1e300}), "yaw"),
            (json!({"colour": "red"}), "params"),
        ] {
            let err = apply(&p, change.clone()).unwrap_err();
            assert!(
                err.to_string().starts_with(&format!("{name}: ")),
                "{change}: {err}"
            );
        }
    }

    #[test]
    fn only_surface_parameters_rebuild() {
        let p = Params::default();
        let moved = apply(&p, json!({"yaw": 90, "zoom": 2, "wireframe": true})).unwrap();
        assert!(!p.needs_rebuild(&moved));
        let other = apply(&p, json!({"level": 3})).unwrap();
        assert!(p.needs_rebuild(&other));
        assert!(!p.is_uniform_grid() || p.lod.is_none());
        let fractional = apply(&p, json!({"level": 5.5})).unwrap();
        assert!(!fractional.is_uniform_grid());
    }
}
