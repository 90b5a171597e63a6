//! Posing against an independent f64 evaluation of the glTF 2.0 specification
//! (`animation_scene/mod.rs`: own quaternions, slerp, Hermite splines, 4×4 products and
//! inverses), and the refusals of bad input.

// The reference spells the specification's formulas out with indices and plain tuples.
#![allow(clippy::needless_range_loop, clippy::type_complexity)]

use tessella_core::animation::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Poser,
    Property, Sampler, Transform,
};
use tessella_core::AnimationError;

mod animation_scene;
use animation_scene::*;

// ---------------------------------------------------------------- comparisons

fn diagonal(points: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::MAX; 3];
    let mut hi = [f64::MIN; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt()
}

/// Poses `model` and compares with the reference: positions within 1e-6 of the bounding box's
/// diagonal, normals within 1e-5.
fn assert_matches(model: &AnimatedMesh, clip: Option<usize>, time: f32) {
    let poser = Poser::new(model.clone()).expect("valid scene");
    let (positions, normals) = poser.pose(clip, time).expect("pose");
    let (want_p, want_n) = reference(model, clip, time);
    let tolerance = 1e-6 * diagonal(&want_p);
    assert_eq!(positions.len(), want_p.len());
    for (v, (got, want)) in positions.iter().zip(&want_p).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= tolerance,
            "clip {clip:?} t={time} vertex {v}: {got:?} vs {want:?} ({d:e} > {tolerance:e})"
        );
    }
    let normals = normals.expect("the scene has normals");
    assert_eq!(normals.len(), want_n.len());
    for (v, (got, want)) in normals.iter().zip(&want_n).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= 1e-5,
            "clip {clip:?} t={time} normal {v}: {got:?} vs {want:?} ({d:e})"
        );
    }
}

/// Before the first key, on keys, between keys, after the last.
const TIMES: [f32; 10] = [-1.0, 0.0, 0.1, 0.2, 0.4, 0.77, 1.0, 1.5, 1.95, 7.0];

