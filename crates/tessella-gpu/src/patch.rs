//! Bind group 0 of every pipeline: the stencil, the control nets, and the displacement, i.e.
//! what `shaders/eval.wgsl` and `shaders/displace.wgsl` read. Uploaded unchanged from
//! tessella-core's `Stencil` and `PatchNets`.

use crate::context::{GpuContext, READ, UNIFORM};
use crate::displace::{self, Displacement};
use crate::error::GpuError;
use crate::gpu_types::EvalParams;
use tessella_core::displace::FaceFrame;
use tessella_core::{Basis, NormalMode, PatchNets, Stencil};

// How eval.wgsl numbers normal modes and sizes a normal net, shared with `wgsl_constants`
// (defined with the other Rust twins of WGSL layouts; named here too, where group 0 uses them).
use crate::gpu_types::normal_mode_code;

/// Layout of group 0, for the given shader stages: the patch's seven bindings, then `extra`
/// read-only storage buffers of the caller's (a renderer's draw tables, bindings 7, 8, ...).
pub(crate) fn layout(
    ctx: &GpuContext,
    visibility: wgpu::ShaderStages,
    extra: usize,
) -> wgpu::BindGroupLayout {
    let [r, u] = [(visibility, READ), (visibility, UNIFORM)];
    let mut entries = vec![r, r, r, u, u, r, r];
    entries.extend(std::iter::repeat_n(r, extra));
    ctx.buffer_layout("patch", &entries)
}

/// The GPU copies of one mesh's nets plus a pattern's stencil.
pub(crate) struct PatchBuffers {
    pub stencil: wgpu::Buffer,
    pub points: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub eval: wgpu::Buffer,
    pub displace: wgpu::Buffer,
    pub displace_data: wgpu::Buffer,
    /// The canonical edge table (`crate::canonical`), fixed per plan.
    pub edges: wgpu::Buffer,
    /// Byte offset of the face records in `displace_data`; `None` without displacement.
    displace_faces_at: Option<u64>,
    pub face_count: u32,
    /// The uniform `eval` holds (whole nets bound).
    pub eval_params: EvalParams,
}

