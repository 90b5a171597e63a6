//! Validation of an [`AnimatedMesh`], done once when a [`super::Poser`] is made, so that posing
//! never meets bad data: every index in range, every number finite, every count consistent.

use super::model::{AnimatedMesh, Clip, Instance, Interpolation, Property, Skin, Transform};
use crate::AnimationError;
use glam::DMat4;

/// What validation learns and posing needs.
#[derive(Debug, Clone)]
pub(crate) struct Checked {
    /// Node indices, every parent before its children.
    pub order: Vec<u32>,
    /// The sum of the instances' vertex counts.
    pub vertex_count: usize,
    /// True when every instance has normals.
    pub has_normals: bool,
}

/// Checks `mesh` as [`super::Poser::new`] documents.
pub(crate) fn check(mesh: &AnimatedMesh) -> Result<Checked, AnimationError> {
    let order = check_nodes(mesh)?;
    for (index, skin) in mesh.skins.iter().enumerate() {
        check_skin(index, skin, mesh.nodes.len())?;
    }
    // Morph target count per node, from the instances it draws.
    let mut targets: Vec<Option<(usize, usize)>> = vec![None; mesh.nodes.len()];
    let mut vertex_count = 0usize;
    for (index, instance) in mesh.instances.iter().enumerate() {
        check_instance(mesh, index, instance, vertex_count)?;
        let node = instance.node as usize;
        let count = instance.targets.len();
        match targets[node] {
            Some((first, other)) if other != count => {
                return Err(AnimationError::TargetCountMismatch {
                    node,
                    first,
                    second: index,
                    counts: [other, count],
                });
            }
            Some(_) => {}
            None => targets[node] = Some((index, count)),
        }
        if let Some(weights) = &mesh.nodes[node].weights {
            if weights.len() != count {
                return Err(AnimationError::WeightCount {
                    what: format!("node {node}'s weights (drawing instance {index})"),
                    got: weights.len(),
                    expected: count,
                });
            }
        }
        vertex_count += instance.positions.len();
    }
    if let Some(uvs) = &mesh.uvs {
        if uvs.len() != vertex_count {
            return Err(AnimationError::UvCount {
                got: uvs.len(),
                expected: vertex_count,
            });
        }
    }
    for (face, triangle) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = triangle.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(AnimationError::TriangleIndex {
                face,
                index,
                count: vertex_count,
            });
        }
    }
    for (index, clip) in mesh.clips.iter().enumerate() {
        check_clip(mesh, index, clip, &targets)?;
    }
    Ok(Checked {
        order,
        vertex_count,
        has_normals: mesh.instances.iter().all(|i| i.normals.is_some()),
    })
}

/// Parents in range and without cycles, finite transforms; returns the nodes parents first.
fn check_nodes(mesh: &AnimatedMesh) -> Result<Vec<u32>, AnimationError> {
    let nodes = &mesh.nodes;
    for (node, n) in nodes.iter().enumerate() {
        if let Some(parent) = n.parent {
            if parent as usize >= nodes.len() {
                return Err(AnimationError::ParentOutOfRange {
                    node,
                    parent,
                    nodes: nodes.len(),
                });
            }
        }
        let finite = |what, values: &[f32]| {
            if values.iter().all(|v| v.is_finite()) {
                Ok(())
            } else {
                Err(AnimationError::NonFiniteTransform { node, what })
            }
        };
        match &n.transform {
            Transform::Trs {
                translation,
                rotation,
                scale,
            } => {
                finite("translation", translation)?;
                finite("rotation", rotation)?;
                finite("scale", scale)?;
            }
            Transform::Matrix(m) => finite("matrix", m)?,
        }
        if let Some(weights) = &n.weights {
            finite("morph weights", weights)?;
        }
    }
    // Depth of every node, walking up until a node of known depth; a node met twice on one
    // walk closes a cycle.
    const UNKNOWN: usize = usize::MAX;
    const ON_PATH: usize = usize::MAX - 1;
    let mut depth = vec![UNKNOWN; nodes.len()];
    let mut path = Vec::new();
    for start in 0..nodes.len() {
        let mut node = start;
        let mut base = loop {
            match depth[node] {
                ON_PATH => return Err(AnimationError::ParentCycle { node }),
                UNKNOWN => {}
                known => break known + 1,
            }
            depth[node] = ON_PATH;
            path.push(node);
            match nodes[node].parent {
                Some(parent) => node = parent as usize,
                None => break 0,
            }
        };
        while let Some(node) = path.pop() {
            depth[node] = base;
            base += 1;
        }
    }
    let mut order: Vec<u32> = (0..nodes.len() as u32).collect();
    order.sort_by_key(|&n| depth[n as usize]);
    Ok(order)
}

