//! Control nets built on the GPU from coarse vertices the caller already has there (an
//! engine's own skinning output, [`CoarseInput`]): one compute dispatch, one thread per face,
//! running the net builders generated from the CPU's own Rust
//! ([`tessella_core::shader::net_builder`]) and writing the nets where a renderer or the
//! evaluator reads them ([`NetsTarget`]). Nothing crosses the bus per frame.
//!
//! Flat, Phong, PN and PN-AEN nets are built here (with either normal net); PNG1, the
//! scalar-tagged and the quadratic schemes read more than a face's corners and its neighbours'
//! normals and stay on the CPU (`update(frame)` with the frame's CPU nets).

use crate::coarse::{CoarseInput, CoarseStream};
use crate::context::{GpuContext, READ, UNIFORM, WRITE};
use crate::error::GpuError;
use crate::gpu_types::NetsParams;
use std::sync::Mutex;
use tessella_core::refine::Surface;
use tessella_core::scheme::pn_aen;
use tessella_core::shader::{self, Lang, NetBuilder};
use tessella_core::{Basis, NormalMode, Scheme};

/// Threads per workgroup (`@workgroup_size(64)` in `shaders/nets.wgsl`).
const WORKGROUP: u64 = 64;

/// Storage buffers the builder binds in the compute stage.
const NETS_STORAGE_BUFFERS: u32 = 6;

/// Where [`GpuNetBuilder::record`] writes a frame's nets: the nets buffers of a renderer or
/// evaluator, from [`crate::PatternRenderer::nets_target`],
/// [`crate::AdaptiveRenderer::nets_target`] or [`crate::GpuEvaluator::nets_target`], in the
/// layout of [`tessella_core::PatchNets`].
#[derive(Debug, Clone, Copy)]
pub struct NetsTarget<'a> {
    pub(crate) points: &'a wgpu::Buffer,
    pub(crate) normals: &'a wgpu::Buffer,
    pub(crate) faces: usize,
    pub(crate) k: usize,
    pub(crate) normal_mode: NormalMode,
    /// The evaluator's copy of the coarse vertices (its corners copy them).
    pub(crate) coarse: Option<CoarseCopy<'a>>,
}

/// Where the evaluator keeps a frame's coarse positions and normals (`refine.wgsl`'s
/// `mesh_f32`): float indices of vertex 0's.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CoarseCopy<'a> {
    pub buffer: &'a wgpu::Buffer,
    pub vertices: usize,
    pub positions_at: u32,
    pub normals_at: u32,
}

impl<'a> NetsTarget<'a> {
    /// Nets in the caller's own buffers (`STORAGE`; `COPY_SRC` to read them back), laid out
    /// as [`tessella_core::PatchNets`] of the cubic basis: `faces * 10` control points and
    /// `faces * 6` normal-net entries, three `f32` each, from byte 0. `normal_mode` is the one
    /// the builder was made for.
    pub fn new(
        points: &'a wgpu::Buffer,
        normals: &'a wgpu::Buffer,
        faces: usize,
        normal_mode: NormalMode,
    ) -> NetsTarget<'a> {
        NetsTarget {
            points,
            normals,
            faces,
            k: Basis::Cubic.len(),
            normal_mode,
            coarse: None,
        }
    }

    /// Patches (coarse triangles) the target holds.
    pub fn faces(&self) -> usize {
        self.faces
    }
    /// Control points per patch.
    pub fn control_points(&self) -> usize {
        self.k
    }
    /// The normal mode the target's consumer draws with.
    pub fn normal_mode(&self) -> NormalMode {
        self.normal_mode
    }
}

/// The compute pipeline of one (scheme, normal net), shared through the context's cache.
#[derive(Clone)]
struct Pipelines {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// The schemes whose nets the GPU builds, as the pipeline key and the WGSL glue name them.
#[derive(Debug, Clone, Copy, PartialEq)]
enum GpuScheme {
    Flat,
    Phong,
    Pn,
    PnAen,
}

impl GpuScheme {
    fn of(scheme: &Scheme) -> Result<GpuScheme, GpuError> {
        // The mapping is the core's (NetBuilder::points_for), shared with WebGL2's net pass.
        match NetBuilder::points_for(scheme) {
            Some(NetBuilder::FlatPoints) => Ok(GpuScheme::Flat),
            Some(NetBuilder::PhongPoints) => Ok(GpuScheme::Phong),
            Some(NetBuilder::PnPoints) => Ok(GpuScheme::Pn),
            Some(NetBuilder::PnAenPoints) => Ok(GpuScheme::PnAen),
            _ => Err(GpuError::BadOption(format!(
                "the GPU builds the control nets of the flat, phong, pn and pn-aen schemes; \
                 '{}' nets are built on the CPU: hand the renderer or evaluator the frame's \
                 CPU nets (update(frame) / record) instead",
                scheme.name()
            ))),
        }
    }

