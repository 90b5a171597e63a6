//! Reading a scene: the container, the JSON (kept whole, as a `serde_json::Value`), the
//! buffers, the extension checks and the `gltf` crate's validation of every index.

use super::super::data::{check_glb_header, load_uri};
use super::super::Buffers;
use super::{extensions, meshopt_views, Scene};
use crate::IoError;
use serde_json::Value;
use std::path::Path;

/// Reads `bytes` (a `.gltf` or `.glb` file named `path`) into a [`Scene`].
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    format: &'static str,
    external: Buffers<'_>,
) -> Result<Scene, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format,
        message,
    };
    let unsupported = |message: String| IoError::Unsupported {
        path: path.to_path_buf(),
        format,
        message,
    };
    check_glb_header(bytes).map_err(parse)?;
    let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
        let (json, bin) = glb_chunks(bytes).map_err(parse)?;
        (json, bin.map(<[u8]>::to_vec))
    } else {
        (bytes, None)
    };
    let mut json: Value =
        serde_json::from_slice(json_bytes).map_err(|e| parse(format!("bad JSON: {e}")))?;
    if !json.is_object() {
        return Err(parse("the JSON is not an object".into()));
    }
    for name in string_list(&json, "extensionsRequired") {
        if let Some(why) = extensions::refusal(&name) {
            return Err(unsupported(why));
        }
    }
    refuse_draco_without_fallback(&json).map_err(unsupported)?;
    // Structure first (no buffer is read for a file whose indices are wrong), then the data.
    let mut document = validate(&json).map_err(parse)?;
    check_channels(&json).map_err(parse)?;
    check_quantization(&json).map_err(parse)?;
    check_structure(&json).map_err(parse)?;
    let mut buffers = load_buffers(path, &json, blob, format, external)?;
    if meshopt_views::decode(&mut json, &mut buffers).map_err(parse)? {
        // The decoded views point at new buffers: the document must see them.
        document = validate(&json).map_err(parse)?;
    }
    super::data_checks::check(&document, &buffers).map_err(parse)?;
    Ok(Scene {
        json,
        document,
        buffers,
        path: path.to_path_buf(),
        format,
    })
}

/// A top-level array of strings (`extensionsUsed`, `extensionsRequired`).
pub(super) fn string_list(json: &Value, key: &str) -> Vec<String> {
    json.get(key)
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .filter_map(|v| v.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

/// Draco that is only used (not required) leaves plain accessors beside the compressed data,
/// and those are read; a primitive whose POSITION has no buffer view has nothing else.
fn refuse_draco_without_fallback(json: &Value) -> Result<(), String> {
    let accessors = json.get("accessors").and_then(Value::as_array);
    for (m, mesh) in arr(json, "meshes").iter().enumerate() {
        for (p, primitive) in arr(mesh, "primitives").iter().enumerate() {
            if primitive
                .pointer("/extensions/KHR_draco_mesh_compression")
                .is_none()
            {
                continue;
            }
            let position = primitive
                .pointer("/attributes/POSITION")
                .and_then(super::json::whole)
                .and_then(|i| accessors?.get(i as usize));
            if position.is_none_or(|a| a.get("bufferView").is_none()) {
                return Err(format!(
                    "mesh {m} primitive {p}: {}",
                    extensions::refusal("KHR_draco_mesh_compression").unwrap_or_default()
                ));
            }
        }
    }
    Ok(())
}

/// The array at `key` of an object, or an empty one.
pub(super) fn arr<'a>(json: &'a Value, key: &str) -> &'a [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// Loads every buffer: the GLB chunk, `data:` URIs, files beside the `.gltf`. A fallback
/// buffer of `EXT_meshopt_compression` (no data of its own) loads as empty.
fn load_buffers(
    path: &Path,
    json: &Value,
    mut blob: Option<Vec<u8>>,
    format: &'static str,
    external: Buffers<'_>,
) -> Result<Vec<Vec<u8>>, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format,
        message,
    };
    let mut out = Vec::new();
    for (b, buffer) in arr(json, "buffers").iter().enumerate() {
        let length = buffer
            .get("byteLength")
            .and_then(super::json::whole)
            .ok_or_else(|| parse(format!("buffer {b} has no byteLength")))?
            as usize;
        let fallback = buffer
            .pointer("/extensions/EXT_meshopt_compression/fallback")
            .and_then(Value::as_bool)
            == Some(true);
        // A buffer with nothing to load (no binary chunk, a remote URI, a meshopt fallback)
        // loads as empty: only reading a view of it is an error, and that names the view.
        let data = match buffer.get("uri").and_then(Value::as_str) {
            Some(uri) if uri.contains("://") => Vec::new(),
            Some(uri) => load_uri(path, uri, format, external)?,
            None if fallback => Vec::new(),
            None => blob.take().unwrap_or_default(),
        };
        if !data.is_empty() && data.len() < length {
            return Err(parse(format!(
                "buffer {b} holds {} bytes but declares byteLength {length}",
                data.len()
            )));
        }
        out.push(data);
    }
    Ok(out)
}

