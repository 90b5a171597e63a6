//! What a GPU needs to pose an animated mesh itself: per frame the deform matrices and morph
//! weights ([`deform`], behind `Poser::deform_into` and `Poser::pose_into` both), once per
//! model the per-vertex tables that say which matrices and weights each vertex reads
//! ([`DeformTable`]), and the per-vertex formula written once, generic over [`Real`]
//! ([`skin_normal_of`], traced into WGSL by [`crate::shader::skin_normal`]).

use super::hierarchy::NodeState;
use super::model::AnimatedMesh;
use crate::scalar::Real;
use glam::Mat4;

/// Where each instance's matrices and weights sit in the frame's lists, fixed by the model.
#[derive(Debug, Clone)]
pub(super) struct Bases {
    /// Per instance: its skin's first joint matrix, or its own world matrix when unskinned.
    pub instance_matrix: Vec<usize>,
    /// Per instance, its first morph weight (instances without targets own none).
    pub instance_weight: Vec<usize>,
    /// Every skin's joints, then one per unskinned instance.
    pub matrix_count: usize,
    /// The instances' target counts together.
    pub weight_count: usize,
}

impl Bases {
    pub(super) fn new(model: &AnimatedMesh) -> Bases {
        let mut skin = Vec::with_capacity(model.skins.len());
        let mut matrix_count = 0;
        for s in &model.skins {
            skin.push(matrix_count);
            matrix_count += s.joints.len();
        }
        let mut instance_matrix = Vec::with_capacity(model.instances.len());
        let mut instance_weight = Vec::with_capacity(model.instances.len());
        let mut weight_count = 0;
        for instance in &model.instances {
            instance_matrix.push(match instance.skin {
                Some(s) => skin[s as usize],
                None => {
                    matrix_count += 1;
                    matrix_count - 1
                }
            });
            instance_weight.push(weight_count);
            weight_count += instance.targets.len();
        }
        Bases {
            instance_matrix,
            instance_weight,
            matrix_count,
            weight_count,
        }
    }
}

/// The frame's deform matrices and morph weights from the nodes' state, in [`Bases`]' order:
/// each skin's joint matrices `world(joint) · inverse_bind`, then each unskinned instance's
/// node's world matrix; each instance's target weights (its node's animated or stored
/// weights, else the mesh's defaults; zero past their end). The one place they are computed.
pub(super) fn deform(
    model: &AnimatedMesh,
    state: &NodeState,
    mut matrix: impl FnMut(Mat4),
    weights: &mut Vec<f32>,
) {
    for s in &model.skins {
        for (&j, ib) in s.joints.iter().zip(&s.inverse_binds) {
            matrix(state.world[j as usize] * Mat4::from_cols_array(ib));
        }
    }
    for instance in model.instances.iter().filter(|i| i.skin.is_none()) {
        matrix(state.world[instance.node as usize]);
    }
    weights.clear();
    for instance in &model.instances {
        let w = state.weights[instance.node as usize]
            .as_deref()
            .unwrap_or(&instance.default_weights);
        let count = instance.targets.len();
        weights.extend((0..count).map(|t| w.get(t).copied().unwrap_or(0.0)));
    }
}

/// Per vertex, what a GPU reads to pose it: made once per model by [`Poser::deform_table`](super::Poser::deform_table);
/// each frame then needs only [`Poser::deform_into`](super::Poser::deform_into)'s matrices and weights.
///
/// A vertex's posed position is `M · (p + Σ_t w_t Δp_t)` and its normal `normalize(N(M) ·
/// (n + Σ_t w_t Δn_t))` (falling back to the morphed rest normal normalised, else `+Z`, where
/// that is not finite: [`skin_normal_of`]), where `w_t` are the weights
/// `weights[morph[1] + t]` for `t < morph[0]`, `Δ` the deltas at `morph[2] + t`, and
/// `M = Σ_k a_k matrices[i_k] / Σ_k a_k` over the vertex's `slots` pairs `(i_k, a_k)` whose
/// weight is positive. [`Poser::pose_into`](super::Poser::pose_into) computes the same.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeformTable {
    /// The number of deform matrices a frame has ([`Poser::deform_into`](super::Poser::deform_into)).
    pub matrix_count: usize,
    /// The number of morph weights a frame has.
    pub weight_count: usize,
    /// Influence slots per vertex (at least 1): the most positive joint weights any vertex
    /// has.
    pub slots: usize,
    /// `vertex * slots + k`: the `k`th influence's index into the frame's deform matrices, in
    /// the order of the model's influence sets and their four joints; unused slots 0. An
    /// unskinned vertex has one influence, its instance's world matrix, with weight 1.
    pub matrices: Vec<u32>,
    /// `vertex * slots + k`: the `k`th influence's weight (positive); unused slots 0.
    pub weights: Vec<f32>,
    /// Per vertex: its instance's target count, the index of its instance's first weight in
    /// the frame's weights, and the index of its first delta in `position_deltas` and
    /// `normal_deltas` (its targets' deltas follow, one per target).
    pub morphs: Vec<[u32; 3]>,
    /// Morph position displacements, each vertex's targets in order.
    pub position_deltas: Vec<[f32; 3]>,
    /// Morph normal displacements, as `position_deltas`; zero where a target has no normals.
    pub normal_deltas: Vec<[f32; 3]>,
}

