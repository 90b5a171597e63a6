//! Reads a glTF 2.0 file's animation data into a [`tessella_core::animation::AnimatedMesh`]:
//! the data posing needs, not posed (the core poses it).
//!
//! What is read (glTF 2.0 specification, sections 3.5 "Nodes and Hierarchy", 3.7 "Meshes",
//! 3.7.2.2 "Morph Targets", 3.7.3 "Skins", 3.11 "Animations", 3.6.2.3 "Sparse Accessors"):
//!
//! - Every node of the file, in the file's order: its name, its parent (from the nodes'
//!   `children`; a node with two parents or a cycle is an error), its transform as stored
//!   (`matrix` or `translation`/`rotation`/`scale`) and its `weights`.
//! - Every skin: its joints, inverse bind matrices (the identity for each joint where the file
//!   gives no accessor; extra matrices are ignored) and `skeleton`.
//! - One [`Instance`] per node with a mesh, for the nodes of the default scene (or the first
//!   scene; every node if the file has no scene) in the order [`super::read()`] takes them. Its
//!   triangle primitives are merged as [`super::read()`] merges them (same modes, indices and
//!   checks), with positions and normals in the mesh's own space, untransformed; their
//!   triangles, offset by the instance's `first_vertex`, go to [`AnimatedMesh::triangles`].
//!   NORMAL is kept only if every primitive has it, TEXCOORD_0 (flipped to the OBJ/PLY
//!   convention, see [`super`]) only if every primitive of every instance has it.
//! - `JOINTS_n`/`WEIGHTS_n` for n = 0, 1, ... while both are present: joints u8 or u16, weights
//!   f32 or normalised u8/u16 (`c / 255`, `c / 65535`). Primitives with fewer sets than others
//!   get zero weights in the missing ones. They are kept only for a node with a skin.
//! - Morph targets: POSITION and NORMAL displacements (zeros for a primitive whose target lacks
//!   one; a target's normals only where the instance has normals); TANGENT is ignored. The
//!   mesh's `weights` are the default weights (zeros where absent). Every primitive of a mesh
//!   must have the same number of targets.
//! - Every animation as a [`Clip`] named by the animation's name, else `animation N`: per
//!   channel the target node, the path, the sampler's interpolation, its input times (f32) and
//!   its output values flattened to f32; rotations and weights stored as normalised i8, u8,
//!   i16 or u16 are converted as the specification says (`max(c / 127, -1)`, `c / 255`,
//!   `max(c / 32767, -1)`, `c / 65535`).
//!
//! Sparse accessors and accessors without a buffer view (zeros, then the sparse values) are
//! accepted for every accessor read here. Structural problems are [`IoError::Parse`] or
//! [`IoError::Unsupported`] naming the mesh, skin, animation or accessor: indices out of range,
//! component types or dimensions the specification does not allow, counts that do not match
//! the vertex or key count, JOINTS without WEIGHTS, a channel target node that does not exist.
//! Semantic checks (weights that sum to zero, times that do not increase, joint indices past
//! the skin, matrices that cannot be inverted, an animated node with a matrix) are left to the
//! core's validation of the animated mesh.

use super::data::{check_accessor, Buffers};
use super::read::{merge_attribute, open, read_primitive, scene_nodes, Context, Primitive};
use crate::IoError;
use gltf::accessor::{DataType, Dimensions, Item};
use gltf::animation::Property as GltfProperty;
use gltf::Accessor;
use std::path::Path;
use tessella_core::animation::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Property,
    Sampler, Skin, Transform,
};

