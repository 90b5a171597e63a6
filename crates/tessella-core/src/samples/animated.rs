//! An animated sample: [`super::creature`]'s shape with a skeleton, two sets of joint
//! influences, a morph target and three clips, so every kind of glTF animation data has a
//! case the project generates itself (`tessella samples` writes it as `animated-creature.glb`).

use super::{creature_on, normalize, CREATURE_BUMPS};
use crate::animation::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Property,
    Sampler, Skin, Transform,
};

/// The joints: name, parent joint (`None`: the rig node), translation from the parent.
const JOINTS: [(&str, Option<usize>, [f32; 3]); 7] = [
    ("hips", None, [0.0, -0.2, 0.0]),
    ("spine", Some(0), [0.0, 0.5, 0.0]),
    ("head", Some(1), [0.0, 0.6, 0.0]),
    ("arm.R", Some(1), [0.6, -0.1, 0.0]),
    ("arm.L", Some(1), [-0.6, -0.1, 0.0]),
    ("leg.R", Some(0), [0.3, -0.4, 0.0]),
    ("leg.L", Some(0), [-0.3, -0.4, 0.0]),
];

/// Node index of joint `j`: node 0 draws the mesh, node 1 is the rig above the joints.
const fn joint_node(j: usize) -> u32 {
    2 + j as u32
}

/// A unit quaternion `[x, y, z, w]` turning `degrees` about the unit `axis`.
fn turn(axis: [f32; 3], degrees: f32) -> [f32; 4] {
    let (s, c) = (degrees.to_radians() / 2.0).sin_cos();
    [axis[0] * s, axis[1] * s, axis[2] * s, c]
}

fn sampler(interpolation: Interpolation, times: &[f32], values: Vec<f32>) -> Sampler {
    Sampler {
        interpolation,
        times: times.to_vec(),
        values,
    }
}

fn rotations(
    node: u32,
    axis: [f32; 3],
    times: &[f32],
    degrees: &[f32],
    i: Interpolation,
) -> Channel {
    Channel {
        node,
        property: Property::Rotation,
        sampler: sampler(
            i,
            times,
            degrees.iter().flat_map(|&d| turn(axis, d)).collect(),
        ),
    }
}

