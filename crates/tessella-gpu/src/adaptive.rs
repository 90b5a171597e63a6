//! The instanced renderer for levels that change every frame: the spacing's parts (strips and
//! interiors of the tessellator's patterns, or the grids) are uploaded once; per frame only
//! coarse data crosses the bus — the nets, one record per face and one instance per face and
//! part (`tessella_core::refine::instanced`).

#[cfg(feature = "blocking")]
use crate::context::WRITE;
use crate::context::{GpuContext, READ, UNIFORM};
use crate::error::GpuError;
use crate::gpu_types::normal_mode_code;
use crate::gpu_types::AdaptiveParams;
use crate::patch::{check_nets_shape, write_nets};
use crate::renderer::{draw_buffers, CODE_VERTICES};
use crate::shading::Shading;
use std::ops::Range;
use tessella_core::refine::instanced::{PartTable, RECORD_WORDS};
use tessella_core::refine::{canonical, Frame, InstancedDriver, Lod, Spacing, Surface};
use tessella_core::shader::{self, Lang};

/// Storage buffers the adaptive renderer binds in the vertex stage: the nets, the records and
/// the instances. A shading may bind what the device allows beyond them.
pub const ADAPTIVE_VERTEX_STORAGE_BUFFERS: u32 = 4;

/// Instances per face at most: three strips and an interior.
const MAX_PARTS_PER_FACE: u64 = 4;

/// Draws a deforming mesh whose per-edge levels change every frame, with the hardware
/// tessellator's patterns or geomorphing grids, crack-free and without rebuilding anything per
/// frame: [`AdaptiveRenderer::set_levels`] (or [`AdaptiveRenderer::set_lod`]) uploads one record
/// per face and one instance per face and part, [`AdaptiveRenderer::update`] the frame's nets;
/// both are O(coarse) whatever the levels. The vertex shader places each point from the face's
/// levels and evaluates the basis there (`shaders/adaptive.wgsl`).
///
/// ```no_run
/// # fn demo(ctx: &tessella_gpu::GpuContext, pass: &mut wgpu::RenderPass<'_>,
/// #         shading: &tessella_gpu::Shading,
/// #         shading_group: &wgpu::BindGroup) -> Result<(), tessella_gpu::GpuError> {
/// use tessella_core::refine::{Spacing, Surface, SurfaceOptions};
/// use tessella_core::{samples, Scheme};
/// use tessella_gpu::AdaptiveRenderer;
/// let mesh = samples::icosphere(1);
/// // The surface alone (topology and scheme): no level, the levels come every frame.
/// let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn))?;
/// let mut frame = surface.frame(&mesh)?;
/// let mut renderer =
///     AdaptiveRenderer::new(ctx, &surface, &frame, shading, Spacing::FractionalOdd)?;
/// // Every frame: new levels (one per unique edge), new nets, one draw call per part used.
/// let levels = vec![5.5; surface.topology().edges.len()];
/// renderer.set_levels(&levels, None)?;
/// let moved: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| 1.1 * c)).collect();
/// surface.update(&mut frame, &moved, None)?;
/// renderer.update(&frame)?;
/// renderer.draw(pass, shading_group);
/// # Ok(()) }
/// ```
pub struct AdaptiveRenderer {
    ctx: GpuContext,
    spacing: Spacing,
    pipeline: wgpu::RenderPipeline,
    /// Per part: its index range and first vertex in `vertices`.
    parts: Vec<GpuPart>,
    /// Point codes, each part's distinct codes one after the other.
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Every part's triangles unrolled, `code | corner << 30`.
    wire: wgpu::Buffer,
    points: wgpu::Buffer,
    normals: wgpu::Buffer,
    records: wgpu::Buffer,
    instances: wgpu::Buffer,
    patch_group: wgpu::BindGroup,
    // Read by the (blocking) capture only.
    #[cfg_attr(not(feature = "blocking"), allow(dead_code))]
    patch_layout: wgpu::BindGroupLayout,
    /// The WGSL constants the shaders are compiled with (basis, normal mode, spacing).
    #[cfg_attr(not(feature = "blocking"), allow(dead_code))]
    constants: String,
    /// The part table and the last [`AdaptiveRenderer::set_levels`]: draws and triangle count.
    driver: InstancedDriver,
    /// What the per-frame records need (topology, triangles), and whose frames are taken.
    surface: Surface,
    /// Coarse triangles and basis size.
    shape: (usize, usize),
    /// Bytes kept in the GPU buffers made at creation (parts, nets, per-face buffers).
    bytes: u64,
}

