//! tessella's curved surfaces in Bevy: add [`Tessellate`] to an entity that has `Mesh3d` and
//! `MeshMaterial3d<StandardMaterial>`, and [`TessellaPlugin`] draws it as tessella's curved
//! surface, shaded by Bevy's PBR (the entity's own `StandardMaterial`, Bevy's lights and
//! shadows). Removing `Tessellate` brings the plain mesh back. An entity Bevy animates (a
//! `SkinnedMesh` posed by its `AnimationPlayer`, morph weights) is skinned and its control
//! nets built on the GPU each frame, uploading its joint matrices and morph weights alone
//! ([`TessellaPosing`]; on the CPU, uploading its nets, where that cannot run).
//!
//! How (see `docs/bevy.md`): with uniform levels, by default ([`TessellaDraw::Mesh`]), the
//! entity gets one child drawing a Bevy mesh of its own with the refined surface's welded
//! topology and the entity's own `StandardMaterial`: a compute pass in the render world
//! evaluates each welded vertex (only in frames whose nets changed) and writes its position and
//! normal straight into Bevy's vertex buffer, so every pass draws it with Bevy's own shaders,
//! as a static mesh. The evaluation is tessella-gpu's exported WGSL module
//! (`tessella_point(face, vertex)` over the patch group's seven buffers), registered as the Bevy
//! shader import `tessella_bevy::patch_<normals>`. The other draws give the entity an
//! `ExtendedMaterial<StandardMaterial, TessellaExtension>` whose vertex shaders (main pass and
//! prepass, so shadows and depth follow the curved surface) place the points, over a mesh whose
//! vertices hold only their coarse triangle and pattern vertex: [`TessellaDraw::PerFrame`]
//! reads them from the compute pass's buffer (entities of one mesh and material share that
//! buffer and one material, a slot each, so Bevy draws a crowd in one batch a pass);
//! [`TessellaDraw::Welded`] evaluates in each pass's vertex stage; [`TessellaDraw::Runs`]
//! repeats the level's refinement pattern for runs of up to [`run_faces`] coarse triangles
//! ([`RUN_VERTICES`] vertices), one Bevy mesh shared by every entity, one child per run with
//! the run's first triangle in its `MeshTag`, batched by Bevy into one instanced draw. Either
//! way a few children at any coarse size, culled by their nets' boxes. Per-edge LOD draws a
//! few children a part of the spacing, each a run of that part's instances.

mod animate;
mod gltf_extras;
mod lod;
mod lod_material;
mod material;
mod pattern;
mod per_frame;
mod picking;
mod pool;
mod surface;

use bevy::camera::primitives::Aabb;
use bevy::camera::visibility::NoAutoAabb;
use bevy::light::{NotShadowCaster, NotShadowReceiver};
use bevy::mesh::morph::MeshMorphWeights;
use bevy::mesh::skinning::SkinnedMesh;
use bevy::mesh::MeshTag;
use bevy::picking::Pickable;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use tessella_core::{RefineOptions, Scheme};

pub use animate::{TessellaPosing, UploadStats};
pub use gltf_extras::{ExtraInfluences, InventedNormals};
pub use lod::{LodCameraMarker, LodLevels};
pub use lod_material::{adaptive_module_for_bevy, TessellaLodMaterial};
pub use material::{
    patch_module_for_bevy, NormalModeKey, TessellaExtension, TessellaKey, TessellaMaterial,
    FIRST_BINDING,
};
pub use pattern::{
    build, face_boxes, pattern_mesh, run_faces, to_bevy_mesh, to_tessella_mesh, welded_mesh, Built,
    RUN_VERTICES, WELDED_VERTICES,
};
pub use per_frame::EvaluationStats;
pub use tessella_core;

use animate::Animated;
use lod::LodState;
use lod_material::{TessellaLodExtension, TessellaLodKey};
use pattern::storage;
use picking::PickMesh;
use surface::Surface;
use tessella_core::refine::{instanced, Levels, Lod, Spacing};

/// Draws an entity's mesh as tessella's curved surface: the options of tessella's one
/// options type ([`RefineOptions`]: scheme, level or LOD, spacing, normals, ...): uniform
/// whole levels ([`Tessellate::new`]) or per-edge levels from a LOD ([`Tessellate::lod`]).
/// Reflected as an opaque value (the options are tessella's own type).
#[derive(Component, Reflect, Clone, Debug)]
#[reflect(opaque)]
#[reflect(Component, Debug, Clone)]
pub struct Tessellate(pub RefineOptions);

impl Tessellate {
    /// `level` segments per coarse edge with `scheme`, the scheme's default normals.
    pub fn new(scheme: Scheme, level: u32) -> Tessellate {
        Tessellate(RefineOptions::new(scheme, level))
    }

