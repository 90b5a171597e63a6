//! tessella's curved surfaces in Bevy: add [`Tessellate`] to an entity that has `Mesh3d` and
//! `MeshMaterial3d<StandardMaterial>`, and [`TessellaPlugin`] draws it as one refinement
//! pattern per coarse triangle whose vertex stage evaluates the triangle's patch, shaded by
//! Bevy's PBR (the entity's own `StandardMaterial`, Bevy's lights and shadows). Removing
//! `Tessellate` brings the plain mesh back.
//!
//! How (see `docs/bevy.md`): the entity's material becomes an
//! `ExtendedMaterial<StandardMaterial, TessellaExtension>` whose vertex shaders (main pass and
//! prepass, so shadows and depth follow the curved surface) call `tessella_point(face,
//! vertex)` from tessella-gpu's exported WGSL module, registered as the Bevy shader import
//! `tessella_bevy::patch_<normals>`. The patch group's seven buffers are the material's
//! storage bindings 100 to 106. The mesh drawn is the pattern repeated once per coarse
//! triangle, each vertex carrying (coarse triangle, pattern vertex) in `UV_1`: this is the
//! material-extension form of the refinement pattern (Bevy's mesh pipeline uses
//! `instance_index` for its own per-mesh data, so the pattern is not instanced by the GPU).

use bevy::asset::{uuid_handle, RenderAssetUsages};
use bevy::camera::primitives::Aabb;
use bevy::camera::visibility::NoAutoAabb;
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::pbr::{
    ExtendedMaterial, MaterialExtension, MaterialExtensionKey, MaterialExtensionPipeline,
};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, RenderPipelineDescriptor, SpecializedMeshPipelineError,
};
use bevy::render::storage::ShaderBuffer;
use bevy::shader::ShaderRef;
use tessella_core::refine::Plan;
use tessella_core::{NormalMode, RefineOptions, Scheme};

pub use tessella_core;

/// The material a tessellated entity is drawn with: its own `StandardMaterial`, extended.
pub type TessellaMaterial = ExtendedMaterial<StandardMaterial, TessellaExtension>;

/// First binding of the patch group inside Bevy's material group (0..100 are the base
/// material's, as Bevy's extended-material convention has it).
pub const FIRST_BINDING: u32 = 100;

/// Bevy's material bind group index (`bevy::pbr::MATERIAL_BIND_GROUP_INDEX`).
const MATERIAL_GROUP: u32 = 3;

const VERTEX_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a01");
const PREPASS_SHADER: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a02");
const PATCH_LINEAR: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a03");
const PATCH_QUADRATIC: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a04");
const PATCH_REAL: Handle<Shader> = uuid_handle!("5d6f0f5e-7c1e-4b0a-9a51-2f3c1b7e9a05");

/// Draws an entity's mesh as tessella's curved surface: the options of tessella's one
/// options type ([`RefineOptions`]: scheme, level, normals, ...). Uniform whole levels only
/// for now (per-edge and screen-space levels are not drawn by this plugin yet).
#[derive(Component, Clone, Debug)]
pub struct Tessellate(pub RefineOptions);

impl Tessellate {
    /// `level` segments per coarse edge with `scheme`, the scheme's default normals.
    pub fn new(scheme: Scheme, level: u32) -> Tessellate {
        Tessellate(RefineOptions::new(scheme, level))
    }
}

/// What a tessellated entity had before [`Tessellate`] came: given back when it goes.
#[derive(Component, Clone, Debug)]
pub struct Untessellated {
    pub mesh: Handle<Mesh>,
    pub material: Handle<StandardMaterial>,
    /// The options the current pattern mesh was built for.
    built_for: String,
}

