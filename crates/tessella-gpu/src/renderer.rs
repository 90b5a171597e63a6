//! The render path of the GMR paper: one refinement pattern per level, uploaded once; the
//! coarse triangles' control nets in a storage buffer; one instanced draw (instance = coarse
//! triangle) whose vertex shader evaluates position and normal. Renders offscreen and reads
//! the picture back.

use crate::camera::{bounding_sphere, Camera};
use crate::context::GpuContext;
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::gpu_types::RenderUniforms;
use crate::patch::{self, PatchBuffers};
use image::RgbaImage;
use tessella_core::scheme::build_nets;
use tessella_core::{Mesh, PatchNets, Pattern, RefineError, RefineOptions, Stencil};

pub(crate) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
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
        }
    }
}

impl RenderOptions {
    fn validate(&self) -> Result<(), GpuError> {
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
/// use tessella_gpu::{render, AdapterChoice, GpuContext, RenderOptions};
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let picture = render(&ctx, &samples::icosphere(1), &RefineOptions::new(Scheme::Pn, 16),
///                      &RenderOptions { size: (256, 256), ..Default::default() })?;
/// picture.save("pn.png").unwrap();
/// # Ok::<(), tessella_gpu::GpuError>(())
/// ```
pub fn render(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    options.validate()?;
    let scene = PatternScene::new(ctx, mesh, refine, &options.displacement)?;
    let target = Target::new(ctx, options.size);
    let uniforms = scene_uniforms(mesh, options, refine.level, &scene.displacement_reach);
    scene.draw(ctx, &target, &uniforms, options.background);
    ctx.check()?;
    target.read(ctx)
}

/// Renders one panel per `(label, options)` side by side, with the labels drawn on top.
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
    let pictures = panels
        .iter()
        .map(|(_, refine)| render(ctx, mesh, refine, options))
        .collect::<Result<Vec<_>, _>>()?;
    let labels: Vec<&str> = panels.iter().map(|(l, _)| l.as_str()).collect();
    Ok(crate::font::side_by_side(&pictures, &labels))
}

/// Uniforms for a framed view of `mesh`.
pub(crate) fn scene_uniforms(
    mesh: &Mesh,
    options: &RenderOptions,
    level: u32,
    reach: &f32,
) -> RenderUniforms {
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
        wire_color: [0.0, 0.0, 0.004, 0.75],
        flags: [
            options.wireframe as u32,
            level,
            options.displacement.is_some() as u32,
            0,
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

/// The compiled render pipelines, built once per [`GpuContext`].
pub(crate) struct Pipelines {
    pub patch_layout: wgpu::BindGroupLayout,
    pub render_layout: wgpu::BindGroupLayout,
    pub pattern: wgpu::RenderPipeline,
    pub fixed: wgpu::RenderPipeline,
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Pipelines {
        let patch_layout = patch::layout(ctx, wgpu::ShaderStages::VERTEX);
        let render_layout = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("render"),
                entries: &[
                    wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::VERTEX,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Storage { read_only: true },
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                ],
            });
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("render.wgsl"),
                source: wgpu::ShaderSource::Wgsl(
                    patch::shader_source(include_str!("shaders/render.wgsl")).into(),
                ),
            });
        let pattern_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("pattern"),
                bind_group_layouts: &[Some(&patch_layout), Some(&render_layout)],
                immediate_size: 0,
            });
        let fixed_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("static"),
                bind_group_layouts: &[None, Some(&render_layout)],
                immediate_size: 0,
            });
        let pattern_attrs = wgpu::vertex_attr_array![0 => Uint32];
        let fixed_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let make =
            |layout: &wgpu::PipelineLayout, entry: &str, buffer: wgpu::VertexBufferLayout| {
                ctx.device
                    .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                        label: Some(entry),
                        layout: Some(layout),
                        vertex: wgpu::VertexState {
                            module: &module,
                            entry_point: Some(entry),
                            compilation_options: Default::default(),
                            buffers: &[Some(buffer)],
                        },
                        primitive: wgpu::PrimitiveState {
                            topology: wgpu::PrimitiveTopology::TriangleList,
                            front_face: wgpu::FrontFace::Ccw,
                            cull_mode: None,
                            ..Default::default()
                        },
                        depth_stencil: Some(wgpu::DepthStencilState {
                            format: DEPTH_FORMAT,
                            depth_write_enabled: Some(true),
                            depth_compare: Some(wgpu::CompareFunction::Less),
                            stencil: Default::default(),
                            bias: Default::default(),
                        }),
                        multisample: wgpu::MultisampleState {
                            count: SAMPLES,
                            ..Default::default()
                        },
                        fragment: Some(wgpu::FragmentState {
                            module: &module,
                            entry_point: Some("fs_main"),
                            compilation_options: Default::default(),
                            targets: &[Some(COLOR_FORMAT.into())],
                        }),
                        multiview_mask: None,
                        cache: None,
                    })
            };
        Pipelines {
            pattern: make(
                &pattern_layout,
                "vs_pattern",
                wgpu::VertexBufferLayout {
                    array_stride: 4,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &pattern_attrs,
                },
            ),
            fixed: make(
                &fixed_layout,
                "vs_static",
                wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &fixed_attrs,
                },
            ),
            patch_layout,
            render_layout,
        }
    }
}

