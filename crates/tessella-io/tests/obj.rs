mod common;

use common::{assert_same, bits3, Sample};
use std::fs;
use tessella_io::{read_mesh, read_raw, write_mesh, IoError, MeshView, WriteOptions};

#[test]
fn round_trip_keeps_every_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sample.obj");
    let sample = Sample::new();
    write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
    assert_same(&read_raw(&path).unwrap(), &sample, true, true);
}

#[test]
fn round_trip_without_normals_or_uvs() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    for (normals, uvs) in [(false, false), (true, false), (false, true)] {
        let path = dir.path().join(format!("n{normals}_t{uvs}.obj"));
        let view = MeshView {
            normals: normals.then_some(&sample.normals[..]),
            uvs: uvs.then_some(&sample.uvs[..]),
            ..sample.view()
        };
        write_mesh(&path, view, &WriteOptions::default()).unwrap();
        assert_same(&read_raw(&path).unwrap(), &sample, normals, uvs);
    }
}

/// Three quads of a cube meeting at the origin, each with its own normal.
const CUBE_CORNER: &str = "\
# three faces of a unit cube around the origin corner
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 0 1 1
vn 0 0 -1
vn 0 -1 0
vn -1 0 0
f 1//1 4//1 3//1 2//1
f 1//2 2//2 6//2 5//2
f 1//3 5//3 7//3 4//3
";

#[test]
fn split_normals_become_separate_vertices_and_quads_share_theirs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("corner.obj");
    fs::write(&path, CUBE_CORNER).unwrap();
    let raw = read_raw(&path).unwrap();
    // Each quad has 4 distinct (v, vn) pairs, shared by its two fan triangles.
    assert_eq!(raw.triangles.len(), 6);
    assert_eq!(raw.positions.len(), 12);
    let normals = raw.normals.as_ref().unwrap();
    let mut at_origin: Vec<[f32; 3]> = (0..raw.positions.len())
        .filter(|&i| raw.positions[i] == [0.0, 0.0, 0.0])
        .map(|i| normals[i])
        .collect();
    at_origin.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        at_origin,
        vec![[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
    );
    // Fan triangulation of `f 1 4 3 2`: (1,4,3) and (1,3,2), by position.
    let corner = |t: [u32; 3]| t.map(|i| raw.positions[i as usize]);
    assert_eq!(
        corner(raw.triangles[0]),
        [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]
    );
    assert_eq!(
        corner(raw.triangles[1]),
        [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
    );
    // Every triangle's geometric normal agrees with its vertex normals (winding kept).
    for t in &raw.triangles {
        let [a, b, c] = corner(*t).map(glam::Vec3::from);
        let n = (b - a).cross(c - a).normalize();
        for &i in t {
            assert_eq!(n, glam::Vec3::from(normals[i as usize]));
        }
    }
    let mesh = read_mesh(&path).unwrap();
    assert!(!mesh.normals_computed());
    assert_eq!(mesh.vertex_count(), 12);
}

#[test]
fn groups_do_not_cut_shared_vertices_apart() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("groups.obj");
    fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng first\nf 1 2 3\ng second\nusemtl red\nf 2 4 3\n",
    )
    .unwrap();
    let raw = read_raw(&path).unwrap();
    assert_eq!(raw.positions.len(), 4);
    assert_eq!(raw.triangles, vec![[0, 1, 2], [1, 3, 2]]);
    assert!(raw.normals.is_none() && raw.uvs.is_none());
    // No normals in the file: the core computes them (+Z for this flat square).
    let mesh = read_mesh(&path).unwrap();
    assert!(mesh.normals_computed());
    assert!(mesh.normals().iter().all(|n| *n == [0.0, 0.0, 1.0]));
}

#[test]
fn texture_coordinates_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("uv.obj");
    fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 1 0\nf 1/1 2/2 3/1\n",
    )
    .unwrap();
    let raw = read_raw(&path).unwrap();
    // (v1,vt1), (v2,vt2), (v3,vt1): three distinct pairs.
    assert_eq!(raw.uvs.unwrap(), vec![[0.25, 0.5], [1.0, 0.0], [0.25, 0.5]]);
    assert_eq!(bits3(&raw.positions).len(), 3);
}

#[test]
fn mixing_corners_with_and_without_normals_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mixed.obj");
    fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n",
    )
    .unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(matches!(err, IoError::Parse { .. }), "{err}");
    assert!(err.to_string().contains("normal"), "{err}");
}

#[test]
fn garbage_line_is_a_parse_error_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.obj");
    fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n").unwrap();
    let err = read_raw(&path).unwrap_err();
    let message = err.to_string();
    assert!(matches!(err, IoError::Parse { .. }), "{message}");
    assert!(message.contains("line 3"), "{message}");
    assert!(message.contains("garbage.obj"), "{message}");
}

#[test]
fn index_out_of_range_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("range.obj");
    fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let err = read_raw(&path).unwrap_err();
    assert!(matches!(err, IoError::Parse { .. }), "{err}");
    assert!(err.to_string().contains("out of bounds"), "{err}");
}

#[test]
fn degenerate_triangle_is_reported_by_read_mesh_with_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.obj");
    fs::write(&path, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    assert!(read_raw(&path).is_ok());
    let err = read_mesh(&path).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::Mesh {
                source: tessella_core::MeshError::ZeroArea { face: 0 },
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("flat.obj"), "{err}");
}
