//! `read_animated`: glTF 2.0 nodes, skins, morph targets, influences and clips, from small
//! files built here (one buffer as a base64 data URI, or a GLB binary chunk).

use base64::Engine;
use serde_json::{json, Value};
use tessella_core::animation::{AnimatedMesh, Interpolation, MorphTarget, Property, Transform};
use tessella_io::{read_animated, read_animated_bytes, read_raw_bytes, IoError};

const B64: base64::engine::GeneralPurpose = base64::engine::general_purpose::STANDARD;

const FLOAT: u32 = 5126;
const U8: u32 = 5121;
const U16: u32 = 5123;
const I16: u32 = 5122;

/// Packs arrays into one buffer, one buffer view and accessor each.
#[derive(Default)]
struct Pack {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

fn components(kind: &str) -> usize {
    match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT4" => 16,
        _ => unreachable!(),
    }
}

impl Pack {
    /// Appends `bytes` as a buffer view (4-byte aligned); returns its index.
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend(bytes);
        self.views.len() - 1
    }

    fn accessor(
        &mut self,
        bytes: &[u8],
        component: u32,
        kind: &str,
        n: usize,
        normalized: bool,
    ) -> usize {
        let size = match component {
            U8 => 1,
            U16 | I16 => 2,
            _ => 4,
        };
        let count = n / components(kind);
        assert_eq!(bytes.len(), count * components(kind) * size);
        let view = self.view(bytes);
        let mut accessor =
            json!({"bufferView": view, "componentType": component, "count": count, "type": kind});
        if normalized {
            accessor["normalized"] = json!(true);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn f32(&mut self, kind: &str, values: &[f32]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, FLOAT, kind, values.len(), false)
    }

    /// POSITION, with the min and max glTF asks for.
    fn positions(&mut self, values: &[f32]) -> usize {
        let a = self.f32("VEC3", values);
        self.accessors[a]["min"] = json!([-100.0, -100.0, -100.0]);
        self.accessors[a]["max"] = json!([100.0, 100.0, 100.0]);
        a
    }

    fn u8(&mut self, kind: &str, values: &[u8], normalized: bool) -> usize {
        self.accessor(values, U8, kind, values.len(), normalized)
    }

    fn u16(&mut self, kind: &str, values: &[u16], normalized: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, U16, kind, values.len(), normalized)
    }

    fn i16(&mut self, kind: &str, values: &[i16]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, I16, kind, values.len(), true)
    }

    /// A VEC3 f32 accessor of `count` zeros without a buffer view, with sparse values at
    /// `indices` (u8).
    fn sparse_vec3(&mut self, count: usize, indices: &[u8], values: &[f32]) -> usize {
        let index_view = self.view(indices);
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let value_view = self.view(&bytes);
        self.accessors.push(json!({
            "componentType": FLOAT, "count": count, "type": "VEC3",
            "sparse": {"count": indices.len(),
                       "indices": {"bufferView": index_view, "componentType": U8},
                       "values": {"bufferView": value_view}}
        }));
        self.accessors.len() - 1
    }

    /// `doc` with the buffer as a data URI.
    fn gltf(&self, mut doc: Value) -> Value {
        doc["buffers"] = json!([{"byteLength": self.bin.len(),
            "uri": format!("data:application/octet-stream;base64,{}", B64.encode(&self.bin))}]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc
    }

    /// `doc` as a GLB container with the buffer in its binary chunk.
    fn glb(&self, mut doc: Value) -> Vec<u8> {
        doc["buffers"] = json!([{"byteLength": self.bin.len()}]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        let mut text = serde_json::to_vec(&doc).unwrap();
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend(b"glTF");
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((text.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(text);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }
}

/// Accessor indices of [`sample`] that the bad-input tests change.
struct Ids {
    weights0_a: usize,
    translation_out: usize,
    inverse_binds: usize,
    sparse: usize,
}

const SQRT_HALF: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Six nodes: root (translation) → hip (rotation, scale) → knee (matrix); body (mesh 0,
/// skin 0: two primitives with two and one influence sets); face (mesh 1, translated, node
/// weights, two morph targets, the first's positions sparse); prop (mesh 2, skin 1 without
/// inverse binds, no normals). Two animations with every property and interpolation.
fn sample() -> (Pack, Value, Ids) {
    let mut p = Pack::default();
    // mesh 0 primitive 0: indexed, f32 uvs, JOINTS_0 u8 + WEIGHTS_0 f32, JOINTS_1 u16 +
    // WEIGHTS_1 normalised u8.
    let pos_a = p.positions(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    let nrm_a = p.f32("VEC3", &[0., 0., 1.].repeat(3));
    let uv_a = p.f32("VEC2", &[0., 0., 1., 0., 0., 0.25]);
    let idx_a = p.u16("SCALAR", &[0, 1, 2], false);
    let j0_a = p.u8("VEC4", &[0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0], false);
    let w0_a = p.f32(
        "VEC4",
        &[0.5, 0.5, 0., 0., 1., 0., 0., 0., 0.75, 0., 0., 0.],
    );
    let j1_a = p.u16("VEC4", &[0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0], false);
    let w1_a = p.u8("VEC4", &[0, 0, 0, 0, 0, 0, 0, 0, 51, 0, 0, 0], true);
    // mesh 0 primitive 1: a fan of 4, normalised u16 uvs, JOINTS_0 u16 + normalised u16 weights.
    let pos_b = p.positions(&[0., 0., 1., 1., 0., 1., 1., 1., 1., 0., 1., 1.]);
    let nrm_b = p.f32("VEC3", &[0., 0., 1.].repeat(4));
    let uv_b = p.u16("VEC2", &[0, 0, 65535, 0, 65535, 65535, 0, 65535], true);
    let j0_b = p.u16("VEC4", &[1, 0, 0, 0].repeat(4), false);
    let w0_b = p.u16("VEC4", &[65535, 0, 0, 0].repeat(4), true);
    // mesh 1: morph targets.
    let pos_c = p.positions(&[0., 0., 0., 2., 0., 0., 0., 2., 0.]);
    let nrm_c = p.f32("VEC3", &[0., 0., 1.].repeat(3));
    let uv_c = p.f32("VEC2", &[0.; 6]);
    let idx_c = p.u8("SCALAR", &[0, 1, 2], false);
    let t0_pos = p.sparse_vec3(3, &[2], &[0., 0., 1.]);
    let t0_nrm = p.f32("VEC3", &[0., 0., 0., 0., 0., 0., 0., 1., 0.]);
    let t1_pos = p.f32("VEC3", &[1., 0., 0.].repeat(3));
    // mesh 2: no normals.
    let pos_d = p.positions(&[5., 0., 0., 6., 0., 0., 5., 1., 0.]);
    let uv_d = p.f32("VEC2", &[0.; 6]);
    let j0_d = p.u8("VEC4", &[0; 12], false);
    let w0_d = p.f32("VEC4", &[1., 0., 0., 0.].repeat(3));
    // skin 0's inverse binds: the identity and a translation by (0, -3, 0).
    let mut binds = vec![
        1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
    ];
    binds.extend([
        1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., -3., 0., 1.,
    ]);
    let ibm = p.f32("MAT4", &binds);
    // animations
    let t2 = p.f32("SCALAR", &[0., 1.]);
    let t3 = p.f32("SCALAR", &[0., 0.5, 1.]);
    let translation_out = p.f32("VEC3", &[0., 0., 0., 1., 2., 3.]);
    let rotation_i16 = p.i16("VEC4", &[0, 0, 0, 32767, 0, 32767, 0, 0, -32768, 0, 0, 0]);
    let scale_cubic: Vec<f32> = (0..18).map(|i| i as f32).collect();
    let scale_out = p.f32("VEC3", &scale_cubic);
    let weights_out = p.f32("SCALAR", &[0., 1., 1., 0.]);
    let rotation_cubic: Vec<f32> = (0..24).map(|i| i as f32 / 24.0).collect();
    let rotation_out = p.f32("VEC4", &rotation_cubic);
    let weights_u8 = p.u8("SCALAR", &[255, 0, 0, 255], true);
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 3, 4, 5]}],
        "nodes": [
            {"name": "root", "translation": [0.0, 1.0, 0.0], "children": [1]},
            {"name": "hip", "rotation": [0.0, SQRT_HALF, 0.0, SQRT_HALF], "scale": [2.0, 2.0, 2.0],
             "children": [2]},
            {"name": "knee", "matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                                        0.0, 0.0, 1.0, 0.0, 0.0, 3.0, 0.0, 1.0]},
            {"name": "body", "mesh": 0, "skin": 0},
            {"mesh": 1, "weights": [0.5, 0.25], "translation": [0.0, 0.0, 5.0]},
            {"name": "prop", "mesh": 2, "skin": 1}
        ],
        "meshes": [
            {"primitives": [
                {"attributes": {"POSITION": pos_a, "NORMAL": nrm_a, "TEXCOORD_0": uv_a,
                    "JOINTS_0": j0_a, "WEIGHTS_0": w0_a, "JOINTS_1": j1_a, "WEIGHTS_1": w1_a},
                 "indices": idx_a},
                {"attributes": {"POSITION": pos_b, "NORMAL": nrm_b, "TEXCOORD_0": uv_b,
                    "JOINTS_0": j0_b, "WEIGHTS_0": w0_b},
                 "mode": 6}
            ]},
            {"primitives": [
                {"attributes": {"POSITION": pos_c, "NORMAL": nrm_c, "TEXCOORD_0": uv_c},
                 "indices": idx_c,
                 "targets": [{"POSITION": t0_pos, "NORMAL": t0_nrm}, {"POSITION": t1_pos}]}
             ],
             "weights": [0.1, 0.2]},
            {"primitives": [
                {"attributes": {"POSITION": pos_d, "TEXCOORD_0": uv_d,
                    "JOINTS_0": j0_d, "WEIGHTS_0": w0_d}}
            ]}
        ],
        "skins": [
            {"name": "rig", "joints": [1, 2], "inverseBindMatrices": ibm, "skeleton": 0},
            {"joints": [1]}
        ],
        "animations": [
            {"name": "walk",
             "samplers": [
                {"input": t2, "output": translation_out},
                {"input": t3, "output": rotation_i16, "interpolation": "STEP"},
                {"input": t2, "output": scale_out, "interpolation": "CUBICSPLINE"},
                {"input": t2, "output": weights_out, "interpolation": "LINEAR"}
             ],
             "channels": [
                {"sampler": 0, "target": {"node": 1, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 0, "path": "scale"}},
                {"sampler": 3, "target": {"node": 4, "path": "weights"}}
             ]},
            {"samplers": [
                {"input": t2, "output": rotation_out, "interpolation": "CUBICSPLINE"},
                {"input": t2, "output": weights_u8, "interpolation": "STEP"}
             ],
             "channels": [
                {"sampler": 1, "target": {"node": 4, "path": "weights"}},
                {"sampler": 0, "target": {"node": 1, "path": "rotation"}}
             ]}
        ]
    });
    let ids = Ids {
        weights0_a: w0_a,
        translation_out,
        inverse_binds: ibm,
        sparse: t0_pos,
    };
    (p, doc, ids)
}

fn read_gltf(doc: &Value) -> Result<AnimatedMesh, IoError> {
    read_animated_bytes("anim.gltf", doc.to_string().as_bytes(), &[])
}

fn identity() -> [f32; 16] {
    glam::Mat4::IDENTITY.to_cols_array()
}

#[test]
fn nodes_skins_instances_and_clips_are_read() {
    let (pack, doc, _) = sample();
    let mesh = read_gltf(&pack.gltf(doc)).unwrap();

    // Nodes: names, parents from children, TRS and matrix transforms, weights.
    let names: Vec<Option<&str>> = mesh.nodes.iter().map(|n| n.name.as_deref()).collect();
    assert_eq!(
        names,
        [
            Some("root"),
            Some("hip"),
            Some("knee"),
            Some("body"),
            None,
            Some("prop")
        ]
    );
    let parents: Vec<Option<u32>> = mesh.nodes.iter().map(|n| n.parent).collect();
    assert_eq!(parents, [None, Some(0), Some(1), None, None, None]);
    assert_eq!(
        mesh.nodes[0].transform,
        Transform::Trs {
            translation: [0.0, 1.0, 0.0],
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [1.0; 3]
        }
    );
    assert_eq!(
        mesh.nodes[1].transform,
        Transform::Trs {
            translation: [0.0; 3],
            rotation: [0.0, SQRT_HALF, 0.0, SQRT_HALF],
            scale: [2.0; 3]
        }
    );
    let mut knee = identity();
    knee[13] = 3.0;
    assert_eq!(mesh.nodes[2].transform, Transform::Matrix(knee));
    assert_eq!(mesh.nodes[4].weights, Some(vec![0.5, 0.25]));
    assert_eq!(mesh.nodes[3].weights, None);

    // Skins: joints, inverse binds given and absent (identity), skeleton, name.
    assert_eq!(mesh.skins.len(), 2);
    assert_eq!(mesh.skins[0].name.as_deref(), Some("rig"));
    assert_eq!(mesh.skins[0].joints, [1, 2]);
    let mut bind = identity();
    bind[13] = -3.0;
    assert_eq!(mesh.skins[0].inverse_binds, [identity(), bind]);
    assert_eq!(mesh.skins[0].skeleton, Some(0));
    assert_eq!(mesh.skins[1].joints, [1]);
    assert_eq!(mesh.skins[1].inverse_binds, [identity()]);
    assert_eq!(mesh.skins[1].skeleton, None);

    // Instances: nodes 3, 4 and 5, in mesh space (node 4's translation is not applied).
    assert_eq!(mesh.instances.len(), 3);
    let [body, face, prop] = &mesh.instances[..] else {
        unreachable!()
    };
    assert_eq!((body.node, body.skin, body.first_vertex), (3, Some(0), 0));
    assert_eq!((face.node, face.skin, face.first_vertex), (4, None, 7));
    assert_eq!((prop.node, prop.skin, prop.first_vertex), (5, Some(1), 10));
    assert_eq!(
        body.positions,
        [
            [0., 0., 0.],
            [1., 0., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.]
        ]
    );
    assert_eq!(body.normals, Some(vec![[0., 0., 1.]; 7]));
    assert_eq!(face.positions, [[0., 0., 0.], [2., 0., 0.], [0., 2., 0.]]);
    assert_eq!(prop.positions, [[5., 0., 0.], [6., 0., 0.], [5., 1., 0.]]);
    assert_eq!(prop.normals, None);
    // Triangles: primitive 0 indexed, primitive 1 a fan (p_i = v_(i+1), v_(i+2), v_0), then
    // the other instances offset by their first vertex.
    assert_eq!(
        mesh.triangles,
        [[0, 1, 2], [4, 5, 3], [5, 6, 3], [7, 8, 9], [10, 11, 12]]
    );
    // uvs: flipped (v' = 1 - v); f32 and normalised u16.
    let uvs = mesh.uvs.as_ref().unwrap();
    assert_eq!(uvs.len(), 13);
    assert_eq!(
        uvs[..7],
        [
            [0., 1.],
            [1., 1.],
            [0., 0.75],
            [0., 1.],
            [1., 1.],
            [1., 0.],
            [0., 0.]
        ]
    );

    // Influences: two sets on the body (the fan has one: its second set is zero).
    assert_eq!(body.influences.len(), 2);
    assert_eq!(
        body.influences[0].joints,
        [
            [0, 1, 0, 0],
            [1, 0, 0, 0],
            [0, 0, 0, 0],
            [1, 0, 0, 0],
            [1, 0, 0, 0],
            [1, 0, 0, 0],
            [1, 0, 0, 0]
        ]
    );
    assert_eq!(
        body.influences[0].weights,
        [
            [0.5, 0.5, 0., 0.],
            [1., 0., 0., 0.],
            [0.75, 0., 0., 0.],
            [1., 0., 0., 0.],
            [1., 0., 0., 0.],
            [1., 0., 0., 0.],
            [1., 0., 0., 0.]
        ]
    );
    let mut joints1 = vec![[0u16; 4]; 7];
    joints1[2] = [1, 0, 0, 0];
    assert_eq!(body.influences[1].joints, joints1);
    let mut weights1 = vec![[0f32; 4]; 7];
    weights1[2] = [51.0 / 255.0, 0., 0., 0.];
    assert_eq!(body.influences[1].weights, weights1);
    assert_eq!(prop.influences.len(), 1);
    assert_eq!(prop.influences[0].joints, [[0; 4]; 3]);
    assert_eq!(prop.influences[0].weights, [[1., 0., 0., 0.]; 3]);
    assert!(face.influences.is_empty());

    // Morph targets: the sparse positions, normals, a target without normals, mesh weights.
    assert!(body.targets.is_empty() && body.default_weights.is_empty());
    assert_eq!(
        face.targets,
        [
            MorphTarget {
                positions: vec![[0., 0., 0.], [0., 0., 0.], [0., 0., 1.]],
                normals: Some(vec![[0., 0., 0.], [0., 0., 0.], [0., 1., 0.]]),
            },
            MorphTarget {
                positions: vec![[1., 0., 0.]; 3],
                normals: None,
            }
        ]
    );
    assert_eq!(face.default_weights, [0.1, 0.2]);

    // Clips.
    assert_eq!(mesh.clips.len(), 2);
    let walk = &mesh.clips[0];
    assert_eq!(walk.name, "walk");
    let summary: Vec<(u32, Property, Interpolation)> = walk
        .channels
        .iter()
        .map(|c| (c.node, c.property, c.sampler.interpolation))
        .collect();
    assert_eq!(
        summary,
        [
            (1, Property::Translation, Interpolation::Linear),
            (1, Property::Rotation, Interpolation::Step),
            (0, Property::Scale, Interpolation::CubicSpline),
            (4, Property::Weights, Interpolation::Linear)
        ]
    );
    assert_eq!(walk.channels[0].sampler.times, [0., 1.]);
    assert_eq!(walk.channels[0].sampler.values, [0., 0., 0., 1., 2., 3.]);
    assert_eq!(walk.channels[1].sampler.times, [0., 0.5, 1.]);
    // Normalised i16: c / 32767, at least -1.
    assert_eq!(
        walk.channels[1].sampler.values,
        [0., 0., 0., 1., 0., 1., 0., 0., -1., 0., 0., 0.]
    );
    let cubic: Vec<f32> = (0..18).map(|i| i as f32).collect();
    assert_eq!(walk.channels[2].sampler.values, cubic);
    assert_eq!(walk.channels[3].sampler.values, [0., 1., 1., 0.]);
    let second = &mesh.clips[1];
    assert_eq!(second.name, "animation 1");
    assert_eq!(second.channels[0].property, Property::Weights);
    assert_eq!(
        second.channels[0].sampler.interpolation,
        Interpolation::Step
    );
    assert_eq!(second.channels[0].sampler.values, [1., 0., 0., 1.]);
    assert_eq!(
        second.channels[1].sampler.interpolation,
        Interpolation::CubicSpline
    );
    let cubic: Vec<f32> = (0..24).map(|i| i as f32 / 24.0).collect();
    assert_eq!(second.channels[1].sampler.values, cubic);
}

#[test]
fn glb_files_and_paths_read_the_same() {
    let (pack, doc, _) = sample();
    let from_gltf = read_gltf(&pack.gltf(doc.clone())).unwrap();
    let glb = pack.glb(doc);
    let from_glb = read_animated_bytes("anim.glb", &glb, &[]).unwrap();
    assert_eq!(from_glb, from_gltf);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("anim.glb");
    std::fs::write(&path, &glb).unwrap();
    assert_eq!(read_animated(&path).unwrap(), from_gltf);
    // Other formats hold no animation.
    let err = read_animated_bytes("mesh.obj", b"v 0 0 0\n", &[]).unwrap_err();
    assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
}

/// The static reader still reads the same file as a world-space mesh (node 4 translated),
/// with the same triangles and uvs.
#[test]
fn the_static_reader_reads_a_skinned_file_as_before() {
    let (pack, doc, _) = sample();
    let text = pack.gltf(doc).to_string();
    let raw = read_raw_bytes("anim.gltf", text.as_bytes(), &[]).unwrap();
    let animated = read_gltf(&serde_json::from_str(&text).unwrap()).unwrap();
    assert_eq!(raw.triangles, animated.triangles);
    assert_eq!(raw.uvs, animated.uvs);
    // prop has no normals: the merged static mesh has none.
    assert_eq!(raw.normals, None);
    let mut expected: Vec<[f32; 3]> = animated
        .instances
        .iter()
        .flat_map(|i| i.positions.clone())
        .collect();
    for p in &mut expected[7..10] {
        p[2] += 5.0;
    }
    assert_eq!(raw.positions, expected);
    // ... and refuses the sparse accessor only when it reads it: the morph targets it does
    // not read do not matter, a sparse POSITION does.
    let (pack, mut doc, ids) = sample();
    doc["meshes"][1]["primitives"][0]["attributes"]["POSITION"] = json!(ids.sparse);
    let mut doc = pack.gltf(doc);
    doc["accessors"][ids.sparse]["min"] = json!([-1.0, -1.0, -1.0]);
    doc["accessors"][ids.sparse]["max"] = json!([1.0, 1.0, 1.0]);
    let err = read_raw_bytes("anim.gltf", doc.to_string().as_bytes(), &[]).unwrap_err();
    assert!(err.to_string().contains("is sparse"), "{err}");
    let animated = read_gltf(&doc).unwrap();
    assert_eq!(
        animated.instances[1].positions,
        [[0., 0., 0.], [0., 0., 0.], [0., 0., 1.]]
    );
}

#[test]
fn a_primitive_without_uvs_drops_them_for_all() {
    let (pack, mut doc, _) = sample();
    let attributes = doc["meshes"][2]["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap();
    attributes.remove("TEXCOORD_0");
    let mesh = read_gltf(&pack.gltf(doc)).unwrap();
    assert_eq!(mesh.uvs, None);
}

/// Reads `doc` changed by `change` and returns the error's message.
fn error_of(change: impl FnOnce(&mut Value, &Ids)) -> String {
    let (pack, doc, ids) = sample();
    let mut doc = pack.gltf(doc);
    change(&mut doc, &ids);
    let err = read_gltf(&doc).expect_err("a bad file");
    assert!(
        matches!(err, IoError::Parse { .. } | IoError::Unsupported { .. }),
        "{err}"
    );
    let message = err.to_string();
    assert!(message.contains("anim.gltf"), "{message}");
    message
}

#[track_caller]
fn assert_names(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "{message:?} does not name {part:?}");
    }
}