#[test]
fn linear_matches_the_spec() {
    let model = scene(Interpolation::Linear);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn step_matches_the_spec() {
    let model = scene(Interpolation::Step);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn cubic_spline_matches_the_spec() {
    let model = scene(Interpolation::CubicSpline);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn rest_pose_matches_the_spec() {
    let mut model = scene(Interpolation::Linear);
    assert_matches(&model, None, 0.0);
    // Node weights override the mesh's default weights.
    model.nodes[MESH_NODE as usize].weights = Some(vec![0.7, 0.4]);
    assert_matches(&model, None, 0.0);
}

#[test]
fn before_the_first_key_and_after_the_last_hold_the_end_poses() {
    let model = scene(Interpolation::CubicSpline);
    let poser = Poser::new(model.clone()).unwrap();
    assert_eq!(poser.duration(0).unwrap(), 2.0);
    // Every channel starts at 0 or 0.2 and ends at 1.7 or 2.0.
    assert_eq!(
        poser.pose(Some(0), -3.0).unwrap(),
        poser.pose(Some(0), 0.0).unwrap()
    );
    assert_eq!(
        poser.pose(Some(0), 2.0).unwrap(),
        poser.pose(Some(0), 100.0).unwrap()
    );
    assert_matches(&model, Some(0), -3.0);
    assert_matches(&model, Some(0), 100.0);
}

/// A skinned node's own transform is ignored; the root above the joints moves the mesh.
#[test]
fn skinned_node_transform_ignored_and_parent_above_joints_applies() {
    let model = scene(Interpolation::Linear);
    let base = Poser::new(model.clone()).unwrap().pose(None, 0.0).unwrap();
    let mut moved = model.clone();
    moved.nodes[MESH_NODE as usize].transform = Transform::default();
    assert_eq!(Poser::new(moved).unwrap().pose(None, 0.0).unwrap(), base);

    let mut shifted = model.clone();
    shifted.nodes[ROOT as usize].transform = Transform::Trs {
        translation: [1.0, 2.0, 3.0],
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
    };
    let (p, _) = Poser::new(shifted.clone())
        .unwrap()
        .pose(None, 0.0)
        .unwrap();
    assert_ne!(p[0], base.0[0]);
    assert_matches(&shifted, None, 0.0);
}

/// Weights are divided by their sum: doubling every weight changes nothing.
#[test]
fn weights_are_normalised_by_their_sum() {
    let model = scene(Interpolation::Linear);
    let mut doubled = model.clone();
    for set in &mut doubled.instances[0].influences {
        for w in &mut set.weights {
            *w = w.map(|x| 2.0 * x);
        }
    }
    let a = Poser::new(model).unwrap().pose(Some(0), 0.6).unwrap();
    let b = Poser::new(doubled.clone())
        .unwrap()
        .pose(Some(0), 0.6)
        .unwrap();
    for (p, q) in a.0.iter().zip(&b.0) {
        for i in 0..3 {
            assert!((p[i] - q[i]).abs() < 1e-5, "{p:?} vs {q:?}");
        }
    }
    assert_matches(&doubled, Some(0), 0.6);
}

/// Eight joints per vertex across two influence sets, each set alone giving another pose.
#[test]
fn two_influence_sets_both_count() {
    let model = scene(Interpolation::Linear);
    let mut first_only = model.clone();
    first_only.instances[0].influences.truncate(1);
    let a = Poser::new(model).unwrap().pose(Some(0), 0.5).unwrap();
    let b = Poser::new(first_only.clone())
        .unwrap()
        .pose(Some(0), 0.5)
        .unwrap();
    assert_ne!(a.0, b.0);
    assert_matches(&first_only, Some(0), 0.5);
}

/// An unskinned instance follows its node's world matrix, through a matrix node.
#[test]
fn unskinned_instance_follows_its_node() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    let first = model.instances[1].first_vertex as usize;
    let (p0, _) = poser.pose(Some(0), 0.2).unwrap();
    let (p1, _) = poser.pose(Some(0), 1.2).unwrap();
    assert_ne!(p0[first], p1[first]);
    assert_matches(&model, Some(0), 0.2);
    assert_matches(&model, Some(0), 1.2);
}

/// Morph targets alone: a node with no skin at the origin, weights animated linearly.
#[test]
fn morph_targets_move_positions_and_normals() {
    let mut rng = Lcg(99);
    let (positions, normals, triangles) = grid(&mut rng, 3, 1.0);
    let n = positions.len();
    let model = AnimatedMesh {
        triangles,
        uvs: None,
        nodes: vec![Node::default()],
        skins: Vec::new(),
        instances: vec![Instance {
            node: 0,
            positions,
            normals: Some(normals),
            targets: vec![
                MorphTarget {
                    positions: (0..n).map(|_| rng.vec3(-0.2, 0.2)).collect(),
                    normals: Some((0..n).map(|_| rng.vec3(-0.3, 0.3)).collect()),
                },
                MorphTarget {
                    positions: (0..n).map(|_| rng.vec3(-0.2, 0.2)).collect(),
                    normals: Some((0..n).map(|_| rng.vec3(-0.3, 0.3)).collect()),
                },
            ],
            default_weights: vec![0.0, 0.0],
            ..Instance::default()
        }],
        clips: vec![Clip {
            name: "morph".into(),
            channels: vec![Channel {
                node: 0,
                property: Property::Weights,
                sampler: Sampler {
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 1.0],
                    values: vec![0.0, 0.0, 1.0, 0.5],
                },
            }],
        }],
    };
    let poser = Poser::new(model.clone()).unwrap();
    let (rest, _) = poser.pose(None, 0.0).unwrap();
    assert_eq!(rest, model.instances[0].positions);
    let (p, _) = poser.pose(Some(0), 0.5).unwrap();
    let t = &model.instances[0].targets;
    for v in 0..n {
        for i in 0..3 {
            let want = model.instances[0].positions[v][i]
                + 0.5 * t[0].positions[v][i]
                + 0.25 * t[1].positions[v][i];
            assert!((p[v][i] - want).abs() < 1e-6);
        }
    }
    for time in [0.25, 0.5, 1.0, 3.0] {
        assert_matches(&model, Some(0), time);
    }
}

#[test]
fn pose_into_mesh_and_clip_lookup() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    assert_eq!(poser.vertex_count(), 34);
    assert!(poser.has_normals());
    assert_eq!(poser.clip_index("anim").unwrap(), 0);
    assert_eq!(poser.clip_index("0").unwrap(), 0);
    let mut p = vec![[0.0; 3]; 34];
    let mut n = vec![[0.0; 3]; 34];
    poser.pose_into(Some(0), 0.3, &mut p, Some(&mut n)).unwrap();
    let (p2, n2) = poser.pose(Some(0), 0.3).unwrap();
    assert_eq!((p.clone(), Some(n.clone())), (p2, n2));
    let mut only = vec![[0.0; 3]; 34];
    poser.pose_into(Some(0), 0.3, &mut only, None).unwrap();
    assert_eq!(only, p);
    let mesh = poser.mesh(Some(0), 0.3).unwrap();
    assert_eq!(mesh.positions(), &p[..]);
    assert_eq!(mesh.triangles(), &model.triangles[..]);

    // Without normals on some instance, poses carry positions only and the mesh computes them.
    let mut bare = model.clone();
    bare.instances[1].normals = None;
    let poser = Poser::new(bare).unwrap();
    assert!(!poser.has_normals());
    let (q, none) = poser.pose(Some(0), 0.3).unwrap();
    assert_eq!((q, none), (p, None));
    assert!(poser.mesh(Some(0), 0.3).unwrap().normals_computed());
    let err = poser
        .pose_into(Some(0), 0.3, &mut only, Some(&mut n))
        .unwrap_err();
    assert_eq!(err, AnimationError::NoNormals);
}

