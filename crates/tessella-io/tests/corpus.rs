//! The bad-input corpus at the repository root (`tests/corpus/`, described by
//! `tests/corpus/expected.json`): every bad file is an error containing its expected text, every
//! good file loads with its expected counts. The CLI and Python tests run the same files.
use serde_json::Value;
use std::path::{Path, PathBuf};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus")
}

fn manifest() -> Value {
    let text = std::fs::read_to_string(corpus().join("expected.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn the_manifest_lists_every_file_and_at_least_forty_bad_ones() {
    let manifest = manifest();
    for kind in ["bad", "good"] {
        let listed = manifest[kind].as_object().unwrap();
        let mut files: Vec<String> = std::fs::read_dir(corpus().join(kind))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            // A glTF's external buffer is data, not a mesh file.
            .filter(|name| !name.ends_with(".bin"))
            .collect();
        files.sort();
        let mut names: Vec<String> = listed.keys().cloned().collect();
        names.sort();
        assert_eq!(files, names, "{kind}/ and expected.json disagree");
    }
    assert!(manifest["bad"].as_object().unwrap().len() >= 40);
}

#[test]
fn every_bad_file_is_refused_with_its_message() {
    for (name, expected) in manifest()["bad"].as_object().unwrap() {
        let path = corpus().join("bad").join(name);
        let expected = expected.as_str().unwrap();
        let result = std::panic::catch_unwind(|| tessella_io::read_mesh(&path));
        let Ok(result) = result else {
            panic!("{name}: the reader panicked");
        };
        let err = match result {
            Ok(mesh) => panic!("{name} loaded ({} vertices)", mesh.vertex_count()),
            Err(err) => err,
        };
        let message = format!(
            "{err} {}",
            std::error::Error::source(&err).map_or(String::new(), |s| s.to_string())
        );
        assert!(
            message.contains(expected),
            "{name}: {message:?} lacks {expected:?}"
        );
    }
}

#[test]
fn every_good_file_loads_with_its_counts() {
    for (name, counts) in manifest()["good"].as_object().unwrap() {
        let path = corpus().join("good").join(name);
        let mesh = tessella_io::read_mesh(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            mesh.vertex_count() as u64,
            counts["vertices"].as_u64().unwrap(),
            "{name}"
        );
        assert_eq!(
            mesh.face_count() as u64,
            counts["triangles"].as_u64().unwrap(),
            "{name}"
        );
    }
}

/// The same files read from memory, as the browser reads them (`read_mesh_bytes`): the same
/// messages, and a `.gltf` file's external buffer comes from the bytes given with it.
#[test]
fn the_corpus_read_from_bytes_gives_the_same_results() {
    let manifest = manifest();
    for (name, expected) in manifest["bad"].as_object().unwrap() {
        let bytes = std::fs::read(corpus().join("bad").join(name)).unwrap();
        let expected = expected.as_str().unwrap();
        let err = match tessella_io::read_mesh_bytes(name, &bytes, &[]) {
            Ok(mesh) => panic!("{name} loaded ({} vertices)", mesh.vertex_count()),
            Err(err) => err,
        };
        let message = format!(
            "{err} {}",
            std::error::Error::source(&err).map_or(String::new(), |s| s.to_string())
        );
        assert!(
            message.contains(expected),
            "{name}: {message:?} lacks {expected:?}"
        );
    }
    let buffer = std::fs::read(corpus().join("good/buffer data.bin")).unwrap();
    for (name, counts) in manifest["good"].as_object().unwrap() {
        let bytes = std::fs::read(corpus().join("good").join(name)).unwrap();
        let given = [("buffer data.bin", buffer.as_slice())];
        let mesh = tessella_io::read_mesh_bytes(name, &bytes, &given)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            (mesh.vertex_count() as u64, mesh.face_count() as u64),
            (
                counts["vertices"].as_u64().unwrap(),
                counts["triangles"].as_u64().unwrap()
            ),
            "{name}"
        );
    }
    // Without its buffer the external-buffer file is refused, naming the file it needs.
    let bytes = std::fs::read(corpus().join("good/gltf-external-buffer.gltf")).unwrap();
    let err = tessella_io::read_mesh_bytes("gltf-external-buffer.gltf", &bytes, &[]).unwrap_err();
    assert!(err.to_string().contains("buffer%20data.bin"), "{err}");
}
