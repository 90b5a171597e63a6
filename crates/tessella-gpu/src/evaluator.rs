//! The GPU evaluator: the compute path behind [`tessella_core::refine::Evaluator`]. Made once
//! per [`Plan`] (it uploads the stencil, the pattern and the topology tables then), it writes
//! each [`Frame`]'s refined vertices into a `wgpu` buffer, its own or the caller's, uploading
//! only the frame's coarse data (control nets, coarse positions, normals and UVs).
//!
//! Output order is the plan's (the CPU's `OutputLayout`); the vertex format is any
//! [`VertexFormat`], the CPU's (stride and offsets of position, normal, uv, in floats), so one
//! dispatch fills an engine's interleaved vertex buffer. The default is
//! [`VertexFormat::POSITION_NORMAL`], or [`VertexFormat::POSITION_NORMAL_UV`] when the mesh has
//! texture coordinates.
//!
//! [`GpuEvaluator::record`] records the frame's dispatches into the caller's encoder (the
//! engine submits it with its own work); [`Evaluator::evaluate`] is the convenience that
//! submits them itself.
//!
//! Work is split into chunks that fit one storage-buffer binding and one dispatch, so an
//! output that fits in one buffer can be refined whatever the binding limit.

use crate::context::{GpuContext, READ, UNIFORM, WRITE};
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::gpu_types::normal_mode_code;
use crate::gpu_types::RefineParams;
use crate::patch::{self, PatchBuffers};
use tessella_core::displace::face_frames;
use tessella_core::pattern::PointClass;
use tessella_core::refine::{Evaluator, Frame, Plan, PlanSizes, Tiling, VertexFormat};
use tessella_core::{NormalMode, PatchNets, Pattern};
#[cfg(feature = "blocking")]
use tessella_core::{RefinedMesh, Refiner};

/// Threads per workgroup of both kernels (`@workgroup_size(64)` in `refine.wgsl`).
const WORKGROUP: u64 = 64;

/// Largest staging buffer for one batch of chunks read back together.
#[cfg(feature = "blocking")]
const STAGING_BYTES: u64 = 256 << 20;

/// Options of [`GpuEvaluator::with_options`] and [`gpu_refine_with`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GpuRefineOptions {
    /// Applied to every output vertex after evaluation.
    pub displacement: Displacement,
    /// Caps the vertices or triangles per chunk below what the device allows (for tests of
    /// the chunking; `None` uses the device limits).
    pub max_chunk_items: Option<u32>,
    /// Caps the coarse faces whose control nets one binding holds below what the binding
    /// limit allows (for tests of the net windows; `None` uses the device limits).
    pub max_net_faces: Option<u32>,
    /// The output's interleaved layout; `None`: position and normal, and uv when the mesh
    /// has texture coordinates ([`GpuEvaluator::vertex_format`]).
    pub vertex_format: Option<VertexFormat>,
}

/// Where [`GpuEvaluator::record`] writes one frame's vertices (format:
/// [`GpuEvaluator::vertex_format`]).
#[derive(Debug)]
#[non_exhaustive]
pub enum GpuOutput<'a> {
    /// The evaluator's own vertex buffer (`VERTEX | STORAGE | COPY_SRC`), made on first use and
    /// kept: [`GpuEvaluator::vertex_buffer`], [`GpuEvaluator::read_back`].
    Own,
    /// The caller's buffer, from byte `offset` (a multiple of 4). It needs `STORAGE` usage and
    /// room for [`GpuEvaluator::vertex_bytes`] bytes after `offset`; add `VERTEX` to draw it.
    Buffer {
        buffer: &'a wgpu::Buffer,
        offset: u64,
    },
}

/// The refined triangles' index width of [`GpuEvaluator::write_indices`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IndexWidth {
    U16,
    U32,
}

impl IndexWidth {
    /// The narrowest width that holds the plan's vertex indices.
    pub fn for_plan(plan: &Plan) -> IndexWidth {
        if plan.fits_u16() {
            IndexWidth::U16
        } else {
            IndexWidth::U32
        }
    }

    /// Bytes of the plan's refined triangles at this width, rounded up to 4 (the size of the
    /// buffer [`GpuEvaluator::write_indices`] fills).
    pub fn buffer_bytes(self, plan: &Plan) -> u64 {
        (plan.triangle_count() as u64 * 3 * self.bytes()).next_multiple_of(4)
    }

    /// The `wgpu` index format.
    pub fn format(self) -> wgpu::IndexFormat {
        match self {
            IndexWidth::U16 => wgpu::IndexFormat::Uint16,
            IndexWidth::U32 => wgpu::IndexFormat::Uint32,
        }
    }
    fn bytes(self) -> u64 {
        match self {
            IndexWidth::U16 => 2,
            IndexWidth::U32 => 4,
        }
    }
}

/// The compiled refinement kernels of one kind of evaluator, shared through the context's cache.
#[derive(Clone)]
struct Pipelines {
    patch_layout: wgpu::BindGroupLayout,
    refine_layout: wgpu::BindGroupLayout,
    vertices: wgpu::ComputePipeline,
    indices: wgpu::ComputePipeline,
}

impl Pipelines {
    fn new(ctx: &GpuContext, normal_mode: NormalMode, displacement: &Displacement) -> Pipelines {
        let patch_layout = patch::layout(ctx, wgpu::ShaderStages::COMPUTE, 0);
        let compute = wgpu::ShaderStages::COMPUTE;
        let refine_layout = ctx.buffer_layout(
            "refine",
            &[
                (compute, UNIFORM),
                (compute, READ),
                (compute, READ),
                (compute, WRITE),
            ],
        );
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("refine"),
                bind_group_layouts: &[Some(&patch_layout), Some(&refine_layout)],
                immediate_size: 0,
            });
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("refine.wgsl"),
                source: wgpu::ShaderSource::Wgsl(
                    patch::shader_source(&refine_wgsl(), normal_mode, displacement, None).into(),
                ),
            });
        let pipeline = |entry| {
            ctx.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        };
        Pipelines {
            vertices: pipeline("refine_vertices"),
            indices: pipeline("refine_indices"),
            patch_layout,
            refine_layout,
        }
    }
}

