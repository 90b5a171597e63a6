mod common;

use common::{assert_same, bits3, Sample};
use std::fs;
use std::path::Path;
use tessella_io::{read_mesh, read_raw, write_mesh, IoError, MeshView, WriteOptions};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

#[test]
fn binary_round_trip_keeps_every_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sample.ply");
    let sample = Sample::new();
    write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
    let bytes = fs::read(&path).unwrap();
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
    assert!(
        header.contains("format binary_little_endian 1.0"),
        "{header}"
    );
    assert!(header.contains("property list uchar uint vertex_indices"));
    // 5 vertices of 8 floats, 4 faces of 1 + 3*4 bytes.
    assert_eq!(bytes.len() - header_end, 5 * 8 * 4 + 4 * 13);
    assert_same(&read_raw(&path).unwrap(), &sample, true, true);
}

#[test]
fn ascii_round_trip_keeps_every_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sample.ply");
    let sample = Sample::new();
    write_mesh(
        &path,
        sample.view(),
        &WriteOptions {
            ply_ascii: true,
            ..Default::default()
        },
    )
    .unwrap();
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("ply\nformat ascii 1.0\n"), "{text}");
    assert!(text.contains("\n3 0 1 2\n"), "{text}");
    assert_same(&read_raw(&path).unwrap(), &sample, true, true);
}

#[test]
fn positions_only_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    let view = MeshView {
        normals: None,
        uvs: None,
        ..sample.view()
    };
    for ascii in [false, true] {
        let path = dir.path().join(format!("bare_{ascii}.ply"));
        write_mesh(
            &path,
            view,
            &WriteOptions {
                ply_ascii: ascii,
                ..Default::default()
            },
        )
        .unwrap();
        assert_same(&read_raw(&path).unwrap(), &sample, false, false);
    }
}

#[test]
fn refined_mesh_is_written_through_its_view() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("refined.ply");
    let coarse = tessella_core::samples::tetrahedron();
    let options = tessella_core::RefineOptions::new(tessella_core::Scheme::Pn, 3);
    let refined = tessella_core::refine(&coarse, &options).unwrap();
    write_mesh(&path, MeshView::from(&refined), &WriteOptions::default()).unwrap();
    let raw = read_raw(&path).unwrap();
    assert_eq!(bits3(&raw.positions), bits3(&refined.positions));
    assert_eq!(
        bits3(raw.normals.as_ref().unwrap()),
        bits3(&refined.normals)
    );
    assert_eq!(raw.triangles, refined.triangles);
}

#[test]
fn extra_properties_edges_and_polygons_are_read() {
    let raw = read_raw(&fixture("creased_quad.ply")).unwrap();
    assert_eq!(raw.positions.len(), 5);
    assert_eq!(raw.positions[4], [0.5, 2.0, 0.0]);
    assert!(raw.normals.is_none());
    // s/t are texture coordinates.
    assert_eq!(raw.uvs.as_ref().unwrap()[4], [0.5, 1.5]);
    // The quad is fan-triangulated around its first corner.
    assert_eq!(raw.triangles, vec![[0, 1, 2], [0, 2, 3], [3, 2, 4]]);
    let names: Vec<&str> = raw.vertex_scalars.keys().map(String::as_str).collect();
    assert_eq!(names, ["bias", "crease_x", "sharpness", "tension"]);
    assert_eq!(raw.vertex_scalars["tension"], [1.0, 1.0, 0.5, 1.0, 1.0]);
    assert_eq!(raw.vertex_scalars["sharpness"], [0.0, 2.0, 0.0, 0.0, 0.0]);
    assert_eq!(raw.vertex_scalars["bias"], [0.5, 0.5, 0.5, 0.25, 0.5]);
    assert_eq!(raw.vertex_scalars["crease_x"], [0.0, 0.0, 1.0, 0.0, 0.0]);
    assert_eq!(raw.edges.len(), 2);
    assert_eq!(raw.edges[0].vertices, [0, 1]);
    assert_eq!(raw.edges[0].scalars.len(), 1);
    assert_eq!(raw.edges[0].scalars["sharpness"], 2.5);
    assert_eq!(raw.edges[1].vertices, [2, 3]);
    assert_eq!(raw.edges[1].scalars["sharpness"], 0.75);
    let mesh = read_mesh(&fixture("creased_quad.ply")).unwrap();
    assert_eq!(mesh.face_count(), 3);
}

/// A hand-made big-endian binary PLY: one triangle with normals and `texture_u/v`, a `short`
/// index list, and an extra `uchar` property.
fn big_endian_ply() -> Vec<u8> {
    let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\n\
property float x\nproperty float y\nproperty float z\n\
property float nx\nproperty float ny\nproperty float nz\n\
property float texture_u\nproperty float texture_v\nproperty uchar quality\n\
element face 1\nproperty list uchar short vertex_indices\nend_header\n"
        .to_vec();
    let vertices: [([f32; 8], u8); 3] = [
        ([0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0], 7),
        ([2.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0], 8),
        ([0.0, 2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0], 9),
    ];
    for (floats, quality) in vertices {
        for x in floats {
            bytes.extend(x.to_be_bytes());
        }
        bytes.push(quality);
    }
    bytes.push(3);
    for i in [0i16, 1, 2] {
        bytes.extend(i.to_be_bytes());
    }
    bytes
}

#[test]
fn big_endian_binary_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("be.ply");
    fs::write(&path, big_endian_ply()).unwrap();
    let raw = read_raw(&path).unwrap();
    assert_eq!(
        raw.positions,
        vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
    );
    assert_eq!(raw.normals.unwrap(), vec![[0.0, 0.0, 1.0]; 3]);
    assert_eq!(raw.uvs.unwrap(), vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    assert_eq!(raw.triangles, vec![[0, 1, 2]]);
    assert_eq!(raw.vertex_scalars["quality"], [7.0, 8.0, 9.0]);
}

#[test]
fn truncated_binary_is_a_parse_error() {
    let dir = tempfile::tempdir().unwrap();
    let whole = big_endian_ply();
    // Cut inside the vertex data, inside the face list, and right after the header.
    for cut in [
        whole.len() - 1,
        whole.len() - 5,
        whole.len() - 40,
        whole.len() - 3 * 33 - 7,
    ] {
        let path = dir.path().join(format!("cut{cut}.ply"));
        fs::write(&path, &whole[..cut]).unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(matches!(err, IoError::Parse { .. }), "cut at {cut}: {err}");
        assert!(err.to_string().contains(&format!("cut{cut}.ply")), "{err}");
    }
}

#[test]
fn face_index_out_of_range_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("range.ply");
    fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
    )
    .unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::IndexOutOfRange {
                what: "triangle",
                item: 0,
                index: 3,
                count: 3,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn negative_index_and_missing_coordinates_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let negative = dir.path().join("negative.ply");
    fs::write(
        &negative,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n",
    )
    .unwrap();
    let err = read_raw(&negative).unwrap_err();
    assert!(err.to_string().contains("invalid vertex index -1"), "{err}");
    let no_z = dir.path().join("no_z.ply");
    fs::write(
        &no_z,
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
end_header\n0 0\n",
    )
    .unwrap();
    let err = read_raw(&no_z).unwrap_err();
    assert!(err.to_string().contains("x, y, z"), "{err}");
}

#[test]
fn bad_ascii_number_names_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.ply");
    fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(matches!(err, IoError::Parse { .. }), "{err}");
    assert!(err.to_string().contains("Line 11"), "{err}");
}
