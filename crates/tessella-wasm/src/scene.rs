//! `refineGltf`: a whole glTF scene refined and written back as GLB
//! (`tessella_io::gltf::scene`), every triangle primitive with its material, attributes, morph
//! targets and skin; nodes, materials, textures, animations and extensions kept. The same code
//! as the CLI's `tessella refine in.glb -o out.glb`, so the same bytes.

use crate::errors;
use crate::files::GltfBuffers;
use crate::options::{self, Options};
use serde_json::{json, Map, Value};
use tessella_core::refine::{Levels, Spacing};
use tessella_io::gltf::scene::{
    JointSets, RefinedScene, Scene, SceneLevels, SceneOptions, Tangents, MAX_JOINT_SETS,
};
use tessella_io::gltf::Buffers;
use wasm_bindgen::prelude::*;

/// The scene's options from the JS options object: `maxEdge` (a length, instead of `level`)
/// taken out, the rest read as `refine`'s options; the options that work on one merged mesh
/// only (`lod`, `spacing`, a fractional `level`, `soup`, `origin`) are refused by name.
pub fn scene_options(json: &str) -> Result<SceneOptions, String> {
    let mut map: Map<String, Value> = options::parse(json)?;
    map.retain(|_, v| !v.is_null());
    let max_edge = map.remove("maxEdge");
    let tangents = match map.remove("tangents") {
        None => Tangents::Recomputed,
        Some(Value::String(name)) => Tangents::parse(&name).ok_or_else(|| {
            format!(
                "tangents: 'recomputed' (MikkTSpace on the refined mesh) or 'carried' (the \
                 file's tangents, interpolated), got '{name}'"
            )
        })?,
        Some(other) => return Err(format!("tangents: 'recomputed' or 'carried', got {other}")),
    };
    let joint_sets = match map.remove("jointSets") {
        None => JointSets::AsInput,
        Some(value) => {
            let text = match &value {
                Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            JointSets::parse(&text).ok_or_else(|| {
                format!(
                    "jointSets: 'input' (as many sets as the file has) or a number of sets from 1 to {MAX_JOINT_SETS}, got {value}"
                )
            })?
        }
    };
    if max_edge.is_some() && map.contains_key("level") {
        return Err(
            "level and maxEdge both given: give one (level: the same level for every \
                    primitive; maxEdge: each primitive's level from a target edge length)"
                .into(),
        );
    }
    let Options { refine, origin } = Options::from_map(&map)?;
    let merged_only = [
        (matches!(refine.levels, Levels::Lod(_)), "lod"),
        (refine.spacing != Spacing::Grid, "spacing"),
        (
            !matches!(refine.levels, Levels::Uniform(x) if x.fract() == 0.0),
            "a fractional level",
        ),
        (!refine.weld, "soup"),
        (origin, "origin"),
    ];
    if let Some((_, option)) = merged_only.iter().find(|(on, _)| *on) {
        return Err(format!(
            "{option} works on one mesh (refine); a glTF scene is refined primitive by \
             primitive with a whole level or maxEdge"
        ));
    }
    let levels = match max_edge {
        Some(value) => {
            let length = match &value {
                Value::Number(n) => n.as_f64(),
                Value::String(s) => s.parse::<f64>().ok(),
                _ => None,
            }
            .filter(|l| l.is_finite() && *l > 0.0 && *l as f32 > 0.0);
            match length {
                Some(l) => SceneLevels::MaxEdge(l as f32),
                None => {
                    return Err(format!(
                        "maxEdge: must be a length above 0 (the refined edges' target length \
                         in world units), got {value}"
                    ))
                }
            }
        }
        None => SceneLevels::Uniform(
            refine
                .uniform_grid_level()
                .expect("a whole grid level, checked above"),
        ),
    };
    Ok(SceneOptions::new(refine, levels)
        .with_tangents(tangents)
        .with_joint_sets(joint_sets))
}

/// The name a file's bytes are read under (its format and the name in messages): a GLB
/// starts with the magic `glTF`; anything else is read as a `.gltf` (JSON).
pub fn file_name(bytes: &[u8]) -> &'static str {
    match bytes.starts_with(b"glTF") {
        true => "scene.glb",
        false => "scene.gltf",
    }
}

/// Reads, refines and writes a scene; the messages are tessella-io's.
pub fn refine(bytes: &[u8], buffers: &GltfBuffers, json: &str) -> Result<RefinedGltf, String> {
    let options = scene_options(json)?;
    let given = buffers.given()?;
    let scene = Scene::from_bytes(file_name(bytes), bytes, Buffers::Given(&given))
        .map_err(|e| errors::message(&e))?;
    let refined = scene.refine(&options).map_err(|e| errors::message(&e))?;
    let glb = refined.to_glb().map_err(|e| errors::message(&e))?;
    Ok(RefinedGltf {
        glb,
        report: report(&refined).to_string(),
    })
}

/// One entry per refined primitive, as JS reads it.
fn report(refined: &RefinedScene) -> Value {
    let entries: Vec<Value> = refined
        .primitives
        .iter()
        .zip(&refined.which)
        .map(|(r, &(mesh, primitive))| {
            json!({
                "mesh": mesh,
                "primitive": primitive,
                "level": r.level,
                "coarseTriangles": r.coarse_triangles,
                "degenerate": r.degenerate,
                "vertices": r.vertices,
                "triangles": r.triangles,
                "notes": r.notes,
            })
        })
        .collect();
    Value::Array(entries)
}

