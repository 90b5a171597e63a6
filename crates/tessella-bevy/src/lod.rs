//! Screen-space LOD: per-edge levels from Bevy's camera every frame, crack-free (each coarse
//! edge's level is computed from that edge's data alone, and its points are evaluated from the
//! edge's own data in canonical direction, the same bits from both faces). The spacing's parts
//! (tessellator strips and interiors, or grids: `tessella_core::refine::instanced::PartTable`)
//! are Bevy meshes made once, the first time a part is drawn, and shared by every entity: each
//! part repeated a power of two of times up to [`RUN_VERTICES`] vertices. A child draws a run
//! of one part's instances (a coarse triangle's part each): the part mesh of the run's length,
//! its mesh tag the run's first word in the frame's instance buffer. So an entity has a few
//! children a part (the binary digits of the part's instance count, and one a full run), not
//! one a triangle. Per frame only coarse data changes: the per-face level records and the
//! instance words (two buffer rewrites) and which runs the children draw.

use crate::pattern::{face_boxes, rewrite, run_box, RUN_VERTICES};
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
use tessella_core::refine::instanced::PartTable;
use tessella_core::refine::{Camera as LodCamera, InstancedDriver, Lod, Spacing};

use crate::lod_material::TessellaLodMaterial;

/// An entity drawn with per-edge levels: what each frame's levels are made from and written to.
#[derive(Component)]
pub(crate) struct LodState {
    /// The level function; a screen or distance LOD's camera is replaced each frame by Bevy's.
    pub lod: Lod,
    /// The part table (its spacing the entity's), and this frame's levels (picking refines
    /// with them) made into records and instances.
    pub driver: InstancedDriver,
    pub records: Handle<ShaderBuffer>,
    /// The frame's instance words (`face | side << 30`), [`MAX_PARTS`] a triangle of room.
    pub instances: Handle<ShaderBuffer>,
    pub material: Handle<TessellaLodMaterial>,
    records_written: Vec<u32>,
    instances_written: Vec<u32>,
    no_cast: bool,
    no_receive: bool,
}

