mod common;

use common::{bits3, Sample};
use std::fs;
use tessella_io::{read_mesh, read_raw, write_mesh, IoError, MeshView, WriteOptions};

/// Two triangles of the unit square sharing the edge (1,0,0)-(0,1,0). The second triangle
/// writes one shared coordinate as -0, which must weld with 0; facet normals are wrong on
/// purpose, since they are ignored.
const ASCII: &str = "solid square
  facet normal 0 0 -1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 0 1 0
    endloop
  endfacet
  facet normal 1 0 0
    outer loop
      vertex 1 0 0
      vertex 1 1 0
      vertex 0 1 -0
    endloop
  endfacet
endsolid square
";

fn expected() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    (
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [1, 3, 2]],
    )
}

#[test]
fn ascii_corners_with_equal_positions_are_welded() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("square.stl");
    fs::write(&path, ASCII).unwrap();
    let raw = read_raw(&path).unwrap();
    let (positions, triangles) = expected();
    assert_eq!(bits3(&raw.positions), bits3(&positions));
    assert_eq!(raw.triangles, triangles);
    assert!(raw.normals.is_none() && raw.uvs.is_none());
    // Smooth normals come from the core: +Z everywhere, not the file's facet normals.
    let mesh = read_mesh(&path).unwrap();
    assert!(mesh.normals().iter().all(|n| *n == [0.0, 0.0, 1.0]));
}

/// The same square as binary STL; the 80-byte header starts with "solid", as some exporters
/// write it, which must not make the file look like ascii.
fn binary() -> Vec<u8> {
    let mut bytes = b"solid square, but binary".to_vec();
    bytes.resize(80, b' ');
    bytes.extend(2u32.to_le_bytes());
    let facets = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, -0.0f32]],
    ];
    for facet in facets {
        bytes.extend([0u8; 12]);
        for corner in facet {
            for c in corner {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

#[test]
fn binary_corners_are_welded_even_with_a_solid_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("square_bin.stl");
    fs::write(&path, binary()).unwrap();
    let raw = read_raw(&path).unwrap();
    let (positions, triangles) = expected();
    assert_eq!(bits3(&raw.positions), bits3(&positions));
    assert_eq!(raw.triangles, triangles);
}

#[test]
fn truncated_binary_is_a_parse_error() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = binary();
    for cut in [bytes.len() - 1, bytes.len() - 50, 90, 83] {
        let path = dir.path().join(format!("cut{cut}.stl"));
        fs::write(&path, &bytes[..cut]).unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(matches!(err, IoError::Parse { .. }), "cut {cut}: {err}");
    }
}

#[test]
fn unnamed_solid_is_read_as_ascii() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("unnamed.stl");
    fs::write(&path, ASCII.replacen("solid square", "solid", 1)).unwrap();
    assert_eq!(read_raw(&path).unwrap().triangles, expected().1);
}

#[test]
fn round_trip_keeps_positions_and_drops_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sample.stl");
    let sample = Sample::new();
    write_mesh(&path, sample.view(), &WriteOptions::default()).unwrap();
    // 80-byte header, count, 50 bytes per facet.
    assert_eq!(fs::read(&path).unwrap().len(), 84 + 50 * 4);
    let raw = read_raw(&path).unwrap();
    assert_eq!(bits3(&raw.positions), bits3(&sample.positions));
    assert_eq!(raw.triangles, sample.triangles);
    assert!(raw.normals.is_none() && raw.uvs.is_none());
    // The view without attributes writes the same bytes.
    let bare = dir.path().join("bare.stl");
    let view = MeshView {
        normals: None,
        uvs: None,
        ..sample.view()
    };
    write_mesh(&bare, view, &WriteOptions::default()).unwrap();
    assert_eq!(fs::read(&bare).unwrap(), fs::read(&path).unwrap());
}