// ---------------------------------------------------------------- refusals

/// `Poser::new` refuses `model` with an error matching `pattern` whose message holds every
/// one of `words`.
macro_rules! refuses {
    ($model:expr, $pattern:pat, $($word:expr),+) => {{
        let err = Poser::new($model).expect_err("bad input accepted");
        assert!(matches!(err, $pattern), "wrong error: {err:?}");
        let message = err.to_string();
        $(assert!(message.contains($word), "{message:?} does not name {:?}", $word);)+
    }};
}

fn base() -> AnimatedMesh {
    scene(Interpolation::Linear)
}

#[test]
fn refuses_joint_index_past_the_skin() {
    let mut m = base();
    m.instances[0].influences[1].joints[5][2] = 8;
    refuses!(
        m,
        AnimationError::JointOutOfRange {
            instance: 0,
            vertex: 5,
            set: 1,
            joint: 8,
            ..
        },
        "instance 0",
        "vertex 5",
        "joint 8"
    );
}

#[test]
fn refuses_nan_negative_and_all_zero_weights() {
    let mut m = base();
    m.instances[0].influences[0].weights[3][1] = f32::NAN;
    refuses!(
        m,
        AnimationError::BadWeight {
            instance: 0,
            vertex: 3,
            ..
        },
        "vertex 3",
        "NaN"
    );
    let mut m = base();
    m.instances[0].influences[1].weights[4][0] = -0.5;
    refuses!(
        m,
        AnimationError::BadWeight {
            instance: 0,
            vertex: 4,
            set: 1,
            ..
        },
        "vertex 4",
        "-0.5"
    );
    let mut m = base();
    for set in &mut m.instances[0].influences {
        set.weights[6] = [0.0; 4];
    }
    refuses!(
        m,
        AnimationError::ZeroWeights {
            instance: 0,
            vertex: 6
        },
        "instance 0",
        "vertex 6"
    );
}

#[test]
fn refuses_bad_inverse_binds() {
    let mut m = base();
    m.skins[0].inverse_binds[2] = [0.0; 16];
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 2,
            ..
        },
        "skin 0",
        "joint 2",
        "singular"
    );
    let mut m = base();
    let mut flat = [1.0; 16]; // rank one
    flat[15] = 1.0;
    m.skins[0].inverse_binds[3] = flat;
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 3,
            ..
        },
        "joint 3",
        "singular"
    );
    let mut m = base();
    m.skins[0].inverse_binds[1][5] = f32::INFINITY;
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 1,
            ..
        },
        "joint 1",
        "not finite"
    );
    let mut m = base();
    m.skins[0].inverse_binds.pop();
    refuses!(
        m,
        AnimationError::InverseBindCount {
            skin: 0,
            got: 7,
            expected: 8
        },
        "skin 0"
    );
    let mut m = base();
    m.skins[0].joints[4] = 40;
    refuses!(
        m,
        AnimationError::JointNodeOutOfRange {
            skin: 0,
            joint: 4,
            node: 40,
            ..
        },
        "node 40"
    );
}

