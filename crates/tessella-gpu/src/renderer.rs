//! The render path of the GMR paper: one refinement pattern per level, uploaded once; the
//! coarse triangles' control nets in a storage buffer, re-uploaded per frame; one instanced
//! draw (instance = coarse triangle) whose vertex shader evaluates position and normal.
//!
//! [`PatternRenderer`] records into the caller's render pass; the caller owns the targets, the
//! encoder and the submission (tessella-view's offscreen pictures are one such caller).

use crate::context::GpuContext;
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::gpu_types::normal_mode_code;
use crate::patch::{self, PatchBuffers};
use crate::shading::Shading;
use tessella_core::displace::face_frames;
use tessella_core::refine::{Frame, Plan};
use tessella_core::NormalMode;

/// Storage buffers the pattern renderer binds in the vertex stage: the patch's five and its two
/// draw tables, all in group 0. A shading may bind what the device allows beyond them (one under
/// WebGPU's default of eight).
pub const PATTERN_VERTEX_STORAGE_BUFFERS: u32 = 7;

/// The render pipelines of one kind of renderer and shading, shared through the context's cache.
#[derive(Clone)]
struct Pipelines {
    /// Group 0: the patch, then the instance faces (binding 7) and face UVs (binding 8).
    patch_layout: wgpu::BindGroupLayout,
    pattern: wgpu::RenderPipeline,
    fixed: wgpu::RenderPipeline,
}

impl Pipelines {
    fn new(
        ctx: &GpuContext,
        shading: &Shading,
        normal_mode: NormalMode,
        displacement: &Displacement,
    ) -> Pipelines {
        let patch_layout = patch::layout(ctx, wgpu::ShaderStages::VERTEX, 2);
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("render.wgsl"),
                source: wgpu::ShaderSource::Wgsl(
                    shading
                        .append_to(&patch::shader_source(
                            include_str!("shaders/render.wgsl"),
                            normal_mode,
                            displacement,
                            None,
                        ))
                        .into(),
                ),
            });
        let pattern_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("pattern"),
                bind_group_layouts: &[Some(&patch_layout), Some(shading.layout)],
                immediate_size: 0,
            });
        let fixed_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("static"),
                bind_group_layouts: &[None, Some(shading.layout)],
                immediate_size: 0,
            });
        let fixed_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        Pipelines {
            pattern: shading.pipeline(
                ctx,
                &module,
                &pattern_layout,
                "tessella_vs_pattern",
                CODE_VERTICES,
            ),
            fixed: shading.pipeline(
                ctx,
                &module,
                &fixed_layout,
                "tessella_vs_static",
                wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &fixed_attrs,
                },
            ),
            patch_layout,
        }
    }
}

/// A vertex buffer of one `u32` per vertex (a stencil row or a point code, corner bits on top).
pub(crate) const CODE_VERTICES: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 4,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &[wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Uint32,
        offset: 0,
        shader_location: 0,
    }],
};

/// The buffers one instanced draw reads, under `labels`: `vertices` (a vertex buffer),
/// `indices` (an index buffer) and `wire` (the unrolled triangles' vertex buffer), in that
/// order; the pattern renderer's and the adaptive renderer's.
pub(crate) fn draw_buffers(
    ctx: &GpuContext,
    labels: [&str; 3],
    [vertices, indices, wire]: [&[u8]; 3],
) -> [wgpu::Buffer; 3] {
    use wgpu::BufferUsages as U;
    [
        ctx.buffer_init(labels[0], vertices, U::VERTEX),
        ctx.buffer_init(labels[1], indices, U::INDEX),
        ctx.buffer_init(labels[2], wire, U::VERTEX),
    ]
}

