//! `Deformer`: a mesh posed with an engine's own skeleton — three.js's bones, posed by its
//! `AnimationMixer` — by the core's [`Poser::pose_with`] (linear blend skinning, morph
//! targets, normals by the blended matrix's inverse transpose), so `TessellatedMesh`
//! follows a `SkinnedMesh` or a morphing `Mesh` with the same code as `readAnimated`'s poses.
//!
//! Built once per source: the rest positions and normals, the four joint indices and weights
//! per vertex, and the morph targets' displacements, as one instance of a one-skin model
//! whose joints the caller moves. Every frame: the joints' matrices (already taking the mesh's
//! bind space to its posed space) and the morph weights in, the posed positions and normals
//! out, into arrays the caller owns.

use crate::{arrays, errors};
use tessella_core::animation::{
    AnimatedMesh, Influences, Instance, MorphTarget, Node, Poser, Skin,
};
use wasm_bindgen::prelude::*;

const IDENTITY: [f32; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

#[wasm_bindgen]
pub struct Deformer {
    poser: Poser,
    matrices: Vec<[f32; 16]>,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
}

/// What a source gives to be deformed: flat arrays as three.js holds them.
pub struct Source<'a> {
    pub positions: &'a [f32],
    pub normals: Option<&'a [f32]>,
    /// Four joint indices per vertex; empty for a mesh without a skeleton.
    pub joints: &'a [u32],
    /// Four weights per vertex, with `joints`.
    pub weights: &'a [f32],
    /// The skeleton's joint count (0: no skeleton; the caller then passes one matrix).
    pub joint_count: u32,
    /// Morph targets: `targets × vertices × 3` position displacements.
    pub position_deltas: &'a [f32],
    /// The same for normals, or empty where the targets leave normals alone.
    pub normal_deltas: &'a [f32],
    pub targets: u32,
}

crate::arrays::poser_exports!(Deformer);

#[wasm_bindgen]
impl Deformer {
    #[wasm_bindgen(constructor)]
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        positions: &[f32],
        normals: &[f32],
        joints: &[u32],
        weights: &[f32],
        joint_count: u32,
        position_deltas: &[f32],
        normal_deltas: &[f32],
        targets: u32,
    ) -> Result<Deformer, JsError> {
        Deformer::with(&Source {
            positions,
            normals: (!normals.is_empty()).then_some(normals),
            joints,
            weights,
            joint_count,
            position_deltas,
            normal_deltas,
            targets,
        })
        .map_err(errors::text)
    }

    /// The matrices a frame takes: the joint count, or 1 without a skeleton.
    #[wasm_bindgen(js_name = matrixCount)]
    pub fn matrix_count(&self) -> usize {
        self.poser.deform_matrix_count()
    }

    /// Poses the mesh with `matrices` (16 numbers each, column-major) and the morph `weights`
    /// into `positions` (and `normals`, when the source has them; pass an empty array
    /// otherwise). On error the outputs are left untouched.
    pub fn pose(
        &mut self,
        matrices: &[f32],
        weights: &[f32],
        positions: &mut [f32],
        normals: &mut [f32],
    ) -> Result<(), JsError> {
        self.pose_into(matrices, weights, positions, normals)
            .map_err(errors::text)
    }

    /// The box that holds the curved surface of the pose: the vertices posed with `matrices`
    /// and `weights` (positions only, on the CPU), each of the `indices` triangles' box grown
    /// by `reach` times its longest edge (the core's `mesh::patch_bounds`; `reach` is the scheme's
    /// control reach: 0.5 for PN and PN-AEN, `|alpha|` for Phong, 0 for flat). Six numbers:
    /// the low corner, then the high one. What GPU posing culls by, the posed nets never
    /// leaving the GPU.
    #[wasm_bindgen(js_name = posedBounds)]
    pub fn posed_bounds(
        &mut self,
        matrices: &[f32],
        weights: &[f32],
        indices: &[u32],
        reach: f32,
    ) -> Result<Vec<f32>, JsError> {
        self.posed_bounds_of(matrices, weights, indices, reach)
            .map_err(errors::text)
    }
}

