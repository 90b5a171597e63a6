//! The draws evaluated once a frame: the refined surface's welded vertices evaluated by a
//! compute pass, which every render pass (shadow maps, prepass, main) then reads as it would a
//! static mesh's vertices. [`TessellaDraw::Mesh`](crate::TessellaDraw::Mesh) (the default)
//! writes each vertex's position and normal into the entity's own Bevy mesh, in Bevy's vertex
//! buffer (found each frame through Bevy's `MeshAllocator`: a mesh the allocator moved is
//! evaluated again), which Bevy's own shaders draw;
//! [`TessellaDraw::PerFrame`](crate::TessellaDraw::PerFrame) into the entity's slot of a
//! storage buffer that the tessellated material's vertex stages read.
//!
//! The kernel calls the same `tessella_point` the per-draw vertex stage calls (tessella-gpu's
//! exported module, rebound as the material's), over the same seven patch buffers the material
//! binds, so the two draws place the same points. It runs in the render world before Bevy's
//! own passes are recorded (`RenderSystems::PrepareResources`, after the frame's buffer
//! uploads), only for surfaces whose nets changed since their last evaluation: a still surface
//! is evaluated once. An entity posed on the GPU ([`GpuPose`]) has its coarse mesh skinned and
//! its nets built first, in the same submission, by tessella-gpu's `GpuSkinner` and
//! `GpuNetBuilder` writing the entity's net buffers.

use crate::animate::GpuPose;
use crate::material::{patch_module_of_for_bevy, NormalModeKey, FIRST_BINDING};
use crate::pattern::VERTEX_MESH_STRIDE;
use crate::pool::{Pools, Seat, EVALUATED_FLOATS};
use crate::surface::Surface;
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntry, BindGroupLayout, BindGroupLayoutEntry, BindingResource, BindingType,
    Buffer, BufferBinding, BufferBindingType, BufferId, BufferInitDescriptor, BufferUsages,
    ComputePassDescriptor, ComputePipeline, PipelineCompilationOptions, PipelineLayoutDescriptor,
    RawComputePipelineDescriptor, ShaderModuleDescriptor, ShaderSource, ShaderStages,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::storage::{GpuShaderBuffer, ShaderBuffer};
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderSystems};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use tessella_core::{Basis, NormalMode};
use tessella_gpu::{GpuContext, GpuNetBuilder, GpuSkinner, NetsDispatch, NetsTarget};

/// Threads a workgroup: 2^22 welded vertices at most ([`crate::WELDED_VERTICES`]) need 16,384
/// workgroups, inside the 65,535 one dimension of a dispatch allows.
const WORKGROUP: u32 = 256;

/// Binding of each welded vertex's origin (coarse triangle, pattern vertex) in the kernel's
/// group, after the patch group's seven.
const ORIGINS_BINDING: u32 = FIRST_BINDING + 7;

/// The material's patch buffers a per-frame job binds (stencil, nets, uniforms, displacement,
/// edge table), before its origins, output and placement.
pub const PATCH_BUFFERS: usize = 7;

/// Binding of the evaluated vertices: in the kernel's group, and in the material's (where the
/// coarse texture coordinates hold 107).
pub const EVALUATED_BINDING: u32 = FIRST_BINDING + 8;

/// Binding of the output's placement in the kernel's group: the first word written in the
/// bound range, the words from one vertex to the next (6 in a pool's slot; 8 in a mesh's
/// vertex buffer, whose uv the pass leaves alone) and the vertex count.
const PLACEMENT_BINDING: u32 = FIRST_BINDING + 9;

/// What the per-frame pass did since the app started, counted by the render world: the welded
/// vertices it evaluated (when it submits the pass: a still surface adds its vertices once, a
/// deforming one in every frame its nets change, a surface drawn otherwise never) and the bind
/// groups it made (one per surface and output place: a deforming surface reuses its own).
#[derive(Resource, Clone, Default, Debug)]
pub struct EvaluationStats {
    evaluated: Arc<AtomicU64>,
    bind_groups: Arc<AtomicU64>,
}

