//! The offscreen target the pictures and benchmarks draw into: multisampled colour with
//! depth, resolved into a texture that can be read back. Drawing and reading have a blocking
//! form (the `blocking` feature) and an async one that also runs in a browser.

use crate::scene::clear_color;
use image::RgbaImage;
use tessella_gpu::{GpuContext, GpuError, TargetFormats};

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Multisampling smooths silhouettes, which is what the pictures are about.
const SAMPLES: u32 = 4;

/// A 2D texture of `size` pixels (one layer, no mipmaps): what [`Target`], the viewer's
/// frame targets and the screenshots are made of. Call it inside [`GpuContext::scoped`] to get
/// wgpu's validation errors back.
pub fn texture(
    ctx: &GpuContext,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The attachments of a multisampled pass ([`begin_pass`]).
#[derive(Clone, Copy)]
pub struct PassViews<'a> {
    /// Multisampled colour, resolved into `resolve` at the end of the pass.
    pub color: &'a wgpu::TextureView,
    /// Single-sampled colour: what the pass leaves.
    pub resolve: &'a wgpu::TextureView,
    /// Depth, of the same sample count as `color`.
    pub depth: &'a wgpu::TextureView,
}

/// Begins the pass every picture and viewer frame is drawn in: colour cleared to `background`
/// and resolved, depth cleared to 1; the multisampled colour and the depth are discarded after
/// the pass.
pub fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    views: PassViews<'_>,
    background: [u8; 4],
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: views.color,
            depth_slice: None,
            resolve_target: Some(views.resolve),
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear_color(background)),
                store: wgpu::StoreOp::Discard,
            },
        })],
        depth_stencil_attachment: Some(tessella_gpu::cleared_depth(views.depth)),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// An offscreen multisampled colour target with depth, resolved for readback.
pub struct Target {
    color: wgpu::TextureView,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth: wgpu::TextureView,
}

impl Target {
    /// The formats of this target's pass, for an [`crate::Appearance`] drawing into it.
    pub const FORMATS: TargetFormats = TargetFormats {
        color: COLOR_FORMAT,
        depth: Some(DEPTH_FORMAT),
        samples: SAMPLES,
    };

    /// Makes the textures (`size` within 1..=8192 per side).
    pub fn new(ctx: &GpuContext, size: (u32, u32)) -> Result<Target, GpuError> {
        ctx.scoped(|| Target::make(ctx, size))
    }

    fn make(ctx: &GpuContext, size: (u32, u32)) -> Target {
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = texture(ctx, "color", size, COLOR_FORMAT, SAMPLES, attach);
        let readable = attach | wgpu::TextureUsages::COPY_SRC;
        let resolve = texture(ctx, "resolve", size, COLOR_FORMAT, 1, readable);
        let depth = texture(ctx, "depth", size, DEPTH_FORMAT, SAMPLES, attach);
        Target {
            color: color.create_view(&Default::default()),
            resolve_view: resolve.create_view(&Default::default()),
            resolve,
            depth: depth.create_view(&Default::default()),
        }
    }

    /// Clears to `background`, lets `record` draw into the pass, submits and waits: any error
    /// wgpu reports for the frame is returned.
    #[cfg(feature = "blocking")]
    pub fn draw(
        &self,
        ctx: &GpuContext,
        background: [u8; 4],
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<(), GpuError> {
        ctx.submit_and_wait(self.record(ctx, background, record))
    }

    /// [`Target::draw`] without blocking the web's thread: resolves when the GPU has finished
    /// the frame (natively it waits, see [`GpuContext::work_done_async`]).
    pub async fn draw_async(
        &self,
        ctx: &GpuContext,
        background: [u8; 4],
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<(), GpuError> {
        ctx.submit(self.record(ctx, background, record))?;
        ctx.work_done_async().await
    }

    /// An encoder holding one frame: the cleared target and what `record` draws into it.
    fn record(
        &self,
        ctx: &GpuContext,
        background: [u8; 4],
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> wgpu::CommandEncoder {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = self.begin(&mut encoder, background);
            record(&mut pass);
        }
        encoder
    }

    fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        background: [u8; 4],
    ) -> wgpu::RenderPass<'e> {
        let views = PassViews {
            color: &self.color,
            resolve: &self.resolve_view,
            depth: &self.depth,
        };
        begin_pass(encoder, "draw", views, background)
    }

    /// Copies the resolved picture back.
    #[cfg(feature = "blocking")]
    pub fn read(&self, ctx: &GpuContext) -> Result<RgbaImage, GpuError> {
        read_texture(ctx, &self.resolve)
    }

    /// [`Target::read`] without blocking the web's thread.
    pub async fn read_async(&self, ctx: &GpuContext) -> Result<RgbaImage, GpuError> {
        let (staging, padded) = record_copy(ctx, &self.resolve)?;
        let bytes = ctx.map_and_copy_driven_async(&staging).await?;
        unpad(&self.resolve, padded, &bytes)
    }
}

/// Copies a single-sampled RGBA8 texture (`COPY_SRC` usage) back to the CPU, waiting for it.
#[cfg(feature = "blocking")]
pub fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<RgbaImage, GpuError> {
    let (staging, padded) = record_copy(ctx, texture)?;
    let bytes = ctx.map_and_copy(&staging)?;
    unpad(texture, padded, &bytes)
}

/// Submits a copy of `texture` into a new staging buffer with rows padded to 256 bytes;
/// returns the buffer and the padded row length.
fn record_copy(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<(wgpu::Buffer, u64), GpuError> {
    let (w, h) = (texture.width(), texture.height());
    let padded = (w as u64 * 4).div_ceil(256) * 256;
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("picture"),
        size: padded * h as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded as u32),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    ctx.submit(encoder)?;
    Ok((staging, padded))
}

/// The picture of `texture` from its padded rows.
fn unpad(texture: &wgpu::Texture, padded: u64, bytes: &[u8]) -> Result<RgbaImage, GpuError> {
    let (w, h) = (texture.width(), texture.height());
    let row = w as usize * 4;
    let mut pixels = Vec::with_capacity(row * h as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        pixels.extend_from_slice(&bytes[start..start + row]);
    }
    RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| GpuError::Readback("picture size mismatch".into()))
}
