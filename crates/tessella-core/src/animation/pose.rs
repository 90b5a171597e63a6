//! [`Poser`]: a validated animated mesh, posed at any moment of any clip into buffers the
//! caller owns.

use super::check::{check, Checked};
use super::deform::{deform, table, Bases, DeformTable};
use super::hierarchy::{node_state, NodeState};
use super::model::{AnimatedMesh, Clip, Instance};
use crate::{AnimationError, Mesh};
use glam::{Mat3A, Mat4, Vec3A, Vec4};
use rayon::prelude::*;

/// Vertices per parallel task.
const CHUNK: usize = 2048;

/// An [`AnimatedMesh`] checked once, then posed as often as asked.
///
/// [`Poser::new`] validates everything posing reads, so that posing itself only fails on a bad
/// argument (an unknown clip, a non-finite time, a buffer of the wrong length) and never
/// panics. A pose follows the glTF 2.0 specification
/// (<https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>, "Animations",
/// "Skins", "Morph Targets" and Appendix C):
///
/// 1. each node's local transform is its stored one with the clip's channels sampled over it,
///    and world matrices follow the hierarchy (`world = world(parent) · local`);
/// 2. morph targets are added to the instance's positions and normals, weighted by the node's
///    animated weights, else its `weights`, else the mesh's `default_weights`;
/// 3. a skinned instance is moved by linear blend skinning with the joint matrices
///    `world(joint) · inverse_bind` (the skinned node's own transform is ignored, as the
///    specification says); its normals by the inverse transpose of each vertex's blended
///    matrix, renormalised. Joint weights that do not sum to one are divided by their sum
///    (as three.js's `GLTFLoader` does);
/// 4. an unskinned instance is moved by its node's world matrix, its normals by that matrix's
///    inverse transpose.
///
/// Posed positions are in the scene's space. Where a transform is singular (a joint scaled to
/// zero), a normal falls back to its unposed direction.
///
/// Normals: when every instance has normals ([`Poser::has_normals`]), poses can carry them;
/// otherwise pose positions only and let [`Mesh::new`] or [`Mesh::update`] compute normals
/// from them ([`Poser::mesh`] does so).
///
/// ```
/// use tessella_core::animation::{
///     AnimatedMesh, Channel, Clip, Instance, Interpolation, Node, Poser, Property, Sampler,
/// };
/// // One triangle drawn by node 0, which a clip moves 2 units along x over one second.
/// let model = AnimatedMesh {
///     triangles: vec![[0, 1, 2]],
///     nodes: vec![Node::default()],
///     instances: vec![Instance {
///         positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
///         normals: Some(vec![[0.0, 0.0, 1.0]; 3]),
///         ..Instance::default()
///     }],
///     clips: vec![Clip {
///         name: "slide".into(),
///         channels: vec![Channel {
///             node: 0,
///             property: Property::Translation,
///             sampler: Sampler {
///                 interpolation: Interpolation::Linear,
///                 times: vec![0.0, 1.0],
///                 values: vec![0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
///             },
///         }],
///     }],
///     ..AnimatedMesh::default()
/// };
/// let poser = Poser::new(model)?;
/// let slide = poser.clip_index("slide")?;
/// assert_eq!(poser.duration(slide)?, 1.0);
///
/// let mut positions = vec![[0.0; 3]; poser.vertex_count()];
/// let mut normals = vec![[0.0; 3]; poser.vertex_count()];
/// poser.pose_into(Some(slide), 0.25, &mut positions, Some(&mut normals))?;
/// assert_eq!(positions[1], [1.5, 0.0, 0.0]);
/// assert_eq!(normals[1], [0.0, 0.0, 1.0]);
///
/// // Posing then refining: a tessella_core::Mesh of the pose.
/// let mesh = poser.mesh(Some(slide), 5.0)?; // past the end: the last pose
/// assert_eq!(mesh.positions()[0], [2.0, 0.0, 0.0]);
/// # Ok::<(), tessella_core::AnimationError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Poser {
    model: AnimatedMesh,
    checked: Checked,
    /// Where each instance's deform matrices and morph weights sit in a frame's lists.
    bases: Bases,
}

