//! # tessella-io
//!
//! Mesh files for tessella: read OBJ, PLY, glTF/GLB and STL into a [`RawMesh`] or a validated
//! [`tessella_core::Mesh`]; write any [`MeshView`] (a coarse [`tessella_core::Mesh`] or a
//! [`tessella_core::RefinedMesh`]) as OBJ, PLY (binary or ascii), glTF, GLB or STL.
//!
//! ```
//! use tessella_io::{read_mesh, write_mesh, MeshView, WriteOptions};
//! let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("tetrahedron.glb");
//! let mesh = tessella_core::samples::tetrahedron();
//! write_mesh(&path, MeshView::from(&mesh), &WriteOptions::default())?;
//! let back = read_mesh(&path)?;
//! assert_eq!(back.positions(), mesh.positions());
//! assert_eq!(back.triangles(), mesh.triangles());
//! # Ok::<(), tessella_io::IoError>(())
//! ```
//!
//! ## What each format keeps
//!
//! | format | read | written |
//! | --- | --- | --- |
//! | `.obj` | `v`, `vt`, `vn`, polygons (fan-triangulated); one vertex per distinct `v/vt/vn` triple | `v`, `vt`, `vn`, `f a/a/a` |
//! | `.ply` | ascii, binary LE/BE; `x y z`, `nx ny nz`, `u v`/`s t`/`texture_u texture_v`, extra vertex scalars, polygons (fan-triangulated), `edge` element | binary LE (default) or ascii; `x y z nx ny nz u v`, `vertex_indices` |
//! | `.gltf`, `.glb` | triangle primitives of the default scene in world space, merged (zero-area triangles left out); `data:` URIs or `.bin` files beside it; quantised and meshopt-compressed files | one primitive: POSITION (with min/max), NORMAL, TEXCOORD_0, u32 indices; `.gltf` embeds the buffer as base64 |
//! | `.stl` | ascii or binary; corners with equal positions welded; facet normals ignored | binary; geometric facet normals; normals and uvs are lost |
//!
//! Conventions: triangles are counter-clockwise; texture coordinates have their origin at the
//! image's bottom-left (OBJ/PLY), so glTF's `v` is flipped on read and write (see [`gltf`]).
//! Details per format are in the module docs ([`obj`], [`ply`], [`gltf`], [`stl`]).
//!
//! ## Scenes
//! [`gltf::scene`] reads a glTF file once, refines every triangle primitive on its own and
//! writes the same document back, with its nodes, materials, textures, skins, animations and
//! extensions (`tessella refine` for glTF in and out).
//!
//! ## Animation
//! [`read_animated`] reads a glTF file's nodes, skins, morph targets and clips, with its meshes
//! in their own space, into a [`tessella_core::animation::AnimatedMesh`] for the core to pose.
//!
//! ## Tags
//! [`tags`] reads shape tags from a sidecar JSON and from PLY properties, and layers every tag
//! source (split normals, crease angle, PLY, JSON) in one place for the CLI and Python.
//!
//! ## Height maps
//! [`read_height_map`] reads an image (PNG) as a [`tessella_core::displace::HeightMap`] for
//! displacement.
//!
//! ## Errors
//! Every failure is an [`IoError`] naming the file: unknown extensions, malformed or truncated
//! files, files without triangles, indices out of range, and (for [`read_mesh`]) the core's
//! [`tessella_core::MeshError`]. Readers never panic on bad input.
//!
//! ## Writing is atomic
//! [`write_mesh`] writes through [`write_atomic`]: an unnamed file in the target's folder (Linux's
//! `O_TMPFILE`; elsewhere a named temporary file) gets the target's name only once it is
//! complete, so a failure leaves the old file (or none), and so does a killed process on Linux.

mod atomic;
mod encode;
mod error;
mod format;
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing;
pub mod gltf;
mod height_map;
pub mod obj;
pub mod ply;
mod raw;
mod refined;
mod sample_scene;
pub mod stl;
pub mod stream;
pub mod tags;