/// Draws a plan's frames with the refinement pattern (GMR section 3.2): the pattern and the
/// stencil are uploaded once, [`PatternRenderer::update`] uploads a frame's control nets, and
/// [`PatternRenderer::draw`] records one instanced draw per pattern into the caller's render
/// pass, shaded by the caller's [`Shading`] with the caller's bind group 1.
///
/// ```no_run
/// # fn demo(ctx: &tessella_gpu::GpuContext, view: &wgpu::TextureView,
/// #         shading_wgsl: &str, shading_layout: &wgpu::BindGroupLayout,
/// #         shading_group: &wgpu::BindGroup) -> Result<(), tessella_gpu::GpuError> {
/// use tessella_core::refine::Plan;
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gpu::{Displacement, PatternRenderer, Shading, TargetFormats};
/// let mesh = samples::icosphere(1);
/// let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 16))?;
/// let frame = plan.frame(&mesh)?;
/// let shading = Shading {
///     wgsl: shading_wgsl,
///     layout: shading_layout,
///     formats: TargetFormats {
///         color: wgpu::TextureFormat::Rgba8UnormSrgb,
///         depth: None,
///         samples: 1,
///     },
/// };
/// let renderer = PatternRenderer::new(ctx, &plan, &frame, &shading, &Displacement::None)?;
/// let mut encoder = ctx.device.create_command_encoder(&Default::default());
/// {
///     let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
///         color_attachments: &[Some(wgpu::RenderPassColorAttachment {
///             view,
///             depth_slice: None,
///             resolve_target: None,
///             ops: wgpu::Operations::default(),
///         })],
///         ..Default::default()
///     });
///     renderer.draw(&mut pass, shading_group);
/// }
/// ctx.submit_and_wait(encoder)?;
/// # Ok(()) }
/// ```
pub struct PatternRenderer {
    ctx: GpuContext,
    pipelines: Pipelines,
    /// Coarse triangles and basis size the renderer was made for.
    shape: (usize, usize),
    normal_mode: NormalMode,
    level: u32,
    patches: PatchBuffers,
    /// Group 0: the patch, the instance faces and the face UVs.
    patch_group: wgpu::BindGroup,
    /// The patterns: one `u32` stencil row per point, and their triangles, one pattern after
    /// the other (one for a uniform plan, one per distinct tile of an adaptive one).
    pattern_vertices: wgpu::Buffer,
    pattern_indices: wgpu::Buffer,
    /// Per pattern: its index range and the instances (coarse faces) drawn with it.
    draws: Vec<TileDraw>,
    /// Instance → coarse face (faces grouped by pattern).
    instance_faces: wgpu::Buffer,
    /// The pattern's triangles unrolled: three `row | corner << 30` each.
    wire_vertices: wgpu::Buffer,
    face_uvs: wgpu::Buffer,
    displacement_reach: f32,
    /// The plan's position ids, for the displacement's per-frame face records; `None` without
    /// displacement.
    position_ids: Option<Vec<u32>>,
}

impl std::fmt::Debug for PatternRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PatternRenderer")
            .field("faces", &self.shape.0)
            .field("level", &self.level)
            .finish()
    }
}

impl PatternRenderer {
    /// Compiles the pipelines for `shading` and uploads the plan's pattern and stencil and the
    /// first frame's nets (and its UVs, for height maps).
    pub fn new(
        ctx: &GpuContext,
        plan: &Plan,
        frame: &Frame,
        shading: &Shading,
        displacement: &Displacement,
    ) -> Result<PatternRenderer, GpuError> {
        plan.check_frame(frame)?;
        ctx.check_storage_buffers(
            "the pattern renderer",
            "vertex",
            PATTERN_VERTEX_STORAGE_BUFFERS,
        )?;
        let mesh = frame.mesh();
        displacement.validate(mesh.uvs().is_some())?;
        let tiles = Tiles::new(plan)?;
        let face_uvs: Vec<f32> = match mesh.uvs() {
            Some(uv) => mesh
                .triangles()
                .iter()
                .flat_map(|t| t.map(|v| uv[v as usize]))
                .flatten()
                .collect(),
            None => vec![0.0],
        };
        ctx.scoped(|| {
            let key = format!(
                "pattern|{}|{}|{}",
                shading.cache_key(),
                normal_mode_code(plan.normal_mode()),
                crate::displace::kind_code(displacement)
            );
            let pipelines = ctx.pipelines(&key, || {
                Pipelines::new(ctx, shading, plan.normal_mode(), displacement)
            })?;
            let edges = crate::canonical::edge_table(
                plan.options().scheme.basis(),
                &tiles.patterns,
                &plan
                    .tiling()
                    .map_or(vec![], |t| t.tiles.iter().map(|t| t.morph).collect()),
                plan.triangles(),
                &plan.topology().position_ids,
            );
            let patches = PatchBuffers::new(
                ctx,
                &tiles.weights,
                frame.nets(),
                displacement,
                &edges,
                false,
            )?;
            let position_ids = patches
                .displaced()
                .then(|| plan.topology().position_ids.clone());
            if let Some(ids) = &position_ids {
                patches.update_displace_faces(ctx, &face_frames(mesh, ids));
            }
            let [pattern_vertices, pattern_indices, wire_vertices] = draw_buffers(
                ctx,
                [
                    "pattern vertices",
                    "pattern indices",
                    "pattern unrolled vertices",
                ],
                [
                    bytemuck::cast_slice(&tiles.rows),
                    bytemuck::cast_slice(&tiles.indices),
                    bytemuck::cast_slice(&tiles.wire),
                ],
            );
            let instance_faces = ctx.storage_buffer(
                "instance faces",
                bytemuck::cast_slice(&tiles.instance_faces),
                wgpu::BufferUsages::empty(),
            );
            let face_uvs = ctx.storage_buffer(
                "face uvs",
                bytemuck::cast_slice(&face_uvs),
                wgpu::BufferUsages::empty(),
            );
            let patch_group =
                patches.bind_group(ctx, &pipelines.patch_layout, &[&instance_faces, &face_uvs]);
            Ok(PatternRenderer {
                ctx: ctx.clone(),
                pipelines,
                shape: (plan.face_count(), plan.options().scheme.basis().len()),
                normal_mode: plan.normal_mode(),
                level: tiles.level,
                patches,
                patch_group,
                pattern_vertices,
                pattern_indices,
                draws: tiles.draws,
                instance_faces,
                wire_vertices,
                face_uvs,
                displacement_reach: displacement_reach(displacement),
                position_ids,
            })
        })?
    }