/// One dispatch: `count` items from output item `first`, written into `window` (a bound byte
/// range of a buffer) from `f32`/`u32` index `base`.
struct Chunk<'b> {
    buffer: &'b wgpu::Buffer,
    window: (u64, u64),
    base: u32,
    first: u64,
    count: u64,
}

/// The nets of a window of faces, bound as group 0 for the output vertices before `end` (and
/// from the previous window's `end`), which read only those faces' nets.
struct NetWindow {
    end: u64,
    group: wgpu::BindGroup,
}

/// The GPU implementation of [`Evaluator`]: made once per [`Plan`], evaluates its frames.
///
/// ```no_run
/// use tessella_core::refine::{Evaluator, Plan};
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gpu::{AdapterChoice, GpuContext, GpuEvaluator, GpuOutput};
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let mesh = samples::icosphere(1);
/// let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 8))?;
/// let mut frame = plan.frame(&mesh)?;
/// let mut gpu = GpuEvaluator::new(&ctx, &plan)?;
/// let (indices, format) = gpu.index_buffer(&plan)?; // once per topology
/// for t in 0..3 {
///     let s = 1.0 + 0.1 * t as f32;
///     let moved: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| s * c)).collect();
///     plan.update(&mut frame, &moved, None)?;
///     gpu.evaluate(&plan, &frame, GpuOutput::Own)?; // uploads nets only, then one dispatch
///     // draw gpu.vertex_buffer() with `indices` (format `format`) ...
/// }
/// # Ok::<(), tessella_gpu::GpuError>(())
/// ```
pub struct GpuEvaluator {
    ctx: GpuContext,
    pipelines: Pipelines,
    /// Identifies the plan: its sizes and its basis size.
    plan_key: (PlanSizes, usize),
    patches: PatchBuffers,
    /// Group 0 per window of output vertices: one window binding all nets when they fit one
    /// binding, else windows whose faces' nets do.
    nets: Vec<NetWindow>,
    mesh_u32: wgpu::Buffer,
    mesh_f32: wgpu::Buffer,
    params: RefineParams,
    format: VertexFormat,
    max_chunk_items: Option<u32>,
    own: Option<wgpu::Buffer>,
    own_indices: Option<(wgpu::Buffer, IndexWidth)>,
    /// Bytes the last [`Evaluator::evaluate`] wrote to the GPU.
    uploaded: u64,
    normal_mode: NormalMode,
    coarse_vertices: usize,
    /// `true` once the plan's UVs are in `mesh_f32` (a CPU frame's upload, or
    /// [`GpuEvaluator::write_uvs`]); always for a plan without UVs.
    uvs_written: bool,
}

impl std::fmt::Debug for GpuEvaluator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuEvaluator")
            .field("vertices", &self.plan_key.0.vertices)
            .field("triangles", &self.plan_key.0.triangles)
            .finish()
    }
}

impl GpuEvaluator {
    /// Compiles the kernels and uploads the plan's stencil and tables (once).
    pub fn new(ctx: &GpuContext, plan: &Plan) -> Result<GpuEvaluator, GpuError> {
        GpuEvaluator::with_options(ctx, plan, &GpuRefineOptions::default())
    }

