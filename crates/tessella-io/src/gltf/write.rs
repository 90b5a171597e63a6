//! Writes one mesh, one node, one scene; the binary data is streamed, never copied whole.

use super::flip_v;
use crate::ply::VertexScalars;
use crate::MeshView;
use base64::engine::general_purpose::STANDARD;
use serde_json::{json, Value};
use std::io::Write;

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
/// Stands in for the base64 data in the JSON text until the data is streamed in its place.
const PLACEHOLDER: &str = "@TESSELLA_BUFFER@";

/// The attribute name of an extra vertex scalar: application-specific glTF attributes start
/// with an underscore (glTF 2.0 spec, 3.7.2.1), so `T` is written as `_T`.
pub(crate) fn attribute_name(name: &str) -> String {
    format!("_{name}")
}

/// The JSON document for `mesh` and the byte length of its single buffer.
fn document(mesh: &MeshView, scalars: &VertexScalars, uri: Option<String>) -> (Value, u64) {
    let shape = Shape {
        vertices: mesh.positions.len() as u64,
        triangles: mesh.triangles.len() as u64,
        normals: mesh.normals.is_some(),
        uvs: mesh.uvs.is_some(),
        bounds: tessella_core::mesh::bounds(mesh.positions),
        scalars: scalars
            .iter()
            .map(|(name, values)| {
                let range = fold_range((f32::INFINITY, f32::NEG_INFINITY), values);
                (name.to_string(), range)
            })
            .collect(),
    };
    document_for(&shape, uri)
}

/// `(lo, hi)` widened by `values`, one value after the other (a streamed writer folds its
/// runs in file order and gets the same bits as one fold over the whole array).
pub(crate) fn fold_range((lo, hi): (f32, f32), values: &[f32]) -> (f32, f32) {
    values
        .iter()
        .fold((lo, hi), |(lo, hi), &x| (lo.min(x), hi.max(x)))
}

/// What the JSON document says about a mesh: its sizes, attributes and position bounds.
pub(crate) struct Shape {
    pub vertices: u64,
    pub triangles: u64,
    pub normals: bool,
    pub uvs: bool,
    pub bounds: ([f32; 3], [f32; 3]),
    /// Extra per-vertex scalars: each name and its values' `(min, max)`.
    pub scalars: Vec<(String, (f32, f32))>,
}

/// The JSON document for a mesh of `shape` and the byte length of its single buffer.
fn document_for(shape: &Shape, uri: Option<String>) -> (Value, u64) {
    let n = shape.vertices;
    let (mut views, mut accessors) = (Vec::new(), Vec::new());
    let mut offset = 0u64;
    let mut push = |bytes: u64, target: u32, accessor: Value| {
        views.push(
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes, "target": target}),
        );
        let mut accessor = accessor;
        accessor["bufferView"] = json!(views.len() - 1);
        accessors.push(accessor);
        offset += bytes;
        accessors.len() - 1
    };
    let (lo, hi) = shape.bounds;
    let mut attributes = serde_json::Map::new();
    let position = push(
        12 * n,
        ARRAY_BUFFER,
        json!({"componentType": FLOAT, "count": n, "type": "VEC3", "min": lo, "max": hi}),
    );
    attributes.insert("POSITION".into(), json!(position));
    if shape.normals {
        let normal = push(
            12 * n,
            ARRAY_BUFFER,
            json!({"componentType": FLOAT, "count": n, "type": "VEC3"}),
        );
        attributes.insert("NORMAL".into(), json!(normal));
    }
    if shape.uvs {
        let uv = push(
            8 * n,
            ARRAY_BUFFER,
            json!({"componentType": FLOAT, "count": n, "type": "VEC2"}),
        );
        attributes.insert("TEXCOORD_0".into(), json!(uv));
    }
    for (name, (lo, hi)) in &shape.scalars {
        let (lo, hi) = (*lo, *hi);
        let mut accessor = json!({"componentType": FLOAT, "count": n, "type": "SCALAR"});
        if lo <= hi {
            accessor["min"] = json!([lo]);
            accessor["max"] = json!([hi]);
        }
        let index = push(4 * n, ARRAY_BUFFER, accessor);
        attributes.insert(attribute_name(name), json!(index));
    }
    let f = shape.triangles;
    let indices = push(
        12 * f,
        ELEMENT_ARRAY_BUFFER,
        json!({"componentType": UNSIGNED_INT, "count": 3 * f, "type": "SCALAR"}),
    );
    let mut buffer = json!({"byteLength": offset});
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    let doc = json!({
        "asset": {"version": "2.0", "generator": "tessella"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": indices, "mode": 4}]}],
        "buffers": [buffer],
        "bufferViews": views,
        "accessors": accessors,
    });
    (doc, offset)
}