impl EvaluationStats {
    /// The welded vertices evaluated so far.
    pub fn evaluated_vertices(&self) -> u64 {
        self.evaluated.load(Ordering::Relaxed)
    }

    /// The bind groups the pass made so far.
    pub fn bind_groups_made(&self) -> u64 {
        self.bind_groups.load(Ordering::Relaxed)
    }
}

/// Frees the pool slots of entities that sit elsewhere now ([`Pools::release`]): runs before
/// `tessellate` seats this frame's.
pub(crate) fn release_slots(mut pools: ResMut<Pools>, seated: Query<&PerFrameSource>) {
    pools.release(|e| seated.get(e).ok().and_then(|s| s.target.seat()));
}

/// What the render world needs to evaluate an entity's surface: on the tessellated entity,
/// with its [`Surface`], whose version says when the nets changed.
#[derive(Component, Clone, Debug)]
pub(crate) struct PerFrameSource {
    /// The patch group's seven buffers (bindings 100 to 106), the material's.
    pub patch: [Handle<ShaderBuffer>; PATCH_BUFFERS],
    /// Per welded vertex, its coarse triangle and pattern vertex (two `u32`).
    pub origins: Handle<ShaderBuffer>,
    /// Where the evaluated vertices go.
    pub target: Target,
    pub mode: NormalModeKey,
    pub basis: Basis,
    pub vertices: u32,
}

/// Where an entity's evaluated vertices go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Target {
    /// A slot of its pool's buffer, [`EVALUATED_FLOATS`] floats a welded vertex, which the
    /// material's vertex stages read ([`crate::TessellaDraw::PerFrame`]).
    Slot(Seat),
    /// The position and normal of each vertex of its own Bevy mesh, in Bevy's vertex buffer
    /// ([`crate::TessellaDraw::Mesh`]: Bevy's own shaders read them).
    Mesh(AssetId<Mesh>),
}

impl Target {
    /// The pool slot, for [`Target::Slot`].
    pub fn seat(&self) -> Option<Seat> {
        match self {
            Target::Slot(seat) => Some(*seat),
            Target::Mesh(_) => None,
        }
    }
}

/// The kernel's WGSL for a normal mode and basis: the material's evaluation module for that
/// basis (its control points a constant: the sums unrolled), moved to group 0, then
/// tessella-gpu's entry evaluating one welded vertex a thread (`evaluation_entry`).
pub fn kernel_wgsl(mode: NormalMode, basis: Basis) -> String {
    let module = patch_module_of_for_bevy(mode, basis).replace("@group(3)", "@group(0)");
    let entry = tessella_gpu::wgsl::evaluation_entry(
        0,
        [ORIGINS_BINDING, EVALUATED_BINDING, PLACEMENT_BINDING],
        WORKGROUP,
    );
    format!("{module}\n{entry}")
}

/// The welded vertices' origins as the kernel reads them: per vertex, its coarse triangle and
/// its pattern vertex, from the welded mesh's `UV_1` (`(pattern vertex, triangle)`, exact in
/// `f32`).
pub(crate) fn origins_bytes(ids: &[[f32; 2]]) -> Vec<u8> {
    let origins: Vec<[u32; 2]> = ids.iter().map(|&[v, f]| [f as u32, v as u32]).collect();
    bytemuck::cast_slice(&origins).to_vec()
}

/// Adds the extraction and the evaluation to the render app (none without one: a headless
/// app with no renderer draws nothing to evaluate for).
pub(crate) fn register(app: &mut App) {
    let stats = app
        .world_mut()
        .get_resource_or_init::<EvaluationStats>()
        .clone();
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    render_app
        .insert_resource(stats)
        .init_resource::<Evaluations>()
        .add_systems(ExtractSchedule, extract)
        .add_systems(Render, evaluate.in_set(RenderSystems::PrepareResources));
}

/// The render world's evaluations: one kernel per normal mode and basis, made when first needed, and
/// per tessellated entity what it evaluates and which version of its nets it last did.
#[derive(Resource, Default)]
struct Evaluations {
    /// Bevy's device and queue as tessella-gpu's context (its own error scopes), made once.
    ctx: Option<GpuContext>,
    kernels: HashMap<(NormalModeKey, Basis), Result<Kernel, String>>,
    jobs: HashMap<Entity, Job>,
}

