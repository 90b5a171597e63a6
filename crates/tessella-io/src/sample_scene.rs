//! The bundled sample scene (`samples/scene.glb`): a small glTF asset with what real assets
//! hold, made here so tests and pictures depend on no downloaded file.
//!
//! - a node hierarchy with names, extras, a camera and a `KHR_lights_punctual` light;
//! - a ball of two primitives with two materials (one painted with vertex colours, one
//!   textured with an embedded PNG, a normal map and `KHR_texture_transform`, which the file
//!   requires), `TEXCOORD_0`, `TEXCOORD_1`, `COLOR_0`, `TANGENT`, an integer `_REGION`
//!   attribute, two degenerate triangles (a repeated corner, and two corners at one position) and a
//!   morph target;
//! - a ring mesh shown by two nodes (one a scaled child of the other), sharing the textured
//!   material;
//! - lines and points, copied as they are;
//! - two clips: the ring spinning and the ball inflating (morph weights).
//!
//! [`sample_scene`]`(true)` stores the triangle meshes' attributes as normalised integers
//! (`KHR_mesh_quantization`, required): positions as 16-bit, normals and tangents as 8-bit,
//! texture coordinates as 16-bit.
//!
//! ```
//! let scene = tessella_io::gltf::scene::Scene::from_bytes(
//!     "scene.glb",
//!     &tessella_io::sample_scene(false),
//!     tessella_io::gltf::Buffers::Given(&[]),
//! )?;
//! assert_eq!(scene.counts().triangle_primitives, 3);
//! # Ok::<(), tessella_io::IoError>(())
//! ```

use serde_json::{json, Value};
use std::f32::consts::PI;

const F32: u32 = 5126;
const I8: u32 = 5120;
const U8: u32 = 5121;
const I16: u32 = 5122;
const U16: u32 = 5123;
const TYPES: [&str; 4] = ["SCALAR", "VEC2", "VEC3", "VEC4"];

/// The document's one buffer being built.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        self.data.resize(self.data.len().next_multiple_of(4), 0);
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.data.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            view["target"] = t.into();
        }
        self.data.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// Floats, `width` per element, stored as `component` (normalised unless float).
    fn attribute(&mut self, values: &[f32], width: usize, component: u32, bounds: bool) -> usize {
        self.stored(values, width, component, bounds, Some(34962))
    }

    /// Animation data: floats in a view with no target.
    fn keys(&mut self, values: &[f32], width: usize) -> usize {
        self.stored(values, width, F32, width == 1, None)
    }

    fn stored(
        &mut self,
        values: &[f32],
        width: usize,
        component: u32,
        bounds: bool,
        target: Option<u32>,
    ) -> usize {
        let bytes: Vec<u8> = match component {
            F32 => values.iter().flat_map(|v| v.to_le_bytes()).collect(),
            I16 => values
                .iter()
                .flat_map(|v| ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16).to_le_bytes())
                .collect(),
            U16 => values
                .iter()
                .flat_map(|v| ((v.clamp(0.0, 1.0) * 65535.0).round() as u16).to_le_bytes())
                .collect(),
            I8 => values
                .iter()
                .map(|v| (v.clamp(-1.0, 1.0) * 127.0).round() as i8 as u8)
                .collect(),
            _ => values
                .iter()
                .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect(),
        };
        // Vertex attributes are 4-byte aligned per element (glTF 2.0 section 3.6.2.4).
        let size = bytes.len() / (values.len() / width).max(1);
        let stride = size.next_multiple_of(4);
        let bytes = if stride == size {
            bytes
        } else {
            bytes
                .chunks(size)
                .flat_map(|e| {
                    e.iter()
                        .copied()
                        .chain(std::iter::repeat_n(0, stride - size))
                })
                .collect()
        };
        let view = self.view(&bytes, target);
        if stride != size {
            self.views[view]["byteStride"] = stride.into();
        }
        let mut accessor = json!({
            "bufferView": view,
            "componentType": component,
            "count": values.len() / width,
            "type": TYPES[width - 1],
        });
        if component != F32 {
            accessor["normalized"] = true.into();
        }
        if bounds {
            let stored = |v: f32| match component {
                I16 => (v.clamp(-1.0, 1.0) * 32767.0).round() / 32767.0,
                _ => v,
            };
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for e in values.chunks(width) {
                for c in 0..width {
                    lo[c] = lo[c].min(stored(e[c]));
                    hi[c] = hi[c].max(stored(e[c]));
                }
            }
            if component == I16 {
                // Bounds of a normalised accessor are in its stored integers.
                accessor["min"] =
                    json!(lo.iter().map(|v| (v * 32767.0).round()).collect::<Vec<_>>());
                accessor["max"] =
                    json!(hi.iter().map(|v| (v * 32767.0).round()).collect::<Vec<_>>());
            } else {
                accessor["min"] = json!(lo);
                accessor["max"] = json!(hi);
            }
        }
        self.push(accessor)
    }

    fn ints(&mut self, values: &[u32], width: usize, component: u32, target: Option<u32>) -> usize {
        let bytes: Vec<u8> = match component {
            U8 => values.iter().map(|&v| v as u8).collect(),
            U16 => values
                .iter()
                .flat_map(|&v| (v as u16).to_le_bytes())
                .collect(),
            _ => values.iter().flat_map(|&v| v.to_le_bytes()).collect(),
        };
        // A vertex attribute's elements are padded to 4 bytes.
        let size = bytes.len() / (values.len() / width).max(1);
        let stride = if target == Some(34962) {
            size.next_multiple_of(4)
        } else {
            size
        };
        let bytes: Vec<u8> = bytes
            .chunks(size)
            .flat_map(|e| {
                e.iter()
                    .copied()
                    .chain(std::iter::repeat_n(0, stride - size))
            })
            .collect();
        let view = self.view(&bytes, target);
        if stride != size {
            self.views[view]["byteStride"] = stride.into();
        }
        self.push(json!({
            "bufferView": view,
            "componentType": component,
            "count": values.len() / width,
            "type": TYPES[width - 1],
        }))
    }

    fn push(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }
}

