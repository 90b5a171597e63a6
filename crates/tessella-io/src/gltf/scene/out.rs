//! The output document and its one buffer.
//!
//! Everything the refined primitives no longer use is dropped; everything else keeps its
//! bytes and is renumbered: the accessors still referenced (skins' inverse bind matrices,
//! animation samplers, points and lines, `EXT_mesh_gpu_instancing`), their buffer views and the
//! images' buffer views are copied into one new buffer, then the refined primitives' data is
//! appended. References are rewritten where glTF 2.0 and the accepted extensions put them.

use super::load::arr;
use serde_json::{json, Value};
use std::collections::{BTreeSet, HashMap};

/// glTF's component types.
pub(super) const U8: u32 = 5121;
pub(super) const U16: u32 = 5123;
pub(super) const U32: u32 = 5125;
pub(super) const F32: u32 = 5126;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The document being written and its buffer.
pub(super) struct Out {
    pub json: Value,
    pub bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    /// Whether an attribute left as it was still needs `KHR_mesh_quantization`.
    quantized: bool,
}

/// Every place an accessor index stands outside the refined primitives: `f` gets each one.
fn accessor_refs(
    json: &mut Value,
    refined: &BTreeSet<(usize, usize)>,
    f: &mut dyn FnMut(&mut Value),
) {
    if let Some(meshes) = json.get_mut("meshes").and_then(Value::as_array_mut) {
        for (m, mesh) in meshes.iter_mut().enumerate() {
            let Some(primitives) = mesh.get_mut("primitives").and_then(Value::as_array_mut) else {
                continue;
            };
            for (p, primitive) in primitives.iter_mut().enumerate() {
                if refined.contains(&(m, p)) {
                    continue;
                }
                if let Some(attributes) = primitive
                    .get_mut("attributes")
                    .and_then(Value::as_object_mut)
                {
                    attributes.values_mut().for_each(&mut *f);
                }
                if let Some(indices) = primitive.get_mut("indices") {
                    f(indices);
                }
                if let Some(targets) = primitive.get_mut("targets").and_then(Value::as_array_mut) {
                    for target in targets.iter_mut().filter_map(Value::as_object_mut) {
                        target.values_mut().for_each(&mut *f);
                    }
                }
            }
        }
    }
    if let Some(skins) = json.get_mut("skins").and_then(Value::as_array_mut) {
        for skin in skins {
            if let Some(ibm) = skin.get_mut("inverseBindMatrices") {
                f(ibm);
            }
        }
    }
    if let Some(animations) = json.get_mut("animations").and_then(Value::as_array_mut) {
        for animation in animations {
            for sampler in animation
                .get_mut("samplers")
                .and_then(Value::as_array_mut)
                .into_iter()
                .flatten()
            {
                for key in ["input", "output"] {
                    if let Some(v) = sampler.get_mut(key) {
                        f(v);
                    }
                }
            }
        }
    }
    if let Some(nodes) = json.get_mut("nodes").and_then(Value::as_array_mut) {
        for node in nodes {
            if let Some(attributes) = node
                .pointer_mut("/extensions/EXT_mesh_gpu_instancing/attributes")
                .and_then(Value::as_object_mut)
            {
                attributes.values_mut().for_each(&mut *f);
            }
        }
    }
}

/// The buffer-view references of an accessor.
fn view_refs(accessor: &mut Value, f: &mut dyn FnMut(&mut Value)) {
    if let Some(v) = accessor.get_mut("bufferView") {
        f(v);
    }
    for part in ["/sparse/indices/bufferView", "/sparse/values/bufferView"] {
        if let Some(v) = accessor.pointer_mut(part) {
            f(v);
        }
    }
}