/// What [`AdaptiveRenderer::capture`] reads back: per drawn vertex (three per triangle) its
/// position, unit normal and barycentric point in its coarse triangle; per triangle its face.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CapturedTriangles {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub barycentric: Vec<[f32; 3]>,
    pub faces: Vec<u32>,
}

#[derive(Debug, Clone)]
struct GpuPart {
    indices: Range<u32>,
    base_vertex: i32,
}

impl std::fmt::Debug for AdaptiveRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AdaptiveRenderer")
            .field("faces", &self.shape.0)
            .field("spacing", &self.spacing)
            .field("draws", &self.driver.frame().draws.len())
            .finish()
    }
}

/// The part table as GPU arrays: per part its distinct codes and local indices, and the
/// unrolled triangles' vertices.
struct PartArrays {
    vertices: Vec<u32>,
    indices: Vec<u32>,
    wire: Vec<u32>,
    parts: Vec<GpuPart>,
}

impl PartArrays {
    fn new(table: &PartTable) -> PartArrays {
        let mut out = PartArrays {
            vertices: Vec::new(),
            indices: Vec::new(),
            wire: Vec::new(),
            parts: Vec::with_capacity(table.ranges.len()),
        };
        for (part, range) in table.ranges.iter().enumerate() {
            let base = out.vertices.len();
            let first = out.indices.len() as u32;
            let (codes, local) = table.part_vertices(part as u32);
            out.vertices.extend(codes);
            out.indices.extend(local);
            for t in &table.triangles[range.start as usize..range.end as usize] {
                for (corner, &code) in t.iter().enumerate() {
                    out.wire.push(code | (corner as u32) << 30);
                }
            }
            out.parts.push(GpuPart {
                indices: first..out.indices.len() as u32,
                base_vertex: base as i32,
            });
        }
        out
    }
}