    /// Per-edge levels chosen every frame by `lod` (crack-free), divided with `spacing`: a
    /// screen LOD (`Lod::Screen`: pixels per refined edge) or a distance LOD sees from Bevy's
    /// camera (one with [`LodCameraMarker`], else the first active 3D camera), its own camera
    /// and size fields ignored; a tolerance LOD needs none.
    pub fn lod(scheme: Scheme, lod: Lod, spacing: Spacing) -> Tessellate {
        let mut options = RefineOptions::new(scheme, 1).with_spacing(spacing);
        options.levels = Levels::Lod(lod);
        Tessellate(options)
    }
}

/// How a tessellated entity with uniform levels is drawn (absent: [`TessellaDraw::Mesh`]).
/// Each is one instanced draw of Bevy's mesh pipeline, in every pass (shadows, prepass,
/// main); they trade GPU memory against vertex work (`docs/bevy.md` has the measurements).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[reflect(Component, Debug, Clone, Default)]
#[non_exhaustive]
pub enum TessellaDraw {
    /// The welded topology of [`TessellaDraw::Welded`], its vertices evaluated once a frame
    /// (only in frames whose nets changed: once for a still surface) by a compute pass into a
    /// buffer of 24 bytes a refined vertex, which every pass then reads as a static mesh's
    /// vertices are read: no pass evaluates. Meshes over [`WELDED_VERTICES`] vertices are
    /// drawn in runs instead.
    PerFrame,
    /// The refined surface as a Bevy mesh of its own (the welded topology, 32 bytes a vertex:
    /// position, normal, texture coordinates, plus the indices: a static mesh's size, for each
    /// entity), whose positions and normals the per-frame compute pass writes straight into
    /// Bevy's vertex buffer (only in frames whose nets changed), drawn with the entity's own
    /// `StandardMaterial` by Bevy's own shaders: every pass reads it as a static mesh, at a
    /// static mesh's cost. Meshes over [`WELDED_VERTICES`] vertices are drawn in runs instead.
    #[default]
    Mesh,
    /// The refined surface's welded topology, one child entity: each refined vertex is
    /// evaluated once per pass, as many vertices as a static mesh of the same surface, so
    /// the cost does not grow with the coarse triangle count. Its own mesh of 40 bytes a
    /// refined vertex plus the indices (a static mesh's size), made once per topology and
    /// level; meshes over [`WELDED_VERTICES`] vertices are drawn in runs instead.
    Welded,
    /// The pattern repeated in runs of consecutive triangles, one child a run: one run mesh a
    /// level, shared by every entity (a few MB whatever the size), but each triangle's edge
    /// and corner points evaluated by each triangle that has them.
    Runs,
}

/// What a tessellated entity had before [`Tessellate`] came: given back when it goes.
#[derive(Component, Reflect, Clone, Debug)]
#[reflect(Component, Debug, Clone)]
pub struct Untessellated {
    pub mesh: Handle<Mesh>,
    pub material: Handle<StandardMaterial>,
    /// The options the current patches were built for.
    built_for: String,
}

/// Registers the material, the shader modules, the glTF reader of extra joint influences and
/// the systems that swap an entity's mesh and material when [`Tessellate`] comes or goes and
/// pose the animated ones.
pub struct TessellaPlugin;

/// The plugin's systems, in `PostUpdate` after transform propagation and before Bevy computes
/// bounds and visibility: patches built or removed, animated entities posed, LOD levels chosen.
/// Order an app's own systems against it (`.after(TessellaSystems)` sees this frame's patches,
/// poses and [`LodLevels`]).
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TessellaSystems;

impl Plugin for TessellaPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins((
            MaterialPlugin::<TessellaMaterial>::default(),
            MaterialPlugin::<TessellaLodMaterial>::default(),
        ));
        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
        let registered = material::register_shaders(&mut shaders)
            .and_then(|()| lod_material::register_shaders(&mut shaders));
        if let Err(e) = registered {
            error!("tessella: {e}");
        }
        gltf_extras::register(app);
        per_frame::register(app);
        // TessellaDraw::Mesh: the compute pass writes into Bevy's vertex buffers.
        if let Some(render_app) = app.get_sub_app_mut(bevy::render::RenderApp) {
            let mut settings = render_app
                .world_mut()
                .get_resource_or_init::<bevy::render::mesh::allocator::MeshAllocatorSettings>(
            );
            settings.extra_buffer_usages |= bevy::render::render_resource::BufferUsages::STORAGE;
        }
        app.init_resource::<UploadStats>()
            .init_resource::<PatternMeshes>()
            .init_resource::<WeldedMeshes>()
            .init_resource::<pool::Pools>()
            .init_resource::<lod::PartMeshes>();
        register_types(app);
        app.add_systems(
            PostUpdate,
            (
                untessellate,
                per_frame::release_slots,
                tessellate,
                animate::pose,
                lod::levels,
            )
                .chain()
                .in_set(TessellaSystems)
                .after(bevy::transform::TransformSystems::Propagate)
                .before(bevy::camera::visibility::VisibilitySystems::CalculateBounds)
                .before(bevy::camera::visibility::VisibilitySystems::VisibilityPropagate),
        );
    }

    fn finish(&self, app: &mut App) {
        // Tessellated entities are picked wherever the app picks Bevy's meshes
        // (`MeshPickingPlugin`, added before or after this plugin).
        let world = app.world();
        if world.contains_resource::<bevy::picking::mesh_picking::MeshPickingSettings>()
            && world.contains_resource::<bevy::picking::backend::ray::RayMap>()
        {
            app.add_systems(
                PreUpdate,
                picking::pick.in_set(bevy::picking::PickingSystems::Backend),
            );
        }
    }
}

