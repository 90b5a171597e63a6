//! A tessellated entity that Bevy animates: its `SkinnedMesh` joints (posed by Bevy's
//! `AnimationPlayer`) and its morph weights pose the *coarse* mesh each frame with tessella's
//! skinning (`tessella_core::animation::Poser::pose_with`: morph targets, then every joint
//! influence set, normals by the inverse transpose), the control nets are rebuilt, and only the
//! two net buffers are rewritten: bytes in proportion to the coarse triangles, whatever the
//! level.

use crate::gltf_extras::ExtraInfluences;
use crate::pattern::{face_boxes, rewrite, run_box};
use crate::surface::Surface;
use crate::{Patch, Patches};
use bevy::camera::primitives::Aabb;
use bevy::mesh::morph::{MeshMorphWeights, MorphWeights};
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::mesh::VertexAttributeValues;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use tessella_core::animation::{
    AnimatedMesh, Influences, Instance, MorphTarget, Node, Poser, Skin,
};
use tessella_core::refine::Frame;

/// Bytes tessella handed to Bevy for upload: every buffer it made or rewrote, counted when
/// handed over (Bevy uploads them in that frame's render). A deforming entity adds its two
/// net buffers a frame; a still one adds nothing.
#[derive(Resource, Clone, Default, Debug)]
pub struct UploadStats(Arc<AtomicU64>);

impl UploadStats {
    /// The bytes handed over since the app started.
    pub fn total(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }
    pub(crate) fn add(&self, bytes: u64) {
        self.0.fetch_add(bytes, Ordering::Relaxed);
    }
}

/// What posing a tessellated entity needs, made once when it is tessellated.
#[derive(Component)]
pub(crate) struct Animated {
    poser: Poser,
    net_points: Handle<ShaderBuffer>,
    net_normals: Handle<ShaderBuffer>,
    skinned: bool,
    matrices: Vec<[f32; 16]>,
    weights: Vec<f32>,
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    /// The deform the nets were last built for; an unchanged one uploads nothing.
    posed_for: Option<(Vec<[f32; 16]>, Vec<f32>)>,
}

impl Animated {
    /// The animation of `plain` (a Bevy mesh of `joints` joints and `targets` morph targets)
    /// as a one-instance tessella model: the caller gives each frame's joint matrices already
    /// composed, so the model's joints are stand-in nodes with identity inverse binds. `frame`
    /// is the surface's frame as built (its mesh is the bind pose).
    pub(crate) fn new(
        plain: &Mesh,
        extra: Option<&ExtraInfluences>,
        joints: Option<usize>,
        frame: &Frame,
        net_points: Handle<ShaderBuffer>,
        net_normals: Handle<ShaderBuffer>,
    ) -> Result<Animated, String> {
        let mesh = frame.mesh();
        let positions = mesh.positions().to_vec();
        let has_normals = plain.attribute(Mesh::ATTRIBUTE_NORMAL).is_some();
        let normals = has_normals.then(|| mesh.normals().to_vec());
        let count = positions.len();
        let targets = morph_targets(plain, count);
        let mut influences = Vec::new();
        if joints.is_some() {
            let ids = match plain.attribute(Mesh::ATTRIBUTE_JOINT_INDEX) {
                Some(VertexAttributeValues::Uint16x4(j)) => j.clone(),
                _ => return Err("a skinned mesh without Uint16x4 joint indices".into()),
            };
            let weights = match plain.attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT) {
                Some(VertexAttributeValues::Float32x4(w)) => w.clone(),
                _ => return Err("a skinned mesh without Float32x4 joint weights".into()),
            };
            influences.push(Influences {
                joints: ids,
                weights,
            });
            influences.extend(extra.map(|e| e.sets()).unwrap_or_default());
        }
        let joint_count = joints.unwrap_or(0);
        let mut nodes = vec![Node::default(); 1 + joint_count];
        nodes[0].name = Some("mesh".into());
        let skins = match joints {
            Some(j) => vec![Skin {
                name: None,
                joints: (1..=j as u32).collect(),
                inverse_binds: vec![Mat4::IDENTITY.to_cols_array(); j],
                skeleton: None,
            }],
            None => Vec::new(),
        };
        let model = AnimatedMesh {
            triangles: mesh.triangles().to_vec(),
            uvs: None,
            nodes,
            skins,
            instances: vec![Instance {
                node: 0,
                skin: joints.map(|_| 0),
                first_vertex: 0,
                positions: positions.clone(),
                normals: normals.clone(),
                default_weights: vec![0.0; targets.len()],
                targets,
                influences,
            }],
            clips: Vec::new(),
        };
        let poser = Poser::new(model).map_err(|e| e.to_string())?;
        Ok(Animated {
            poser,
            net_points,
            net_normals,
            skinned: joints.is_some(),
            matrices: Vec::new(),
            weights: Vec::new(),
            positions,
            normals,
            posed_for: None,
        })
    }
}

