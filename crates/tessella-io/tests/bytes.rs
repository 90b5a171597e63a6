//! Files in memory (`write_mesh_bytes`, `read_mesh_bytes`: what the browser uses) hold the same
//! bytes as the files `write_mesh` writes, and read back to the mesh written.
use tessella_io::{read_mesh_bytes, write_mesh, write_mesh_bytes, Format, MeshView, WriteOptions};

#[test]
fn bytes_in_memory_equal_the_files_and_read_back() {
    let mesh = tessella_core::samples::icosphere(1);
    let dir = tempfile::tempdir().unwrap();
    for (name, format) in [
        ("m.obj", Format::Obj),
        ("m.ply", Format::Ply),
        ("m.gltf", Format::Gltf),
        ("m.glb", Format::Glb),
        ("m.stl", Format::Stl),
    ] {
        let path = dir.path().join(name);
        write_mesh(&path, MeshView::from(&mesh), &WriteOptions::default()).unwrap();
        let bytes = write_mesh_bytes(format, MeshView::from(&mesh)).unwrap();
        assert_eq!(bytes, std::fs::read(&path).unwrap(), "{name}");
        let back = read_mesh_bytes(name, &bytes, &[]).unwrap();
        assert_eq!(back.face_count(), mesh.face_count(), "{name}");
        // OBJ and STL renumber the vertices: compare the sets of points.
        let sorted = |p: &[[f32; 3]]| {
            let mut bits: Vec<[u32; 3]> = p.iter().map(|v| v.map(f32::to_bits)).collect();
            bits.sort();
            bits
        };
        assert_eq!(sorted(back.positions()), sorted(mesh.positions()), "{name}");
    }
}

#[test]
fn a_bad_mesh_is_refused_before_anything_is_encoded() {
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let view = MeshView {
        positions: &positions,
        normals: None,
        uvs: None,
        triangles: &[[0, 1, 7]],
    };
    let err = write_mesh_bytes(Format::Glb, view).unwrap_err();
    assert!(err.to_string().contains('7'), "{err}");
}
