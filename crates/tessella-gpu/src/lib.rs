//! # tessella-gpu
//!
//! The GPU backend of tessella, on [wgpu] with WGSL shaders: the GPU refines the coarse mesh
//! itself and only coarse data crosses the bus (Boubekeur & Schlick 2005, "Generic Mesh
//! Refinement on GPU", GMR).
//!
//! It consumes tessella-core's tables unchanged: the per-triangle control nets
//! ([`tessella_core::PatchNets`]) and the pattern's stencil ([`tessella_core::Stencil`]). The
//! shaders only compute the generic weighted sum `Σ w_k C_k` (`shaders/eval.wgsl`, the twin of
//! `tessella_core::refine::eval_point`), with the basis size `K` as a uniform, so on the stencil paths
//! (compute, `PatternRenderer`) every basis the core knows runs with no WGSL change; the
//! `AdaptiveRenderer`, whose points move with each frame's levels, computes the weights in its
//! vertex shader, with code generated from the core's own formulas ([`tessella_core::shader`]:
//! cubic Bernstein and PNG1 weights, the normal net's and a canonical edge's).
//!
//! - [`GpuContext::new`]`(`[`AdapterChoice`]`)` opens a device (a clear [`GpuError::NoAdapter`]
//!   when there is none; nothing here panics on a missing GPU); [`GpuContext::from_device`]
//!   wraps the caller's own `wgpu::Device` and `wgpu::Queue`.
//! - **Evaluator:** [`GpuEvaluator`] implements [`tessella_core::refine::Evaluator`], like the
//!   CPU's `CpuEvaluator`: made once per [`tessella_core::refine::Plan`] (stencil and tables
//!   uploaded then), it writes each frame's refined vertices into its own vertex buffer or the
//!   caller's ([`GpuOutput`]), uploading only the frame's coarse data; [`GpuEvaluator::index_buffer`]
//!   / [`GpuEvaluator::write_indices`] give the indices once. [`gpu_refine`] /
//!   [`gpu_refine_with`] read a whole refined mesh back, identical to the CPU's
//!   [`tessella_core::Refiner::refine`].
//! - **Renderer:** [`PatternRenderer`] draws one instanced pattern per coarse triangle (GMR
//!   section 3.2) into the caller's render pass; per frame only the nets are uploaded. It places
//!   the points; the caller's [`Shading`] (its WGSL's `shade_vertex` and `fs_main`, its bind
//!   group 1) colours them: tessella-gpu draws no colour of its own.
//!   [`AdaptiveRenderer`], made from a [`tessella_core::refine::Surface`] (topology and scheme,
//!   no level), draws per-edge levels that change every frame: the patterns' parts are uploaded
//!   once (`tessella_core::refine::instanced`), per frame one record per face. A device without
//!   storage buffers in the vertex stage ([`GpuContext::with_downlevel`]) has the renderers
//!   refused with [`GpuError::NoVertexStorage`]; the evaluator's compute path still works.
//! - **Nets built on the GPU:** [`GpuNetBuilder`], made once from a
//!   [`tessella_core::refine::Surface`], builds a frame's control nets (flat, Phong, PN,
//!   PN-AEN; the other schemes' nets stay on the CPU) from coarse vertices the caller already
//!   has in a storage buffer ([`CoarseInput`], an engine's own skinning output) into a
//!   consumer's [`NetsTarget`] (`nets_target()` of [`PatternRenderer`], [`AdaptiveRenderer`],
//!   [`PatchBindings`], [`GpuEvaluator`], which then evaluates with
//!   [`GpuEvaluator::record_built`]): one dispatch in the caller's encoder, no per-frame upload,
//!   equal to the CPU's nets within `1e-6` relative (`docs/engine.md`).
//! - **Displacement:** [`tessella_core::displace`]'s [`Displacement`] (sine, Perlin, height
//!   map; re-exported here because [`GpuRefineOptions`] and [`PatternRenderer`] take it) in
//!   both GPU paths (`shaders/displace.wgsl`), with the core's direction rule: hard edges and
//!   split corners move along one shared direction and stay closed. The per-face records that
//!   rule needs are uploaded with each frame.
//!
//! Errors reach the caller: tessella's own work runs inside wgpu error scopes of its own
//! ([`GpuContext::scoped`]), so a rejected frame is an `Err`; [`GpuContext::from_device`] leaves
//! the engine's handlers alone. [`GpuEvaluator::record`] records into the engine's encoder, in
//! the engine's [`tessella_core::refine::VertexFormat`]; [`PatchBindings`] gives WGSL an engine's
//! own shader calls (`docs/engine.md`). Nothing per frame blocks; the blocking forms are the
//! default `blocking` feature, and without it the crate builds for the web (wgpu's `webgpu`).
//! Pictures, cameras, labels, animations and benchmarks live in the `tessella-view` crate.
//!
//! ```no_run
//! use tessella_core::{samples, RefineOptions, Refiner, Scheme};
//! use tessella_gpu::{gpu_refine, AdapterChoice, GpuContext};
//!
//! let ctx = GpuContext::new(AdapterChoice::Auto)?;
//! let mesh = samples::icosphere(1);
//! let refined = gpu_refine(&ctx, &Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, 8))?)?;
//! assert_eq!(refined.triangles.len(), mesh.face_count() * 64);
//! # Ok::<(), tessella_gpu::GpuError>(())
//! ```
//!
//! `examples/engine.rs` is an engine frame (its encoder, a 32-byte vertex, its shader calling
//! `tessella_point`); `examples/deform.rs` owns its device, deforms a mesh over frames, evaluates into its own
//! vertex buffer and draws it with its own pipeline.
//!
//! ## Shaders
//! `shaders/eval.wgsl` (patch evaluation) and `shaders/displace.wgsl` (displacement) are
//! prepended to `shaders/refine.wgsl` (compute) and `shaders/render.wgsl` (the vertex entry
//! points). The adaptive renderer's are the weights generated by [`tessella_core::shader`] (at
//! any point, straight-line code) + `shaders/adaptive.wgsl` (points from level records, whose
//! layout constants the core generates too), then `shaders/adaptive_draw.wgsl`, or
//! `shaders/adaptive_capture.wgsl` for the read-back. The render pipelines end with
//! `shaders/vertex.wgsl` ([`VERTEX_WGSL`], the `TessellaVertex` handed over) and the caller's
//! shading. `shaders/nets.wgsl` (the GPU net builder's kernel) follows the net builders
//! generated from the schemes' Rust ([`tessella_core::shader::net_builder`]).
//! The layout constants both sides use are generated from Rust (`wgsl_constants.rs`) and
//! prepended to every shader. Uniform structs have Rust twins in `gpu_types.rs` with size/offset assertions;
//! `displace.wgsl` holds the displacement's bindings and reads; its offsets and direction are
//! generated from `tessella_core::displace` ([`tessella_core::shader::displace_wgsl`]). The tests
//! compare GPU and CPU outputs.
//!
//! Linux without a GPU: `apt-get install mesa-vulkan-drivers libvulkan1` gives lavapipe, a
//! software Vulkan adapter ([`AdapterChoice::Software`]); the tests run on it and fail (not
//! skip) without it.

mod adaptive;
mod canonical;
mod coarse;
mod context;
mod displace;
mod error;
mod evaluator;
mod gpu_types;
mod net_builder;
mod patch;
mod pipeline_cache;
mod renderer;
mod shading;
pub mod wgsl;
mod wgsl_constants;

pub use adaptive::{AdaptiveRenderer, CapturedTriangles, ADAPTIVE_VERTEX_STORAGE_BUFFERS};
pub use coarse::{CoarseInput, CoarseStream};
pub use context::{AdapterChoice, GpuContext, COMPUTE_STORAGE_BUFFERS, READ, UNIFORM, WRITE};
pub use error::GpuError;
#[cfg(feature = "blocking")]
pub use evaluator::{gpu_refine, gpu_refine_with};
pub use evaluator::{GpuEvaluator, GpuOutput, GpuRefineOptions, IndexWidth};
pub use net_builder::{GpuNetBuilder, NetsTarget};
pub use renderer::{PatternRenderer, PATTERN_VERTEX_STORAGE_BUFFERS};
pub use shading::{Shading, TargetFormats, VERTEX_WGSL};
pub use tessella_core::displace::Displacement;
pub use wgsl::PatchBindings;
