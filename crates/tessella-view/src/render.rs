//! Offscreen pictures: a multisampled target with readback, drawn by tessella-gpu's
//! [`PatternRenderer`], framed by the camera module.

use crate::camera::{bounding_sphere, Camera};
use crate::colormap::{self, FieldColors};
use image::RgbaImage;
use tessella_core::refine::Plan;
use tessella_core::{Mesh, RefineOptions};
use tessella_gpu::{
    Displacement, GpuContext, GpuError, PatternRenderer, RenderUniforms, TargetFormats,
};

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Multisampling smooths silhouettes, which is what the pictures are about.
const SAMPLES: u32 = 4;
/// Largest picture side.
const MAX_SIDE: u32 = 8192;

/// How to draw a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Orbit about the vertical axis, degrees (0 looks along -Z).
    pub yaw: f32,
    /// Elevation of the eye, degrees.
    pub pitch: f32,
    /// 1 frames the mesh's bounding sphere; larger values move closer.
    pub zoom: f32,
    /// Overlay the refinement pattern's edges.
    pub wireframe: bool,
    /// Clear colour, sRGB with alpha.
    pub background: [u8; 4],
    /// Surface colour, sRGB.
    pub color: [u8; 3],
    /// Displacement applied in the vertex shader.
    pub displacement: Displacement,
    /// Paint back faces in this sRGB colour instead of shading them: on a closed surface they
    /// show only through cracks (a crack finder).
    pub back_color: Option<[u8; 3]>,
    /// Colour the surface by this per-vertex field (instead of `color`), with a colour bar on
    /// the right (its width taken from `size`).
    pub field: Option<FieldColors>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            size: (512, 512),
            yaw: 30.0,
            pitch: 20.0,
            zoom: 1.0,
            wireframe: false,
            background: [255, 255, 255, 255],
            color: [120, 160, 215],
            displacement: Displacement::None,
            back_color: None,
            field: None,
        }
    }
}

impl RenderOptions {
    /// Checks size, zoom and angles.
    pub fn validate(&self) -> Result<(), GpuError> {
        let (w, h) = self.size;
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
            return Err(GpuError::BadOption(format!(
                "picture size {w}x{h} must be within 1x1 ..= {MAX_SIDE}x{MAX_SIDE}"
            )));
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            return Err(GpuError::BadOption(format!(
                "zoom must be positive, got {}",
                self.zoom
            )));
        }
        if !self.yaw.is_finite() || !self.pitch.is_finite() {
            return Err(GpuError::BadOption("yaw and pitch must be finite".into()));
        }
        Ok(())
    }
}

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

/// Widths of `n` panels filling `total` pixels with [`crate::font::GAP`]-pixel separators;
/// `None` when a panel would be narrower than one pixel.
pub fn panel_widths(total: u32, n: usize) -> Option<Vec<u32>> {
    let n = u32::try_from(n).ok().filter(|&n| n > 0)?;
    let room = total.checked_sub((n - 1).checked_mul(crate::font::GAP)?)?;
    let (base, extra) = (room / n, room % n);
    (base > 0).then(|| (0..n).map(|i| base + u32::from(i < extra)).collect())
}

/// The camera [`render`] views `mesh` with, for the view-dependent LOD functions
/// (`Lod::Screen`, `Lod::Distance`): levels then follow what this very picture shows.
pub fn lod_camera(mesh: &Mesh, options: &RenderOptions) -> tessella_core::refine::Camera {
    let (center, radius) = bounding_sphere(mesh.positions());
    let (w, h) = options.size;
    let cam = Camera::framing(
        center,
        radius * 1.2,
        options.yaw,
        options.pitch,
        options.zoom,
        w.max(1) as f32 / h.max(1) as f32,
    );
    tessella_core::refine::Camera {
        eye: cam.eye.into(),
        target: center.into(),
        fov_y_deg: crate::camera::FOV_Y_DEGREES,
    }
}

/// Uniforms for a view of `mesh` framed by its bounding sphere grown by `reach` (how far
/// displacement can move a point).
pub fn scene_uniforms(mesh: &Mesh, options: &RenderOptions, reach: f32) -> RenderUniforms {
    let (center, radius) = bounding_sphere(mesh.positions());
    // Curved patches bulge past the coarse hull, displacement further.
    let radius = radius * 1.2 + reach;
    let (w, h) = options.size;
    let cam = Camera::framing(
        center,
        radius,
        options.yaw,
        options.pitch,
        options.zoom,
        w as f32 / h as f32,
    );
    let c = options.color.map(srgb_to_linear);
    RenderUniforms {
        view_proj: cam.view_proj.to_cols_array_2d(),
        eye: cam.eye.extend(1.0).into(),
        light_dir: cam.light_dir.extend(0.0).into(),
        base_color: [c[0], c[1], c[2], 1.0],
        wire_color: [0.004, 0.006, 0.015, 1.0],
        flags: [
            options.wireframe as u32,
            0,
            options.displacement.is_some() as u32,
            options.back_color.map_or(0, |[r, g, b]| {
                1 << 24 | r as u32 | (g as u32) << 8 | (b as u32) << 16
            }),
        ],
    }
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// An offscreen multisampled colour target with depth, resolved for readback.
pub struct Target {
    color: wgpu::TextureView,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth: wgpu::TextureView,
    size: (u32, u32),
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
            size,
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
        let [r, g, b] =
            [background[0], background[1], background[2]].map(|c| srgb_to_linear(c) as f64);
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("draw"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.color,
                depth_slice: None,
                resolve_target: Some(&self.resolve_view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r,
                        g,
                        b,
                        a: background[3] as f64 / 255.0,
                    }),
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
        let (w, h) = self.size;
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
            self.resolve.as_image_copy(),
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
}
