//! Skin influences at refined vertices: each corner's joints and weights, blended with the
//! vertex's barycentric weights, the strongest kept (four per set; as many sets as the input
//! had, or more where [`JointSets::UpTo`] allows and a vertex needs them), renormalised to sum
//! to one.
//!
//! Skinning these weights is not the same as refining the skinned coarse mesh: the posed
//! refined vertex is a blend of joint transforms applied to a point, where refine-then-pose
//! applies them to corners first. The two differ where joints bend; the tests measure by how
//! much.

use super::carry::Origins;
use super::JointSets;

/// `joints` and `weights`: per set, four per coarse vertex. Returns the same number of sets at
/// every output vertex: the input's, or with [`JointSets::UpTo`] as many as the vertex with the
/// most influences needs, within the limit.
pub(super) fn blend(
    origins: &Origins,
    joints: &[Vec<u32>],
    weights: &[Vec<f32>],
    joint_sets: JointSets,
) -> (Vec<Vec<u32>>, Vec<Vec<f32>>) {
    let input_sets = joints.len();
    let mut sum: Vec<(u32, f64)> = Vec::with_capacity(input_sets * 12);
    let sets = match joint_sets {
        JointSets::UpTo(limit) if limit as usize > input_sets => {
            let most = (0..origins.len())
                .map(|v| {
                    influences(origins, v, joints, weights, &mut sum);
                    sum.len()
                })
                .max()
                .unwrap_or(0);
            most.div_ceil(4).clamp(input_sets, limit as usize)
        }
        _ => input_sets,
    };
    let keep = sets * 4;
    let n = origins.len();
    let mut out_joints = vec![Vec::with_capacity(n * 4); sets];
    let mut out_weights = vec![Vec::with_capacity(n * 4); sets];
    for v in 0..n {
        influences(origins, v, joints, weights, &mut sum);
        // Strongest first; equal weights by joint, so the result does not depend on order.
        sum.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        sum.truncate(keep);
        let total: f64 = sum.iter().map(|e| e.1).sum();
        for s in 0..sets {
            for c in 0..4 {
                match sum.get(s * 4 + c) {
                    Some(&(j, w)) if total > 0.0 => {
                        out_joints[s].push(j);
                        out_weights[s].push((w / total) as f32);
                    }
                    _ => {
                        out_joints[s].push(0);
                        out_weights[s].push(0.0);
                    }
                }
            }
        }
    }
    (out_joints, out_weights)
}

/// Output vertex `v`'s influences (joint, weight), every corner's weighted by the vertex's
/// barycentric weight and summed per joint, into `sum` (unordered).
fn influences(
    origins: &Origins,
    v: usize,
    joints: &[Vec<u32>],
    weights: &[Vec<f32>],
    sum: &mut Vec<(u32, f64)>,
) {
    let sets = joints.len();
    let (t, l) = (&origins.corners[v], &origins.weights[v]);
    sum.clear();
    for k in 0..3 {
        if l[k] == 0.0 {
            continue;
        }
        let corner = t[k] as usize;
        for s in 0..sets {
            for i in 0..4 {
                let w = weights[s][corner * 4 + i] as f64 * l[k];
                if w <= 0.0 {
                    continue;
                }
                let j = joints[s][corner * 4 + i];
                match sum.iter_mut().find(|(jj, _)| *jj == j) {
                    Some(e) => e.1 += w,
                    None => sum.push((j, w)),
                }
            }
        }
    }
}