/// One triangle primitive's arrays before storing.
#[derive(Default)]
struct Part {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    tangents: Vec<[f32; 4]>,
    colors: Vec<[f32; 4]>,
    region: Vec<u32>,
    triangles: Vec<[u32; 3]>,
}

impl Part {
    /// Copies vertex `v` of `from` (its arrays) into this part: its new index.
    fn take(&mut self, from: &Part, v: usize) -> u32 {
        self.positions.push(from.positions[v]);
        self.normals.push(from.normals[v]);
        self.uvs.push(from.uvs[v]);
        self.tangents.push(from.tangents[v]);
        self.colors.push(from.colors[v]);
        self.region.push(from.region[v]);
        self.positions.len() as u32 - 1
    }

    /// A copy of vertex `v`: its new index.
    fn duplicate(&mut self, v: usize) -> u32 {
        self.positions.push(self.positions[v]);
        self.normals.push(self.normals[v]);
        self.uvs.push(self.uvs[v]);
        self.tangents.push(self.tangents[v]);
        self.colors.push(self.colors[v]);
        self.region.push(self.region[v]);
        self.positions.len() as u32 - 1
    }

    /// Stores the part; `quantized`: integer attributes where glTF allows them with
    /// `KHR_mesh_quantization`.
    fn store(&self, bin: &mut Bin, quantized: bool, extras: bool) -> Value {
        let (pos, dir, uv) = if quantized {
            (I16, I8, U16)
        } else {
            (F32, F32, F32)
        };
        let mut attributes = json!({
            "POSITION": bin.attribute(self.positions.as_flattened(), 3, pos, true),
            "NORMAL": bin.attribute(self.normals.as_flattened(), 3, dir, false),
        });
        if extras {
            let uv1: Vec<[f32; 2]> = self.uvs.iter().map(|t| [t[0] * 0.5, t[1] * 0.5]).collect();
            attributes["TEXCOORD_0"] = bin.attribute(self.uvs.as_flattened(), 2, uv, false).into();
            attributes["TEXCOORD_1"] = bin.attribute(uv1.as_flattened(), 2, uv, false).into();
            attributes["TANGENT"] = bin
                .attribute(self.tangents.as_flattened(), 4, dir, false)
                .into();
            attributes["COLOR_0"] = bin
                .attribute(self.colors.as_flattened(), 4, U8, false)
                .into();
            attributes["_REGION"] = bin.ints(&self.region, 1, U16, Some(34962)).into();
        }
        let wide = self.positions.len() > u16::MAX as usize;
        let indices = bin.ints(
            self.triangles.as_flattened(),
            1,
            if wide { 5125 } else { U16 },
            Some(34963),
        );
        json!({ "attributes": attributes, "indices": indices })
    }
}