/// How an instance's vertices leave mesh space.
enum Deform<'a> {
    /// Linear blend skinning with these joint matrices.
    Skin(&'a [Mat4]),
    /// One matrix for every vertex, and its normal matrix.
    Rigid(Mat4, Mat3A),
}

impl Poser {
    /// Validates `model` and keeps it for posing.
    ///
    /// Refused, with an error naming the clip, channel, skin, instance, node or vertex: a
    /// parent index out of range or a cycle of parents; a non-finite node transform; a skin's
    /// joint naming a missing node, a count of inverse bind matrices other than its joints', or
    /// an inverse bind matrix that is non-finite or not invertible; an instance on a missing
    /// node or skin, not starting where the previous one ends, or whose normals, morph targets
    /// or influences do not have one entry per position; non-finite positions, normals or
    /// morph displacements; default or node weights whose count is not the target count, or
    /// instances of one node with different target counts; a skinned instance without
    /// influences, a joint index past its skin's joints, a weight that is NaN, infinite or
    /// negative, or a vertex whose weights are all zero; texture coordinates not one per
    /// vertex; a triangle indexing past the vertices; a channel on a missing node, a
    /// translation/rotation/scale channel on a node with a matrix, a weights channel on a node
    /// drawing no mesh; a sampler without keys, with key times not finite or not strictly
    /// increasing, with non-finite values, or with a value count other than keys × components
    /// (× 3 for `CUBICSPLINE`; 3 components for translation and scale, 4 for rotation, the
    /// target count for weights).
    ///
    /// Accepted as they are: weights not summing to one (normalised by their sum), joints with
    /// zero weight, unused joints and nodes, influences on an unskinned instance (unused), a
    /// skinned node's own transform (ignored).
    pub fn new(model: AnimatedMesh) -> Result<Poser, AnimationError> {
        let checked = check(&model)?;
        let bases = Bases::new(&model);
        Ok(Poser {
            model,
            checked,
            bases,
        })
    }

    /// The animated mesh being posed.
    pub fn model(&self) -> &AnimatedMesh {
        &self.model
    }

    /// Gives the animated mesh back.
    pub fn into_model(self) -> AnimatedMesh {
        self.model
    }

    /// The number of vertices a pose has: the instances' together.
    pub fn vertex_count(&self) -> usize {
        self.checked.vertex_count
    }

    /// True when every instance has normals, so that poses can carry normals; otherwise pass
    /// no normal buffer and let the core compute normals from the posed positions.
    pub fn has_normals(&self) -> bool {
        self.checked.has_normals
    }

    /// The number of clips.
    pub fn clip_count(&self) -> usize {
        self.model.clips.len()
    }

    /// The clips' names, in the file's order (an index into them names a clip too).
    pub fn clip_names(&self) -> impl Iterator<Item = &str> {
        self.model.clips.iter().map(|c| c.name.as_str())
    }

    /// The index of a clip given by name or, when no clip has that name, by decimal index.
    pub fn clip_index(&self, name_or_index: &str) -> Result<usize, AnimationError> {
        let clips = &self.model.clips;
        if let Some(index) = clips.iter().position(|c| c.name == name_or_index) {
            return Ok(index);
        }
        match name_or_index.trim().parse::<usize>() {
            Ok(index) if index < clips.len() => Ok(index),
            _ => Err(self.unknown_clip(name_or_index.to_string())),
        }
    }

    /// A clip's duration in seconds: the largest last key time of its channels (0 without
    /// channels). Posing at a later time gives the clip's last pose.
    pub fn duration(&self, clip: usize) -> Result<f32, AnimationError> {
        Ok(self
            .clip(Some(clip))?
            .iter()
            .flat_map(|c| &c.channels)
            .filter_map(|c| c.sampler.times.last().copied())
            .fold(0.0, f32::max))
    }

