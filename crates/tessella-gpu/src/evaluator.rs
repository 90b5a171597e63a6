//! The compute path: refine on the GPU into the same vertex order and indices as the CPU
//! (tessella-core's `OutputLayout`), then read the result back.
//!
//! Outputs are produced in chunks, each no larger than one storage-buffer binding and one
//! dispatch's workgroup count, so any output that fits in CPU memory can be refined.

use crate::context::GpuContext;
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::gpu_types::RefineParams;
use crate::patch::{self, PatchBuffers};
use tessella_core::{Pattern, RefinedMesh, Refiner};

/// Threads per workgroup of both kernels (`@workgroup_size(64)` in `refine.wgsl`).
const WORKGROUP: u64 = 64;

/// Largest staging buffer for one batch of chunks read back together.
const STAGING_BYTES: u64 = 256 << 20;

#[derive(Debug, Clone, Copy)]
enum Job {
    Vertices,
    Indices,
}

/// Options of [`gpu_refine_with`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GpuRefineOptions {
    /// Applied to every output vertex after evaluation.
    pub displacement: Displacement,
    /// Caps the vertices or triangles per chunk below what the device allows (for tests of
    /// the chunking; `None` uses the device limits).
    pub max_chunk_items: Option<u32>,
}

/// The compiled refinement kernels, built once per [`GpuContext`].
pub(crate) struct Pipelines {
    patch_layout: wgpu::BindGroupLayout,
    refine_layout: wgpu::BindGroupLayout,
    vertices: wgpu::ComputePipeline,
    indices: wgpu::ComputePipeline,
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Pipelines {
        let patch_layout = patch::layout(ctx, wgpu::ShaderStages::COMPUTE);
        let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let read = wgpu::BufferBindingType::Storage { read_only: true };
        let write = wgpu::BufferBindingType::Storage { read_only: false };
        let refine_layout = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("refine"),
                entries: &[
                    buffer(0, wgpu::BufferBindingType::Uniform),
                    buffer(1, read),
                    buffer(2, read),
                    buffer(3, write),
                    buffer(4, write),
                ],
            });
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
                    patch::shader_source(include_str!("shaders/refine.wgsl")).into(),
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

/// Refines on the GPU: the same vertices (to float rounding) and the same indices as
/// [`Refiner::refine`].
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
pub fn gpu_refine(ctx: &GpuContext, refiner: &Refiner) -> Result<RefinedMesh, GpuError> {
    gpu_refine_with(ctx, refiner, &GpuRefineOptions::default())
}