/// The ball: an icosphere with spherical texture coordinates, tangents along the parallels,
/// colours by height and a region id per octant.
fn ball(subdivisions: u32) -> Part {
    let sphere = tessella_core::samples::icosphere(subdivisions);
    let mut part = Part::default();
    for p in sphere.positions() {
        let (x, y, z) = (p[0], p[1], p[2]);
        let u = 0.5 + y.atan2(x) / (2.0 * PI);
        let v = 0.5 - z.clamp(-1.0, 1.0).asin() / PI;
        let t = glam::Vec3::new(-y, x, 0.0)
            .try_normalize()
            .unwrap_or(glam::Vec3::X);
        part.positions.push(*p);
        part.normals.push(*p);
        part.uvs.push([u, v]);
        part.tangents.push([t.x, t.y, t.z, 1.0]);
        part.colors.push([0.5 + 0.5 * z, 0.3, 0.5 - 0.5 * z, 1.0]);
        part.region
            .push((x > 0.0) as u32 + 2 * (y > 0.0) as u32 + 4 * (z > 0.0) as u32);
    }
    part.triangles = sphere.triangles().to_vec();
    part
}

/// The faces of `whole` for which `keep` holds, with only their vertices.
fn split(whole: &Part, keep: impl Fn(&[u32; 3]) -> bool) -> Part {
    let mut part = Part::default();
    let mut map = std::collections::HashMap::new();
    for t in whole.triangles.iter().filter(|t| keep(t)) {
        let t = t.map(|v| *map.entry(v).or_insert_with(|| part.take(whole, v as usize)));
        part.triangles.push(t);
    }
    part
}

/// The ring: a torus within the unit cube (so 16-bit normalised positions hold it), with
/// texture coordinates by angle.
fn ring(around: u32, tube: u32) -> Part {
    let torus = tessella_core::samples::torus(0.68, 0.26, around, tube);
    let mut part = Part::default();
    for (p, n) in torus.positions().iter().zip(torus.normals()) {
        let u = 0.5 + p[1].atan2(p[0]) / (2.0 * PI);
        let v = 0.5 + n[2].atan2((n[0] * n[0] + n[1] * n[1]).sqrt()) / (2.0 * PI);
        part.positions.push(*p);
        part.normals.push(*n);
        part.uvs.push([u, v]);
        let t = glam::Vec3::new(-p[1], p[0], 0.0).normalize();
        part.tangents.push([t.x, t.y, t.z, 1.0]);
        part.colors.push([1.0; 4]);
        part.region.push(0);
    }
    part.triangles = torus.triangles().to_vec();
    part
}

/// A 64×64 checker PNG.
fn checker_png() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(64, 64, |x, y| {
        if (x / 8 + y / 8) % 2 == 0 {
            image::Rgba([235, 200, 90, 255])
        } else {
            image::Rgba([40, 90, 160, 255])
        }
    });
    let mut png = Vec::new();
    image::DynamicImage::ImageRgba8(image)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("encoding a PNG in memory");
    png
}

/// The sample scene as GLB bytes (see the module's documentation).
pub fn sample_scene(quantized: bool) -> Vec<u8> {
    sample_scene_detailed(quantized, 2, [24, 12])
}