impl PatchBuffers {
    /// These nets as a [`crate::GpuNetBuilder`]'s target: `shape` is (faces, control points
    /// per face) of the nets the buffers were made for.
    pub fn nets_target(
        &self,
        shape: (usize, usize),
        normal_mode: NormalMode,
    ) -> crate::NetsTarget<'_> {
        crate::NetsTarget {
            points: &self.points,
            normals: &self.normals,
            faces: shape.0,
            k: shape.1,
            normal_mode,
            coarse: None,
        }
    }

    /// `stencil`: the weights rows of every pattern point drawn (`Stencil::weights`, or several
    /// patterns' rows one after the other), `Stencil::stride_for(K)` floats each.
    /// `split_nets`: the caller binds the nets in windows of faces
    /// ([`PatchBuffers::bind_group_window`]), so they need only fit one buffer; otherwise nets
    /// over one binding are refused.
    pub fn new(
        ctx: &GpuContext,
        stencil: &[f32],
        nets: &PatchNets,
        displacement: &Displacement,
        edges: &[u32],
        split_nets: bool,
    ) -> Result<PatchBuffers, GpuError> {
        let limit = ctx.max_binding();
        let net_bytes = (nets.points.len() as u64 * 12).max(nets.normals.len() as u64 * 12);
        let (nets_what, nets_limit) = if split_nets {
            (
                "the control nets (in one buffer)",
                ctx.limits.max_buffer_size,
            )
        } else {
            ("the control nets", limit)
        };
        if net_bytes > nets_limit {
            return Err(GpuError::TooLarge {
                what: nets_what,
                bytes: net_bytes,
                limit: nets_limit,
            });
        }
        for (what, bytes) in [
            ("the pattern's stencil", stencil.len() as u64 * 4),
            ("the canonical edge table", edges.len() as u64 * 4),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        let k = nets.basis.len() as u32;
        let eval = EvalParams {
            k,
            stride: Stencil::stride_for(nets.basis.len()) as u32,
            face_count: nets.len() as u32,
            points_base: 0,
            normals_base: 0,
            _pad: [0; 3],
        };
        let (dparams, ddata) = displace::gpu_data(displacement, nets.len());
        let data_bytes = ddata.len() as u64 * 4;
        if data_bytes > limit {
            return Err(GpuError::TooLarge {
                what: "the displacement data",
                bytes: data_bytes,
                limit,
            });
        }
        let copy = wgpu::BufferUsages::COPY_DST;
        let uniform =
            |label, bytes: &[u8]| ctx.buffer_init(label, bytes, wgpu::BufferUsages::UNIFORM | copy);
        Ok(PatchBuffers {
            stencil: ctx.storage_buffer("stencil", bytemuck::cast_slice(stencil), copy),
            points: ctx.storage_buffer("net points", bytemuck::cast_slice(&nets.points), copy),
            normals: ctx.storage_buffer("net normals", bytemuck::cast_slice(&nets.normals), copy),
            eval: uniform("eval params", bytemuck::bytes_of(&eval)),
            displace: uniform("displace params", bytemuck::bytes_of(&dparams)),
            displace_data: ctx.storage_buffer("displace data", bytemuck::cast_slice(&ddata), copy),
            edges: ctx.storage_buffer(
                "canonical edges",
                bytemuck::cast_slice(edges),
                wgpu::BufferUsages::empty(),
            ),
            displace_faces_at: (dparams.faces_at != displace::NO_FACES)
                .then_some(dparams.faces_at as u64 * 4),
            face_count: nets.len() as u32,
            eval_params: eval,
        })
    }

    /// Replaces the nets with new ones of the same size: the only per-frame upload of a
    /// deforming mesh. Returns the bytes written.
    pub fn update_nets(&self, ctx: &GpuContext, nets: &PatchNets) -> u64 {
        write_nets(ctx, &self.points, &self.normals, nets)
    }

    /// `true` when a displacement is bound (its face records need writing per frame).
    pub fn displaced(&self) -> bool {
        self.displace_faces_at.is_some()
    }

    /// Writes the displacement's per-face records (position means and split masks, from
    /// `tessella_core::displace::face_frames` of the frame's mesh): once per frame of a
    /// deforming mesh that is displaced, like the nets. Without it every vertex moves along its
    /// own normal, and hard edges open. Does nothing without displacement; returns the bytes
    /// written.
    pub fn update_displace_faces(&self, ctx: &GpuContext, faces: &[FaceFrame]) -> u64 {
        let Some(at) = self.displace_faces_at else {
            return 0;
        };
        assert_eq!(faces.len(), self.face_count as usize, "one record per face");
        let records = displace::face_records(faces);
        ctx.queue
            .write_buffer(&self.displace_data, at, bytemuck::cast_slice(&records));
        records.len() as u64 * 4
    }

    /// Bytes held on the GPU.
    pub fn byte_size(&self) -> u64 {
        [
            &self.stencil,
            &self.points,
            &self.normals,
            &self.eval,
            &self.displace,
            &self.displace_data,
            &self.edges,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }

    /// Group 0 with the whole nets bound, then `extra` (bindings 7, 8, ...).
    pub fn bind_group(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        extra: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let points = (0, self.points.size());
        let normals = (0, self.normals.size());
        self.bind_group_window(ctx, layout, &self.eval, (points, normals), extra)
    }

    /// Group 0 with only the byte ranges `points` and `normals` (offset, size) of the nets
    /// bound, and `eval` as the uniform (an [`EvalParams`] whose `points_base` and
    /// `normals_base` are the ranges' offsets in floats), then `extra` (bindings 7, 8, ...).
    pub fn bind_group_window(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        eval: &wgpu::Buffer,
        (points, normals): ((u64, u64), (u64, u64)),
        extra: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let window = |buffer, (offset, size): (u64, u64)| {
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer,
                offset,
                size: wgpu::BufferSize::new(size),
            })
        };
        let resources = [
            self.stencil.as_entire_binding(),
            window(&self.points, points),
            window(&self.normals, normals),
            eval.as_entire_binding(),
            self.displace.as_entire_binding(),
            self.displace_data.as_entire_binding(),
            self.edges.as_entire_binding(),
        ];
        let entries: Vec<_> = resources
            .into_iter()
            .chain(extra.iter().map(|b| b.as_entire_binding()))
            .enumerate()
            .map(|(i, resource)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource,
            })
            .collect();
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("patch"),
            layout,
            entries: &entries,
        })
    }
}

/// Writes `nets` into the point and normal-net buffers of a renderer or evaluator; returns the
/// bytes written.
pub(crate) fn write_nets(
    ctx: &GpuContext,
    points: &wgpu::Buffer,
    normals: &wgpu::Buffer,
    nets: &PatchNets,
) -> u64 {
    let p: &[u8] = bytemuck::cast_slice(&nets.points);
    let n: &[u8] = bytemuck::cast_slice(&nets.normals);
    ctx.queue.write_buffer(points, 0, p);
    ctx.queue.write_buffer(normals, 0, n);
    (p.len() + n.len()) as u64
}

/// Refuses a frame whose nets are not `shape`: (patches, control points per patch).
pub(crate) fn check_nets_shape(nets: &PatchNets, shape: (usize, usize)) -> Result<(), GpuError> {
    if (nets.len(), nets.basis.len()) != shape {
        return Err(GpuError::BadOption(format!(
            "a frame of {} patches of {} control points, the renderer draws {} of {}",
            nets.len(),
            nets.basis.len(),
            shape.0,
            shape.1
        )));
    }
    Ok(())
}