impl Out {
    /// The output document before the refined primitives are written: `json` with the
    /// accessors and views that outlive refinement renumbered and their bytes copied.
    /// `capacity`: the bytes the refined primitives will add, about (one allocation instead of
    /// a copy at every doubling).
    pub fn new(
        mut json: Value,
        buffers: &[Vec<u8>],
        refined: &BTreeSet<(usize, usize)>,
        capacity: usize,
    ) -> Result<Out, String> {
        let mut kept = BTreeSet::new();
        accessor_refs(&mut json, refined, &mut |v| {
            if let Some(i) = super::json::whole(v) {
                kept.insert(i as usize);
            }
        });
        let old_accessors = arr(&json, "accessors").to_vec();
        let quantized = quantized_left(&json, refined, &old_accessors);
        let accessor_map: HashMap<usize, usize> = kept
            .iter()
            .enumerate()
            .map(|(new, &old)| (old, new))
            .collect();
        accessor_refs(&mut json, refined, &mut |v| {
            if let Some(new) = super::json::whole(v).and_then(|i| accessor_map.get(&(i as usize))) {
                *v = (*new).into();
            }
        });
        let mut accessors: Vec<Value> = kept
            .iter()
            .map(|&i| {
                old_accessors
                    .get(i)
                    .cloned()
                    .ok_or(format!("accessor {i} is missing"))
            })
            .collect::<Result<_, _>>()?;
        let mut views_used = BTreeSet::new();
        for accessor in &mut accessors {
            view_refs(accessor, &mut |v| {
                if let Some(i) = super::json::whole(v) {
                    views_used.insert(i as usize);
                }
            });
        }
        for image in arr(&json, "images") {
            if let Some(i) = image.get("bufferView").and_then(super::json::whole) {
                views_used.insert(i as usize);
            }
        }
        let old_views = arr(&json, "bufferViews").to_vec();
        let mut out = Out {
            json,
            bin: Vec::with_capacity(capacity),
            views: Vec::new(),
            accessors: Vec::new(),
            quantized,
        };
        let mut view_map = HashMap::new();
        for &v in &views_used {
            let view = old_views
                .get(v)
                .ok_or(format!("bufferView {v} is missing"))?;
            let buffer = view.get("buffer").and_then(super::json::whole).unwrap_or(0) as usize;
            let offset = view
                .get("byteOffset")
                .and_then(super::json::whole)
                .unwrap_or(0) as usize;
            let length = view
                .get("byteLength")
                .and_then(super::json::whole)
                .unwrap_or(0) as usize;
            let bytes = buffers
                .get(buffer)
                .and_then(|b| b.get(offset..offset.checked_add(length)?))
                .ok_or(format!(
                    "bufferView {v} reaches past the end of buffer {buffer}"
                ))?;
            let mut view = view.clone();
            out.align();
            view["buffer"] = 0.into();
            view["byteOffset"] = out.bin.len().into();
            out.bin.extend_from_slice(bytes);
            view_map.insert(v, out.views.len());
            out.views.push(view);
        }
        let remap_view = &mut |v: &mut Value| {
            if let Some(new) = super::json::whole(v).and_then(|i| view_map.get(&(i as usize))) {
                *v = (*new).into();
            }
        };
        for accessor in &mut accessors {
            view_refs(accessor, remap_view);
        }
        if let Some(images) = out.json.get_mut("images").and_then(Value::as_array_mut) {
            for image in images {
                if let Some(v) = image.get_mut("bufferView") {
                    remap_view(v);
                }
            }
        }
        out.accessors = accessors;
        Ok(out)
    }

    fn align(&mut self) {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
    }