/// The sample scene with a finer ball (an icosphere subdivided `ball` times: `20 · 4^ball`
/// triangles) and ring (`ring_quads[0] × ring_quads[1]` quads), for measurements at real sizes.
pub fn sample_scene_detailed(
    quantized: bool,
    ball_subdivisions: u32,
    ring_quads: [u32; 2],
) -> Vec<u8> {
    let mut bin = Bin::default();
    let whole = ball(ball_subdivisions);
    let upper = split(&whole, |t| {
        t.iter()
            .map(|&v| whole.positions[v as usize][2])
            .sum::<f32>()
            > 0.0
    });
    let mut lower = split(&whole, |t| {
        t.iter()
            .map(|&v| whole.positions[v as usize][2])
            .sum::<f32>()
            <= 0.0
    });
    // Degenerate triangles, as exported assets have them: a repeated corner, and two corners
    // at one position (a vertex and its copy).
    let [a, b, _] = lower.triangles[0];
    lower.triangles.push([a, a, b]);
    let twin = lower.duplicate(a as usize);
    lower.triangles.push([a, twin, b]);
    let mut ball_upper = upper.store(&mut bin, quantized, true);
    let ball_lower = lower.store(&mut bin, quantized, true);
    // A morph target on the upper half: the cap pushed out along its normals.
    let bump: Vec<f32> = upper
        .positions
        .iter()
        .flat_map(|p| {
            let s = 0.3 * p[2].max(0.0).powi(2);
            [p[0] * s, p[1] * s, p[2] * s]
        })
        .collect();
    ball_upper["targets"] = json!([{ "POSITION": bin.attribute(&bump, 3, F32, true) }]);
    // Every primitive of a mesh has the same targets: the lower half's moves nothing.
    let still = vec![0.0; lower.positions.len() * 3];
    let lower_target = json!([{ "POSITION": bin.attribute(&still, 3, F32, true) }]);
    let ring = ring(ring_quads[0], ring_quads[1]).store(&mut bin, quantized, true);
    let lines = bin.attribute(
        &[0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5, 0.0],
        3,
        F32,
        true,
    );
    let points = bin.attribute(&[1.5, 0.0, 0.0, 0.0, 1.5, 0.0], 3, F32, true);
    // Clips: the ring spins about z; the ball's cap inflates.
    let times = bin.keys(&[0.0, 1.0, 2.0], 1);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let spin = bin.keys(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h, 0.0, 0.0, 1.0, 0.0], 4);
    let inflate = bin.keys(&[0.0, 1.0, 0.0], 1);
    let png = checker_png();
    let image_view = bin.view(&png, None);
    let mut extensions_required = vec!["KHR_texture_transform"];
    if quantized {
        extensions_required.push("KHR_mesh_quantization");
    }
    let mut extensions_used = vec!["KHR_lights_punctual"];
    extensions_used.extend(&extensions_required);
    let json = json!({
        "asset": { "version": "2.0", "generator": "tessella sample scene" },
        "extensionsUsed": extensions_used,
        "extensionsRequired": extensions_required,
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "directional", "name": "Sun", "intensity": 3.0, "color": [1.0, 0.95, 0.9] }
        ] } },
        "scene": 0,
        "scenes": [{ "name": "Room", "nodes": [0] }],
        "nodes": [
            { "name": "Room", "children": [1, 2, 4, 5, 6], "extras": { "note": "kept through refinement" } },
            { "name": "Ball", "mesh": 0, "translation": [-1.2, 0.0, 0.0], "weights": [0.0] },
            { "name": "RingA", "mesh": 1, "translation": [1.3, 0.0, 0.0], "children": [3] },
            { "name": "RingB", "mesh": 1, "scale": [0.4, 0.4, 0.4], "translation": [0.0, 0.0, 0.6] },
            { "name": "Guides", "mesh": 2, "translation": [0.0, -1.2, 0.0] },
            { "name": "Camera", "camera": 0, "translation": [0.0, -1.0, 6.0] },
            { "name": "Sun", "rotation": [-0.3826834, 0.0, 0.0, 0.9238795],
              "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "cameras": [{ "name": "View", "type": "perspective",
            "perspective": { "yfov": 0.7, "znear": 0.05, "zfar": 100.0, "aspectRatio": 1.5 } }],
        "meshes": [
            { "name": "Ball", "weights": [0.0], "primitives": [
                { "attributes": ball_upper["attributes"], "indices": ball_upper["indices"],
                  "targets": ball_upper["targets"], "material": 0 },
                { "attributes": ball_lower["attributes"], "indices": ball_lower["indices"],
                  "targets": lower_target, "material": 1 }
            ], "extras": { "targetNames": ["Inflate"] } },
            { "name": "Ring", "primitives": [
                { "attributes": ring["attributes"], "indices": ring["indices"], "material": 1 }
            ] },
            { "name": "Guides", "primitives": [
                { "attributes": { "POSITION": lines }, "mode": 1 },
                { "attributes": { "POSITION": points }, "mode": 0 }
            ] }
        ],
        "materials": [
            { "name": "Painted", "pbrMetallicRoughness": { "baseColorFactor": [0.9, 0.35, 0.3, 1.0],
                "metallicFactor": 0.0, "roughnessFactor": 0.5 } },
            { "name": "Checker", "doubleSided": false,
              "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "extensions": {
                  "KHR_texture_transform": { "scale": [2.0, 2.0] } } },
                "metallicFactor": 0.0, "roughnessFactor": 0.6 },
              "normalTexture": { "index": 0, "texCoord": 1, "scale": 0.2 } }
        ],
        "textures": [{ "sampler": 0, "source": 0 }],
        "samplers": [{ "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497 }],
        "images": [{ "name": "checker", "bufferView": image_view, "mimeType": "image/png" }],
        "animations": [
            { "name": "spin", "samplers": [{ "input": times, "output": spin, "interpolation": "LINEAR" }],
              "channels": [{ "sampler": 0, "target": { "node": 2, "path": "rotation" } }] },
            { "name": "inflate", "samplers": [{ "input": times, "output": inflate, "interpolation": "LINEAR" }],
              "channels": [{ "sampler": 0, "target": { "node": 1, "path": "weights" } }] }
        ],
        "accessors": bin.accessors,
        "bufferViews": bin.views,
        "buffers": [{ "byteLength": bin.data.len() }],
    });
    crate::gltf::scene::glb(&json, &bin.data).expect("a small scene fits a GLB")
}