#[test]
fn refuses_bad_key_times() {
    let mut m = base();
    m.clips[0].channels[1].sampler.times[2] = 0.9; // equal to the key before
    refuses!(
        m,
        AnimationError::BadKeyTime {
            clip: 0,
            channel: 1,
            key: 2,
            ..
        },
        "clip 0 \"anim\"",
        "channel 1",
        "key time 2",
        "strictly increasing"
    );
    let mut m = base();
    m.clips[0].channels[3].sampler.times[1] = 0.0;
    refuses!(
        m,
        AnimationError::BadKeyTime {
            channel: 3,
            key: 1,
            ..
        },
        "channel 3"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.times[3] = f32::INFINITY;
    refuses!(
        m,
        AnimationError::BadKeyTime {
            channel: 0,
            key: 3,
            ..
        },
        "channel 0",
        "not finite"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.times.clear();
    m.clips[0].channels[0].sampler.values.clear();
    refuses!(
        m,
        AnimationError::NoKeys { channel: 0, .. },
        "channel 0",
        "no keys"
    );
    let mut m = base();
    m.clips[0].channels[2].sampler.values[1] = f32::NAN;
    refuses!(
        m,
        AnimationError::NonFiniteValue {
            channel: 2,
            index: 1,
            ..
        },
        "channel 2",
        "value 1"
    );
}

#[test]
fn refuses_value_counts_other_than_keys_times_components() {
    let mut m = base();
    m.clips[0].channels[1].sampler.values.pop(); // translation, 3 keys × 3
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 1,
            got: 8,
            expected: 9,
            ..
        },
        "channel 1",
        "8 values",
        "expected 9"
    );
    let mut m = base();
    m.clips[0].channels[7].sampler.values.push(0.0); // weights of 2 targets, 4 keys
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 7,
            components: 2,
            expected: 8,
            ..
        },
        "channel 7",
        "2 components"
    );
    let mut m = scene(Interpolation::CubicSpline);
    m.clips[0].channels[0].sampler.values.truncate(16); // rotation: 4 keys × 4 × 3 = 48
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 0,
            expected: 48,
            cubic: true,
            ..
        },
        "CUBICSPLINE",
        "expected 48"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.interpolation = Interpolation::CubicSpline;
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 0,
            got: 16,
            expected: 48,
            ..
        },
        "channel 0"
    );
}

#[test]
fn refuses_channels_on_missing_matrix_or_meshless_nodes() {
    let mut m = base();
    m.clips[0].channels[4].node = 12;
    refuses!(
        m,
        AnimationError::ChannelNode {
            clip: 0,
            channel: 4,
            node: 12,
            nodes: 12,
            ..
        },
        "channel 4",
        "node 12"
    );
    let mut m = base();
    m.clips[0].channels[4].node = 11;
    refuses!(
        m,
        AnimationError::ChannelOnMatrix {
            channel: 4,
            node: 11,
            ..
        },
        "node 11",
        "matrix"
    );
    let mut m = base();
    m.clips[0].channels[7].node = 3;
    refuses!(
        m,
        AnimationError::WeightsWithoutMesh {
            channel: 7,
            node: 3,
            ..
        },
        "node 3",
        "no mesh"
    );
}

#[test]
fn refuses_bad_parents() {
    let mut m = base();
    m.nodes[4].parent = Some(99);
    refuses!(
        m,
        AnimationError::ParentOutOfRange {
            node: 4,
            parent: 99,
            ..
        },
        "node 4",
        "node 99"
    );
    let mut m = base();
    m.nodes[1].parent = Some(3); // 1 → 3 → 2 → 1
    refuses!(m, AnimationError::ParentCycle { .. }, "cycle");
    let mut m = base();
    m.nodes[6].parent = Some(6);
    refuses!(m, AnimationError::ParentCycle { node: 6 }, "node 6");
    let mut m = base();
    m.nodes[2].transform = Transform::Trs {
        translation: [0.0, f32::NAN, 0.0],
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
    };
    refuses!(
        m,
        AnimationError::NonFiniteTransform {
            node: 2,
            what: "translation"
        },
        "node 2"
    );
}

