//! The material of an entity with per-edge levels (screen-space LOD): its `StandardMaterial`
//! extended with tessella-gpu's adaptive evaluation module (the one `AdaptiveRenderer` draws
//! with, `tessella_gpu::wgsl::adaptive_module`), registered once per basis, normal mode and
//! spacing family as the Bevy import `tessella_bevy::adaptive_<basis>_<normals>_<family>`.

use crate::material::{insert_shader, rebind, vertex_extension, MATERIAL_GROUP};
use bevy::asset::{uuid::Uuid, uuid_handle};
use bevy::pbr::ExtendedMaterial;
use bevy::prelude::*;
use bevy::render::render_resource::AsBindGroup;
use bevy::render::storage::ShaderBuffer;
use std::marker::PhantomData;
use tessella_core::refine::Spacing;
use tessella_core::{Basis, NormalMode};

/// The material of a tessellated entity with per-edge levels.
pub type TessellaLodMaterial = ExtendedMaterial<StandardMaterial, TessellaLodExtension>;

const LOD_VERTEX_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9b01");
const LOD_PREPASS_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9b02");
/// The adaptive modules' handles: this plus the module's index.
const ADAPTIVE_UUID: u128 = 0x5d6f0f5e_7c1e_4b0a_9a51_2f3c1b7e9c00;

/// The extension's data: the adaptive module's four buffers at 100 to 103 (net points, net
/// normals, edge parameters, per-face level records), the coarse texture coordinates at 107
/// and this frame's instance words at 108.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
#[bind_group_data(TessellaLodKey)]
pub struct TessellaLodExtension {
    #[storage(100, read_only)]
    pub net_points: Handle<ShaderBuffer>,
    #[storage(101, read_only)]
    pub net_normals: Handle<ShaderBuffer>,
    #[storage(102, read_only)]
    pub params: Handle<ShaderBuffer>,
    #[storage(103, read_only)]
    pub records: Handle<ShaderBuffer>,
    #[storage(107, read_only)]
    pub face_uvs: Handle<ShaderBuffer>,
    /// The frame's instance words (`face | side << 30`), the parts' draws in order.
    #[storage(108, read_only)]
    pub instances: Handle<ShaderBuffer>,
    /// Which adaptive module the shaders import.
    #[reflect(ignore)]
    pub key: TessellaLodKey,
}

/// Pipeline key of the extension: the module variant (an index into [`variants`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct TessellaLodKey {
    variant: u32,
}

impl TessellaLodKey {
    /// The key of the module for `basis`, `mode` and `spacing`.
    pub fn of(basis: Basis, mode: NormalMode, spacing: Spacing) -> TessellaLodKey {
        let wanted = (basis, normals_of(mode), spacing == Spacing::Grid);
        let variant = variants()
            .position(|(b, m, grid)| (b, m, grid) == wanted)
            .unwrap_or(0) as u32;
        TessellaLodKey { variant }
    }
}

impl From<&TessellaLodExtension> for TessellaLodKey {
    fn from(e: &TessellaLodExtension) -> TessellaLodKey {
        e.key
    }
}

/// The normal modes with a module of their own (the others draw as quadratic's).
fn normals_of(mode: NormalMode) -> NormalMode {
    use tessella_core::shader::{normal_mode_code, NORMALS_LINEAR, NORMALS_REAL};
    match normal_mode_code(mode) {
        NORMALS_LINEAR | NORMALS_REAL => mode,
        _ => NormalMode::Quadratic,
    }
}

/// Every module variant: basis, normal mode, grid (else a tessellator spacing).
fn variants() -> impl Iterator<Item = (Basis, NormalMode, bool)> {
    [Basis::Cubic, Basis::Png1].into_iter().flat_map(|b| {
        [NormalMode::Linear, NormalMode::Quadratic, NormalMode::Real]
            .into_iter()
            .flat_map(move |m| [false, true].into_iter().map(move |g| (b, m, g)))
    })
}

/// A variant's module name and shader def.
fn variant_name((basis, mode, grid): (Basis, NormalMode, bool)) -> String {
    let basis = tessella_core::shader::basis_name(basis);
    let mode = tessella_core::shader::normal_mode_name(mode);
    let family = if grid { "grid" } else { "tessellator" };
    format!("adaptive_{basis}_{mode}_{family}")
}

fn shader_def(name: &str) -> String {
    format!("TESSELLA_{}", name.to_ascii_uppercase())
}

impl TessellaLodKey {
    /// The shader def of this key's adaptive module.
    fn shader_defs(self) -> Vec<String> {
        let variant = variants().nth(self.variant as usize);
        variant
            .map(|v| shader_def(&variant_name(v)))
            .into_iter()
            .collect()
    }
}

vertex_extension!(TessellaLodExtension, LOD_VERTEX_SHADER, LOD_PREPASS_SHADER);

/// tessella-gpu's adaptive module rebound into Bevy's material group: group 3, bindings 100
/// to 103, the uniform as read-only storage. Only the declarations change.
pub fn adaptive_module_for_bevy(basis: Basis, mode: NormalMode, spacing: Spacing) -> String {
    let source = tessella_gpu::wgsl::adaptive_module(MATERIAL_GROUP, basis, mode, spacing);
    rebind(source, 4)
}

const LOD_VERTEX_WESL: &str = include_str!("lod_vertex.wesl");
const LOD_PREPASS_WESL: &str = include_str!("lod_prepass.wesl");

/// Puts every adaptive module variant and the two LOD vertex shaders (their imports, one per
/// variant under its shader def, generated here) into `Assets<Shader>`.
pub(crate) fn register_shaders(shaders: &mut Assets<Shader>) -> Result<(), String> {
    let mut imports = String::new();
    for (i, v) in variants().enumerate() {
        let name = variant_name(v);
        let spacing = if v.2 {
            Spacing::Grid
        } else {
            Spacing::FractionalOdd
        };
        let source = adaptive_module_for_bevy(v.0, v.1, spacing);
        let handle: Handle<Shader> =
            Handle::Uuid(Uuid::from_u128(ADAPTIVE_UUID + i as u128), PhantomData);
        insert_shader(shaders, &handle, &name, source)?;
        imports.push_str(&format!(
            "@if({})\nimport tessella_bevy::{name}::tessella_adaptive_point;\n",
            shader_def(&name)
        ));
    }
    let marker = "// (generated by lod_material.rs).\n";
    for (handle, source, name) in [
        (LOD_VERTEX_SHADER, LOD_VERTEX_WESL, "lod_vertex"),
        (LOD_PREPASS_SHADER, LOD_PREPASS_WESL, "lod_prepass"),
    ] {
        let source = source.replacen(marker, &format!("{marker}{imports}"), 1);
        insert_shader(shaders, &handle, name, source)?;
    }
    Ok(())
}
