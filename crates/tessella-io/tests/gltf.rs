mod common;

use base64::Engine;
use common::{assert_same, bits2, bits3, Sample};
use serde_json::json;
use std::fs;
use std::path::Path;
use tessella_io::{read_raw, write_mesh, IoError, MeshView, WriteOptions};

const B64: base64::engine::GeneralPurpose = base64::engine::general_purpose::STANDARD;

#[test]
fn gltf_and_glb_round_trips_keep_every_bit() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    for name in ["sample.gltf", "sample.glb"] {
        let path = dir.path().join(name);
        write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
        assert_same(&read_raw(&path).unwrap(), &sample, true, true);
    }
}

#[test]
fn attributes_are_optional_on_write() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    let view = MeshView {
        normals: None,
        uvs: None,
        ..sample.view()
    };
    let path = dir.path().join("bare.glb");
    write_mesh(&path, view, &WriteOptions::default()).unwrap();
    assert_same(&read_raw(&path).unwrap(), &sample, false, false);
}

/// Reads a written file with the `gltf` crate alone (its validation included) and checks what
/// the glTF spec asks of it.
fn check_with_gltf_crate(path: &Path, sample: &Sample) {
    let bytes = fs::read(path).unwrap();
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&bytes).unwrap();
    let buffer = document.buffers().next().unwrap();
    let data = match buffer.source() {
        gltf::buffer::Source::Bin => blob.unwrap(),
        gltf::buffer::Source::Uri(uri) => {
            let payload = uri
                .strip_prefix("data:application/octet-stream;base64,")
                .expect("embedded buffer");
            B64.decode(payload).unwrap()
        }
    };
    assert!(data.len() >= buffer.length());
    let mesh = document.meshes().next().unwrap();
    let primitive = mesh.primitives().next().unwrap();
    assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
    // Bounds computed here, independently of the writer.
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &sample.positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let accessor = primitive.get(&gltf::Semantic::Positions).unwrap();
    let as_f32 = |v: serde_json::Value| -> Vec<f32> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap() as f32)
            .collect()
    };
    assert_eq!(as_f32(accessor.min().unwrap()), lo);
    assert_eq!(as_f32(accessor.max().unwrap()), hi);
    let reader = primitive.reader(|_| Some(&data[..]));
    let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(bits3(&positions), bits3(&sample.positions));
    let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    assert_eq!(bits3(&normals), bits3(&sample.normals));
    // glTF's uv origin is the top-left: v is stored flipped.
    let uvs: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
    let flipped: Vec<[f32; 2]> = sample.uvs.iter().map(|t| [t[0], 1.0 - t[1]]).collect();
    assert_eq!(bits2(&uvs), bits2(&flipped));
    let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    let expected: Vec<u32> = sample.triangles.iter().flatten().copied().collect();
    assert_eq!(indices, expected);
    // The scene shows the mesh.
    let scene = document.default_scene().unwrap();
    assert_eq!(scene.nodes().next().unwrap().mesh().unwrap().index(), 0);
}

#[test]
fn written_files_read_back_with_the_gltf_crate() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    for name in ["check.gltf", "check.glb"] {
        let path = dir.path().join(name);
        write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
        check_with_gltf_crate(&path, &sample);
    }
}

#[test]
fn glb_container_layout_follows_the_spec() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("layout.glb");
    let sample = Sample::new();
    write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
    let bytes = fs::read(&path).unwrap();
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(word(4), 2);
    assert_eq!(word(8), bytes.len());
    let json_len = word(12);
    assert_eq!(&bytes[16..20], b"JSON");
    assert_eq!(json_len % 4, 0);
    let bin_at = 20 + json_len;
    assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
    // positions 5*12 + normals 5*12 + uvs 5*8 + indices 4*3*4
    assert_eq!(word(bin_at), 60 + 60 + 40 + 48);
    assert_eq!(bin_at + 8 + word(bin_at), bytes.len());
}