/// The extension's data: the patch group's seven buffers (tessella-gpu's
/// [`tessella_gpu::wgsl::patch_bytes`]), bound at 100 to 106 in Bevy's material group.
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
    /// Which evaluation module the shaders import (a compile-time constant of the module).
    #[reflect(ignore)]
    pub normal_mode: NormalModeKey,
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
    fn of(mode: NormalMode) -> NormalModeKey {
        match mode {
            NormalMode::Linear => NormalModeKey::Linear,
            NormalMode::Real => NormalModeKey::Real,
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

/// Pipeline key of the extension: the normal mode picks the imported module.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TessellaKey {
    normal_mode: NormalModeKey,
}

impl From<&TessellaExtension> for TessellaKey {
    fn from(e: &TessellaExtension) -> TessellaKey {
        TessellaKey {
            normal_mode: e.normal_mode,
        }
    }
}

impl MaterialExtension for TessellaExtension {
    fn vertex_shader() -> ShaderRef {
        VERTEX_SHADER.into()
    }
    fn prepass_vertex_shader() -> ShaderRef {
        PREPASS_SHADER.into()
    }
    fn deferred_vertex_shader() -> ShaderRef {
        PREPASS_SHADER.into()
    }
    fn specialize(
        _pipeline: &MaterialExtensionPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        key: MaterialExtensionKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        descriptor
            .vertex
            .shader_defs
            .push(key.bind_group_data.normal_mode.def().into());
        Ok(())
    }
}

/// tessella-gpu's exported evaluation module for `mode`, rebound into Bevy's material group:
/// group 3, bindings 100 to 106, and the two uniforms as read-only storage (a material's
/// raw-byte buffers are storage buffers). Only the declarations change; the evaluation is
/// tessella's generated code as it is.
pub fn patch_module_for_bevy(mode: NormalMode) -> String {
    let mut source = tessella_gpu::wgsl::patch_module(MATERIAL_GROUP, mode);
    for b in (0..7).rev() {
        source = source.replace(
            &format!("@binding({b})"),
            &format!("@binding({})", FIRST_BINDING + b),
        );
    }
    source.replace("var<uniform>", "var<storage, read>")
}

const VERTEX_WESL: &str = include_str!("vertex.wesl");
const PREPASS_WESL: &str = include_str!("prepass.wesl");

/// Registers the material, the shader modules and the systems that swap an entity's mesh and
/// material when [`Tessellate`] comes or goes.
pub struct TessellaPlugin;

impl Plugin for TessellaPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(MaterialPlugin::<TessellaMaterial>::default());
        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
        for (handle, mode, name) in [
            (PATCH_LINEAR, NormalMode::Linear, "patch_linear"),
            (PATCH_QUADRATIC, NormalMode::Quadratic, "patch_quadratic"),
            (PATCH_REAL, NormalMode::Real, "patch_real"),
        ] {
            let path = format!("embedded://tessella_bevy/{name}.wesl");
            let _ = shaders.insert(
                handle.id(),
                Shader::from_wesl(patch_module_for_bevy(mode), path),
            );
        }
        let _ = shaders.insert(
            VERTEX_SHADER.id(),
            Shader::from_wesl(VERTEX_WESL, "embedded://tessella_bevy/vertex.wesl"),
        );
        let _ = shaders.insert(
            PREPASS_SHADER.id(),
            Shader::from_wesl(PREPASS_WESL, "embedded://tessella_bevy/prepass.wesl"),
        );
        app.add_systems(
            PostUpdate,
            (restore_material, untessellate, tessellate)
                .chain()
                .before(bevy::camera::visibility::VisibilitySystems::CalculateBounds),
        );
    }
}

/// The pattern mesh and the extension's buffers of one plan.
pub struct PatternMesh {
    pub mesh: Mesh,
    pub bytes: [Vec<u8>; 7],
    pub normal_mode: NormalMode,
    /// A box around the curved surface: the control points' (each patch lies in its control
    /// net's convex hull).
    pub aabb: (Vec3, Vec3),
}

