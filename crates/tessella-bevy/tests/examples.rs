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

/// A glTF textured with a JPEG (the image format most glTF files use besides PNG) draws its
/// texture: the examples enable Bevy's JPEG decoder. A glTF that cannot load (its buffer
/// missing) is an error exit naming the file, not a blank picture and exit 0.
#[test]
fn gltf_scene_draws_a_jpeg_texture_and_refuses_a_broken_file() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("jpeg");
    std::fs::create_dir_all(&dir).unwrap();
    let mut jpeg = Vec::new();
    image::RgbImage::from_pixel(8, 8, image::Rgb([30, 200, 40]))
        .write_to(
            &mut std::io::Cursor::new(&mut jpeg),
            image::ImageFormat::Jpeg,
        )
        .unwrap();
    let sphere = tessella_bevy::tessella_core::samples::icosphere(1);
    let file = common::write_gltf(&dir, "green", &sphere, true, Some(&jpeg));
    let out = dir.join("green.png");
    let mut cmd = Command::new(common::example("gltf_scene"));
    cmd.arg(&file)
        .args(["--level", "4", "--size", "200x150", "--screenshot"])
        .arg(&out);
    common::run(cmd);
    let img = image::open(&out).unwrap().to_rgba8();
    let green = img
        .pixels()
        .filter(|p| {
            let [r, g, b] = [0, 1, 2].map(|c| p.0[c] as i32);
            g > r + 40 && g > b + 40
        })
        .count();
    eprintln!("jpeg: {green} green pixels");
    assert!(green > 1000, "only {green} pixels of the green texture");

    let broken = common::write_gltf(&dir, "broken", &sphere, true, None);
    std::fs::remove_file(dir.join("broken.bin")).unwrap();
    let shot = dir.join("broken.png");
    match std::fs::remove_file(&shot) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => panic!("{}: {e}", shot.display()),
        _ => {}
    }
    let failed = Command::new(common::example("gltf_scene"))
        .arg(&broken)
        .args(["--size", "200x150", "--screenshot"])
        .arg(&shot)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&failed.stderr);
    assert!(!failed.status.success(), "a broken file exits 0: {stderr}");
    assert!(
        stderr.contains("broken"),
        "the error does not name the file: {stderr}"
    );
    assert!(
        !shot.exists(),
        "a picture was written for a file that did not load"
    );
}
