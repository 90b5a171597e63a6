//! WGSL an engine composes into its own shaders: the refined point and normal of (coarse
//! triangle, pattern vertex), with the bind group it reads. The contract (bindings, function,
//! conventions) is written out in `docs/engine.md`; [`crate::PatternRenderer`] draws with the
//! same evaluation module (`shaders/eval.wgsl`).

use crate::context::GpuContext;
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::patch::{self, PatchBuffers};
use tessella_core::refine::{Frame, Plan};

/// Storage buffers the patch group binds in each stage that sees it (an engine's vertex
/// shader adds its own to these; WebGPU's default allows 8 per stage).
pub const PATCH_STORAGE_BUFFERS: u32 = 5;

/// The entry point an engine calls, appended to the evaluation module.
const ENTRY: &str = "
// tessella's exported entry point (docs/engine.md): the refined point of pattern vertex
// `vertex` on coarse triangle `face`.
struct TessellaPoint {
    position: vec3<f32>,
    normal: vec3<f32>,
    // The pattern vertex's barycentric coordinates on the coarse triangle (l1, l2, l3).
    barycentric: vec3<f32>,
}

fn tessella_point(face: u32, vertex: u32) -> TessellaPoint {
    let sp = tessella_eval_patch(face, vertex);
    return TessellaPoint(sp.position, sp.normal, sp.l);
}
";

/// The patch group of a plan, for an engine's own pipelines: the stencil (uploaded once) and
/// the control nets (uploaded per frame by [`PatchBindings::update`]), bound at the group
/// index the engine chose.
///
/// An engine draws `plan.pattern().triangles` as its index buffer (`u32`, one pattern per
/// coarse triangle: `instance_index` is the coarse triangle, `vertex_index` the pattern
/// vertex) and calls `tessella_point(instance, vertex)` from [`PatchBindings::wgsl`] in its
/// vertex shader.
pub struct PatchBindings {
    ctx: GpuContext,
    group_index: u32,
    normal_mode: tessella_core::NormalMode,
    basis: tessella_core::Basis,
    shape: (usize, usize),
    patches: PatchBuffers,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

impl std::fmt::Debug for PatchBindings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PatchBindings")
            .field("group", &self.group_index)
            .field("faces", &self.shape.0)
            .finish()
    }
}

impl PatchBindings {
    /// Uploads the plan's stencil and the frame's nets into a group visible to `visibility`
    /// (the engine's vertex stage, say), to be bound at `group_index` (0 to 3). Plans of one
    /// level only (an adaptive plan's tiles are [`crate::AdaptiveRenderer`]'s).
    pub fn new(
        ctx: &GpuContext,
        plan: &Plan,
        frame: &Frame,
        group_index: u32,
        visibility: wgpu::ShaderStages,
    ) -> Result<PatchBindings, GpuError> {
        check_one_level(plan)?;
        if group_index > 3 {
            return Err(GpuError::BadOption(format!(
                "bind group index {group_index}; WebGPU has groups 0 to 3"
            )));
        }
        plan.check_frame(frame)?;
        // The vertex stage may have no storage buffers at all (a downlevel flag).
        let stage = if visibility.contains(wgpu::ShaderStages::VERTEX) {
            "vertex"
        } else if visibility.contains(wgpu::ShaderStages::COMPUTE) {
            "compute"
        } else {
            "fragment"
        };
        ctx.check_storage_buffers("the exported patch group", stage, PATCH_STORAGE_BUFFERS)?;
        let basis = plan.options().scheme.basis();
        let edges = edge_table_of(plan);
        ctx.scoped(|| {
            let patches = PatchBuffers::new(
                ctx,
                &plan.stencil().weights,
                frame.nets(),
                &Displacement::None,
                &edges,
                false,
            )?;
            let layout = patch::layout(ctx, visibility, 0);
            let group = patches.bind_group(ctx, &layout, &[]);
            Ok(PatchBindings {
                ctx: ctx.clone(),
                group_index,
                normal_mode: plan.normal_mode(),
                basis,
                shape: (frame.nets().len(), basis.len()),
                patches,
                layout,
                group,
            })
        })?
    }

