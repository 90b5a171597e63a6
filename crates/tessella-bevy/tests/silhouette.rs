//! The plugin's pictures against `tessella render` (the independent reference: tessella's own
//! renderer, not Bevy) of the same mesh, scheme, level and camera: the silhouettes agree
//! (IoU ≥ 0.98); removing `Tessellate` brings back the plain mesh's silhouette, which
//! `tessella render --scheme flat` (the coarse triangles) draws.
//!
//! Runs the `view` example (which `cargo test` builds) and the CLI binary of the root
//! workspace (`TESSELLA_BIN`, else `target/release/tessella`, else `target/debug/tessella`), headless on
//! whatever Vulkan device there is (lavapipe on a machine without a GPU).

mod common;

use common::run;
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
    common::example("view")
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
    // A glTF without normals: Bevy's loader invents flat ones (splitting every vertex); the
    // plugin refines with computed smooth ones, as `tessella render` does with the same file.
    let no_normals = common::write_gltf(
        &dir,
        "tetrahedron-no-normals",
        &tessella_core::samples::tetrahedron(),
        false,
        None,
    );
    let no_normals = no_normals.to_string_lossy().to_string();
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
        (
            no_normals.as_str(),
            "pn",
            8,
            ["--yaw", "30", "--pitch", "20", "--zoom", "1"],
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

/// The three ways of drawing a uniform level, per frame (each refined vertex evaluated once a
/// frame by a compute pass), welded (each refined vertex evaluated once a pass) and in runs
/// (the pattern per triangle, 4 runs of 1456 triangles here), draw the same surface: the
/// pictures agree pixel for pixel but for a few edge pixels, and all match `tessella render`.
#[test]
fn per_frame_welded_and_run_draws_are_the_same_surface() {
    let dir = tempfile_dir("draws");
    let (file, scheme, level) = ("samples/icosphere-4k.obj", "pn", 8u32);
    let view = ["--yaw", "20", "--pitch", "15", "--zoom", "1"];
    let draw = |mode: &str| {
        let out = dir.join(format!("{mode}.png"));
        let mut cmd = Command::new(view_example());
        cmd.arg(repo().join(file))
            .args(["--scheme", scheme, "--level", &level.to_string()])
            .args(["--size", SIZE, "--draw", mode])
            .args(view)
            .arg("--screenshot")
            .arg(&out);
        run(cmd);
        out
    };
    let (per_frame, welded, runs) = (draw("per-frame"), draw("welded"), draw("runs"));
    let mesh = draw("mesh");
    let reference = cli_render(&dir, "cli", file, scheme, level, &view);
    let (d, _) = differ(&welded, &runs, 8);
    let (e, _) = differ(&per_frame, &welded, 8);
    let (m, _) = differ(&mesh, &welded, 8);
    let (a, b, c) = (
        iou(&welded, &reference),
        iou(&runs, &reference),
        iou(&per_frame, &reference),
    );
    eprintln!("welded vs runs: {d:.5} of the pixels differ, per frame vs welded {e:.5}, mesh vs welded {m:.5}; IoU with CLI {a:.4} / {b:.4} / {c:.4}");
    assert!(
        m < 0.002,
        "{m} of the pixels differ between the mesh draw and welded"
    );
    assert!(
        d < 0.002,
        "{d} of the pixels differ between welded and runs"
    );
    assert!(
        e < 0.002,
        "{e} of the pixels differ between per frame and welded"
    );
    assert!(
        a >= 0.98 && b >= 0.98 && c >= 0.98,
        "IoU with tessella render {a} / {b} / {c}"
    );
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

/// Renders `view` arguments with the example into `out`.
fn bevy_view(file: &str, args: &[&str], out: &Path) {
    let mut cmd = Command::new(view_example());
    cmd.arg(repo().join(file))
        .args(["--size", SIZE])
        .args(args)
        .arg("--screenshot")
        .arg(out);
    run(cmd);
}

const CREATURE: &str = "samples/animated-creature.glb";

/// The skinned, morphing creature loaded by Bevy's glTF loader and played by Bevy's
/// `AnimationPlayer` (held at a time): the tessellated surface's silhouette matches `tessella
/// render --clip --time` of the same file (tessella's own posing and renderer), for a skinning
/// clip with two influence sets, a translating one and a morph-weight one. Posed on the GPU
/// (the default: skinned and its nets built by tessella-gpu in Bevy's render world) and on
/// the CPU, the pictures agree but for a few edge pixels.
#[test]
fn skinned_character_played_by_bevy_matches_tessella_render_of_the_clip() {
    let dir = tempfile_dir("skinned");
    let camera = ["--yaw", "25", "--pitch", "15", "--zoom", "1"];
    let rest = dir.join("rest-bevy.png");
    let mut args = vec!["--scheme", "pn", "--level", "8"];
    args.extend(camera);
    bevy_view(CREATURE, &args, &rest);
    for (clip, time) in [("wave", "0.5"), ("hop", "0.3"), ("breathe", "1.2")] {
        let posed = dir.join(format!("{clip}-bevy.png"));
        let mut a = args.clone();
        a.extend(["--clip", clip, "--time", time]);
        bevy_view(CREATURE, &a, &posed);
        let on_cpu = dir.join(format!("{clip}-bevy-cpu.png"));
        a.extend(["--pose", "cpu"]);
        bevy_view(CREATURE, &a, &on_cpu);
        let mut view = camera.to_vec();
        view.extend(["--clip", clip, "--time", time]);
        let reference = cli_render(&dir, &format!("{clip}-cli"), CREATURE, "pn", 8, &view);
        let curved = iou(&posed, &reference);
        let moved = iou(&posed, &rest);
        let (apart, _) = differ(&posed, &on_cpu, 8);
        eprintln!("{clip} at {time}: IoU Bevy/CLI {curved:.4}, posed/rest {moved:.4}, GPU/CPU posing {apart:.5} of the pixels differ");
        assert!(
            apart < 0.002,
            "{clip}: {apart} of the pixels differ between GPU and CPU posing"
        );
        assert!(
            curved >= 0.98,
            "{clip}: Bevy vs tessella render IoU {curved}"
        );
        assert!(
            moved < curved,
            "{clip}: the posed picture is no nearer tessella's pose than the rest pose"
        );
    }
}

/// A crowd drawn `PerFrame` shares one material, so Bevy draws it in one batch a pass, each
/// copy reading its own slot of the pool's buffer (its `MeshTag`): nine copies held each at its
/// own time of a clip (`--stagger`), posed on the GPU and on the CPU, match the welded draw
/// (a material and an evaluation a copy) but for a few edge pixels, and are not the picture
/// of the nine at one time (a copy reading another's slot would draw the other's pose). The
/// default draw (`Mesh`: each copy's own mesh, written by the compute pass, drawn with the
/// copies' shared `StandardMaterial`, no tessellated material at all) matches too.
#[test]
fn a_crowd_shares_one_material_and_each_copy_draws_its_own_pose() {
    let dir = tempfile_dir("crowd");
    let base = [
        "--scheme", "pn", "--level", "4", "--crowd", "9", "--clip", "hop", "--time", "0.1",
        "--size", "256x256", "--frames", "1",
    ];
    let draw = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = base.to_vec();
        args.extend(extra);
        let stdout = view_stdout(CREATURE, &args, &out);
        let materials = stdout
            .lines()
            .filter_map(|l| l.split("\"tessella_materials\":").nth(1))
            .filter_map(|v| v.trim_end_matches('}').parse::<u32>().ok())
            .next_back()
            .unwrap_or_else(|| panic!("{name}: no material count in {stdout}"));
        (out, materials)
    };
    let stagger = ["--stagger", "0.13"];
    let pooled = ["--draw", "per-frame"];
    let (gpu, gpu_materials) = draw(
        "pooled-gpu",
        &[&stagger[..], &pooled, &["--pose", "gpu"]].concat(),
    );
    let (cpu, cpu_materials) = draw(
        "pooled-cpu",
        &[&stagger[..], &pooled, &["--pose", "cpu"]].concat(),
    );
    let (own, own_materials) = draw("welded", &[&stagger[..], &["--draw", "welded"]].concat());
    // The default draw: a mesh each, posed on the GPU.
    let (meshes, mesh_materials) = draw("meshes", &stagger);
    let (together, _) = draw("together", &pooled);
    // The mesh draw uses the entities' StandardMaterial: no tessellated material at all.
    assert_eq!(
        (gpu_materials, cpu_materials, own_materials, mesh_materials),
        (1, 1, 9, 0)
    );
    let (m, _) = differ(&meshes, &own, 8);
    assert!(
        m < 0.002,
        "{m} of the pixels differ between the mesh draw and welded"
    );
    let (a, _) = differ(&gpu, &own, 8);
    let (b, _) = differ(&cpu, &own, 8);
    let (c, _) = differ(&gpu, &together, 8);
    eprintln!("pooled vs welded: {a:.5} (GPU posing), {b:.5} (CPU); staggered vs together {c:.5}");
    assert!(a < 0.002 && b < 0.002, "{a} / {b} of the pixels differ");
    assert!(
        c > 0.01,
        "the staggered crowd looks like the crowd at one time ({c})"
    );
}

/// The creature refined offline (`tessella refine` writes the glTF scene back: skin, morph
/// targets and clips kept) plays in Bevy as a plain skinned mesh (Bevy's glTF loader, its own
/// skinning and morphing, no tessellation): its silhouette matches tessella's own posing of
/// the same file (`tessella render --clip --time --scheme flat --level 1`, which draws the
/// refined triangles as they are). How far refined-then-skinned lies from posed-then-refined is
/// measured in tessella-io's tests/scene.rs.
#[test]
fn the_offline_refined_character_plays_in_bevy() {
    let dir = tempfile_dir("refined-skinned");
    let refined = dir.join("creature-pn8.glb");
    let mut cmd = Command::new(cli());
    cmd.arg("refine")
        .arg(repo().join(CREATURE))
        .arg("-o")
        .arg(&refined)
        .args(["--scheme", "pn", "--level", "8"]);
    run(cmd);
    let file = refined.to_str().expect("a UTF-8 path");
    let camera = ["--yaw", "25", "--pitch", "15", "--zoom", "1"];
    for (clip, time) in [("wave", "0.5"), ("hop", "0.3"), ("breathe", "1.2")] {
        let posed = dir.join(format!("{clip}-bevy-plain.png"));
        let mut args = vec!["--plain"];
        args.extend(camera);
        args.extend(["--clip", clip, "--time", time]);
        bevy_view(file, &args, &posed);
        let mut view = camera.to_vec();
        view.extend(["--clip", clip, "--time", time]);
        let reference = cli_render(&dir, &format!("{clip}-cli"), file, "flat", 1, &view);
        let overlap = iou(&posed, &reference);
        eprintln!("refined offline, {clip} at {time}: IoU Bevy/CLI {overlap:.4}");
        assert!(
            overlap >= 0.98,
            "{clip}: the offline-refined file played by Bevy vs tessella render IoU {overlap}"
        );
    }
}

/// While Bevy plays a clip, each frame uploads the same bytes at levels 4 and 32: posed on the
/// CPU, the coarse mesh's control nets and nothing else, in proportion to the coarse
/// triangles; posed on the GPU (the default), the joint matrices and morph weights alone (64
/// bytes a deform matrix, 4 a weight, as tessella's own poser of the file counts them).
#[test]
fn a_deforming_entity_uploads_coarse_bytes_whatever_the_level() {
    let dir = tempfile_dir("stats");
    let triangles = tessella_io::read_mesh(&repo().join(CREATURE))
        .unwrap()
        .face_count() as u64;
    let model = tessella_io::read_animated(&repo().join(CREATURE)).unwrap();
    let poser = tessella_bevy::tessella_core::animation::Poser::new(model).unwrap();
    let deform = (poser.deform_matrix_count() * 64 + poser.morph_weight_count() * 4) as u64;
    for posing in ["cpu", "gpu"] {
        let mut per_level = Vec::new();
        for level in ["4", "32"] {
            let out = dir.join(format!("stats-{posing}-{level}.png"));
            let mut cmd = Command::new(view_example());
            cmd.arg(repo().join(CREATURE))
                .args(["--size", "96x96", "--scheme", "pn", "--level", level])
                .args(["--clip", "wave", "--time", "0.1", "--frames", "6"])
                .args(["--stats", "--pose", posing])
                .arg("--screenshot")
                .arg(&out);
            let (stdout, _) = run(cmd);
            let bytes = uploaded_bytes(&stdout);
            eprintln!("posed on the {posing}, level {level}: bytes per frame {bytes:?} for {triangles} coarse triangles");
            assert!(bytes.len() >= 4, "too few stats lines:\n{stdout}");
            // Every frame of a playing clip deforms. On the CPU each uploads at most 256
            // bytes a coarse triangle (PN's nets: 10 points and 6 normals of 16 bytes would
            // be 256); on the GPU the deform alone.
            for &b in &bytes {
                match posing {
                    "cpu" => assert!(b > deform && b <= 256 * triangles, "{b} bytes in a frame"),
                    _ => assert_eq!(b, deform, "bytes in a frame posed on the GPU"),
                }
            }
            per_level.push(bytes[1..].to_vec());
        }
        assert_eq!(
            per_level[0], per_level[1],
            "the upload depends on the level"
        );
    }
}

/// The per-frame draw (the default) evaluates a still surface once and a playing one once a
/// frame: the welded vertices evaluated so far stay at one surface's count while nothing
/// moves, and grow by that count with each frame of a playing clip. A playing surface binds
/// the same buffers each frame, so its bind group is made once. The welded draw, which
/// evaluates in its vertex stages, never runs the pass.
#[test]
fn the_per_frame_pass_runs_once_per_change() {
    let dir = tempfile_dir("evaluations");
    let view = |draw: &str, clip: bool| {
        let mut args = vec!["--size", "96x96", "--scheme", "pn", "--level", "4"];
        args.extend(["--draw", draw, "--frames", "6", "--stats"]);
        if clip {
            args.extend(["--clip", "wave", "--time", "0.1"]);
        }
        let out = dir.join(format!("{draw}-{clip}.png"));
        view_stdout(CREATURE, &args, &out)
    };
    let totals = |stdout: &str| {
        let totals = stat(stdout, "evaluated_vertices");
        assert!(totals.len() >= 4, "too few stats lines:\n{stdout}");
        totals
    };
    let stats = |draw: &str, clip: bool| totals(&view(draw, clip));
    let still = stats("per-frame", false);
    let once = still[0];
    eprintln!("still: {still:?}");
    assert!(once > 0, "the still surface was never evaluated");
    assert!(
        still.iter().all(|&t| t == once),
        "a still surface evaluated again"
    );
    let playing_run = view("per-frame", true);
    let playing = totals(&playing_run);
    eprintln!("playing: {playing:?}");
    // A frame's count lands when its render submits: a step may hold two frames or none,
    // never part of one.
    let steps: Vec<u64> = playing.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(
        steps.iter().all(|s| s % once == 0),
        "{steps:?} not whole surfaces"
    );
    let frames = (playing[playing.len() - 1] - playing[0]) / once;
    assert!(
        frames as usize >= steps.len() - 1,
        "{frames} evaluations in {} frames",
        steps.len()
    );
    let bind_groups = stat(&playing_run, "bind_groups");
    eprintln!("bind groups made: {bind_groups:?}");
    assert!(
        bind_groups.len() == playing.len() && bind_groups.iter().all(|&b| b == 1),
        "a playing surface made bind groups again: {bind_groups:?}"
    );
    let welded = stats("welded", true);
    assert!(
        welded.iter().all(|&t| t == 0),
        "the welded draw ran the pass: {welded:?}"
    );
}

/// The `uploaded_bytes` of each `--stats` line the example printed.
fn uploaded_bytes(stdout: &str) -> Vec<u64> {
    stat(stdout, "uploaded_bytes")
}

/// The `name` field of each `--stats` line the example printed.
fn stat(stdout: &str, name: &str) -> Vec<u64> {
    let key = format!("\"{name}\":");
    stdout
        .lines()
        .filter(|l| l.starts_with("{\"frame\""))
        .filter_map(|l| l.split(key.as_str()).nth(1))
        .map(|rest| rest.split([',', '}']).next().unwrap().parse().unwrap())
        .collect()
}

/// The JSON `pick` line the example printed: (hit, subject, depth).
fn picked(stdout: &str) -> (bool, bool, f64) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("{\"pick\""))
        .unwrap_or_else(|| panic!("no pick line in:\n{stdout}"));
    let field = |name: &str| {
        line.split(&format!("\"{name}\":"))
            .nth(1)
            .map(|r| r.split([',', '}']).next().unwrap().to_string())
    };
    let hit = field("hit").as_deref() == Some("true");
    let subject = field("subject").as_deref() == Some("true");
    let depth = field("depth").map_or(f64::NAN, |d| d.parse().unwrap());
    (hit, subject, depth)
}