#[test]
fn refuses_instance_attribute_lengths_that_disagree() {
    let mut m = base();
    m.instances[0].normals.as_mut().unwrap().pop();
    refuses!(
        m,
        AnimationError::AttributeLength {
            instance: 0,
            got: 24,
            expected: 25,
            ..
        },
        "instance 0",
        "normals",
        "24"
    );
    let mut m = base();
    m.instances[1].targets[0].positions.push([0.0; 3]);
    refuses!(
        m,
        AnimationError::AttributeLength {
            instance: 1,
            got: 10,
            expected: 9,
            ..
        },
        "instance 1",
        "morph target 0's positions"
    );
    let mut m = base();
    m.instances[0].targets[0].normals.as_mut().unwrap().pop();
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "morph target 0's normals"
    );
    let mut m = base();
    m.instances[0].influences[1].joints.pop();
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "influence set 1's joints"
    );
    let mut m = base();
    m.instances[0].influences[0].weights.push([1.0; 4]);
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "influence set 0's weights"
    );
    let mut m = base();
    m.instances[0].default_weights.pop();
    refuses!(
        m,
        AnimationError::WeightCount {
            got: 1,
            expected: 2,
            ..
        },
        "instance 0's default weights"
    );
    let mut m = base();
    m.nodes[PROP_NODE as usize].weights = Some(vec![1.0, 2.0]);
    refuses!(
        m,
        AnimationError::WeightCount {
            got: 2,
            expected: 1,
            ..
        },
        "node 10"
    );
    let mut m = base();
    m.instances[1].first_vertex = 3;
    refuses!(
        m,
        AnimationError::InstanceRange {
            instance: 1,
            first_vertex: 3,
            expected: 25
        },
        "instance 1"
    );
    let mut m = base();
    m.instances[1].positions[2][0] = f32::NAN;
    m.instances[1].positions.truncate(9);
    refuses!(
        m,
        AnimationError::NonFiniteAttribute {
            instance: 1,
            vertex: 2,
            ..
        },
        "vertex 2"
    );
    let mut m = base();
    m.uvs = Some(vec![[0.0; 2]; 3]);
    refuses!(
        m,
        AnimationError::UvCount {
            got: 3,
            expected: 34
        },
        "34"
    );
    let mut m = base();
    m.instances[0].influences.clear();
    refuses!(
        m,
        AnimationError::NoInfluences {
            instance: 0,
            skin: 0
        },
        "instance 0"
    );
}

#[test]
fn refuses_skin_and_node_indices_out_of_range() {
    let mut m = base();
    m.instances[0].skin = Some(1);
    refuses!(
        m,
        AnimationError::SkinOutOfRange {
            instance: 0,
            skin: 1,
            skins: 1
        },
        "instance 0",
        "skin 1"
    );
    let mut m = base();
    m.instances[1].node = 50;
    refuses!(
        m,
        AnimationError::InstanceNodeOutOfRange {
            instance: 1,
            node: 50,
            ..
        },
        "node 50"
    );
}

#[test]
fn refuses_triangles_past_the_vertices() {
    let mut m = base();
    m.triangles[7][1] = 34;
    refuses!(
        m,
        AnimationError::TriangleIndex {
            face: 7,
            index: 34,
            count: 34
        },
        "triangle 7",
        "vertex 34"
    );
}

#[test]
fn accepts_valid_but_odd_input() {
    let mut m = base();
    m.skins[0].joints.push(11); // an unused joint
    m.skins[0].inverse_binds.push(IDENTITY.map(|x| x as f32));
    m.instances[1].influences = vec![Influences {
        joints: vec![[0; 4]; 9],
        weights: vec![[0.0; 4]; 9],
    }]; // influences on an unskinned instance: unused
    m.instances[0].influences[0].weights[0] = [0.0, 0.0, 0.0, 3.0]; // sums to 3
    assert!(Poser::new(m.clone()).is_ok());
    assert_matches(&m, Some(0), 0.5);
}

