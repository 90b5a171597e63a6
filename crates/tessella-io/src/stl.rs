//! STL: read with `stl_io` (ascii and binary), written binary (50-byte records, encoded in
//! parallel blocks).
//!
//! STL stores a triangle soup: every triangle repeats its corner coordinates. Reading welds
//! corners whose positions are equal as f32 values (bit-identical, with -0.0 taken as 0.0) into
//! one vertex, so the mesh is connected wherever the file's coordinates agree exactly. Facet
//! normals are ignored (they are flat; the core computes smooth vertex normals), so
//! [`RawMesh::normals`] is `None`.

use crate::{IoError, MeshView, RawMesh};
use std::collections::HashMap;
use std::io::{Cursor, Write};
use std::path::Path;

const FORMAT: &str = "STL";

/// Reads an ascii or binary STL file held in memory.
pub fn read(path: &Path, mut bytes: Vec<u8>) -> Result<RawMesh, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message,
    };
    prepare(&mut bytes);
    let mut cursor = Cursor::new(bytes);
    let triangles = stl_io::create_stl_reader(&mut cursor).map_err(|e| parse(describe(&e)))?;
    let mut raw = RawMesh::default();
    let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
    for (face, triangle) in triangles.enumerate() {
        let triangle = triangle.map_err(|e| parse(format!("facet {face}: {}", describe(&e))))?;
        let mut t = [0u32; 3];
        for (slot, vertex) in t.iter_mut().zip(triangle.vertices) {
            // -0.0 + 0.0 is +0.0: equal values get equal keys.
            let p = vertex.0.map(|c| c + 0.0);
            let next = u32::try_from(raw.positions.len())
                .map_err(|_| parse("more than 4294967295 distinct vertices".into()))?;
            *slot = *welded.entry(p.map(f32::to_bits)).or_insert_with(|| {
                raw.positions.push(p);
                next
            });
        }
        raw.triangles.push(t);
    }
    raw.check(path, FORMAT)?;
    Ok(raw)
}

fn describe(e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        "the file ends early (truncated, or the binary triangle count is wrong)".into()
    } else {
        e.to_string()
    }
}

/// Works around `stl_io` telling ascii from binary by a leading `solid `: binary files whose
/// 80-byte header starts with "solid" (some exporters do this) are recognised by their exact
/// size, and an ascii `solid` line without a name gets one.
fn prepare(bytes: &mut Vec<u8>) {
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        if bytes.len() as u64 == 84 + 50 * count && bytes.starts_with(b"solid") {
            bytes[..5].copy_from_slice(b"SOLID");
            return;
        }
    }
    let first_line_end = bytes
        .iter()
        .position(|&b| b == b'\n')
        .unwrap_or(bytes.len());
    let first = String::from_utf8_lossy(&bytes[..first_line_end]);
    if first.trim() == "solid" {
        bytes.splice(..first_line_end, b"solid unnamed".iter().copied());
    }
}

/// Writes a binary STL; facet normals are the triangles' geometric normals. Vertex normals and
/// uvs cannot be stored in STL and are dropped.
pub fn write(out: &mut dyn Write, mesh: &MeshView) -> std::io::Result<()> {
    let count = check_count(mesh.triangles.len() as u64)?;
    write_header(out, count)?;
    crate::encode::write_fixed_records(out, mesh.triangles.len(), FACET_BYTES, |f, slot| {
        put_facet(slot, mesh.triangles[f].map(|i| mesh.positions[i as usize]))
    })
}

/// The triangle count as STL stores it, or why it cannot.
pub(crate) fn check_count(triangles: u64) -> std::io::Result<u32> {
    u32::try_from(triangles).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "an STL file holds at most 2^32 - 1 triangles; write .ply instead",
        )
    })
}

/// The 80-byte header and the triangle count.
pub(crate) fn write_header(out: &mut dyn Write, count: u32) -> std::io::Result<()> {
    let mut header = [b' '; 80];
    let note = b"binary STL written by tessella";
    header[..note.len()].copy_from_slice(note);
    out.write_all(&header)?;
    out.write_all(&count.to_le_bytes())
}

/// Facet records for triangles given by their corner positions (a stream's `Corners`).
pub(crate) fn write_facets(out: &mut dyn Write, corners: &[[[f32; 3]; 3]]) -> std::io::Result<()> {
    crate::encode::write_fixed_records(out, corners.len(), FACET_BYTES, |f, slot| {
        put_facet(slot, corners[f])
    })
}

/// Bytes of one facet record: four vectors of three floats, two bytes of attribute count.
const FACET_BYTES: usize = 50;

/// One facet into its slot: the geometric normal, the three corners, a zero attribute byte
/// count.
fn put_facet(slot: &mut [u8], corners: [[f32; 3]; 3]) {
    let [a, b, c] = corners.map(glam::Vec3::from);
    let normal = (b - a).cross(c - a).normalize_or_zero();
    let (vectors, attribute) = slot.split_at_mut(48);
    let mut w = crate::encode::Words::new(vectors);
    for v in [normal, a, b, c] {
        w.floats(v.to_array());
    }
    attribute.copy_from_slice(&[0, 0]);
}