/// The column-major 4×4 identity.
const IDENTITY: [f32; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

/// Component types allowed for rotations and morph target weights (float or normalised).
const UNIT_TYPES: [DataType; 5] = [
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

/// Reads a `.gltf` or `.glb` file held in memory as an animated mesh: nodes, skins, mesh
/// instances in their own space, morph targets, joint influences and clips (see the module
/// docs). External buffers come from `buffers`. Structural problems are errors naming the
/// file and the part; semantic ones are for the core's validation (not called here).
pub fn read_animated(
    path: &Path,
    bytes: &[u8],
    format: &'static str,
    buffers: Buffers<'_>,
) -> Result<AnimatedMesh, IoError> {
    let ctx = Context { path, format };
    let (document, buffers) = open(path, bytes, format, buffers)?;
    let mut mesh = AnimatedMesh {
        nodes: read_nodes(ctx, &document)?,
        skins: read_skins(ctx, &document, &buffers)?,
        ..AnimatedMesh::default()
    };
    let shown: Vec<gltf::Node> = match scene_nodes(&document).map_err(|m| ctx.parse(m))? {
        Some(nodes) => nodes.into_iter().map(|(node, _)| node).collect(),
        None => document.nodes().collect(),
    };
    let mut uvs = Some(Vec::new());
    for node in &shown {
        if let Some(gltf_mesh) = node.mesh() {
            read_instance(ctx, node, &gltf_mesh, &buffers, &mut mesh, &mut uvs)?;
        }
    }
    if mesh.triangles.is_empty() {
        return Err(IoError::NoTriangles {
            path: path.to_path_buf(),
        });
    }
    mesh.uvs = uvs;
    mesh.clips = read_clips(ctx, &document, &buffers)?;
    Ok(mesh)
}

/// Every node, with its parent found from the nodes' children.
fn read_nodes(ctx: Context<'_>, document: &gltf::Document) -> Result<Vec<Node>, IoError> {
    let count = document.nodes().len();
    let mut parents: Vec<Option<usize>> = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            if let Some(other) = parents[child.index()].replace(node.index()) {
                return Err(ctx.parse(format!(
                    "node {} is a child of both node {other} and node {}",
                    child.index(),
                    node.index()
                )));
            }
        }
    }
    // Each node is walked up to a root once: 1 on the current path, 2 known to reach a root.
    let mut state = vec![0u8; count];
    for start in 0..count {
        let mut path = Vec::new();
        let mut at = Some(start);
        while let Some(node) = at.filter(|&n| state[n] != 2) {
            if state[node] == 1 {
                return Err(ctx.parse(format!(
                    "node {node} is its own ancestor (the node hierarchy has a cycle)"
                )));
            }
            state[node] = 1;
            path.push(node);
            at = parents[node];
        }
        for node in path {
            state[node] = 2;
        }
    }
    Ok(document
        .nodes()
        .map(|node| Node {
            name: node.name().map(str::to_owned),
            parent: parents[node.index()].map(|p| p as u32),
            transform: match node.transform() {
                gltf::scene::Transform::Matrix { matrix } => {
                    Transform::Matrix(*matrix.as_flattened().first_chunk().unwrap_or(&IDENTITY))
                }
                gltf::scene::Transform::Decomposed {
                    translation,
                    rotation,
                    scale,
                } => Transform::Trs {
                    translation,
                    rotation,
                    scale,
                },
            },
            weights: node.weights().map(<[f32]>::to_vec),
        })
        .collect())
}