    /// The WGSL to put before the engine's own: `tessella_point` and what it calls, at
    /// `@group(group_index)`, bindings 0 to 6 (see `docs/engine.md`).
    pub fn wgsl(&self) -> String {
        patch_module_of(self.group_index, self.normal_mode, self.basis)
    }

    /// The group's layout, for the engine's pipeline layout at `group_index`.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// The bind group to set at `group_index`.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.group
    }

    /// The group's nets, for a [`GpuNetBuilder`](crate::GpuNetBuilder) to write from coarse
    /// vertices already on the GPU instead of [`PatchBindings::update`]'s upload.
    pub fn nets_target(&self) -> crate::NetsTarget<'_> {
        self.patches.nets_target(self.shape, self.normal_mode)
    }

    /// Writes the frame's control nets (`queue.write_buffer`: they land before the next
    /// submission); returns the bytes written.
    pub fn update(&self, frame: &Frame) -> Result<u64, GpuError> {
        patch::check_nets_shape(frame.nets(), self.shape)?;
        self.ctx
            .scoped(|| self.patches.update_nets(&self.ctx, frame.nets()))
    }
}

/// Refuses an adaptive plan: the exported module draws one pattern on every face.
fn check_one_level(plan: &Plan) -> Result<(), GpuError> {
    if plan.tiling().is_some() {
        return Err(GpuError::BadOption(
            "the exported WGSL module draws plans of one level; this plan has per-edge levels"
                .into(),
        ));
    }
    Ok(())
}

/// The canonical edge table of a plan of one level (its one pattern, no geomorphs).
fn edge_table_of(plan: &Plan) -> Vec<u32> {
    crate::canonical::edge_table(
        plan.options().scheme.basis(),
        &[plan.pattern()],
        &[],
        plan.triangles(),
        &plan.topology().position_ids,
    )
}

/// The patch group's contents, binding by binding (0 to 6: stencil, net points, net normals,
/// evaluation uniform, displacement uniform, displacement data, canonical edge table), for an
/// engine that makes the buffers itself (Bevy's material assets): the bytes
/// [`PatchBindings::new`] uploads. A deforming mesh rewrites bindings 1 and 2 per frame
/// (`frame.nets()`'s points and normals).
pub fn patch_bytes(plan: &Plan, frame: &Frame) -> Result<[Vec<u8>; 7], GpuError> {
    check_one_level(plan)?;
    plan.check_frame(frame)?;
    let nets = frame.nets();
    let basis = plan.options().scheme.basis();
    let edges = edge_table_of(plan);
    let eval = crate::gpu_types::EvalParams {
        k: basis.len() as u32,
        stride: tessella_core::Stencil::stride_for(basis.len()) as u32,
        face_count: nets.len() as u32,
        points_base: 0,
        normals_base: 0,
        _pad: [0; 3],
    };
    let (dparams, ddata) = crate::displace::gpu_data(&Displacement::None, nets.len());
    let bytes = |b: &[u8]| b.to_vec();
    Ok([
        bytes(bytemuck::cast_slice(&plan.stencil().weights)),
        bytes(bytemuck::cast_slice(&nets.points)),
        bytes(bytemuck::cast_slice(&nets.normals)),
        bytes(bytemuck::bytes_of(&eval)),
        bytes(bytemuck::bytes_of(&dparams)),
        bytes(bytemuck::cast_slice(&ddata)),
        bytes(bytemuck::cast_slice(&edges)),
    ])
}

/// The evaluation module (no displacement) with its bindings at `@group(group_index)`, and
/// `tessella_point`.
pub fn patch_module(group_index: u32, normal_mode: tessella_core::NormalMode) -> String {
    let source = patch::shader_source(ENTRY, normal_mode, &Displacement::None, None);
    source.replace("@group(0)", &format!("@group({group_index})"))
}

/// [`patch_module`] for the patches of one basis only: its number of control points is a
/// constant of the module rather than the uniform's, so the weighted sums have a constant
/// bound (what a per-frame evaluation kernel, compiled per surface kind, wants).
pub fn patch_module_of(
    group_index: u32,
    normal_mode: tessella_core::NormalMode,
    basis: tessella_core::Basis,
) -> String {
    let source = patch::shader_source(ENTRY, normal_mode, &Displacement::None, Some(basis));
    source.replace("@group(0)", &format!("@group({group_index})"))
}

