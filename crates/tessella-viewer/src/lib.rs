//! # tessella-viewer
//!
//! The interactive viewer's engine, platform-neutral: a [`Viewer`] owns a
//! [`tessella_gpu::GpuContext`], the loaded coarse mesh, its surfaces and tessella-gpu's
//! renderers (the [`tessella_gpu::PatternRenderer`] for one whole grid level, the
//! [`tessella_gpu::AdaptiveRenderer`] for fractional, tessellator and LOD levels), the camera
//! and the [`Params`]; it draws one frame into a `wgpu::TextureView` the caller gives (a
//! canvas's current texture, a window's, an offscreen texture) without ever waiting for the
//! GPU.
//!
//! - Parameters have `tessella render`'s names and meanings, parsed by the same code
//!   (`params.rs`); the camera *is* `tessella render`'s (`tessella_view::scene_uniforms`), so the
//!   same yaw, pitch, zoom and size give the same picture.
//! - Per frame only coarse data crosses the bus: the control nets when the mesh deforms
//!   (`deform.rs`, [`Viewer::move_vertex`]), one level record per face and one instance per face
//!   and part when a LOD follows the camera; [`Stats`] counts those bytes.
//! - [`Viewer::pick`] ray-casts the coarse mesh with the view's own matrix; tags edited with
//!   [`Viewer::set_edge_sharpness`] / [`Viewer::set_vertex_tension`] rebuild the surfaces at once
//!   and save as the CLI's tags JSON ([`Viewer::tags_json`]).
//! - Every call returns a `Result`; on error the previous mesh, parameters and surfaces stay.
//!
//! [`CoarseViewer`] is the same coarse side (files, clips, parameters, tags, poses: the shared
//! [`scene`]) without a GPU: the web page's WebGL2 fallback draws its packed control nets.
//!
//! In the browser, `web.rs` (wasm32 only) is the `WebViewer` of `CONTRACT.md`, built by
//! `build-web.sh`; its `bench()` runs tessella-bench's browser benchmark (GMR's Figure 7 and the
//! scheme tables) on the viewer's device. `docs/viewer.md` says what is drawn and what crosses the bus.

mod clock;
mod coarse;
mod deform;
mod error;
mod panel;
pub mod params;
mod pick;
pub mod playback;
pub mod present;
pub mod scene;
mod stats;
mod viewer;
#[cfg(target_arch = "wasm32")]
pub mod web;

pub use coarse::CoarseViewer;
pub use error::ViewerError;
pub use params::{Animation, Params};
pub use pick::Picked;
pub use stats::Stats;
pub use viewer::{Viewer, FIRST_SAMPLE, SAMPLES};