    /// [`GpuEvaluator::new`] with displacement and a chunk-size cap.
    pub fn with_options(
        ctx: &GpuContext,
        plan: &Plan,
        options: &GpuRefineOptions,
    ) -> Result<GpuEvaluator, GpuError> {
        ctx.check_storage_buffers(
            "the GPU evaluator's compute pass",
            "compute",
            crate::context::COMPUTE_STORAGE_BUFFERS,
        )?;
        if plan.tiling().is_some() && options.displacement != Displacement::None {
            return Err(GpuError::BadOption(
                "displacement of adaptive and tessellator plans is not supported on the GPU \
                 compute path"
                    .into(),
            ));
        }
        let has_uv = plan.has_uvs();
        options.displacement.validate(has_uv)?;
        let format = output_format(plan, options.vertex_format)?;
        let layout = plan.layout();
        if layout.triangle_count > u32::MAX as u64 {
            return Err(GpuError::TooLarge {
                what: "the refined triangle count",
                bytes: layout.triangle_count * 12,
                limit: u32::MAX as u64 * 12,
            });
        }
        let (u32s, mut params) = match plan.tiling() {
            None => index_tables(plan),
            Some(tiling) => adaptive_tables(plan, tiling),
        };
        let word = |o: Option<usize>| o.map_or(NONE, |o| o as u32);
        params.out_stride = format.stride as u32;
        params.out_position = format.position as u32;
        params.out_normal = word(format.normal);
        params.out_uv = word(format.uv);
        let f32_len = coarse_f32_len(plan);
        let limit = ctx.max_binding();
        for (what, bytes) in [
            ("the mesh's index tables", u32s.len() as u64 * 4),
            ("the mesh's vertex data", f32_len as u64 * 4),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        let basis = plan.options().scheme.basis();
        let faces = plan.face_count();
        let blank = PatchNets {
            basis,
            normal_mode: plan.normal_mode(),
            points: vec![[0.0; 3]; faces * basis.len()],
            normals: vec![[0.0; 3]; faces * 6],
        };
        // An adaptive plan: every distinct tile's stencil rows and pattern, one after the other
        // (the lookup table's rows count across them).
        let (weights, patterns): (std::borrow::Cow<[f32]>, Vec<&Pattern>) = match plan.tiling() {
            None => (
                plan.stencil().weights.as_slice().into(),
                vec![plan.pattern()],
            ),
            Some(tiling) => (
                tiling
                    .tiles
                    .iter()
                    .flat_map(|t| t.stencil.weights.iter().copied())
                    .collect::<Vec<f32>>()
                    .into(),
                tiling.tiles.iter().map(|t| &t.pattern).collect(),
            ),
        };
        ctx.scoped(|| {
            let key = format!(
                "refine|{}|{}",
                normal_mode_code(plan.normal_mode()),
                crate::displace::kind_code(&options.displacement)
            );
            let pipelines = ctx.pipelines(&key, || {
                Pipelines::new(ctx, plan.normal_mode(), &options.displacement)
            })?;
            let patches = PatchBuffers::new(
                ctx,
                &weights,
                &blank,
                &options.displacement,
                &crate::canonical::edge_table(
                    basis,
                    &patterns,
                    &plan
                        .tiling()
                        .map_or(vec![], |t| t.tiles.iter().map(|t| t.morph).collect()),
                    plan.triangles(),
                    &plan.topology().position_ids,
                ),
                true,
            )?;
            let nets = net_windows(ctx, plan, &u32s, &params, &patches, &pipelines, options)?;
            let copy = wgpu::BufferUsages::COPY_DST;
            let none = wgpu::BufferUsages::empty();
            let mesh_u32 = ctx.storage_buffer("mesh u32", bytemuck::cast_slice(&u32s), none);
            let zeros = vec![0.0f32; f32_len];
            let mesh_f32 = ctx.storage_buffer("mesh f32", bytemuck::cast_slice(&zeros), copy);
            Ok(GpuEvaluator {
                ctx: ctx.clone(),
                pipelines,
                plan_key: plan_key(plan),
                patches,
                nets,
                mesh_u32,
                mesh_f32,
                params,
                format,
                max_chunk_items: options.max_chunk_items,
                own: None,
                own_indices: None,
                uploaded: 0,
                normal_mode: plan.normal_mode(),
                coarse_vertices: plan.coarse_vertex_count(),
                uvs_written: !has_uv,
            })
        })?
    }

    /// Bytes the last [`Evaluator::evaluate`] uploaded: the frame's control nets and coarse
    /// vertices (and displacement face records), O(coarse) whatever the plan's levels; the
    /// stencils, lookup and topology tables were uploaded once, by [`GpuEvaluator::new`].
    pub fn uploaded_bytes(&self) -> u64 {
        self.uploaded
    }

    /// The layout of the output vertices ([`GpuRefineOptions::vertex_format`]).
    pub fn vertex_format(&self) -> VertexFormat {
        self.format
    }

    /// Floats per output vertex: the format's stride.
    pub fn vertex_stride(&self) -> usize {
        self.format.stride
    }

    /// Bytes one frame's vertices take.
    pub fn vertex_bytes(&self) -> u64 {
        self.plan_key.0.vertices as u64 * self.vertex_stride() as u64 * 4
    }

    /// The evaluator's own vertex buffer, once [`GpuOutput::Own`] was evaluated into.
    pub fn vertex_buffer(&self) -> Option<&wgpu::Buffer> {
        self.own.as_ref()
    }

    /// Copies the evaluator's own vertex buffer back (waits for the GPU): `vertex_stride()`
    /// floats per vertex.
    #[cfg(feature = "blocking")]
    pub fn read_back(&self) -> Result<Vec<f32>, GpuError> {
        let own = self.own_or_err()?;
        let bytes = self.ctx.read_buffer(own, 0, own.size())?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// [`GpuEvaluator::read_back`] without blocking (the web's form; see
    /// [`GpuContext::map_and_copy_async`]).
    pub async fn read_back_async(&self) -> Result<Vec<f32>, GpuError> {
        let own = self.own_or_err()?;
        let bytes = self.ctx.read_buffer_async(own, 0, own.size()).await?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    fn own_or_err(&self) -> Result<&wgpu::Buffer, GpuError> {
        self.own.as_ref().ok_or_else(|| {
            GpuError::BadOutput("nothing evaluated into the evaluator's own buffer yet".into())
        })
    }

    /// An index buffer (`INDEX | COPY_SRC`) holding the plan's refined triangles, `u16` when
    /// [`Plan::fits_u16`], else `u32`; made on first call and kept (indices do not change
    /// between frames).
    pub fn index_buffer(
        &mut self,
        plan: &Plan,
    ) -> Result<(&wgpu::Buffer, wgpu::IndexFormat), GpuError> {
        self.check_plan(plan)?;
        if self.own_indices.is_none() {
            let width = IndexWidth::for_plan(plan);
            let size = width.buffer_bytes(plan);
            let buffer = self.ctx.scoped(|| {
                self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("refined indices"),
                    size: size.max(4),
                    usage: wgpu::BufferUsages::INDEX
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            })?;
            self.write_indices(plan, &buffer, 0, width)?;
            self.own_indices = Some((buffer, width));
        }
        let (buffer, width) = self.own_indices.as_ref().expect("made above");
        Ok((buffer, width.format()))
    }

    /// Writes the plan's refined triangles into the caller's `buffer` from byte `offset` (a
    /// multiple of 4) as `width` integers. Needs `COPY_DST` usage and room for
    /// `triangles × 3 × width` bytes (rounded up to 4). Call once per topology.
    pub fn write_indices(
        &self,
        plan: &Plan,
        buffer: &wgpu::Buffer,
        offset: u64,
        width: IndexWidth,
    ) -> Result<(), GpuError> {
        self.check_plan(plan)?;
        let bytes: Vec<u8> = match width {
            IndexWidth::U32 => bytemuck::cast_slice(plan.indices()).to_vec(),
            IndexWidth::U16 => {
                let mut out = vec![[0u16; 3]; plan.triangle_count()];
                plan.write_indices(&mut out)?;
                let mut bytes = bytemuck::cast_slice::<_, u8>(&out).to_vec();
                bytes.resize(bytes.len().next_multiple_of(4), 0);
                bytes
            }
        };
        check_buffer(
            buffer,
            offset,
            bytes.len() as u64,
            wgpu::BufferUsages::COPY_DST,
        )?;
        self.ctx
            .scoped(|| self.ctx.queue.write_buffer(buffer, offset, &bytes))
    }

    fn check_plan(&self, plan: &Plan) -> Result<(), GpuError> {
        if plan_key(plan) != self.plan_key {
            return Err(GpuError::BadOption(
                "this GPU evaluator was made for another plan".into(),
            ));
        }
        Ok(())
    }

    /// Uploads the frame's coarse data: nets, positions, normals, UVs. O(coarse triangles).
    /// Returns the bytes written.
    fn upload(&self, plan: &Plan, frame: &Frame) -> Result<u64, GpuError> {
        self.check_plan(plan)?;
        plan.check_frame(frame)?;
        let mesh = frame.mesh();
        let mut coarse: Vec<f32> = Vec::with_capacity(coarse_f32_len(plan));
        coarse.extend(mesh.positions().iter().flatten());
        coarse.extend(mesh.normals().iter().flatten());
        if let Some(uvs) = mesh.uvs() {
            coarse.extend(uvs.iter().flatten());
        }
        self.ctx
            .queue
            .write_buffer(&self.mesh_f32, 0, bytemuck::cast_slice(&coarse));
        let mut bytes = coarse.len() as u64 * 4;
        if self.patches.displaced() {
            let faces = face_frames(mesh, &plan.topology().position_ids);
            bytes += self.patches.update_displace_faces(&self.ctx, &faces);
        }
        Ok(bytes + self.patches.update_nets(&self.ctx, frame.nets()))
    }

    /// Items one chunk may hold, from the dispatch limit and the caller's cap.
    fn item_cap(&self) -> u64 {
        let dispatch = self.ctx.limits.max_compute_workgroups_per_dimension as u64 * WORKGROUP;
        let cap = self.max_chunk_items.map_or(u64::MAX, |c| c.max(1) as u64);
        dispatch.min(cap)
    }

    /// Splits `total` vertices written into `buffer` from byte `offset` into chunks, each
    /// with a binding window within the device's binding limit and offset alignment.
    fn vertex_chunks<'b>(
        &self,
        buffer: &'b wgpu::Buffer,
        offset: u64,
        total: u64,
    ) -> Result<Vec<Chunk<'b>>, GpuError> {
        let stride = self.format.stride as u64 * 4;
        let align = self.ctx.limits.min_storage_buffer_offset_alignment.max(4) as u64;
        let max_binding = self.ctx.max_binding() / 4 * 4;
        let mut chunks = Vec::new();
        let mut first = 0;
        while first < total {
            let start = offset + first * stride;
            let window_start = start / align * align;
            let window_len = max_binding.min(buffer.size() - window_start) / 4 * 4;
            let fit = window_len.saturating_sub(start - window_start) / stride;
            let count = fit
                .min(self.item_cap())
                .min(total - first)
                .min(self.net_window(first).1 - first);
            if count == 0 {
                return Err(GpuError::TooLarge {
                    what: "one refined vertex",
                    bytes: stride + align,
                    limit: max_binding,
                });
            }
            chunks.push(Chunk {
                buffer,
                window: (window_start, window_len),
                base: ((start - window_start) / 4) as u32,
                first,
                count,
            });
            first += count;
        }
        Ok(chunks)
    }

    /// The net window of output vertex `vertex`: its index in `nets` and its end.
    fn net_window(&self, vertex: u64) -> (usize, u64) {
        let i = self
            .nets
            .partition_point(|w| w.end <= vertex)
            .min(self.nets.len() - 1);
        (i, self.nets[i].end)
    }

    /// Records one dispatch of `pipeline` over `chunk`.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, chunk: &Chunk, vertices: bool) {
        let params = RefineParams {
            first: chunk.first as u32,
            count: chunk.count as u32,
            out_base: chunk.base,
            ..self.params
        };
        let params_buffer = self.ctx.buffer_init(
            "refine params",
            bytemuck::bytes_of(&params),
            wgpu::BufferUsages::UNIFORM,
        );
        let window = wgpu::BufferBinding {
            buffer: chunk.buffer,
            offset: chunk.window.0,
            size: wgpu::BufferSize::new(chunk.window.1),
        };
        let group = self
            .ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("refine"),
                layout: &self.pipelines.refine_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: params_buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: self.mesh_u32.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: self.mesh_f32.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Buffer(window),
                    },
                ],
            });
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(if vertices {
            &self.pipelines.vertices
        } else {
            &self.pipelines.indices
        });
        // The index kernel reads no nets: any window will do.
        let (window, end) = if vertices {
            self.net_window(chunk.first)
        } else {
            (0, 0)
        };
        debug_assert!(!vertices || chunk.first + chunk.count <= end);
        pass.set_bind_group(0, &self.nets[window].group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups(chunk.count.div_ceil(WORKGROUP) as u32, 1, 1);
    }

    fn own_buffer(&mut self) -> Result<&wgpu::Buffer, GpuError> {
        if self.own.is_none() {
            let size = self.vertex_bytes().max(4);
            let limit = self.ctx.limits.max_buffer_size;
            if size > limit {
                return Err(GpuError::TooLarge {
                    what: "the refined vertices",
                    bytes: size,
                    limit,
                });
            }
            let buffer = self.ctx.scoped(|| {
                self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("refined vertices"),
                    size,
                    usage: wgpu::BufferUsages::VERTEX
                        | wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            })?;
            self.own = Some(buffer);
        }
        Ok(self.own.as_ref().expect("made above"))
    }
}

