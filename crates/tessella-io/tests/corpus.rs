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