/// Bevy's picking convention reaches the tessellated entity through its curved surface: a
/// pointer over a pixel that the curved patches cover but the coarse triangles do not
/// (found from `tessella render`'s pictures) hits the entity; with the plain mesh it hits
/// nothing. In the middle of the mesh both hit, the curved surface no farther away.
#[test]
fn picking_hits_the_curved_surface_not_the_coarse_mesh() {
    let dir = tempfile_dir("picking");
    let file = "samples/tetrahedron.obj";
    let view = ["--yaw", "30", "--pitch", "20", "--zoom", "1"];
    let curved = silhouette(&cli_render(&dir, "pn", file, "pn", 8, &view));
    let flat = silhouette(&cli_render(&dir, "flat", file, "flat", 1, &view));
    let ((curved, (w, h)), (flat, _)) = (curved, flat);
    let at = |m: &[bool], x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && m[(y * w as i64 + x) as usize]
    };
    // A pixel 3 pixels deep inside the curved silhouette and 3 pixels outside the flat one.
    let deep = |x: i64, y: i64, m: &[bool], want: bool| {
        (-3..=3).all(|dy| (-3..=3).all(|dx| at(m, x + dx, y + dy) == want))
    };
    let bulge = (0..h as i64)
        .flat_map(|y| (0..w as i64).map(move |x| (x, y)))
        .find(|&(x, y)| deep(x, y, &curved, true) && deep(x, y, &flat, false))
        .expect("no pixel where the curved surface bulges past the coarse one");
    // The coarse silhouette's centroid.
    let inside: Vec<(i64, i64)> = (0..h as i64)
        .flat_map(|y| (0..w as i64).map(move |x| (x, y)))
        .filter(|&(x, y)| at(&flat, x, y))
        .collect();
    let n = inside.len() as i64;
    let middle = inside
        .iter()
        .fold((0, 0), |(sx, sy), (x, y)| (sx + x, sy + y));
    let middle = (middle.0 / n, middle.1 / n);
    assert!(
        deep(middle.0, middle.1, &flat, true),
        "{middle:?} is not inside"
    );
    let pick = |(x, y): (i64, i64), plain: bool| {
        let mut cmd = Command::new(view_example());
        cmd.arg(repo().join(file))
            .args(["--size", SIZE, "--scheme", "pn", "--level", "8"])
            .args(view)
            .args(["--pick", &format!("{x},{y}")])
            .arg("--screenshot")
            .arg(dir.join("pick.png"));
        if plain {
            cmd.arg("--plain");
        }
        picked(&run(cmd).0)
    };
    let (hit, subject, _) = pick(bulge, false);
    eprintln!("bulge pixel {bulge:?}: tessellated hit {hit}, on the entity {subject}");
    assert!(
        hit && subject,
        "the curved surface at {bulge:?} was not picked"
    );
    let (hit, _, _) = pick(bulge, true);
    assert!(!hit, "the plain mesh was picked at {bulge:?}, outside it");
    let (hit, subject, curved_depth) = pick(middle, false);
    let (plain_hit, _, plain_depth) = pick(middle, true);
    eprintln!("middle pixel {middle:?}: depths tessellated {curved_depth}, plain {plain_depth}");
    assert!(hit && subject && plain_hit);
    assert!(
        curved_depth <= plain_depth + 1e-4,
        "the curved surface is behind the flat one"
    );
}