    fn builder(self) -> NetBuilder {
        match self {
            GpuScheme::Flat => NetBuilder::FlatPoints,
            GpuScheme::Phong => NetBuilder::PhongPoints,
            GpuScheme::Pn => NetBuilder::PnPoints,
            GpuScheme::PnAen => NetBuilder::PnAenPoints,
        }
    }

    /// The call `nets.wgsl` makes for a face's points.
    fn points_call(self) -> &'static str {
        match self {
            GpuScheme::Flat => "    return tessella_flat_points(p, n);\n",
            GpuScheme::Phong => "    return tessella_phong_points(p, n, params.alpha);\n",
            GpuScheme::Pn => "    return tessella_pn_points(p, n);\n",
            GpuScheme::PnAen => {
                "    var m: array<vec3<f32>, 6>;\n    \
                 for (var j = 0u; j < 6u; j++) {\n        \
                 m[j] = coarse_normal(topology[params.across_at + face * 6u + j]);\n    }\n    \
                 return tessella_pn_aen_points(p, n, m);\n"
            }
        }
    }
}

/// The normal net a mode builds (the core's [`NetBuilder::normals_for`]).
fn normal_builder(mode: NormalMode) -> NetBuilder {
    NetBuilder::normals_for(mode)
}

impl Pipelines {
    fn new(ctx: &GpuContext, scheme: GpuScheme, normals: NetBuilder) -> Pipelines {
        let compute = wgpu::ShaderStages::COMPUTE;
        let layout = ctx.buffer_layout(
            "nets",
            &[
                (compute, UNIFORM),
                (compute, READ),
                (compute, READ),
                (compute, READ),
                (compute, WRITE),
                (compute, WRITE),
                (compute, WRITE),
            ],
        );
        let source = source(scheme, normals);
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("nets.wgsl"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("nets"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = ctx
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("tessella_build_nets"),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some("tessella_build_nets"),
                compilation_options: Default::default(),
                cache: None,
            });
        Pipelines { layout, pipeline }
    }
}

/// The net-building kernel's WGSL for `scheme`'s points and the `normals` net: the core's
/// generated builders, the two calls `nets.wgsl` makes, then `nets.wgsl`.
fn source(scheme: GpuScheme, normals: NetBuilder) -> String {
    let k = Basis::Cubic.len();
    [
        crate::wgsl_constants::source(),
        format!("const TESSELLA_NETS_K: u32 = {k}u;\n"),
        shader::net_builder(Lang::Wgsl, scheme.builder()),
        shader::net_builder(Lang::Wgsl, normals),
        format!(
            "fn tessella_nets_points(face: u32, p: array<vec3<f32>, 3>, n: array<vec3<f32>, 3>) -> array<vec3<f32>, {k}> {{\n{}}}\n",
            scheme.points_call()
        ),
        format!(
            "fn tessella_nets_normals(p: array<vec3<f32>, 3>, n: array<vec3<f32>, 3>) -> array<vec3<f32>, 6> {{\n    return {}(p, n);\n}}\n",
            normals.function_name()
        ),
        NetsParams::wgsl(),
        include_str!("shaders/nets.wgsl").to_string(),
    ]
    .join("\n")
}

/// [`source`] for `scheme` with the quadratic normal net (for the uniform twins' test).
#[cfg(test)]
pub(crate) fn source_for(scheme: &Scheme) -> String {
    let gpu = GpuScheme::of(scheme).expect("a scheme whose nets the GPU builds");
    source(gpu, NetBuilder::QuadraticNormals)
}

