//! Replays the fuzz targets' committed inputs (`fuzz/regressions/<target>/`: inputs that once
//! crashed; `fuzz/seeds/<target>/`: the seed corpus) through the same harness functions the
//! targets call (`tessella_io::fuzzing`), so CI keeps every fuzz finding fixed without nightly
//! or cargo-fuzz.
use std::path::{Path, PathBuf};
use tessella_io::{fuzzing, Format};

const TARGETS: [&str; 7] = [
    "obj",
    "ply_ascii",
    "ply_binary",
    "gltf",
    "stl",
    "tags_json",
    "refine",
];

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// What the fuzz target `target` does with one input (fuzz/fuzz_targets/<target>.rs).
fn run_target(target: &str, data: &[u8]) -> bool {
    match target {
        "obj" => fuzzing::check_reader(Format::Obj, data),
        "ply_ascii" => fuzzing::check_reader(Format::Ply, &fuzzing::ply_input(false, data)),
        "ply_binary" => fuzzing::check_reader(Format::Ply, &fuzzing::ply_input(true, data)),
        "gltf" if data.starts_with(b"glTF") => fuzzing::check_reader(Format::Glb, data),
        "gltf" => fuzzing::check_reader(Format::Gltf, data),
        "stl" => fuzzing::check_reader(Format::Stl, data),
        "tags_json" => fuzzing::check_tags_json(data),
        "refine" => fuzzing::check_refine(data),
        _ => panic!("unknown fuzz target {target}"),
    }
}

fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = fuzz_dir().join(kind).join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|entries| entries.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    files.retain(|p| p.is_file() && !p.ends_with(".gitkeep"));
    files.sort();
    files
}

#[test]
fn every_fuzz_target_has_a_harness_and_seeds() {
    for target in TARGETS {
        let source = fuzz_dir().join(format!("fuzz_targets/{target}.rs"));
        assert!(source.is_file(), "{} missing", source.display());
        assert!(!inputs("seeds", target).is_empty(), "no seeds for {target}");
    }
}

#[test]
fn seed_corpus_replays_without_a_panic() {
    let mut accepted = 0;
    for target in TARGETS {
        for file in inputs("seeds", target) {
            let data = std::fs::read(&file).unwrap();
            accepted += usize::from(run_target(target, &data));
        }
    }
    // The seeds hold valid files of every kind, so the harness gets past the readers.
    assert!(accepted >= 12, "only {accepted} seeds gave a mesh");
}

#[test]
fn fuzz_regressions_replay_without_a_panic() {
    let mut count = 0;
    for target in TARGETS {
        for file in inputs("regressions", target) {
            let data = std::fs::read(&file).unwrap();
            let result = std::panic::catch_unwind(|| run_target(target, &data));
            assert!(result.is_ok(), "{target}: {} panics", file.display());
            count += 1;
        }
    }
    assert!(count >= 1, "no regression inputs found");
}

/// The one crash found so far: a GLB header declaring a total length under 12 bytes made the
/// `gltf` crate subtract with overflow (a panic in debug builds).
#[test]
fn glb_with_a_total_length_under_its_header_is_an_error() {
    let data =
        std::fs::read(fuzz_dir().join("regressions/gltf/glb-total-length-under-header")).unwrap();
    let err = fuzzing::read_bytes(Format::Glb, &data).unwrap_err();
    assert!(err.to_string().contains("total length of 7 bytes"), "{err}");
}

/// Found by the gltf target: a POSITION accessor index past the end of `accessors` made the
/// `gltf` crate's validation index out of bounds (a panic in every build).
#[test]
fn gltf_position_accessor_past_the_end_is_an_error() {
    let data =
        std::fs::read(fuzz_dir().join("regressions/gltf/position-accessor-out-of-range")).unwrap();
    let err = fuzzing::read_bytes(Format::Gltf, &data).unwrap_err();
    assert!(
        err.to_string()
            .contains("uses accessor 0, but the file has only 0 accessors"),
        "{err}"
    );
}

/// Found by the ply_binary target (a timeout): an element without properties and a count of
/// billions was read as empty rows for ever.
#[test]
fn ply_element_without_properties_is_an_error_at_once() {
    let data = std::fs::read(
        fuzz_dir().join("regressions/ply_binary/element-without-properties-huge-count"),
    )
    .unwrap();
    let start = std::time::Instant::now();
    let err = fuzzing::read_bytes(Format::Ply, &fuzzing::ply_input(true, &data)).unwrap_err();
    assert!(err.to_string().contains("but no properties"), "{err}");
    assert!(start.elapsed().as_secs() < 5);
}