/// Registers the plugin's components for reflection (the glTF reader registers its own).
fn register_types(app: &mut App) {
    app.register_type::<Tessellate>()
        .register_type::<TessellaDraw>()
        .register_type::<TessellaPosing>()
        .register_type::<Untessellated>()
        .register_type::<Patch>()
        .register_type::<Patches>()
        .register_type::<LodLevels>()
        .register_type::<LodCameraMarker>();
}

/// A child of the tessellated entity: with uniform levels, drawing the patches of coarse
/// triangles `face..face + count` (a run of up to [`run_faces`] triangles drawing the level's
/// shared run mesh with `face` in its `MeshTag`, or the whole welded mesh); with per-edge LOD,
/// a run of `count` instances of one part (each a coarse triangle's part), their instance words
/// from `face` on in the frame's instance buffer (`face` in the tag too).
#[derive(Component, Reflect, Clone, Copy, Debug)]
#[reflect(Component, Debug, Clone)]
pub struct Patch {
    /// The first coarse triangle.
    pub face: u32,
    /// How many coarse triangles, from `face` on.
    pub count: u32,
}

/// A tessellated entity's patch children, in triangle order.
#[derive(Component, Reflect, Clone, Debug, Default)]
#[reflect(Component, Debug, Clone, Default)]
pub struct Patches(pub Vec<Entity>);

/// The welded meshes drawn, by the coarse mesh and the options: entities that share a mesh
/// (a crowd spawned from one glTF) share its welded mesh, and its origins for the per-frame
/// evaluation, while one of them draws it.
#[derive(Resource, Default)]
struct WeldedMeshes(bevy::platform::collections::HashMap<(AssetId<Mesh>, String), Welded>);

/// A welded mesh and, once a per-frame entity asked for them, its vertices' origins.
struct Welded {
    mesh: AssetId<Mesh>,
    origins: Option<Handle<ShaderBuffer>>,
}

impl WeldedMeshes {
    /// The welded mesh of `plan` for the coarse mesh and options in `key` (the one drawn
    /// already, or a new one), and with `origins` its vertices' origins (made once).
    fn get(
        &mut self,
        meshes: &mut Assets<Mesh>,
        buffers: &mut Assets<ShaderBuffer>,
        key: (AssetId<Mesh>, String),
        plan: &tessella_core::refine::Plan,
        origins: bool,
    ) -> Result<(Handle<Mesh>, Option<Handle<ShaderBuffer>>), String> {
        let drawn = self
            .0
            .get(&key)
            .and_then(|w| meshes.get_strong_handle(w.mesh));
        // A new mesh's vertex origins, kept for its origins buffer (found once).
        let mut found = None;
        let handle = match drawn {
            Some(handle) => handle,
            None => {
                // Entries whose mesh every entity dropped go.
                self.0.retain(|_, w| meshes.contains(w.mesh));
                let points = pattern::welded_points(plan)?;
                if origins {
                    found = Some(points.1.clone());
                }
                let handle = meshes.add(pattern::welded_mesh_of(plan, points)?);
                let welded = Welded {
                    mesh: handle.id(),
                    origins: None,
                };
                self.0.insert(key.clone(), welded);
                handle
            }
        };
        let welded = self.0.get_mut(&key).expect("inserted above");
        if origins && welded.origins.is_none() {
            let ids = match found {
                Some(ids) => ids,
                None => pattern::welded_points(plan)?.1,
            };
            welded.origins = Some(storage(buffers, &per_frame::origins_bytes(&ids)));
        }
        let origins = welded.origins.clone().filter(|_| origins);
        Ok((handle, origins))
    }
}

/// The run meshes drawn so far, by level and number of triangles: the full run of a level is
/// shared by every tessellated entity and every run; a shorter last run by the entities whose
/// triangle count leaves it.
#[derive(Resource, Default)]
struct PatternMeshes(bevy::platform::collections::HashMap<(u32, usize), Handle<Mesh>>);

impl PatternMeshes {
    /// The mesh of `faces` triangles of `pattern`, made the first time it is asked for.
    fn get(
        &mut self,
        meshes: &mut Assets<Mesh>,
        pattern: &tessella_core::Pattern,
        faces: usize,
    ) -> Result<Handle<Mesh>, String> {
        let key = (pattern.level, faces);
        if let Some(handle) = self.0.get(&key) {
            return Ok(handle.clone());
        }
        let handle = meshes.add(pattern_mesh(pattern, faces)?);
        self.0.insert(key, handle.clone());
        Ok(handle)
    }
}