/// Builds a surface's control nets on the GPU from coarse vertices in the caller's storage
/// buffers ([`CoarseInput`]), into a renderer's or the evaluator's nets ([`NetsTarget`]):
/// the nets equal the CPU's ([`tessella_core::scheme::build_nets`]) within f32 rounding.
///
/// Made once per [`Surface`] (the triangles, and PN-AEN's neighbour table
/// [`pn_aen::across_table`], are uploaded then); [`GpuNetBuilder::record`] records one dispatch
/// per frame into the caller's encoder and uploads nothing (zero bytes per frame; only a
/// change of the input's layout writes a 48-byte uniform). Record it before the consumer's
/// pass in the same encoder (or an earlier submission).
///
/// Flat, Phong, PN and PN-AEN, with either normal net; other schemes are refused
/// ([`GpuError::BadOption`]) and keep their CPU nets. The normals are normalised in `f32`; a
/// zero normal gives its faces NaN nets (the CPU refuses such a mesh).
///
/// ```no_run
/// # fn demo(ctx: &tessella_gpu::GpuContext, skinned: &wgpu::Buffer,
/// #         renderer: &tessella_gpu::PatternRenderer,
/// #         surface: &tessella_core::refine::Surface) -> Result<(), tessella_gpu::GpuError> {
/// use tessella_gpu::{CoarseInput, CoarseStream, GpuNetBuilder};
/// // Once: the surface's triangles (and PN-AEN's neighbours) go to the GPU.
/// let builder = GpuNetBuilder::new(ctx, surface)?;
/// // Every frame: the engine's interleaved vertices (normal at byte 0, position at 16, 32
/// // bytes a vertex) become the renderer's nets, before its draw.
/// let input = CoarseInput {
///     positions: CoarseStream { buffer: skinned, offset: 0, stride: 32, first: 16 },
///     normals: CoarseStream { buffer: skinned, offset: 0, stride: 32, first: 0 },
/// };
/// let mut encoder = ctx.device.create_command_encoder(&Default::default());
/// builder.record(&mut encoder, input, renderer.nets_target()?)?;
/// // ... the render pass with renderer.draw(...), then submit.
/// # Ok(()) }
/// ```
pub struct GpuNetBuilder {
    ctx: GpuContext,
    pipelines: Pipelines,
    scheme: Scheme,
    normal_mode: NormalMode,
    faces: usize,
    vertices: usize,
    across_at: u32,
    /// The triangles, then (PN-AEN) the across table.
    topology: wgpu::Buffer,
    /// Bound as `out_coarse` when the target keeps no coarse copy.
    placeholder: wgpu::Buffer,
    /// The last uniform written and its buffer: rewritten only when the input's layout or the
    /// target changes.
    params: Mutex<Option<(NetsParams, wgpu::Buffer)>>,
}

impl std::fmt::Debug for GpuNetBuilder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuNetBuilder")
            .field("scheme", &self.scheme)
            .field("normal_mode", &self.normal_mode)
            .field("faces", &self.faces)
            .finish()
    }
}

impl GpuNetBuilder {
    /// Whether the GPU builds `scheme`'s nets (flat, Phong, PN, PN-AEN): an engine picks its
    /// posing path with it before making a builder.
    pub fn builds(scheme: &Scheme) -> bool {
        GpuScheme::of(scheme).is_ok()
    }