    /// Poses the mesh at `time` seconds of clip `clip` (`None`: the rest pose, the nodes'
    /// stored transforms and weights) into `positions` and, when given, `normals`, one entry
    /// per vertex ([`Poser::vertex_count`]). Normals can be asked for only when
    /// [`Poser::has_normals`].
    ///
    /// Errors on an unknown clip, a non-finite time, a buffer of the wrong length, or normals
    /// asked for that the mesh does not have; the buffers are then left untouched.
    pub fn pose_into(
        &self,
        clip: Option<usize>,
        time: f32,
        positions: &mut [[f32; 3]],
        normals: Option<&mut [[f32; 3]]>,
    ) -> Result<(), AnimationError> {
        let state = self.node_state(clip, time)?;
        self.check_buffers(positions, normals.as_deref())?;
        // The frame's deform matrices and weights, as `deform_into` gives them to a GPU.
        let mut matrices: Vec<Mat4> = Vec::with_capacity(self.bases.matrix_count);
        let mut weights = Vec::with_capacity(self.bases.weight_count);
        deform(&self.model, &state, |m| matrices.push(m), &mut weights);
        self.pose_deformed(&matrices, &weights, positions, normals);
        Ok(())
    }

    /// Poses the mesh with a frame's deform matrices and morph weights given by the caller
    /// (an engine's own skeleton, e.g. three.js's bones posed by its `AnimationMixer`), laid
    /// out as [`Poser::deform_into`] gives them: [`Poser::deform_matrix_count`] column-major
    /// matrices (each skin's joint matrices, then each unskinned instance's world matrix) and
    /// [`Poser::morph_weight_count`] weights. Morphing, blending and the normals are those of
    /// [`Poser::pose_into`], which poses with this same code.
    ///
    /// Errors on a matrix or weight count other than the model's, a non-finite matrix entry
    /// or weight, a buffer of the wrong length, or normals asked for that the mesh does not
    /// have; the buffers are then left untouched.
    ///
    /// ```
    /// use tessella_core::animation::Poser;
    /// let poser = Poser::new(tessella_core::samples::animated_creature(0))?;
    /// let (mut matrices, mut weights) = (Vec::new(), Vec::new());
    /// poser.deform_into(Some(0), 0.5, &mut matrices, &mut weights)?;
    /// let mut ours = vec![[0.0; 3]; poser.vertex_count()];
    /// poser.pose_with(&matrices, &weights, &mut ours, None)?;
    /// let (clip, _) = poser.pose(Some(0), 0.5)?;
    /// assert_eq!(ours, clip);
    /// # Ok::<(), tessella_core::AnimationError>(())
    /// ```
    pub fn pose_with(
        &self,
        matrices: &[[f32; 16]],
        weights: &[f32],
        positions: &mut [[f32; 3]],
        normals: Option<&mut [[f32; 3]]>,
    ) -> Result<(), AnimationError> {
        let counts = [
            ("deform matrices", matrices.len(), self.bases.matrix_count),
            ("morph weights", weights.len(), self.bases.weight_count),
        ];
        for (what, got, expected) in counts {
            if got != expected {
                return Err(AnimationError::DeformCount {
                    what,
                    got,
                    expected,
                });
            }
        }
        if let Some(index) = matrices
            .iter()
            .position(|m| !m.iter().all(|x| x.is_finite()))
        {
            let what = "deform matrix";
            return Err(AnimationError::NonFiniteDeform { what, index });
        }
        if let Some(index) = weights.iter().position(|w| !w.is_finite()) {
            let what = "morph weight";
            return Err(AnimationError::NonFiniteDeform { what, index });
        }
        self.check_buffers(positions, normals.as_deref())?;
        let matrices: Vec<Mat4> = matrices.iter().map(Mat4::from_cols_array).collect();
        self.pose_deformed(&matrices, weights, positions, normals);
        Ok(())
    }

