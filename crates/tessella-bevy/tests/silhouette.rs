//! The plugin's pictures against `tessella render` (the independent reference: tessella's own
//! renderer, not Bevy) of the same mesh, scheme, level and camera: the silhouettes agree
//! (IoU ≥ 0.98); removing `Tessellate` brings back the plain mesh's silhouette, which
//! `tessella render --scheme flat` (the coarse triangles) draws.
//!
//! Runs the `view` example (which `cargo test` builds) and the CLI binary of the root
//! workspace (`TESSELLA_BIN`, else `target/release/tessella`, else `target/debug/tessella`), headless on
//! whatever Vulkan device there is (lavapipe on a machine without a GPU).

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn cli() -> PathBuf {
    if let Some(bin) = std::env::var_os("TESSELLA_BIN") {
        return PathBuf::from(bin);
    }
    ["target/release/tessella", "target/debug/tessella"]
        .iter()
        .map(|p| repo().join(p))
        .find(|p| p.exists())
        .expect(
            "no tessella CLI: run `cargo build -p tessella-cli` (or --release) in the repository \
             root, or set TESSELLA_BIN",
        )
}

fn view_example() -> PathBuf {
    // CARGO_TARGET_TMPDIR is <target>/tmp; `cargo test` builds the examples into
    // <target>/<profile>/examples.
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("..");
    let profile = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let bin = target.join(profile).join("examples/view");
    assert!(
        bin.exists(),
        "{} is missing (cargo test builds it)",
        bin.display()
    );
    bin
}

fn run(mut cmd: Command) {
    let out = cmd.output().expect("the command starts");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}\n{stderr}",
        String::from_utf8_lossy(&out.stdout),
    );
    // Bevy logs wgpu validation errors and shader errors (and draws on): a picture is not
    // enough, the log must be clean too.
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("ERROR")).collect();
    assert!(
        errors.is_empty(),
        "{cmd:?} logged errors:\n{}",
        errors.join("\n")
    );
}

/// Pixels that differ from the white background by more than a little.
fn silhouette(path: &Path) -> (Vec<bool>, (u32, u32)) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    let mask = img
        .pixels()
        .map(|p| p.0[..3].iter().any(|&c| c < 215))
        .collect();
    (mask, img.dimensions())
}

fn iou(a: &Path, b: &Path) -> f64 {
    let (ma, da) = silhouette(a);
    let (mb, db) = silhouette(b);
    assert_eq!(da, db, "{} and {} differ in size", a.display(), b.display());
    let inter = ma.iter().zip(&mb).filter(|(x, y)| **x && **y).count();
    let union = ma.iter().zip(&mb).filter(|(x, y)| **x || **y).count();
    assert!(
        union > 100,
        "{} and {} show nothing",
        a.display(),
        b.display()
    );
    inter as f64 / union as f64
}

const SIZE: &str = "192x192";

fn cli_render(
    dir: &Path,
    name: &str,
    file: &str,
    scheme: &str,
    level: u32,
    view: &[&str],
) -> PathBuf {
    let out = dir.join(format!("{name}.png"));
    let mut cmd = Command::new(cli());
    cmd.arg("render")
        .arg(repo().join(file))
        .args([
            "--scheme",
            scheme,
            "--level",
            &level.to_string(),
            "--size",
            SIZE,
        ])
        .args(view)
        .arg("-o")
        .arg(&out);
    run(cmd);
    out
}

