//! # tessella-gl
//!
//! PN triangles (and every other tessella scheme) on the OpenGL 4 tessellation stages, after
//! van Veen: a tessellation control shader sets the levels, the fixed-function tessellator makes
//! the pattern (equal, fractional-odd or fractional-even spacing), a tessellation evaluation
//! shader evaluates the patch and its normals (the normal net — linear or Vlachos' quadratic,
//! "fake" — or `Du × Dv`, "real"). Runs headless through EGL (Mesa's llvmpipe in software).
//!
//! ## Where the formulas come from
//!
//! The tessellation control shader builds each patch's control net, as van Veen's does, from
//! the patch's corners (flat, Phong, PN) or from a 6-vertex patch that adds each edge's opposite
//! neighbour corner (PNG1, in double precision as the CPU builds it), so per frame only the
//! coarse positions and normals cross the bus ([`NetSource::Shader`]). Schemes whose nets need
//! more (PN-AEN, scalar-tagged, quadratic elements) take the nets tessella-core builds on the
//! CPU from storage buffers indexed by `gl_PrimitiveID` ([`NetSource::Buffers`]). The TCS also
//! sets the levels (uniform, or per face from the levels the CPU plan resolved: each edge's
//! level from that edge alone, so the output is crack-free); the TES sums `Σ w_k(l) C_k`.
//! The weights (cubic Bernstein, PNG1's rational weights, the normal net's) and the control
//! shader's net builders (flat, Phong, PN, and PNG1's net and smoothed normals in doubles) are
//! generated from tessella-core's own functions ([`tessella_core::shader`]), so they exist
//! once; the tests compare every GL vertex with the CPU refinement of the same scheme, spacing
//! and levels.
//!
//! ## The evaluator
//!
//! [`GlEvaluator`] implements tessella-core's `Evaluator`: made once per plan, it writes each
//! frame into the caller's [`GlRefined`] (the hardware's triangle soup with each vertex's face
//! and tessellation coordinate), uploading only the frame's coarse data. It runs the hardware
//! spacings only and does not displace (see [`GlEvaluator::with_displacement`]).

#[cfg(feature = "testing")]
mod compare;
mod context;
mod error;
mod program;
mod refine;
mod shaders;

#[cfg(feature = "testing")]
pub use compare::{compare, Comparison};
pub use context::{DriverInfo, GlContext};
pub use error::{GlError, DRIVER_PACKAGES};
pub use refine::{
    gl_clip_from_zero_to_one, hardware_spacing, DrawMode, GlEvaluator, GlRefined, GlTessellator,
    LevelSource, NetSource, Prepared, ShaderNets,
};
pub use shaders::{glsl_sources, ShaderSources};
