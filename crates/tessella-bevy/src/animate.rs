//! A tessellated entity that Bevy animates: its `SkinnedMesh` joints (posed by Bevy's
//! `AnimationPlayer`) and its morph weights pose the *coarse* mesh each frame with tessella's
//! skinning (`tessella_core::animation::Poser::pose_with`: morph targets, then every joint
//! influence set, normals by the inverse transpose), the control nets are rebuilt, and only the
//! two net buffers are rewritten: bytes in proportion to the coarse triangles, whatever the
//! level. Or, with a draw evaluated once a frame and [`TessellaPosing::Gpu`] where the GPU can (the
//! default), the frame's joint matrices and morph weights alone go to the render world, which
//! skins the coarse mesh and builds the nets on the GPU ([`GpuPose`], `per_frame.rs`).

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
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use tessella_core::animation::{
    AnimatedMesh, Influences, Instance, MorphTarget, Node, Poser, Skin,
};
use tessella_core::refine::{Frame, Plan};

/// Where a tessellated entity that Bevy animates is posed (absent: [`TessellaPosing::Gpu`]).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[reflect(Component, Debug, Clone, Default)]
#[non_exhaustive]
pub enum TessellaPosing {
    /// On the GPU where it can run: tessella-gpu's skinning and net builder in the render
    /// world, on Bevy's device, write the nets the per-frame pass evaluates; a frame uploads
    /// the joint matrices and morph weights alone. It runs with the draws evaluated once a
    /// frame ([`crate::TessellaDraw::Mesh`], the default, and
    /// [`crate::TessellaDraw::PerFrame`]), a scheme whose nets the GPU builds (flat, Phong,
    /// PN, PN-AEN) and a mesh with normals; elsewhere, or when the device refuses it, the
    /// entity is posed on the CPU. The posed surface stays on the GPU: the entity is
    /// frustum-culled by a box from its coarse vertices skinned on the CPU, and picking
    /// poses its CPU frame when a ray asks.
    #[default]
    Gpu,
    /// On the CPU: tessella's skinning poses the coarse mesh, the nets are rebuilt and
    /// uploaded (bytes in proportion to the coarse triangles).
    Cpu,
}

/// The frame's deform of an entity posed on the GPU, for the render world: its poser and
/// plan (the skinner and net builder are made from them once), this frame's joint matrices
/// and morph weights, and the flag the render world raises when the GPU path cannot run.
#[derive(Component, Clone, Debug)]
pub(crate) struct GpuPose {
    pub poser: Arc<Poser>,
    pub plan: Arc<Plan>,
    pub matrices: Vec<[f32; 16]>,
    pub weights: Vec<f32>,
    pub refused: Arc<AtomicBool>,
}

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
    poser: Arc<Poser>,
    net_points: Handle<ShaderBuffer>,
    net_normals: Handle<ShaderBuffer>,
    skinned: bool,
    matrices: Vec<[f32; 16]>,
    weights: Vec<f32>,
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    /// The deform the nets were last built for; an unchanged one uploads nothing.
    posed_for: Option<(Vec<[f32; 16]>, Vec<f32>)>,
    /// The surface version whose pose the CPU frame holds, for an entity posed on the GPU
    /// (posed on the CPU when picking asks: [`Animated::pose_frame`]).
    frame_for: Option<u64>,
}

/// The box around a GPU-posed entity's surface, from its coarse vertices skinned on the CPU
/// (positions only, O(coarse), nothing uploaded): the core's `patch_bounds` with the scheme's
/// control reach (one edge for a scheme without one, which the CPU poses anyway).
pub(crate) fn pose_box(plan: &Plan, positions: &[[f32; 3]]) -> Result<(Vec3, Vec3), String> {
    let reach = plan.options().scheme.control_reach().unwrap_or(1.0);
    tessella_core::mesh::patch_bounds(positions, plan.triangles(), reach)
        .map(|(lo, hi)| (Vec3::from(lo), Vec3::from(hi)))
        .map_err(|e| e.to_string())
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
        let poser = Arc::new(Poser::new(model).map_err(|e| e.to_string())?);
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
            frame_for: None,
        })
    }

    /// Poses the CPU frame of an entity posed on the GPU with the deform the GPU drew (once a
    /// surface version), so picking casts its rays against the pose on screen. A CPU-posed
    /// entity's frame is posed already.
    pub(crate) fn pose_frame(
        &mut self,
        gpu: &GpuPose,
        surface: &mut Surface,
    ) -> Result<(), String> {
        if gpu.refused.load(Ordering::Relaxed)
            || gpu.matrices.is_empty()
            || self.frame_for == Some(surface.version)
        {
            return Ok(());
        }
        self.poser
            .pose_with(
                &gpu.matrices,
                &gpu.weights,
                &mut self.positions,
                self.normals.as_deref_mut(),
            )
            .map_err(|e| e.to_string())?;
        let Surface { plan, frame, .. } = surface;
        plan.update(frame, &self.positions, self.normals.as_deref())
            .map_err(|e| e.to_string())?;
        self.frame_for = Some(surface.version);
        Ok(())
    }

    /// The entity's [`GpuPose`] when its posing can run on the GPU as far as the CPU can
    /// tell (the device may still refuse it): a poser with normals, nets the GPU builds.
    pub(crate) fn gpu_pose(&self, plan: &Arc<Plan>) -> Option<GpuPose> {
        let built_on_gpu = tessella_gpu::GpuNetBuilder::builds(&plan.options().scheme);
        (self.poser.has_normals() && built_on_gpu).then(|| GpuPose {
            poser: self.poser.clone(),
            plan: plan.clone(),
            matrices: Vec::new(),
            weights: Vec::new(),
            refused: Arc::new(AtomicBool::new(false)),
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
    Option<&'a mut GpuPose>,
    // Its children's boxes are the LOD's to set (`lod::levels`, after this).
    Has<crate::lod::LodState>,
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
    for (entity, mut animated, mut surface, global, skin, morph, patches, gpu, lod) in &mut query {
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
        // On the GPU: the render world skins and builds the nets from the matrices and
        // weights, the bytes uploaded. A refused GPU path (it raised the flag) poses here.
        if let Some(mut gpu) = gpu.filter(|g| !g.refused.load(Ordering::Relaxed)) {
            gpu.matrices.clone_from(&animated.matrices);
            gpu.weights.clone_from(&animated.weights);
            stats.add((gpu.matrices.len() * 64 + gpu.weights.len() * 4) as u64);
            surface.version += 1;
            // The culling box, from the coarse vertices skinned here (positions alone).
            let skinned = animated
                .poser
                .pose_with(
                    &animated.matrices,
                    &animated.weights,
                    &mut animated.positions,
                    None,
                )
                .map_err(|e| e.to_string())
                .and_then(|()| pose_box(&surface.plan, &animated.positions));
            match skinned {
                Ok((lo, hi)) => {
                    for child in &patches.0 {
                        if let Ok((_, mut aabb)) = boxes.get_mut(*child) {
                            *aabb = Aabb::from_min_max(lo, hi);
                        }
                    }
                }
                Err(e) => error!("cannot bound {entity}'s pose: {e}"),
            }
            animated.posed_for = Some((animated.matrices.clone(), animated.weights.clone()));
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
        if lod {
            animated.posed_for = Some((animated.matrices.clone(), animated.weights.clone()));
            continue;
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
