//! Bad input of every kind gives an `IoError` naming the file, never a panic.
mod common;

use std::fs;
use tessella_io::{read_mesh, read_raw, write_mesh, Format, IoError, WriteOptions};

const EXTENSIONS: [&str; 5] = ["obj", "ply", "gltf", "glb", "stl"];

#[test]
fn empty_files_are_errors_for_every_format() {
    let dir = tempfile::tempdir().unwrap();
    for ext in EXTENSIONS {
        let path = dir.path().join(format!("empty.{ext}"));
        fs::write(&path, "").unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(
            matches!(err, IoError::Parse { .. } | IoError::NoTriangles { .. }),
            "{ext}: {err}"
        );
        assert!(err.to_string().contains(&format!("empty.{ext}")), "{err}");
        assert!(read_mesh(&path).is_err());
    }
}

#[test]
fn files_without_triangles_are_no_triangles_errors() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "points.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n".to_string(),
        ),
        (
            "points.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
property float z\nend_header\n0 0 0\n"
                .to_string(),
        ),
        ("empty_solid.stl", "solid x\nendsolid x\n".to_string()),
    ];
    for (name, text) in cases {
        let path = dir.path().join(name);
        fs::write(&path, text).unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(matches!(err, IoError::NoTriangles { .. }), "{name}: {err}");
    }
}

#[test]
fn unknown_extensions_list_the_supported_ones() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["mesh.fbx", "mesh", "mesh.obj.bak"] {
        let path = dir.path().join(name);
        fs::write(&path, "v 0 0 0\n").unwrap();
        let err = read_raw(&path).unwrap_err();
        assert!(matches!(err, IoError::UnknownExtension { .. }), "{err}");
        let message = err.to_string();
        for ext in EXTENSIONS {
            assert!(message.contains(&format!(".{ext}")), "{message}");
        }
        let written = write_mesh(
            &path,
            common::Sample::new().view(),
            &WriteOptions::default(),
        );
        assert!(matches!(written, Err(IoError::UnknownExtension { .. })));
    }
    assert_eq!(Format::from_path("A.GLB".as_ref()).unwrap(), Format::Glb);
}

#[test]
fn missing_file_is_a_read_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.ply");
    let err = read_raw(&path).unwrap_err();
    assert!(matches!(err, IoError::Read { .. }), "{err}");
    assert!(err.to_string().contains("absent.ply"), "{err}");
}

/// Deterministic junk bytes (an LCG), with and without each format's magic words in front.
#[test]
fn random_junk_never_panics() {
    let dir = tempfile::tempdir().unwrap();
    let mut state = 12345u64;
    let mut junk = |len: usize| -> Vec<u8> {
        (0..len)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 56) as u8
            })
            .collect()
    };
    let prefixes: [&[u8]; 6] = [
        b"",
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
        b"glTF\x02\x00\x00\x00",
        b"solid ",
        b"v 0 0 0\nf ",
        b"{\"asset\":{\"version\":\"2.0\"},",
    ];
    for (round, len) in [0usize, 1, 7, 84, 300, 5000].into_iter().enumerate() {
        for prefix in prefixes {
            for ext in EXTENSIONS {
                let path = dir.path().join(format!("junk{round}.{ext}"));
                let mut bytes = prefix.to_vec();
                bytes.extend(junk(len));
                fs::write(&path, bytes).unwrap();
                // Whatever the outcome, it must be a value, not a panic.
                let _ = read_mesh(&path);
            }
        }
    }
}
