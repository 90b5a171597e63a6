//! Node transforms at a moment of a clip: each node's local transform (its stored one, with
//! the clip's channels sampled over it), then world matrices down the hierarchy
//! (`world = world(parent) · local`), and the nodes' morph weights.

use super::model::{AnimatedMesh, Clip, Interpolation, Property, Transform};
use super::sample::sample;
use glam::{Mat4, Quat, Vec3, Vec4};

/// Every node's world matrix and morph weights at one moment.
pub(crate) struct NodeState {
    pub world: Vec<Mat4>,
    /// The node's weights: animated, else `node.weights`, else `None`.
    pub weights: Vec<Option<Vec<f32>>>,
}

/// A node's local transform while it is being animated.
#[derive(Clone, Copy)]
enum Local {
    Trs([f32; 3], [f32; 4], [f32; 3]),
    Matrix(Mat4),
}

/// Poses the nodes of a validated `mesh`; `order` lists parents before children, `clip` is
/// `None` for the rest pose.
pub(crate) fn node_state(
    mesh: &AnimatedMesh,
    order: &[u32],
    clip: Option<&Clip>,
    time: f32,
) -> NodeState {
    let mut locals: Vec<Local> = mesh
        .nodes
        .iter()
        .map(|n| match n.transform {
            Transform::Trs {
                translation,
                rotation,
                scale,
            } => Local::Trs(translation, rotation, scale),
            Transform::Matrix(m) => Local::Matrix(Mat4::from_cols_array(&m)),
        })
        .collect();
    let mut weights: Vec<Option<Vec<f32>>> = mesh.nodes.iter().map(|n| n.weights.clone()).collect();
    for channel in clip.iter().flat_map(|c| &c.channels) {
        let node = channel.node as usize;
        if channel.property == Property::Weights {
            // Validation made the sampler's component count the node's target count.
            let s = &channel.sampler;
            let per_key = if s.interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            let count = s.values.len() / (s.times.len() * per_key);
            let mut out = vec![0.0; count];
            sample(&channel.sampler, time, false, &mut out);
            weights[node] = Some(out);
            continue;
        }
        // Validation refused T/R/S channels on matrix nodes.
        if let Local::Trs(t, r, s) = &mut locals[node] {
            match channel.property {
                Property::Translation => sample(&channel.sampler, time, false, t),
                Property::Rotation => sample(&channel.sampler, time, true, r),
                Property::Scale => sample(&channel.sampler, time, false, s),
                Property::Weights => {}
            }
        }
    }
    let mut world = vec![Mat4::IDENTITY; mesh.nodes.len()];
    for &node in order {
        let node = node as usize;
        let local = match locals[node] {
            Local::Trs(t, r, s) => Mat4::from_scale_rotation_translation(
                Vec3::from(s),
                Vec4::from_array(r)
                    .try_normalize()
                    .map_or(Quat::IDENTITY, Quat::from_vec4),
                Vec3::from(t),
            ),
            Local::Matrix(m) => m,
        };
        world[node] = match mesh.nodes[node].parent {
            Some(parent) => world[parent as usize] * local,
            None => local,
        };
    }
    NodeState { world, weights }
}