/// Streams the buffer: positions, normals, uvs (v flipped), extra scalars, indices,
/// little-endian.
fn write_buffer(
    out: &mut dyn Write,
    mesh: &MeshView,
    scalars: &VertexScalars,
) -> std::io::Result<()> {
    use crate::encode::write_le;
    write_le(out, mesh.positions)?;
    if let Some(normals) = mesh.normals {
        write_le(out, normals)?;
    }
    if let Some(uvs) = mesh.uvs {
        crate::encode::write_records(out, uvs.len(), 8, |i, out| {
            flip_v(uvs[i])
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes()))
        })?;
    }
    for (_, values) in scalars {
        write_le(out, values)?;
    }
    write_le(out, mesh.triangles)
}

/// Writes `.glb` (`binary`) or `.gltf` with the buffer embedded as a base64 `data:` URI.
/// Errors with `InvalidInput` when a `.glb` would exceed the format's 4 GiB limit.
pub fn write(out: &mut dyn Write, mesh: &MeshView, binary: bool) -> std::io::Result<()> {
    write_with_scalars(out, mesh, &[], binary)
}

/// [`write()`] with extra per-vertex scalars as float `SCALAR` attributes named `_NAME` (one
/// value per vertex; the caller checks the lengths, as [`crate::write_mesh_with_scalars`]
/// does).
pub fn write_with_scalars(
    out: &mut dyn Write,
    mesh: &MeshView,
    scalars: &VertexScalars,
    binary: bool,
) -> std::io::Result<()> {
    if binary {
        let (doc, bin_len) = document(mesh, scalars, None);
        write_glb_header(out, &doc, bin_len)?;
        write_buffer(out, mesh, scalars)?;
        write_glb_padding(out, bin_len)
    } else {
        let (doc, _) = document(mesh, scalars, Some(embedded_uri()));
        write_gltf_text(out, &doc, |encoder| write_buffer(encoder, mesh, scalars))
    }
}

/// The buffer's URI in a `.gltf`'s JSON: base64 data, written in later by [`write_gltf_text`].
pub(crate) fn embedded_uri() -> String {
    format!("data:application/octet-stream;base64,{PLACEHOLDER}")
}

/// The `.gltf` document of a mesh of `shape`, its buffer embedded.
pub(crate) fn gltf_document(shape: &Shape) -> Value {
    document_for(shape, Some(embedded_uri())).0
}

/// Writes `doc` as JSON text with the buffer's bytes, from `buffer`, base64-encoded into the
/// URI on the fly (never held whole).
pub(crate) fn write_gltf_text(
    out: &mut dyn Write,
    doc: &Value,
    buffer: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(doc).map_err(std::io::Error::other)?;
    let (head, tail) = text
        .split_once(PLACEHOLDER)
        .ok_or_else(|| std::io::Error::other("glTF writer lost its buffer placeholder"))?;
    out.write_all(head.as_bytes())?;
    {
        let mut encoder = base64::write::EncoderWriter::new(&mut *out, &STANDARD);
        buffer(&mut encoder)?;
        encoder.finish()?;
    }
    out.write_all(tail.as_bytes())?;
    out.write_all(b"\n")
}

/// The GLB document of a mesh of `shape`, and its buffer's length.
pub(crate) fn glb_document(shape: &Shape) -> (Value, u64) {
    document_for(shape, None)
}

/// The file header, the JSON chunk and the BIN chunk's header, for a buffer of `bin_len`
/// bytes (the chunk lengths known before the data).
pub(crate) fn write_glb_header(
    out: &mut dyn Write,
    doc: &Value,
    bin_len: u64,
) -> std::io::Result<()> {
    {
        let mut json = serde_json::to_vec(&doc).map_err(std::io::Error::other)?;
        json.resize(json.len().next_multiple_of(4), b' ');
        let bin_padded = bin_len.next_multiple_of(4);
        let total = 12 + 8 + json.len() as u64 + 8 + bin_padded;
        let total = u32::try_from(total).map_err(|_| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("a GLB file holds at most 4 GiB, this mesh needs {total} bytes; write .gltf or .ply instead"),
            )
        })?;
        out.write_all(b"glTF")?;
        out.write_all(&2u32.to_le_bytes())?;
        out.write_all(&total.to_le_bytes())?;
        out.write_all(&(json.len() as u32).to_le_bytes())?;
        out.write_all(b"JSON")?;
        out.write_all(&json)?;
        out.write_all(&(bin_padded as u32).to_le_bytes())?;
        out.write_all(b"BIN\0")
    }
}

/// The zero bytes that pad the BIN chunk to a multiple of 4.
pub(crate) fn write_glb_padding(out: &mut dyn Write, bin_len: u64) -> std::io::Result<()> {
    out.write_all(&vec![0; (bin_len.next_multiple_of(4) - bin_len) as usize])
}
