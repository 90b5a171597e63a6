//! Offscreen pictures: a multisampled target with readback, drawn by tessella-gpu's
//! [`PatternRenderer`], framed by [`crate::scene`]'s camera. Blocks (the `blocking` feature).

use crate::colormap;
use crate::scene::{clear_color, panel_widths, scene_uniforms, RenderOptions};
use image::RgbaImage;
use tessella_core::refine::Plan;
use tessella_core::{Mesh, RefineOptions};
use tessella_gpu::{GpuContext, GpuError, PatternRenderer, TargetFormats};

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Multisampling smooths silhouettes, which is what the pictures are about.
const SAMPLES: u32 = 4;

/// Renders `mesh` refined with `refine` (scheme, level, normals; `weld` does not matter here).
///
/// ```no_run
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gpu::{AdapterChoice, GpuContext};
/// use tessella_view::{render, RenderOptions};
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let picture = render(&ctx, &samples::icosphere(1), &RefineOptions::new(Scheme::Pn, 16),
///                      &RenderOptions { size: (256, 256), ..Default::default() })?;
/// # Ok::<(), tessella_gpu::GpuError>(())
/// ```
pub fn render(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    options.validate()?;
    let Some(field) = &options.field else {
        return render_view(ctx, mesh, refine, options);
    };
    let bar = colormap::color_bar(field, options.size.1, options.background);
    let view = RenderOptions {
        size: (view_width(options, bar.width())?, options.size.1),
        ..options.clone()
    };
    Ok(colormap::with_bar(
        &render_view(ctx, mesh, refine, &view)?,
        &bar,
    ))
}

/// The width left for the surface beside a colour bar `bar` pixels wide.
fn view_width(options: &RenderOptions, bar: u32) -> Result<u32, GpuError> {
    options
        .size
        .0
        .checked_sub(bar)
        .filter(|&w| w > 0)
        .ok_or_else(|| {
            GpuError::BadOption(format!(
                "a picture {} pixels wide has no room beside a {bar}-pixel colour bar",
                options.size.0
            ))
        })
}

/// The picture of the surface alone (a field colours it, the bar is drawn by the caller).
fn render_view(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    options.validate()?;
    let plan = Plan::new(mesh, refine)?;
    let frame = plan.frame(mesh)?;
    let mut renderer =
        PatternRenderer::new(ctx, &plan, &frame, &Target::FORMATS, &options.displacement)?;
    if let Some(field) = &options.field {
        let nets = tessella_core::fields::face_nets(mesh, &field.name, &field.values)
            .map_err(|e| GpuError::BadOption(e.to_string()))?;
        let colors = field.colormap.samples_f32();
        renderer.set_field(Some((&nets, &colors, field.resolved_range())))?;
    }
    let target = Target::new(ctx, options.size)?;
    renderer.set_uniforms(&scene_uniforms(
        mesh,
        options,
        renderer.displacement_reach(),
    ));
    target.draw(ctx, options.background, |pass| renderer.draw(pass))?;
    target.read(ctx)
}

/// Renders one panel per `(label, options)` side by side, with the labels drawn on top.
/// `options.size` is the size of the whole picture: the panels share its width (less the
/// separators), the first ones one pixel wider when it does not divide evenly. A width too
/// small for one pixel per panel is an error.
pub fn render_compare(
    ctx: &GpuContext,
    mesh: &Mesh,
    panels: &[(String, RefineOptions)],
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    if panels.is_empty() {
        return Err(GpuError::BadOption(
            "nothing to compare: give at least one panel".into(),
        ));
    }
    options.validate()?;
    let bar = options
        .field
        .as_ref()
        .map(|f| colormap::color_bar(f, options.size.1, options.background));
    let total = match &bar {
        Some(bar) => view_width(options, bar.width())?,
        None => options.size.0,
    };
    let widths = panel_widths(total, panels.len()).ok_or_else(|| {
        GpuError::BadOption(format!(
            "a picture {} pixels wide has no room for {} panels",
            options.size.0,
            panels.len()
        ))
    })?;
    let pictures = panels
        .iter()
        .zip(&widths)
        .map(|((_, refine), &w)| {
            let panel = RenderOptions {
                size: (w, options.size.1),
                ..options.clone()
            };
            render_view(ctx, mesh, refine, &panel)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let labels: Vec<&str> = panels.iter().map(|(l, _)| l.as_str()).collect();
    let row = crate::font::side_by_side(&pictures, &labels);
    Ok(match &bar {
        Some(bar) => colormap::with_bar(&row, bar),
        None => row,
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
    /// What [`PatternRenderer`]s drawing into this target are made for.
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
        let texture = |label, format, samples, usage| {
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
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = texture("color", COLOR_FORMAT, SAMPLES, attach);
        let resolve = texture(
            "resolve",
            COLOR_FORMAT,
            1,
            attach | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = texture("depth", DEPTH_FORMAT, SAMPLES, attach);
        Target {
            color: color.create_view(&Default::default()),
            resolve_view: resolve.create_view(&Default::default()),
            resolve,
            depth: depth.create_view(&Default::default()),
        }
    }

    /// Clears to `background`, lets `record` draw into the pass, submits and waits: any error
    /// wgpu reports for the frame is returned.
    pub fn draw(
        &self,
        ctx: &GpuContext,
        background: [u8; 4],
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<(), GpuError> {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = self.begin(&mut encoder, background);
            record(&mut pass);
        }
        ctx.submit_and_wait(encoder)
    }

    fn begin<'e>(
        &'e self,
        encoder: &'e mut wgpu::CommandEncoder,
        background: [u8; 4],
    ) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("draw"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.color,
                depth_slice: None,
                resolve_target: Some(&self.resolve_view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear_color(background)),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Copies the resolved picture back.
    pub fn read(&self, ctx: &GpuContext) -> Result<RgbaImage, GpuError> {
        read_texture(ctx, &self.resolve)
    }
}

/// Copies a single-sampled RGBA8 texture (`COPY_SRC` usage) back to the CPU, waiting for it.
pub fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<RgbaImage, GpuError> {
    let (w, h) = (texture.width(), texture.height());
    let row = w as u64 * 4;
    let padded = row.div_ceil(256) * 256;
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
    ctx.submit_and_wait(encoder)?;
    let bytes = ctx.map_and_copy(&staging)?;
    let mut pixels = Vec::with_capacity((row * h as u64) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        pixels.extend_from_slice(&bytes[start..start + row as usize]);
    }
    RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| GpuError::Readback("picture size mismatch".into()))
}