/// What [`tessellate`] reads of an entity.
type TessellateItem<'a> = (
    Entity,
    Ref<'a, Tessellate>,
    Option<&'a Mesh3d>,
    Option<&'a MeshMaterial3d<StandardMaterial>>,
    Option<&'a Untessellated>,
    Option<&'a Patches>,
    (
        Option<&'a SkinnedMesh>,
        Option<&'a MeshMorphWeights>,
        Option<&'a ExtraInfluences>,
    ),
    (
        Has<NotShadowCaster>,
        Has<NotShadowReceiver>,
        Has<InventedNormals>,
        Option<&'a TessellaDraw>,
        Option<&'a TessellaPosing>,
    ),
);

/// The assets [`tessellate`] reads and adds.
type TessellateAssets<'w> = (
    ResMut<'w, Assets<Mesh>>,
    Res<'w, Assets<StandardMaterial>>,
    ResMut<'w, Assets<TessellaMaterial>>,
    ResMut<'w, Assets<ShaderBuffer>>,
    ResMut<'w, PatternMeshes>,
    ResMut<'w, Assets<TessellaLodMaterial>>,
    ResMut<'w, lod::PartMeshes>,
    ResMut<'w, WeldedMeshes>,
    ResMut<'w, pool::Pools>,
);

/// Builds the patches of entities whose [`Tessellate`] is new or changed (once their mesh and
/// material have loaded): the entity's own mesh and material come off (kept in
/// [`Untessellated`]) and one [`Patch`] child per coarse triangle draws the level's pattern.
fn tessellate(
    mut commands: Commands,
    query: Query<TessellateItem>,
    assets: TessellateAssets,
    stats: Res<UploadStats>,
) {
    let (
        mut meshes,
        standard,
        mut materials,
        mut buffers,
        mut patterns,
        mut lod_materials,
        mut parts,
        mut welded,
        mut pools,
    ) = assets;
    for (entity, tess, mesh3d, material, untessellated, patches, deform, flags) in &query {
        let (skin, morph, extra) = deform;
        let (no_cast, no_receive, invented, draw, posing) = flags;
        let draw = draw.copied().unwrap_or_default();
        let posing = posing.copied().unwrap_or_default();
        let key = format!("{:?} {draw:?} {posing:?}", tess.0);
        let (plain_mesh, plain_material) = match (untessellated, mesh3d, material) {
            (Some(u), _, _) if u.built_for == key => continue,
            (Some(u), _, _) => (u.mesh.clone(), u.material.clone()),
            (None, Some(m), Some(s)) => (m.0.clone(), s.0.clone()),
            (None, _, _) => {
                warn!("Tessellate on {entity} needs Mesh3d and MeshMaterial3d<StandardMaterial>");
                commands.entity(entity).remove::<Tessellate>();
                continue;
            }
        };
        let (Some(plain), Some(base)) = (meshes.get(&plain_mesh), standard.get(&plain_material))
        else {
            continue; // not loaded yet: try again next frame
        };
        // Copies of the coarse mesh and material: the pattern mesh may be added below.
        let (plain, base) = (plain.clone(), base.clone());
        // With per-edge LOD the levels come every frame (`lod::levels`); the plan is made at
        // level 1 for the topology, the nets and posing (nets do not depend on the level).
        let lod = match &tess.0.levels {
            Levels::Lod(l) => Some(l.clone()),
            _ => None,
        };
        let mut options = tess.0.clone();
        if lod.is_some() {
            options.levels = Levels::Uniform(1.0);
            options.spacing = Spacing::Grid;
        }
        let built =
            pattern::read_mesh(&plain, !invented).and_then(|m| pattern::build(&m, &options));
        // The welded mesh (with the origins of its vertices when they are evaluated per
        // frame), or the runs: consecutive triangles, each drawing the level's run mesh (the
        // last one maybe a shorter one).
        let mut origins = None;
        let mut welded_mesh = None;
        let mut own_mesh = None;
        let runs = match (&built, &lod) {
            (Ok(b), None)
                if draw == TessellaDraw::Mesh && b.plan.vertex_count() <= WELDED_VERTICES =>
            {
                let face_uvs: &[[f32; 2]] = bytemuck::cast_slice(&b.bytes[7]);
                pattern::vertex_mesh(&b.plan, face_uvs).map(|(mesh, ids)| {
                    let handle = meshes.add(mesh);
                    origins = Some(storage(&mut buffers, &per_frame::origins_bytes(&ids)));
                    own_mesh = Some(handle.id());
                    vec![(0..b.boxes.len(), handle)]
                })
            }
            (Ok(b), None)
                if draw != TessellaDraw::Runs && b.plan.vertex_count() <= WELDED_VERTICES =>
            {
                let key = (plain_mesh.id(), format!("{:?}", tess.0));
                let per_frame = draw == TessellaDraw::PerFrame;
                welded
                    .get(&mut meshes, &mut buffers, key, &b.plan, per_frame)
                    .map(|(m, o)| {
                        origins = o;
                        welded_mesh = Some(m.id());
                        vec![(0..b.boxes.len(), m)]
                    })
            }
            (Ok(b), None) => runs(&mut patterns, &mut meshes, b),
            _ => Ok(Vec::new()),
        };
        let (built, runs) = match (built, runs) {
            (Ok(b), Ok(r)) => (b, r),
            (Err(e), _) | (_, Err(e)) => {
                error!("cannot tessellate {entity}: {e}");
                commands.entity(entity).remove::<Tessellate>();
                continue;
            }
        };
        // Bevy animates it: tessella poses the coarse mesh each frame (`animate::pose`).
        let animated = (skin.is_some() || morph.is_some()).then(|| skin.map(|s| s.joints.len()));
        let handles = built.bytes.each_ref().map(|b| storage(&mut buffers, b));
        let made: usize = built.bytes.iter().map(|b| pattern::padded(b).len()).sum();
        stats.add(made as u64);
        let animated = match animated {
            None => None,
            Some(joints) => {
                let made = Animated::new(
                    &plain,
                    extra,
                    joints,
                    &built.frame,
                    handles[1].clone(),
                    handles[2].clone(),
                );
                match made {
                    Ok(a) => Some(a),
                    Err(e) => {
                        error!("cannot animate the tessellated {entity}: {e}");
                        commands.entity(entity).remove::<Tessellate>();
                        continue;
                    }
                }
            }
        };
        if let Some(old) = patches {
            for child in &old.0 {
                commands.entity(*child).despawn();
            }
        }
        if let Some(lod) = lod {
            // The LOD's children come with its first levels (`lod::levels`).
            let basis = built.frame.nets().basis;
            let params = storage(
                &mut buffers,
                &tessella_gpu::wgsl::adaptive_params_bytes(basis),
            );
            let record_bytes = built.boxes.len() * instanced::RECORD_WORDS * 4;
            let records = storage(&mut buffers, &vec![0u8; record_bytes]);
            // Room for a triangle's most parts, so the buffer keeps its size from frame to
            // frame (Bevy rewrites it in place).
            let instance_bytes = built.boxes.len() * lod::MAX_PARTS * 4;
            let instances = storage(&mut buffers, &vec![0u8; instance_bytes]);
            let [_, b1, b2, _, _, _, _, b7] = handles;
            let spacing = tess.0.spacing;
            let material = lod_materials.add(TessellaLodMaterial {
                base,
                extension: TessellaLodExtension {
                    net_points: b1,
                    net_normals: b2,
                    params,
                    records: records.clone(),
                    face_uvs: b7,
                    instances: instances.clone(),
                    key: TessellaLodKey::of(basis, built.normal_mode, spacing),
                },
            });
            let state = LodState::new(
                lod,
                parts.table(spacing),
                (records, instances),
                material,
                (no_cast, no_receive),
            );
            commands
                .entity(entity)
                .insert((state, LodLevels::default()))
                .remove::<(per_frame::PerFrameSource, animate::GpuPose)>();
            finish(
                &mut commands,
                entity,
                animated,
                built,
                Vec::new(),
                Untessellated {
                    mesh: plain_mesh,
                    material: plain_material,
                    built_for: key,
                },
            );
            continue;
        }
        commands.entity(entity).remove::<(LodState, LodLevels)>();
        let [b0, b1, b2, b3, b4, b5, b6, b7] = handles;
        let normal_mode = NormalModeKey::of(built.normal_mode);
        let extension = |evaluated: Handle<ShaderBuffer>, per_frame: bool| TessellaExtension {
            stencil: b0.clone(),
            net_points: b1.clone(),
            net_normals: b2.clone(),
            eval_params: b3.clone(),
            displace_params: b4.clone(),
            displace_data: b5.clone(),
            edge_table: b6.clone(),
            face_uvs: b7.clone(),
            evaluated,
            normal_mode,
            per_frame,
        };
        // Per frame: a slot of the buffer the compute pass writes and the vertex stages read,
        // in a pool whose material every entity of the same welded mesh and base material
        // shares (`pool.rs`: Bevy draws them in one batch).
        let per_frame = origins.map(|origins| {
            let vertices = built.plan.vertex_count() as u32;
            let target = match (own_mesh, welded_mesh) {
                (Some(mesh), _) => per_frame::Target::Mesh(mesh),
                (None, mesh) => per_frame::Target::Slot(pools.join(
                    entity,
                    mesh.unwrap_or_default(),
                    plain_material.id(),
                    vertices,
                    &mut buffers,
                    &mut materials,
                    |evaluated| TessellaMaterial {
                        base: base.clone(),
                        extension: extension(evaluated, true),
                    },
                )),
            };
            per_frame::PerFrameSource {
                patch: [&b0, &b1, &b2, &b3, &b4, &b5, &b6].map(|b| b.clone()),
                origins,
                target,
                mode: normal_mode,
                basis: built.plan.options().scheme.basis(),
                vertices,
            }
        });
        match &per_frame {
            Some(p) => commands.entity(entity).insert(p.clone()),
            None => commands
                .entity(entity)
                .remove::<per_frame::PerFrameSource>(),
        };
        // Posed on the GPU: with the per-frame draw, where the GPU builds the nets.
        let gpu_pose = match (&animated, &per_frame, posing) {
            (Some(a), Some(_), TessellaPosing::Gpu) => a.gpu_pose(&built.plan),
            _ => None,
        };
        match gpu_pose {
            Some(p) => commands.entity(entity).insert(p),
            None => commands.entity(entity).remove::<animate::GpuPose>(),
        };
        // The pool's material, its slot's first vertex in the tag; the entity's own
        // StandardMaterial for its own mesh; or a material of its own.
        let (material, pooled_tag) = match per_frame.as_ref().map(|p| p.target) {
            Some(per_frame::Target::Slot(seat)) => {
                let pool = &pools.0[&seat.pool];
                let tessellated = pool.material.clone();
                (
                    ChildMaterial::Tessella(tessellated),
                    Some(seat.slot * pool.stride),
                )
            }
            Some(per_frame::Target::Mesh(_)) => {
                (ChildMaterial::Standard(plain_material.clone()), None)
            }
            None => (
                ChildMaterial::Tessella(materials.add(TessellaMaterial {
                    base,
                    extension: extension(b7.clone(), false),
                })),
                None,
            ),
        };
        let children: Vec<Entity> = runs
            .into_iter()
            .map(|(faces, mesh)| {
                let (lo, hi) = pattern::run_box(&built.boxes[faces.clone()]);
                let mut child = commands.spawn((
                    Patch {
                        face: faces.start as u32,
                        count: faces.len() as u32,
                    },
                    Mesh3d(mesh),
                    MeshTag::new(pooled_tag.unwrap_or(faces.start as u32)),
                    Transform::IDENTITY,
                    // Bevy's own box would be the pattern's; each run has its nets'.
                    Aabb::from_min_max(lo, hi),
                    NoAutoAabb,
                    // Picked through the parent's surface (`picking`), not the pattern.
                    Pickable::IGNORE,
                    ChildOf(entity),
                ));
                match &material {
                    ChildMaterial::Tessella(m) => child.insert(MeshMaterial3d(m.clone())),
                    ChildMaterial::Standard(m) => child.insert(MeshMaterial3d(m.clone())),
                };
                if no_cast {
                    child.insert(NotShadowCaster);
                }
                if no_receive {
                    child.insert(NotShadowReceiver);
                }
                child.id()
            })
            .collect();
        let untessellated = Untessellated {
            mesh: plain_mesh,
            material: plain_material,
            built_for: key,
        };
        finish(
            &mut commands,
            entity,
            animated,
            built,
            children,
            untessellated,
        );
    }
}