/// Builds the control nets for rendering (no output layout needed).
pub(crate) fn nets_for(
    mesh: &Mesh,
    refine: &RefineOptions,
) -> Result<(Stencil, PatchNets), GpuError> {
    if refine.level == 0 {
        return Err(RefineError::LevelZero.into());
    }
    let topology = mesh.topology();
    let nets = build_nets(mesh, Some(&topology), &refine.scheme, refine.normal_mode())?;
    let stencil = Stencil::new(&Pattern::uniform(refine.level), refine.scheme.basis());
    Ok((stencil, nets))
}

/// A mesh ready to draw with the pattern: nets + pattern buffers.
pub(crate) struct PatternScene {
    pub patches: PatchBuffers,
    patch_group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
    render_group: wgpu::BindGroup,
    /// The pattern: one `u32` stencil row per point, and its triangles.
    pattern_vertices: wgpu::Buffer,
    pattern_indices: wgpu::Buffer,
    pattern_index_count: u32,
    face_uvs: wgpu::Buffer,
    /// How far displacement can move a point (for framing).
    pub displacement_reach: f32,
}

impl PatternScene {
    pub fn new(
        ctx: &GpuContext,
        mesh: &Mesh,
        refine: &RefineOptions,
        displacement: &Displacement,
    ) -> Result<PatternScene, GpuError> {
        displacement.validate(mesh.uvs().is_some())?;
        let (stencil, nets) = nets_for(mesh, refine)?;
        let pipelines = ctx.render_pipelines();
        let patches = PatchBuffers::new(ctx, &stencil, &nets, displacement)?;
        let patch_group = patches.bind_group(ctx, &pipelines.patch_layout);
        let pattern = Pattern::uniform(refine.level);
        let rows: Vec<u32> = (0..pattern.points.len() as u32).collect();
        let indices: Vec<u32> = pattern.triangles.iter().flatten().copied().collect();
        let init = |label, contents: &[u8], usage| ctx.buffer_init(label, contents, usage);
        let pattern_vertices = init(
            "pattern vertices",
            bytemuck::cast_slice(&rows),
            wgpu::BufferUsages::VERTEX,
        );
        let pattern_indices = init(
            "pattern indices",
            bytemuck::cast_slice(&indices),
            wgpu::BufferUsages::INDEX,
        );
        let face_uvs: Vec<f32> = match mesh.uvs() {
            Some(uv) => mesh
                .triangles()
                .iter()
                .flat_map(|t| t.map(|v| uv[v as usize]))
                .flatten()
                .collect(),
            None => vec![0.0],
        };
        let face_uvs = ctx.storage_buffer(
            "face uvs",
            bytemuck::cast_slice(&face_uvs),
            wgpu::BufferUsages::empty(),
        );
        let uniforms = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render uniforms"),
            size: std::mem::size_of::<RenderUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let render_group = render_group(ctx, &pipelines.render_layout, &uniforms, &face_uvs);
        let displacement_reach = match displacement {
            Displacement::None => 0.0,
            Displacement::Sine { amplitude, .. }
            | Displacement::Perlin { amplitude, .. }
            | Displacement::HeightMap { amplitude, .. } => amplitude.abs(),
        };
        Ok(PatternScene {
            patches,
            patch_group,
            uniforms,
            render_group,
            pattern_vertices,
            pattern_indices,
            pattern_index_count: indices.len() as u32,
            face_uvs,
            displacement_reach,
        })
    }

    /// Bytes this scene keeps on the GPU (nets, stencil, pattern).
    pub fn byte_size(&self) -> u64 {
        self.patches.byte_size()
            + self.pattern_vertices.size()
            + self.pattern_indices.size()
            + self.face_uvs.size()
            + self.uniforms.size()
    }

    /// Pattern vertices stored on the GPU.
    pub fn pattern_vertex_count(&self) -> u64 {
        self.pattern_vertices.size() / 4
    }

    /// Draws into `target` (one instanced draw) and waits for the GPU.
    pub fn draw(
        &self,
        ctx: &GpuContext,
        target: &Target,
        uniforms: &RenderUniforms,
        background: [u8; 4],
    ) {
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = target.begin(&mut encoder, background);
            pass.set_pipeline(&ctx.render_pipelines().pattern);
            pass.set_bind_group(0, &self.patch_group, &[]);
            pass.set_bind_group(1, &self.render_group, &[]);
            pass.set_vertex_buffer(0, self.pattern_vertices.slice(..));
            pass.set_index_buffer(self.pattern_indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.pattern_index_count, 0, 0..self.patches.face_count);
        }
        // Errors surface through ctx.check() at the caller.
        let _ = ctx.submit_and_wait(encoder);
    }
}

pub(crate) fn render_group(
    ctx: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    face_uvs: &wgpu::Buffer,
) -> wgpu::BindGroup {
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("render"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: face_uvs.as_entire_binding(),
            },
        ],
    })
}

/// An offscreen multisampled colour target with depth, resolved for readback.
pub(crate) struct Target {
    color: wgpu::TextureView,
    resolve: wgpu::Texture,
    resolve_view: wgpu::TextureView,
    depth: wgpu::TextureView,
    size: (u32, u32),
}

impl Target {
    pub fn new(ctx: &GpuContext, size: (u32, u32)) -> Target {
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

    pub fn begin<'e>(
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