/// Picking reaches a character posed on the GPU (the default) where it is drawn, not at its
/// rest pose: with one camera (framed on the static creature), a pixel that the hop clip's pose
/// covers and the rest pose does not (3 pixels deep either way, from Bevy's pictures posed on
/// the CPU and at rest) picks the entity, and a pixel the rest pose covers and the hop's does
/// not picks nothing. Posed on the CPU, the same.
#[test]
fn picking_hits_the_gpu_posed_character_where_it_is_drawn() {
    let dir = tempfile_dir("picking-posed");
    let framing = repo().join("samples/creature.obj");
    let framing = framing.to_str().unwrap();
    let mut common = vec!["--size", SIZE, "--scheme", "pn", "--level", "8"];
    common.extend([
        "--yaw", "25", "--pitch", "15", "--zoom", "1", "--frame", framing,
    ]);
    let posed_args = ["--clip", "hop", "--time", "0.3"];
    let rest = dir.join("rest.png");
    bevy_view(CREATURE, &common, &rest);
    let posed = dir.join("posed.png");
    let mut args = common.clone();
    args.extend(posed_args);
    args.extend(["--pose", "cpu"]);
    bevy_view(CREATURE, &args, &posed);
    let ((rest, (w, h)), (posed, _)) = (silhouette(&rest), silhouette(&posed));
    let at = |m: &[bool], x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && m[(y * w as i64 + x) as usize]
    };
    let deep = |x: i64, y: i64, m: &[bool], want: bool| {
        (-3..=3).all(|dy| (-3..=3).all(|dx| at(m, x + dx, y + dy) == want))
    };
    let find = |inside: &[bool], outside: &[bool]| {
        (0..h as i64)
            .flat_map(|y| (0..w as i64).map(move |x| (x, y)))
            .find(|&(x, y)| deep(x, y, inside, true) && deep(x, y, outside, false))
    };
    let moved_in =
        find(&posed, &rest).expect("no pixel the hop's pose covers and the rest does not");
    let moved_out =
        find(&rest, &posed).expect("no pixel the rest pose covers and the hop's does not");
    let pick = |(x, y): (i64, i64), posing: &str| {
        let mut args = common.clone();
        args.extend(posed_args);
        let pixel = format!("{x},{y}");
        args.extend(["--pose", posing, "--pick", pixel.as_str()]);
        let (hit, subject, _) = picked(&view_stdout(CREATURE, &args, &dir.join("pick.png")));
        hit && subject
    };
    for posing in ["gpu", "cpu"] {
        let (inside, outside) = (pick(moved_in, posing), pick(moved_out, posing));
        eprintln!(
            "posed on the {posing}: picked at {moved_in:?} {inside}, at {moved_out:?} {outside}"
        );
        assert!(
            inside,
            "posed on the {posing}: the drawn pose at {moved_in:?} was not picked"
        );
        assert!(
            !outside,
            "posed on the {posing}: the rest pose at {moved_out:?} was picked"
        );
    }
}