pub use atomic::{
    sync_folder, write_atomic, write_atomic_with, Durability, TEMP_PREFIX, TEMP_SUFFIX,
};
pub use error::IoError;
pub use format::Format;
pub use height_map::read_height_map;
pub use raw::{MeshView, RawEdge, RawMesh};
pub use refined::RefinedSource;
pub use sample_scene::{sample_scene, sample_scene_detailed};
pub use stream::{write_streamed, MeshSource};

use std::io::BufReader;
use std::path::Path;

/// How [`write_mesh`] encodes formats that have choices.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// Write `.ply` as ascii instead of binary little-endian.
    pub ply_ascii: bool,
    /// Whether the file is flushed to the disk before it gets its name (the default), or left
    /// in the system's cache for a later [`sync_folder`] (many files at once).
    pub durability: Durability,
}

/// Reads what a mesh file holds, picking the format by extension. Checks that there are
/// triangles, that attribute counts match and that indices are in range; geometry is checked by
/// [`read_mesh`].
pub fn read_raw(path: &Path) -> Result<RawMesh, IoError> {
    let format = Format::from_path(path)?;
    let read_error = |source| IoError::Read {
        path: path.to_path_buf(),
        source,
    };
    match format {
        Format::Obj => {
            let file = std::fs::File::open(path).map_err(read_error)?;
            obj::read(path, BufReader::new(file))
        }
        Format::Ply | Format::PlyAscii => {
            let file = std::fs::File::open(path).map_err(read_error)?;
            ply::read(path, BufReader::new(file))
        }
        Format::Gltf | Format::Glb => {
            let bytes = std::fs::read(path).map_err(read_error)?;
            gltf::read(path, &bytes, format.name())
        }
        Format::Stl => {
            let bytes = std::fs::read(path).map_err(read_error)?;
            stl::read(path, bytes)
        }
    }
}

/// Reads a mesh file held in memory (the browser's way: no file system is touched). `name` is
/// the file's name: its extension picks the format and messages name it. A `.gltf` file's
/// external buffers come from `buffers`, (relative URI, bytes) pairs.
///
/// ```
/// let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// let raw = tessella_io::read_raw_bytes("triangle.obj", obj, &[])?;
/// assert_eq!(raw.triangles, vec![[0, 1, 2]]);
/// # Ok::<(), tessella_io::IoError>(())
/// ```
pub fn read_raw_bytes(
    name: &str,
    bytes: &[u8],
    buffers: &[(&str, &[u8])],
) -> Result<RawMesh, IoError> {
    let path = Path::new(name);
    let format = Format::from_path(path)?;
    match format {
        Format::Obj => obj::read(path, bytes),
        Format::Ply | Format::PlyAscii => ply::read(path, bytes),
        Format::Gltf | Format::Glb => {
            gltf::read_with(path, bytes, format.name(), gltf::Buffers::Given(buffers))
        }
        Format::Stl => stl::read(path, bytes.to_vec()),
    }
}

