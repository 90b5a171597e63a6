//! The uniform twins' test: each `#[repr(C)]` struct of `gpu_types` against the layout naga
//! reads out of the WGSL the pipelines compile (its own file, so that `gpu_types` imports none
//! of the modules whose shaders it reads).

use crate::displace::Displacement;
use crate::gpu_types::*;
use std::mem::{offset_of, size_of};
use tessella_core::{Basis, NormalMode};
use wgpu::naga;

/// The struct `name` of WGSL `source` as naga lays it out: its size, and each member's
/// name and byte offset.
fn wgsl_layout(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    let found = module.types.iter().find_map(|(_, t)| match &t.inner {
        naga::TypeInner::Struct { members, span } if t.name.as_deref() == Some(name) => {
            let members = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            Some((*span, members))
        }
        _ => None,
    });
    found.unwrap_or_else(|| panic!("no struct {name} in the WGSL"))
}

/// A Rust twin against its WGSL struct: the same size, and each named field at the offset
/// of the WGSL member of that name (the padding, `_pad`, is covered by the size).
macro_rules! twin {
    ($source:expr, $wgsl:literal, $ty:ident { $($field:ident),+ $(,)? }) => {{
        let (span, members) = wgsl_layout(&$source, $wgsl);
        assert_eq!(span as usize, size_of::<$ty>(), "{} size", stringify!($ty));
        let named: Vec<&(String, u32)> =
            members.iter().filter(|(m, _)| !m.starts_with('_')).collect();
        let fields = [$((stringify!($field), offset_of!($ty, $field))),+];
        assert_eq!(named.len(), fields.len(), "{}: {members:?}", stringify!($ty));
        for (field, offset) in fields {
            let member = members.iter().find(|(m, _)| m == field);
            assert_eq!(
                member.map(|m| m.1 as usize),
                Some(offset),
                "{}.{field}",
                stringify!($ty)
            );
        }
    }};
}

/// Every uniform struct the crate's WGSL declares, as printed from its Rust twin into the shader
/// text the pipelines compile, has the Rust layout, field by field (naga lays the WGSL out).
#[test]
fn every_uniform_twin_matches_its_wgsl_struct() {
    let patch = crate::patch::shader_source("", NormalMode::Quadratic, &Displacement::None, None);
    twin!(
        patch,
        "TessellaEvalParams",
        EvalParams {
            k,
            stride,
            face_count,
            points_base,
            normals_base
        }
    );
    twin!(
        patch,
        "TessellaDisplaceParams",
        DisplaceParams {
            amplitude,
            frequency,
            map_width,
            map_height,
            faces_at
        }
    );
    let refine = crate::patch::shader_source(
        &crate::evaluator::refine_wgsl(),
        NormalMode::Quadratic,
        &Displacement::None,
        None,
    );
    twin!(
        refine,
        "RefineParams",
        RefineParams {
            level,
            weld,
            first,
            count,
            input_vertices,
            edge_base,
            interior_base,
            interior_per_face,
            points_per_face,
            has_uv,
            triangles_at,
            vertex_owner_at,
            edge_owner_at,
            edges_at,
            face_edges_at,
            corner_points_at,
            edge_points_at,
            interior_points_at,
            point_codes_at,
            pattern_triangles_at,
            positions_at,
            normals_at,
            uvs_at,
            out_base,
            adaptive,
            lookup_at,
            out_stride,
            out_position,
            out_normal,
            out_uv,
        }
    );
    let adaptive = crate::wgsl::adaptive_module(
        0,
        Basis::Cubic,
        NormalMode::Quadratic,
        tessella_core::refine::Spacing::Grid,
    );
    twin!(
        adaptive,
        "TessellaAdaptiveParams",
        AdaptiveParams {
            edge_controls,
            edge_normals
        }
    );
    let nets = crate::net_builder::source_for(&tessella_core::Scheme::Pn);
    twin!(
        nets,
        "NetsParams",
        NetsParams {
            faces,
            vertices,
            positions_stride,
            positions_first,
            normals_stride,
            normals_first,
            across_at,
            copy_coarse,
            coarse_positions_at,
            coarse_normals_at,
            alpha,
        }
    );
    let skin = crate::skinner::source();
    twin!(
        skin,
        "SkinParams",
        SkinParams {
            vertex_count,
            slots,
            weights_at,
            morphs_at,
            deltas_at,
            normal_deltas_at,
            row,
            out_stride,
            position_first,
            normal_first,
        }
    );
}

/// No shader file types a uniform struct: each is printed from its Rust twin, once a module.
#[test]
fn no_shader_file_declares_a_uniform_struct() {
    let files = [
        include_str!("shaders/eval.wgsl"),
        include_str!("shaders/displace.wgsl"),
        include_str!("shaders/refine.wgsl"),
        include_str!("shaders/adaptive.wgsl"),
        include_str!("shaders/nets.wgsl"),
        include_str!("shaders/skin.wgsl"),
    ];
    let names = [
        EvalParams::WGSL_NAME,
        DisplaceParams::WGSL_NAME,
        RefineParams::WGSL_NAME,
        AdaptiveParams::WGSL_NAME,
        NetsParams::WGSL_NAME,
        SkinParams::WGSL_NAME,
    ];
    for file in files {
        for name in names {
            assert!(!file.contains(&format!("struct {name} ")), "{name}");
        }
    }
    let patch = crate::patch::shader_source("", NormalMode::Real, &Displacement::None, None);
    for name in [EvalParams::WGSL_NAME, DisplaceParams::WGSL_NAME] {
        assert_eq!(
            patch.matches(&format!("struct {name} {{")).count(),
            1,
            "{name}"
        );
    }
}