#[test]
fn uv_flip_moves_other_values_by_at_most_one_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let mut sample = Sample::new();
    sample.uvs = vec![
        [0.1, 0.3],
        [0.2, 0.01],
        [0.7, 0.123_456_7],
        [0.0, 1e-3],
        [1.0, 0.49],
    ];
    let path = dir.path().join("uv.gltf");
    write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
    let raw = read_raw(&path).unwrap();
    for (got, want) in raw.uvs.unwrap().iter().zip(&sample.uvs) {
        assert_eq!(got[0].to_bits(), want[0].to_bits());
        // 1 - (1 - v): the inner subtraction rounds to a multiple of 2^-24 near 1.
        assert!((got[1] - want[1]).abs() <= 6e-8, "{got:?} vs {want:?}");
    }
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// One triangle (0,0,0) (1,0,0) (0,1,0) with +Z normals, shown by two nodes: one translated by
/// (10,0,0), one mirrored in x under a parent that translates by (0,5,0). The buffer is an
/// external file with a space in its name.
#[test]
fn node_transforms_are_applied_and_mirroring_keeps_winding() {
    let dir = tempfile::tempdir().unwrap();
    let mut buffer = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    buffer.extend(f32_bytes(&[0.0, 0.0, 1.0].repeat(3)));
    fs::write(dir.path().join("tri data.bin"), &buffer).unwrap();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "translation": [10.0, 0.0, 0.0]},
            {"translation": [0.0, 5.0, 0.0], "children": [2]},
            {"mesh": 0, "scale": [-1.0, 1.0, 1.0]}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
        "buffers": [{"byteLength": 72, "uri": "tri%20data.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 36}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}
        ]
    });
    let path = dir.path().join("nodes.gltf");
    fs::write(&path, serde_json::to_string(&doc).unwrap()).unwrap();
    let raw = read_raw(&path).unwrap();
    assert_eq!(
        raw.positions,
        vec![
            [10.0, 0.0, 0.0],
            [11.0, 0.0, 0.0],
            [10.0, 1.0, 0.0],
            [0.0, 5.0, 0.0],
            [-1.0, 5.0, 0.0],
            [0.0, 6.0, 0.0],
        ]
    );
    // Non-indexed primitive: corners in order; the mirrored copy is re-wound.
    assert_eq!(raw.triangles, vec![[0, 1, 2], [3, 5, 4]]);
    // Normals stay +Z (mirroring x does not flip a z normal) and agree with the winding.
    assert_eq!(raw.normals.as_ref().unwrap(), &vec![[0.0, 0.0, 1.0]; 6]);
    for t in &raw.triangles {
        let [a, b, c] = t.map(|i| glam::Vec3::from(raw.positions[i as usize]));
        assert!((b - a).cross(c - a).z > 0.0);
    }
    let mesh = tessella_io::read_mesh(&path).unwrap();
    assert_eq!(mesh.face_count(), 2);
}

/// Wraps `buffer` as a data URI in a one-primitive document with the given mode and indices.
fn embedded(positions: &[f32], indices: Option<&[u8]>, mode: u32) -> serde_json::Value {
    let mut buffer = f32_bytes(positions);
    let count = positions.len() / 3;
    let mut views = vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": buffer.len()})];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": count,
        "type": "VEC3", "min": [-10.0, -10.0, -10.0], "max": [10.0, 10.0, 10.0]}),
    ];
    let mut primitive = json!({"attributes": {"POSITION": 0}, "mode": mode});
    if let Some(indices) = indices {
        views.push(json!({"buffer": 0, "byteOffset": buffer.len(), "byteLength": indices.len()}));
        accessors.push(
            json!({"bufferView": 1, "componentType": 5121, "count": indices.len(),
            "type": "SCALAR"}),
        );
        primitive["indices"] = json!(1);
        buffer.extend(indices);
    }
    json!({
        "asset": {"version": "2.0"},
        "meshes": [{"primitives": [primitive]}],
        "buffers": [{"byteLength": buffer.len(),
                     "uri": format!("data:application/octet-stream;base64,{}", B64.encode(&buffer))}],
        "bufferViews": views,
        "accessors": accessors
    })
}