    /// Compiles (or takes from the context's cache) the pipeline of the surface's scheme and
    /// normal mode and uploads its triangles and, for PN-AEN, its neighbour table. Refuses the
    /// schemes the GPU does not build.
    pub fn new(ctx: &GpuContext, surface: &Surface) -> Result<GpuNetBuilder, GpuError> {
        let scheme = surface.options().scheme;
        let gpu_scheme = GpuScheme::of(&scheme)?;
        ctx.check_storage_buffers("the GPU net builder", "compute", NETS_STORAGE_BUFFERS)?;
        let triangles = surface.triangles();
        let mut words: Vec<u32> = triangles.iter().flatten().copied().collect();
        let across_at = words.len();
        if gpu_scheme == GpuScheme::PnAen {
            words.extend(
                pn_aen::across_table(triangles, surface.topology())
                    .iter()
                    .flatten(),
            );
        }
        let limit = ctx.max_binding().min(u32::MAX as u64);
        let bytes = words.len() as u64 * 4;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: "the coarse triangles (and PN-AEN's neighbours)",
                bytes,
                limit,
            });
        }
        let normal_mode = surface.normal_mode();
        let normals = normal_builder(normal_mode);
        ctx.scoped(|| {
            let key = format!(
                "nets|{}|{}",
                gpu_scheme.builder().function_name(),
                normals.function_name()
            );
            let pipelines = ctx.pipelines(&key, || Pipelines::new(ctx, gpu_scheme, normals))?;
            let none = wgpu::BufferUsages::empty();
            Ok(GpuNetBuilder {
                topology: ctx.storage_buffer("nets topology", bytemuck::cast_slice(&words), none),
                placeholder: ctx.storage_buffer("nets placeholder", &[0; 4], none),
                ctx: ctx.clone(),
                pipelines,
                scheme,
                normal_mode,
                faces: surface.face_count(),
                vertices: surface.coarse_vertex_count(),
                across_at: across_at as u32,
                params: Mutex::new(None),
            })
        })?
    }

    /// Records into `encoder` the dispatch that builds the nets of the coarse vertices in
    /// `input` (one per vertex of the surface, in its vertex order) into `target`. Returns the
    /// bytes written to the GPU: 0, or 48 when the input's layout (or the target) changed since
    /// the last call. Refuses an input the streams' rules reject ([`CoarseStream`]'s: `STORAGE`
    /// usage, aligned offset, room for every vertex) and a target of another shape (faces,
    /// control points, normal mode) before recording anything; errors of the recorded work
    /// itself show when the caller submits.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        input: CoarseInput<'_>,
        target: NetsTarget<'_>,
    ) -> Result<u64, GpuError> {
        let Some(dispatch) = self.bind(input, target)? else {
            return Ok(0);
        };
        self.ctx.scoped(|| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("tessella nets"),
                timestamp_writes: None,
            });
            dispatch.dispatch(&mut pass);
        })?;
        Ok(dispatch.written)
    }

    /// What [`GpuNetBuilder::record`] checks and binds, without a pass: the dispatch to
    /// record into a compute pass the caller began ([`NetsDispatch::dispatch`]; many builders
    /// in one pass, after the pass that wrote `input`), or `None` when there is nothing to
    /// build. Refuses what `record` refuses.
    pub fn bind(
        &self,
        input: CoarseInput<'_>,
        target: NetsTarget<'_>,
    ) -> Result<Option<NetsDispatch>, GpuError> {
        self.check_target(&target)?;
        let align = self.ctx.limits.min_storage_buffer_offset_alignment;
        input
            .positions
            .check("the coarse positions", self.vertices, align)?;
        input
            .normals
            .check("the coarse normals", self.vertices, align)?;
        let threads = match target.coarse {
            Some(_) => self.faces.max(self.vertices),
            None => self.faces,
        } as u64;
        if threads == 0 || self.vertices == 0 {
            return Ok(None);
        }
        let limit = self.ctx.max_binding();
        let positions = binding(
            input.positions,
            self.vertices,
            limit,
            "the coarse positions",
        )?;
        let normals = binding(input.normals, self.vertices, limit, "the coarse normals")?;
        let groups = threads.div_ceil(WORKGROUP);
        let per_dimension = u64::from(self.ctx.limits.max_compute_workgroups_per_dimension).max(1);
        let (x, y) = (groups.min(per_dimension), groups.div_ceil(per_dimension));
        if y > per_dimension {
            return Err(GpuError::TooLarge {
                what: "the coarse faces' dispatch",
                bytes: threads,
                limit: per_dimension * per_dimension * WORKGROUP,
            });
        }
        let [positions_stride, positions_first] = input.positions.words();
        let [normals_stride, normals_first] = input.normals.words();
        let (copy_coarse, coarse_positions_at, coarse_normals_at) = match target.coarse {
            Some(c) => (1, c.positions_at, c.normals_at),
            None => (0, 0, 0),
        };
        let params = NetsParams {
            faces: self.faces as u32,
            vertices: self.vertices as u32,
            positions_stride,
            positions_first,
            normals_stride,
            normals_first,
            across_at: self.across_at,
            copy_coarse,
            coarse_positions_at,
            coarse_normals_at,
            alpha: match self.scheme {
                Scheme::Phong { alpha } => alpha,
                _ => 0.0,
            },
            _pad: 0,
        };
        self.ctx.scoped(|| {
            let (uniform, written) = self.params_buffer(params);
            let coarse = target.coarse.map_or(&self.placeholder, |c| c.buffer);
            let entries = [
                uniform.as_entire_binding(),
                self.topology.as_entire_binding(),
                positions,
                normals,
                target.points.as_entire_binding(),
                target.normals.as_entire_binding(),
                coarse.as_entire_binding(),
            ];
            let entries: Vec<_> = entries
                .into_iter()
                .enumerate()
                .map(|(i, resource)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource,
                })
                .collect();
            let group = self
                .ctx
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("nets"),
                    layout: &self.pipelines.layout,
                    entries: &entries,
                });
            Some(NetsDispatch {
                pipeline: self.pipelines.pipeline.clone(),
                group,
                groups: (x as u32, y as u32),
                written,
            })
        })
    }

    /// The scheme whose nets this builder makes.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The normal mode whose normal net this builder makes.
    pub fn normal_mode(&self) -> NormalMode {
        self.normal_mode
    }

    /// Refuses a target of another shape than the surface's nets.
    fn check_target(&self, target: &NetsTarget) -> Result<(), GpuError> {
        let k = Basis::Cubic.len();
        if (target.faces, target.k) != (self.faces, k) {
            return Err(GpuError::BadOption(format!(
                "the nets target holds {} patches of {} control points, the builder makes {} \
                 of {k}",
                target.faces, target.k, self.faces
            )));
        }
        if target.normal_mode != self.normal_mode {
            return Err(GpuError::BadOption(format!(
                "the nets target draws {:?} normals, the builder was made for {:?}",
                target.normal_mode, self.normal_mode
            )));
        }
        if let Some(c) = target.coarse {
            if c.vertices != self.vertices {
                return Err(GpuError::BadOption(format!(
                    "the nets target has {} coarse vertices, the builder's surface {}",
                    c.vertices, self.vertices
                )));
            }
        }
        let limit = self.ctx.max_binding();
        let bytes = (self.faces * k * 12) as u64;
        for (buffer, bytes) in [
            (target.points, bytes),
            (target.normals, (self.faces * 6 * 12) as u64),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge {
                    what: "the control nets built on the GPU (written through one binding)",
                    bytes,
                    limit,
                });
            }
            if !buffer.usage().contains(wgpu::BufferUsages::STORAGE) {
                return Err(GpuError::BadOption(format!(
                    "the nets target's buffer usage {:?} lacks STORAGE",
                    buffer.usage()
                )));
            }
            if bytes > buffer.size() {
                return Err(GpuError::BadOption(format!(
                    "the nets target's buffer has {} bytes, the nets need {bytes}",
                    buffer.size()
                )));
            }
        }
        Ok(())
    }

    /// The uniform holding `params`, and the bytes written for it: the last one again when it
    /// holds the same (nothing written), else a new one.
    fn params_buffer(&self, params: NetsParams) -> (wgpu::Buffer, u64) {
        // A panic while holding the lock cannot leave the slot half-written (one store).
        let mut slot = self.params.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((held, buffer)) = slot.as_ref() {
            if *held == params {
                return (buffer.clone(), 0);
            }
        }
        let bytes = bytemuck::bytes_of(&params);
        let buffer = self
            .ctx
            .buffer_init("nets params", bytes, wgpu::BufferUsages::UNIFORM);
        *slot = Some((params, buffer.clone()));
        (buffer, bytes.len() as u64)
    }
}

/// One net build, bound and checked ([`GpuNetBuilder::bind`]), to record into a compute pass.
#[derive(Debug)]
pub struct NetsDispatch {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    groups: (u32, u32),
    written: u64,
}

impl NetsDispatch {
    /// Records the build into `pass`.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
    }

    /// The bytes binding it wrote to the GPU: 0, or 48 when the input's layout (or the
    /// target) changed since the builder's last call.
    pub fn written(&self) -> u64 {
        self.written
    }
}

/// The bytes of `stream` its `vertices` span, bound from its offset (`vertices > 0`).
fn binding<'a>(
    stream: CoarseStream<'a>,
    vertices: usize,
    limit: u64,
    what: &'static str,
) -> Result<wgpu::BindingResource<'a>, GpuError> {
    let size = (vertices as u64 - 1) * u64::from(stream.stride) + u64::from(stream.first) + 12;
    if size > limit {
        return Err(GpuError::TooLarge {
            what,
            bytes: size,
            limit,
        });
    }
    Ok(wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer: stream.buffer,
        offset: stream.offset,
        size: wgpu::BufferSize::new(size),
    }))
}