/// The posed normal of a vertex: the normal matrix of `m` (the upper 3×3 of its blended
/// matrix, columns `m[0]`, `m[1]`, `m[2]`) — its cofactor matrix, negated where the
/// determinant is negative, the inverse transpose up to a positive factor — times `n` (the
/// morphed rest normal), normalised; where that has no finite unit length (a singular matrix),
/// `n` normalised; where neither has, `+Z`.
///
/// The CPU pose computes this with glam; the unit tests check the two equal bit for bit, and
/// [`crate::shader::skin_normal`] traces this function into WGSL.
pub fn skin_normal_of<T: Real>(m: [[T; 3]; 3], n: [T; 3]) -> [T; 3] {
    let cross = |a: [T; 3], b: [T; 3]| {
        [
            a[1] * b[2] - b[1] * a[2],
            a[2] * b[0] - b[2] * a[0],
            a[0] * b[1] - b[0] * a[1],
        ]
    };
    let dot = |a: [T; 3], b: [T; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let [c0, c1, c2] = m;
    let (a, b, c) = (cross(c1, c2), cross(c2, c0), cross(c0, c1));
    // Negated where the determinant is negative: -det positive (and finite).
    let det = dot(c0, a);
    let signed = |v: [T; 3]| v.map(|x| T::select_positive_finite(-det, -x, x));
    let (a, b, c) = (signed(a), signed(b), signed(c));
    let normal: [T; 3] = std::array::from_fn(|i| a[i] * n[0] + b[i] * n[1] + c[i] * n[2]);
    let normalize_or = |v: [T; 3], fallback: [T; 3]| {
        let rcp = T::lit(1.0) / dot(v, v).sqrt();
        std::array::from_fn(|i| T::select_positive_finite(rcp, v[i] * rcp, fallback[i]))
    };
    let z = [T::lit(0.0), T::lit(0.0), T::lit(1.0)];
    normalize_or(normal, normalize_or(n, z))
}

/// [`DeformTable`] of `model` (`n` vertices), its matrices indexed as `bases` says.
pub(super) fn table(model: &AnimatedMesh, bases: &Bases, n: usize) -> DeformTable {
    // Positive weights per vertex, in the order `blend` sums them.
    let mut pairs: Vec<(u32, f32)> = Vec::new();
    let mut starts: Vec<usize> = Vec::with_capacity(n + 1);
    let mut morphs = Vec::with_capacity(n);
    let mut position_deltas = Vec::new();
    let mut normal_deltas = Vec::new();
    for (index, instance) in model.instances.iter().enumerate() {
        let base = bases.instance_matrix[index] as u32;
        let targets = instance.targets.len();
        for v in 0..instance.positions.len() {
            starts.push(pairs.len());
            if instance.skin.is_some() {
                for set in &instance.influences {
                    for (&j, &w) in set.joints[v].iter().zip(&set.weights[v]) {
                        if w > 0.0 {
                            pairs.push((base + u32::from(j), w));
                        }
                    }
                }
            } else {
                pairs.push((base, 1.0));
            }
            morphs.push([
                targets as u32,
                bases.instance_weight[index] as u32,
                position_deltas.len() as u32,
            ]);
            for target in &instance.targets {
                position_deltas.push(target.positions[v]);
                normal_deltas.push(target.normals.as_ref().map_or([0.0; 3], |d| d[v]));
            }
        }
    }
    starts.push(pairs.len());
    let slots = starts
        .windows(2)
        .map(|w| w[1] - w[0])
        .max()
        .unwrap_or(0)
        .max(1);
    let mut matrices = vec![0u32; n * slots];
    let mut weights = vec![0f32; n * slots];
    for v in 0..n {
        for (k, &(m, w)) in pairs[starts[v]..starts[v + 1]].iter().enumerate() {
            matrices[v * slots + k] = m;
            weights[v * slots + k] = w;
        }
    }
    DeformTable {
        matrix_count: bases.matrix_count,
        weight_count: bases.weight_count,
        slots,
        matrices,
        weights,
        morphs,
        position_deltas,
        normal_deltas,
    }
}
