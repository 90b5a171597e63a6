//! The uniform structs the WGSL reads, written once, here: each is `#[repr(C)]`, `Pod` and
//! pinned by size and offset assertions, and its WGSL declaration is printed from it
//! (`wgsl()`, by [`uniform!`]), so no shader file types a struct layout. `uniform_twins.rs`
//! reads each struct's layout out of the WGSL the pipelines compile (naga) and compares it
//! field by field with the Rust one.

use bytemuck::{Pod, Zeroable};
use std::mem::{offset_of, size_of};
use tessella_core::NormalMode;

/// How a field of a uniform struct is declared in WGSL.
pub(crate) trait WgslField {
    /// The member declaration(s) of field `name`, one a line.
    fn declare(name: &str) -> String;
}

impl WgslField for u32 {
    fn declare(name: &str) -> String {
        format!("    {name}: u32,\n")
    }
}

impl WgslField for f32 {
    fn declare(name: &str) -> String {
        format!("    {name}: f32,\n")
    }
}

/// Padding: `N` `u32` members `{name}0`, `{name}1`, ... (a WGSL uniform array's stride is 16
/// bytes, so words cannot be an array there).
impl<const N: usize> WgslField for [u32; N] {
    fn declare(name: &str) -> String {
        (0..N).map(|i| format!("    {name}{i}: u32,\n")).collect()
    }
}

/// `N` rows of four words: `array<vec4<u32>, N>`.
impl<const N: usize> WgslField for [[u32; 4]; N] {
    fn declare(name: &str) -> String {
        format!("    {name}: array<vec4<u32>, {N}>,\n")
    }
}