/// Reads a Bevy triangle mesh as a tessella mesh (positions, normals if any, triangles).
pub fn to_tessella_mesh(mesh: &Mesh) -> Result<tessella_core::Mesh, String> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err("tessella refines triangle lists".into());
    }
    let positions: Vec<[f32; 3]> = match mesh.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) => p.clone(),
        _ => return Err("the mesh has no Float32x3 positions".into()),
    };
    let normals = match mesh.attribute(Mesh::ATTRIBUTE_NORMAL) {
        Some(bevy::mesh::VertexAttributeValues::Float32x3(n)) => Some(n.clone()),
        _ => None,
    };
    let indices: Vec<u32> = match mesh.indices() {
        Some(i) => i.iter().map(|i| i as u32).collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    tessella_core::Mesh::new(positions, normals, None, triangles).map_err(|e| e.to_string())
}

/// A Bevy mesh of a tessella mesh (what the examples load files into).
pub fn to_bevy_mesh(mesh: &tessella_core::Mesh) -> Mesh {
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, mesh.positions().to_vec())
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, mesh.normals().to_vec())
    .with_inserted_indices(Indices::U32(
        mesh.triangles().iter().flatten().copied().collect(),
    ))
}

/// Builds the pattern mesh for `mesh` refined with `options`: per coarse triangle `f` and
/// pattern vertex `v`, a vertex whose `UV_1` is `(f, v)` (exact in `f32` below 2^24), whose
/// `UV_0` is the coarse mesh's texture coordinates interpolated linearly (the pattern point's
/// barycentric `(l2, l3)` without them), and whose position and normal are the flat
/// triangle's (unused by the shaders, which evaluate the patch; kept so the mesh is an
/// ordinary Bevy mesh).
pub fn pattern_mesh(
    mesh: &tessella_core::Mesh,
    options: &RefineOptions,
) -> Result<PatternMesh, String> {
    let plan = Plan::new(mesh, options).map_err(|e| e.to_string())?;
    let frame = plan.frame(mesh).map_err(|e| e.to_string())?;
    let bytes = tessella_gpu::wgsl::patch_bytes(&plan, &frame).map_err(|e| e.to_string())?;
    let pattern = plan.pattern();
    let faces = plan.triangles();
    let n = pattern.points.len();
    if faces.len() * n >= 1 << 24 {
        return Err(format!(
            "{} coarse triangles of {} pattern vertices: over the 2^24 vertex ids a float carries",
            faces.len(),
            n
        ));
    }
    let mut positions = Vec::with_capacity(faces.len() * n);
    let mut normals = Vec::with_capacity(faces.len() * n);
    let mut ids = Vec::with_capacity(faces.len() * n);
    let mut uvs = Vec::with_capacity(faces.len() * n);
    let mut indices = Vec::with_capacity(faces.len() * pattern.triangles.len() * 3);
    let p = mesh.positions();
    let nm = mesh.normals();
    for (f, t) in faces.iter().enumerate() {
        let base = (f * n) as u32;
        for (v, l) in pattern.points.iter().enumerate() {
            let mix = |a: &[[f32; 3]]| {
                let [x, y, z] = t.map(|i| Vec3::from(a[i as usize]));
                (x * l[0] as f32 + y * l[1] as f32 + z * l[2] as f32).to_array()
            };
            positions.push(mix(p));
            normals.push(Vec3::from(mix(nm)).normalize_or(Vec3::Z).to_array());
            ids.push([f as f32, v as f32]);
            uvs.push(match mesh.uvs() {
                Some(uv) => {
                    let [x, y, z] = t.map(|i| Vec2::from(uv[i as usize]));
                    (x * l[0] as f32 + y * l[1] as f32 + z * l[2] as f32).to_array()
                }
                None => [l[1] as f32, l[2] as f32],
            });
        }
        indices.extend(pattern.triangles.iter().flatten().map(|&i| base + i));
    }
    let bevy_mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
    // StandardMaterial's shaders read UV_0 whenever a mesh has UV channels.
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_1, ids)
    .with_inserted_indices(Indices::U32(indices));
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for c in &frame.nets().points {
        let c = Vec3::from(*c);
        lo = lo.min(c);
        hi = hi.max(c);
    }
    Ok(PatternMesh {
        mesh: bevy_mesh,
        bytes,
        normal_mode: plan.normal_mode(),
        aabb: (lo, hi),
    })
}

