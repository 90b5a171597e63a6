//! Screen-space LOD: per-edge levels from Bevy's camera every frame, crack-free (each coarse
//! edge's level is computed from that edge's data alone, and its points are evaluated from the
//! edge's own data in canonical direction, the same bits from both faces). The spacing's parts
//! (tessellator strips and interiors, or grids: `tessella_core::refine::instanced::PartTable`)
//! are Bevy meshes made once, the first time a part is drawn, and shared by every entity. Per
//! frame only coarse data changes: the per-face level records (one buffer rewrite) and which
//! part each patch child draws with which `face | side << 30` tag.

use crate::pattern::{face_boxes, rewrite};
use crate::surface::Surface;
use crate::{Patch, Patches, UploadStats};
use bevy::asset::RenderAssetUsages;
use bevy::camera::primitives::Aabb;
use bevy::camera::visibility::NoAutoAabb;
use bevy::light::{NotShadowCaster, NotShadowReceiver};
use bevy::mesh::{Indices, MeshTag, PrimitiveTopology};
use bevy::picking::Pickable;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use std::sync::Arc;
use tessella_core::refine::instanced::{frame_instances, PartTable};
use tessella_core::refine::{lod, Camera as LodCamera, Lod, Spacing};

use crate::lod_material::TessellaLodMaterial;

/// An entity drawn with per-edge levels: what each frame's levels are made from and written to.
#[derive(Component)]
pub(crate) struct LodState {
    /// The level function; a screen or distance LOD's camera is replaced each frame by Bevy's.
    pub lod: Lod,
    pub spacing: Spacing,
    pub table: Arc<PartTable>,
    pub records: Handle<ShaderBuffer>,
    pub material: Handle<TessellaLodMaterial>,
    /// This frame's per-edge levels and per-face minimums (picking refines with them).
    pub levels: Option<(Vec<f32>, Option<Vec<f32>>)>,
    records_written: Vec<u32>,
    no_cast: bool,
    no_receive: bool,
}

impl LodState {
    pub(crate) fn new(
        lod: Lod,
        spacing: Spacing,
        table: Arc<PartTable>,
        records: Handle<ShaderBuffer>,
        material: Handle<TessellaLodMaterial>,
        shadows: (bool, bool),
    ) -> LodState {
        LodState {
            lod,
            spacing,
            table,
            records,
            material,
            levels: None,
            records_written: Vec::new(),
            no_cast: shadows.0,
            no_receive: shadows.1,
        }
    }
}

/// What an entity's per-edge LOD chose this frame, for the app to read: the triangles drawn,
/// and the LOD as evaluated (with Bevy's camera in the entity's own space and the target's
/// size, for a screen or distance LOD).
#[derive(Component, Reflect, Clone, Debug, Default)]
#[reflect(Component, Debug, Clone, Default)]
pub struct LodLevels {
    pub triangles: u64,
    /// Not reflected (tessella's own type).
    #[reflect(ignore)]
    pub lod: Option<Lod>,
}

/// Which camera the LOD sees from: a camera with this component, else the first active 3D
/// camera.
#[derive(Component, Reflect, Clone, Copy, Debug, Default)]
#[reflect(Component, Debug, Clone, Default)]
pub struct LodCameraMarker;

/// The spacings' part tables and the Bevy meshes of the parts drawn so far.
#[derive(Resource, Default)]
pub(crate) struct PartMeshes {
    tables: HashMap<Spacing, Arc<PartTable>>,
    meshes: HashMap<(Spacing, u32), Handle<Mesh>>,
}

impl PartMeshes {
    pub(crate) fn table(&mut self, spacing: Spacing) -> Arc<PartTable> {
        self.tables
            .entry(spacing)
            .or_insert_with(|| Arc::new(PartTable::new(spacing)))
            .clone()
    }

    fn mesh(&mut self, meshes: &mut Assets<Mesh>, table: &PartTable, part: u32) -> Handle<Mesh> {
        self.meshes
            .entry((table.spacing, part))
            .or_insert_with(|| meshes.add(part_mesh(table, part)))
            .clone()
    }
}

/// A part as a Bevy mesh: its distinct point codes as vertices (`UV_1` = (code, 0), exact in
/// `f32`), its triangles as indices. Position, normal and `UV_0` are placeholders (the shaders
/// place each code with the face's record).
fn part_mesh(table: &PartTable, part: u32) -> Mesh {
    let range = table.ranges[part as usize].clone();
    let mut codes: Vec<u32> = Vec::new();
    let mut local: HashMap<u32, u32> = HashMap::default();
    let mut indices = Vec::new();
    for t in &table.triangles[range.start as usize..range.end as usize] {
        for &code in t {
            let next = codes.len() as u32;
            let i = *local.entry(code).or_insert_with(|| {
                codes.push(code);
                next
            });
            indices.push(i);
        }
    }
    let n = codes.len();
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; n])
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; n])
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, vec![[0.0f32; 2]; n])
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_UV_1,
        codes
            .iter()
            .map(|&c| [c as f32, 0.0])
            .collect::<Vec<[f32; 2]>>(),
    )
    .with_inserted_indices(Indices::U32(indices))
}

