//! The one error type of this crate. Every variant names the file and says what is wrong.

use std::path::PathBuf;
use thiserror::Error;

/// Why a mesh file could not be read or written.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// The extension names no format this crate knows.
    #[error("{path}: unknown mesh file extension {extension:?}; supported extensions are .obj, .ply, .gltf, .glb and .stl", path = path.display())]
    UnknownExtension { path: PathBuf, extension: String },
    /// The operating system refused to read the file.
    #[error("cannot read {path}: {source}", path = path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The operating system refused to write the file (nothing was left at `path`).
    #[error("cannot write {path}: {source}", path = path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The file is not a well-formed file of its format (truncated, garbage, bad numbers).
    #[error("{path}: malformed {format} file: {message}", path = path.display())]
    Parse {
        path: PathBuf,
        format: &'static str,
        message: String,
    },
    /// The file is well formed but uses a feature this crate does not read.
    #[error("{path}: unsupported {format} content: {message}", path = path.display())]
    Unsupported {
        path: PathBuf,
        format: &'static str,
        message: String,
    },
    /// The file holds no triangle at all.
    #[error("{path}: the file holds no triangles; tessella refines triangle meshes (points and lines are ignored)", path = path.display())]
    NoTriangles { path: PathBuf },
    /// A face or edge uses a vertex the file does not have.
    #[error("{path}: {what} {item} uses vertex {index}, but the file has only {count} vertices", path = path.display())]
    IndexOutOfRange {
        path: PathBuf,
        what: &'static str,
        item: usize,
        index: u64,
        count: usize,
    },
    /// The arrays handed to a writer do not fit together.
    #[error("{path}: cannot write this mesh: {message}", path = path.display())]
    BadMesh { path: PathBuf, message: String },
    /// A part of the file (a glTF primitive) could not be refined as asked.
    #[error("{path}: {part}: {source}", path = path.display())]
    Refine {
        path: PathBuf,
        part: String,
        #[source]
        source: Box<tessella_core::RefineError>,
    },
    /// The file was read but its mesh failed validation.
    #[error("{path}: {source}", path = path.display())]
    Mesh {
        path: PathBuf,
        #[source]
        source: tessella_core::MeshError,
    },
}