/// [`gpu_refine`] with displacement and chunk-size options.
pub fn gpu_refine_with(
    ctx: &GpuContext,
    refiner: &Refiner,
    options: &GpuRefineOptions,
) -> Result<RefinedMesh, GpuError> {
    let mesh = refiner.mesh();
    let layout = *refiner.layout();
    let has_uv = mesh.uvs().is_some();
    options.displacement.validate(has_uv)?;
    if layout.triangle_count > u32::MAX as u64 {
        return Err(GpuError::TooLarge {
            what: "the refined triangle count",
            bytes: layout.triangle_count * 12,
            limit: u32::MAX as u64 * 12,
        });
    }
    let tables = Tables::new(refiner);
    let limit = ctx.max_binding();
    for (what, bytes) in [
        ("the mesh's index tables", tables.u32s.len() as u64 * 4),
        ("the mesh's vertex data", tables.f32s.len() as u64 * 4),
    ] {
        if bytes > limit {
            return Err(GpuError::TooLarge { what, bytes, limit });
        }
    }
    let pipelines = ctx.refine_pipelines();
    let patches = PatchBuffers::new(
        ctx,
        refiner.stencil(),
        refiner.nets(),
        &options.displacement,
    )?;
    let patch_group = patches.bind_group(ctx, &pipelines.patch_layout);
    let none = wgpu::BufferUsages::empty();
    let mesh_u32 = ctx.storage_buffer("mesh u32", bytemuck::cast_slice(&tables.u32s), none);
    let mesh_f32 = ctx.storage_buffer("mesh f32", bytemuck::cast_slice(&tables.f32s), none);

    // Chunk sizes: one binding, one dispatch, and the caller's cap.
    let floats_per_vertex: u64 = if has_uv { 8 } else { 6 };
    let dispatch_cap = ctx.limits.max_compute_workgroups_per_dimension as u64 * WORKGROUP;
    let cap = |bytes_per_item: u64| {
        let mut n = (limit / bytes_per_item).min(dispatch_cap);
        if let Some(c) = options.max_chunk_items {
            n = n.min(c.max(1) as u64);
        }
        n.max(1)
    };
    let vertex_chunk = cap(floats_per_vertex * 4).min(layout.vertex_count.max(1));
    let triangle_chunk = cap(12).min(layout.triangle_count.max(1));
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let out_vertices = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out vertices"),
        size: vertex_chunk * floats_per_vertex * 4,
        usage,
        mapped_at_creation: false,
    });
    let out_indices = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out indices"),
        size: triangle_chunk * 12,
        usage,
        mapped_at_creation: false,
    });
    let nv = layout.vertex_count as usize;
    let mut out = RefinedMesh {
        positions: Vec::with_capacity(nv),
        normals: Vec::with_capacity(nv),
        uvs: has_uv.then(|| Vec::with_capacity(nv)),
        triangles: Vec::with_capacity(layout.triangle_count as usize),
    };

    // Every chunk is one dispatch plus a copy into a staging buffer; dispatches are batched
    // into as few submissions as the staging size cap allows (each submission costs a wait).
    let mut jobs = Vec::new();
    for (kind, total, chunk, item_bytes) in [
        (
            Job::Vertices,
            layout.vertex_count,
            vertex_chunk,
            floats_per_vertex * 4,
        ),
        (Job::Indices, layout.triangle_count, triangle_chunk, 12),
    ] {
        let mut first = 0;
        while first < total {
            let count = chunk.min(total - first);
            jobs.push((kind, first, count, count * item_bytes));
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
        for &(kind, first, count, size) in batch {
            let params = RefineParams {
                first: first as u32,
                count: count as u32,
                ..tables.params
            };
            let params_buffer = ctx.buffer_init(
                "refine params",
                bytemuck::bytes_of(&params),
                wgpu::BufferUsages::UNIFORM,
            );
            let refine_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("refine"),
                layout: &pipelines.refine_layout,
                entries: &[
                    (0, &params_buffer),
                    (1, &mesh_u32),
                    (2, &mesh_f32),
                    (3, &out_vertices),
                    (4, &out_indices),
                ]
                .map(|(binding, b)| wgpu::BindGroupEntry {
                    binding,
                    resource: b.as_entire_binding(),
                }),
            });
            let (pipeline, output) = match kind {
                Job::Vertices => (&pipelines.vertices, &out_vertices),
                Job::Indices => (&pipelines.indices, &out_indices),
            };
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &patch_group, &[]);
                pass.set_bind_group(1, &refine_group, &[]);
                pass.dispatch_workgroups(count.div_ceil(WORKGROUP) as u32, 1, 1);
            }
            encoder.copy_buffer_to_buffer(output, 0, &staging, offset, size);
            offset += size;
        }
        ctx.submit_and_wait(encoder)?;
        // Copied into u32s so the casts below are aligned.
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&ctx.map_and_copy(&staging)?);
        let mut offset = 0;
        for &(kind, _, count, size) in batch {
            let bytes = &words[(offset / 4) as usize..((offset + size) / 4) as usize];
            offset += size;
            let c = count as usize;
            match kind {
                Job::Vertices => {
                    let floats: &[f32] = bytemuck::cast_slice(bytes);
                    out.positions
                        .extend(floats[..3 * c].chunks_exact(3).map(|v| [v[0], v[1], v[2]]));
                    out.normals.extend(
                        floats[3 * c..6 * c]
                            .chunks_exact(3)
                            .map(|v| [v[0], v[1], v[2]]),
                    );
                    if let Some(uvs) = out.uvs.as_mut() {
                        uvs.extend(floats[6 * c..8 * c].chunks_exact(2).map(|v| [v[0], v[1]]));
                    }
                }
                Job::Indices => {
                    let ints: &[u32] = bytemuck::cast_slice(bytes);
                    out.triangles
                        .extend(ints.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
                }
            }
        }
        batch_start = batch_end;
    }
    Ok(out)
}

/// Everything `refine.wgsl` reads besides group 0, packed into one `u32` and one `f32` array.
struct Tables {
    u32s: Vec<u32>,
    f32s: Vec<f32>,
    params: RefineParams,
}

const NONE: u32 = u32::MAX;

impl Tables {
    fn new(refiner: &Refiner) -> Tables {
        let mesh = refiner.mesh();
        let layout = refiner.layout();
        let stencil = refiner.stencil();
        let pattern = refiner.pattern();
        let level = layout.level;
        let mut u32s: Vec<u32> = Vec::new();
        let at = |data: &mut dyn Iterator<Item = u32>, u32s: &mut Vec<u32>| {
            let start = u32s.len() as u32;
            u32s.extend(data);
            start
        };
        let mut p = RefineParams {
            level,
            weld: layout.weld as u32,
            input_vertices: mesh.vertex_count() as u32,
            edge_base: layout.edge_base as u32,
            interior_base: layout.interior_base as u32,
            interior_per_face: Pattern::interior_count(level) as u32,
            points_per_face: Pattern::point_count(level) as u32,
            has_uv: mesh.uvs().is_some() as u32,
            ..Default::default()
        };
        p.triangles_at = at(&mut mesh.triangles().iter().flatten().copied(), &mut u32s);
        if let Some(topo) = refiner.topology() {
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
        }
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

        let mut f32s: Vec<f32> = mesh.positions().iter().flatten().copied().collect();
        p.normals_at = f32s.len() as u32;
        f32s.extend(mesh.normals().iter().flatten());
        p.uvs_at = f32s.len() as u32;
        if let Some(uvs) = mesh.uvs() {
            f32s.extend(uvs.iter().flatten());
        }
        Tables {
            u32s,
            f32s,
            params: p,
        }
    }
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