/// The displacement functions generated from the core, traced once per process (every
/// pipeline of every renderer includes them).
fn displace_wgsl() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(tessella_core::shader::displace_wgsl)
}

/// The evaluation's normal glue (`tessella_real_normal`, `tessella_unit_or_zero`,
/// `tessella_corner_normal`), generated once per process.
pub(crate) fn surface_normal_wgsl() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| tessella_core::shader::surface_normal(tessella_core::shader::Lang::Wgsl))
}

/// A canonical edge point's sums and normal (`tessella_canonical_edge`), generated once per
/// process.
pub(crate) fn canonical_edge_wgsl() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| tessella_core::shader::canonical_edge(tessella_core::shader::Lang::Wgsl))
}

/// A coarse edge's point in canonical order, `tessella_canonical_edge_point` (and
/// `tessella_edge_forward`), for a pipeline compiled for one normal mode; generated once per
/// process. The pattern's and the adaptive renderer's hosts define the edge tables' reads.
pub(crate) fn canonical_edge_point_wgsl() -> &'static str {
    use tessella_core::shader::{canonical_edge_point, EdgeSources, Lang};
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        canonical_edge_point(
            Lang::Wgsl,
            &EdgeSources {
                context: ("", ""),
                net_normals: "TESSELLA_NORMAL_MODE != TESSELLA_MODE_REAL",
            },
        )
    })
}

/// The normal's sources of a WGSL evaluation of patch `face` in a pipeline compiled for one
/// normal mode (`TESSELLA_NORMAL_MODE`): the real normal from `du`, `dv` in `Real`, the net's
/// statements `net`, the face's first three control points as its corners. The pattern's and
/// the adaptive renderer's evaluations differ only in `du`, `dv` and `net`.
pub(crate) fn face_normal_sources<'a>(
    du: &'a str,
    dv: &'a str,
    net: &'a str,
) -> tessella_core::shader::NormalSources<'a> {
    tessella_core::shader::NormalSources {
        real: Some(tessella_core::shader::RealNormalSource {
            when: Some("TESSELLA_NORMAL_MODE == TESSELLA_MODE_REAL"),
            du,
            dv,
        }),
        net,
        corners: [
            "tessella_net_point(face, 0u)",
            "tessella_net_point(face, 1u)",
            "tessella_net_point(face, 2u)",
        ],
    }
}

/// A stencil row's unit normal, `tessella_patch_normal(face, base)`: the core's normal steps
/// ([`tessella_core::shader::normal_glue`]) over `eval.wgsl`'s sums of the row at `base`,
/// generated once per process.
pub(crate) fn patch_normal_wgsl() -> &'static str {
    use tessella_core::shader::{normal_glue, Lang};
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        let glue = normal_glue(
            Lang::Wgsl,
            &face_normal_sources(
                "tessella_combine_points(face, base + k)",
                "tessella_combine_points(face, base + 2u * k)",
                "for (var j = 0u; j < TESSELLA_NORMAL_NET_LEN; j++) {\n    \
                 n += tessella_stencil[base + 3u * k + j] * tessella_net_normal(face, j);\n}",
            ),
        );
        format!(
            "fn tessella_patch_normal(face: u32, base: u32) -> vec3<f32> {{\n    \
             let k = tessella_k();\n{glue}    return n;\n}}\n"
        )
    })
}

/// The WGSL source of a pipeline: the normal mode and the displacement as constants, the
/// generated normal glue, canonical edge sums and canonical edge point, `tessella_patch_normal`, the shared
/// evaluation and displacement modules (each after its uniform struct, printed from its Rust
/// twin), then its own.
/// Constants rather than uniforms, so each pipeline compiles only its own branch (a software
/// rasteriser runs the whole body of a branch on a uniform: Perlin noise or `Du × Dv` for every
/// vertex that needs neither).
pub(crate) fn shader_source(
    own: &str,
    normal_mode: NormalMode,
    displacement: &Displacement,
    basis: Option<Basis>,
) -> String {
    [
        &crate::wgsl_constants::source(),
        &format!(
            "const TESSELLA_NORMAL_MODE: u32 = {}u;\nconst TESSELLA_DISPLACE_KIND: u32 = {}u;\nconst TESSELLA_FIXED_K: u32 = {}u;\n",
            normal_mode_code(normal_mode),
            displace::kind_code(displacement),
            basis.map_or(0, |b| b.len())
        ),
        surface_normal_wgsl(),
        canonical_edge_wgsl(),
        canonical_edge_point_wgsl(),
        patch_normal_wgsl(),
        &crate::gpu_types::EvalParams::wgsl(),
        include_str!("shaders/eval.wgsl"),
        &crate::gpu_types::DisplaceParams::wgsl(),
        include_str!("shaders/displace.wgsl"),
        displace_wgsl(),
        own,
    ]
    .join("\n")
}