fn storage(buffers: &mut Assets<ShaderBuffer>, bytes: &[u8]) -> Handle<ShaderBuffer> {
    // An empty binding is invalid; the shader never reads past the data.
    let mut data = bytes.to_vec();
    data.resize(data.len().max(16).next_multiple_of(4), 0);
    buffers.add(ShaderBuffer::new(data, RenderAssetUsages::RENDER_WORLD))
}

/// What [`tessellate`] reads of an entity.
type TessellateItem<'a> = (
    Entity,
    Ref<'a, Tessellate>,
    &'a Mesh3d,
    Option<&'a MeshMaterial3d<StandardMaterial>>,
    Option<&'a Untessellated>,
);

/// Swaps in the pattern mesh and the extended material for entities whose [`Tessellate`] is
/// new or changed (once their mesh has loaded).
fn tessellate(
    mut commands: Commands,
    query: Query<TessellateItem, Without<PendingMaterial>>,
    mut meshes: ResMut<Assets<Mesh>>,
    standard: Res<Assets<StandardMaterial>>,
    mut materials: ResMut<Assets<TessellaMaterial>>,
    mut buffers: ResMut<Assets<ShaderBuffer>>,
) {
    for (entity, tess, mesh3d, material, untessellated) in &query {
        let key = format!("{:?}", tess.0);
        let (plain_mesh, plain_material) = match (untessellated, material) {
            (Some(u), _) if u.built_for == key => continue,
            (Some(u), _) => (u.mesh.clone(), u.material.clone()),
            (None, Some(m)) => (mesh3d.0.clone(), m.0.clone()),
            (None, None) => {
                warn!("Tessellate on {entity} needs MeshMaterial3d<StandardMaterial>");
                continue;
            }
        };
        let (Some(plain), Some(base)) = (meshes.get(&plain_mesh), standard.get(&plain_material))
        else {
            continue; // not loaded yet: try again next frame
        };
        let built = to_tessella_mesh(plain).and_then(|m| pattern_mesh(&m, &tess.0));
        let built = match built {
            Ok(b) => b,
            Err(e) => {
                error!("cannot tessellate {entity}: {e}");
                commands.entity(entity).remove::<Tessellate>();
                continue;
            }
        };
        let [b0, b1, b2, b3, b4, b5, b6] = built.bytes.each_ref().map(|b| storage(&mut buffers, b));
        let material = materials.add(TessellaMaterial {
            base: base.clone(),
            extension: TessellaExtension {
                stencil: b0,
                net_points: b1,
                net_normals: b2,
                eval_params: b3,
                displace_params: b4,
                displace_data: b5,
                edge_table: b6,
                normal_mode: NormalModeKey::of(built.normal_mode),
            },
        });
        let (lo, hi) = built.aabb;
        let mut e = commands.entity(entity);
        if untessellated.is_some() {
            // Rebuilt for new options: the material type stays.
            e.insert(MeshMaterial3d(material));
        } else {
            // From StandardMaterial: the extended material comes next frame (see
            // `untessellate`).
            e.remove::<MeshMaterial3d<StandardMaterial>>()
                .insert(PendingMaterial::Tessella(material));
        }
        e.insert((
            Mesh3d(meshes.add(built.mesh)),
            // Bevy's own box would be the flat triangles'; the curve bulges past them.
            Aabb::from_min_max(lo, hi),
            NoAutoAabb,
            Untessellated {
                mesh: plain_mesh,
                material: plain_material,
                built_for: key,
            },
        ));
    }
}

/// A material put on one frame after the entity's other material type went.
#[derive(Component)]
enum PendingMaterial {
    Plain(Handle<StandardMaterial>),
    Tessella(Handle<TessellaMaterial>),
}