/// The compute entry `tessella_evaluate` of an engine's per-frame evaluation, for a module
/// that holds `tessella_point` ([`patch_module`], [`patch_module_of`], [`PatchBindings::wgsl`]):
/// thread `i` evaluates welded vertex `i`, `tessella_origins[i]` = (coarse triangle, pattern
/// vertex), and writes its position and normal (six floats) from word
/// `tessella_placement.x + tessella_placement.y * i` of `tessella_evaluated`, for
/// `i < tessella_placement.z` (a stride of 6 packs the vertices; a larger one writes into a
/// vertex buffer with more attributes). Its bindings sit at `@group(group)`, numbered
/// `bindings` = origins (`array<vec2<u32>>`), evaluated (`array<f32>`, read-write), placement
/// (a `vec4<u32>` uniform); `workgroup` threads a workgroup, along x.
pub fn evaluation_entry(group: u32, bindings: [u32; 3], workgroup: u32) -> String {
    let [origins, evaluated, placement] = bindings;
    format!(
        "@group({group}) @binding({origins}) var<storage, read> tessella_origins: array<vec2<u32>>;
@group({group}) @binding({evaluated}) var<storage, read_write> tessella_evaluated: array<f32>;
@group({group}) @binding({placement}) var<uniform> tessella_placement: vec4<u32>;

@compute @workgroup_size({workgroup})
fn tessella_evaluate(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    if i >= tessella_placement.z || i >= arrayLength(&tessella_origins) {{
        return;
    }}
    let origin = tessella_origins[i];
    let point = tessella_point(origin.x, origin.y);
    let at = tessella_placement.x + tessella_placement.y * i;
    tessella_evaluated[at] = point.position.x;
    tessella_evaluated[at + 1u] = point.position.y;
    tessella_evaluated[at + 2u] = point.position.z;
    tessella_evaluated[at + 3u] = point.normal.x;
    tessella_evaluated[at + 4u] = point.normal.y;
    tessella_evaluated[at + 5u] = point.normal.z;
}}
"
    )
}

/// The adaptive evaluation module (levels per edge that change every frame, the module
/// [`AdaptiveRenderer`](crate::AdaptiveRenderer) draws with) for an engine's own vertex shader,
/// its bindings at `@group(group_index)`: 0 net points, 1 net normals (the nets' bytes as
/// [`patch_bytes`] gives them), 2 a uniform of [`adaptive_params_bytes`], 3 the per-face records
/// (`tessella_core::refine::instanced::frame_instances`' `records`). The caller's shader calls
/// `tessella_adaptive_point(code, instance)`, with `code` a vertex of one of
/// `tessella_core::refine::instanced::PartTable`'s parts (a point code) and `instance` the
/// instance drawing it (`face | side << 30`, `frame_instances`' `instances`); it returns the
/// position, normal and barycentric point. Points on a coarse edge get the same bits from both
/// faces.
pub fn adaptive_module(
    group_index: u32,
    basis: tessella_core::Basis,
    normal_mode: tessella_core::NormalMode,
    spacing: tessella_core::refine::Spacing,
) -> String {
    let source = [
        crate::adaptive::constants(basis, normal_mode, spacing),
        include_str!("shaders/adaptive.wgsl").to_string(),
    ]
    .join("\n");
    source.replace("@group(0)", &format!("@group({group_index})"))
}