/// A uniform struct and its WGSL declaration `struct NAME { ... }` (`wgsl()`), from one list of
/// fields: the Rust attributes and field docs pass through; the WGSL gets the fields in order.
macro_rules! uniform {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident as $wgsl:literal {
            $($(#[$field_meta:meta])* pub $field:ident: $ty:ty,)+
        }
    ) => {
        $(#[$meta])*
        $vis struct $name {
            $($(#[$field_meta])* pub $field: $ty,)+
        }
        impl $name {
            /// The WGSL name of this struct.
            #[cfg(test)]
            pub(crate) const WGSL_NAME: &'static str = $wgsl;
            /// The WGSL declaration of this struct, printed from its fields.
            pub(crate) fn wgsl() -> String {
                let mut s = format!("struct {} {{\n", $wgsl);
                $(s += &<$ty as WgslField>::declare(stringify!($field));)+
                s + "}\n"
            }
        }
    };
}

/// `NormalMode` as `eval.wgsl` numbers it.
pub(crate) fn normal_mode_code(mode: NormalMode) -> u32 {
    tessella_core::shader::normal_mode_code(mode)
}

/// Bytes of one face's normal net (6 points).
pub(crate) const NORMAL_NET_BYTES: u64 = 6 * 12;

uniform! {
    /// The uniform `shaders/eval.wgsl` reads.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, Pod, Zeroable)]
    pub(crate) struct EvalParams as "TessellaEvalParams" {
        pub k: u32,
        pub stride: u32,
        pub face_count: u32,
        /// `f32` index in the nets of the first float the bound `net_points` window holds (0
        /// unless the compute path splits the nets into windows of faces).
        pub points_base: u32,
        /// The same for `net_normals`.
        pub normals_base: u32,
        pub _pad: [u32; 3],
    }
}
const _: () = assert!(size_of::<EvalParams>() == 32);
const _: () = assert!(offset_of!(EvalParams, face_count) == 8);
const _: () = assert!(offset_of!(EvalParams, normals_base) == 16);

uniform! {
    /// The uniform `shaders/displace.wgsl` reads. The kind is the constant
    /// `TESSELLA_DISPLACE_KIND` (compiled in): 0 none, 1 sine `a sin(f |P|)`, 2 Perlin
    /// `a noise(f P)`, 3 height map `a h(uv)`.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, Pod, Zeroable)]
    pub(crate) struct DisplaceParams as "TessellaDisplaceParams" {
        /// `a` and `f`.
        pub amplitude: f32,
        pub frequency: f32,
        pub map_width: u32,
        pub map_height: u32,
        /// Index in `displace_data` of the first face record, or `u32::MAX` for none.
        pub faces_at: u32,
        pub _pad: [u32; 3],
    }
}
const _: () = assert!(size_of::<DisplaceParams>() == 32);
const _: () = assert!(offset_of!(DisplaceParams, map_height) == 12);
const _: () = assert!(offset_of!(DisplaceParams, faces_at) == 16);

uniform! {
    /// The uniform `shaders/refine.wgsl` reads.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub(crate) struct RefineParams as "RefineParams" {
        pub level: u32,
        pub weld: u32,
        /// The chunk's first output item (vertex or triangle).
        pub first: u32,
        /// The chunk's items.
        pub count: u32,
        /// `V`, the coarse vertices.
        pub input_vertices: u32,
        pub edge_base: u32,
        pub interior_base: u32,
        /// `(N-1)(N-2)/2` and `(N+1)(N+2)/2`.
        pub interior_per_face: u32,
        pub points_per_face: u32,
        pub has_uv: u32,
        /// Offset (in `u32`s, as the `*_at` fields up to `pattern_triangles_at`) in `mesh_u32`
        /// of the `F x 3` corner indices.
        pub triangles_at: u32,
        /// Per vertex its owner: `face * 4 + corner`, or none.
        pub vertex_owner_at: u32,
        /// Per edge its owner: `face * 4 + edge slot`.
        pub edge_owner_at: u32,
        /// `E x 2` vertex indices, lower first.
        pub edges_at: u32,
        /// `F x 3` edge ids.
        pub face_edges_at: u32,
        /// The 3 corner, `3 x (N-1)` edge (by edge, then step) and interior pattern points.
        pub corner_points_at: u32,
        pub edge_points_at: u32,
        pub interior_points_at: u32,
        /// Per pattern point its code: `class << 30 | edge << 28 | index`.
        pub point_codes_at: u32,
        /// `N^2 x 3` pattern triangles.
        pub pattern_triangles_at: u32,
        /// Offset (in `f32`s, as `normals_at` and `uvs_at`) of the positions in `mesh_f32`.
        pub positions_at: u32,
        pub normals_at: u32,
        pub uvs_at: u32,
        /// `f32` index of the chunk's first vertex in the bound output window.
        pub out_base: u32,
        /// 1 for an adaptive plan: every output vertex is read from the lookup table.
        pub adaptive: u32,
        /// Offset (in `u32`s) of the adaptive lookup: per output vertex, its face (or none) and
        /// stencil row (`row | (corner + 1) << 30`).
        pub lookup_at: u32,
        /// The output's `VertexFormat`, in words: stride, then the offsets of position, normal and
        /// uv (`u32::MAX`: not written; neither is a word no attribute covers).
        pub out_stride: u32,
        pub out_position: u32,
        pub out_normal: u32,
        pub out_uv: u32,
        pub _pad: [u32; 2],
    }
}
const _: () = assert!(size_of::<RefineParams>() == 128);
const _: () = assert!(offset_of!(RefineParams, out_stride) == 104);
const _: () = assert!(offset_of!(RefineParams, out_uv) == 116);
const _: () = assert!(offset_of!(RefineParams, lookup_at) == 100);
const _: () = assert!(offset_of!(RefineParams, has_uv) == 36);
const _: () = assert!(offset_of!(RefineParams, pattern_triangles_at) == 76);
const _: () = assert!(offset_of!(RefineParams, uvs_at) == 88);

uniform! {
    /// The uniform `shaders/adaptive.wgsl` reads.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
    pub(crate) struct AdaptiveParams as "TessellaAdaptiveParams" {
        /// Per edge `k`: `canonical::edge_controls`.
        pub edge_controls: [[u32; 4]; 3],
        /// Per edge `k`: `canonical::edge_normal_controls`, then 0.
        pub edge_normals: [[u32; 4]; 3],
    }
}
const _: () = assert!(size_of::<AdaptiveParams>() == 96);
const _: () = assert!(offset_of!(AdaptiveParams, edge_normals) == 48);

uniform! {
    /// The uniform `shaders/nets.wgsl` reads.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
    pub(crate) struct NetsParams as "NetsParams" {
        pub faces: u32,
        pub vertices: u32,
        /// The coarse positions' stride and first `x`, in floats from the bound offset.
        pub positions_stride: u32,
        pub positions_first: u32,
        pub normals_stride: u32,
        pub normals_first: u32,
        /// Index in `topology` of the first PN-AEN across-table entry (after the triangles).
        pub across_at: u32,
        /// 1: copy the normalised coarse vertices into `coarse` (the evaluator's), 0: not.
        pub copy_coarse: u32,
        /// Float indices in `coarse` of vertex 0's position and normal.
        pub coarse_positions_at: u32,
        pub coarse_normals_at: u32,
        /// Phong's shape factor.
        pub alpha: f32,
        pub _pad: u32,
    }
}
const _: () = assert!(size_of::<NetsParams>() == 48);
const _: () = assert!(offset_of!(NetsParams, across_at) == 24);
const _: () = assert!(offset_of!(NetsParams, alpha) == 40);

uniform! {
    /// The uniform `shaders/skin.wgsl` reads.
    #[repr(C)]
    #[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
    pub(crate) struct SkinParams as "SkinParams" {
        pub vertex_count: u32,
        /// Influences per vertex (`DeformTable::slots`).
        pub slots: u32,
        /// Index (in `f32`s) in the frame buffer of the first morph weight (after the matrices).
        pub weights_at: u32,
        /// Index (in `u32`s) in the table of the per-vertex morph records: (target count,
        /// weight base, delta base).
        pub morphs_at: u32,
        /// Indices (in `f32`s) in the rest buffer of the position and normal deltas (xyz).
        pub deltas_at: u32,
        pub normal_deltas_at: u32,
        /// Threads per row of the 2D dispatch.
        pub row: u32,
        /// The output's stride (in `f32`s) and the first word of a vertex's position and normal
        /// (`CoarseStream`).
        pub out_stride: u32,
        pub position_first: u32,
        pub normal_first: u32,
        pub _pad: [u32; 2],
    }
}
const _: () = assert!(size_of::<SkinParams>() == 48);
const _: () = assert!(offset_of!(SkinParams, row) == 24);
const _: () = assert!(offset_of!(SkinParams, normal_first) == 36);