/// A refined scene: the GLB bytes (taken once) and the per-primitive report (JSON).
#[wasm_bindgen]
#[derive(Debug, Default)]
pub struct RefinedGltf {
    glb: Vec<u8>,
    report: String,
}

#[wasm_bindgen]
impl RefinedGltf {
    #[wasm_bindgen(js_name = takeGlb)]
    pub fn take_glb(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.glb)
    }
    /// The per-primitive report as JSON text.
    #[wasm_bindgen(getter)]
    pub fn report(&self) -> String {
        self.report.clone()
    }
}

/// `refineGltf` for JS: see `js/src/index.js`.
#[wasm_bindgen(js_name = refineGltf)]
pub fn refine_js(bytes: &[u8], buffers: &GltfBuffers, json: &str) -> Result<RefinedGltf, JsError> {
    refine(bytes, buffers, json).map_err(errors::text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(name: &str) -> Vec<u8> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/");
        std::fs::read(format!("{path}{name}")).unwrap()
    }

    #[test]
    fn options_map_to_the_scene_levels() {
        let o = scene_options(r#"{"scheme":"phong","level":3,"alpha":0.5}"#).unwrap();
        assert_eq!(o.levels, SceneLevels::Uniform(3));
        assert_eq!(o.refine.scheme, tessella_core::Scheme::Phong { alpha: 0.5 });
        let o = scene_options(r#"{"maxEdge":0.25,"level":null}"#).unwrap();
        assert_eq!(o.levels, SceneLevels::MaxEdge(0.25));
        assert_eq!(scene_options("{}").unwrap().levels, SceneLevels::Uniform(8));
        assert_eq!(scene_options("{}").unwrap().tangents, Tangents::Recomputed);
        let o = scene_options(r#"{"tangents":"carried"}"#).unwrap();
        assert_eq!(o.tangents, Tangents::Carried);
        assert_eq!(o.joint_sets, JointSets::AsInput);
        let o = scene_options(r#"{"jointSets":3}"#).unwrap();
        assert_eq!(o.joint_sets, JointSets::UpTo(3));
        let o = scene_options(r#"{"jointSets":"input"}"#).unwrap();
        assert_eq!(o.joint_sets, JointSets::AsInput);
    }

    #[test]
    fn bad_scene_options_say_why() {
        for (json, expected) in [
            (
                r#"{"level":3,"maxEdge":0.1}"#,
                "level and maxEdge both given",
            ),
            (r#"{"maxEdge":0}"#, "maxEdge: must be a length above 0"),
            (r#"{"maxEdge":"NaN"}"#, "maxEdge: must be a length above 0"),
            (r#"{"maxEdge":"long"}"#, "maxEdge: must be a length above 0"),
            (r#"{"level":2.5}"#, "a fractional level works on one mesh"),
            (r#"{"lod":"tolerance:0.1"}"#, "lod works on one mesh"),
            (
                r#"{"spacing":"equal","level":3}"#,
                "spacing works on one mesh",
            ),
            (r#"{"soup":true}"#, "soup works on one mesh"),
            (r#"{"origin":true}"#, "origin works on one mesh"),
            (r#"{"levle":3}"#, "levle: unknown option"),
            (r#"{"level":0}"#, "level: must be a finite number above 0"),
            (r#"{"tangents":"guessed"}"#, "tangents: 'recomputed'"),
            (r#"{"jointSets":9}"#, "jointSets: 'input' (as many sets as the file has) or a number of sets from 1 to 8, got 9"),
            (r#"{"jointSets":1.5}"#, "jointSets: 'input'"),
            (
                r#"{"tangents":3}"#,
                "tangents: 'recomputed' or 'carried', got 3",
            ),
        ] {
            let err = scene_options(json).map(|_| ()).unwrap_err();
            assert!(err.contains(expected), "{json}: {err:?} lacks {expected:?}");
        }
    }

    #[test]
    fn a_scene_is_refined_whole_with_a_report() {
        let bytes = sample("scene.glb");
        let mut out = refine(&bytes, &GltfBuffers::default(), r#"{"level":2}"#).unwrap();
        let report: Value = serde_json::from_str(&out.report()).unwrap();
        let entries = report.as_array().unwrap();
        assert!(!entries.is_empty());
        for e in entries {
            assert_eq!(e["level"], 2);
            assert_eq!(
                e["triangles"].as_u64().unwrap(),
                4 * e["coarseTriangles"].as_u64().unwrap()
            );
        }
        let glb = out.take_glb();
        assert_eq!(&glb[..4], b"glTF");
        // The output reads back as a scene.
        Scene::from_bytes("out.glb", &glb, Buffers::Given(&[])).unwrap();
    }

    #[test]
    fn broken_files_are_errors() {
        let bytes = sample("scene.glb");
        let none = GltfBuffers::default();
        let err = refine(&bytes[..bytes.len() / 2], &none, "{}")
            .map(|_| ())
            .unwrap_err();
        assert!(err.contains("scene.glb"), "{err}");
        let err = refine(b"{", &none, "{}").map(|_| ()).unwrap_err();
        assert!(err.contains("scene.gltf"), "{err}");
    }
}