/// Reads a `.gltf` or `.glb` file's animation data (nodes, skins, mesh instances in their own
/// space, morph targets, joint influences, clips; see [`gltf::read_animated`]), not validated:
/// `tessella_core::animation::Poser::new` validates it. Other formats hold no animation:
/// an [`IoError::Unsupported`].
pub fn read_animated(path: &Path) -> Result<tessella_core::animation::AnimatedMesh, IoError> {
    let format = animated_format(path)?;
    let bytes = std::fs::read(path).map_err(|source| IoError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    gltf::read_animated(path, &bytes, format.name(), gltf::Buffers::Folder)
}

/// [`read_animated`] of a file held in memory, as [`read_raw_bytes`] reads one: `name` picks
/// the format and is named in messages, and a `.gltf` file's external buffers come from
/// `buffers`.
pub fn read_animated_bytes(
    name: &str,
    bytes: &[u8],
    buffers: &[(&str, &[u8])],
) -> Result<tessella_core::animation::AnimatedMesh, IoError> {
    let path = Path::new(name);
    let format = animated_format(path)?;
    gltf::read_animated(path, bytes, format.name(), gltf::Buffers::Given(buffers))
}

fn animated_format(path: &Path) -> Result<Format, IoError> {
    match Format::from_path(path)? {
        format @ (Format::Gltf | Format::Glb) => Ok(format),
        format => Err(IoError::Unsupported {
            path: path.to_path_buf(),
            format: format.name(),
            message: "only glTF (.gltf, .glb) files hold animations".into(),
        }),
    }
}

/// [`read_raw_bytes`], validated into a [`tessella_core::Mesh`] as [`read_mesh`] does.
pub fn read_mesh_bytes(
    name: &str,
    bytes: &[u8],
    buffers: &[(&str, &[u8])],
) -> Result<tessella_core::Mesh, IoError> {
    validate(Path::new(name), read_raw_bytes(name, bytes, buffers)?)
}

/// Encodes `mesh` as a file of `format` in memory, after the same checks as [`write_mesh`].
pub fn write_mesh_bytes(format: Format, mesh: MeshView) -> Result<Vec<u8>, IoError> {
    let path = Path::new(match format {
        Format::Obj => "mesh.obj",
        Format::Ply | Format::PlyAscii => "mesh.ply",
        Format::Gltf => "mesh.gltf",
        Format::Glb => "mesh.glb",
        Format::Stl => "mesh.stl",
    });
    mesh.check(path)?;
    let mut out = Vec::new();
    match format {
        Format::Obj => obj::write(&mut out, &mesh),
        Format::Ply => ply::write(&mut out, &mesh, false),
        Format::PlyAscii => ply::write(&mut out, &mesh, true),
        Format::Gltf => gltf::write(&mut out, &mesh, false),
        Format::Glb => gltf::write(&mut out, &mesh, true),
        Format::Stl => stl::write(&mut out, &mesh),
    }
    .map_err(|source| IoError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(out)
}

/// Reads a mesh file and validates it into a [`tessella_core::Mesh`] (normals computed when the
/// file has none).
pub fn read_mesh(path: &Path) -> Result<tessella_core::Mesh, IoError> {
    validate(path, read_raw(path)?)
}

/// [`read_mesh`] with the file's per-vertex fields ([`RawMesh::vertex_scalars`]: PLY vertex
/// properties, glTF `_NAME` attributes), by name.
pub fn read_mesh_with_fields(
    path: &Path,
) -> Result<
    (
        tessella_core::Mesh,
        std::collections::BTreeMap<String, Vec<f32>>,
    ),
    IoError,
> {
    let mut raw = read_raw(path)?;
    let fields = std::mem::take(&mut raw.vertex_scalars);
    Ok((validate(path, raw)?, fields))
}

fn validate(path: &Path, raw: RawMesh) -> Result<tessella_core::Mesh, IoError> {
    tessella_core::Mesh::new(raw.positions, raw.normals, raw.uvs, raw.triangles).map_err(|source| {
        IoError::Mesh {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Whether files of `path`'s format hold extra per-vertex scalars (PLY vertex properties,
/// glTF `_NAME` attributes) for [`write_mesh_with_scalars`].
pub fn holds_vertex_scalars(path: &Path) -> bool {
    matches!(
        Format::from_path(path),
        Ok(Format::Ply | Format::PlyAscii | Format::Gltf | Format::Glb)
    )
}

/// [`write_mesh`] with extra per-vertex scalars (solution fields): `property float NAME` in
/// PLY, float `SCALAR` attributes `_NAME` in glTF/GLB. Other formats cannot hold them: an
/// error, unless `scalars` is empty. Each needs one value per vertex and a distinct name
/// without whitespace.
pub fn write_mesh_with_scalars(
    path: &Path,
    mesh: MeshView,
    scalars: &ply::VertexScalars,
    options: &WriteOptions,
) -> Result<(), IoError> {
    if scalars.is_empty() {
        return write_mesh(path, mesh, options);
    }
    let format = Format::from_path(path)?;
    match format {
        Format::Ply | Format::PlyAscii => {
            let ascii = options.ply_ascii || format == Format::PlyAscii;
            ply::write_file_with(path, mesh, scalars, None, ascii)
        }
        Format::Gltf | Format::Glb => {
            // The same name and length checks as PLY's.
            mesh.check(path)?;
            let names: Vec<&str> = scalars.iter().map(|(name, _)| *name).collect();
            check_vertex_extras(path, format, &names, false)?;
            let n = mesh.positions.len();
            if let Some((name, values)) = scalars.iter().find(|(_, v)| v.len() != n) {
                return Err(IoError::BadMesh {
                    path: path.to_path_buf(),
                    message: format!(
                        "vertex attribute {name:?} has {} values for {n} vertices",
                        values.len()
                    ),
                });
            }
            let binary = format == Format::Glb;
            write_atomic_with(path, options.durability, |out| {
                gltf::write_with_scalars(out, &mesh, scalars, binary)
            })
        }
        _ => {
            let names: Vec<&str> = scalars.iter().map(|(name, _)| *name).collect();
            check_vertex_extras(path, format, &names, false)
        }
    }
}

/// Whether a file of `format` can hold per-vertex scalars named `names` (and, with `origin`,
/// each vertex's origin): PLY property names are ascii without whitespace, distinct, not one
/// of the standard properties; glTF attribute names are without whitespace and distinct; the
/// other formats hold neither. The checks of [`write_mesh_with_scalars`],
/// [`ply::write_file_with`] and the streamed writer, lengths aside.
pub(crate) fn check_vertex_extras(
    path: &Path,
    format: Format,
    names: &[&str],
    origin: bool,
) -> Result<(), IoError> {
    let unsupported = |message: String| IoError::Unsupported {
        path: path.to_path_buf(),
        format: format.name(),
        message,
    };
    let ply = matches!(format, Format::Ply | Format::PlyAscii);
    if origin && !ply {
        return Err(unsupported(
            "it cannot hold the vertices' origins; write .ply".into(),
        ));
    }
    if names.is_empty() {
        return Ok(());
    }
    let (what, reserved): (&str, &[&str]) = match format {
        Format::Ply | Format::PlyAscii => ("vertex property", ply::RESERVED),
        Format::Gltf | Format::Glb => ("vertex attribute", &[]),
        _ => {
            return Err(unsupported(format!(
                "it cannot hold per-vertex fields ({}); write .ply, .gltf or .glb",
                names.join(", ")
            )))
        }
    };
    for (i, name) in names.iter().enumerate() {
        let bad_name =
            name.is_empty() || name.chars().any(char::is_whitespace) || (ply && !name.is_ascii());
        let message = if bad_name {
            match ply {
                true => {
                    format!("{what} {name:?} is not a PLY property name (ascii, no whitespace)")
                }
                false => format!("{what} {name:?} is not a name without whitespace"),
            }
        } else if reserved.contains(name) || names[..i].contains(name) {
            format!("{what} {name:?} is given twice")
        } else {
            continue;
        };
        return Err(IoError::BadMesh {
            path: path.to_path_buf(),
            message,
        });
    }
    Ok(())
}

/// Writes `mesh` in the format named by `path`'s extension, atomically (see [`write_atomic`]).
/// The arrays are checked first (matching lengths, indices in range, finite positions, at least
/// one triangle).
pub fn write_mesh(path: &Path, mesh: MeshView, options: &WriteOptions) -> Result<(), IoError> {
    let format = match Format::from_path(path)? {
        Format::Ply if options.ply_ascii => Format::PlyAscii,
        format => format,
    };
    mesh.check(path)?;
    write_atomic_with(path, options.durability, |out| match format {
        Format::Obj => obj::write(out, &mesh),
        Format::Ply => ply::write(out, &mesh, false),
        Format::PlyAscii => ply::write(out, &mesh, true),
        Format::Gltf => gltf::write(out, &mesh, false),
        Format::Glb => gltf::write(out, &mesh, true),
        Format::Stl => stl::write(out, &mesh),
    })
}
