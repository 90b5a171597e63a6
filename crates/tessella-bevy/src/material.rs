//! The extended material a tessellated entity is drawn with: its own `StandardMaterial` plus
//! the patch group's seven buffers and the coarse texture coordinates, and the vertex shaders (main pass and prepass) that call
//! tessella-gpu's exported WGSL module, registered as Bevy shader imports.

use bevy::asset::uuid_handle;
use bevy::pbr::ExtendedMaterial;
use bevy::prelude::*;
use bevy::render::render_resource::AsBindGroup;
use bevy::render::storage::ShaderBuffer;
use std::borrow::Cow;
use tessella_core::NormalMode;

/// The material a tessellated entity is drawn with: its own `StandardMaterial`, extended.
pub type TessellaMaterial = ExtendedMaterial<StandardMaterial, TessellaExtension>;

/// First binding of the patch group inside Bevy's material group (0..100 are the base
/// material's, as Bevy's extended-material convention has it).
pub const FIRST_BINDING: u32 = 100;

/// Bevy's material bind group index (`bevy::pbr::MATERIAL_BIND_GROUP_INDEX`).
pub(crate) const MATERIAL_GROUP: u32 = 3;

const VERTEX_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a01");
const PREPASS_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a02");
const PATCH_LINEAR: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a03");
const PATCH_QUADRATIC: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a04");
const PATCH_REAL: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a05");
const FACE_UVS: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a06");

/// The extension's data: the patch group's seven buffers (tessella-gpu's
/// [`tessella_gpu::wgsl::patch_bytes`]), bound at 100 to 106 in Bevy's material group, and
/// the coarse texture coordinates at 107, the evaluated vertices at 108.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
#[bind_group_data(TessellaKey)]
pub struct TessellaExtension {
    #[storage(100, read_only)]
    pub stencil: Handle<ShaderBuffer>,
    #[storage(101, read_only)]
    pub net_points: Handle<ShaderBuffer>,
    #[storage(102, read_only)]
    pub net_normals: Handle<ShaderBuffer>,
    #[storage(103, read_only)]
    pub eval_params: Handle<ShaderBuffer>,
    #[storage(104, read_only)]
    pub displace_params: Handle<ShaderBuffer>,
    #[storage(105, read_only)]
    pub displace_data: Handle<ShaderBuffer>,
    #[storage(106, read_only)]
    pub edge_table: Handle<ShaderBuffer>,
    /// The coarse triangles' texture coordinates, three a triangle.
    #[storage(107, read_only)]
    pub face_uvs: Handle<ShaderBuffer>,
    /// With `per_frame`, the welded vertices evaluated this frame (six floats a vertex:
    /// position, normal) that the vertex stages read instead of evaluating; otherwise any
    /// buffer (unread).
    #[storage(108, read_only)]
    pub evaluated: Handle<ShaderBuffer>,
    /// Which evaluation module the shaders import (a compile-time constant of the module).
    #[reflect(ignore)]
    pub normal_mode: NormalModeKey,
    /// The vertex stages read `evaluated` at the welded vertex (`TessellaDraw::PerFrame`).
    pub per_frame: bool,
}

/// The normal mode as a pipeline key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum NormalModeKey {
    Linear,
    #[default]
    Quadratic,
    Real,
}

impl NormalModeKey {
    /// The key of a normal mode (the modes without a module of their own use quadratic's).
    pub fn of(mode: NormalMode) -> NormalModeKey {
        match tessella_core::shader::normal_mode_code(mode) {
            tessella_core::shader::NORMALS_LINEAR => NormalModeKey::Linear,
            tessella_core::shader::NORMALS_REAL => NormalModeKey::Real,
            _ => NormalModeKey::Quadratic,
        }
    }
    fn def(self) -> &'static str {
        match self {
            NormalModeKey::Linear => "TESSELLA_NORMALS_LINEAR",
            NormalModeKey::Quadratic => "TESSELLA_NORMALS_QUADRATIC",
            NormalModeKey::Real => "TESSELLA_NORMALS_REAL",
        }
    }
}

/// Pipeline key of the extension: the normal mode picks the imported module, `per_frame`
/// whether the vertex stages evaluate or read the frame's evaluated vertices.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TessellaKey {
    normal_mode: NormalModeKey,
    per_frame: bool,
}

impl From<&TessellaExtension> for TessellaKey {
    fn from(e: &TessellaExtension) -> TessellaKey {
        TessellaKey {
            normal_mode: e.normal_mode,
            per_frame: e.per_frame,
        }
    }
}

impl TessellaKey {
    /// The shader defs of this key's pipeline: the imported module's, and the per-frame read.
    fn shader_defs(self) -> Vec<String> {
        let mut defs = vec![self.normal_mode.def().to_string()];
        if self.per_frame {
            defs.push("TESSELLA_PER_FRAME".into());
        }
        defs
    }
}