#[test]
fn bad_arguments_leave_the_buffers_untouched() {
    let poser = Poser::new(base()).unwrap();
    let sentinel = [[7.0f32, 8.0, 9.0]; 34];
    let (mut p, mut n) = (sentinel, sentinel);
    let err = poser
        .pose_into(Some(1), 0.0, &mut p, Some(&mut n))
        .unwrap_err();
    assert!(matches!(err, AnimationError::UnknownClip { .. }));
    assert!(err.to_string().contains("\"anim\""), "{err}");
    let err = poser
        .pose_into(Some(0), f32::NAN, &mut p, Some(&mut n))
        .unwrap_err();
    assert!(matches!(err, AnimationError::BadTime(_)));
    let err = poser
        .pose_into(Some(0), f32::INFINITY, &mut p, None)
        .unwrap_err();
    assert!(matches!(err, AnimationError::BadTime(_)));
    let err = poser
        .pose_into(Some(0), 0.5, &mut p, Some(&mut n[..33]))
        .unwrap_err();
    assert!(matches!(
        err,
        AnimationError::BufferLength {
            what: "normals",
            got: 33,
            expected: 34
        }
    ));
    let err = poser
        .pose_into(None, 0.5, &mut p[..30], Some(&mut n))
        .unwrap_err();
    assert!(matches!(
        err,
        AnimationError::BufferLength {
            what: "positions",
            got: 30,
            ..
        }
    ));
    assert_eq!((p, n), (sentinel, sentinel));

    assert!(matches!(
        poser.clip_index("walk"),
        Err(AnimationError::UnknownClip { .. })
    ));
    assert!(matches!(
        poser.clip_index("1"),
        Err(AnimationError::UnknownClip { .. })
    ));
    assert!(poser.duration(3).is_err());
    assert!(poser.mesh(Some(2), 0.0).is_err());
}

// ---------------------------------------------------------------- what a GPU poses with

/// A pose computed in f64 from [`Poser::deform_into`]'s matrices and weights and
/// [`Poser::deform_table`], as a GPU computes it: morph, blend the vertex's matrices divided
/// by their weight sum, move the point, the normal by the blend's cofactor matrix with the
/// determinant's sign, renormalised (the morphed rest normal where that fails).
fn pose_from_table(poser: &Poser, clip: Option<usize>, time: f32) -> Pose64 {
    let table = poser.deform_table();
    let (mut matrices, mut weights) = (Vec::new(), Vec::new());
    poser
        .deform_into(clip, time, &mut matrices, &mut weights)
        .expect("deform");
    assert_eq!(matrices.len(), table.matrix_count);
    assert_eq!(weights.len(), table.weight_count);
    let rest_p: Vec<[f32; 3]> = poser
        .model()
        .instances
        .iter()
        .flat_map(|i| i.positions.iter().copied())
        .collect();
    let rest_n: Vec<[f32; 3]> = poser
        .model()
        .instances
        .iter()
        .flat_map(|i| i.normals.as_ref().expect("normals").iter().copied())
        .collect();
    let f = |v: [f32; 3]| v.map(f64::from);
    let (mut out_p, mut out_n) = (Vec::new(), Vec::new());
    for v in 0..poser.vertex_count() {
        let [count, wbase, dbase] = table.morphs[v].map(|x| x as usize);
        let (mut p, mut n) = (f(rest_p[v]), f(rest_n[v]));
        for t in 0..count {
            let w = f64::from(weights[wbase + t]);
            for i in 0..3 {
                p[i] += w * f64::from(table.position_deltas[dbase + t][i]);
                n[i] += w * f64::from(table.normal_deltas[dbase + t][i]);
            }
        }
        let mut m = [0.0; 16];
        let mut sum = 0.0;
        for k in 0..table.slots {
            let w = f64::from(table.weights[v * table.slots + k]);
            let j = table.matrices[v * table.slots + k] as usize;
            for i in 0..16 {
                m[i] += w * f64::from(matrices[j][i]);
            }
            sum += w;
        }
        let m = m.map(|x| x / sum);
        out_p.push(transform_point(&m, p));
        let normal = transform_normal(&m, n);
        out_n.push(if normal.iter().all(|x| x.is_finite()) {
            normal
        } else {
            normalize3(n)
        });
    }
    (out_p, out_n)
}