/// The LOD camera in the entity's own space (its mesh's): Bevy's camera eye and view direction
/// moved by the inverse of the entity's transform, the vertical field of view, the target's
/// size in physical pixels.
fn lod_in_local_space(
    lod: &Lod,
    camera: (&Camera, &GlobalTransform, &Projection),
    entity: &GlobalTransform,
) -> Option<Lod> {
    let (camera, eye_transform, projection) = camera;
    let local = entity.affine().inverse();
    let eye = local.transform_point3(eye_transform.translation());
    let target = local.transform_point3(eye_transform.translation() + *eye_transform.forward());
    let fov_y_deg = match projection {
        Projection::Perspective(p) => p.fov.to_degrees(),
        _ => return None,
    };
    let size = camera.physical_target_size()?;
    let at = LodCamera {
        eye: eye.to_array(),
        target: target.to_array(),
        fov_y_deg,
    };
    Some(match lod {
        Lod::Screen { pixels, .. } => Lod::Screen {
            pixels: *pixels,
            camera: at,
            size: [size.x, size.y],
        },
        Lod::Distance { near, far, max, .. } => Lod::Distance {
            near: *near,
            far: *far,
            max: *max,
            eye: at.eye,
        },
        other => other.clone(),
    })
}

/// What [`levels`] reads and writes of a LOD entity.
type LodItem<'a> = (
    Entity,
    &'a mut LodState,
    &'a Surface,
    &'a GlobalTransform,
    &'a mut Patches,
    &'a mut LodLevels,
);

/// The patch children's components the LOD rewrites.
type PatchItem<'a> = (
    &'a mut Patch,
    &'a mut Mesh3d,
    &'a mut MeshTag,
    &'a mut Aabb,
    &'a mut Visibility,
);

/// The cameras a LOD may see from.
type LodCameras<'w, 's> = Query<
    'w,
    's,
    (
        &'static Camera,
        &'static GlobalTransform,
        &'static Projection,
        Has<LodCameraMarker>,
    ),
    With<Camera3d>,
>;

/// Each frame: every LOD entity's levels from the camera, its records rewritten when they
/// changed, and its patch children set to draw the parts the levels need (more children spawned
/// when a frame needs more, the rest hidden).
#[allow(clippy::too_many_arguments)]
pub(crate) fn levels(
    mut commands: Commands,
    mut entities: Query<LodItem>,
    mut patches: Query<PatchItem>,
    cameras: LodCameras,
    mut parts: ResMut<PartMeshes>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut buffers: ResMut<Assets<ShaderBuffer>>,
    stats: Res<UploadStats>,
) {
    let camera = cameras
        .iter()
        .filter(|c| c.0.is_active)
        .max_by_key(|c| (c.3, -c.0.order));
    for (entity, mut state, surface, global, mut children, mut chosen) in &mut entities {
        let state = &mut *state;
        let lod = match camera {
            Some((c, t, p, _)) => lod_in_local_space(&state.lod, (c, t, p), global),
            None => None,
        };
        let lod = match (lod, &state.lod) {
            (Some(l), _) => l,
            (None, l @ Lod::Tolerance { .. }) => l.clone(),
            // No camera to see from yet: nothing drawn this frame.
            (None, _) => continue,
        };
        let plan = &surface.plan;
        let frame = &surface.frame;
        let made = lod::levels(frame.mesh(), plan.topology(), frame.nets(), &lod).and_then(
            |(edges, faces)| {
                let fi = frame_instances(
                    &state.table,
                    plan.topology(),
                    plan.triangles(),
                    &plan.topology().position_ids,
                    &edges,
                    faces.as_deref(),
                )?;
                Ok((edges, faces, fi))
            },
        );
        let (edges, faces, fi) = match made {
            Ok(m) => m,
            Err(e) => {
                error!("cannot choose the levels of {entity}: {e}");
                continue;
            }
        };
        if fi.records != state.records_written {
            if let Some(mut buffer) = buffers.get_mut(&state.records) {
                stats.add(rewrite(&mut buffer, bytemuck::cast_slice(&fi.records)));
                state.records_written = fi.records.clone();
            }
        }
        state.levels = Some((edges, faces));
        chosen.triangles = fi.triangles;
        chosen.lod = Some(lod);
        let boxes = face_boxes(frame);
        let mut k = 0;
        for draw in &fi.draws {
            let mesh = parts.mesh(&mut meshes, &state.table, draw.part);
            for &instance in
                &fi.instances[draw.instances.start as usize..draw.instances.end as usize]
            {
                let face = (instance & 0x3fff_ffff) as usize;
                let (lo, hi) = boxes[face];
                let aabb = Aabb::from_min_max(lo, hi);
                match children.0.get(k).and_then(|c| patches.get_mut(*c).ok()) {
                    Some((mut patch, mut m, mut tag, mut b, mut v)) => {
                        if patch.face != face as u32 {
                            patch.face = face as u32;
                        }
                        if m.0 != mesh {
                            m.0 = mesh.clone();
                        }
                        if tag.value != instance {
                            *tag = MeshTag::new(instance);
                        }
                        if *b != aabb {
                            *b = aabb;
                        }
                        if *v != Visibility::Inherited {
                            *v = Visibility::Inherited;
                        }
                    }
                    None => {
                        let mut child = commands.spawn((
                            Patch {
                                face: face as u32,
                                count: 1,
                            },
                            Mesh3d(mesh.clone()),
                            MeshMaterial3d(state.material.clone()),
                            MeshTag::new(instance),
                            Transform::IDENTITY,
                            Visibility::Inherited,
                            aabb,
                            NoAutoAabb,
                            Pickable::IGNORE,
                            ChildOf(entity),
                        ));
                        if state.no_cast {
                            child.insert(NotShadowCaster);
                        }
                        if state.no_receive {
                            child.insert(NotShadowReceiver);
                        }
                        let id = child.id();
                        if k < children.0.len() {
                            children.0[k] = id;
                        } else {
                            children.0.push(id);
                        }
                    }
                }
                k += 1;
            }
        }
        for child in &children.0[k.min(children.0.len())..] {
            if let Ok((_, _, _, _, mut v)) = patches.get_mut(*child) {
                if *v != Visibility::Hidden {
                    *v = Visibility::Hidden;
                }
            }
        }
    }
}