/// The JSON `lod` line the example printed: triangles, and the camera and size it saw with.
fn lod_line(stdout: &str) -> (u64, Option<(String, String)>) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("{\"lod\""))
        .unwrap_or_else(|| panic!("no lod line in:\n{stdout}"));
    let field = |name: &str| {
        line.split(&format!("\"{name}\":")).nth(1).map(|r| {
            r.trim_start_matches('"')
                .split(['"', ',', '}'])
                .next()
                .unwrap()
                .to_string()
        })
    };
    let quoted = |name: &str| {
        line.split(&format!("\"{name}\":\""))
            .nth(1)
            .map(|r| r.split('"').next().unwrap().to_string())
    };
    let triangles = field("triangles").unwrap().parse().unwrap();
    (triangles, quoted("camera").zip(quoted("size")))
}

/// Background pixels the silhouette encloses (not reachable from the border through
/// background): cracks between patches would show as these.
fn holes(path: &Path) -> usize {
    let (mask, (w, h)) = silhouette(path);
    let (w, h) = (w as usize, h as usize);
    let mut seen = vec![false; w * h];
    let mut stack: Vec<usize> = (0..w * h)
        .filter(|&i| {
            let (x, y) = (i % w, i / w);
            (x == 0 || y == 0 || x == w - 1 || y == h - 1) && !mask[i]
        })
        .collect();
    while let Some(i) = stack.pop() {
        if seen[i] || mask[i] {
            continue;
        }
        seen[i] = true;
        let (x, y) = (i % w, i / w);
        if x > 0 {
            stack.push(i - 1);
        }
        if x + 1 < w {
            stack.push(i + 1);
        }
        if y > 0 {
            stack.push(i - w);
        }
        if y + 1 < h {
            stack.push(i + w);
        }
    }
    (0..w * h).filter(|&i| !mask[i] && !seen[i]).count()
}