struct Kernel {
    pipeline: ComputePipeline,
    layout: BindGroupLayout,
}

struct Job {
    source: PerFrameSource,
    output: Output,
    version: u64,
    evaluated: Option<u64>,
    /// Where the last evaluation wrote (the buffer, the bound range's first byte, the
    /// placement's words: first word, stride, vertex count) and the placement uniform it
    /// bound: a mesh that Bevy's allocator moved, or a new mesh, is evaluated again.
    placed: Option<(BufferId, u64, [u32; 4], Buffer)>,
    /// This frame's deform, for an entity posed on the GPU.
    pose: Option<GpuPose>,
    /// Its skinner and net builder, made at its first pose.
    posing: Option<Posing>,
    /// The bind group of its last evaluation and what it binds: made again only when a buffer
    /// or the output's range changes, not each frame its nets do.
    bound: Option<(BindKey, BindGroup)>,
}

/// What a job's bind group binds: the ids of its buffers (patch, origins, output, placement)
/// and the output's bound range.
#[derive(PartialEq)]
struct BindKey {
    buffers: [BufferId; PATCH_BUFFERS + 3],
    at: u64,
    size: u64,
}

/// Every element, or `None` where one is missing (or there are none): the per-frame lookups
/// without a `Vec`.
fn all_some<T: Copy, const N: usize>(items: [Option<T>; N]) -> Option<[T; N]> {
    let mut out = [(*items.first()?)?; N];
    for (o, item) in out.iter_mut().zip(items) {
        *o = item?;
    }
    Some(out)
}

struct Posing {
    skinner: GpuSkinner,
    builder: GpuNetBuilder,
}

/// A job's output as the render world finds it each frame.
#[derive(Clone, PartialEq)]
enum Output {
    /// Its pool's buffer and its slot's byte offset there.
    Slot(Handle<ShaderBuffer>, u64),
    /// Its own mesh, in Bevy's mesh allocator.
    Mesh(AssetId<Mesh>),
}

/// What [`extract`] reads of a per-frame entity.
type Extracted = (
    Entity,
    &'static PerFrameSource,
    &'static Surface,
    Option<&'static GpuPose>,
);

/// Copies each per-frame entity's source, output slot and nets version into the render
/// world; entities gone (or drawn otherwise now) lose their job. A new output (another slot,
/// or the pool's buffer grown) is evaluated again.
fn extract(
    mut evaluations: ResMut<Evaluations>,
    query: Extract<Query<Extracted>>,
    pools: Extract<Res<Pools>>,
) {
    let mut live = HashSet::new();
    for (entity, source, surface, pose) in &query {
        let output = match source.target {
            Target::Slot(seat) => {
                let Some(pool) = pools.0.get(&seat.pool) else {
                    continue; // not seated yet
                };
                Output::Slot(pool.buffer.clone(), pool.offset(seat.slot))
            }
            Target::Mesh(mesh) => Output::Mesh(mesh),
        };
        live.insert(entity);
        let job = evaluations.jobs.entry(entity).or_insert_with(|| Job {
            source: source.clone(),
            output: output.clone(),
            version: surface.version,
            evaluated: None,
            placed: None,
            pose: None,
            posing: None,
            bound: None,
        });
        if job.source.origins != source.origins || job.source.patch != source.patch {
            job.source = source.clone();
            job.evaluated = None;
            job.posing = None;
        }
        if job.output != output {
            job.output = output;
            job.evaluated = None;
        }
        job.version = surface.version;
        job.pose = pose.cloned();
    }
    evaluations.jobs.retain(|entity, _| live.contains(entity));
}