/// The Bevy mesh's morph targets (Bevy keeps them target by target, vertex by vertex).
fn morph_targets(plain: &Mesh, count: usize) -> Vec<MorphTarget> {
    let Some(all) = plain.get_morph_targets() else {
        return Vec::new();
    };
    if count == 0 {
        return Vec::new();
    }
    all.chunks_exact(count)
        .map(|t| MorphTarget {
            positions: t.iter().map(|a| a.position.to_array()).collect(),
            normals: Some(t.iter().map(|a| a.normal.to_array()).collect()),
        })
        .collect()
}

/// The system parameters [`pose`] reads besides its query.
type Deformers<'w, 's> = (
    Query<'w, 's, &'static GlobalTransform>,
    Query<'w, 's, &'static MorphWeights>,
    Res<'w, Assets<SkinnedMeshInverseBindposes>>,
);

/// What [`pose`] reads and writes of a tessellated entity.
type Posed<'a> = (
    Entity,
    &'a mut Animated,
    &'a mut Surface,
    &'a GlobalTransform,
    Option<&'a SkinnedMesh>,
    Option<&'a MeshMorphWeights>,
    &'a Patches,
);

/// Poses every animated tessellated entity with this frame's joints and weights, rebuilds its
/// nets and its patches' boxes, and rewrites its two net buffers when the deform changed. Runs
/// after Bevy's transform propagation (the joints' global transforms are this frame's).
pub(crate) fn pose(
    mut query: Query<Posed>,
    mut boxes: Query<(&Patch, &mut Aabb)>,
    (transforms, morph_weights, bindposes): Deformers,
    mut buffers: ResMut<Assets<ShaderBuffer>>,
    stats: Res<UploadStats>,
) {
    for (entity, mut animated, mut surface, global, skin, morph, patches) in &mut query {
        let animated = &mut *animated;
        let surface = &mut *surface;
        animated.matrices.clear();
        if animated.skinned {
            let Some(skin) = skin else { continue };
            let Some(inverse_binds) = bindposes.get(&skin.inverse_bindposes) else {
                continue; // not loaded yet
            };
            // Into the entity's own space: the vertex shader applies its transform after.
            let local_from_world = global.affine().inverse();
            for (j, joint) in skin.joints.iter().enumerate() {
                let (Ok(joint), Some(bind)) = (transforms.get(*joint), inverse_binds.get(j)) else {
                    break;
                };
                let m = Mat4::from(local_from_world * joint.affine()) * *bind;
                animated.matrices.push(m.to_cols_array());
            }
        } else {
            animated.matrices.push(Mat4::IDENTITY.to_cols_array());
        }
        animated.weights.clear();
        match morph {
            Some(MeshMorphWeights::Value { weights }) => animated.weights.extend(weights),
            Some(MeshMorphWeights::Reference(source)) => {
                if let Ok(w) = morph_weights.get(*source) {
                    animated.weights.extend(w.weights());
                }
            }
            None => {}
        }
        let targets = animated.poser.morph_weight_count();
        animated.weights.resize(targets, 0.0);
        let same = animated
            .posed_for
            .as_ref()
            .is_some_and(|(m, w)| *m == animated.matrices && *w == animated.weights);
        if same {
            continue;
        }
        let posed = animated.poser.pose_with(
            &animated.matrices,
            &animated.weights,
            &mut animated.positions,
            animated.normals.as_deref_mut(),
        );
        let rebuilt = posed.map_err(|e| e.to_string()).and_then(|()| {
            surface
                .plan
                .update(
                    &mut surface.frame,
                    &animated.positions,
                    animated.normals.as_deref(),
                )
                .map_err(|e| e.to_string())
        });
        if let Err(e) = rebuilt {
            error!("cannot pose {entity}: {e}");
            animated.posed_for = Some((animated.matrices.clone(), animated.weights.clone()));
            continue;
        }
        surface.version += 1;
        let nets = surface.frame.nets();
        for (handle, bytes) in [
            (&animated.net_points, bytemuck::cast_slice(&nets.points)),
            (&animated.net_normals, bytemuck::cast_slice(&nets.normals)),
        ] {
            if let Some(mut buffer) = buffers.get_mut(handle) {
                stats.add(rewrite(&mut buffer, bytes));
            }
        }
        let face_boxes = face_boxes(&surface.frame);
        for child in &patches.0 {
            if let Ok((patch, mut aabb)) = boxes.get_mut(*child) {
                let first = patch.face as usize;
                let run = first..(first + patch.count as usize).min(face_boxes.len());
                let (lo, hi) = run_box(&face_boxes[run]);
                *aabb = Aabb::from_min_max(lo, hi);
            }
        }
        animated.posed_for = Some((animated.matrices.clone(), animated.weights.clone()));
    }
}
