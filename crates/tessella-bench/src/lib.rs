//! # tessella-bench
//!
//! tessella's benchmarks, out of the libraries they measure: what `tessella bench` (and its
//! `--gpu` and `--gl`) prints, and what the web page's `bench()` reports. The libraries
//! (tessella-view, tessella-gl, tessella-viewer) and the CLI hold none of it; this crate calls
//! their public API like any application.
//!
//! - [`cpu`] (feature `cpu`): the machine's memory bandwidth measured as STREAM does (plain
//!   and non-temporal stores), then refinement against it: one-shot on all cores and on one,
//!   every scheme per frame (the roofline table), a deforming mesh updated against rebuilt,
//!   and every file writer; [`cpu::Report`] is `tessella bench --json`.
//! - [`gpu`] (feature `gpu`): CPU against GPU refinement, the GMR paper's Figure 7 (a static
//!   refined vertex buffer against the instanced pattern), frame time by scheme, mixed
//!   patterns, and levels that change every frame. The frame-timed bodies are `async`, so the
//!   same code runs natively (the blocking forms, feature `blocking`) and in a browser.
//! - [`gpu_animated`] (feature `blocking`): an animated mesh's frame on its three paths to
//!   the pattern renderer (CPU nets, GPU nets from the caller's buffer, GPU skinning), timed
//!   with the bytes each uploads.
//! - [`web`] (feature `gpu`): the browser's `bench()`: its JSON configuration, checked before
//!   anything runs, and its report; tessella-viewer's wasm entry `WebViewer::bench` calls it.
//! - [`gl`] (feature `gl`): PN on the OpenGL 4 tessellator against the CPU refinement of the
//!   same plan; [`gl::tables`] adds the instanced pattern (with `blocking`) at the nearest grid
//!   level: `tessella bench --gl`.
//!
//! Every figure is a median of timed runs after a warm-up; rows carry the adapter's or driver's
//! name, and a software one's numbers are marked, since only ratios mean something there.

#[cfg(feature = "cpu")]
pub mod cpu;
#[cfg(feature = "gl")]
pub mod gl;
#[cfg(feature = "gpu")]
pub mod gpu;
#[cfg(feature = "blocking")]
pub mod gpu_animated;
#[cfg(feature = "gpu")]
pub mod web;