impl AdaptiveRenderer {
    /// Compiles the pipeline for `shading`, uploads `spacing`'s parts and the first frame's
    /// nets. The surface gives the mesh's topology and scheme (no level: the levels come with
    /// each [`AdaptiveRenderer::set_levels`]); `frame` is one of its frames (a plan's
    /// [`tessella_core::refine::Plan::surface`] serves too). Nothing is drawn before the first
    /// [`AdaptiveRenderer::set_levels`].
    pub fn new(
        ctx: &GpuContext,
        surface: &Surface,
        frame: &Frame,
        shading: &Shading,
        spacing: Spacing,
    ) -> Result<AdaptiveRenderer, GpuError> {
        surface.check_frame(frame)?;
        // Its patch group (nets, records) and the draw group's instances.
        ctx.check_storage_buffers(
            "the adaptive renderer",
            "vertex",
            ADAPTIVE_VERTEX_STORAGE_BUFFERS,
        )?;
        let nets = frame.nets();
        let faces = surface.face_count();
        // Under 4 GiB a binding's u32 indices in the shaders cannot wrap.
        let limit = ctx.max_binding().min(u32::MAX as u64);
        let record_bytes = faces as u64 * RECORD_WORDS as u64 * 4;
        let instance_bytes = faces as u64 * MAX_PARTS_PER_FACE * 4;
        for (what, bytes) in [
            ("the control nets", nets.points.len() as u64 * 12),
            ("the normal nets", nets.normals.len() as u64 * 12),
            ("the per-face level records", record_bytes),
            ("the instances", instance_bytes),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        let table = PartTable::new(spacing);
        let arrays = PartArrays::new(&table);
        let basis = nets.basis;
        let constants = constants(basis, nets.normal_mode, spacing);
        let params = params(basis);
        ctx.scoped(|| {
            let copy = wgpu::BufferUsages::COPY_DST;
            let storage = |label, bytes: u64| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes.max(4).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
                    usage: wgpu::BufferUsages::STORAGE | copy,
                    mapped_at_creation: false,
                })
            };
            let points = ctx.storage_buffer("net points", bytemuck::cast_slice(&nets.points), copy);
            let normals =
                ctx.storage_buffer("net normals", bytemuck::cast_slice(&nets.normals), copy);
            let params = ctx.buffer_init(
                "adaptive params",
                bytemuck::bytes_of(&params),
                wgpu::BufferUsages::UNIFORM,
            );
            let records = storage("level records", record_bytes);
            let instances = storage("instances", instance_bytes);
            let [vertices, indices, wire] = draw_buffers(
                ctx,
                ["part codes", "part indices", "part wireframe"],
                [
                    bytemuck::cast_slice(&arrays.vertices),
                    bytemuck::cast_slice(&arrays.indices),
                    bytemuck::cast_slice(&arrays.wire),
                ],
            );
            let patch_layout = adaptive_layout(ctx);
            let patch_layout_for_capture = patch_layout.clone();
            let patch_group = ctx.buffer_group(
                "adaptive",
                &patch_layout,
                &[&points, &normals, &params, &records, &instances],
            );
            // The prelude names the basis, normal mode and spacing: with the shading, the key.
            let key = format!("adaptive draw|{}|{constants}", shading.cache_key());
            let pipeline = ctx.pipelines(&key, || {
                let module = ctx
                    .device
                    .create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some("adaptive.wgsl"),
                        source: wgpu::ShaderSource::Wgsl(
                            shading
                                .append_to(
                                    &[
                                        &constants,
                                        include_str!("shaders/adaptive.wgsl"),
                                        include_str!("shaders/adaptive_draw.wgsl"),
                                    ]
                                    .concat(),
                                )
                                .into(),
                        ),
                    });
                let layout = ctx
                    .device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("adaptive"),
                        bind_group_layouts: &[Some(&patch_layout), Some(shading.layout)],
                        immediate_size: 0,
                    });
                shading.pipeline(ctx, &module, &layout, "tessella_vs_adaptive", CODE_VERTICES)
            })?;
            let bytes = [
                &vertices, &indices, &wire, &points, &normals, &records, &instances, &params,
            ]
            .iter()
            .map(|b| b.size())
            .sum();
            Ok(AdaptiveRenderer {
                ctx: ctx.clone(),
                spacing,
                pipeline,
                parts: arrays.parts,
                vertices,
                indices,
                wire,
                points,
                normals,
                records,
                instances,
                patch_group,
                patch_layout: patch_layout_for_capture,
                constants: constants.clone(),
                driver: InstancedDriver::with_table(std::sync::Arc::new(table)),
                surface: surface.clone(),
                shape: (faces, basis.len()),
                bytes,
            })
        })?
    }

    /// Sets the levels of the next draws: one per unique edge (`Topology::edges` order, as
    /// `Levels::PerEdge`), optionally a minimum inner level per face; clamped as the spacing
    /// does (grid levels above `instanced::MAX_GRID_LEVEL` are drawn at it). Uploads one record
    /// per face and one instance per face and part; returns the bytes written.
    pub fn set_levels(
        &mut self,
        edge_levels: &[f32],
        face_minimums: Option<&[f32]>,
    ) -> Result<u64, GpuError> {
        let frame = self
            .driver
            .set_levels(&self.surface, edge_levels, face_minimums)?;
        let records: &[u8] = bytemuck::cast_slice(&frame.records);
        let instances: &[u8] = bytemuck::cast_slice(&frame.instances);
        self.ctx.queue.write_buffer(&self.records, 0, records);
        if !instances.is_empty() {
            self.ctx.queue.write_buffer(&self.instances, 0, instances);
        }
        Ok((records.len() + instances.len()) as u64)
    }

    /// [`AdaptiveRenderer::set_levels`] with the levels `lod` gives on `frame`'s mesh (a
    /// camera that moves, a mesh that deforms: new levels every frame). Grid levels are drawn
    /// at most at `instanced::MAX_GRID_LEVEL` (64), below the tolerance LOD's cap of 1024.
    pub fn set_lod(&mut self, frame: &Frame, lod: &Lod) -> Result<u64, GpuError> {
        // A foreign frame is refused first (by the driver), as before a frame's nets are read.
        let (edges, faces) = self.driver.levels(&self.surface, frame, lod)?;
        check_nets_shape(frame.nets(), self.shape)?;
        self.set_levels(&edges, faces.as_deref())
    }

    /// The per-edge levels of the latest draws, as given (before the spacing's clamp).
    pub fn edge_levels(&self) -> &[f32] {
        self.driver.edge_levels()
    }

    /// The levels `lod` gives on `frame`, per edge and per face, without drawing them: for a
    /// host that adjusts them before [`AdaptiveRenderer::set_levels`] (the core's
    /// [`InstancedDriver::levels`]).
    pub fn levels(
        &self,
        frame: &Frame,
        lod: &Lod,
    ) -> Result<(Vec<f32>, Option<Vec<f32>>), GpuError> {
        Ok(self.driver.levels(&self.surface, frame, lod)?)
    }

    /// Uploads `frame`'s control nets (a frame of the renderer's surface, moved by
    /// [`Surface::update`]); returns the bytes written.
    pub fn update(&self, frame: &Frame) -> Result<u64, GpuError> {
        self.surface.check_frame(frame)?;
        check_nets_shape(frame.nets(), self.shape)?;
        Ok(write_nets(
            &self.ctx,
            &self.points,
            &self.normals,
            frame.nets(),
        ))
    }

    /// The renderer's nets, for a [`GpuNetBuilder`](crate::GpuNetBuilder) to write from
    /// coarse vertices already on the GPU instead of [`AdaptiveRenderer::update`]'s upload
    /// (levels then come from [`AdaptiveRenderer::set_levels`]: [`AdaptiveRenderer::set_lod`]
    /// reads a CPU frame).
    pub fn nets_target(&self) -> crate::NetsTarget<'_> {
        crate::NetsTarget {
            points: &self.points,
            normals: &self.normals,
            faces: self.shape.0,
            k: self.shape.1,
            normal_mode: self.surface.normal_mode(),
            coarse: None,
        }
    }

    /// Records one instanced draw per part used into `pass` (whose attachments match the
    /// [`Shading`]'s formats), with `shading` as bind group 1.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        self.set_groups(pass, shading);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &self.driver.frame().draws {
            let p = &self.parts[d.part as usize];
            pass.draw_indexed(p.indices.clone(), p.base_vertex, d.instances.clone());
        }
    }

    /// [`AdaptiveRenderer::draw`] with the parts' triangles unrolled, three vertices each with
    /// its own `corner` (see [`crate::PatternRenderer::draw_unrolled`]).
    pub fn draw_unrolled(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        self.set_groups(pass, shading);
        pass.set_vertex_buffer(0, self.wire.slice(..));
        for d in &self.driver.frame().draws {
            let r = &self.parts[d.part as usize].indices;
            pass.draw(r.clone(), d.instances.clone());
        }
    }

    fn set_groups(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.patch_group, &[]);
        pass.set_bind_group(1, shading, &[]);
    }

    /// Reads back the triangles the current levels draw, evaluated by the vertex shader's own
    /// code in a compute pass (`shaders/adaptive_capture.wgsl`): three vertices per triangle
    /// (the grid's zero-area triangles included). For tests and debugging: its size is the
    /// refined mesh's. Blocks (the `blocking` feature).
    #[cfg(feature = "blocking")]
    pub fn capture(&self) -> Result<CapturedTriangles, GpuError> {
        let mut jobs: Vec<[u32; 2]> = Vec::new();
        let mut faces = Vec::new();
        let (frame, table) = (self.driver.frame(), self.driver.table());
        for d in &frame.draws {
            let range = &table.ranges[d.part as usize];
            let tris = &table.triangles[range.start as usize..range.end as usize];
            for &inst in &frame.instances[d.instances.start as usize..d.instances.end as usize] {
                for t in tris {
                    jobs.extend(t.map(|code| [inst, code]));
                    faces.push(inst & 0x3fff_ffff);
                }
            }
        }
        let out_bytes = jobs.len() as u64 * 36;
        let limit = self.ctx.max_binding().min(u32::MAX as u64);
        if out_bytes > limit {
            return Err(GpuError::TooLarge {
                what: "the captured triangles",
                bytes: out_bytes,
                limit,
            });
        }
        let ctx = &self.ctx;
        let bytes = ctx.scoped(|| -> Result<Vec<u8>, GpuError> {
            let jobs_buffer = ctx.storage_buffer(
                "capture jobs",
                bytemuck::cast_slice(&jobs),
                wgpu::BufferUsages::empty(),
            );
            let out = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("captured"),
                size: out_bytes.max(4),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let compute = wgpu::ShaderStages::COMPUTE;
            let layout = ctx.buffer_layout("capture", &[(compute, READ), (compute, WRITE)]);
            let group = ctx.buffer_group("capture", &layout, &[&jobs_buffer, &out]);
            let key = format!("adaptive capture|{}", self.constants);
            let pipeline = ctx.pipelines(&key, || {
                let module = ctx
                    .device
                    .create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some("adaptive_capture.wgsl"),
                        source: wgpu::ShaderSource::Wgsl(
                            [
                                &self.constants,
                                include_str!("shaders/adaptive.wgsl"),
                                include_str!("shaders/adaptive_capture.wgsl"),
                            ]
                            .concat()
                            .into(),
                        ),
                    });
                let pipeline_layout =
                    ctx.device
                        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                            label: Some("capture"),
                            bind_group_layouts: &[Some(&self.patch_layout), Some(&layout)],
                            immediate_size: 0,
                        });
                ctx.device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some("cs_capture"),
                        layout: Some(&pipeline_layout),
                        module: &module,
                        entry_point: Some("cs_capture"),
                        compilation_options: Default::default(),
                        cache: None,
                    })
            })?;
            let groups = (jobs.len() as u64).div_ceil(64);
            let max = ctx.limits.max_compute_workgroups_per_dimension as u64;
            let (x, y) = (groups.min(max), groups.div_ceil(max));
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &self.patch_group, &[]);
                pass.set_bind_group(1, &group, &[]);
                pass.dispatch_workgroups(x as u32, y as u32, 1);
            }
            ctx.submit_and_wait(encoder)?;
            ctx.read_buffer(&out, 0, out_bytes)
        })??;
        let floats: &[f32] = bytemuck::cast_slice(&bytes);
        let mut c = CapturedTriangles {
            faces,
            ..Default::default()
        };
        for v in floats.chunks_exact(9) {
            c.positions.push([v[0], v[1], v[2]]);
            c.normals.push([v[3], v[4], v[5]]);
            c.barycentric.push([v[6], v[7], v[8]]);
        }
        Ok(c)
    }

    /// Draw calls of the current levels: one per part used.
    pub fn draw_count(&self) -> usize {
        self.driver.frame().draws.len()
    }

    /// Triangles the current levels draw (grid: with the zero-area ones the rasteriser skips).
    pub fn triangle_count(&self) -> u64 {
        self.driver.frame().triangles
    }

    /// The surface drawn (its frames are the ones [`AdaptiveRenderer::update`] takes).
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// The spacing drawn.
    pub fn spacing(&self) -> Spacing {
        self.spacing
    }

    /// Bytes kept on the GPU: the parts (built once), the nets and the per-face buffers.
    pub fn byte_size(&self) -> u64 {
        self.bytes
    }
}