/// What a patch child is drawn with: the tessellated material (evaluating, or reading a pool's
/// slot), or the entity's own `StandardMaterial` over a mesh the compute pass writes.
enum ChildMaterial {
    Tessella(Handle<TessellaMaterial>),
    Standard(Handle<StandardMaterial>),
}

/// A run: its coarse triangles and the run mesh that draws them.
type Run = (std::ops::Range<usize>, Handle<Mesh>);

/// The runs of a mesh built with uniform levels.
fn runs(
    patterns: &mut PatternMeshes,
    meshes: &mut Assets<Mesh>,
    built: &pattern::Built,
) -> Result<Vec<Run>, String> {
    let pattern = built.plan.pattern();
    let faces = built.boxes.len();
    let per_run = run_faces(pattern.points.len());
    (0..faces)
        .step_by(per_run)
        .map(|first| {
            let run = first..(first + per_run).min(faces);
            let mesh = patterns.get(meshes, pattern, run.len())?;
            Ok((run, mesh))
        })
        .collect()
}

/// The tessellated entity's own components: its mesh and material off, its surface, patches
/// and animation on.
fn finish(
    commands: &mut Commands,
    entity: Entity,
    animated: Option<Animated>,
    built: pattern::Built,
    children: Vec<Entity>,
    untessellated: Untessellated,
) {
    let mut e = commands.entity(entity);
    match animated {
        Some(a) => e.insert(a),
        None => e.remove::<Animated>(),
    };
    e.remove::<(Mesh3d, MeshMaterial3d<StandardMaterial>)>()
        .insert((
            Surface {
                plan: built.plan,
                frame: built.frame,
                version: 0,
            },
            PickMesh::default(),
            Patches(children),
            untessellated,
        ));
}