fn check_skin(index: usize, skin: &Skin, nodes: usize) -> Result<(), AnimationError> {
    if let Some((joint, &node)) = skin
        .joints
        .iter()
        .enumerate()
        .find(|(_, &n)| n as usize >= nodes)
    {
        return Err(AnimationError::JointNodeOutOfRange {
            skin: index,
            joint,
            node,
            nodes,
        });
    }
    if skin.inverse_binds.len() != skin.joints.len() {
        return Err(AnimationError::InverseBindCount {
            skin: index,
            got: skin.inverse_binds.len(),
            expected: skin.joints.len(),
        });
    }
    for (joint, m) in skin.inverse_binds.iter().enumerate() {
        if let Some(reason) = matrix_problem(m) {
            return Err(AnimationError::BadInverseBind {
                skin: index,
                joint,
                reason,
            });
        }
    }
    Ok(())
}

/// Why a column-major matrix cannot be inverted, if it cannot: a non-finite entry, or a
/// determinant that is zero relative to the product of the column lengths (Hadamard's bound,
/// so that the test does not depend on the matrix's scale), computed in f64.
fn matrix_problem(m: &[f32; 16]) -> Option<&'static str> {
    if !m.iter().all(|v| v.is_finite()) {
        return Some("not finite");
    }
    let d = DMat4::from_cols_array(&m.map(f64::from));
    let bound = d.x_axis.length() * d.y_axis.length() * d.z_axis.length() * d.w_axis.length();
    let det = d.determinant();
    // Finite entries make a finite determinant and bound in f64.
    if det.abs() <= 1e-12 * bound || !d.inverse().is_finite() {
        return Some("singular (not invertible)");
    }
    None
}

fn check_instance(
    mesh: &AnimatedMesh,
    index: usize,
    instance: &Instance,
    first: usize,
) -> Result<(), AnimationError> {
    let nodes = mesh.nodes.len();
    if instance.node as usize >= nodes {
        return Err(AnimationError::InstanceNodeOutOfRange {
            instance: index,
            node: instance.node,
            nodes,
        });
    }
    if instance.first_vertex as usize != first {
        return Err(AnimationError::InstanceRange {
            instance: index,
            first_vertex: instance.first_vertex,
            expected: first,
        });
    }
    let count = instance.positions.len();
    let length = |what: String, got: usize| {
        if got == count {
            Ok(())
        } else {
            Err(AnimationError::AttributeLength {
                instance: index,
                what,
                got,
                expected: count,
            })
        }
    };
    let finite = |what: String, values: &[[f32; 3]]| match values
        .iter()
        .position(|v| !v.iter().all(|c| c.is_finite()))
    {
        None => Ok(()),
        Some(vertex) => Err(AnimationError::NonFiniteAttribute {
            instance: index,
            what,
            vertex,
        }),
    };
    finite("position".into(), &instance.positions)?;
    if let Some(normals) = &instance.normals {
        length("normals".into(), normals.len())?;
        finite("normal".into(), normals)?;
    }
    for (t, target) in instance.targets.iter().enumerate() {
        length(
            format!("morph target {t}'s positions"),
            target.positions.len(),
        )?;
        finite(format!("morph target {t}'s position"), &target.positions)?;
        if let Some(normals) = &target.normals {
            length(format!("morph target {t}'s normals"), normals.len())?;
            finite(format!("morph target {t}'s normal"), normals)?;
        }
    }
    if instance.default_weights.len() != instance.targets.len() {
        return Err(AnimationError::WeightCount {
            what: format!("instance {index}'s default weights"),
            got: instance.default_weights.len(),
            expected: instance.targets.len(),
        });
    }
    if !instance.default_weights.iter().all(|w| w.is_finite()) {
        return Err(AnimationError::NonFiniteAttribute {
            instance: index,
            what: "default morph weights".into(),
            vertex: 0,
        });
    }
    for (set, influences) in instance.influences.iter().enumerate() {
        length(
            format!("influence set {set}'s joints"),
            influences.joints.len(),
        )?;
        length(
            format!("influence set {set}'s weights"),
            influences.weights.len(),
        )?;
    }
    let Some(skin) = instance.skin else {
        return Ok(()); // influences without a skin are unused
    };
    let Some(joints) = mesh.skins.get(skin as usize).map(|s| s.joints.len()) else {
        return Err(AnimationError::SkinOutOfRange {
            instance: index,
            skin,
            skins: mesh.skins.len(),
        });
    };
    if instance.influences.is_empty() && count > 0 {
        return Err(AnimationError::NoInfluences {
            instance: index,
            skin,
        });
    }
    for vertex in 0..count {
        let mut sum = 0.0f32;
        for (set, influences) in instance.influences.iter().enumerate() {
            for (&joint, &value) in influences.joints[vertex]
                .iter()
                .zip(&influences.weights[vertex])
            {
                if joint as usize >= joints {
                    return Err(AnimationError::JointOutOfRange {
                        instance: index,
                        vertex,
                        set,
                        joint,
                        skin,
                        joints,
                    });
                }
                if !(value.is_finite() && value >= 0.0) {
                    return Err(AnimationError::BadWeight {
                        instance: index,
                        vertex,
                        set,
                        value,
                    });
                }
                sum += value;
            }
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return Err(AnimationError::ZeroWeights {
                instance: index,
                vertex,
            });
        }
    }
    Ok(())
}