    fn view(&mut self, bytes: &[u8], target: u32) -> usize {
        self.align();
        let view = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
            "target": target,
        });
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// A float accessor of `width` components per element; `bounds`: with `min`/`max` (required
    /// for POSITION).
    pub fn floats(&mut self, data: &[f32], width: usize, bounds: bool) -> usize {
        let view = self.view(bytemuck::cast_slice(data), ARRAY_BUFFER);
        let mut accessor = json!({
            "bufferView": view,
            "componentType": F32,
            "count": data.len() / width,
            "type": type_name(width),
        });
        if bounds {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for e in data.chunks_exact(width) {
                for c in 0..width {
                    lo[c] = lo[c].min(e[c]);
                    hi[c] = hi[c].max(e[c]);
                }
            }
            accessor["min"] = json!(lo);
            accessor["max"] = json!(hi);
        }
        self.push(accessor)
    }

    /// An integer vertex attribute (`U8`, `U16` or `U32` components, not normalised), each
    /// element padded to a multiple of 4 bytes as vertex attributes must be (glTF 2.0 section
    /// 3.6.2.4).
    pub fn ints(&mut self, data: &[u32], width: usize, component: u32) -> usize {
        let size = match component {
            U8 => 1,
            U16 => 2,
            _ => 4,
        };
        let element = size * width;
        let stride = element.next_multiple_of(4);
        let mut bytes = Vec::with_capacity(data.len() / width * stride);
        for e in data.chunks_exact(width) {
            for &x in e {
                bytes.extend_from_slice(&x.to_le_bytes()[..size]);
            }
            bytes.resize(bytes.len() + stride - element, 0);
        }
        let view = self.view(&bytes, ARRAY_BUFFER);
        if stride != element {
            self.views[view]["byteStride"] = stride.into();
        }
        self.push(json!({
            "bufferView": view,
            "componentType": component,
            "count": data.len() / width,
            "type": type_name(width),
        }))
    }

    /// Triangle indices, 16-bit when every index fits.
    pub fn indices(&mut self, triangles: &[[u32; 3]], vertices: usize) -> usize {
        let flat = triangles.as_flattened();
        let component = if vertices <= u16::MAX as usize {
            let narrow: Vec<u16> = flat.iter().map(|&i| i as u16).collect();
            self.view(bytemuck::cast_slice(&narrow), ELEMENT_ARRAY_BUFFER);
            U16
        } else {
            self.view(bytemuck::cast_slice(flat), ELEMENT_ARRAY_BUFFER);
            U32
        };
        let view = self.views.len() - 1;
        self.push(json!({
            "bufferView": view,
            "componentType": component,
            "count": flat.len(),
            "type": "SCALAR",
        }))
    }

    fn push(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// The finished document: one buffer (`uri` for a `.gltf`'s `.bin`, none for a GLB), the
    /// views and accessors, and the extension lists without what was decoded.
    pub fn finish(mut self, uri: Option<&str>) -> (Value, Vec<u8>) {
        self.align();
        let mut buffer = json!({ "byteLength": self.bin.len() });
        if let Some(uri) = uri {
            buffer["uri"] = uri.into();
        }
        let quantized = self.quantized;
        let object = self
            .json
            .as_object_mut()
            .expect("a glTF document is an object");
        object.insert("buffers".into(), json!([buffer]));
        object.insert("bufferViews".into(), Value::Array(self.views));
        object.insert("accessors".into(), Value::Array(self.accessors));
        if self.bin.is_empty() {
            object.remove("buffers");
        }
        for list in ["extensionsUsed", "extensionsRequired"] {
            if let Some(names) = object.get_mut(list).and_then(Value::as_array_mut) {
                names.retain(|n| {
                    let n = n.as_str().unwrap_or("");
                    n != "EXT_meshopt_compression"
                        && n != "KHR_draco_mesh_compression"
                        && (n != "KHR_mesh_quantization" || quantized)
                });
                if names.is_empty() {
                    object.remove(list);
                }
            }
        }
        (self.json, self.bin)
    }
}

/// Whether a primitive left unrefined, or an instanced node, keeps an integer attribute where
/// glTF 2.0 alone wants floats (what `KHR_mesh_quantization` allows).
fn quantized_left(json: &Value, refined: &BTreeSet<(usize, usize)>, accessors: &[Value]) -> bool {
    let integer = |i: &Value| {
        super::json::whole(i)
            .and_then(|i| accessors.get(i as usize))
            .and_then(|a| a.get("componentType"))
            .and_then(super::json::whole)
            != Some(F32 as u64)
    };
    let float_semantic = |name: &str| {
        matches!(
            name,
            "POSITION" | "NORMAL" | "TANGENT" | "TRANSLATION" | "ROTATION" | "SCALE"
        ) || name.starts_with("TEXCOORD_")
    };
    let unrefined = arr(json, "meshes").iter().enumerate().any(|(m, mesh)| {
        arr(mesh, "primitives")
            .iter()
            .enumerate()
            .any(|(p, primitive)| {
                !refined.contains(&(m, p))
                    && primitive
                        .get("attributes")
                        .and_then(Value::as_object)
                        .is_some_and(|a| a.iter().any(|(k, v)| float_semantic(k) && integer(v)))
            })
    });
    let instanced = arr(json, "nodes").iter().any(|node| {
        node.pointer("/extensions/EXT_mesh_gpu_instancing/attributes")
            .and_then(Value::as_object)
            .is_some_and(|a| a.iter().any(|(k, v)| float_semantic(k) && integer(v)))
    });
    unrefined || instanced
}

fn type_name(width: usize) -> &'static str {
    match width {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        _ => "VEC4",
    }
}
