//! glTF 2.0: `.gltf` (JSON) and `.glb` (binary container). Read with the `gltf` crate, written
//! with `serde_json`.
//!
//! Texture coordinates: glTF puts the uv origin at the image's top-left, OBJ and PLY at the
//! bottom-left. [`crate::RawMesh`] uses the OBJ/PLY convention, so glTF's `v` is flipped
//! (`v' = 1 - v`) on read and on write, as Blender and trimesh do. The flip is exact for
//! `v` in `[0.5, 1]` and for short binary fractions (0.25, 0.125, ...); elsewhere a round trip
//! through glTF may move `v` by one unit in the last place.

//!
//! Extra per-vertex scalars (solution fields such as a temperature) are application-specific
//! attributes: a float `SCALAR` attribute `_NAME` is read into
//! [`crate::RawMesh::vertex_scalars`] as `NAME` (kept only when every primitive has it), and
//! written back as `_NAME`.
//!
//! Two readers share the parsing, buffer loading, accessor checks and primitive assembly:
//! [`read()`] gives the default scene's triangles in world space (a static mesh), and
//! [`read_animated`] gives nodes, skins, morph targets and clips with each mesh in its own
//! space, for the core to pose.

mod animated;
mod data;
mod read;
pub mod scene;
mod write;
mod write_animated;

pub use animated::read_animated;
pub use data::Buffers;
pub use read::{read, read_with};
pub(crate) use write::{
    fold_range, glb_document, gltf_document, write_glb_header, write_glb_padding, write_gltf_text,
    Shape,
};
pub use write::{write, write_with_scalars};
pub use write_animated::write_animated;

/// Flips a texture coordinate between glTF's and OBJ/PLY's conventions (an involution).
pub(crate) fn flip_v(uv: [f32; 2]) -> [f32; 2] {
    [uv[0], 1.0 - uv[1]]
}
