//! `readMesh` and `writeMesh`: mesh files as bytes (OBJ, PLY, glTF/GLB, STL), by tessella-io's
//! in-memory readers and writers; the file system is never touched.

use crate::{errors, refine::Arrays};
use std::path::Path;
use tessella_io::{Format, MeshView};
use wasm_bindgen::prelude::*;

/// The file name a format (`"obj"`) or a file name (`"bunny.obj"`) stands for: the extension
/// picks the reader, the name appears in messages.
pub fn file_name(format: &str) -> String {
    match format.contains('.') {
        true => format.to_string(),
        false => format!("mesh.{format}"),
    }
}

/// Reads a mesh file's bytes and validates the mesh (the core's checks). `buffer_names`,
/// `buffer_lengths` and `buffer_data` (all the buffers one after the other) are a `.gltf`
/// file's external buffers by relative URI.
pub fn read(bytes: &[u8], format: &str, buffers: &GltfBuffers) -> Result<Arrays, String> {
    let mesh = tessella_io::read_mesh_bytes(&file_name(format), bytes, &buffers.given()?)
        .map_err(|e| errors::message(&e))?;
    Ok(Arrays::from_mesh(&mesh))
}

/// A `.gltf` file's external buffers by relative URI, as JS hands them over: the names, the
/// lengths, and all the bytes one after the other (`readMesh` and `readAnimated` take them).
#[wasm_bindgen]
#[derive(Debug, Default)]
pub struct GltfBuffers {
    names: Vec<String>,
    lengths: Vec<u32>,
    data: Vec<u8>,
}

#[wasm_bindgen]
impl GltfBuffers {
    #[wasm_bindgen(constructor)]
    pub fn new(names: Vec<String>, lengths: Vec<u32>, data: Vec<u8>) -> GltfBuffers {
        GltfBuffers {
            names,
            lengths,
            data,
        }
    }
}

impl GltfBuffers {
    /// The buffers as tessella-io's in-memory readers take them: (relative URI, bytes) pairs.
    pub fn given(&self) -> Result<Vec<(&str, &[u8])>, String> {
        if self.names.len() != self.lengths.len()
            || self.lengths.iter().map(|&n| n as usize).sum::<usize>() != self.data.len()
        {
            return Err(
                "the glTF buffers given do not fit together (names, lengths, bytes)".into(),
            );
        }
        let mut given = Vec::with_capacity(self.names.len());
        let mut at = 0;
        for (name, &len) in self.names.iter().zip(&self.lengths) {
            given.push((name.as_str(), &self.data[at..at + len as usize]));
            at += len as usize;
        }
        Ok(given)
    }
}

/// Encodes flat arrays as a file of `format`: `obj`, `ply` (binary), `ply-ascii`, `gltf`,
/// `glb` or `stl`.
pub fn write(
    format: &str,
    positions: &[f32],
    indices: &[u32],
    normals: Option<&[f32]>,
    uvs: Option<&[f32]>,
) -> Result<Vec<u8>, String> {
    let format = match format.to_ascii_lowercase().as_str() {
        "ply-ascii" => Format::PlyAscii,
        other => Format::from_path(Path::new(&file_name(other))).map_err(|_| {
            format!("unknown mesh format {format:?}; use obj, ply, ply-ascii, gltf, glb or stl")
        })?,
    };
    let positions = crate::arrays::as_points(positions, "positions")?;
    let normals = normals
        .map(|n| crate::arrays::as_points(n, "normals"))
        .transpose()?;
    let uvs = uvs.map(crate::arrays::uvs).transpose()?;
    let triangles = crate::arrays::triangles(indices)?;
    let view = MeshView {
        positions,
        normals,
        uvs: uvs.as_deref(),
        triangles: &triangles,
    };
    tessella_io::write_mesh_bytes(format, view).map_err(|e| errors::message(&e))
}

/// `readMesh` for JS: see `js/src/index.js`.
#[wasm_bindgen(js_name = readMesh)]
pub fn read_js(bytes: &[u8], format: &str, buffers: &GltfBuffers) -> Result<Arrays, JsError> {
    read(bytes, format, buffers).map_err(errors::text)
}

/// `writeMesh` for JS: see `js/src/index.js`.
#[wasm_bindgen(js_name = writeMesh)]
pub fn write_js(
    format: &str,
    positions: &[f32],
    indices: &[u32],
    normals: Option<Vec<f32>>,
    uvs: Option<Vec<f32>>,
) -> Result<Vec<u8>, JsError> {
    write(
        format,
        positions,
        indices,
        normals.as_deref(),
        uvs.as_deref(),
    )
    .map_err(errors::text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_file_reads_back_and_names_are_checked() {
        let m = tessella_core::samples::tetrahedron();
        let p = crate::arrays::flat(m.positions());
        let i: &[u32] = bytemuck::cast_slice(m.triangles());
        for format in ["obj", "ply", "ply-ascii", "gltf", "GLB", "stl"] {
            let bytes = write(format, p, i, None, None).unwrap();
            let read_as = if format == "ply-ascii" { "ply" } else { format };
            let mut back = read(&bytes, &read_as.to_lowercase(), &GltfBuffers::default()).unwrap();
            assert_eq!(back.take_indices().len(), i.len(), "{format}");
        }
        let err = write("fbx", p, i, None, None).unwrap_err();
        assert!(err.contains("unknown mesh format \"fbx\""), "{err}");
        let err = read(b"v 0 0 0\n", "m.fbx", &GltfBuffers::default()).unwrap_err();
        assert!(err.contains("unknown mesh file extension"), "{err}");
        let mismatched = GltfBuffers::new(vec!["a.bin".into()], vec![3], vec![0]);
        let err = read(b"", "obj", &mismatched).unwrap_err();
        assert!(err.contains("do not fit together"), "{err}");
    }
}