/// A waving, hopping, breathing creature on an icosphere subdivided `subdivisions` times
/// (`20 · 4^s` triangles; 2 gives [`super::creature`]'s 320, 4 gives 5,120).
///
/// - Nodes: 0 draws the mesh (skinned), 1 is a rig node (a matrix transform) above the seven
///   joints (hips, spine, head, both arms, both legs), whose bind pose is their rest pose.
/// - Each vertex has two sets of four influences (`JOINTS_0`/`WEIGHTS_0`, `_1`), weights from
///   the creature's own bumps, summing to one.
/// - One morph target, `inflate`: the torso pushed out along its normals.
/// - Clips: `wave` (LINEAR: the right arm waves, the left arm and the head turn), `hop`
///   (CUBICSPLINE hips translation, STEP leg rotations), `breathe` (CUBICSPLINE weights of the
///   morph target).
///
/// ```
/// let creature = tessella_core::samples::animated_creature(2);
/// assert_eq!(creature.triangles.len(), 320);
/// assert_eq!(creature.clips.len(), 3);
/// ```
pub fn animated_creature(subdivisions: u32) -> AnimatedMesh {
    let rest = creature_on(subdivisions);
    let sphere = super::icosphere(subdivisions);
    let mut sets = [Influences::default(), Influences::default()];
    let mut inflate = Vec::with_capacity(rest.vertex_count());
    for (u, n) in sphere.positions().iter().zip(rest.normals()) {
        // The limbs' and head's weights: the bumps that shape them.
        let bump = |k: usize| {
            let (dir, _, width) = CREATURE_BUMPS[k];
            let d = normalize(dir);
            let cos = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
            (-(1.0 - cos) / (width * width)).exp()
        };
        let [head, arm_r, arm_l, leg_r, leg_l] = [0, 1, 2, 3, 4].map(bump);
        let body = 0.6;
        let (hips, spine) = (
            body * (0.5 - u[1]).clamp(0.0, 1.0),
            body * (0.5 + u[1]).clamp(0.0, 1.0),
        );
        let raw = [hips, spine, head, arm_r, arm_l, leg_r, leg_l];
        let total: f32 = raw.iter().sum();
        let w = raw.map(|x| x / total);
        sets[0].joints.push([0, 1, 2, 3]);
        sets[0].weights.push([w[0], w[1], w[2], w[3]]);
        sets[1].joints.push([4, 5, 6, 0]);
        sets[1].weights.push([w[4], w[5], w[6], 0.0]);
        // The torso breathes: little where a limb or the head takes over.
        let torso = 0.1 * (1.0 - (head + arm_r + arm_l + leg_r + leg_l).min(1.0));
        inflate.push(n.map(|c| c * torso));
    }

    let mut nodes = vec![
        Node {
            name: Some("creature".into()),
            weights: Some(vec![0.0]),
            ..Default::default()
        },
        Node {
            name: Some("rig".into()),
            transform: Transform::Matrix([
                1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]),
            ..Default::default()
        },
    ];
    let mut world = [[0.0f32; 3]; JOINTS.len()];
    for (j, (name, parent, t)) in JOINTS.iter().enumerate() {
        let base = parent.map_or([0.0; 3], |p| world[p]);
        world[j] = [base[0] + t[0], base[1] + t[1], base[2] + t[2]];
        nodes.push(Node {
            name: Some((*name).into()),
            parent: Some(parent.map_or(1, joint_node)),
            transform: Transform::Trs {
                translation: *t,
                rotation: [0.0, 0.0, 0.0, 1.0],
                scale: [1.0; 3],
            },
            weights: None,
        });
    }
    // The bind pose is the rest pose: each joint's inverse bind is the translation back.
    let inverse_binds = world
        .iter()
        .map(|p| {
            [
                1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -p[0], -p[1], -p[2],
                1.0,
            ]
        })
        .collect();
    let skin = Skin {
        name: Some("creature rig".into()),
        joints: (0..JOINTS.len()).map(joint_node).collect(),
        inverse_binds,
        skeleton: Some(1),
    };

    let z = [0.0, 0.0, 1.0];
    let [head, arm_r, arm_l, leg_r, leg_l, hips] = [2, 3, 4, 5, 6, 0].map(joint_node);
    let wave = Clip {
        name: "wave".into(),
        channels: vec![
            rotations(
                arm_r,
                z,
                &[0.0, 0.5, 1.0, 1.5, 2.0],
                &[0.0, 60.0, 15.0, 60.0, 0.0],
                Interpolation::Linear,
            ),
            rotations(
                arm_l,
                z,
                &[0.0, 1.0, 2.0],
                &[0.0, -12.0, 0.0],
                Interpolation::Linear,
            ),
            rotations(
                head,
                [0.0, 1.0, 0.0],
                &[0.0, 0.7, 1.4, 2.0],
                &[0.0, 25.0, -25.0, 0.0],
                Interpolation::Linear,
            ),
        ],
    };
    // Hermite keys: in-tangent, value, out-tangent per key.
    let low = [0.0, -0.2, 0.0];
    let hop = Clip {
        name: "hop".into(),
        channels: vec![
            Channel {
                node: hips,
                property: Property::Translation,
                sampler: sampler(
                    Interpolation::CubicSpline,
                    &[0.0, 0.4, 0.8],
                    [
                        [0.0; 3],
                        low,
                        [0.0, 1.5, 0.0],
                        [0.0; 3],
                        [0.0, 0.15, 0.0],
                        [0.0; 3],
                        [0.0, -1.5, 0.0],
                        low,
                        [0.0; 3],
                    ]
                    .concat(),
                ),
            },
            rotations(
                leg_r,
                [1.0, 0.0, 0.0],
                &[0.0, 0.2, 0.6],
                &[0.0, 25.0, 0.0],
                Interpolation::Step,
            ),
            rotations(
                leg_l,
                [1.0, 0.0, 0.0],
                &[0.0, 0.2, 0.6],
                &[0.0, -25.0, 0.0],
                Interpolation::Step,
            ),
        ],
    };
    let breathe = Clip {
        name: "breathe".into(),
        channels: vec![Channel {
            node: 0,
            property: Property::Weights,
            sampler: sampler(
                Interpolation::CubicSpline,
                &[0.0, 1.0, 2.0],
                vec![0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            ),
        }],
    };

    let instance = Instance {
        node: 0,
        skin: Some(0),
        first_vertex: 0,
        positions: rest.positions().to_vec(),
        normals: Some(rest.normals().to_vec()),
        targets: vec![MorphTarget {
            positions: inflate,
            normals: None,
        }],
        default_weights: vec![0.0],
        influences: sets.to_vec(),
    };
    AnimatedMesh {
        triangles: rest.triangles().to_vec(),
        uvs: None,
        nodes,
        skins: vec![skin],
        instances: vec![instance],
        clips: vec![wave, hop, breathe],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animation::Poser;

    #[test]
    fn the_sample_is_valid_its_rest_pose_is_the_creature_and_every_clip_moves_it() {
        let creature = super::super::creature();
        let poser = Poser::new(animated_creature(2)).expect("the sample is valid glTF animation");
        // The bind pose is the rest pose: skinning at rest gives the creature back.
        let (rest, _) = poser.pose(None, 0.0).unwrap();
        for (a, b) in rest.iter().zip(creature.positions()) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-5, "{a:?} vs {b:?}");
            }
        }
        for (clip, name) in ["wave", "hop", "breathe"].iter().enumerate() {
            assert_eq!(poser.clip_index(name).unwrap(), clip);
            let duration = poser.duration(clip).unwrap();
            let (mid, normals) = poser.pose(Some(clip), duration * 0.37).unwrap();
            let moved = mid
                .iter()
                .zip(creature.positions())
                .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0f32, f32::max))
                .fold(0.0f32, f32::max);
            assert!(moved > 0.02, "{name} moves the creature by {moved}");
            let normals = normals.expect("the sample has normals");
            assert!(normals
                .iter()
                .all(|n| ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-4));
        }
    }
}
