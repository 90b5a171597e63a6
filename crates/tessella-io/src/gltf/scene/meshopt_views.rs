//! `EXT_meshopt_compression`: buffer views whose bytes are meshoptimizer streams, decoded on
//! reading with meshoptimizer's own decoder (the `meshopt` crate, native builds only: it
//! compiles meshoptimizer's C++, which the WebAssembly build has no compiler for).
//!
//! A decoded view points at a buffer of its own, appended to the loaded buffers, and loses the
//! extension: everything after reading sees plain buffer views.

use serde_json::Value;

/// Decodes every compressed view of `json` into a new buffer; returns whether any was.
pub(super) fn decode(json: &mut Value, buffers: &mut Vec<Vec<u8>>) -> Result<bool, String> {
    let Some(views) = json.get_mut("bufferViews").and_then(Value::as_array_mut) else {
        return Ok(false);
    };
    let mut decoded = Vec::new();
    for (v, view) in views.iter_mut().enumerate() {
        let Some(ext) = view
            .get("extensions")
            .and_then(|e| e.get("EXT_meshopt_compression"))
            .cloned()
        else {
            continue;
        };
        let bytes = decode_view(&ext, buffers).map_err(|m| format!("bufferView {v}: {m}"))?;
        let object = view.as_object_mut().ok_or("bufferView is not an object")?;
        object.insert("buffer".into(), buffers.len().into());
        object.insert("byteOffset".into(), 0.into());
        object.insert("byteLength".into(), bytes.len().into());
        if let Some(exts) = object.get_mut("extensions").and_then(Value::as_object_mut) {
            exts.remove("EXT_meshopt_compression");
            if exts.is_empty() {
                object.remove("extensions");
            }
        }
        decoded.push(serde_json::json!({ "byteLength": bytes.len() }));
        buffers.push(bytes);
    }
    // Each decoded view's buffer joins the document's list, so indices stay valid.
    let any = !decoded.is_empty();
    if let Some(list) = json.get_mut("buffers").and_then(Value::as_array_mut) {
        list.extend(decoded);
    }
    Ok(any)
}

#[cfg(not(target_arch = "wasm32"))]
fn field(ext: &Value, name: &str) -> Result<usize, String> {
    ext.get(name)
        .and_then(super::json::whole)
        .map(|x| x as usize)
        .ok_or_else(|| format!("EXT_meshopt_compression has no whole number {name}"))
}

#[cfg(not(target_arch = "wasm32"))]
fn decode_view(ext: &Value, buffers: &[Vec<u8>]) -> Result<Vec<u8>, String> {
    let buffer = field(ext, "buffer")?;
    let offset = ext
        .get("byteOffset")
        .and_then(super::json::whole)
        .unwrap_or(0) as usize;
    let length = field(ext, "byteLength")?;
    let stride = field(ext, "byteStride")?;
    let count = field(ext, "count")?;
    let mode = ext.get("mode").and_then(Value::as_str).unwrap_or("");
    let filter = ext.get("filter").and_then(Value::as_str).unwrap_or("NONE");
    let source = buffers.get(buffer).ok_or_else(|| {
        format!("EXT_meshopt_compression names buffer {buffer}, which is missing")
    })?;
    let source = offset
        .checked_add(length)
        .and_then(|end| source.get(offset..end))
        .ok_or_else(|| format!("EXT_meshopt_compression's bytes reach past buffer {buffer}"))?;
    if stride == 0 || stride > 256 || count > (1 << 28) {
        return Err(format!(
            "EXT_meshopt_compression byteStride {stride}, count {count}"
        ));
    }
    // u32 storage: the filters read 16- and 32-bit words in place.
    let mut words = vec![0u32; (count * stride).div_ceil(4)];
    let out = words.as_mut_ptr().cast::<std::ffi::c_void>();
    use meshopt::ffi;
    // SAFETY: `words` holds at least `count * stride` bytes, which is all the decoders and
    // filters write; the source slice is read within its length.
    let code = unsafe {
        match mode {
            "ATTRIBUTES" => {
                ffi::meshopt_decodeVertexBuffer(out, count, stride, source.as_ptr(), source.len())
            }
            "TRIANGLES" => {
                ffi::meshopt_decodeIndexBuffer(out, count, stride, source.as_ptr(), source.len())
            }
            "INDICES" => {
                ffi::meshopt_decodeIndexSequence(out, count, stride, source.as_ptr(), source.len())
            }
            other => return Err(format!("EXT_meshopt_compression mode {other:?}")),
        }
    };
    if code != 0 {
        return Err(format!(
            "the meshopt {mode} stream does not decode (code {code})"
        ));
    }
    let filter_ok = match (filter, stride) {
        ("NONE", _) => true,
        ("OCTAHEDRAL", 4 | 8) | ("QUATERNION", 8) => true,
        ("EXPONENTIAL", s) => s % 4 == 0,
        _ => false,
    };
    if !filter_ok || (filter != "NONE" && mode != "ATTRIBUTES") {
        return Err(format!(
            "EXT_meshopt_compression filter {filter:?} with byteStride {stride} in mode {mode}"
        ));
    }
    // SAFETY: as above; each filter walks `count` elements of `stride` bytes.
    unsafe {
        match filter {
            "OCTAHEDRAL" => ffi::meshopt_decodeFilterOct(out, count, stride),
            "QUATERNION" => ffi::meshopt_decodeFilterQuat(out, count, stride),
            "EXPONENTIAL" => ffi::meshopt_decodeFilterExp(out, count, stride),
            _ => {}
        }
    }
    let mut bytes: Vec<u8> = bytemuck::cast_slice(&words).to_vec();
    bytes.truncate(count * stride);
    Ok(bytes)
}

#[cfg(target_arch = "wasm32")]
fn decode_view(_ext: &Value, _buffers: &[Vec<u8>]) -> Result<Vec<u8>, String> {
    Err(super::extensions::meshopt_unavailable())
}