fn assert_table_pose_matches(poser: &Poser, clip: Option<usize>, time: f32) {
    let (positions, normals) = poser.pose(clip, time).expect("pose");
    let (want_p, want_n) = pose_from_table(poser, clip, time);
    let tolerance = 1e-6 * diagonal(&want_p);
    for (v, (got, want)) in positions.iter().zip(&want_p).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= tolerance,
            "clip {clip:?} t={time} vertex {v}: {got:?} vs {want:?} ({d:e} > {tolerance:e})"
        );
    }
    for (v, (got, want)) in normals.expect("normals").iter().zip(&want_n).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= 1e-5,
            "clip {clip:?} t={time} normal {v}: {got:?} vs {want:?}"
        );
    }
}

/// Posing from the deform matrices, weights and table (what a GPU is given) equals
/// `pose_into`: the test scene (two influence sets, weights not summing to one, zero weights,
/// a target without normals, an unskinned instance under an animated parent) and the
/// creature sample.
#[test]
fn deform_matrices_and_table_pose_as_pose_into() {
    for kind in [
        Interpolation::Linear,
        Interpolation::Step,
        Interpolation::CubicSpline,
    ] {
        let poser = Poser::new(scene(kind)).unwrap();
        for time in TIMES {
            assert_table_pose_matches(&poser, Some(0), time);
        }
        assert_table_pose_matches(&poser, None, 0.0);
    }
    let creature = Poser::new(tessella_core::samples::animated_creature(1)).unwrap();
    for clip in 0..creature.clip_count() {
        let end = creature.duration(clip).unwrap();
        for s in [0.0, 0.3, 0.71, 1.0] {
            assert_table_pose_matches(&creature, Some(clip), s * end);
        }
    }
}