/// The adaptive module's binding 2 (each edge's boundary control points and normal-net
/// entries for `basis`).
pub fn adaptive_params_bytes(basis: tessella_core::Basis) -> Vec<u8> {
    bytemuck::bytes_of(&crate::adaptive::params(basis)).to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgpu::naga;

    /// `source` parsed and validated by naga, or a panic with naga's message.
    fn validated(source: &str) -> naga::Module {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        module
    }

    /// Every name the module an engine includes declares (functions, structs, bindings,
    /// constants) is tessella's: `tessella_`, `Tessella` or `TESSELLA_`.
    #[test]
    fn the_exported_module_declares_only_prefixed_names() {
        for mode in [
            tessella_core::NormalMode::Quadratic,
            tessella_core::NormalMode::Real,
        ] {
            let source = patch_module(2, mode);
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
            let mut names: Vec<String> = Vec::new();
            names.extend(module.functions.iter().filter_map(|(_, f)| f.name.clone()));
            names.extend(module.types.iter().filter_map(|(_, t)| match t.inner {
                naga::TypeInner::Struct { .. } => t.name.clone(),
                _ => None,
            }));
            names.extend(
                module
                    .global_variables
                    .iter()
                    .filter_map(|(_, g)| g.name.clone()),
            );
            names.extend(module.constants.iter().filter_map(|(_, c)| c.name.clone()));
            assert!(names.len() > 30, "{names:?}");
            assert!(names.iter().any(|n| n == "tessella_point"), "{names:?}");
            for name in names {
                assert!(
                    ["tessella_", "Tessella", "TESSELLA_"]
                        .iter()
                        .any(|p| name.starts_with(p)),
                    "the exported WGSL declares `{name}`"
                );
            }
            assert!(source.contains("@group(2)") && !source.contains("@group(0)"));
        }
    }

    /// The adaptive module parses and validates for every basis, normal mode and spacing
    /// family, with its four bindings in the group asked for.
    #[test]
    fn the_adaptive_module_validates() {
        use tessella_core::refine::Spacing;
        for basis in [tessella_core::Basis::Cubic, tessella_core::Basis::Png1] {
            for mode in [
                tessella_core::NormalMode::Quadratic,
                tessella_core::NormalMode::Real,
            ] {
                for spacing in [Spacing::FractionalOdd, Spacing::Grid] {
                    let source = adaptive_module(3, basis, mode, spacing);
                    validated(&source);
                    assert_eq!(source.matches("@group(3) @binding(").count(), 4);
                    assert!(source.contains("fn tessella_adaptive_point("));
                }
            }
        }
        assert_eq!(adaptive_params_bytes(tessella_core::Basis::Cubic).len(), 96);
    }

    /// The adaptive point on the tessellator's spacings is the core's generated one, once;
    /// the shader file only branches to it (the placement and its read-back are typed nowhere
    /// here; the grid's plans keep their own blend of edge weights).
    #[test]
    fn the_tessellator_point_is_the_cores_adaptive_point() {
        use tessella_core::shader::{self, Lang};
        let source = adaptive_module(
            0,
            tessella_core::Basis::Cubic,
            tessella_core::NormalMode::Quadratic,
            tessella_core::refine::Spacing::FractionalOdd,
        );
        let steps = shader::adaptive_point(Lang::Wgsl, &crate::adaptive::TESSELLATOR_POINT);
        assert_eq!(source.matches(&steps).count(), 1);
        let typed = include_str!("shaders/adaptive.wgsl");
        for call in ["tessella_locate(", "tessella_tessellator_point("] {
            assert!(!typed.contains(call), "{call} typed in adaptive.wgsl");
        }
        assert!(typed
            .contains("return tessella_tessellator_adaptive_point(face, rec, code, inst >> 30u);"));
    }

    /// A per-basis module with the evaluation entry beside it, its bindings in another group,
    /// validates as one compute module whose entry is `tessella_evaluate`.
    #[test]
    fn the_evaluation_entry_validates_beside_the_module() {
        for basis in [tessella_core::Basis::Cubic, tessella_core::Basis::Png1] {
            let source = format!(
                "{}\n{}",
                patch_module_of(0, tessella_core::NormalMode::Real, basis),
                evaluation_entry(1, [4, 5, 6], 256)
            );
            let module = validated(&source);
            let entries: Vec<&str> = module
                .entry_points
                .iter()
                .map(|e| e.name.as_str())
                .collect();
            assert_eq!(entries, ["tessella_evaluate"]);
            assert_eq!(module.entry_points[0].workgroup_size, [256, 1, 1]);
            for binding in 4..=6 {
                assert!(source.contains(&format!("@group(1) @binding({binding}) var")));
            }
        }
    }
}
