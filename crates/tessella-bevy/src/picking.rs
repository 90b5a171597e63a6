//! Picking a tessellated entity the way Bevy picks meshes: a picking backend that casts each
//! pointer's ray against the curved surface as drawn (tessella's CPU refinement of the
//! entity's current frame at its current levels, made again only when the pose or the levels
//! changed and a ray asks; an entity posed on the GPU has its frame posed on the CPU then, with
//! the deform the GPU drew) and reports
//! the hit on the tessellated entity itself, so `Pointer<Click>` and friends reach it and
//! bubble up its parents. Its patch children are `Pickable::IGNORE`: their pattern mesh is
//! not where the surface is.

use crate::animate::{Animated, GpuPose};
use crate::lod::LodState;
use crate::surface::Surface;
use bevy::camera::visibility::RenderLayers;
use bevy::picking::backend::ray::RayMap;
use bevy::picking::backend::{HitData, PointerHits};
use bevy::picking::mesh_picking::ray_cast::{ray_mesh_intersection, Backfaces};
use bevy::picking::mesh_picking::{MeshPickingCamera, MeshPickingSettings};
use bevy::picking::Pickable;
use bevy::prelude::*;
use tessella_core::refine::{Levels, Plan, RefinedMesh};

/// The refined triangles rays are cast against, and the surface version (and per-edge levels)
/// they were made for.
#[derive(Component, Default)]
pub(crate) struct PickMesh {
    made_for: Option<u64>,
    levels: Option<(Vec<f32>, Option<Vec<f32>>)>,
    refined: RefinedMesh,
    indices: Vec<u32>,
}

impl PickMesh {
    fn refresh(&mut self, surface: &Surface, lod: Option<&LodState>) -> Result<(), String> {
        // This frame's levels, as the LOD driver chose them; none before its first choice (a
        // surface has edges, so its levels are never empty once chosen).
        let levels = lod
            .map(|l| (l.driver.edge_levels(), l.driver.face_minimums()))
            .filter(|(edges, _)| !edges.is_empty());
        let made_with = self
            .levels
            .as_ref()
            .map(|(edges, faces)| (edges.as_slice(), faces.as_deref()));
        if self.made_for == Some(surface.version) && made_with == levels {
            return Ok(());
        }
        match (lod, levels) {
            // Per-edge levels: a plan of this frame's levels.
            (Some(state), Some((edges, faces))) => {
                let mut options = surface.plan.options().clone();
                options.spacing = state.driver.spacing();
                options.levels = Levels::PerEdge {
                    edges: edges.into(),
                    faces: faces.map(Into::into),
                };
                let mesh = surface.frame.mesh();
                let plan = Plan::new(mesh, &options).map_err(|e| e.to_string())?;
                let frame = plan.frame(mesh).map_err(|e| e.to_string())?;
                plan.refine_into(&frame, &mut self.refined, &|_| {})
                    .map_err(|e| e.to_string())?;
            }
            (Some(_), None) => {
                self.refined = RefinedMesh::default();
            }
            (None, _) => surface
                .plan
                .refine_into(&surface.frame, &mut self.refined, &|_| {})
                .map_err(|e| e.to_string())?,
        }
        self.levels = levels.map(|(edges, faces)| (edges.to_vec(), faces.map(<[f32]>::to_vec)));
        self.indices.clear();
        self.indices
            .extend(self.refined.triangles.iter().flatten().copied());
        self.made_for = Some(surface.version);
        Ok(())
    }
}

/// What [`pick`] reads of a tessellated entity.
type Target<'a> = (
    Entity,
    &'a mut Surface,
    &'a mut PickMesh,
    &'a GlobalTransform,
    Option<&'a InheritedVisibility>,
    Option<&'a Pickable>,
    Option<&'a RenderLayers>,
    Option<&'a LodState>,
    Option<(&'a mut Animated, &'a GpuPose)>,
);

/// Bevy's picking cameras.
type Cameras<'w, 's> = Query<
    'w,
    's,
    (
        &'static Camera,
        Has<MeshPickingCamera>,
        Option<&'static RenderLayers>,
    ),
>;

/// Casts every pointer ray against every visible, pickable tessellated entity (following
/// `MeshPickingSettings`' markers and render layers as Bevy's mesh backend does) and reports the
/// nearest hit on each as a `PointerHits` message.
pub(crate) fn pick(
    settings: Option<Res<MeshPickingSettings>>,
    rays: Res<RayMap>,
    cameras: Cameras,
    mut targets: Query<Target>,
    mut hits: MessageWriter<PointerHits>,
) {
    let require_markers = settings.is_some_and(|s| s.require_markers);
    for (&ray_id, &ray) in rays.iter() {
        let Ok((camera, marked_camera, camera_layers)) = cameras.get(ray_id.camera) else {
            continue;
        };
        if require_markers && !marked_camera {
            continue;
        }
        let camera_layers = camera_layers.cloned().unwrap_or_default();
        let mut picks = Vec::new();
        for (entity, mut surface, mut mesh, global, visible, pickable, layers, lod, gpu) in
            &mut targets
        {
            let shown = visible.is_none_or(|v| v.get());
            let hoverable = pickable.is_none_or(|p| p.is_hoverable);
            let marked = !require_markers || pickable.is_some();
            let layered = camera_layers.intersects(&layers.cloned().unwrap_or_default());
            if !(shown && hoverable && marked && layered) {
                continue;
            }
            let posed = match gpu {
                Some((mut animated, pose)) => animated.pose_frame(pose, &mut surface),
                None => Ok(()),
            };
            if let Err(e) = posed.and_then(|()| mesh.refresh(&surface, lod)) {
                error!("cannot pick {entity}: {e}");
                continue;
            }
            let hit = ray_mesh_intersection(
                ray,
                &global.affine(),
                &mesh.refined.positions,
                Some(&mesh.refined.normals),
                Some(&mesh.indices),
                None,
                Backfaces::Cull,
            );
            if let Some(hit) = hit {
                let data = HitData::new(
                    ray_id.camera,
                    hit.distance,
                    Some(hit.point),
                    Some(hit.normal),
                );
                picks.push((entity, data));
            }
        }
        if !picks.is_empty() {
            hits.write(PointerHits::new(ray_id.pointer, picks, camera.order as f32));
        }
    }
}
