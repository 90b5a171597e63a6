//! glTF 2.0: `.gltf` (JSON) and `.glb` (binary container). Read with the `gltf` crate, written
//! with `serde_json`.
//!
//! Texture coordinates: glTF puts the uv origin at the image's top-left, OBJ and PLY at the
//! bottom-left. [`crate::RawMesh`] uses the OBJ/PLY convention, so glTF's `v` is flipped
//! (`v' = 1 - v`) on read and on write, as Blender and trimesh do. The flip is exact for
//! `v` in `[0.5, 1]` and for short binary fractions (0.25, 0.125, ...); elsewhere a round trip
//! through glTF may move `v` by one unit in the last place.

mod read;
mod write;

pub use read::read;
pub use write::write;

/// Flips a texture coordinate between glTF's and OBJ/PLY's conventions (an involution).
fn flip_v(uv: [f32; 2]) -> [f32; 2] {
    [uv[0], 1.0 - uv[1]]
}