#[test]
fn tessellated_entity_matches_tessella_render_and_removing_it_brings_the_plain_mesh_back() {
    let dir = tempfile_dir("silhouette");
    for (file, scheme, level, view) in [
        (
            "samples/tetrahedron.obj",
            "pn",
            8u32,
            ["--yaw", "30", "--pitch", "20", "--zoom", "1"],
        ),
        (
            "samples/torus.obj",
            "phong",
            6,
            ["--yaw", "-40", "--pitch", "35", "--zoom", "1.3"],
        ),
    ] {
        let stem = Path::new(file)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_string();
        let tessellated = dir.join(format!("{stem}-bevy-{scheme}.png"));
        let plain = dir.join(format!("{stem}-bevy-plain.png"));
        let mut cmd = Command::new(view_example());
        cmd.arg(repo().join(file))
            .args([
                "--scheme",
                scheme,
                "--level",
                &level.to_string(),
                "--size",
                SIZE,
            ])
            .args(view)
            .arg("--screenshot")
            .arg(&tessellated)
            .arg("--then-plain")
            .arg(&plain);
        run(cmd);
        let reference = cli_render(
            &dir,
            &format!("{stem}-cli-{scheme}"),
            file,
            scheme,
            level,
            &view,
        );
        let reference_flat = cli_render(&dir, &format!("{stem}-cli-flat"), file, "flat", 1, &view);
        let curved = iou(&tessellated, &reference);
        let flat = iou(&plain, &reference_flat);
        let changed = iou(&tessellated, &plain);
        eprintln!("{file} {scheme} {level}: IoU tessellated/CLI {curved:.4}, plain/CLI flat {flat:.4}, tessellated/plain {changed:.4}");
        assert!(
            curved >= 0.98,
            "{file}: tessellated vs tessella render IoU {curved}"
        );
        assert!(
            flat >= 0.98,
            "{file}: plain vs tessella render --scheme flat IoU {flat}"
        );
        // The curved surface's silhouette is not the coarse one's: Tessellate changed it.
        assert!(changed < 0.97, "{file}: tessellated vs plain IoU {changed}");
    }
}

fn tempfile_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn rgb(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// Fraction of pixels whose colours differ by more than `tol` in some channel, and how many
/// pixels of `a` are darker than `b`'s by more than `tol` in every channel.
fn differ(a: &Path, b: &Path, tol: i32) -> (f64, usize) {
    let (a, b) = (rgb(a), rgb(b));
    assert_eq!(a.dimensions(), b.dimensions());
    let mut diff = 0;
    let mut darker = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d: Vec<i32> = (0..3).map(|c| p.0[c] as i32 - q.0[c] as i32).collect();
        if d.iter().any(|x| x.abs() > tol) {
            diff += 1;
        }
        if d.iter().all(|&x| x < -tol) {
            darker += 1;
        }
    }
    (diff as f64 / (a.width() * a.height()) as f64, darker)
}

/// Bevy's PBR of the tessellated entity, over a ground plane that receives its shadow, against
/// Bevy's PBR of the same surface refined offline by `tessella refine` and loaded as a plain
/// mesh (framed by the coarse mesh's camera): the lit surface, its normals and the shadow it
/// casts (drawn by the extension's prepass vertex stage) agree; and the light's shadow is
/// there (the ground darkens where it falls).
#[test]
fn tessellated_shading_and_shadow_match_the_offline_refined_mesh() {
    let dir = tempfile_dir("shading");
    let (file, scheme, level) = ("samples/torus.obj", "phong", 6u32);
    let refined = dir.join("torus-refined.obj");
    let mut cmd = Command::new(cli());
    cmd.arg("refine")
        .arg(repo().join(file))
        .args(["--scheme", scheme, "--level", &level.to_string()])
        .arg("-o")
        .arg(&refined);
    run(cmd);
    let view = |name: &str, extra: &[&str], input: &Path| {
        let out = dir.join(format!("{name}.png"));
        let mut cmd = Command::new(view_example());
        cmd.arg(input)
            .args(["--size", SIZE, "--ground", "--scheme", scheme])
            .args(["--level", &level.to_string()])
            .args(extra)
            .arg("--screenshot")
            .arg(&out);
        run(cmd);
        out
    };
    let coarse = repo().join(file);
    let tessellated = view("tessellated", &[], &coarse);
    let frame = coarse.to_string_lossy().to_string();
    let offline = view("offline", &["--plain", "--frame", &frame], &refined);
    let unshadowed = view("no-shadows", &["--no-shadows"], &coarse);
    let (d, _) = differ(&tessellated, &offline, 24);
    let (_, shadowed) = differ(&tessellated, &unshadowed, 24);
    eprintln!(
        "tessellated vs offline: {:.4} of the pixels differ; {shadowed} pixels in shadow",
        d
    );
    assert!(
        d < 0.01,
        "{:.4} of the pixels differ from the offline-refined mesh's",
        d
    );
    assert!(
        shadowed > 200,
        "only {shadowed} pixels darkened by the shadow"
    );
}