#[test]
fn structural_errors_name_what_is_wrong() {
    // Accessor indices out of range: an attribute, a morph target, an animation output.
    let m = error_of(|d, _| d["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = json!(99));
    assert_names(&m, &["mesh 0 primitive 0", "accessor 99"]);
    let m = error_of(|d, _| d["meshes"][1]["primitives"][0]["targets"][1]["POSITION"] = json!(99));
    assert_names(&m, &["meshes[1].primitives[0].targets[1]", "out of bounds"]);
    let m = error_of(|d, _| d["animations"][0]["samplers"][0]["output"] = json!(99));
    assert_names(&m, &["animations[0].samplers[0].output"]);
    // A channel whose target node is missing; a skin joint past the nodes.
    let m = error_of(|d, _| d["animations"][1]["channels"][1]["target"]["node"] = json!(6));
    assert_names(
        &m,
        &["animation 1 channel 1 targets node 6", "only 6 nodes"],
    );
    let m = error_of(|d, _| d["animations"][1]["channels"][0]["target"]["path"] = json!("colour"));
    assert_names(&m, &["animation 1 channel 0 targets a path other than"]);
    let m = error_of(|d, _| d["skins"][0]["joints"] = json!([1, 6]));
    assert_names(&m, &["skins[0].joints"]);
    // Wrong component types or dimensions.
    let m = error_of(|d, ids| {
        d["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(ids.weights0_a)
    });
    assert_names(&m, &["mesh 0 primitive 0 JOINTS_0", "F32"]);
    // VEC4 elements no longer fit the accessor's view.
    let m = error_of(|d, ids| d["accessors"][ids.translation_out]["type"] = json!("VEC4"));
    assert_names(
        &m,
        &[
            "animation 0 channel 0 output",
            "reaches past the end of bufferView",
        ],
    );
    let m = error_of(|d, ids| d["accessors"][ids.inverse_binds]["componentType"] = json!(U16));
    assert_names(&m, &["skin 0 inverseBindMatrices"]);
    // Counts that do not match.
    let m = error_of(|d, ids| d["accessors"][ids.weights0_a]["count"] = json!(2));
    assert_names(
        &m,
        &["mesh 0 primitive 0 WEIGHTS_0", "2 values for 3 positions"],
    );
    let m = error_of(|d, ids| d["accessors"][ids.translation_out]["count"] = json!(1));
    assert_names(
        &m,
        &[
            "animation 0 channel 0: output accessor",
            "1 values for 2 keys",
        ],
    );
    let m =
        error_of(|d, _| d["animations"][0]["samplers"][3]["interpolation"] = json!("CUBICSPLINE"));
    assert_names(
        &m,
        &["animation 0 channel 3", "4 values for 2 keys (expected 12)"],
    );
    let m = error_of(|d, ids| d["accessors"][ids.inverse_binds]["count"] = json!(1));
    assert_names(
        &m,
        &["skin 0 inverseBindMatrices", "1 matrices for 2 joints"],
    );
    let m = error_of(|d, ids| d["accessors"][ids.sparse]["count"] = json!(4));
    assert_names(
        &m,
        &[
            "mesh 1 primitive 0 target 0 POSITION",
            "4 values for 3 positions",
        ],
    );
    let m = error_of(|d, _| d["meshes"][1]["weights"] = json!([1.0]));
    assert_names(&m, &["mesh 1 has 1 weights for 2 morph targets"]);
    // JOINTS without WEIGHTS, and the other way round.
    let m = error_of(|d, _| {
        d["meshes"][0]["primitives"][0]["attributes"]
            .as_object_mut()
            .unwrap()
            .remove("WEIGHTS_1");
    });
    assert_names(&m, &["mesh 0 primitive 0 has JOINTS_1 without WEIGHTS_1"]);
    let m = error_of(|d, _| {
        d["meshes"][2]["primitives"][0]["attributes"]
            .as_object_mut()
            .unwrap()
            .remove("JOINTS_0");
    });
    assert_names(&m, &["mesh 2 primitive 0 has WEIGHTS_0 without JOINTS_0"]);
    // Primitives with different numbers of morph targets.
    let m = error_of(|d, _| d["meshes"][0]["primitives"][1]["targets"] = json!([{"POSITION": 0}]));
    assert_names(
        &m,
        &["mesh 0 primitive 1 has 1 morph targets but primitive 0 has 0"],
    );
    // A weights channel on a node without a mesh.
    let m = error_of(|d, _| d["animations"][0]["channels"][3]["target"]["node"] = json!(2));
    assert_names(&m, &["animation 0 channel 3", "node 2, which has no mesh"]);
    // Sparse data past the end of its view.
    let m =
        error_of(|d, ids| d["accessors"][ids.sparse]["sparse"]["values"]["byteOffset"] = json!(8));
    assert_names(&m, &["accessor", "sparse values", "past the end"]);
    // Hierarchies that are not trees.
    let m = error_of(|d, _| d["nodes"][3]["children"] = json!([2]));
    assert_names(&m, &["node 2 is a child of both node 1 and node 3"]);
    let m = error_of(|d, _| d["nodes"][2]["children"] = json!([0]));
    assert_names(&m, &["cycle"]);
}

/// Accessors the `gltf` crate's iterators would panic on (in debug builds): no elements, a
/// stride shorter than an element. Both readers refuse them: the empty one where it is read
/// (unsupported), the short stride as a malformed file.
#[test]
fn empty_accessors_and_short_strides_are_errors_not_panics() {
    for (name, change) in [
        ("empty", json!({"count": 0})),
        ("stride", json!({"stride": 4})),
    ] {
        let (pack, doc, ids) = sample();
        let mut doc = pack.gltf(doc);
        match name {
            "empty" => doc["accessors"][ids.weights0_a]["count"] = change["count"].clone(),
            _ => {
                let view = doc["accessors"][ids.translation_out]["bufferView"]
                    .as_u64()
                    .unwrap();
                doc["bufferViews"][view as usize]["byteStride"] = change["stride"].clone();
            }
        }
        let err = read_gltf(&doc).unwrap_err();
        if name == "empty" {
            assert!(matches!(err, IoError::Unsupported { .. }), "{err}");
        } else {
            // A stride shorter than an element is a malformed file, named by its use.
            assert!(matches!(err, IoError::Parse { .. }), "{err}");
            assert!(
                err.to_string().contains("animation 0 channel 0 output"),
                "{err}"
            );
        }
    }
    // The static reader on an empty POSITION accessor.
    let (pack, doc, _) = sample();
    let mut doc = pack.gltf(doc);
    doc["accessors"][0]["count"] = json!(0);
    let err = read_raw_bytes("anim.gltf", doc.to_string().as_bytes(), &[]).unwrap_err();
    assert!(
        err.to_string().contains("accessor 0 has no elements"),
        "{err}"
    );
    // ... and on a POSITION view with a 4-byte stride.
    let (pack, doc, _) = sample();
    let mut doc = pack.gltf(doc);
    doc["bufferViews"][0]["byteStride"] = json!(4);
    let err = read_raw_bytes("anim.gltf", doc.to_string().as_bytes(), &[]).unwrap_err();
    assert!(err.to_string().contains("byteStride of 4"), "{err}");
}