/// Runs the example and returns its stdout.
fn view_stdout(file: &str, args: &[&str], out: &Path) -> String {
    let mut cmd = Command::new(view_example());
    cmd.arg(repo().join(file))
        .args(args)
        .arg("--screenshot")
        .arg(out);
    run(cmd).0
}

/// Screen-space LOD from Bevy's camera: for each tessellator spacing, the entity draws as many
/// triangles as `tessella refine --lod` makes with the camera and size the plugin saw (the same
/// per-edge levels), its silhouette matches `tessella render --lod` of the same view, and no
/// crack lets the background through. A camera nearer draws more triangles.
#[test]
fn lod_entity_draws_tessellas_levels_crack_free() {
    let dir = tempfile_dir("lod");
    let file = "samples/creature.obj";
    let view = ["--yaw", "30", "--pitch", "20", "--zoom", "1"];
    for spacing in ["fractional-odd", "fractional-even", "equal"] {
        let out = dir.join(format!("lod-{spacing}.png"));
        let mut args = vec!["--size", SIZE, "--scheme", "pn", "--lod", "screen:6"];
        args.extend(["--spacing", spacing]);
        args.extend(view);
        let stdout = view_stdout(file, &args, &out);
        let (triangles, seen) = lod_line(&stdout);
        let (camera, size) = seen.expect("a screen LOD reports its camera");
        let refined = dir.join("lod.ply");
        let mut cmd = Command::new(cli());
        cmd.arg("refine")
            .arg(repo().join(file))
            .args(["--scheme", "pn", "--lod", "screen:6", "--spacing", spacing])
            .args(["--camera", &camera, "--size", &size])
            .arg("-o")
            .arg(&refined);
        let (stdout, stderr) = run(cmd);
        let said = stderr + &stdout;
        let cli_triangles: u64 = said
            .split(" triangles (")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no triangle count in {said}"));
        let mut render_view = view.to_vec();
        render_view.extend(["--lod", "screen:6", "--spacing", spacing]);
        let reference = cli_render(
            &dir,
            &format!("lod-cli-{spacing}"),
            file,
            "pn",
            16,
            &render_view,
        );
        let iou = iou(&out, &reference);
        let holes = holes(&out);
        eprintln!("{spacing}: {triangles} triangles (refine: {cli_triangles}), IoU {iou:.4}, {holes} holes");
        assert_eq!(
            triangles, cli_triangles,
            "{spacing}: triangles differ from refine's"
        );
        assert!(
            iou >= 0.98,
            "{spacing}: IoU {iou} against tessella render --lod"
        );
        assert_eq!(holes, 0, "{spacing}: cracks");
    }
    let count = |zoom: &str| {
        let mut args = vec!["--size", SIZE, "--scheme", "pn", "--lod", "screen:6"];
        args.extend(["--yaw", "30", "--pitch", "20", "--zoom", zoom]);
        lod_line(&view_stdout(file, &args, &dir.join("zoom.png"))).0
    };
    let (near, far) = (count("2"), count("0.5"));
    eprintln!("zoom 2: {near} triangles, zoom 0.5: {far}");
    assert!(near > 2 * far, "near {near} vs far {far}");
}

/// A skinned character with per-edge LOD while its clip plays: each frame uploads the nets, the
/// level records and the instance words, coarse data only.
#[test]
fn a_deforming_lod_entity_uploads_coarse_bytes() {
    let dir = tempfile_dir("lod-stats");
    let triangles = tessella_io::read_mesh(&repo().join(CREATURE))
        .unwrap()
        .face_count() as u64;
    let args = [
        "--size", "96x96", "--scheme", "pn", "--lod", "screen:4", "--clip", "wave", "--time",
        "0.1", "--frames", "6", "--stats",
    ];
    let stdout = view_stdout(CREATURE, &args, &dir.join("lod-stats.png"));
    let bytes = uploaded_bytes(&stdout);
    eprintln!("LOD, wave playing: bytes per frame {bytes:?} for {triangles} coarse triangles");
    assert!(bytes.len() >= 4, "too few stats lines:\n{stdout}");
    // Nets (192 bytes a triangle), records (96) and instance words (16) at most.
    for &b in &bytes {
        assert!(b > 0 && b <= 304 * triangles, "{b} bytes in a frame");
    }
}
