//! The checks the fuzz targets (`fuzz/fuzz_targets/*.rs`) run on each input, kept here so that
//! ordinary tests replay the saved regression inputs and seed corpus through the very same code
//! (`tests/fuzz_regressions.rs`). Behind the `fuzzing` feature (off by default): the fuzz crate
//! and this crate's tests turn it on; it is not part of the library's API.
//!
//! Each `check_*` function takes arbitrary bytes and panics only when a property is broken: a
//! reader may refuse the bytes with an error, but what it accepts must fit together (attribute
//! counts, indices in range) and validation must not panic; [`check_refine`] builds a small mesh
//! and options from the bytes and asks for an error or finite output with valid indices.

use crate::{obj, ply, stl, Format, IoError, RawMesh};
use std::io::Cursor;
use std::path::Path;
use tessella_core::{Mesh, Named, NormalMode, RefineOptions, Scheme};

/// The folder fuzzed glTF files pretend to live in: it does not exist, so external buffers are
/// never found.
const FUZZ_FOLDER: &str = "/nonexistent-tessella-fuzz";

/// Reads `bytes` as a file of `format`, as [`crate::read_raw`] reads a file.
pub fn read_bytes(format: Format, bytes: &[u8]) -> Result<RawMesh, IoError> {
    let name = match format {
        Format::Obj => "input.obj",
        Format::Ply | Format::PlyAscii => "input.ply",
        Format::Gltf => "input.gltf",
        Format::Glb => "input.glb",
        Format::Stl => "input.stl",
    };
    let path = Path::new(FUZZ_FOLDER).join(name);
    match format {
        Format::Obj => obj::read(&path, Cursor::new(bytes)),
        Format::Ply | Format::PlyAscii => ply::read(&path, Cursor::new(bytes)),
        Format::Gltf | Format::Glb => crate::gltf::read(&path, bytes, format.name()),
        Format::Stl => stl::read(&path, bytes.to_vec()),
    }
}

/// A PLY file from fuzz input: a fixed `ply` line and `format` line (`ascii`, or for `binary`
/// little-endian when the first byte is even and big-endian when odd), then the input (the rest
/// of the header and the body).
pub fn ply_input(binary: bool, data: &[u8]) -> Vec<u8> {
    let (format, rest) = match (binary, data.split_first()) {
        (false, _) => ("ascii", data),
        (true, Some((b, rest))) if b % 2 == 1 => ("binary_big_endian", rest),
        (true, Some((_, rest))) => ("binary_little_endian", rest),
        (true, None) => ("binary_little_endian", data),
    };
    let mut out = format!("ply\nformat {format} 1.0\n").into_bytes();
    out.extend_from_slice(rest);
    out
}

/// Reads `bytes` as `format`; panics if the reader panics or accepts something inconsistent.
/// Returns whether the bytes gave a valid [`Mesh`].
pub fn check_reader(format: Format, bytes: &[u8]) -> bool {
    let raw = match read_bytes(format, bytes) {
        Ok(raw) => raw,
        Err(e) => {
            // Every error names the file (or the glTF's buffer file beside it).
            assert!(e.to_string().contains(FUZZ_FOLDER), "{e}");
            return false;
        }
    };
    let n = raw.positions.len();
    assert!(
        !raw.triangles.is_empty(),
        "accepted a file without triangles"
    );
    assert!(raw.triangles.iter().flatten().all(|&i| (i as usize) < n));
    assert!(raw.normals.as_ref().is_none_or(|v| v.len() == n));
    assert!(raw.uvs.as_ref().is_none_or(|v| v.len() == n));
    assert!(raw.vertex_scalars.values().all(|v| v.len() == n));
    assert!(raw
        .edges
        .iter()
        .all(|e| e.vertices.iter().all(|&i| (i as usize) < n)));
    let RawMesh {
        positions,
        normals,
        uvs,
        triangles,
        vertex_scalars,
        edges,
    } = raw;
    let Ok(mesh) = Mesh::new(positions, normals, uvs, triangles) else {
        return false;
    };
    assert!(mesh.positions().iter().flatten().all(|c| c.is_finite()));
    assert!(mesh.normals().iter().flatten().all(|c| c.is_finite()));
    // PLY tag columns go through the tag reader too; an error is fine, a panic is not.
    let _ = crate::tags::from_ply(&mesh, &vertex_scalars, &edges);
    true
}