impl GpuEvaluator {
    /// Uploads the frame's coarse data (`queue.write_buffer`, so it lands before the next
    /// submission) and records into the caller's `encoder` the dispatches that write its
    /// vertices into `out`; the caller submits the encoder, with its own passes after (a draw
    /// reading the buffer). Record one frame per submission: a second `record` before the
    /// submit overwrites the first frame's coarse data. An unusable output buffer, or work
    /// wgpu rejects, is an `Err` (checked in error scopes of tessella's own, which the
    /// caller's work does not enter).
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        plan: &Plan,
        frame: &Frame,
        out: GpuOutput<'_>,
    ) -> Result<(), GpuError> {
        self.check_plan(plan)?;
        plan.check_frame(frame)?;
        let (buffer, offset) = self.output(out)?;
        let chunks = self.vertex_chunks(&buffer, offset, plan.vertex_count() as u64)?;
        self.uploaded = self.upload(plan, frame)?;
        self.uvs_written = true;
        self.ctx.scoped(|| {
            for chunk in &chunks {
                self.encode(encoder, chunk, true);
            }
        })
    }

    /// The evaluator's nets and coarse vertices, for a [`GpuNetBuilder`](crate::GpuNetBuilder)
    /// to write from coarse vertices already on the GPU; then
    /// [`GpuEvaluator::record_built`] evaluates them. Refused with displacement (its per-face
    /// records are made on the CPU from each frame's mesh: [`GpuEvaluator::record`] with a CPU
    /// frame is the path there). The builder writes the nets through one binding: nets over
    /// the device's binding limit are refused by its `record` ([`GpuError::TooLarge`]).
    pub fn nets_target(&self) -> Result<crate::NetsTarget<'_>, GpuError> {
        self.check_built()?;
        Ok(crate::NetsTarget {
            points: &self.patches.points,
            normals: &self.patches.normals,
            faces: self.patches.face_count as usize,
            k: self.plan_key.1,
            normal_mode: self.normal_mode,
            coarse: Some(crate::net_builder::CoarseCopy {
                buffer: &self.mesh_f32,
                vertices: self.coarse_vertices,
                positions_at: self.params.positions_at,
                normals_at: self.params.normals_at,
            }),
        })
    }

    /// [`GpuEvaluator::record`] for a frame whose nets and coarse vertices a
    /// [`GpuNetBuilder`](crate::GpuNetBuilder) recorded into [`GpuEvaluator::nets_target`]
    /// earlier in the same encoder (or submission): records the dispatches that write the
    /// plan's vertices into `out` and uploads no coarse data. A plan with UVs needs them
    /// written once first ([`GpuEvaluator::write_uvs`], or any [`GpuEvaluator::record`]).
    pub fn record_built(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        plan: &Plan,
        out: GpuOutput<'_>,
    ) -> Result<(), GpuError> {
        self.check_plan(plan)?;
        self.check_built()?;
        if !self.uvs_written {
            return Err(GpuError::BadOption(
                "the plan has texture coordinates and none were written yet: call write_uvs \
                 once (the nets builder writes positions and normals only)"
                    .into(),
            ));
        }
        let (buffer, offset) = self.output(out)?;
        let chunks = self.vertex_chunks(&buffer, offset, plan.vertex_count() as u64)?;
        self.uploaded = 0;
        self.ctx.scoped(|| {
            for chunk in &chunks {
                self.encode(encoder, chunk, true);
            }
        })
    }

    /// Writes the coarse texture coordinates that [`GpuEvaluator::record_built`] interpolates
    /// (one per coarse vertex; they do not move with the mesh, so once); returns the bytes
    /// written.
    pub fn write_uvs(&mut self, plan: &Plan, uvs: &[[f32; 2]]) -> Result<u64, GpuError> {
        self.check_plan(plan)?;
        if !plan.has_uvs() {
            return Err(GpuError::BadOption(
                "the plan's mesh has no texture coordinates".into(),
            ));
        }
        if uvs.len() != self.coarse_vertices {
            return Err(GpuError::BadOption(format!(
                "{} texture coordinates for {} coarse vertices",
                uvs.len(),
                self.coarse_vertices
            )));
        }
        let bytes: &[u8] = bytemuck::cast_slice(uvs);
        let at = u64::from(self.params.uvs_at) * 4;
        self.ctx
            .scoped(|| self.ctx.queue.write_buffer(&self.mesh_f32, at, bytes))?;
        self.uvs_written = true;
        Ok(bytes.len() as u64)
    }

    /// Refuses GPU-built nets on a displaced evaluator.
    fn check_built(&self) -> Result<(), GpuError> {
        if self.patches.displaced() {
            return Err(GpuError::BadOption(
                "a displaced GPU evaluator reads per-face records made on the CPU from each \
                 frame's mesh, so its nets cannot be built on the GPU; record CPU frames with \
                 record(), or evaluate without displacement"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The buffer and byte offset `out` names, checked.
    fn output(&mut self, out: GpuOutput<'_>) -> Result<(wgpu::Buffer, u64), GpuError> {
        match out {
            GpuOutput::Own => Ok((self.own_buffer()?.clone(), 0)),
            GpuOutput::Buffer { buffer, offset } => {
                check_buffer(
                    buffer,
                    offset,
                    self.vertex_bytes(),
                    wgpu::BufferUsages::STORAGE,
                )?;
                Ok((buffer.clone(), offset))
            }
        }
    }
}

impl Evaluator for GpuEvaluator {
    type Output<'a> = GpuOutput<'a>;
    type Error = GpuError;

    /// The convenience beside [`GpuEvaluator::record`]: records the frame into an encoder of
    /// its own and submits it, without waiting for the GPU (commands the caller submits
    /// afterwards run after it).
    fn evaluate(&mut self, plan: &Plan, frame: &Frame, out: GpuOutput<'_>) -> Result<(), GpuError> {
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        self.record(&mut encoder, plan, frame, out)?;
        self.ctx.submit(encoder).map(|_| ())
    }
}

/// The evaluator's output format: the caller's, checked against the plan, or the default.
fn output_format(plan: &Plan, wanted: Option<VertexFormat>) -> Result<VertexFormat, GpuError> {
    let Some(format) = wanted else {
        return Ok(if plan.has_uvs() {
            VertexFormat::POSITION_NORMAL_UV
        } else {
            VertexFormat::POSITION_NORMAL
        });
    };
    format.validate()?;
    if format.uv.is_some() && !plan.has_uvs() {
        return Err(GpuError::BadOption(
            "the vertex format asks for texture coordinates and the mesh has none".into(),
        ));
    }
    Ok(format)
}

/// Refuses a caller buffer without `usage`, with a misaligned offset, or too small.
fn check_buffer(
    buffer: &wgpu::Buffer,
    offset: u64,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> Result<(), GpuError> {
    if !buffer.usage().contains(usage) {
        return Err(GpuError::BadOutput(format!(
            "the buffer's usage {:?} lacks {usage:?}",
            buffer.usage()
        )));
    }
    if !offset.is_multiple_of(4) {
        return Err(GpuError::BadOutput(format!(
            "offset {offset} is not a multiple of 4"
        )));
    }
    if offset.saturating_add(bytes) > buffer.size() {
        return Err(GpuError::BadOutput(format!(
            "{bytes} bytes from offset {offset} do not fit a buffer of {} bytes",
            buffer.size()
        )));
    }
    Ok(())
}

/// Refines on the GPU: the same vertices (to float rounding) and the same indices as
/// [`Refiner::refine`]. A thin wrapper over [`GpuEvaluator`] that also computes the indices on
/// the GPU and reads everything back.
///
/// ```no_run
/// use tessella_core::{samples, RefineOptions, Refiner, Scheme};
/// use tessella_gpu::{gpu_refine, AdapterChoice, GpuContext};
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let mesh = samples::icosphere(1);
/// let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, 8))?;
/// let out = gpu_refine(&ctx, &refiner)?;
/// assert_eq!(out.triangles.len(), mesh.face_count() * 64);
/// # Ok::<(), tessella_gpu::GpuError>(())
/// ```
#[cfg(feature = "blocking")]
pub fn gpu_refine(ctx: &GpuContext, refiner: &Refiner) -> Result<RefinedMesh, GpuError> {
    gpu_refine_with(ctx, refiner, &GpuRefineOptions::default())
}

/// [`gpu_refine`] with displacement and chunk-size options. Outputs larger than one GPU buffer
/// are refined chunk by chunk through a scratch buffer.
#[cfg(feature = "blocking")]
pub fn gpu_refine_with(
    ctx: &GpuContext,
    refiner: &Refiner,
    options: &GpuRefineOptions,
) -> Result<RefinedMesh, GpuError> {
    let plan = refiner.plan();
    // Read back in the default format, which the loop below unpacks.
    let options = GpuRefineOptions {
        vertex_format: None,
        ..options.clone()
    };
    let gpu = GpuEvaluator::with_options(ctx, plan, &options)?;
    gpu.upload(plan, refiner.frame())?;
    let layout = *plan.layout();
    let floats = gpu.vertex_stride() as u64;
    let item_cap = gpu.item_cap();
    let limit = ctx.max_binding().min(ctx.limits.max_buffer_size);
    let vertex_chunk = (limit / (floats * 4))
        .min(item_cap)
        .min(layout.vertex_count)
        .max(1);
    let triangle_chunk = (limit / 12).min(item_cap).min(layout.triangle_count).max(1);
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let scratch = |label, size| {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let (out_vertices, out_indices) = ctx.scoped(|| {
        (
            scratch("out vertices", vertex_chunk * floats * 4),
            scratch("out indices", triangle_chunk * 12),
        )
    })?;
    let nv = layout.vertex_count as usize;
    let mut out = RefinedMesh {
        positions: Vec::with_capacity(nv),
        normals: Vec::with_capacity(nv),
        uvs: plan.has_uvs().then(|| Vec::with_capacity(nv)),
        triangles: Vec::with_capacity(layout.triangle_count as usize),
    };

    // Every chunk is one dispatch plus a copy into a staging buffer; dispatches are batched
    // into as few submissions as the staging size cap allows (each submission costs a wait).
    // An adaptive plan's triangles are the plan's own (no index kernel for tiles).
    let adaptive = plan.tiling().is_some();
    let triangle_total = if adaptive { 0 } else { layout.triangle_count };
    let mut jobs = Vec::new();
    for (vertices, total, chunk, item_bytes) in [
        (true, layout.vertex_count, vertex_chunk, floats * 4),
        (false, triangle_total, triangle_chunk, 12),
    ] {
        let mut first = 0;
        while first < total {
            let mut count = chunk.min(total - first);
            if vertices {
                count = count.min(gpu.net_window(first).1 - first);
            }
            jobs.push((vertices, first, count, count * item_bytes));
            first += count;
        }
    }
    let staging_cap = STAGING_BYTES.min(ctx.limits.max_buffer_size);
    let mut batch_start = 0;
    while batch_start < jobs.len() {
        let mut batch_end = batch_start;
        let mut bytes = 0;
        while batch_end < jobs.len()
            && (batch_end == batch_start || bytes + jobs[batch_end].3 <= staging_cap)
        {
            bytes += jobs[batch_end].3;
            batch_end += 1;
        }
        let batch = &jobs[batch_start..batch_end];
        let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("refine readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        let mut offset = 0;
        for &(vertices, first, count, size) in batch {
            let output = if vertices {
                &out_vertices
            } else {
                &out_indices
            };
            let chunk = Chunk {
                buffer: output,
                window: (0, output.size()),
                base: 0,
                first,
                count,
            };
            gpu.encode(&mut encoder, &chunk, vertices);
            encoder.copy_buffer_to_buffer(output, 0, &staging, offset, size);
            offset += size;
        }
        ctx.submit_and_wait(encoder)?;
        // Copied into u32s so the casts below are aligned.
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&ctx.map_and_copy(&staging)?);
        let mut offset = 0;
        for &(vertices, _, _, size) in batch {
            let part = &words[(offset / 4) as usize..((offset + size) / 4) as usize];
            offset += size;
            if vertices {
                let floats: &[f32] = bytemuck::cast_slice(part);
                for v in floats.chunks_exact(gpu.vertex_stride()) {
                    out.positions.push([v[0], v[1], v[2]]);
                    out.normals.push([v[3], v[4], v[5]]);
                    if let Some(uvs) = out.uvs.as_mut() {
                        uvs.push([v[6], v[7]]);
                    }
                }
            } else {
                out.triangles
                    .extend(part.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
            }
        }
        batch_start = batch_end;
    }
    if adaptive {
        out.triangles.extend_from_slice(plan.indices());
    }
    Ok(out)
}

/// The coarse face whose net output vertex `g` is evaluated from (`None`: none, a coarse vertex
/// no face uses), read from the plan's tables as `refine.wgsl` reads them.
fn vertex_face(u32s: &[u32], p: &RefineParams, g: u64) -> Option<u64> {
    let g = g as usize;
    let owner = |at: u32, i: usize| match u32s[at as usize + i] {
        NONE => None,
        o => Some(o as u64 >> 2),
    };
    if p.adaptive != 0 {
        return match u32s[p.lookup_at as usize + g * 2] {
            NONE => None,
            f => Some(f as u64),
        };
    }
    let g32 = g as u32;
    if p.weld == 0 {
        return Some((g32 / p.points_per_face) as u64);
    }
    if g32 < p.input_vertices {
        owner(p.vertex_owner_at, g)
    } else if g32 < p.interior_base {
        owner(
            p.edge_owner_at,
            ((g32 - p.edge_base) / (p.level - 1)) as usize,
        )
    } else {
        Some(((g32 - p.interior_base) / p.interior_per_face) as u64)
    }
}

/// Group 0 for every window of output vertices: all nets in one window when they fit one
/// binding (and `max_net_faces`), else consecutive vertex ranges whose faces span few enough
/// faces for their nets to fit one binding window, bound from an aligned offset.
fn net_windows(
    ctx: &GpuContext,
    plan: &Plan,
    u32s: &[u32],
    params: &RefineParams,
    patches: &PatchBuffers,
    pipelines: &Pipelines,
    options: &GpuRefineOptions,
) -> Result<Vec<NetWindow>, GpuError> {
    let total = plan.vertex_count() as u64;
    let faces = plan.face_count() as u64;
    let point_bytes = plan.options().scheme.basis().len() as u64 * 12;
    let normal_bytes = crate::gpu_types::NORMAL_NET_BYTES;
    let face_bytes = point_bytes.max(normal_bytes);
    let cap = options.max_net_faces.map_or(u64::MAX, |c| c.max(1) as u64);
    let limit = ctx.max_binding() / 4 * 4;
    if faces * face_bytes <= limit && faces <= cap {
        return Ok(vec![NetWindow {
            end: total,
            group: patches.bind_group(ctx, &pipelines.patch_layout, &[]),
        }]);
    }
    let align = ctx.limits.min_storage_buffer_offset_alignment.max(4) as u64;
    let per_window = (limit.saturating_sub(align) / face_bytes).min(cap);
    if per_window == 0 {
        return Err(GpuError::TooLarge {
            what: "one coarse face's control net",
            bytes: face_bytes + align,
            limit,
        });
    }
    let mut windows = Vec::new();
    let mut push = |end: u64, (lo, hi): (u64, u64)| {
        let range = |bytes: u64, buffer: &wgpu::Buffer| {
            let start = lo * bytes / align * align;
            (start, ((hi + 1) * bytes).min(buffer.size()) - start)
        };
        let points = range(point_bytes, &patches.points);
        let normals = range(normal_bytes, &patches.normals);
        let eval = crate::gpu_types::EvalParams {
            points_base: (points.0 / 4) as u32,
            normals_base: (normals.0 / 4) as u32,
            ..patches.eval_params
        };
        let eval = ctx.buffer_init(
            "eval params (net window)",
            bytemuck::bytes_of(&eval),
            wgpu::BufferUsages::UNIFORM,
        );
        let group =
            patches.bind_group_window(ctx, &pipelines.patch_layout, &eval, (points, normals), &[]);
        windows.push(NetWindow { end, group });
    };
    let mut span: Option<(u64, u64)> = None;
    for g in 0..total {
        let Some(f) = vertex_face(u32s, params, g) else {
            continue;
        };
        span = match span {
            None => Some((f, f)),
            Some((lo, hi)) if hi.max(f) - lo.min(f) < per_window => Some((lo.min(f), hi.max(f))),
            Some(old) => {
                push(g, old);
                Some((f, f))
            }
        };
    }
    push(total, span.unwrap_or((0, 0)));
    Ok(windows)
}

fn plan_key(plan: &Plan) -> (PlanSizes, usize) {
    (plan.sizes(), plan.options().scheme.basis().len())
}

/// Floats of a frame's coarse data in `mesh_f32`: positions, normals, UVs.
fn coarse_f32_len(plan: &Plan) -> usize {
    plan.coarse_vertex_count() * if plan.has_uvs() { 8 } else { 6 }
}

const NONE: u32 = u32::MAX;

/// The refinement kernels' own WGSL: `RefineParams` printed from its Rust twin, then
/// `refine.wgsl`.
pub(crate) fn refine_wgsl() -> String {
    RefineParams::wgsl() + include_str!("shaders/refine.wgsl")
}

/// Everything `refine.wgsl` reads from `mesh_u32` (fixed per plan), and the offsets of both
/// tables.
fn index_tables(plan: &Plan) -> (Vec<u32>, RefineParams) {
    let layout = plan.layout();
    let stencil = plan.stencil();
    let pattern = plan.pattern();
    let topo = plan.topology();
    let level = layout.level;
    let mut u32s: Vec<u32> = Vec::new();
    let at = |data: &mut dyn Iterator<Item = u32>, u32s: &mut Vec<u32>| {
        let start = u32s.len() as u32;
        u32s.extend(data);
        start
    };
    let nv = plan.coarse_vertex_count();
    let mut p = RefineParams {
        level,
        weld: layout.weld as u32,
        input_vertices: nv as u32,
        edge_base: layout.edge_base as u32,
        interior_base: layout.interior_base as u32,
        interior_per_face: Pattern::interior_count(level) as u32,
        points_per_face: Pattern::point_count(level) as u32,
        has_uv: plan.has_uvs() as u32,
        ..Default::default()
    };
    p.triangles_at = at(&mut plan.triangles().iter().flatten().copied(), &mut u32s);
    p.vertex_owner_at = at(
        &mut topo
            .vertex_owner
            .iter()
            .map(|o| o.map_or(NONE, |(f, c)| f * 4 + c as u32)),
        &mut u32s,
    );
    p.edge_owner_at = at(
        &mut topo.edge_owner.iter().map(|&(f, k)| f * 4 + k as u32),
        &mut u32s,
    );
    p.edges_at = at(&mut topo.edges.iter().flatten().copied(), &mut u32s);
    p.face_edges_at = at(&mut topo.face_edges.iter().flatten().copied(), &mut u32s);
    p.corner_points_at = at(&mut (0..3).map(|c| stencil.corner_point(c)), &mut u32s);
    p.edge_points_at = at(
        &mut stencil.edge_points.iter().flatten().copied(),
        &mut u32s,
    );
    p.interior_points_at = at(&mut stencil.interior_points.iter().copied(), &mut u32s);
    p.point_codes_at = at(
        &mut point_codes(stencil, pattern.points.len()).into_iter(),
        &mut u32s,
    );
    p.pattern_triangles_at = at(&mut pattern.triangles.iter().flatten().copied(), &mut u32s);
    p.positions_at = 0;
    p.normals_at = (nv * 3) as u32;
    p.uvs_at = (nv * 6) as u32;
    (u32s, p)
}

/// What `refine.wgsl` reads from `mesh_u32` for an adaptive plan: the coarse triangles and, per
/// output vertex, the face that evaluates it and its row in the tiles' concatenated stencil
/// (`row | (corner + 1) << 30` for a corner, whose position is copied from the input), or
/// `NONE` and the vertex for a coarse vertex no face uses. Slots and owners are those of
/// tessella-core's adaptive layout: welded = corners (owner face) | each edge's points from the
/// lower vertex index (owner face) | each face's interior; soup = each face's points.
fn adaptive_tables(plan: &Plan, tiling: &Tiling) -> (Vec<u32>, RefineParams) {
    let topo = plan.topology();
    let tris = plan.triangles();
    let weld = plan.layout().weld;
    let nv = plan.coarse_vertex_count();
    let mut row0 = Vec::with_capacity(tiling.tiles.len());
    let mut rows = 0u32;
    for t in &tiling.tiles {
        row0.push(rows);
        rows += t.pattern.points.len() as u32;
    }
    let mut u32s: Vec<u32> = tris.iter().flatten().copied().collect();
    let lookup_at = u32s.len();
    u32s.resize(lookup_at + plan.vertex_count() * 2, NONE);
    let mut set = |slot: u64, face: usize, word: u32| {
        let i = lookup_at + slot as usize * 2;
        u32s[i] = face as u32;
        u32s[i + 1] = word;
    };
    let corner = |c: usize| (c as u32 + 1) << 30;
    for f in 0..tris.len() {
        let tile = tiling.tile(f);
        let r = row0[tiling.face_tile[f] as usize];
        let base = tiling.face_offset[f];
        if !weld {
            for p in 0..tile.pattern.points.len() {
                let flag = match tile.pattern.classes[p] {
                    PointClass::Corner { corner: c } => corner(c as usize),
                    _ => 0,
                };
                set(base + p as u64, f, (r + p as u32) | flag);
            }
            continue;
        }
        for (i, &p) in tile.interior.iter().enumerate() {
            set(base + i as u64, f, r + p);
        }
    }
    if weld {
        for v in 0..nv {
            match topo.vertex_owner[v] {
                Some((f, c)) => {
                    let f = f as usize;
                    let r = row0[tiling.face_tile[f] as usize];
                    let p = tiling.tile(f).corners[c as usize];
                    set(v as u64, f, (r + p) | corner(c as usize));
                }
                None => set(v as u64, NONE as usize, v as u32),
            }
        }
        for (e, &(f, k)) in topo.edge_owner.iter().enumerate() {
            let (f, k) = (f as usize, k as usize);
            let tile = tiling.tile(f);
            let r = row0[tiling.face_tile[f] as usize];
            let by_index = tris[f][k] == topo.edges[e][0];
            let m = tile.edges[k].len();
            for (s, &p) in tile.edges[k].iter().enumerate() {
                let slot = if by_index { s } else { m - 1 - s };
                set(tiling.edge_offset[e] + slot as u64, f, r + p);
            }
        }
    }
    let params = RefineParams {
        level: plan.layout().level,
        weld: weld as u32,
        input_vertices: nv as u32,
        has_uv: plan.has_uvs() as u32,
        triangles_at: 0,
        positions_at: 0,
        normals_at: (nv * 3) as u32,
        uvs_at: (nv * 6) as u32,
        adaptive: 1,
        lookup_at: lookup_at as u32,
        ..Default::default()
    };
    (u32s, params)
}

/// Per pattern point, its class as `refine.wgsl` decodes it: `class << 30 | edge << 28 | index`
/// with class 0 = corner (index = corner), 1 = edge (index = step - 1), 2 = interior.
fn point_codes(stencil: &tessella_core::Stencil, points: usize) -> Vec<u32> {
    let mut codes = vec![0u32; points];
    for c in 0..3 {
        codes[stencil.corner_point(c) as usize] = c as u32;
    }
    for (k, edge) in stencil.edge_points.iter().enumerate() {
        for (s, &p) in edge.iter().enumerate() {
            codes[p as usize] = 1 << 30 | (k as u32) << 28 | s as u32;
        }
    }
    for (i, &p) in stencil.interior_points.iter().enumerate() {
        codes[p as usize] = 2 << 30 | i as u32;
    }
    codes
}