impl Deformer {
    /// [`Deformer::new`] with a `String` error.
    pub fn with(source: &Source) -> Result<Deformer, String> {
        let positions = arrays::points(source.positions, "positions")?;
        let n = positions.len();
        let normals = source
            .normals
            .map(|v| arrays::points(v, "normals"))
            .transpose()?;
        if normals.as_ref().is_some_and(|v| v.len() != n) {
            return Err(format!(
                "normals: {} numbers for {n} vertices",
                3 * normals.map_or(0, |v| v.len())
            ));
        }
        let targets = source.targets as usize;
        let per_target = 3 * n;
        if source.position_deltas.len() != targets * per_target {
            return Err(format!(
                "morph targets: {} position numbers for {targets} targets of {n} vertices",
                source.position_deltas.len()
            ));
        }
        let with_normals = !source.normal_deltas.is_empty();
        if with_normals && source.normal_deltas.len() != targets * per_target {
            return Err(format!(
                "morph targets: {} normal numbers for {targets} targets of {n} vertices",
                source.normal_deltas.len()
            ));
        }
        let target_list = (0..targets)
            .map(|t| {
                let range = t * per_target..(t + 1) * per_target;
                Ok(MorphTarget {
                    positions: arrays::points(
                        &source.position_deltas[range.clone()],
                        "morph positions",
                    )?,
                    normals: with_normals
                        .then(|| arrays::points(&source.normal_deltas[range], "morph normals"))
                        .transpose()?,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        let joints = source.joint_count as usize;
        let mut nodes = vec![Node::default(); joints + 1];
        nodes[joints].name = Some("mesh".into());
        let mut skins = Vec::new();
        let mut influences = Vec::new();
        if joints > 0 {
            if source.joints.len() != 4 * n || source.weights.len() != 4 * n {
                return Err(format!(
                    "skinning: {} joint indices and {} weights for {n} vertices (4 each)",
                    source.joints.len(),
                    source.weights.len()
                ));
            }
            if joints > usize::from(u16::MAX) + 1 {
                return Err(format!("skinning: {joints} joints, over 65536"));
            }
            let index = |j: u32| {
                u16::try_from(j).map_err(|_| format!("skinning: joint index {j} is over 65535"))
            };
            let joint_sets = source
                .joints
                .chunks_exact(4)
                .map(|c| Ok([index(c[0])?, index(c[1])?, index(c[2])?, index(c[3])?]))
                .collect::<Result<Vec<_>, String>>()?;
            let weight_sets = source
                .weights
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect();
            influences.push(Influences {
                joints: joint_sets,
                weights: weight_sets,
            });
            skins.push(Skin {
                joints: (0..joints as u32).collect(),
                inverse_binds: vec![IDENTITY; joints],
                ..Skin::default()
            });
        }
        let model = AnimatedMesh {
            nodes,
            skins,
            instances: vec![Instance {
                node: joints as u32,
                skin: (joints > 0).then_some(0),
                positions,
                normals,
                default_weights: vec![0.0; targets],
                targets: target_list,
                influences,
                ..Instance::default()
            }],
            ..AnimatedMesh::default()
        };
        let poser = Poser::new(model).map_err(|e| errors::message(&e))?;
        Ok(Deformer {
            matrices: Vec::with_capacity(poser.deform_matrix_count()),
            positions: vec![[0.0; 3]; n],
            normals: vec![[0.0; 3]; if poser.has_normals() { n } else { 0 }],
            poser,
        })
    }

    /// [`Deformer::posed_bounds`] with a `String` error.
    pub fn posed_bounds_of(
        &mut self,
        matrices: &[f32],
        weights: &[f32],
        indices: &[u32],
        reach: f32,
    ) -> Result<Vec<f32>, String> {
        let (triangles, rest) = indices.as_chunks::<3>();
        if !rest.is_empty() {
            return Err(format!(
                "indices: {} numbers, not 3 a triangle",
                indices.len()
            ));
        }
        self.read_matrices(matrices)?;
        self.poser
            .pose_with(&self.matrices, weights, &mut self.positions, None)
            .map_err(|e| errors::message(&e))?;
        let (lo, hi) = tessella_core::mesh::patch_bounds(&self.positions, triangles, reach)
            .map_err(|e| errors::message(&e))?;
        Ok([lo, hi].concat())
    }

    /// Reads a frame's `matrices` (16 numbers each) into the deformer's own.
    fn read_matrices(&mut self, matrices: &[f32]) -> Result<(), String> {
        if !matrices.len().is_multiple_of(16) {
            return Err(format!(
                "matrices: {} numbers, not 16 per matrix",
                matrices.len()
            ));
        }
        self.matrices.clear();
        self.matrices.extend(matrices.chunks_exact(16).map(|c| {
            let mut m = [0.0; 16];
            m.copy_from_slice(c);
            m
        }));
        Ok(())
    }

    /// [`Deformer::pose`] with a `String` error.
    pub fn pose_into(
        &mut self,
        matrices: &[f32],
        weights: &[f32],
        positions: &mut [f32],
        normals: &mut [f32],
    ) -> Result<(), String> {
        let n = self.poser.vertex_count();
        if positions.len() != 3 * n {
            return Err(format!(
                "positions: room for {} numbers, the mesh has {}",
                positions.len(),
                3 * n
            ));
        }
        let want_normals = if self.poser.has_normals() { 3 * n } else { 0 };
        if normals.len() != want_normals {
            return Err(format!(
                "normals: room for {} numbers, expected {want_normals}",
                normals.len()
            ));
        }
        self.read_matrices(matrices)?;
        let out_normals = self
            .poser
            .has_normals()
            .then_some(self.normals.as_mut_slice());
        self.poser
            .pose_with(&self.matrices, weights, &mut self.positions, out_normals)
            .map_err(|e| errors::message(&e))?;
        positions.copy_from_slice(arrays::flat(&self.positions));
        normals.copy_from_slice(arrays::flat(&self.normals));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle on two joints and one morph target that lifts every vertex by its weight:
    /// vertex 0 half on each joint, vertex 1 on joint 1, vertex 2 on joint 0; and the
    /// matrices that move joint 1 by 2 along x.
    fn two_joints(normals: Option<&[f32]>) -> (Deformer, Vec<f32>) {
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let joints = [0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0];
        let weights = [0.5, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        let deltas = [0.0, 0.0, 1.0].repeat(3);
        let d = Deformer::with(&Source {
            positions: &positions,
            normals,
            joints: &joints,
            weights: &weights,
            joint_count: 2,
            position_deltas: &deltas,
            normal_deltas: &[],
            targets: 1,
        })
        .unwrap();
        let mut moved = IDENTITY;
        moved[12] = 2.0;
        (d, IDENTITY.iter().chain(&moved).copied().collect())
    }

    /// Two joints: joint 1's matrix moves x by 2; a vertex half on each moves by 1.
    #[test]
    fn poses_with_the_given_joints_and_morphs() {
        let normals = [0.0, 0.0, 1.0].repeat(3);
        let (mut d, matrices) = two_joints(Some(&normals));
        assert_eq!(d.matrix_count(), 2);
        let (mut p, mut n) = (vec![0.0; 9], vec![0.0; 9]);
        d.pose_into(&matrices, &[0.5], &mut p, &mut n).unwrap();
        assert_eq!(p, [1.0, 0.0, 0.5, 3.0, 0.0, 0.5, 0.0, 1.0, 0.5]);
        assert_eq!(n, normals);
        // Refused: a wrong count, a NaN; the outputs keep the last pose.
        let e = d
            .pose_into(&matrices[..16], &[0.5], &mut p, &mut n)
            .unwrap_err();
        assert!(e.contains("deform matrices"), "{e}");
        let e = d
            .pose_into(&matrices, &[f32::NAN], &mut p, &mut n)
            .unwrap_err();
        assert!(e.contains("morph weight 0 is not finite"), "{e}");
        assert_eq!(p, [1.0, 0.0, 0.5, 3.0, 0.0, 0.5, 0.0, 1.0, 0.5]);
    }

    /// The posed bounds of one triangle are its posed box grown by the reach times its longest
    /// edge: here the pose above (vertices (1,0,.5), (3,0,.5), (0,1,.5)), longest edge
    /// |(3,0)-(0,1)| = sqrt(10), reach 0.5. Bad indices are errors.
    #[test]
    fn posed_bounds_grow_the_posed_box_by_the_reach() {
        let (mut d, matrices) = two_joints(None);
        let b = d
            .posed_bounds_of(&matrices, &[0.5], &[0, 1, 2], 0.5)
            .unwrap();
        let g = 0.5 * 10f32.sqrt();
        let want = [-g, -g, 0.5 - g, 3.0 + g, 1.0 + g, 0.5 + g];
        for (got, want) in b.iter().zip(want) {
            assert!((got - want).abs() < 1e-6, "{b:?}");
        }
        let e = d
            .posed_bounds_of(&matrices, &[0.5], &[0, 1], 0.5)
            .unwrap_err();
        assert!(e.contains("3 a triangle"), "{e}");
        let e = d
            .posed_bounds_of(&matrices, &[0.5], &[0, 1, 9], 0.5)
            .unwrap_err();
        assert!(e.contains("vertex 9"), "{e}");
    }

    #[test]
    fn bad_sources_are_refused_with_a_reason() {
        let positions = [0.0; 9];
        let source = |joints: &'static [u32], weights: &'static [f32], joint_count| Source {
            positions: &positions,
            normals: None,
            joints,
            weights,
            joint_count,
            position_deltas: &[],
            normal_deltas: &[],
            targets: 0,
        };
        let e = Deformer::with(&source(&[0; 8], &[1.0; 8], 1))
            .err()
            .unwrap();
        assert!(e.contains("8 joint indices"), "{e}");
        let e = Deformer::with(&source(&[3; 12], &[1.0; 12], 2))
            .err()
            .unwrap();
        assert!(e.contains("joint"), "{e}");
        let e = Deformer::with(&source(&[0; 12], &[0.0; 12], 2))
            .err()
            .unwrap();
        assert!(e.contains("weight"), "{e}");
        // No skeleton: one matrix, the mesh's.
        let d = Deformer::with(&source(&[], &[], 0)).unwrap();
        assert_eq!(d.matrix_count(), 1);
    }
}