/// Implements `MaterialExtension` for a tessella extension whose vertex stages are its own:
/// `$vertex` for the main pass, `$prepass` for the prepass and the deferred pass, and the
/// shader defs of its key's `shader_defs()` (the key is the extension's bind-group data).
/// The fragment stages stay the base `StandardMaterial`'s.
macro_rules! vertex_extension {
    ($extension:ty, $vertex:expr, $prepass:expr) => {
        impl bevy::pbr::MaterialExtension for $extension {
            fn vertex_shader() -> bevy::shader::ShaderRef {
                $vertex.into()
            }
            fn prepass_vertex_shader() -> bevy::shader::ShaderRef {
                $prepass.into()
            }
            fn deferred_vertex_shader() -> bevy::shader::ShaderRef {
                $prepass.into()
            }
            fn specialize(
                _pipeline: &bevy::pbr::MaterialExtensionPipeline,
                descriptor: &mut bevy::render::render_resource::RenderPipelineDescriptor,
                _layout: &bevy::mesh::MeshVertexBufferLayoutRef,
                key: bevy::pbr::MaterialExtensionKey<Self>,
            ) -> Result<(), bevy::render::render_resource::SpecializedMeshPipelineError> {
                let defs = key.bind_group_data.shader_defs();
                descriptor
                    .vertex
                    .shader_defs
                    .extend(defs.into_iter().map(Into::into));
                Ok(())
            }
        }
    };
}
pub(crate) use vertex_extension;

vertex_extension!(TessellaExtension, VERTEX_SHADER, PREPASS_SHADER);

/// tessella-gpu's exported evaluation module for `mode`, rebound into Bevy's material group:
/// group 3, bindings 100 to 106, and the two uniforms as read-only storage (a material's
/// raw-byte buffers are storage buffers). Only the declarations change; the evaluation is
/// tessella's generated code as it is.
pub fn patch_module_for_bevy(mode: NormalMode) -> String {
    rebind(tessella_gpu::wgsl::patch_module(MATERIAL_GROUP, mode), 7)
}

/// [`patch_module_for_bevy`] for the patches of one basis (tessella-gpu's `patch_module_of`:
/// its control points a constant of the module), for a kernel compiled per basis.
pub(crate) fn patch_module_of_for_bevy(mode: NormalMode, basis: tessella_core::Basis) -> String {
    rebind(
        tessella_gpu::wgsl::patch_module_of(MATERIAL_GROUP, mode, basis),
        7,
    )
}

/// A tessella module's `count` bindings (0, 1, ...) moved to [`FIRST_BINDING`] on, and its
/// uniforms declared as read-only storage (a material's raw-byte buffers are storage buffers).
pub(crate) fn rebind(mut source: String, count: u32) -> String {
    for b in (0..count).rev() {
        source = source.replace(
            &format!("@binding({b})"),
            &format!("@binding({})", FIRST_BINDING + b),
        );
    }
    source.replace("var<uniform>", "var<storage, read>")
}

const VERTEX_WESL: &str = include_str!("vertex.wesl");
const PREPASS_WESL: &str = include_str!("prepass.wesl");
const FACE_UVS_WESL: &str = include_str!("face_uvs.wesl");

/// Puts tessella's modules and the two vertex shaders into `Assets<Shader>` under the handles
/// the extension names.
pub(crate) fn register_shaders(shaders: &mut Assets<Shader>) -> Result<(), String> {
    let modules = [
        (PATCH_LINEAR, NormalMode::Linear, "patch_linear"),
        (PATCH_QUADRATIC, NormalMode::Quadratic, "patch_quadratic"),
        (PATCH_REAL, NormalMode::Real, "patch_real"),
    ];
    for (handle, mode, name) in modules {
        insert_shader(shaders, &handle, name, patch_module_for_bevy(mode))?;
    }
    for (handle, source, name) in [
        (VERTEX_SHADER, VERTEX_WESL, "vertex"),
        (PREPASS_SHADER, PREPASS_WESL, "prepass"),
        (FACE_UVS, FACE_UVS_WESL, "face_uvs"),
    ] {
        insert_shader(shaders, &handle, name, source)?;
    }
    Ok(())
}

/// Puts the WESL `source` into `Assets<Shader>` under `handle`, importable as
/// `tessella_bevy::<name>` (the import path is the embedded path's).
pub(crate) fn insert_shader(
    shaders: &mut Assets<Shader>,
    handle: &Handle<Shader>,
    name: &str,
    source: impl Into<Cow<'static, str>>,
) -> Result<(), String> {
    let path = format!("embedded://tessella_bevy/{name}.wesl");
    shaders
        .insert(handle.id(), Shader::from_wesl(source, path))
        .map_err(|e| format!("cannot register {name}: {e}"))
}