/// What glTF 2.0 requires of skins, morph targets, views and accessors beyond valid indices
/// (the rules the Khronos validator reports as errors and the `gltf` crate does not check):
/// a file that breaks them is refused, since its refined copy would break them too.
fn check_structure(json: &Value) -> Result<(), String> {
    use super::json::whole;
    let accessors = arr(json, "accessors");
    let count_of = |i: &Value| whole(i).and_then(|i| accessors.get(i as usize));
    for (i, buffer) in arr(json, "buffers").iter().enumerate() {
        if buffer
            .get("byteLength")
            .and_then(whole)
            .is_some_and(|n| n == 0)
        {
            return Err(format!(
                "buffers[{i}].byteLength is 0; a buffer holds at least one byte"
            ));
        }
    }
    let buffers = arr(json, "buffers");
    let views = arr(json, "bufferViews");
    let uses = accessor_uses(json);
    let named = |i: usize| match uses.get(&i) {
        Some(what) => format!("accessors[{i}] ({what})"),
        None => format!("accessors[{i}]"),
    };
    for (i, view) in views.iter().enumerate() {
        let (offset, length) = (
            view.get("byteOffset").and_then(whole).unwrap_or(0),
            view.get("byteLength").and_then(whole).unwrap_or(0),
        );
        let buffer = view.get("buffer").and_then(whole).unwrap_or(0);
        if let Some(buffer_length) = buffers
            .get(buffer as usize)
            .and_then(|b| b.get("byteLength"))
            .and_then(whole)
        {
            if offset.saturating_add(length) > buffer_length {
                return Err(format!(
                    "bufferView {i} reaches past the end of buffer {buffer}: it ends at byte {}, the buffer's byteLength is {buffer_length}",
                    offset.saturating_add(length)
                ));
            }
        }
        if view.get("target").and_then(whole) == Some(34963) && view.get("byteStride").is_some() {
            return Err(format!(
                "bufferViews[{i}] holds indices (target ELEMENT_ARRAY_BUFFER) and has a byteStride; index views are tightly packed"
            ));
        }
        if view
            .get("byteLength")
            .and_then(whole)
            .is_some_and(|n| n == 0)
        {
            return Err(format!(
                "bufferViews[{i}].byteLength is 0; a view holds at least one byte"
            ));
        }
        if let Some(stride) = view.get("byteStride").and_then(whole) {
            if !(4..=252).contains(&stride) || stride % 4 != 0 {
                return Err(format!(
                    "bufferViews[{i}].byteStride is {stride}; it must be a multiple of 4 from 4 to 252"
                ));
            }
        }
    }
    for (i, a) in accessors.iter().enumerate() {
        let component = a.get("componentType").and_then(whole).unwrap_or(0);
        let size = match component {
            5120 | 5121 => 1,
            5122 | 5123 => 2,
            _ => 4,
        };
        if a.get("normalized").and_then(Value::as_bool) == Some(true)
            && matches!(component, 5125 | 5126)
        {
            return Err(format!(
                "accessors[{i}] is normalized with component type {component}; only 8- and 16-bit integers are"
            ));
        }
        if a.get("byteOffset")
            .and_then(whole)
            .is_some_and(|o| o % size != 0)
        {
            return Err(format!(
                "accessors[{i}].byteOffset is not a multiple of its component size {size}"
            ));
        }
        let count = a.get("count").and_then(whole).unwrap_or(0);
        if let Some(sparse) = a.get("sparse").and_then(|s| s.get("count")).and_then(whole) {
            if sparse > count {
                return Err(format!(
                    "accessors[{i}] replaces {sparse} sparse elements of its {count}"
                ));
            }
        }
        let kind = a.get("type").and_then(Value::as_str).unwrap_or("");
        let element = element_size(kind, size);
        let view_index = a.get("bufferView").and_then(whole);
        let view = view_index.and_then(|v| views.get(v as usize));
        if let (Some(view), Some(element)) = (view, element) {
            let stride = view.get("byteStride").and_then(whole);
            if stride.is_some_and(|s| s < element) {
                return Err(format!(
                    "{} has {element}-byte elements but its view has a byteStride of {}",
                    named(i),
                    stride.unwrap_or(0)
                ));
            }
            let end = count.checked_sub(1).map_or(0, |last| {
                a.get("byteOffset").and_then(whole).unwrap_or(0)
                    + last.saturating_mul(stride.unwrap_or(element))
                    + last_element_size(kind, size).unwrap_or(element)
            });
            let length = view.get("byteLength").and_then(whole).unwrap_or(0);
            if end > length {
                return Err(format!(
                    "{} ({count} elements) reaches past the end of bufferView {}: it ends at byte {end}, the view's byteLength is {length}",
                    named(i),
                    view_index.unwrap_or(0)
                ));
            }
        }
    }
    for (i, skin) in arr(json, "skins").iter().enumerate() {
        let joints = arr(skin, "joints").len();
        if joints == 0 {
            return Err(format!("skin {i} has no joints"));
        }
        if let Some(ibm) = skin.get("inverseBindMatrices").and_then(count_of) {
            let mat4 = ibm.get("type").and_then(Value::as_str) == Some("MAT4")
                && ibm.get("componentType").and_then(whole) == Some(5126);
            if !mat4 {
                return Err(format!(
                    "skin {i} inverseBindMatrices is not an accessor of float MAT4s"
                ));
            }
            let count = ibm.get("count").and_then(whole).unwrap_or(0) as usize;
            if count < joints {
                return Err(format!(
                    "skin {i} inverseBindMatrices holds {count} matrices for {joints} joints"
                ));
            }
        }
    }
    for (m, mesh) in arr(json, "meshes").iter().enumerate() {
        let targets: Vec<usize> = arr(mesh, "primitives")
            .iter()
            .map(|p| arr(p, "targets").len())
            .collect();
        if let Some(p) = (1..targets.len()).find(|&p| targets[p] != targets[0]) {
            return Err(format!(
                "mesh {m} primitive {p} has {} morph targets but primitive 0 has {}",
                targets[p], targets[0]
            ));
        }
        let n = targets.first().copied().unwrap_or(0);
        if mesh.get("weights").is_some() && arr(mesh, "weights").len() != n {
            return Err(format!(
                "mesh {m} has {} weights for {n} morph targets",
                arr(mesh, "weights").len()
            ));
        }
    }
    Ok(())
}

