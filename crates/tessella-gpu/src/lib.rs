//! # tessella-gpu
//!
//! The GPU backend of tessella, on [wgpu] with WGSL shaders: the GPU refines the coarse mesh
//! itself and only coarse data crosses the bus (Boubekeur & Schlick 2005, "Generic Mesh
//! Refinement on GPU", GMR).
//!
//! It consumes tessella-core's tables unchanged: the per-triangle control nets
//! ([`tessella_core::PatchNets`]) and the pattern's stencil ([`tessella_core::Stencil`]). The
//! shaders only compute the generic weighted sum `Σ w_k C_k` (`shaders/eval.wgsl`, the twin of
//! `tessella_core::refine::eval_point`), with the basis size `K` as a uniform, so every scheme
//! the core knows (flat, Phong, PN, and any later basis) runs on the GPU with no WGSL change.
//!
//! - [`GpuContext::new`]`(`[`AdapterChoice`]`)` opens a device (a clear [`GpuError::NoAdapter`]
//!   when there is none; nothing here panics on a missing GPU).
//! - **Compute path:** [`gpu_refine`] / [`gpu_refine_with`] produce the same vertex order and
//!   indices as the CPU's [`tessella_core::Refiner::refine`], welded or soup, in chunks that fit
//!   one storage binding and one dispatch.
//! - **Render path:** [`render`] draws one instanced pattern per coarse triangle (GMR section
//!   3.2), Blinn-Phong, optional pattern wireframe; [`render_compare`] puts labelled panels
//!   side by side; [`animate::render_twist`] re-uploads only the nets per frame.
//! - **Displacement:** [`Displacement`] (sine, Perlin, height map) along the normal, on the CPU
//!   ([`Displacement::apply`]) and in both GPU paths (`shaders/displace.wgsl`).
//! - **Benchmarks:** [`mod@bench`] returns rows for Markdown tables (CPU vs GPU refinement, GMR
//!   Figure 7), labelled with the adapter.
//!
//! ```no_run
//! use tessella_core::{samples, RefineOptions, Refiner, Scheme};
//! use tessella_gpu::{gpu_refine, render, AdapterChoice, GpuContext, RenderOptions};
//!
//! let ctx = GpuContext::new(AdapterChoice::Auto)?;
//! let mesh = samples::icosphere(1);
//! let opts = RefineOptions::new(Scheme::Pn, 8);
//! let refined = gpu_refine(&ctx, &Refiner::new(&mesh, &opts)?)?;
//! let picture = render(&ctx, &mesh, &opts, &RenderOptions::default())?;
//! tessella_gpu::save_png(&picture, std::path::Path::new("pn.png"))?;
//! # Ok::<(), tessella_gpu::GpuError>(())
//! ```
//!
//! ## For the CLI
//! - `refine --backend auto`: `GpuContext::new(AdapterChoice::Hardware)`; on any `Err` use the
//!   CPU (a software adapter is for tests, not speed). `--backend gpu`: `AdapterChoice::Auto`
//!   (falls back to a software adapter). Then `gpu_refine(&ctx, &refiner)`; write the file only
//!   after it returned `Ok`.
//! - `render`: [`RenderOptions`] `{ size, yaw, pitch, zoom, wireframe, background, color,
//!   displacement }`, [`render`], [`render_compare`] with `(label, RefineOptions)` panels,
//!   [`save_png`] (temporary file + rename).
//! - `bench`: [`bench::refine_throughput`] + [`bench::refine_table`], [`bench::figure7`] +
//!   [`bench::figure7_table`], [`bench::scheme_frame_times`] + [`bench::scheme_table`] (PN vs
//!   PNG1); `examples/bench_tables.rs` prints all three.
//! - animation: [`animate::render_twist`] writes `frame_000.png`... and returns the bytes
//!   uploaded per frame (nets only) against a refined mesh's bytes.
//!
//! ## Shaders
//! `shaders/eval.wgsl` (patch evaluation) and `shaders/displace.wgsl` (displacement) are
//! prepended to `shaders/refine.wgsl` (compute) and `shaders/render.wgsl` (vertex/fragment).
//! Uniform structs have Rust twins in `gpu_types.rs` with size/offset assertions;
//! `displace.wgsl`'s Rust twin is `displace.rs`. The tests tie each pair together by comparing
//! GPU and CPU outputs.
//!
//! Linux without a GPU: `apt-get install mesa-vulkan-drivers libvulkan1` gives lavapipe, a
//! software Vulkan adapter ([`AdapterChoice::Software`]); the tests run on it and fail (not
//! skip) without it.

pub mod animate;
pub mod bench;
mod camera;
mod compute;
mod context;
mod displace;
mod error;
pub mod font;
mod gpu_types;
mod patch;
mod render;

pub use compute::{gpu_refine, gpu_refine_with, GpuRefineOptions};
pub use context::{AdapterChoice, GpuContext};
pub use displace::{perlin, permutation, Displacement, HeightMap};
pub use error::GpuError;
pub use image::RgbaImage;
pub use render::{render, render_compare, RenderOptions};

/// Writes `image` as a PNG to a temporary file beside `path`, then renames it into place, so
/// a failure never leaves a partial file.
pub fn save_png(image: &RgbaImage, path: &std::path::Path) -> Result<(), GpuError> {
    let fail = |reason: String| GpuError::Write {
        path: path.display().to_string(),
        reason,
    };
    let name = path
        .file_name()
        .ok_or_else(|| fail("the path has no file name".into()))?;
    let tmp = path.with_file_name(format!(".{}.tmp", name.to_string_lossy()));
    let result = image
        .save_with_format(&tmp, image::ImageFormat::Png)
        .map_err(|e| fail(e.to_string()))
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| fail(e.to_string())));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