    /// Uploads `frame`'s control nets (the only per-frame upload of a deforming mesh; with
    /// displacement also its per-face records, see `tessella_core::displace::face_frames`) and
    /// returns the bytes written. The frame must be of a plan with the renderer's triangle
    /// count and basis.
    pub fn update(&self, frame: &Frame) -> Result<u64, GpuError> {
        let nets = frame.nets();
        patch::check_nets_shape(nets, self.shape)?;
        let mut bytes = 0;
        if let Some(ids) = &self.position_ids {
            let mesh = frame.mesh();
            if mesh.vertex_count() != ids.len() {
                return Err(GpuError::BadOption(format!(
                    "a frame of {} vertices, the renderer was made for {}",
                    mesh.vertex_count(),
                    ids.len()
                )));
            }
            bytes += self
                .patches
                .update_displace_faces(&self.ctx, &face_frames(mesh, ids));
        }
        Ok(bytes + self.patches.update_nets(&self.ctx, nets))
    }

    /// The renderer's nets, for a [`GpuNetBuilder`](crate::GpuNetBuilder) to write from
    /// coarse vertices already on the GPU instead of [`PatternRenderer::update`]'s upload.
    /// Refused with displacement: its per-face records are made on the CPU from each frame's
    /// mesh (`update(frame)`, with the frame's CPU nets, is the path there).
    pub fn nets_target(&self) -> Result<crate::NetsTarget<'_>, GpuError> {
        if self.patches.displaced() {
            return Err(GpuError::BadOption(
                "a displaced pattern renderer reads per-face records made on the CPU from each                  frame's mesh, so its nets cannot be built on the GPU; upload the frame's CPU                  nets with update(frame), or draw without displacement"
                    .into(),
            ));
        }
        Ok(self.patches.nets_target(self.shape, self.normal_mode))
    }

    /// Records the instanced draw of every coarse triangle into `pass` (whose attachments
    /// match the [`Shading`]'s formats), with `shading` as bind group 1. Errors show when the
    /// caller submits.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        self.set_groups(pass, shading);
        pass.set_vertex_buffer(0, self.pattern_vertices.slice(..));
        pass.set_index_buffer(self.pattern_indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &self.draws {
            pass.draw_indexed(d.indices.clone(), 0, d.instances.clone());
        }
    }

    /// [`PatternRenderer::draw`] with the pattern's triangles unrolled, three vertices each
    /// with its own `corner`, so the fragment shader knows its place in every pattern triangle
    /// (a wireframe's distance to the edges) whatever the pattern.
    pub fn draw_unrolled(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        self.set_groups(pass, shading);
        pass.set_vertex_buffer(0, self.wire_vertices.slice(..));
        for d in &self.draws {
            pass.draw(d.indices.clone(), d.instances.clone());
        }
    }

    fn set_groups(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipelines.pattern);
        pass.set_bind_group(0, &self.patch_group, &[]);
        pass.set_bind_group(1, shading, &[]);
    }

    /// Records a draw of an already refined, indexed mesh with the same shading (vertices
    /// with `face` `TESSELLA_NO_FACE`): `vertices` holds 24-byte position + normal vertices (a
    /// [`crate::GpuEvaluator`]'s output without UVs), `indices` `index_count` indices of
    /// `format`. GMR Figure 7's static baseline.
    pub fn draw_refined(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        shading: &wgpu::BindGroup,
        vertices: wgpu::BufferSlice<'_>,
        indices: wgpu::BufferSlice<'_>,
        format: wgpu::IndexFormat,
        index_count: u32,
    ) {
        pass.set_pipeline(&self.pipelines.fixed);
        pass.set_bind_group(1, shading, &[]);
        pass.set_vertex_buffer(0, vertices);
        pass.set_index_buffer(indices, format);
        pass.draw_indexed(0..index_count, 0, 0..1);
    }

    /// Bytes this renderer keeps on the GPU (nets, stencil, pattern, draw tables).
    pub fn byte_size(&self) -> u64 {
        self.patches.byte_size()
            + self.pattern_vertices.size()
            + self.pattern_indices.size()
            + self.wire_vertices.size()
            + self.instance_faces.size()
            + self.face_uvs.size()
    }

    /// Draw calls per frame: one per distinct pattern.
    pub fn draw_count(&self) -> usize {
        self.draws.len()
    }

    /// Pattern vertices stored on the GPU: `(N+1)(N+2)/2` whatever the mesh for a uniform plan,
    /// the sum over the distinct tiles for an adaptive one.
    pub fn pattern_vertex_count(&self) -> u64 {
        self.pattern_vertices.size() / 4
    }

    /// How far the displacement can move a point (for framing a camera).
    pub fn displacement_reach(&self) -> f32 {
        self.displacement_reach
    }
}