/// Group 0 of `shaders/adaptive.wgsl`: nets, params, records, then the instances the draw
/// reads (`shaders/adaptive_draw.wgsl`; the capture leaves them).
fn adaptive_layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
    let stages = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE;
    let [r, u] = [(stages, READ), (stages, UNIFORM)];
    ctx.buffer_layout("adaptive", &[r, r, u, r, r])
}

/// The WGSL the adaptive shaders are compiled with, before `shaders/adaptive.wgsl`: the
/// pipeline's constants (basis, normal mode, spacing), the record layout, the printed
/// `TessellaAdaptiveParams`, the weights and glue generated from tessella-core's formulas,
/// `tessella_adaptive_normal` (the normal's steps, [`shader::normal_glue`]) and the point on
/// the tessellator's spacings (`tessella_tessellator_adaptive_point`, [`shader::adaptive_point`]).
pub(crate) fn constants(
    basis: tessella_core::basis::Basis,
    normal_mode: tessella_core::NormalMode,
    spacing: Spacing,
) -> String {
    [
        crate::wgsl_constants::source(),
        shader::record_layout(Lang::Wgsl),
        format!(
            "const TESSELLA_BASIS_K: u32 = {}u;\nconst TESSELLA_NORMAL_MODE: u32 = {}u;\nconst TESSELLA_GRID: bool = {};\n",
            basis.len(),
            normal_mode_code(normal_mode),
            spacing == Spacing::Grid
        ),
        crate::gpu_types::AdaptiveParams::wgsl(),
        shader::patch_sum_wgsl(basis),
        shader::normal_net_sum_wgsl(),
        shader::edge_weights_wgsl(),
        crate::patch::canonical_edge_wgsl().to_string(),
        crate::patch::canonical_edge_point_wgsl().to_string(),
        shader::locate_wgsl(),
        shader::tessellator_point(Lang::Wgsl),
        shader::grid_plan_wgsl(),
        crate::patch::surface_normal_wgsl().to_string(),
        adaptive_normal_wgsl(),
        tessellator_point_wgsl(),
    ]
    .join("\n")
}