    /// The output buffers' lengths, and normals only where the mesh has them.
    fn check_buffers(
        &self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<(), AnimationError> {
        let expected = self.vertex_count();
        if positions.len() != expected {
            return Err(AnimationError::BufferLength {
                what: "positions",
                got: positions.len(),
                expected,
            });
        }
        if let Some(normals) = normals {
            if !self.has_normals() {
                return Err(AnimationError::NoNormals);
            }
            if normals.len() != expected {
                return Err(AnimationError::BufferLength {
                    what: "normals",
                    got: normals.len(),
                    expected,
                });
            }
        }
        Ok(())
    }

    /// Poses every instance with the frame's deform matrices and morph weights (checked).
    fn pose_deformed(
        &self,
        matrices: &[Mat4],
        all_weights: &[f32],
        positions: &mut [[f32; 3]],
        mut normals: Option<&mut [[f32; 3]]>,
    ) {
        let model = &self.model;
        let mut positions = positions;
        for (index, instance) in model.instances.iter().enumerate() {
            let count = instance.positions.len();
            let (out, rest) = std::mem::take(&mut positions).split_at_mut(count);
            positions = rest;
            let out_normals = normals.take().map(|n| {
                let (out, rest) = n.split_at_mut(count);
                normals = Some(rest);
                out
            });
            let first_weight = self.bases.instance_weight[index];
            let weights = &all_weights[first_weight..first_weight + instance.targets.len()];
            let first_matrix = self.bases.instance_matrix[index];
            let deform = match instance.skin {
                Some(skin) => {
                    let joints = model.skins[skin as usize].joints.len();
                    Deform::Skin(&matrices[first_matrix..first_matrix + joints])
                }
                None => {
                    let m = matrices[first_matrix];
                    Deform::Rigid(m, normal_matrix(&m))
                }
            };
            pose_instance(instance, weights, &deform, out, out_normals);
        }
    }

    /// Poses the mesh into new buffers: positions, and normals when [`Poser::has_normals`].
    /// See [`Poser::pose_into`].
    #[allow(clippy::type_complexity)]
    pub fn pose(
        &self,
        clip: Option<usize>,
        time: f32,
    ) -> Result<(Vec<[f32; 3]>, Option<Vec<[f32; 3]>>), AnimationError> {
        let mut positions = vec![[0.0; 3]; self.vertex_count()];
        let mut normals = self
            .has_normals()
            .then(|| vec![[0.0; 3]; self.vertex_count()]);
        self.pose_into(clip, time, &mut positions, normals.as_deref_mut())?;
        Ok((positions, normals))
    }

    /// A [`Mesh`] of the pose, ready to refine: the posed positions, the posed normals (or,
    /// without [`Poser::has_normals`], normals computed by [`Mesh::new`]), the texture
    /// coordinates and the triangles. Errors as [`Poser::pose_into`] does, or as
    /// [`Mesh::new`] does on the posed mesh (e.g. a triangle collapsed to zero area).
    pub fn mesh(&self, clip: Option<usize>, time: f32) -> Result<Mesh, AnimationError> {
        let (positions, normals) = self.pose(clip, time)?;
        Ok(Mesh::new(
            positions,
            normals,
            self.model.uvs.clone(),
            self.model.triangles.clone(),
        )?)
    }

    /// The nodes' world matrices and weights at `time` of `clip`, after checking both.
    fn node_state(&self, clip: Option<usize>, time: f32) -> Result<NodeState, AnimationError> {
        let clip = self.clip(clip)?;
        if !time.is_finite() {
            return Err(AnimationError::BadTime(time));
        }
        Ok(node_state(&self.model, &self.checked.order, clip, time))
    }

    /// Clip `index`, or `None` for the rest pose.
    fn clip(&self, index: Option<usize>) -> Result<Option<&Clip>, AnimationError> {
        match index {
            None => Ok(None),
            Some(i) => match self.model.clips.get(i) {
                Some(clip) => Ok(Some(clip)),
                None => Err(self.unknown_clip(i.to_string())),
            },
        }
    }

    fn unknown_clip(&self, clip: String) -> AnimationError {
        let names: Vec<String> = self
            .model
            .clips
            .iter()
            .take(20)
            .map(|c| format!("{:?}", c.name))
            .collect();
        let mut names = names.join(", ");
        if self.model.clips.len() > 20 {
            names.push_str(", ...");
        } else if names.is_empty() {
            names.push_str("none");
        }
        AnimationError::UnknownClip {
            clip,
            count: self.model.clips.len(),
            names,
        }
    }
}

/// The inverse transpose of `m`'s upper 3×3, up to a positive factor: its cofactor matrix,
/// negated where the determinant is negative. Normals it moves must be renormalised.
fn normal_matrix(m: &Mat4) -> Mat3A {
    let c0 = Vec3A::from_vec4(m.x_axis);
    let c1 = Vec3A::from_vec4(m.y_axis);
    let c2 = Vec3A::from_vec4(m.z_axis);
    let (a, b, c) = (c1.cross(c2), c2.cross(c0), c0.cross(c1));
    let sign = if c0.dot(a) < 0.0 { -1.0 } else { 1.0 };
    Mat3A::from_cols(a * sign, b * sign, c * sign)
}

/// Poses one instance into its slices of the output, in parallel over chunks of vertices.
fn pose_instance(
    instance: &Instance,
    weights: &[f32],
    deform: &Deform,
    positions: &mut [[f32; 3]],
    normals: Option<&mut [[f32; 3]]>,
) {
    // The morph targets that move anything, with their weights.
    let targets: Vec<(usize, f32)> = weights
        .iter()
        .copied()
        .enumerate()
        .filter(|&(t, w)| w != 0.0 && t < instance.targets.len())
        .collect();
    let run = |chunk: usize, p: &mut [[f32; 3]], n: Option<&mut [[f32; 3]]>| {
        pose_chunk(instance, &targets, deform, chunk * CHUNK, p, n);
    };
    match normals {
        Some(normals) => positions
            .par_chunks_mut(CHUNK)
            .zip(normals.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(chunk, (p, n))| run(chunk, p, Some(n))),
        None => positions
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(chunk, p)| run(chunk, p, None)),
    }
}