/// Records and submits the frame's evaluations in three compute passes whatever the number
/// of entities: the skinning of every entity posed on the GPU, then their net building, then
/// one dispatch per surface whose nets changed since its last evaluation (each pass costs a
/// software rasterizer's threads a synchronisation; a pass per entity and stage cost a crowd
/// of 100 about twice its frame). The submission precedes the frame's render passes on the
/// queue, and follows the frame's buffer writes (Bevy's uploads of the nets), so every pass
/// reads this frame's points. A surface whose buffers are not on the GPU yet waits for a
/// later frame.
fn evaluate(
    mut evaluations: ResMut<Evaluations>,
    buffers: Res<RenderAssets<GpuShaderBuffer>>,
    allocator: Res<MeshAllocator>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    stats: Res<EvaluationStats>,
) {
    let Evaluations { ctx, kernels, jobs } = &mut *evaluations;
    // tessella's own error scopes: a rejected kernel or dispatch is reported here, not by
    // Bevy's handler as an error of its frame.
    let ctx = ctx.get_or_insert_with(|| {
        GpuContext::from_device(device.wgpu_device().clone(), (**queue).clone())
    });
    // Each surface's kernel, bind group and vertex count; the posed ones' skinners and nets.
    let mut dispatches = Vec::new();
    let mut posed = Vec::new();
    for (entity, job) in jobs.iter_mut() {
        let source = &job.source;
        // Where the vertices go this frame: the buffer, the first byte and the bytes; the
        // first word written from there and the words a vertex.
        let (out, at, size, [first, stride]) = match &job.output {
            Output::Slot(handle, offset) => {
                let Some(b) = buffers.get(handle) else {
                    continue; // not uploaded yet
                };
                let bytes = u64::from(source.vertices) * (EVALUATED_FLOATS * 4) as u64;
                (&b.buffer, *offset, bytes, [0, EVALUATED_FLOATS as u32])
            }
            Output::Mesh(mesh) => {
                let Some(slice) = allocator.mesh_vertex_slice(mesh) else {
                    continue; // not allocated yet
                };
                // Bound from the storage-offset alignment below the mesh's first vertex.
                let start = u64::from(slice.range.start) * VERTEX_MESH_STRIDE;
                let align = u64::from(device.limits().min_storage_buffer_offset_alignment);
                let bound = start - start % align;
                let bytes = start - bound + u64::from(source.vertices) * VERTEX_MESH_STRIDE;
                let words = (VERTEX_MESH_STRIDE / 4) as u32;
                (
                    slice.buffer,
                    bound,
                    bytes,
                    [((start - bound) / 4) as u32, words],
                )
            }
        };
        let words = [first, stride, source.vertices, 0];
        let moved = job
            .placed
            .as_ref()
            .is_none_or(|(id, byte, held, _)| (*id, *byte, *held) != (out.id(), at, words));
        if job.evaluated == Some(job.version) && !moved {
            continue;
        }
        let kernel = kernels
            .entry((source.mode, source.basis))
            .or_insert_with(|| make_kernel(ctx, &device, source.mode, source.basis));
        let layout = match kernel {
            Ok(k) => &k.layout,
            Err(e) => {
                error!("tessella: cannot evaluate {entity} per frame: {e}");
                job.evaluated = Some(job.version);
                continue;
            }
        };
        let gpu: [Option<&Buffer>; PATCH_BUFFERS + 1] = std::array::from_fn(|i| {
            let handle = source.patch.get(i).unwrap_or(&source.origins);
            buffers.get(handle).map(|b| &b.buffer)
        });
        let Some(gpu) = all_some(gpu) else {
            continue; // not uploaded yet
        };
        if moved {
            let placement = device.create_buffer_with_data(&BufferInitDescriptor {
                label: Some("tessella placement"),
                contents: bytemuck::cast_slice(&words),
                usage: BufferUsages::UNIFORM,
            });
            job.placed = Some((out.id(), at, words, placement));
        }
        let Some((_, _, _, placement)) = &job.placed else {
            continue; // placed just above
        };
        if let Some(pose) = &job.pose {
            if let Some(nets) = pose_on_gpu(ctx, pose, &mut job.posing, (gpu[1], gpu[2])) {
                posed.push((*entity, nets));
            }
        }
        let key = BindKey {
            buffers: std::array::from_fn(|i| match gpu.get(i) {
                Some(b) => b.id(),
                None if i == gpu.len() => out.id(),
                None => placement.id(),
            }),
            at,
            size,
        };
        let group = match &job.bound {
            Some((bound, group)) if *bound == key => Ok(group.clone()),
            _ => {
                let output = BufferBinding {
                    buffer: out,
                    offset: at,
                    size: std::num::NonZero::new(size),
                };
                let entries: Vec<BindGroupEntry> = gpu
                    .iter()
                    .map(|b| b.as_entire_binding())
                    .chain([
                        BindingResource::Buffer(output),
                        placement.as_entire_binding(),
                    ])
                    .zip((0..PATCH_BUFFERS as u32).map(|b| FIRST_BINDING + b).chain([
                        ORIGINS_BINDING,
                        EVALUATED_BINDING,
                        PLACEMENT_BINDING,
                    ]))
                    .map(|(resource, binding)| BindGroupEntry { binding, resource })
                    .collect();
                let made =
                    ctx.scoped(|| device.create_bind_group("tessella per-frame", layout, &entries));
                if let Ok(group) = &made {
                    stats.bind_groups.fetch_add(1, Ordering::Relaxed);
                    job.bound = Some((key, group.clone()));
                }
                made
            }
        };
        match group {
            Ok(group) => dispatches.push(((source.mode, source.basis), group, source.vertices)),
            Err(e) => error!("tessella: cannot evaluate {entity} per frame: {e}"),
        }
        job.evaluated = Some(job.version);
    }
    if dispatches.is_empty() {
        return;
    }
    let mut encoder = device.create_command_encoder(&Default::default());
    let recorded = ctx.scoped(|| {
        if !posed.is_empty() {
            let mut skin = encoder.begin_compute_pass(&ComputePassDescriptor {
                label: Some("tessella skin"),
                ..Default::default()
            });
            for (entity, _) in &posed {
                if let Some(p) = jobs.get(entity).and_then(|j| j.posing.as_ref()) {
                    p.skinner.dispatch(&mut skin);
                }
            }
            drop(skin);
            let mut nets = encoder.begin_compute_pass(&ComputePassDescriptor {
                label: Some("tessella nets"),
                ..Default::default()
            });
            for (_, built) in &posed {
                built.dispatch(&mut nets);
            }
        }
        let mut pass = encoder.begin_compute_pass(&ComputePassDescriptor {
            label: Some("tessella per-frame evaluation"),
            ..Default::default()
        });
        let mut vertices = 0u64;
        for (key, group, count) in &dispatches {
            let Some(Ok(kernel)) = kernels.get(key) else {
                continue; // refused above, with its error
            };
            pass.set_pipeline(&kernel.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(count.div_ceil(WORKGROUP), 1, 1);
            vertices += u64::from(*count);
        }
        vertices
    });
    let submitted = recorded.and_then(|vertices| {
        ctx.scoped(|| queue.submit([encoder.finish()]))?;
        Ok(vertices)
    });
    match submitted {
        Ok(vertices) => {
            stats.evaluated.fetch_add(vertices, Ordering::Relaxed);
        }
        Err(e) => error!("tessella: the per-frame evaluation was refused: {e}"),
    }
}

/// Prepares the skinning and net building of an entity posed on the GPU, the nets written
/// into the material's buffers `nets` (points, normals) ahead of its evaluation: this frame's
/// matrices and weights written, its skinner (in `posing`) and its bound net build (returned)
/// ready to record. Where the GPU cannot (the skinner or builder refused, or their work), the
/// entity's flag is raised and the main world poses it on the CPU from the next frame.
fn pose_on_gpu(
    ctx: &GpuContext,
    pose: &GpuPose,
    posing: &mut Option<Posing>,
    nets: (
        &bevy::render::render_resource::Buffer,
        &bevy::render::render_resource::Buffer,
    ),
) -> Option<NetsDispatch> {
    if pose.refused.load(Ordering::Relaxed) || pose.matrices.is_empty() {
        return None; // posed on the CPU, or not posed yet (the nets are the rest pose's)
    }
    let plan = &pose.plan;
    let made = match posing.take() {
        Some(p) => Ok(p),
        None => GpuSkinner::new(ctx, &pose.poser).and_then(|skinner| {
            let builder = GpuNetBuilder::new(ctx, plan.surface())?;
            Ok(Posing { skinner, builder })
        }),
    };
    let done = made.and_then(|p| {
        p.skinner.update_matrices(&pose.matrices, &pose.weights)?;
        let target = NetsTarget::new(nets.0, nets.1, plan.face_count(), plan.normal_mode());
        let built = p.builder.bind(p.skinner.output(), target)?;
        Ok((p, built))
    });
    match done {
        Ok((p, built)) => {
            *posing = Some(p);
            built
        }
        Err(e) => {
            warn!("tessella: posing on the CPU, the GPU cannot: {e}");
            pose.refused.store(true, Ordering::Relaxed);
            None
        }
    }
}

/// The kernel of `mode` and `basis`: its bind group layout (the patch group's seven read-only buffers, the
/// origins, the output) and pipeline, inside tessella's error scopes.
fn make_kernel(
    ctx: &GpuContext,
    device: &RenderDevice,
    mode: NormalModeKey,
    basis: Basis,
) -> Result<Kernel, String> {
    let normal_mode = match mode {
        NormalModeKey::Linear => NormalMode::Linear,
        NormalModeKey::Quadratic => NormalMode::Quadratic,
        NormalModeKey::Real => NormalMode::Real,
    };
    let storage = |binding: u32, read_only: bool| BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::Buffer {
            ty: BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let placement = BindGroupLayoutEntry {
        binding: PLACEMENT_BINDING,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::Buffer {
            ty: BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let entries: Vec<BindGroupLayoutEntry> = (0..PATCH_BUFFERS as u32)
        .map(|b| storage(FIRST_BINDING + b, true))
        .chain([
            storage(ORIGINS_BINDING, true),
            storage(EVALUATED_BINDING, false),
            placement,
        ])
        .collect();
    ctx.scoped(|| {
        let layout = device.create_bind_group_layout("tessella per-frame", &entries);
        let module = device.create_and_validate_shader_module(ShaderModuleDescriptor {
            label: Some("tessella per-frame evaluation"),
            source: ShaderSource::Wgsl(kernel_wgsl(normal_mode, basis).into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&PipelineLayoutDescriptor {
            label: Some("tessella per-frame"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&RawComputePipelineDescriptor {
            label: Some("tessella per-frame evaluation"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("tessella_evaluate"),
            compilation_options: PipelineCompilationOptions::default(),
            cache: None,
        });
        Kernel { pipeline, layout }
    })
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernel of each normal mode and basis is valid WGSL for naga (the validator wgpu
    /// runs), binds its nine buffers in one group, and evaluates with the material's
    /// `tessella_point`, its sums bounded by the basis' control points.
    #[test]
    fn kernels_validate() {
        for (mode, basis) in [NormalMode::Linear, NormalMode::Quadratic, NormalMode::Real]
            .into_iter()
            .flat_map(|m| [(m, Basis::Cubic), (m, Basis::Png1)])
        {
            let source = kernel_wgsl(mode, basis);
            let fixed = format!("const TESSELLA_FIXED_K: u32 = {}u;", basis.len());
            assert!(source.contains(&fixed), "{mode:?} {basis:?}");
            assert_eq!(source.matches("@group(0) @binding(").count(), 10);
            assert!(!source.contains("@group(3)"));
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{mode:?}: {}", e.emit_to_string(&source)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::empty(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{mode:?}: {e:?}"));
        }
    }

    /// Origins swap the welded mesh's `(pattern vertex, triangle)` into `(triangle, pattern
    /// vertex)` words, exactly (the largest triangle a welded mesh names is under 2^24).
    #[test]
    fn origins_are_exact_words() {
        let ids = [[0.0, 0.0], [44.0, 16_777_215.0], [3.0, 9.0]];
        let words: Vec<[u32; 2]> = bytemuck::cast_slice(&origins_bytes(&ids)).to_vec();
        assert_eq!(words, vec![[0, 0], [16_777_215, 44], [9, 3]]);
    }
}
