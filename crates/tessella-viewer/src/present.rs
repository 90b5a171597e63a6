//! A viewer drawn onto a presentable surface: a browser canvas (WebGPU) or a native window.
//! The surface is configured in its preferred format and viewed in that format's sRGB twin,
//! so the colours are `tessella render`'s whatever the canvas's own format.

use crate::error::ViewerError;
use crate::viewer::Viewer;
use tessella_gpu::GpuContext;

/// A surface and its configuration.
pub struct Presenter {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
}

impl std::fmt::Debug for Presenter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Presenter")
            .field("format", &self.config.format)
            .field("size", &(self.config.width, self.config.height))
            .finish()
    }
}

impl Presenter {
    /// Configures `surface` (made from the instance `ctx` was opened on) at `width × height`.
    pub fn new(
        ctx: &GpuContext,
        surface: wgpu::Surface<'static>,
        width: u32,
        height: u32,
    ) -> Result<Presenter, ViewerError> {
        let adapter = ctx.adapter().ok_or_else(|| {
            ViewerError::Refused(
                "the device's adapter is unknown: open it with GpuContext::for_surface_async"
                    .into(),
            )
        })?;
        let mut config = surface
            .get_default_config(adapter, width.max(1), height.max(1))
            .ok_or_else(|| {
                ViewerError::Refused(format!(
                    "the adapter {} cannot present to this surface",
                    ctx.adapter_label()
                ))
            })?;
        config.view_formats = vec![config.format.add_srgb_suffix()];
        let presenter = Presenter { surface, config };
        presenter.configure(ctx)?;
        Ok(presenter)
    }

    fn configure(&self, ctx: &GpuContext) -> Result<(), ViewerError> {
        Ok(ctx.scoped(|| self.surface.configure(&ctx.device, &self.config))?)
    }

    /// The format the viewer draws in: the surface's, as sRGB.
    pub fn view_format(&self) -> wgpu::TextureFormat {
        self.config.format.add_srgb_suffix()
    }

    /// Reconfigures the surface for a new size.
    pub fn resize(&mut self, ctx: &GpuContext, width: u32, height: u32) -> Result<(), ViewerError> {
        self.config.width = width.max(1);
        self.config.height = height.max(1);
        self.configure(ctx)
    }

    /// Draws `viewer`'s frame at `time_ms` into the surface's next texture and presents it.
    /// `Ok(false)` when the surface had no texture to give this time (occluded, timed out,
    /// outdated: reconfigured for the next frame).
    pub fn frame(
        &mut self,
        ctx: &GpuContext,
        viewer: &mut Viewer,
        time_ms: f64,
    ) -> Result<bool, ViewerError> {
        use wgpu::CurrentSurfaceTexture as Current;
        let texture = match self.surface.get_current_texture() {
            Current::Success(t) | Current::Suboptimal(t) => t,
            Current::Timeout | Current::Occluded => return Ok(false),
            Current::Outdated => {
                self.configure(ctx)?;
                return Ok(false);
            }
            Current::Lost => {
                return Err(ViewerError::Refused(
                    "the drawing surface was lost; reload the page or reopen the window".into(),
                ))
            }
            Current::Validation => {
                // The error itself went to the device's error handler: report it.
                ctx.check()?;
                return Err(ViewerError::Refused(
                    "the drawing surface refused to give a texture".into(),
                ));
            }
        };
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format()),
            ..Default::default()
        });
        viewer.draw(&view, time_ms)?;
        ctx.queue.present(texture);
        Ok(true)
    }
}