/// What each accessor is first used for ("mesh 0 primitive 1 NORMAL", "animation 2 channel 0
/// output", "skin 0 inverseBindMatrices"), for messages.
fn accessor_uses(json: &Value) -> std::collections::HashMap<usize, String> {
    use super::json::whole;
    let mut uses = std::collections::HashMap::new();
    let mut note = |accessor: Option<&Value>, what: String| {
        if let Some(i) = accessor.and_then(whole) {
            uses.entry(i as usize).or_insert(what);
        }
    };
    for (m, mesh) in arr(json, "meshes").iter().enumerate() {
        for (p, primitive) in arr(mesh, "primitives").iter().enumerate() {
            note(
                primitive.get("indices"),
                format!("mesh {m} primitive {p} indices"),
            );
            for (name, a) in primitive
                .get("attributes")
                .and_then(Value::as_object)
                .into_iter()
                .flatten()
            {
                note(Some(a), format!("mesh {m} primitive {p} {name}"));
            }
            for (t, target) in arr(primitive, "targets").iter().enumerate() {
                for (name, a) in target.as_object().into_iter().flatten() {
                    note(Some(a), format!("mesh {m} primitive {p} target {t} {name}"));
                }
            }
        }
    }
    for (a, animation) in arr(json, "animations").iter().enumerate() {
        let samplers = arr(animation, "samplers");
        for (c, channel) in arr(animation, "channels").iter().enumerate() {
            let sampler = channel
                .get("sampler")
                .and_then(whole)
                .and_then(|s| samplers.get(s as usize));
            if let Some(sampler) = sampler {
                note(
                    sampler.get("input"),
                    format!("animation {a} channel {c} input"),
                );
                note(
                    sampler.get("output"),
                    format!("animation {a} channel {c} output"),
                );
            }
        }
    }
    for (k, skin) in arr(json, "skins").iter().enumerate() {
        note(
            skin.get("inverseBindMatrices"),
            format!("skin {k} inverseBindMatrices"),
        );
    }
    uses
}