impl LodState {
    pub(crate) fn new(
        lod: Lod,
        table: Arc<PartTable>,
        (records, instances): (Handle<ShaderBuffer>, Handle<ShaderBuffer>),
        material: Handle<TessellaLodMaterial>,
        shadows: (bool, bool),
    ) -> LodState {
        LodState {
            lod,
            driver: InstancedDriver::with_table(table),
            records,
            instances,
            material,
            records_written: Vec::new(),
            instances_written: Vec::new(),
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

/// Parts a coarse triangle draws at most (its interior and three strips, or one grid).
pub(crate) const MAX_PARTS: usize = 4;

/// The spacings' part tables and the Bevy meshes of the parts drawn so far, by spacing, part
/// and copies.
#[derive(Resource, Default)]
pub(crate) struct PartMeshes {
    tables: HashMap<Spacing, Arc<PartTable>>,
    meshes: HashMap<(Spacing, u32, u32), Handle<Mesh>>,
    vertices: HashMap<(Spacing, u32), usize>,
}

impl PartMeshes {
    pub(crate) fn table(&mut self, spacing: Spacing) -> Arc<PartTable> {
        self.tables
            .entry(spacing)
            .or_insert_with(|| Arc::new(PartTable::new(spacing)))
            .clone()
    }

    /// The distinct vertices of a part.
    fn vertices(&mut self, table: &PartTable, part: u32) -> usize {
        *self
            .vertices
            .entry((table.spacing, part))
            .or_insert_with(|| table.part_vertices(part).0.len())
    }

    fn mesh(
        &mut self,
        meshes: &mut Assets<Mesh>,
        table: &PartTable,
        part: u32,
        copies: u32,
    ) -> Handle<Mesh> {
        self.meshes
            .entry((table.spacing, part, copies))
            .or_insert_with(|| meshes.add(part_mesh(table, part, copies)))
            .clone()
    }
}

/// The runs drawing `count` instances of a part of `vertices` vertices, from instance word
/// `first` on: (first word, copies), each a power of two no larger than the longest run (the
/// most copies within [`RUN_VERTICES`]), the longest first; together they draw each instance
/// once.
pub(crate) fn part_runs(first: u32, count: u32, vertices: usize) -> Vec<(u32, u32)> {
    let fit = (RUN_VERTICES / vertices.max(1)).max(1) as u32;
    let longest = 1u32 << fit.ilog2();
    let mut runs = Vec::new();
    let (mut at, mut left) = (first, count);
    while left > 0 {
        let copies = if left >= longest {
            longest
        } else {
            1 << left.ilog2()
        };
        runs.push((at, copies));
        at += copies;
        left -= copies;
    }
    runs
}

/// A part repeated `copies` times as a Bevy mesh: its distinct point codes as vertices (`UV_1`
/// = (code, copy), exact in `f32`), its triangles as indices, each copy's after the last.
/// Position, normal and `UV_0` are placeholders (the shaders place each code with the face's
/// record).
fn part_mesh(table: &PartTable, part: u32, copies: u32) -> Mesh {
    let (codes, indices) = table.part_vertices(part);
    let n = codes.len();
    let all = n * copies as usize;
    let uvs: Vec<[f32; 2]> = (0..copies)
        .flat_map(|copy| codes.iter().map(move |&c| [c as f32, copy as f32]))
        .collect();
    let indices = (0..copies)
        .flat_map(|copy| indices.iter().map(move |&i| i + copy * n as u32))
        .collect();
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; all])
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; all])
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, vec![[0.0f32; 2]; all])
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_1, uvs)
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
        if let Err(e) = state.driver.update(plan.surface(), frame, &lod) {
            error!("cannot choose the levels of {entity}: {e}");
            continue;
        }
        let fi = state.driver.frame();
        if fi.records != state.records_written {
            if let Some(mut buffer) = buffers.get_mut(&state.records) {
                stats.add(rewrite(&mut buffer, bytemuck::cast_slice(&fi.records)));
                state.records_written = fi.records.clone();
            }
        }
        if fi.instances != state.instances_written {
            if let Some(mut buffer) = buffers.get_mut(&state.instances) {
                // The words, then zeros to the buffer's fixed size.
                let mut words = fi.instances.clone();
                words.resize(plan.face_count() * MAX_PARTS, 0);
                stats.add(rewrite(&mut buffer, bytemuck::cast_slice(&words)));
                state.instances_written = fi.instances.clone();
            }
        }
        chosen.triangles = fi.triangles;
        chosen.lod = Some(lod);
        let boxes = face_boxes(frame);
        let mut k = 0;
        for draw in &fi.draws {
            let vertices = parts.vertices(state.driver.table(), draw.part);
            let count = draw.instances.end - draw.instances.start;
            for (first, copies) in part_runs(draw.instances.start, count, vertices) {
                let mesh = parts.mesh(&mut meshes, state.driver.table(), draw.part, copies);
                let words = &fi.instances[first as usize..(first + copies) as usize];
                let run: Vec<(Vec3, Vec3)> = words
                    .iter()
                    .map(|w| boxes[(w & 0x3fff_ffff) as usize])
                    .collect();
                let (lo, hi) = run_box(&run);
                let aabb = Aabb::from_min_max(lo, hi);
                let patch = Patch {
                    face: first,
                    count: copies,
                };
                match children.0.get(k).and_then(|c| patches.get_mut(*c).ok()) {
                    Some((mut p, mut m, mut tag, mut b, mut v)) => {
                        if p.face != patch.face || p.count != patch.count {
                            *p = patch;
                        }
                        if m.0 != mesh {
                            m.0 = mesh.clone();
                        }
                        if tag.value != first {
                            *tag = MeshTag::new(first);
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
                            patch,
                            Mesh3d(mesh.clone()),
                            MeshMaterial3d(state.material.clone()),
                            MeshTag::new(first),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A part's runs draw each of its instances once, in order, each run a power of two of
    /// copies within the vertex budget: as many runs as full runs plus the binary digits of
    /// the rest, so a part drawn by thousands of triangles takes a few children.
    #[test]
    fn part_runs_cover_each_instance_once() {
        for vertices in [3, 10, 45, 561, 70_000] {
            let fit = (RUN_VERTICES / vertices).max(1) as u32;
            let longest = 1u32 << fit.ilog2();
            for (first, count) in [(0, 1), (7, 13), (100, 1000), (5, 81_920 * 3)] {
                let runs = part_runs(first, count, vertices);
                let mut next = first;
                for &(at, copies) in &runs {
                    assert_eq!(at, next);
                    assert!(copies.is_power_of_two() && copies <= longest);
                    assert!(copies as usize * vertices <= RUN_VERTICES.max(vertices));
                    next += copies;
                }
                assert_eq!(next, first + count);
                let expected = (count / longest + (count % longest).count_ones()) as usize;
                assert_eq!(
                    runs.len(),
                    expected,
                    "{count} instances of {vertices} vertices"
                );
            }
        }
    }

    /// A part mesh of `copies` copies holds the part's points once a copy, `UV_1` = (code,
    /// copy), and each copy's triangles over its own vertices.
    #[test]
    fn part_meshes_repeat_the_part() {
        let table = PartTable::new(Spacing::FractionalOdd);
        for part in [
            0,
            (table.ranges.len() / 2) as u32,
            table.ranges.len() as u32 - 1,
        ] {
            let (codes, indices) = table.part_vertices(part);
            let mesh = part_mesh(&table, part, 4);
            let Some(bevy::mesh::VertexAttributeValues::Float32x2(ids)) =
                mesh.attribute(Mesh::ATTRIBUTE_UV_1)
            else {
                panic!("no UV_1");
            };
            assert_eq!(ids.len(), codes.len() * 4);
            for (i, id) in ids.iter().enumerate() {
                assert_eq!(
                    *id,
                    [codes[i % codes.len()] as f32, (i / codes.len()) as f32]
                );
            }
            let all: Vec<u32> = mesh.indices().unwrap().iter().map(|i| i as u32).collect();
            assert_eq!(all.len(), indices.len() * 4);
            for (k, i) in all.iter().enumerate() {
                let copy = (k / indices.len()) as u32;
                assert_eq!(*i, indices[k % indices.len()] + copy * codes.len() as u32);
            }
        }
    }
}