/// Gives the plain mesh back to entities that lost [`Tessellate`]; the plain material follows
/// next frame ([`restore_material`]). Swapping the material type of an entity within one frame
/// sometimes left Bevy 0.20.1 drawing it with the old type's pipeline and the new type's bind
/// group (a wgpu validation error in the prepass and the opaque pass, seen on removal).
fn untessellate(
    mut commands: Commands,
    mut removed: RemovedComponents<Tessellate>,
    query: Query<&Untessellated, Without<Tessellate>>,
) {
    for entity in removed.read() {
        let Ok(u) = query.get(entity) else { continue };
        commands
            .entity(entity)
            .remove::<(
                MeshMaterial3d<TessellaMaterial>,
                Untessellated,
                Aabb,
                NoAutoAabb,
            )>()
            .insert((
                Mesh3d(u.mesh.clone()),
                PendingMaterial::Plain(u.material.clone()),
            ));
    }
}

fn restore_material(mut commands: Commands, query: Query<(Entity, &PendingMaterial)>) {
    for (entity, pending) in &query {
        let mut entity = commands.entity(entity);
        entity.remove::<PendingMaterial>();
        match pending {
            PendingMaterial::Plain(m) => entity.insert(MeshMaterial3d(m.clone())),
            PendingMaterial::Tessella(m) => entity.insert(MeshMaterial3d(m.clone())),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::samples;

    /// The pattern mesh holds each coarse triangle's pattern once, with (triangle, pattern
    /// vertex) ids in UV_1, and its box holds the curved surface that tessella's CPU refinement
    /// computes (the independent reference: no shader involved).
    #[test]
    fn pattern_mesh_ids_and_box_cover_the_refined_surface() {
        for (mesh, scheme, level) in [
            (samples::tetrahedron(), Scheme::Pn, 8),
            (
                samples::torus(1.0, 0.35, 12, 8),
                Scheme::Phong { alpha: 0.75 },
                6,
            ),
            (samples::creature(), Scheme::PnAen, 4),
        ] {
            let options = RefineOptions::new(scheme, level);
            let built = pattern_mesh(&mesh, &options).unwrap();
            let points = tessella_core::Pattern::point_count(level) as usize;
            let faces = mesh.face_count();
            let Some(bevy::mesh::VertexAttributeValues::Float32x2(ids)) =
                built.mesh.attribute(Mesh::ATTRIBUTE_UV_1)
            else {
                panic!("no UV_1");
            };
            assert_eq!(ids.len(), faces * points);
            for (i, id) in ids.iter().enumerate() {
                assert_eq!(*id, [(i / points) as f32, (i % points) as f32]);
            }
            let refined = tessella_core::refine(&mesh, &options).unwrap();
            let (lo, hi) = built.aabb;
            let slack = (hi - lo).length() * 1e-5;
            for p in &refined.positions {
                let p = Vec3::from(*p);
                assert!(
                    p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                    "{p} outside the box {lo}..{hi}"
                );
            }
            // The refined surface leaves the coarse mesh's box: a box of the flat triangles
            // would cut it.
            let (clo, chi) = mesh.bounds();
            assert!(refined
                .positions
                .iter()
                .any(|p| (0..3).any(|k| p[k] < clo[k] - 1e-4 || p[k] > chi[k] + 1e-4)));
        }
    }

    /// The module registered for Bevy declares its seven bindings in group 3 at 100 to 106,
    /// none elsewhere, and no uniform.
    #[test]
    fn bevy_module_binds_in_the_material_group() {
        for mode in [NormalMode::Linear, NormalMode::Quadratic, NormalMode::Real] {
            let source = patch_module_for_bevy(mode);
            for b in 100..107 {
                assert!(
                    source.contains(&format!("@group(3) @binding({b})")),
                    "binding {b} missing"
                );
            }
            assert_eq!(source.matches("@binding(").count(), 7);
            assert!(!source.contains("var<uniform>"));
            assert!(source.contains("fn tessella_point("));
        }
    }
}