/// What [`tessellator_point_wgsl`]'s adaptive point reads: the face's record at `rec` in the
/// records buffer, and its evaluation, the patch's sums at `l` then the normal's steps.
pub(crate) const TESSELLATOR_POINT: shader::PointSources<'static> = shader::PointSources {
    face: "face",
    context: "",
    record: "rec",
    code: "code",
    side: "side",
    forward_bits: "tessella_records[rec + TESSELLA_FORWARD_WORD]",
    evaluate: "var acc: TessellaSums;\n\
               tessella_add_point(&acc, face, l, 1.0);\n\
               position = acc.p;\n\
               normal = tessella_adaptive_normal(face, acc.du, acc.dv, acc.n);",
};

/// A point on the tessellator's spacings, `tessella_tessellator_adaptive_point(face, rec, code,
/// side)`: the core's adaptive point ([`shader::adaptive_point`]: the placement, its
/// barycentric point, the canonical edge point in place of the patch's on a coarse edge) over
/// this renderer's records and its evaluation (the patch's sums at `l`, then
/// `tessella_adaptive_normal`).
fn tessellator_point_wgsl() -> String {
    let steps = shader::adaptive_point(Lang::Wgsl, &TESSELLATOR_POINT);
    format!(
        "fn tessella_tessellator_adaptive_point(face: u32, rec: u32, code: u32, side: u32) -> \
         TessellaAdaptivePoint {{\n    var position: vec3<f32>;\n    var normal: vec3<f32>;\n\
         {steps}    return TessellaAdaptivePoint(position, normal, l);\n}}\n"
    )
}

/// An adaptive point's unit normal, `tessella_adaptive_normal(face, du, dv, net)`: the core's
/// normal steps ([`shader::normal_glue`]) over the point's summed derivatives and its normal
/// net's sum; on an edge, `tessella_canonical_edge_point` then takes the edge's net normal
/// where the mode does.
fn adaptive_normal_wgsl() -> String {
    let sources = crate::patch::face_normal_sources("du", "dv", "n = net;");
    let glue = shader::normal_glue(Lang::Wgsl, &sources);
    format!(
        "fn tessella_adaptive_normal(face: u32, du: vec3<f32>, dv: vec3<f32>, net: vec3<f32>) \
         -> vec3<f32> {{\n{glue}    return n;\n}}\n"
    )
}

/// The adaptive shaders' uniform: each edge's boundary control points and normal-net entries.
pub(crate) fn params(basis: tessella_core::basis::Basis) -> AdaptiveParams {
    AdaptiveParams {
        edge_controls: [0, 1, 2].map(|k| canonical::edge_controls(basis, k).map(|i| i as u32)),
        edge_normals: [0, 1, 2].map(|k| {
            let [a, b, c] = canonical::edge_normal_controls(k);
            [a as u32, b as u32, c as u32, 0]
        }),
    }
}
