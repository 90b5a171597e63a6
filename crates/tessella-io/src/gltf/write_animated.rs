//! Writes an [`AnimatedMesh`] as glTF 2.0: its nodes (with their hierarchy), one mesh per
//! instance with its morph targets and joint influences, its skins and its clips as
//! animations. The buffer is assembled in memory: an animated mesh is a coarse mesh, small
//! beside the refined ones the streaming writers are for.

use super::flip_v;
use super::write::{embedded_uri, write_glb_header, write_glb_padding, write_gltf_text};
use serde_json::{json, Map, Value};
use std::io::Write;
use tessella_core::animation::{AnimatedMesh, Interpolation, Property, Transform};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;

/// One buffer, its views and their accessors, filled as the document is built.
#[derive(Default)]
struct Packer {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Packer {
    /// Adds `data` as a view (4-byte aligned) read by `accessor`; returns the accessor's index.
    fn push(&mut self, data: &[u8], target: Option<u32>, mut accessor: Value) -> usize {
        self.bytes.resize(self.bytes.len().next_multiple_of(4), 0);
        let mut view =
            json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": data.len()});
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.bytes.extend_from_slice(data);
        self.views.push(view);
        accessor["bufferView"] = json!(self.views.len() - 1);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Float records of `N` components as accessor `kind` ("SCALAR", "VEC3", ...), with their
    /// component-wise `min` and `max` when `bounds` (glTF requires them for POSITION, morph
    /// target positions and animation inputs).
    fn floats<const N: usize>(
        &mut self,
        records: &[[f32; N]],
        kind: &str,
        target: Option<u32>,
        bounds: bool,
    ) -> usize {
        let mut accessor = json!({"componentType": FLOAT, "count": records.len(), "type": kind});
        if bounds && !records.is_empty() {
            let mut lo = [f32::INFINITY; N];
            let mut hi = [f32::NEG_INFINITY; N];
            for r in records {
                for k in 0..N {
                    lo[k] = lo[k].min(r[k]);
                    hi[k] = hi[k].max(r[k]);
                }
            }
            accessor["min"] = json!(lo.to_vec());
            accessor["max"] = json!(hi.to_vec());
        }
        let bytes: Vec<u8> = records
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        self.push(&bytes, target, accessor)
    }
}

fn invalid(message: String) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidInput, message)
}

