//! Animated meshes: glTF 2.0's skins, morph targets, node hierarchy and clips, posed into
//! buffers the caller owns, so that a frame is pose → nets ([`crate::refine::Surface::update`])
//! → evaluate, with only the coarse mesh moving.
//!
//! [`model`] holds the data, as tessella-io reads it from a glTF file (or as a caller builds it):
//! nodes with their local transforms, skins, mesh instances with their vertices in the mesh's
//! own space, morph targets, joint influences, and clips of sampled channels. Posing follows the
//! glTF 2.0 specification: morph targets first, then linear blend skinning of positions, and of
//! normals by the inverse transpose of the blended joint matrix, renormalised; a skinned mesh
//! node's own transform is ignored, and posed positions are in the scene's space.

pub mod model;

pub use model::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Property,
    Sampler, Skin, Transform,
};