/// The number of components a channel's values have per key, or `None` for a weights channel
/// on a node that draws no mesh.
pub(crate) fn components(property: Property, targets: Option<usize>) -> Option<usize> {
    match property {
        Property::Translation | Property::Scale => Some(3),
        Property::Rotation => Some(4),
        Property::Weights => targets,
    }
}

/// The property's name in messages.
fn property_name(property: Property) -> &'static str {
    match property {
        Property::Translation => "translation",
        Property::Rotation => "rotation",
        Property::Scale => "scale",
        Property::Weights => "weights",
    }
}

fn check_clip(
    mesh: &AnimatedMesh,
    clip: usize,
    c: &Clip,
    targets: &[Option<(usize, usize)>],
) -> Result<(), AnimationError> {
    let clip_name = || c.name.clone();
    for (channel, ch) in c.channels.iter().enumerate() {
        let node = ch.node as usize;
        let Some(n) = mesh.nodes.get(node) else {
            return Err(AnimationError::ChannelNode {
                clip,
                clip_name: clip_name(),
                channel,
                node: ch.node,
                nodes: mesh.nodes.len(),
            });
        };
        if ch.property != Property::Weights && matches!(n.transform, Transform::Matrix(_)) {
            return Err(AnimationError::ChannelOnMatrix {
                clip,
                clip_name: clip_name(),
                channel,
                node,
                property: property_name(ch.property),
            });
        }
        let Some(components) = components(ch.property, targets[node].map(|(_, count)| count))
        else {
            return Err(AnimationError::WeightsWithoutMesh {
                clip,
                clip_name: clip_name(),
                channel,
                node,
            });
        };
        let s = &ch.sampler;
        if s.times.is_empty() {
            return Err(AnimationError::NoKeys {
                clip,
                clip_name: clip_name(),
                channel,
            });
        }
        for (key, &time) in s.times.iter().enumerate() {
            let reason = if !time.is_finite() {
                "not finite"
            } else if key > 0 && time <= s.times[key - 1] {
                "not greater than the key before"
            } else {
                continue;
            };
            return Err(AnimationError::BadKeyTime {
                clip,
                clip_name: clip_name(),
                channel,
                key,
                time,
                reason,
            });
        }
        let cubic = s.interpolation == Interpolation::CubicSpline;
        let expected = s.times.len() * components * if cubic { 3 } else { 1 };
        if s.values.len() != expected {
            return Err(AnimationError::ValueCount {
                clip,
                clip_name: clip_name(),
                channel,
                got: s.values.len(),
                keys: s.times.len(),
                components,
                cubic,
                expected,
            });
        }
        if let Some(index) = s.values.iter().position(|v| !v.is_finite()) {
            return Err(AnimationError::NonFiniteValue {
                clip,
                clip_name: clip_name(),
                channel,
                index,
            });
        }
    }
    Ok(())
}