/// The document and its buffer's bytes.
fn document(mesh: &AnimatedMesh, uri: Option<String>) -> std::io::Result<(Value, Vec<u8>)> {
    let mut packer = Packer::default();
    let node_count = mesh.nodes.len();
    let mut node_mesh: Vec<Option<(usize, Option<u32>)>> = vec![None; node_count];
    let mut meshes = Vec::new();
    for (i, instance) in mesh.instances.iter().enumerate() {
        let slot = node_mesh.get_mut(instance.node as usize).ok_or_else(|| {
            invalid(format!(
                "instance {i} is drawn by node {}, but there are {node_count} nodes",
                instance.node
            ))
        })?;
        if slot.is_some() {
            return Err(invalid(format!(
                "node {} draws two instances; a glTF node has one mesh",
                instance.node
            )));
        }
        *slot = Some((meshes.len(), instance.skin));
        let first = instance.first_vertex;
        let end = first as u64 + instance.positions.len() as u64;
        let inside = |v: u32| (first as u64..end).contains(&(v as u64));
        let triangles: Vec<u32> = mesh
            .triangles
            .iter()
            .filter(|t| inside(t[0]))
            .flat_map(|t| t.map(|v| v - first))
            .collect();
        if let Some(t) = mesh
            .triangles
            .iter()
            .find(|t| inside(t[0]) && !t.iter().all(|&v| inside(v)))
        {
            return Err(invalid(format!(
                "triangle {t:?} joins instance {i} to another; glTF primitives cannot share vertices"
            )));
        }
        let mut attributes = Map::new();
        let position = packer.floats(&instance.positions, "VEC3", Some(ARRAY_BUFFER), true);
        attributes.insert("POSITION".into(), json!(position));
        if let Some(normals) = &instance.normals {
            let normal = packer.floats(normals, "VEC3", Some(ARRAY_BUFFER), false);
            attributes.insert("NORMAL".into(), json!(normal));
        }
        if let Some(uvs) = &mesh.uvs {
            let range = first as usize..end as usize;
            let flipped: Vec<[f32; 2]> = uvs
                .get(range)
                .ok_or_else(|| invalid(format!("instance {i} has vertices past the uvs")))?
                .iter()
                .map(|&uv| flip_v(uv))
                .collect();
            let uv = packer.floats(&flipped, "VEC2", Some(ARRAY_BUFFER), false);
            attributes.insert("TEXCOORD_0".into(), json!(uv));
        }
        for (set, influences) in instance.influences.iter().enumerate() {
            let joints: Vec<u8> = influences
                .joints
                .iter()
                .flatten()
                .flat_map(|j| j.to_le_bytes())
                .collect();
            let accessor = json!({"componentType": UNSIGNED_SHORT, "count": influences.joints.len(), "type": "VEC4"});
            let joints = packer.push(&joints, Some(ARRAY_BUFFER), accessor);
            let weights = packer.floats(&influences.weights, "VEC4", Some(ARRAY_BUFFER), false);
            attributes.insert(format!("JOINTS_{set}"), json!(joints));
            attributes.insert(format!("WEIGHTS_{set}"), json!(weights));
        }
        let targets: Vec<Value> = instance
            .targets
            .iter()
            .map(|target| {
                let mut t = Map::new();
                let p = packer.floats(&target.positions, "VEC3", Some(ARRAY_BUFFER), true);
                t.insert("POSITION".into(), json!(p));
                if let Some(normals) = &target.normals {
                    let n = packer.floats(normals, "VEC3", Some(ARRAY_BUFFER), false);
                    t.insert("NORMAL".into(), json!(n));
                }
                Value::Object(t)
            })
            .collect();
        let index_bytes: Vec<u8> = triangles.iter().flat_map(|v| v.to_le_bytes()).collect();
        let indices = packer.push(
            &index_bytes,
            Some(ELEMENT_ARRAY_BUFFER),
            json!({"componentType": UNSIGNED_INT, "count": triangles.len(), "type": "SCALAR"}),
        );
        let mut primitive = json!({"attributes": attributes, "indices": indices, "mode": 4});
        if !targets.is_empty() {
            primitive["targets"] = json!(targets);
        }
        let mut m = json!({"primitives": [primitive]});
        if !instance.default_weights.is_empty() {
            m["weights"] = json!(instance.default_weights);
        }
        meshes.push(m);
    }

    let mut children: Vec<Vec<usize>> = vec![Vec::new(); node_count];
    let mut roots = Vec::new();
    for (i, node) in mesh.nodes.iter().enumerate() {
        match node.parent {
            Some(p) if (p as usize) < node_count => children[p as usize].push(i),
            Some(p) => return Err(invalid(format!("node {i}'s parent {p} does not exist"))),
            None => roots.push(i),
        }
    }
    let nodes: Vec<Value> = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, node)| {
            let mut n = Map::new();
            if let Some(name) = &node.name {
                n.insert("name".into(), json!(name));
            }
            if !children[i].is_empty() {
                n.insert("children".into(), json!(children[i]));
            }
            match node.transform {
                Transform::Trs {
                    translation,
                    rotation,
                    scale,
                } => {
                    n.insert("translation".into(), json!(translation));
                    n.insert("rotation".into(), json!(rotation));
                    n.insert("scale".into(), json!(scale));
                }
                Transform::Matrix(m) => {
                    n.insert("matrix".into(), json!(m.to_vec()));
                }
            }
            if let Some((m, skin)) = node_mesh[i] {
                n.insert("mesh".into(), json!(m));
                if let Some(skin) = skin {
                    n.insert("skin".into(), json!(skin));
                }
            }
            if let Some(weights) = &node.weights {
                n.insert("weights".into(), json!(weights));
            }
            Value::Object(n)
        })
        .collect();

    let skins: Vec<Value> = mesh
        .skins
        .iter()
        .map(|skin| {
            let binds = packer.floats(&skin.inverse_binds, "MAT4", None, false);
            let mut s = json!({"joints": skin.joints, "inverseBindMatrices": binds});
            if let Some(name) = &skin.name {
                s["name"] = json!(name);
            }
            if let Some(skeleton) = skin.skeleton {
                s["skeleton"] = json!(skeleton);
            }
            s
        })
        .collect();

    let mut animations = Vec::new();
    for clip in &mesh.clips {
        let (mut samplers, mut channels) = (Vec::new(), Vec::new());
        for channel in &clip.channels {
            let times: Vec<[f32; 1]> = channel.sampler.times.iter().map(|&t| [t]).collect();
            let input = packer.floats(&times, "SCALAR", None, true);
            let (kind, path) = match channel.property {
                Property::Translation => ("VEC3", "translation"),
                Property::Rotation => ("VEC4", "rotation"),
                Property::Scale => ("VEC3", "scale"),
                Property::Weights => ("SCALAR", "weights"),
                other => {
                    return Err(invalid(format!(
                        "clip {:?} animates {other:?}, which this writer cannot write",
                        clip.name
                    )))
                }
            };
            let values = &channel.sampler.values;
            let output = match kind {
                "VEC3" => packer.floats(&chunks::<3>(values), kind, None, false),
                "VEC4" => packer.floats(&chunks::<4>(values), kind, None, false),
                _ => packer.floats(&chunks::<1>(values), kind, None, false),
            };
            let interpolation = match channel.sampler.interpolation {
                Interpolation::Linear => "LINEAR",
                Interpolation::Step => "STEP",
                Interpolation::CubicSpline => "CUBICSPLINE",
            };
            samplers
                .push(json!({"input": input, "output": output, "interpolation": interpolation}));
            channels.push(json!({"sampler": samplers.len() - 1, "target": {"node": channel.node, "path": path}}));
        }
        animations.push(json!({"name": clip.name, "samplers": samplers, "channels": channels}));
    }

    let mut buffer = json!({"byteLength": packer.bytes.len()});
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": "tessella"},
        "scene": 0,
        "scenes": [{"nodes": roots}],
        "nodes": nodes,
        "meshes": meshes,
        "buffers": [buffer],
        "bufferViews": packer.views,
        "accessors": packer.accessors,
    });
    if !skins.is_empty() {
        doc["skins"] = json!(skins);
    }
    if !animations.is_empty() {
        doc["animations"] = json!(animations);
    }
    Ok((doc, packer.bytes))
}

/// `values` in records of `N` (a trailing partial record is dropped: the core's validation
/// refuses such samplers before they get here).
fn chunks<const N: usize>(values: &[f32]) -> Vec<[f32; N]> {
    values
        .chunks_exact(N)
        .map(|c| std::array::from_fn(|k| c[k]))
        .collect()
}

/// Writes `mesh` as `.glb` (`binary`) or `.gltf` with the buffer embedded as a base64 `data:`
/// URI. Errors with `InvalidInput` for what glTF cannot say (two instances on one node, a
/// triangle across instances, a parent that does not exist).
pub fn write_animated(
    out: &mut dyn Write,
    mesh: &AnimatedMesh,
    binary: bool,
) -> std::io::Result<()> {
    if binary {
        let (doc, bytes) = document(mesh, None)?;
        write_glb_header(out, &doc, bytes.len() as u64)?;
        out.write_all(&bytes)?;
        write_glb_padding(out, bytes.len() as u64)
    } else {
        let (doc, bytes) = document(mesh, Some(embedded_uri()))?;
        write_gltf_text(out, &doc, |encoder| encoder.write_all(&bytes))
    }
}