/// Every skin, with identity inverse bind matrices where the file gives none.
fn read_skins(
    ctx: Context<'_>,
    document: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<Vec<Skin>, IoError> {
    let mut skins = Vec::new();
    for skin in document.skins() {
        let joints: Vec<u32> = skin.joints().map(|j| j.index() as u32).collect();
        let inverse_binds = match skin.inverse_bind_matrices() {
            None => vec![IDENTITY; joints.len()],
            Some(accessor) => {
                let what = format!("skin {} inverseBindMatrices", skin.index());
                let values = floats(
                    ctx,
                    &accessor,
                    Dimensions::Mat4,
                    &[DataType::F32],
                    &what,
                    buffers,
                )?;
                if accessor.count() < joints.len() {
                    return Err(ctx.parse(format!(
                        "{what}: accessor {} has {} matrices for {} joints",
                        accessor.index(),
                        accessor.count(),
                        joints.len()
                    )));
                }
                values
                    .chunks_exact(16)
                    .take(joints.len())
                    .map(|m| *m.first_chunk().unwrap_or(&IDENTITY))
                    .collect()
            }
        };
        skins.push(Skin {
            name: skin.name().map(str::to_owned),
            joints,
            inverse_binds,
            skeleton: skin.skeleton().map(|n| n.index() as u32),
        });
    }
    Ok(skins)
}

/// The number of morph targets of a mesh: the same for every primitive.
fn target_count(ctx: Context<'_>, mesh: &gltf::Mesh<'_>) -> Result<usize, IoError> {
    let mut counts = mesh
        .primitives()
        .map(|p| (p.index(), p.morph_targets().len()));
    let Some((_, first)) = counts.next() else {
        return Ok(0);
    };
    match counts.find(|&(_, count)| count != first) {
        Some((p, count)) => Err(ctx.parse(format!(
            "mesh {} primitive {p} has {count} morph targets but primitive 0 has {first}",
            mesh.index()
        ))),
        None => Ok(first),
    }
}

/// Appends one node's mesh as an instance.
fn read_instance(
    ctx: Context<'_>,
    node: &gltf::Node<'_>,
    mesh: &gltf::Mesh<'_>,
    buffers: &[Vec<u8>],
    out: &mut AnimatedMesh,
    uvs: &mut Option<Vec<[f32; 2]>>,
) -> Result<(), IoError> {
    let targets = target_count(ctx, mesh)?;
    let default_weights = match mesh.weights() {
        Some(weights) if weights.len() != targets => {
            return Err(ctx.parse(format!(
                "mesh {} has {} weights for {targets} morph targets",
                mesh.index(),
                weights.len()
            )))
        }
        Some(weights) => weights.to_vec(),
        None => vec![0.0; targets],
    };
    let first_vertex = out
        .instances
        .last()
        .map_or(0, |i| i.first_vertex as usize + i.positions.len());
    let mut instance = Instance {
        node: node.index() as u32,
        skin: node.skin().map(|s| s.index() as u32),
        first_vertex: first_vertex as u32,
        normals: Some(Vec::new()),
        targets: vec![MorphTarget::default(); targets],
        default_weights,
        ..Instance::default()
    };
    for primitive in mesh.primitives() {
        let what = format!("mesh {} primitive {}", mesh.index(), primitive.index());
        let Some(Primitive {
            positions,
            normals,
            uvs: primitive_uvs,
            triangles,
        }) = read_primitive(ctx, &primitive, &what, buffers, true)?
        else {
            continue;
        };
        let (before, n) = (instance.positions.len(), positions.len());
        let base = first_vertex + before;
        if base + n > u32::MAX as usize {
            return Err(ctx.parse("more than 4294967295 vertices in all".into()));
        }
        out.triangles
            .extend(triangles.iter().map(|t| t.map(|i| i + base as u32)));
        instance.positions.extend(positions);
        merge_attribute(&mut instance.normals, normals);
        merge_attribute(uvs, primitive_uvs);
        for (t, target) in primitive.morph_targets().enumerate() {
            let merged = &mut instance.targets[t];
            let what = format!("{what} target {t}");
            let positions = match target.positions() {
                Some(a) => vectors(ctx, &a, &format!("{what} POSITION"), n, buffers)?,
                None => vec![[0.0; 3]; n],
            };
            merged.positions.extend(positions);
            match target.normals() {
                Some(a) => {
                    let normals = vectors(ctx, &a, &format!("{what} NORMAL"), n, buffers)?;
                    merged
                        .normals
                        .get_or_insert_with(|| vec![[0.0; 3]; before])
                        .extend(normals);
                }
                None => {
                    if let Some(normals) = &mut merged.normals {
                        normals.extend(std::iter::repeat_n([0.0; 3], n));
                    }
                }
            }
        }
        let sets = influences(ctx, &primitive, &what, n, buffers)?;
        while instance.influences.len() < sets.len() {
            instance.influences.push(Influences {
                joints: vec![[0; 4]; before],
                weights: vec![[0.0; 4]; before],
            });
        }
        let mut sets = sets.into_iter();
        for merged in &mut instance.influences {
            let set = sets.next().unwrap_or_else(|| Influences {
                joints: vec![[0; 4]; n],
                weights: vec![[0.0; 4]; n],
            });
            merged.joints.extend(set.joints);
            merged.weights.extend(set.weights);
        }
    }
    if instance.positions.is_empty() {
        return Ok(()); // points or lines only
    }
    if instance.normals.is_none() {
        for target in &mut instance.targets {
            target.normals = None;
        }
    }
    if instance.skin.is_none() {
        instance.influences.clear();
    }
    out.instances.push(instance);
    Ok(())
}

/// A primitive's `JOINTS_n`/`WEIGHTS_n` sets, n = 0, 1, ... while both are present.
fn influences(
    ctx: Context<'_>,
    primitive: &gltf::Primitive<'_>,
    what: &str,
    n: usize,
    buffers: &[Vec<u8>],
) -> Result<Vec<Influences>, IoError> {
    use gltf::Semantic::{Joints, Weights};
    let mut sets = Vec::new();
    for set in 0u32.. {
        let (joints, weights) = match (primitive.get(&Joints(set)), primitive.get(&Weights(set))) {
            (None, None) => break,
            (Some(joints), Some(weights)) => (joints, weights),
            (joints, _) => {
                let (has, lacks) = match joints {
                    Some(_) => ("JOINTS", "WEIGHTS"),
                    None => ("WEIGHTS", "JOINTS"),
                };
                return Err(ctx.parse(format!("{what} has {has}_{set} without {lacks}_{set}")));
            }
        };
        let name = format!("{what} JOINTS_{set}");
        check_accessor(
            &joints,
            Dimensions::Vec4,
            &[DataType::U8, DataType::U16],
            buffers,
            true,
        )
        .map_err(|m| ctx.unsupported(format!("{name}: {m}")))?;
        let joint_values: Vec<[u16; 4]> = match joints.data_type() {
            DataType::U8 => read::<[u8; 4]>(&joints, buffers)
                .into_iter()
                .map(|j| j.map(u16::from))
                .collect(),
            _ => read::<[u16; 4]>(&joints, buffers),
        };
        count_matches(ctx, &name, &joints, joint_values.len(), n)?;
        let name = format!("{what} WEIGHTS_{set}");
        let types = [DataType::F32, DataType::U8, DataType::U16];
        let weight_values = floats(ctx, &weights, Dimensions::Vec4, &types, &name, buffers)?;
        count_matches(ctx, &name, &weights, weight_values.len() / 4, n)?;
        sets.push(Influences {
            joints: joint_values,
            weights: weight_values
                .chunks_exact(4)
                .map(|w| [w[0], w[1], w[2], w[3]])
                .collect(),
        });
    }
    Ok(sets)
}

/// A morph target's VEC3 f32 displacements, one per vertex.
fn vectors(
    ctx: Context<'_>,
    accessor: &Accessor<'_>,
    what: &str,
    n: usize,
    buffers: &[Vec<u8>],
) -> Result<Vec<[f32; 3]>, IoError> {
    let values = floats(
        ctx,
        accessor,
        Dimensions::Vec3,
        &[DataType::F32],
        what,
        buffers,
    )?;
    count_matches(ctx, what, accessor, values.len() / 3, n)?;
    Ok(values.chunks_exact(3).map(|v| [v[0], v[1], v[2]]).collect())
}

fn count_matches(
    ctx: Context<'_>,
    what: &str,
    accessor: &Accessor<'_>,
    got: usize,
    n: usize,
) -> Result<(), IoError> {
    if got == n {
        return Ok(());
    }
    Err(ctx.parse(format!(
        "{what}: accessor {} has {got} values for {n} positions",
        accessor.index()
    )))
}

/// Every animation as a clip.
fn read_clips(
    ctx: Context<'_>,
    document: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<Vec<Clip>, IoError> {
    let mut clips = Vec::new();
    for animation in document.animations() {
        let a = animation.index();
        let mut clip = Clip {
            name: animation
                .name()
                .map_or_else(|| format!("animation {a}"), str::to_owned),
            channels: Vec::new(),
        };
        for channel in animation.channels() {
            let c = channel.index();
            let what = format!("animation {a} channel {c}");
            // The `gltf` crate's validation skips channel targets, and its accessors unwrap
            // them (a panic for a node past the end or an unknown path).
            let target = &document.as_json().animations[a].channels[c].target;
            let nodes = document.nodes().len();
            if target.node.value() >= nodes {
                return Err(ctx.parse(format!(
                    "{what} targets node {}, but the file has only {nodes} nodes",
                    target.node.value()
                )));
            }
            let gltf::json::validation::Checked::Valid(path) = target.path else {
                return Err(ctx.parse(format!(
                    "{what} targets a path other than translation, rotation, scale or weights"
                )));
            };
            let node = channel.target().node();
            let (property, dimensions, types, width): (_, _, &[DataType], _) = match path {
                GltfProperty::Translation => {
                    (Property::Translation, Dimensions::Vec3, &[DataType::F32], 3)
                }
                GltfProperty::Scale => (Property::Scale, Dimensions::Vec3, &[DataType::F32], 3),
                GltfProperty::Rotation => (Property::Rotation, Dimensions::Vec4, &UNIT_TYPES, 4),
                GltfProperty::MorphTargetWeights => {
                    let Some(mesh) = node.mesh() else {
                        return Err(ctx.parse(format!(
                            "{what} animates the weights of node {}, which has no mesh",
                            node.index()
                        )));
                    };
                    let targets = target_count(ctx, &mesh)?;
                    if targets == 0 {
                        return Err(ctx.parse(format!(
                            "{what} animates the weights of node {}, whose mesh {} has no \
                                 morph targets",
                            node.index(),
                            mesh.index()
                        )));
                    }
                    (Property::Weights, Dimensions::Scalar, &UNIT_TYPES, targets)
                }
            };
            let sampler = channel.sampler();
            let interpolation = match sampler.interpolation() {
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let (input, output) = (sampler.input(), sampler.output());
            let times = floats(
                ctx,
                &input,
                Dimensions::Scalar,
                &[DataType::F32],
                &format!("{what} input"),
                buffers,
            )?;
            let values = floats(
                ctx,
                &output,
                dimensions,
                types,
                &format!("{what} output"),
                buffers,
            )?;
            // Elements of the output accessor per key: VEC3/VEC4 one, weights one per target,
            // three times that for a cubic spline (in-tangent, value, out-tangent).
            let per_key = match property {
                Property::Weights => width,
                _ => 1,
            } * match interpolation {
                Interpolation::CubicSpline => 3,
                _ => 1,
            };
            if times.len().checked_mul(per_key) != Some(output.count()) {
                return Err(ctx.parse(format!(
                    "{what}: output accessor {} has {} values for {} keys (expected {})",
                    output.index(),
                    output.count(),
                    times.len(),
                    times.len().saturating_mul(per_key)
                )));
            }
            debug_assert_eq!(values.len(), output.count() * dimensions.multiplicity());
            clip.channels.push(Channel {
                node: node.index() as u32,
                property,
                sampler: Sampler {
                    interpolation,
                    times,
                    values,
                },
            });
        }
        clips.push(clip);
    }
    Ok(clips)
}

/// An accessor's components as floats, flattened, after checking its type and extent;
/// normalised integers are converted as glTF 2.0 section 3.11 says.
fn floats(
    ctx: Context<'_>,
    accessor: &Accessor<'_>,
    dimensions: Dimensions,
    types: &[DataType],
    what: &str,
    buffers: &[Vec<u8>],
) -> Result<Vec<f32>, IoError> {
    check_accessor(accessor, dimensions, types, buffers, true)
        .map_err(|m| ctx.unsupported(format!("{what}: {m}")))?;
    let values = match accessor.data_type() {
        DataType::I8 => units::<i8>(accessor, buffers),
        DataType::U8 => units::<u8>(accessor, buffers),
        DataType::I16 => units::<i16>(accessor, buffers),
        DataType::U16 => units::<u16>(accessor, buffers),
        DataType::F32 => units::<f32>(accessor, buffers),
        DataType::U32 => Vec::new(), // never asked for
    };
    let expected = accessor.count() * dimensions.multiplicity();
    if values.len() != expected {
        return Err(ctx.parse(format!(
            "{what}: accessor {} gave {} of its {expected} components",
            accessor.index(),
            values.len()
        )));
    }
    Ok(values)
}

/// A component type whose values become floats: itself, or a normalised integer.
trait Unit: Item + Copy {
    fn unit(self) -> f32;
}

impl Unit for f32 {
    fn unit(self) -> f32 {
        self
    }
}

impl Unit for i8 {
    fn unit(self) -> f32 {
        (f32::from(self) / 127.0).max(-1.0)
    }
}

impl Unit for u8 {
    fn unit(self) -> f32 {
        f32::from(self) / 255.0
    }
}

impl Unit for i16 {
    fn unit(self) -> f32 {
        (f32::from(self) / 32767.0).max(-1.0)
    }
}

impl Unit for u16 {
    fn unit(self) -> f32 {
        f32::from(self) / 65535.0
    }
}

/// Reads an accessor of `T` components of any dimensions the animated reader uses, flattened.
fn units<T: Unit>(accessor: &Accessor<'_>, buffers: &[Vec<u8>]) -> Vec<f32> {
    let unit = |values: &[T]| values.iter().map(|&v| v.unit()).collect::<Vec<f32>>();
    match accessor.dimensions().multiplicity() {
        1 => unit(&read::<T>(accessor, buffers)),
        3 => read::<[T; 3]>(accessor, buffers)
            .iter()
            .flat_map(|v| unit(v))
            .collect(),
        4 => read::<[T; 4]>(accessor, buffers)
            .iter()
            .flat_map(|v| unit(v))
            .collect(),
        16 => read::<[[T; 4]; 4]>(accessor, buffers)
            .iter()
            .flat_map(|m| unit(m.as_flattened()))
            .collect(),
        _ => Vec::new(),
    }
}

/// Reads an accessor checked by [`check_accessor`] (sparse or not).
fn read<T: Item>(accessor: &Accessor<'_>, buffers: &[Vec<u8>]) -> Vec<T> {
    gltf::accessor::Iter::<T>::new(accessor.clone(), |b| {
        buffers.get(b.index()).map(Vec::as_slice)
    })
    .map(Iterator::collect)
    .unwrap_or_default()
}
