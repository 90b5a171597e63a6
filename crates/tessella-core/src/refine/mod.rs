//! Refinement on the CPU: control nets × stencil, into an indexed mesh.
//!
//! ```
//! use tessella_core::{refine, samples, RefineOptions, Scheme};
//! let mesh = samples::icosphere(1);
//! let out = refine(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
//! assert_eq!(out.triangles.len(), mesh.face_count() * 16);
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

//! Two layers, in the manner of OpenSubdiv's Far and Osd:
//!
//! - `plan/`: what is built once per topology and levels: the options, levels and
//!   LOD, the adaptive tiling and its instanced parts, canonical edge weights and geomorphs, the
//!   output layout, indices and pieces, the surface that builds each frame's nets, and the
//!   [`Plan`] itself. It never imports the evaluator.
//! - `cpu/`: the CPU evaluator on top of it: the kernels, the uniform and adaptive jobs
//!   that dispatch them, edge groups, output sinks and streaming stores, whole-frame and
//!   piece evaluation, the [`Evaluator`] interface and the one-shot [`Refiner`].
//!
//! This file only declares the two and re-exports their public items (the paths other crates
//! use: `refine::Plan`, `refine::Tiling`, `refine::canonical`, ...).

mod cpu;
mod plan;

pub use cpu::evaluator::{CpuEvaluator, Evaluator};
pub use cpu::kernels::eval_point;
#[cfg(feature = "bandwidth")]
pub use cpu::nontemporal::{stream_copy, stream_fill};
pub use cpu::output::{VertexFormat, VertexOutput};
pub use cpu::refiner::{refine, RefinedMesh, Refiner};
pub use plan::conflicts::{Ask, Conflict};
pub use plan::driver::InstancedDriver;
pub(crate) use plan::grid_point;
pub use plan::indices::IndexInt;
pub use plan::layout::{OutputLayout, BYTES_PER_INDEXED_TRIANGLE, NO_FACE};
pub use plan::levels::{Camera, Levels, Lod, Spacing};
pub use plan::options::{RefineOptions, DEFAULT_MAX_OUTPUT_BYTES};
pub use plan::options_text::{parse_bytes, parse_level, parse_size, OptionError, OPTION_KEYS};
pub use plan::pieces::Piece;
pub use plan::sizes::PlanSizes;
pub use plan::surface::{Frame, Surface, SurfaceOptions};
pub use plan::table::Plan;
pub use plan::tiling::{grid_pattern, Morph, Tile, Tiling};
pub use plan::{canonical, instanced, lod, morph, packed};
