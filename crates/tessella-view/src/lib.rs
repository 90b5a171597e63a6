//! # tessella-view
//!
//! Pictures of refined surfaces, on top of tessella-gpu's [`PatternRenderer`], shaded by this
//! crate's [`Appearance`] (light, colours, a field's colormap, the wireframe): an offscreen
//! target with readback ([`render`], [`render_compare`] with labelled panels, [`save_png`]),
//! a camera that frames the mesh, a deforming-mesh animation ([`animate::render_twist`]: one
//! [`tessella_core::refine::Plan`], per frame `Plan::update` + `PatternRenderer::update`, so
//! only the control nets are uploaded). Everything here is for the CLI, examples and tests; an
//! engine uses tessella-gpu directly. The GPU benchmarks that draw with it are a crate of their
//! own, tessella-bench.
//!
//! ```no_run
//! use tessella_core::{samples, RefineOptions, Scheme};
//! use tessella_gpu::{AdapterChoice, GpuContext};
//! use tessella_view::{render, save_png, RenderOptions};
//! let ctx = GpuContext::new(AdapterChoice::Auto)?;
//! let picture = render(&ctx, &samples::icosphere(1), &RefineOptions::new(Scheme::Pn, 8),
//!                      &RenderOptions::default())?;
//! save_png(&picture, std::path::Path::new("pn.png"))?;
//! # Ok::<(), tessella_gpu::GpuError>(())
//! ```

//!
//! The view itself ([`RenderOptions`], [`scene_uniforms`], [`lod_camera`], [`panel_widths`]) is
//! in `scene.rs` and never blocks, so it builds for the web (the interactive viewer,
//! `tessella-viewer`, uses this very camera); the pictures and animations wait for the GPU and
//! are the default `blocking` feature.
//!
//! [`texture`] and [`begin_pass`] (in `target.rs`, beside the offscreen [`Target`]; neither
//! blocks) make the textures and the cleared multisampled pass that the pictures, the viewer's
//! frames and `tessella view`'s screenshots are drawn with.

#[cfg(feature = "blocking")]
pub mod animate;
mod appearance;
mod camera;
pub mod colormap;
pub mod font;
#[cfg(feature = "blocking")]
mod render;
mod scene;
mod target;

pub use appearance::{Appearance, FieldNets, RenderUniforms, Shaded};
pub use camera::{frame_points, Framing, FOV_Y_DEGREES};
pub use colormap::{Colormap, FieldColors};
pub use image::RgbaImage;
#[cfg(feature = "blocking")]
pub use render::{render, render_compare};
pub use scene::{clear_color, lod_camera, panel_widths, scene_uniforms, RenderOptions};
#[cfg(feature = "blocking")]
pub use target::read_texture;
pub use target::{begin_pass, texture, PassViews, Target};
pub use tessella_gpu::{GpuError, PatternRenderer};

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
        // Best effort: the temporary file may not exist; the error reported is `result`'s.
        std::fs::remove_file(&tmp).ok();
    }
    result
}