#[test]
fn strips_and_fans_follow_the_spec_and_u8_indices_work() {
    let dir = tempfile::tempdir().unwrap();
    // A row of 4 points zig-zagging: 0 (0,0) 1 (0,1) 2 (1,0) 3 (1,1).
    let square = [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0];
    let strip = dir.path().join("strip.gltf");
    fs::write(
        &strip,
        embedded(&square, Some(&[0, 2, 1, 3]), 5).to_string(),
    )
    .unwrap();
    // spec: p0 = (v0, v1, v2), p1 = (v1, v3, v2)
    assert_eq!(
        read_raw(&strip).unwrap().triangles,
        vec![[0, 2, 1], [2, 3, 1]]
    );
    let fan = dir.path().join("fan.gltf");
    fs::write(&fan, embedded(&square, Some(&[0, 2, 3, 1]), 6).to_string()).unwrap();
    // spec: p_i = (v_(i+1), v_(i+2), v_0)
    assert_eq!(
        read_raw(&fan).unwrap().triangles,
        vec![[2, 3, 0], [3, 1, 0]]
    );
    let lines = dir.path().join("lines.gltf");
    fs::write(&lines, embedded(&square, None, 1).to_string()).unwrap();
    assert!(matches!(
        read_raw(&lines).unwrap_err(),
        IoError::NoTriangles { .. }
    ));
}

#[test]
fn bad_buffers_and_accessors_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let triangle = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    // Index out of range.
    let path = dir.path().join("range.gltf");
    fs::write(&path, embedded(&triangle, Some(&[0, 1, 7]), 4).to_string()).unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(err.to_string().contains("uses vertex 7"), "{err}");
    // An accessor claiming more elements than its view holds.
    let mut doc = embedded(&triangle, None, 4);
    doc["accessors"][0]["count"] = json!(4);
    fs::write(&path, doc.to_string()).unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(err.to_string().contains("past the end"), "{err}");
    // A buffer shorter than its declared length.
    let mut doc = embedded(&triangle, None, 4);
    doc["buffers"][0]["byteLength"] = json!(400);
    doc["bufferViews"][0]["byteLength"] = json!(400);
    fs::write(&path, doc.to_string()).unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(err.to_string().contains("declares byteLength 400"), "{err}");
    // Positions stored as bytes are not valid glTF positions.
    let mut doc = embedded(&triangle, None, 4);
    doc["accessors"][0]["componentType"] = json!(5121);
    fs::write(&path, doc.to_string()).unwrap();
    assert!(read_raw(&path).is_err());
    // A missing external buffer names the missing file.
    let mut doc = embedded(&triangle, None, 4);
    doc["buffers"][0]["uri"] = json!("missing.bin");
    fs::write(&path, doc.to_string()).unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(
        matches!(&err, IoError::Read { path, .. } if path.ends_with("missing.bin")),
        "{err}"
    );
}

#[test]
fn garbage_and_truncated_glb_are_parse_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.glb");
    let mut garbage = b"glTF".to_vec();
    garbage.extend((0u32..200).map(|i| (i * 37 % 251) as u8));
    fs::write(&path, &garbage).unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(matches!(err, IoError::Parse { .. }), "{err}");
    // A valid file cut short at several places.
    let good = dir.path().join("good.glb");
    write_mesh(&good, Sample::new().view(), &WriteOptions::default()).unwrap();
    let bytes = fs::read(&good).unwrap();
    for cut in [bytes.len() - 1, bytes.len() - 100, 30, 12, 3] {
        let path = dir.path().join(format!("cut{cut}.glb"));
        fs::write(&path, &bytes[..cut]).unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(err.to_string().contains(&format!("cut{cut}.glb")), "{err}");
    }
}
