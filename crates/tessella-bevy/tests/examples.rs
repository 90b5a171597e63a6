//! The showcase examples (`gltf_scene`, `skinned`, `lod_scene`) run headless on lavapipe and
//! draw their subjects over the ground, without an error in the log; the LOD
//! scene draws more triangles for the creatures near the camera than for the far ones.

mod common;

use std::path::Path;
use std::process::Command;

/// Runs an example headless; returns its stdout and the pixels of its subjects: neither the
/// sky (the clear colour) nor the ground (warm: red above blue).
fn run(name: &str, args: &[&str]) -> (String, usize) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("examples");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(format!("{name}.png"));
    let mut cmd = Command::new(common::example(name));
    cmd.args(args)
        .args(["--size", "200x150", "--screenshot"])
        .arg(&out);
    let (stdout, _) = common::run(cmd);
    let img = image::open(&out).unwrap().to_rgba8();
    let sky = [237i32, 240, 245];
    let blue = img
        .pixels()
        .filter(|p| {
            let [r, g, b] = [0, 1, 2].map(|c| p.0[c] as i32);
            let is_sky = (0..3).all(|c| (p.0[c] as i32 - sky[c]).abs() <= 6);
            let is_ground = b < r - 10;
            !is_sky && !is_ground && g > 0
        })
        .count();
    (stdout, blue)
}

#[test]
fn gltf_scene_draws_its_tessellated_meshes() {
    let (_, blue) = run("gltf_scene", &["--level", "6"]);
    eprintln!("gltf_scene: {blue} pixels of the subject");
    assert!(blue > 1000, "only {blue} pixels of the subject");
}

#[test]
fn skinned_draws_the_playing_character() {
    let (_, blue) = run("skinned", &["--clip", "hop"]);
    eprintln!("skinned: {blue} pixels of the subject");
    assert!(blue > 1000, "only {blue} pixels of the subject");
}

#[test]
fn lod_scene_draws_near_creatures_finer() {
    let (stdout, blue) = run("lod_scene", &[]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("{\"triangles\""))
        .unwrap_or_else(|| panic!("no triangles line in {stdout}"));
    let per: Vec<u64> = line
        .trim_start_matches("{\"triangles\":[")
        .trim_end_matches("]}")
        .split(',')
        .map(|n| n.trim().parse().unwrap())
        .collect();
    eprintln!("lod_scene: {blue} pixels, triangles per creature {per:?}");
    assert_eq!(per.len(), 16);
    assert!(blue > 1000, "only {blue} pixels of the subjects");
    let (max, min) = (per.iter().max().unwrap(), per.iter().min().unwrap());
    assert!(
        *max > 4 * *min,
        "triangles {per:?}: the near ones are not finer"
    );
}
