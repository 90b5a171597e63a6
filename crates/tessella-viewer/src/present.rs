//! A viewer drawn onto a presentable surface: a browser canvas (WebGPU) or a native window.
//! The surface is configured in its preferred format and viewed in that format's sRGB twin,
//! so the colours are `tessella render`'s whatever the canvas's own format.
//!
//! Where the surface allows copies into its textures, the viewer draws into a texture of its
//! own (the sRGB format) and copies that into the surface's texture: Chromium's WebGPU on
//! SwiftShader resolves multisampled sRGB into a canvas's sRGB *view* without encoding (the
//! picture comes out in linear values, darker; checked with a plain-JS page: a 4× MSAA clear of
//! 0.2 resolved into the canvas's `rgba8unorm-srgb` view reads back 51, resolved into an own
//! `rgba8unorm-srgb` texture and copied, 124). A copy moves the encoded bytes as they are.

use crate::error::ViewerError;
use crate::viewer::Viewer;
use tessella_gpu::GpuContext;

/// A surface and its configuration.
pub struct Presenter {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The viewer's own colour texture at the surface's size, copied into the surface's
    /// texture each frame; `None` where the surface takes no copies (drawn into directly).
    staging: Option<wgpu::Texture>,
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
        // A WebGPU canvas always takes COPY_DST (the spec allows any usage); natively ask.
        let copy = cfg!(target_arch = "wasm32")
            || surface
                .get_capabilities(adapter)
                .usages
                .contains(wgpu::TextureUsages::COPY_DST);
        if copy {
            config.usage |= wgpu::TextureUsages::COPY_DST;
        }
        let mut presenter = Presenter {
            surface,
            config,
            staging: None,
        };
        presenter.configure(ctx)?;
        Ok(presenter)
    }

    /// Configures the surface at the current size and, where it takes copies, makes the own
    /// colour texture of that size.
    fn configure(&mut self, ctx: &GpuContext) -> Result<(), ViewerError> {
        ctx.scoped(|| self.surface.configure(&ctx.device, &self.config))?;
        if self.config.usage.contains(wgpu::TextureUsages::COPY_DST) {
            self.staging = Some(self.make_staging(ctx)?);
        }
        Ok(())
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

    /// The own colour texture at the surface's current size.
    fn make_staging(&self, ctx: &GpuContext) -> Result<wgpu::Texture, ViewerError> {
        let size = (self.config.width, self.config.height);
        let format = self.view_format();
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let label = "viewer: frame before the surface copy";
        Ok(ctx.scoped(|| tessella_view::texture(ctx, label, size, format, 1, usage))?)
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
        if let Some(staging) = &self.staging {
            let view = staging.create_view(&Default::default());
            viewer.draw(&view, time_ms)?;
            let mut encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("viewer: copy into the surface"),
                });
            encoder.copy_texture_to_texture(
                staging.as_image_copy(),
                texture.texture.as_image_copy(),
                wgpu::Extent3d {
                    width: self.config.width,
                    height: self.config.height,
                    depth_or_array_layers: 1,
                },
            );
            ctx.submit(encoder)?;
        } else {
            let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
                format: Some(self.view_format()),
                ..Default::default()
            });
            viewer.draw(&view, time_ms)?;
        }
        ctx.queue.present(texture);
        Ok(true)
    }
}
