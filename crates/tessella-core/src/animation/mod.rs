//! Animated meshes: glTF 2.0's skins, morph targets, node hierarchy and clips, posed into
//! buffers the caller owns, so that a frame is pose → nets ([`crate::refine::Surface::update`])
//! → evaluate, with only the coarse mesh moving.
//!
//! [`model`] holds the data, as tessella-io reads it from a glTF file (or as a caller builds it):
//! nodes with their local transforms, skins, mesh instances with their vertices in the mesh's
//! own space, morph targets, joint influences, and clips of sampled channels. [`Poser::new`]
//! validates it once; [`Poser::pose_into`] (or [`Poser::pose`], [`Poser::mesh`]) poses it.
//!
//! Implemented, following the glTF 2.0 specification
//! (<https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>, sections "Animations",
//! "Skins", "Morph Targets" and Appendix C, "Animation Sampler Interpolation Modes"):
//! - keyframe sampling: `STEP`, `LINEAR` (rotations by slerp along the shorter arc) and
//!   `CUBICSPLINE` (Hermite, tangents scaled by the key interval), rotations normalised, the
//!   first value before the first key and the last after the last key;
//! - translation, rotation, scale and morph weights channels; nodes given as matrices (not
//!   animated, as the specification requires);
//! - world matrices through the node hierarchy;
//! - morph targets (positions and normals) with node, animated or default weights;
//! - linear blend skinning over any number of four-joint influence sets, weights normalised by
//!   their sum, normals by the inverse transpose of the blended matrix, renormalised; a skinned
//!   mesh node's own transform is ignored and posed positions are in the scene's space;
//! - unskinned instances moved by their node's world matrix.
//!
//! Not covered: tangents, cameras, lights and other glTF extensions' animated properties
//! (`KHR_animation_pointer`).

#![warn(missing_docs)]

mod check;
mod deform;
mod hierarchy;
pub mod model;
mod pose;
mod sample;

pub use deform::{skin_normal_of, DeformTable};
pub use model::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Property,
    Sampler, Skin, Transform,
};
pub use pose::Poser;