fn displacement_reach(displacement: &Displacement) -> f32 {
    match displacement {
        Displacement::None => 0.0,
        Displacement::Sine { amplitude, .. }
        | Displacement::Perlin { amplitude, .. }
        | Displacement::HeightMap { amplitude, .. } => amplitude.abs(),
    }
}

/// One instanced draw: a pattern's index range (or unrolled vertex range, the same numbers)
/// and the instances (positions in `instance_faces`) that use it.
#[derive(Debug, Clone)]
struct TileDraw {
    indices: std::ops::Range<u32>,
    instances: std::ops::Range<u32>,
}

/// A plan's patterns laid out for drawing: a uniform plan's one pattern, or an adaptive plan's
/// distinct tiles one after the other, with the faces grouped by tile.
struct Tiles<'p> {
    patterns: Vec<&'p tessella_core::Pattern>,
    /// Stencil rows of every pattern, concatenated.
    weights: Vec<f32>,
    /// `0..rows`: the vertex buffer of the indexed draw.
    rows: Vec<u32>,
    /// Triangles as global rows.
    indices: Vec<u32>,
    /// Triangles unrolled, `row | corner << 30`.
    wire: Vec<u32>,
    instance_faces: Vec<u32>,
    draws: Vec<TileDraw>,
    /// Largest segment count.
    level: u32,
}

impl<'p> Tiles<'p> {
    fn new(plan: &'p Plan) -> Result<Tiles<'p>, GpuError> {
        let faces = plan.face_count() as u32;
        let (patterns, stencils, face_tile): (Vec<_>, Vec<_>, Vec<u32>) = match plan.tiling() {
            None => (
                vec![plan.pattern()],
                vec![plan.stencil()],
                vec![0; faces as usize],
            ),
            Some(t) => (
                t.tiles.iter().map(|t| &t.pattern).collect(),
                t.tiles.iter().map(|t| &t.stencil).collect(),
                t.face_tile.clone(),
            ),
        };
        // Faces grouped by tile, in face order within a tile.
        let mut counts = vec![0u32; patterns.len()];
        for &t in &face_tile {
            counts[t as usize] += 1;
        }
        let mut starts: Vec<u32> = counts
            .iter()
            .scan(0, |acc, &c| {
                let s = *acc;
                *acc += c;
                Some(s)
            })
            .collect();
        let first_instance = starts.clone();
        let mut instance_faces = vec![0u32; faces as usize];
        for (f, &t) in face_tile.iter().enumerate() {
            instance_faces[starts[t as usize] as usize] = f as u32;
            starts[t as usize] += 1;
        }
        let rows_total: usize = patterns.iter().map(|p| p.points.len()).sum();
        if rows_total >= 1 << 30 {
            return Err(GpuError::TooLarge {
                what: "the patterns' points",
                bytes: rows_total as u64 * 4,
                limit: (1u64 << 30) * 4,
            });
        }
        let mut weights = Vec::new();
        let (mut indices, mut wire, mut draws) = (Vec::new(), Vec::new(), Vec::new());
        let mut row0 = 0u32;
        for (t, (pattern, stencil)) in patterns.iter().zip(&stencils).enumerate() {
            weights.extend_from_slice(&stencil.weights);
            let start = indices.len() as u32;
            for tri in &pattern.triangles {
                indices.extend(tri.map(|p| p + row0));
                wire.extend((0..3u32).map(|c| (tri[c as usize] + row0) | c << 30));
            }
            if counts[t] > 0 && !pattern.triangles.is_empty() {
                draws.push(TileDraw {
                    indices: start..indices.len() as u32,
                    instances: first_instance[t]..first_instance[t] + counts[t],
                });
            }
            row0 += pattern.points.len() as u32;
        }
        Ok(Tiles {
            level: patterns.iter().map(|p| p.level).max().unwrap_or(1),
            rows: (0..row0).collect(),
            patterns,
            weights,
            indices,
            wire,
            instance_faces,
            draws,
        })
    }
}
