//! `tessella refine` and `info` on glTF scenes: the scene written back, the options a scene
//! refuses, broken inputs leaving no output.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../samples")
        .join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn json_of(glb: &Path) -> Value {
    let bytes = std::fs::read(glb).unwrap();
    let glb = gltf::Glb::from_slice(&bytes).unwrap();
    serde_json::from_slice(&glb.json).unwrap()
}

#[test]
fn refine_writes_the_scene_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene-pn4.glb");
    let o = tessella(&[
        "refine",
        s(&sample("scene.glb")),
        "-o",
        s(&out),
        "--level",
        "4",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("3 primitives of 3 meshes"),
        "{}",
        text(&o)
    );
    let (a, b) = (json_of(&sample("scene.glb")), json_of(&out));
    for key in [
        "nodes",
        "materials",
        "textures",
        "images",
        "cameras",
        "animations",
        "meshes",
    ] {
        assert_eq!(
            a[key].as_array().map(Vec::len),
            b[key].as_array().map(Vec::len),
            "{key}"
        );
    }
    assert_eq!(a["nodes"], b["nodes"]);
    // --flatten: the old merged mesh, one primitive, no materials.
    let flat = dir.path().join("flat.glb");
    let o = tessella(&[
        "refine",
        s(&sample("scene-quantized.glb")),
        "-o",
        s(&flat),
        "--level",
        "2",
        "--flatten",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let merged = json_of(&flat);
    assert_eq!(merged["meshes"].as_array().unwrap().len(), 1);
    assert!(merged.get("materials").is_none());
}

#[test]
fn max_edge_chooses_levels_and_info_shows_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene.gltf");
    let o = tessella(&[
        "refine",
        s(&sample("scene.glb")),
        "-o",
        s(&out),
        "--max-edge",
        "0.05",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("level 4/6"), "{}", text(&o));
    assert!(dir.path().join("scene.bin").is_file());
    let info = tessella(&["info", s(&sample("scene.glb")), "--max-edge", "0.05"]);
    let shown = text(&info);
    assert!(info.status.success(), "{shown}");
    assert!(
        shown.contains("mesh 0 primitive 1  170 triangles (2 degenerate), level 6"),
        "{shown}"
    );
    assert!(
        shown.contains("mesh 1 primitive 0  576 triangles (0 degenerate), level 4"),
        "{shown}"
    );
    let o = tessella(&[
        "refine",
        s(&sample("icosphere.obj")),
        "-o",
        s(&dir.path().join("x.ply")),
        "--max-edge",
        "0.1",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("--max-edge chooses a level per glTF primitive"),
        "{}",
        text(&o)
    );
}

#[test]
fn options_for_one_merged_mesh_are_refused_for_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.glb");
    let input = sample("scene.glb");
    for flags in [
        &["--lod", "tolerance:0.01"][..],
        &["--spacing", "fractional-odd", "--level", "3.5"],
        &["--level", "2.5"],
        &["--displace", "sine:0.05,10"],
        &["--crease-angle", "30"],
        &["--soup"],
    ] {
        let mut args = vec!["refine", s(&input), "-o", s(&out)];
        args.extend_from_slice(flags);
        let o = tessella(&args);
        assert!(!o.status.success(), "{flags:?} was accepted");
        assert!(text(&o).contains("--flatten"), "{flags:?}: {}", text(&o));
        assert!(!out.exists(), "{flags:?} left a file");
    }
}

#[test]
fn a_broken_scene_leaves_no_output_and_keeps_an_old_one() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(sample("scene.glb")).unwrap();
    let broken = dir.path().join("broken.glb");
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    let out = dir.path().join("out.glb");
    let o = tessella(&["refine", s(&broken), "-o", s(&out), "--level", "2"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("broken.glb"), "{}", text(&o));
    assert!(!out.exists());
    std::fs::write(&out, b"old").unwrap();
    let o = tessella(&["refine", s(&broken), "-o", s(&out), "--level", "2"]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"old");
    // Absurd levels are refused by the size cap, before anything is written.
    let o = tessella(&[
        "refine",
        s(&sample("scene.glb")),
        "-o",
        s(&dir.path().join("huge.glb")),
        "--level",
        "60000",
    ]);
    assert!(!o.status.success());
    assert!(text(&o).contains("over the limit"), "{}", text(&o));
    assert!(!dir.path().join("huge.glb").exists());
}

#[test]
fn batch_refines_scenes_too() {
    let dir = tempfile::tempdir().unwrap();
    let o = tessella(&[
        "batch",
        s(&sample("scene.glb")),
        s(&sample("animated-creature.glb")),
        "-o",
        s(dir.path()),
        "--format",
        "glb",
        "--level",
        "2",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let creature = json_of(&dir.path().join("animated-creature.glb"));
    assert_eq!(creature["animations"].as_array().unwrap().len(), 3);
    assert_eq!(creature["skins"].as_array().unwrap().len(), 1);
}

/// `--joint-sets`: more influence sets where a refined vertex needs them, refused with a
/// clear message for a bad count and for outputs that are not a scene.
#[test]
fn joint_sets_widen_skins_and_are_refused_outside_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.glb");
    let input = sample("animated-creature.glb");
    let sets = |extra: &[&str]| {
        let mut args = vec!["refine", s(&input), "-o", s(&out), "--level", "3"];
        args.extend_from_slice(extra);
        let o = tessella(&args);
        assert!(o.status.success(), "{}", text(&o));
        let json = json_of(&out);
        let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
        (0..)
            .take_while(|k| attributes[format!("JOINTS_{k}")].is_u64())
            .count()
    };
    // The creature's seven joints fit its two sets: nothing to add.
    assert_eq!(sets(&[]), 2);
    assert_eq!(sets(&["--joint-sets", "8"]), 2);
    for bad in ["0", "9", "many"] {
        let o = tessella(&["refine", s(&input), "-o", s(&out), "--joint-sets", bad]);
        assert!(!o.status.success());
        assert!(
            text(&o).contains("--joint-sets takes input or a number of sets from 1 to 8"),
            "{}",
            text(&o)
        );
    }
    let o = tessella(&[
        "refine",
        s(&input),
        "-o",
        s(&dir.path().join("x.ply")),
        "--joint-sets",
        "2",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("--joint-sets and --tangents shape a glTF scene"),
        "{}",
        text(&o)
    );
}
