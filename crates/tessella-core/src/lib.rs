//! # tessella-core
//!
//! Turns coarse triangle meshes into smooth curved surfaces by *refinement patterns*
//! (Boubekeur & Schlick 2005): one pre-tessellated triangle ([`Pattern`]) is mapped onto every
//! coarse triangle's curved patch.
//!
//! Data flows one way:
//!
//! ```text
//! Mesh ──topology──▶ Topology ─┐
//!   │                          ├─▶ OutputLayout (who owns each shared vertex)
//!   └──scheme──▶ PatchNets ────┤
//! Pattern ──basis──▶ Stencil ──┴─▶ evaluate: vertex = Σ weight × control point ─▶ RefinedMesh
//! ```
//!
//! A scheme ([`Scheme`]) only builds control nets; a basis ([`Basis`]) only says how a net is
//! combined at a barycentric point. Backends (this crate's CPU evaluator, the GPU crate) consume
//! nets and stencils unchanged.
//!
//! Animated meshes (glTF 2.0 node hierarchies, skins, morph targets and clips, in
//! [`animation`]) are posed by [`animation::Poser`] into a fresh [`Mesh`] or into the caller's
//! buffers for [`Mesh::update`], once per frame, before refinement.
//!
//! ## Conventions
//! - Barycentric `(l1, l2, l3)` weigh the corners `(P1, P2, P3)` of a triangle in index order;
//!   control point `b_ijk` has `i` for P1 (see docs/formulas.md).
//! - Triangles are counter-clockwise seen from the side their normals face; refined triangles
//!   keep the winding.
//! - "Level" is the number of segments per coarse edge: level `N` makes `N²` triangles per
//!   coarse triangle.
//! - Normals are unit length on input (normalised when read) and output.

pub mod animation;
pub mod basis;
pub mod displace;
mod error;
pub mod fields;
pub mod framing;
pub mod mesh;
pub mod names;
pub mod pattern;
pub mod quality;
pub mod refine;
pub mod samples;
pub mod scalar;
pub mod scheme;
pub mod shader;
pub mod stencil;
pub mod tags;
pub mod tessellator;

pub use basis::Basis;
pub use displace::{DisplaceError, DisplaceFrame, Displacement, HeightMap, SharedSlots};
pub use error::{AnimationError, MeshError, RefineError};
pub use mesh::{Mesh, Topology, TopologyReport};
pub use names::{Backend, Named, UnknownName};
pub use pattern::Pattern;
pub use quality::QualityReport;
pub use refine::{refine, OutputLayout, RefineOptions, RefinedMesh, Refiner};
pub use scheme::{NormalMode, PatchNets, Scheme};
pub use stencil::Stencil;
pub use tags::{TagError, Tags};

/// The README's Rust examples, compiled and run as doc tests so they stay true.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeExamples;