/// Gives the plain mesh and material back to entities that lost [`Tessellate`], and despawns
/// their patches.
fn untessellate(
    mut commands: Commands,
    mut removed: RemovedComponents<Tessellate>,
    query: Query<(&Untessellated, Option<&Patches>), Without<Tessellate>>,
) {
    for entity in removed.read() {
        let Ok((u, patches)) = query.get(entity) else {
            continue;
        };
        for child in patches.map(|p| p.0.as_slice()).unwrap_or_default() {
            commands.entity(*child).despawn();
        }
        commands
            .entity(entity)
            .remove::<(
                Untessellated,
                Patches,
                Animated,
                Surface,
                PickMesh,
                LodState,
                LodLevels,
                per_frame::PerFrameSource,
                animate::GpuPose,
            )>()
            .insert((Mesh3d(u.mesh.clone()), MeshMaterial3d(u.material.clone())));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::{samples, NormalMode};

    /// The plugin's components are registered for reflection (scene files, inspectors,
    /// `Commands` by type name): each has its `ReflectComponent`, and the opaque `Tessellate`
    /// clones through reflection with its options intact.
    #[test]
    fn components_are_reflected() {
        let mut app = App::new();
        register_types(&mut app);
        let registry = app.world().resource::<AppTypeRegistry>().read();
        for (name, id) in [
            ("Tessellate", std::any::TypeId::of::<Tessellate>()),
            ("TessellaDraw", std::any::TypeId::of::<TessellaDraw>()),
            ("TessellaPosing", std::any::TypeId::of::<TessellaPosing>()),
            ("Untessellated", std::any::TypeId::of::<Untessellated>()),
            ("Patch", std::any::TypeId::of::<Patch>()),
            ("Patches", std::any::TypeId::of::<Patches>()),
            ("LodLevels", std::any::TypeId::of::<LodLevels>()),
            ("LodCameraMarker", std::any::TypeId::of::<LodCameraMarker>()),
        ] {
            assert!(
                registry.get_type_data::<ReflectComponent>(id).is_some(),
                "{name} has no ReflectComponent"
            );
        }
        let tessellate = Tessellate::new(Scheme::PnAen, 5);
        let cloned = tessellate.reflect_clone().expect("clones");
        let back = cloned.downcast_ref::<Tessellate>().expect("a Tessellate");
        assert_eq!(format!("{:?}", back.0), format!("{:?}", tessellate.0));
    }

    /// A run mesh holds the level's pattern once per triangle of the run, with each vertex's
    /// index and triangle in UV_1 and its barycentric in UV_0; the per-triangle boxes together hold the curved surface that
    /// tessella's CPU refinement computes (the independent reference: no shader involved),
    /// which leaves the coarse mesh's box.
    #[test]
    fn pattern_mesh_and_patch_boxes_cover_the_refined_surface() {
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
            let built = build(&mesh, &options).unwrap();
            let faces = 3;
            let run = pattern_mesh(built.plan.pattern(), faces).unwrap();
            let points = tessella_core::Pattern::point_count(level) as usize;
            let Some(bevy::mesh::VertexAttributeValues::Float32x2(ids)) =
                run.attribute(Mesh::ATTRIBUTE_UV_1)
            else {
                panic!("no UV_1");
            };
            assert_eq!(ids.len(), points * faces);
            for (i, id) in ids.iter().enumerate() {
                assert_eq!(*id, [(i % points) as f32, (i / points) as f32]);
            }
            let Some(bevy::mesh::VertexAttributeValues::Float32x2(bary)) =
                run.attribute(Mesh::ATTRIBUTE_UV_0)
            else {
                panic!("no UV_0");
            };
            let pattern = built.plan.pattern();
            for (i, b) in bary.iter().enumerate() {
                let l = pattern.points[i % points];
                assert_eq!(*b, [l[1] as f32, l[2] as f32]);
            }
            // Each triangle of the run is the pattern's, moved to its own vertices.
            let indices: Vec<u32> = run.indices().unwrap().iter().map(|i| i as u32).collect();
            let per_face = pattern.triangles.len() * 3;
            assert_eq!(indices.len(), per_face * faces);
            for (k, i) in indices.iter().enumerate() {
                let own = pattern.triangles[(k % per_face) / 3][k % 3];
                assert_eq!(*i, own + ((k / per_face) * points) as u32);
            }
            assert_eq!(built.boxes.len(), mesh.face_count());
            // Texture coordinates: three a coarse triangle.
            assert_eq!(built.bytes[7].len(), mesh.face_count() * 3 * 8);
            let refined = tessella_core::refine(&mesh, &options).unwrap();
            let (lo, hi) = built
                .boxes
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), (l, h)| {
                    (a.min(*l), b.max(*h))
                });
            let slack = (hi - lo).length() * 1e-5;
            for p in &refined.positions {
                let p = Vec3::from(*p);
                assert!(
                    built
                        .boxes
                        .iter()
                        .any(|(l, h)| p.cmpge(*l - slack).all() && p.cmple(*h + slack).all()),
                    "{p} outside every patch box"
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

    /// The runs cover every coarse triangle once, in order, each within the vertex budget;
    /// the full runs share one mesh, and a second entity of the same level reuses it.
    #[test]
    fn runs_cover_every_triangle_with_shared_meshes() {
        let mut meshes = Assets::<Mesh>::default();
        let mut patterns = PatternMeshes::default();
        let mesh = samples::torus(1.0, 0.35, 160, 128);
        let built = build(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
        let points = built.plan.pattern().points.len();
        let per_run = run_faces(points);
        assert!(per_run * points <= RUN_VERTICES && (per_run + 1) * points > RUN_VERTICES);
        let faces = mesh.face_count();
        let runs = runs(&mut patterns, &mut meshes, &built).unwrap();
        assert_eq!(runs.len(), faces.div_ceil(per_run));
        let mut next = 0;
        for (run, handle) in &runs {
            assert_eq!(run.start, next);
            assert!(!run.is_empty() && run.len() <= per_run);
            next = run.end;
            let drawn = meshes.get(handle).unwrap();
            assert_eq!(drawn.count_vertices(), run.len() * points);
        }
        assert_eq!(next, faces);
        let full: std::collections::HashSet<_> = runs
            .iter()
            .filter(|(r, _)| r.len() == per_run)
            .map(|(_, h)| h.id())
            .collect();
        assert_eq!(full.len(), 1);
        let before = meshes.len();
        let again = super::runs(&mut patterns, &mut meshes, &built).unwrap();
        assert_eq!(meshes.len(), before);
        assert_eq!(again[0].1, runs[0].1);
    }

    /// The welded mesh has one vertex per refined vertex and the plan's triangles; each
    /// vertex names a pattern point at the barycentric the plan gives it. Entities with the
    /// same coarse mesh and options share it; other options make another.
    #[test]
    fn welded_meshes_follow_the_plan_and_are_shared() {
        let mesh = samples::torus(1.0, 0.35, 12, 8);
        let built = build(&mesh, &RefineOptions::new(Scheme::Pn, 5)).unwrap();
        let welded_mesh = pattern::welded_mesh(&built.plan).unwrap();
        assert_eq!(welded_mesh.count_vertices(), built.plan.vertex_count());
        let indices: Vec<u32> = welded_mesh
            .indices()
            .unwrap()
            .iter()
            .map(|i| i as u32)
            .collect();
        let expected: Vec<u32> = built.plan.indices().iter().flatten().copied().collect();
        assert_eq!(indices, expected);
        let (faces, bary) = built.plan.origin();
        let Some(bevy::mesh::VertexAttributeValues::Float32x2(ids)) =
            welded_mesh.attribute(Mesh::ATTRIBUTE_UV_1)
        else {
            panic!("no UV_1");
        };
        let points = &built.plan.pattern().points;
        for ((id, face), l) in ids.iter().zip(&faces).zip(&bary) {
            assert_eq!(id[1], *face as f32);
            let p = points[id[0] as usize];
            assert_eq!([p[1] as f32, p[2] as f32], [l[1], l[2]]);
        }
        // A vertex of every face: none is left to another face's evaluation.
        let owners: std::collections::HashSet<u32> = faces.iter().copied().collect();
        assert_eq!(owners.len(), mesh.face_count());

        let mut meshes = Assets::<Mesh>::default();
        let mut buffers = Assets::<ShaderBuffer>::default();
        let mut welded = WeldedMeshes::default();
        let coarse = AssetId::<Mesh>::default();
        let mut get = |options: &str, origins: bool| {
            let key = (coarse, options.to_string());
            welded
                .get(&mut meshes, &mut buffers, key, &built.plan, origins)
                .unwrap()
        };
        let (a, none) = get("pn 5", false);
        assert!(none.is_none());
        // A per-frame entity asks for the origins: made once, then shared.
        let (b, origins) = get("pn 5", true);
        let (_, again) = get("pn 5", true);
        assert_eq!(a, b);
        assert_eq!(origins, again);
        let (c, _) = get("pn 6", false);
        assert_ne!(a, c);
        assert_eq!(meshes.len(), 2);
        assert_eq!(buffers.len(), 1);
        // The origins are each welded vertex's (triangle, pattern vertex), as UV_1 names them.
        let data = match &buffers.get(&origins.unwrap()).unwrap().data {
            bevy::render::storage::ShaderBufferData::Initialized { data, .. } => data.to_vec(),
            _ => panic!("no origins"),
        };
        let words: &[[u32; 2]] = bytemuck::cast_slice(&data[..ids.len() * 8]);
        for (w, id) in words.iter().zip(ids) {
            assert_eq!(*w, [id[1] as u32, id[0] as u32]);
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