/// Poses vertices `start..start + positions.len()` of one instance.
fn pose_chunk(
    instance: &Instance,
    targets: &[(usize, f32)],
    deform: &Deform,
    start: usize,
    positions: &mut [[f32; 3]],
    mut normals: Option<&mut [[f32; 3]]>,
) {
    let rest_normals = instance.normals.as_deref().unwrap_or(&[]);
    for (i, out) in positions.iter_mut().enumerate() {
        let v = start + i;
        let mut p = Vec3A::from(instance.positions[v]);
        for &(t, w) in targets {
            p += w * Vec3A::from(instance.targets[t].positions[v]);
        }
        // The morphed normal, when asked for (then every instance has normals).
        let n = match (normals.is_some(), rest_normals.get(v)) {
            (true, Some(&n)) => {
                let mut n = Vec3A::from(n);
                for &(t, w) in targets {
                    if let Some(d) = &instance.targets[t].normals {
                        n += w * Vec3A::from(d[v]);
                    }
                }
                Some(n)
            }
            _ => None,
        };
        let (posed, normal) = match deform {
            Deform::Rigid(m, nm) => (m.transform_point3a(p), n.map(|n| *nm * n)),
            Deform::Skin(joints) => {
                let m = blend(instance, joints, v);
                (m.transform_point3a(p), n.map(|n| normal_matrix(&m) * n))
            }
        };
        *out = posed.to_array();
        if let (Some(normals), Some(normal), Some(n)) = (normals.as_deref_mut(), normal, n) {
            let fallback = n.normalize_or(Vec3A::Z);
            normals[i] = normal.normalize_or(fallback).to_array();
        }
    }
}

/// Vertex `v`'s blended joint matrix: its joints' matrices weighted by its weights, divided by
/// their sum (validated positive).
fn blend(instance: &Instance, joints: &[Mat4], v: usize) -> Mat4 {
    let mut cols = [Vec4::ZERO; 4];
    let mut sum = 0.0;
    for set in &instance.influences {
        for (&j, &w) in set.joints[v].iter().zip(&set.weights[v]) {
            if w > 0.0 {
                let m = &joints[j as usize];
                cols[0] += w * m.x_axis;
                cols[1] += w * m.y_axis;
                cols[2] += w * m.z_axis;
                cols[3] += w * m.w_axis;
                sum += w;
            }
        }
    }
    let scale = 1.0 / sum;
    Mat4::from_cols(
        cols[0] * scale,
        cols[1] * scale,
        cols[2] * scale,
        cols[3] * scale,
    )
}