/// The layout: every skin's joints, then one matrix per unskinned instance, the weights of
/// the instances with targets; a joint matrix is `world(joint) · inverse_bind` and the
/// unskinned instance's its node's world matrix; an unskinned vertex reads its instance's
/// matrix with weight 1; zero weights are dropped; a target without normals has zero normal
/// deltas.
#[test]
fn deform_layout_and_table() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    assert_eq!(poser.deform_matrix_count(), 8 + 1);
    assert_eq!(poser.morph_weight_count(), 2 + 1);
    let (mut matrices, mut weights) = (vec![[9.0; 16]; 30], vec![9.0; 30]);
    poser
        .deform_into(Some(0), 0.6, &mut matrices, &mut weights)
        .unwrap();
    assert_eq!((matrices.len(), weights.len()), (9, 3));
    // The reference's world matrices (the same f64 evaluation `reference` uses).
    let world = |node: usize| -> M4 {
        let mut chain = vec![node];
        while let Some(p) = model.nodes[*chain.last().unwrap()].parent {
            chain.push(p as usize);
        }
        let clip = &model.clips[0];
        chain.iter().rev().fold(IDENTITY, |acc, &n| {
            let local = match model.nodes[n].transform {
                Transform::Matrix(m) => m.map(f64::from),
                Transform::Trs {
                    translation,
                    rotation,
                    scale,
                } => {
                    let mut t = translation.map(f64::from);
                    let mut r = rotation.map(f64::from);
                    let mut s = scale.map(f64::from);
                    for c in clip.channels.iter().filter(|c| c.node as usize == n) {
                        match c.property {
                            Property::Translation => {
                                t.copy_from_slice(&sample(&c.sampler, 0.6, 3, false))
                            }
                            Property::Rotation => {
                                r.copy_from_slice(&sample(&c.sampler, 0.6, 4, true))
                            }
                            Property::Scale => {
                                s.copy_from_slice(&sample(&c.sampler, 0.6, 3, false))
                            }
                            Property::Weights => {}
                            other => panic!("the reference evaluator has no {other:?}"),
                        }
                    }
                    trs(t, r, s)
                }
            };
            mul(&acc, &local)
        })
    };
    let skin = &model.skins[0];
    for (k, &j) in skin.joints.iter().enumerate() {
        let want = mul(&world(j as usize), &skin.inverse_binds[k].map(f64::from));
        for i in 0..16 {
            assert!(
                (f64::from(matrices[k][i]) - want[i]).abs() < 1e-5,
                "joint {k}"
            );
        }
    }
    let want = world(PROP_NODE as usize);
    for i in 0..16 {
        assert!((f64::from(matrices[8][i]) - want[i]).abs() < 1e-5, "prop");
    }
    let table = poser.deform_table();
    assert!(table.slots > 4 && table.slots <= 8, "{}", table.slots);
    let first_prop = model.instances[1].first_vertex as usize;
    assert_eq!(table.matrices[first_prop * table.slots], 8);
    assert_eq!(table.weights[first_prop * table.slots], 1.0);
    assert!(
        table.weights[first_prop * table.slots + 1..(first_prop + 1) * table.slots]
            .iter()
            .all(|&w| w == 0.0)
    );
    assert_eq!(table.morphs[first_prop], [1, 2, 2 * first_prop as u32]);
    // Zero weights dropped: each skinned vertex has as many slots in use as positive weights.
    for v in 0..first_prop {
        let positive: usize = model.instances[0]
            .influences
            .iter()
            .map(|set| set.weights[v].iter().filter(|&&w| w > 0.0).count())
            .sum();
        let used = table.weights[v * table.slots..(v + 1) * table.slots]
            .iter()
            .filter(|&&w| w > 0.0)
            .count();
        assert_eq!(used, positive, "vertex {v}");
        // Target 1 has no normals.
        assert_eq!(table.normal_deltas[2 * v + 1], [0.0; 3]);
        assert_eq!(
            table.position_deltas[2 * v + 1],
            model.instances[0].targets[1].positions[v]
        );
    }
    // Bad arguments: errors, the vectors untouched.
    let before = (matrices.clone(), weights.clone());
    assert!(matches!(
        poser.deform_into(Some(5), 0.0, &mut matrices, &mut weights),
        Err(AnimationError::UnknownClip { .. })
    ));
    assert!(matches!(
        poser.deform_into(Some(0), f32::NAN, &mut matrices, &mut weights),
        Err(AnimationError::BadTime(_))
    ));
    assert_eq!(before, (matrices, weights));
}

#[test]
fn posing_with_given_matrices_is_posing_the_clip_and_bad_ones_are_refused() {
    let poser = Poser::new(tessella_core::samples::animated_creature(0)).unwrap();
    let n = poser.vertex_count();
    let (mut matrices, mut weights) = (Vec::new(), Vec::new());
    for clip in 0..poser.clip_count() {
        poser
            .deform_into(Some(clip), 0.3, &mut matrices, &mut weights)
            .unwrap();
        let (mut p, mut nn) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        poser
            .pose_with(&matrices, &weights, &mut p, Some(&mut nn))
            .unwrap();
        let (want_p, want_n) = poser.pose(Some(clip), 0.3).unwrap();
        assert_eq!(p, want_p);
        assert_eq!(Some(nn), want_n);
    }
    let mut p = vec![[7.0; 3]; n];
    let short = &matrices[..matrices.len() - 1];
    let e = poser.pose_with(short, &weights, &mut p, None).unwrap_err();
    assert!(e.to_string().contains("deform matrices"), "{e}");
    let mut bad = matrices.clone();
    bad[1][5] = f32::NAN;
    let e = poser.pose_with(&bad, &weights, &mut p, None).unwrap_err();
    assert!(
        e.to_string().contains("deform matrix 1 is not finite"),
        "{e}"
    );
    if !weights.is_empty() {
        let mut w = weights.clone();
        w[0] = f32::INFINITY;
        let e = poser.pose_with(&matrices, &w, &mut p, None).unwrap_err();
        assert!(e.to_string().contains("morph weight 0"), "{e}");
    }
    assert!(
        p.iter().all(|v| *v == [7.0; 3]),
        "a refused pose wrote the buffer"
    );
}