/// Bytes per element of an accessor of `kind` with `size`-byte components; a matrix's columns
/// start on 4-byte boundaries (glTF 2.0 section 3.6.2.4).
fn element_size(kind: &str, size: u64) -> Option<u64> {
    let column = |rows: u64| (rows * size).next_multiple_of(4);
    Some(match kind {
        "SCALAR" => size,
        "VEC2" => 2 * size,
        "VEC3" => 3 * size,
        "VEC4" => 4 * size,
        "MAT2" => 2 * column(2),
        "MAT3" => 3 * column(3),
        "MAT4" => 4 * column(4),
        _ => return None,
    })
}

/// The bytes the last element needs: a matrix's last column without its padding.
fn last_element_size(kind: &str, size: u64) -> Option<u64> {
    let rows = match kind {
        "MAT2" => 2,
        "MAT3" => 3,
        "MAT4" => 4,
        _ => return element_size(kind, size),
    };
    Some((rows - 1) * (rows * size).next_multiple_of(4) + rows * size)
}

/// Integer positions, normals and tangents (and unnormalised integer texture coordinates) are
/// glTF only with `KHR_mesh_quantization` (glTF 2.0 section 3.7.2.1 lists the core types).
fn check_quantization(json: &Value) -> Result<(), String> {
    if string_list(json, "extensionsUsed")
        .iter()
        .any(|e| e == "KHR_mesh_quantization")
    {
        return Ok(());
    }
    let accessors = arr(json, "accessors");
    for (m, mesh) in arr(json, "meshes").iter().enumerate() {
        for (p, primitive) in arr(mesh, "primitives").iter().enumerate() {
            let Some(attributes) = primitive.get("attributes").and_then(Value::as_object) else {
                continue;
            };
            for (name, index) in attributes {
                let Some(a) = super::json::whole(index).and_then(|i| accessors.get(i as usize))
                else {
                    continue;
                };
                let float = a.get("componentType").and_then(super::json::whole) == Some(5126);
                let normalized = a.get("normalized").and_then(Value::as_bool) == Some(true);
                let core = match name.as_str() {
                    "POSITION" | "NORMAL" | "TANGENT" => float,
                    n if n.starts_with("TEXCOORD_") => float || normalized,
                    _ => true,
                };
                if !core {
                    return Err(format!(
                        "mesh {m} primitive {p}: {name} is stored as integers, which glTF allows \
                         only with KHR_mesh_quantization, and the file does not use it"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Animation channels name a sampler of their animation and an existing node (the `gltf`
/// crate's validation leaves these to its reader).
fn check_channels(json: &Value) -> Result<(), String> {
    let nodes = arr(json, "nodes").len() as u64;
    for (a, animation) in arr(json, "animations").iter().enumerate() {
        let samplers = arr(animation, "samplers").len() as u64;
        for (c, channel) in arr(animation, "channels").iter().enumerate() {
            let sampler = channel.get("sampler").and_then(super::json::whole);
            if sampler.is_none_or(|s| s >= samplers) {
                return Err(format!(
                    "animation {a} channel {c} uses sampler {sampler:?}, but the animation has only {samplers} samplers"
                ));
            }
            if let Some(node) = channel.pointer("/target/node").and_then(super::json::whole) {
                if node >= nodes {
                    return Err(format!(
                        "animation {a} channel {c} targets node {node}, but the file has only {nodes} nodes"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The `gltf` crate's validation of the whole document (every index in range, every
/// required property there), with the accepted required extensions taken off its list (it
/// knows only those compiled into it).
fn validate(json: &Value) -> Result<gltf::Document, String> {
    let mut typed = super::json::with_whole_numbers(json);
    // Optional in glTF 2.0 but required by the typed structures: a scene's `nodes`, and a
    // channel's `target.node` (a channel without one is ignored, section 3.11).
    if let Some(scenes) = typed.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            scene
                .entry("nodes")
                .or_insert_with(|| Value::Array(Vec::new()));
        }
    }
    if let Some(animations) = typed.get_mut("animations").and_then(Value::as_array_mut) {
        for animation in animations {
            if let Some(channels) = animation.get_mut("channels").and_then(Value::as_array_mut) {
                channels.retain(|c| c.pointer("/target/node").is_some());
            }
        }
    }
    let mut root: gltf::json::Root =
        serde_json::from_value(typed).map_err(|e| format!("bad glTF JSON: {e}"))?;
    root.extensions_required.clear();
    // The crate's validation indexes the accessors by each primitive's attribute indices
    // before checking them (a panic found by `fuzz/fuzz_targets/gltf.rs`): check those first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive
                .attributes
                .values()
                .map(|i| i.value())
                .find(|&i| i >= root.accessors.len())
            {
                return Err(format!(
                    "mesh {m} primitive {p} uses accessor {index}, but the file has only {} accessors",
                    root.accessors.len()
                ));
            }
        }
    }
    use gltf::json::validation::{Error, Validate};
    let mut errors = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        // glTF 2.0 allows what the crate calls missing here: an accessor without a buffer
        // view is zeros (section 3.6.2.3), a texture's source may come from an extension.
        let allowed = error == Error::Missing
            && ((path.starts_with("accessors[") && path.ends_with("].bufferView"))
                || (path.starts_with("textures[") && path.ends_with("].source")));
        if !allowed {
            errors.push(format!("{path}: {error}"));
        }
    });
    if !errors.is_empty() {
        return Err(format!("invalid glTF: {}", errors.join("; ")));
    }
    Ok(gltf::Document::from_json_without_validation(root))
}

/// The JSON and binary chunks of a GLB container (glTF 2.0 section 4.4): a 12-byte header, a
/// JSON chunk, then chunks of which the first `BIN` one is the buffer; chunks of other types
/// are skipped, as are bytes past the declared length.
fn glb_chunks(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!(
            "the GLB header is cut short ({} of 12 bytes)",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "GLB version {version}; glTF 2.0 files are version 2"
        ));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!(
            "the GLB header declares {length} bytes, but the file has {}",
            bytes.len()
        ));
    }
    let mut at = 12;
    let (mut json, mut bin) = (None, None);
    while at + 8 <= length {
        let (size, kind) = (word(at).unwrap_or(0) as usize, word(at + 4).unwrap_or(0));
        let data = at
            .checked_add(8 + size)
            .filter(|&end| end <= length)
            .map(|end| &bytes[at + 8..end])
            .ok_or_else(|| {
                let name = if at == 12 { "JSON chunk" } else { "chunk" };
                format!("{name} length exceeds the file: {size} bytes at byte {at}, past the declared end {length}")
            })?;
        // glTF 2.0 section 4.4: chunks are 4-byte aligned, JSON first, at most one BIN and
        // right after it; other chunk types are skipped.
        if size % 4 != 0 {
            return Err(format!(
                "the GLB chunk at byte {at} is {size} bytes long, not a multiple of 4"
            ));
        }
        match kind {
            0x4E4F534A if at == 12 => json = Some(data),
            0x4E4F534A => return Err(format!("a second JSON chunk at byte {at}; a GLB has one")),
            _ if at == 12 => return Err("the GLB's first chunk is not its JSON".into()),
            0x004E4942 if bin.is_some() => {
                return Err(format!(
                    "a second BIN chunk at byte {at}; a GLB has at most one"
                ))
            }
            0x004E4942 if at != 12 + 8 + json.map_or(0, <[u8]>::len) => {
                return Err(format!(
                    "the BIN chunk at byte {at} does not follow the JSON chunk"
                ))
            }
            0x004E4942 => bin = Some(data),
            _ => {}
        }
        at += 8 + size;
    }
    let json = json.ok_or("the GLB has no JSON chunk")?;
    Ok((json, bin))
}