impl Poser {
    /// The number of deform matrices a frame has: every skin's joints, then one per unskinned
    /// instance.
    pub fn deform_matrix_count(&self) -> usize {
        self.bases.matrix_count
    }

    /// The number of morph weights a frame has: the instances' target counts together.
    pub fn morph_weight_count(&self) -> usize {
        self.bases.weight_count
    }

    /// The frame's deform matrices and morph weights at `time` seconds of `clip` (`None`: the
    /// rest pose), for a GPU that poses the vertices itself with [`Poser::deform_table`]:
    /// `matrices` gets every skin's joint matrices `world(joint) · inverse_bind` (skins in
    /// order, each's joints in order), then the world matrix of each unskinned instance's node
    /// (instances in order), column-major; `weights` every instance's morph weights (instances
    /// with targets, in order). The vectors are cleared first and keep their capacity; the
    /// work is O(nodes + joints), nothing per vertex. [`Poser::pose_into`] poses with these
    /// same matrices and weights.
    ///
    /// Errors on an unknown clip or a non-finite time (the vectors are then left untouched).
    ///
    /// ```
    /// use tessella_core::animation::Poser;
    /// let poser = Poser::new(tessella_core::samples::animated_creature(0))?;
    /// let (mut matrices, mut weights) = (Vec::new(), Vec::new());
    /// poser.deform_into(Some(0), 0.5, &mut matrices, &mut weights)?;
    /// assert_eq!(matrices.len(), poser.deform_matrix_count());
    /// assert_eq!(weights.len(), poser.morph_weight_count());
    /// # Ok::<(), tessella_core::AnimationError>(())
    /// ```
    pub fn deform_into(
        &self,
        clip: Option<usize>,
        time: f32,
        matrices: &mut Vec<[f32; 16]>,
        weights: &mut Vec<f32>,
    ) -> Result<(), AnimationError> {
        let state = self.node_state(clip, time)?;
        matrices.clear();
        deform(
            &self.model,
            &state,
            |m| matrices.push(m.to_cols_array()),
            weights,
        );
        Ok(())
    }

    /// The per-vertex tables a GPU poses with ([`DeformTable`]), made once per model.
    pub fn deform_table(&self) -> DeformTable {
        table(&self.model, &self.bases, self.vertex_count())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3A};

    /// A small deterministic generator (no dependency): uniform in [-1, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        }
    }

    /// The generic normal in `f32` equals the CPU pose's glam one bit for bit: random
    /// matrices (some with a negative determinant, some singular, some scaled far up or down)
    /// and normals (some zero).
    #[test]
    fn the_generic_skin_normal_is_the_cpu_one_bit_for_bit() {
        let mut rng = Lcg(7);
        let mut flips = 0;
        for case in 0..20_000 {
            let mut cols: [[f32; 3]; 3] =
                std::array::from_fn(|_| [rng.next(), rng.next(), rng.next()]);
            let scale = [1.0, 1e-3, 1e3, 1e-20][case % 4];
            cols.iter_mut().flatten().for_each(|x| *x *= scale);
            if case % 7 == 0 {
                cols[2] = cols[0].map(|x| x * 2.0); // singular
            }
            let mut n = [rng.next(), rng.next(), rng.next()];
            if case % 11 == 0 {
                n = [0.0; 3];
            }
            let m = Mat4::from_cols(
                Vec3A::from(cols[0]).extend(0.0),
                Vec3A::from(cols[1]).extend(0.0),
                Vec3A::from(cols[2]).extend(0.0),
                glam::Vec4::W,
            );
            let nv = Vec3A::from(n);
            let cpu = (normal_matrix(&m) * nv)
                .normalize_or(nv.normalize_or(Vec3A::Z))
                .to_array();
            let generic = super::super::deform::skin_normal_of(cols, n);
            assert_eq!(
                cpu.map(f32::to_bits),
                generic.map(f32::to_bits),
                "case {case}: {cols:?} {n:?}: {cpu:?} vs {generic:?}"
            );
            let det = Vec3A::from(cols[0]).dot(Vec3A::from(cols[1]).cross(Vec3A::from(cols[2])));
            flips += usize::from(det < 0.0);
        }
        assert!(flips > 1000, "{flips} negative determinants");
    }
}