/// Reads `bytes` as sidecar tag JSON for a small mesh; panics only if the reader panics.
pub fn check_tags_json(bytes: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return false;
    };
    let mesh = tessella_core::samples::tetrahedron();
    match crate::tags::from_json(&mesh, text) {
        Ok(tags) => {
            assert!(tags.vertex_count() <= mesh.vertex_count());
            true
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            false
        }
    }
}

/// Takes bytes from the front of a slice, zeros once it runs out.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// Mostly small whole numbers (so meshes have shape), sometimes any f32 bit pattern (NaN,
    /// infinities, huge and tiny values).
    fn f32(&mut self) -> f32 {
        match self.u8() {
            0..=15 => f32::from_bits(self.u32()),
            b => (b as f32 - 136.0) / 16.0,
        }
    }
}

/// A small mesh and refinement options built from `bytes`; refining must give an error or
/// finite output whose indices are in range and whose counts fit the layout. Returns whether
/// refining succeeded.
pub fn check_refine(bytes: &[u8]) -> bool {
    let mut b = Bytes(bytes);
    let vertex_count = 3 + usize::from(b.u8() % 8);
    let triangle_count = 1 + usize::from(b.u8() % 10);
    let has_normals = b.u8() % 2 == 0;
    let has_uvs = b.u8() % 4 == 0;
    let positions: Vec<[f32; 3]> = (0..vertex_count)
        .map(|_| [b.f32(), b.f32(), b.f32()])
        .collect();
    let normals = has_normals.then(|| {
        (0..vertex_count)
            .map(|_| [b.f32(), b.f32(), b.f32()])
            .collect::<Vec<_>>()
    });
    let uvs = has_uvs.then(|| {
        (0..vertex_count)
            .map(|_| [b.f32(), b.f32()])
            .collect::<Vec<_>>()
    });
    // Indices mostly in range; byte 255 gives an out-of-range one.
    let index = |b: &mut Bytes| match b.u8() {
        255 => vertex_count as u32,
        x => u32::from(x) % vertex_count as u32,
    };
    let triangles: Vec<[u32; 3]> = (0..triangle_count)
        .map(|_| [index(&mut b), index(&mut b), index(&mut b)])
        .collect();
    let scheme = Scheme::ALL[usize::from(b.u8()) % Scheme::ALL.len()];
    let scheme = match b.u8() % 4 {
        0 => scheme.with_alpha(b.f32()),
        _ => scheme,
    };
    let mut options = RefineOptions::new(scheme, u32::from(b.u8() % 9));
    options.normals = match b.u8() % 4 {
        0 => None,
        k => Some(NormalMode::ALL[usize::from(k - 1) % NormalMode::ALL.len()]),
    };
    options.weld = b.u8() % 2 == 0;
    if b.u8() % 8 == 0 {
        options.max_output_bytes = u64::from(b.u32() % 4096);
    }
    let Ok(mesh) = Mesh::new(positions, normals, uvs, triangles) else {
        return false;
    };
    if b.u8() % 4 == 0 {
        let json = format!(
            r#"{{"vertices": [{{"index": {}, "tension": {}, "sharpness": {}}}]}}"#,
            b.u8() % 4,
            b.u8() as f32 / 64.0 - 1.0,
            b.u8() as f32 / 64.0 - 1.0
        );
        if let Ok(tags) = crate::tags::from_json(&mesh, &json) {
            options = options.with_tags(tags);
        }
    }
    let Ok(out) = tessella_core::refine(&mesh, &options) else {
        return false;
    };
    let n = out.positions.len();
    let level = options
        .uniform_grid_level()
        .expect("the fuzzer refines whole grid levels") as usize;
    assert_eq!(
        out.triangles.len(),
        mesh.face_count() * level * level,
        "triangle count"
    );
    assert_eq!(out.normals.len(), n);
    assert!(out.uvs.as_ref().is_none_or(|u| u.len() == n));
    assert!(out.triangles.iter().flatten().all(|&i| (i as usize) < n));
    assert!(
        out.positions.iter().flatten().all(|c| c.is_finite()),
        "non-finite refined position"
    );
    assert!(
        out.normals.iter().flatten().all(|c| c.is_finite()),
        "non-finite refined normal"
    );
    if !options.weld {
        let per_face = (level + 1) * (level + 2) / 2;
        assert_eq!(n, mesh.face_count() * per_face, "soup vertex count");
    }
    true
}
