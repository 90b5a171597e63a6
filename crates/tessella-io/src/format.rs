//! Which file format a path names.

use crate::IoError;
use std::path::Path;

/// A mesh file format. [`Format::from_path`] picks it by extension; `PlyAscii` is only chosen
/// through [`crate::WriteOptions::ply_ascii`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// Wavefront OBJ (text).
    Obj,
    /// PLY, binary little-endian when written (any PLY encoding is read).
    Ply,
    /// PLY, ascii.
    PlyAscii,
    /// glTF 2.0 JSON with the buffer embedded as a `data:` URI (external `.bin` files are read).
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
    /// STL, ascii or binary (written binary).
    Stl,
}

impl Format {
    /// The format named by the file's extension (case-insensitive).
    ///
    /// ```
    /// use tessella_io::Format;
    /// use std::path::Path;
    /// assert_eq!(Format::from_path(Path::new("bunny.PLY")).unwrap(), Format::Ply);
    /// assert!(Format::from_path(Path::new("bunny.fbx")).is_err());
    /// ```
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match extension.as_str() {
            "obj" => Ok(Format::Obj),
            "ply" => Ok(Format::Ply),
            "gltf" => Ok(Format::Gltf),
            "glb" => Ok(Format::Glb),
            "stl" => Ok(Format::Stl),
            _ => Err(IoError::UnknownExtension {
                path: path.to_path_buf(),
                extension,
            }),
        }
    }

    /// The format's name as used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Format::Obj => "OBJ",
            Format::Ply | Format::PlyAscii => "PLY",
            Format::Gltf => "glTF",
            Format::Glb => "GLB",
            Format::Stl => "STL",
        }
    }
}
