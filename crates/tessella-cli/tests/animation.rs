//! `--clip`/`--time` on `refine` and `render`, and `animate --clip`: the bundled animated
//! sample posed and refined end to end. The poses themselves are checked against an f64
//! reading of the glTF specification in tessella-core's tests; here the commands must pose
//! what the poser poses, refuse what it refuses, and leave no file behind on error.

use std::path::Path;
use std::process::{Command, Output};
use tessella_core::animation::Poser;
use tessella_core::Mesh;

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The bundled sample: skinned, morphing, three clips (wave, hop, breathe).
const SAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../samples/animated-creature.glb"
);

fn poser() -> Poser {
    Poser::new(tessella_io::read_animated(Path::new(SAMPLE)).unwrap()).unwrap()
}

fn diagonal(points: &[[f32; 3]]) -> f32 {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt()
}

fn largest_gap(a: &[[f32; 3]], b: &[[f32; 3]]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f32::max)
}

/// Flat at level 1 writes the coarse vertices themselves (PLY keeps their order): they must be
/// the poser's pose at that time, and not the rest pose.
#[test]
fn refine_poses_the_clip_at_the_time_before_refining() {
    let dir = tempfile::tempdir().unwrap();
    let poser = poser();
    let wave = poser.clip_index("wave").unwrap();
    for (clip, time) in [("wave", "0.5"), ("1", "0.25")] {
        let out = dir.path().join(format!("posed-{clip}.ply"));
        let o = tessella(&[
            "refine",
            SAMPLE,
            "--clip",
            clip,
            "--time",
            time,
            "--scheme",
            "flat",
            "--level",
            "1",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let refined: Mesh = tessella_io::read_mesh(&out).unwrap();
        let index = poser.clip_index(clip).unwrap();
        let (expected, _) = poser.pose(Some(index), time.parse().unwrap()).unwrap();
        let (rest, _) = poser.pose(None, 0.0).unwrap();
        let tolerance = 1e-6 * diagonal(&expected);
        assert!(
            largest_gap(refined.positions(), &expected) <= tolerance,
            "{clip} at {time}: the refined coarse vertices are not the pose"
        );
        assert!(
            largest_gap(&rest, &expected) > 100.0 * tolerance,
            "{clip} at {time} does not move the creature; the test would prove nothing"
        );
        assert_eq!(refined.face_count(), poser.model().triangles.len());
    }
    // A curved scheme at a real level poses too: the same count as without --clip.
    let out = dir.path().join("pn.ply");
    let o = tessella(&[
        "refine",
        SAMPLE,
        "--clip",
        "wave",
        "--time",
        "0.5",
        "--level",
        "4",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let refined: Mesh = tessella_io::read_mesh(&out).unwrap();
    assert_eq!(refined.face_count(), poser.model().triangles.len() * 16);
    assert!(wave < poser.clip_count());
}

#[test]
fn bad_clips_and_times_are_refused_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.ply");
    for (args, says) in [
        (vec!["--clip", "dance"], "dance"),
        (vec!["--clip", "7"], "wave"),
        (vec!["--clip", "wave", "--time", "NaN"], "time"),
    ] {
        let mut all = vec!["refine", SAMPLE, "-o", s(&out)];
        all.extend(args.iter().copied());
        let o = tessella(&all);
        assert!(!o.status.success(), "{args:?} was accepted");
        assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
    // --time needs a clip.
    let o = tessella(&["refine", SAMPLE, "-o", s(&out), "--time", "1"]);
    assert!(!o.status.success());
    // A file without animation has no clips to name.
    let plain = dir.path().join("plain.ply");
    tessella_io::write_mesh(
        &plain,
        (&tessella_core::samples::icosphere(1)).into(),
        &Default::default(),
    )
    .unwrap();
    let o = tessella(&["refine", s(&plain), "-o", s(&out), "--clip", "wave"]);
    assert!(!o.status.success());
    assert!(!out.exists());
}

/// `render --clip` draws the pose: another picture than the rest pose's.
#[test]
fn render_draws_the_pose() {
    let dir = tempfile::tempdir().unwrap();
    let picture = |name: &str, pose: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec!["render", SAMPLE, "-o", s(&out), "--size", "96x96"];
        args.extend(pose.iter().copied());
        let o = tessella(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        image::open(&out).unwrap().to_rgba8()
    };
    let rest = picture("rest.png", &[]);
    let posed = picture("posed.png", &["--clip", "wave", "--time", "0.5"]);
    let differing = rest
        .pixels()
        .zip(posed.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 50, "only {differing} pixels moved");
}

/// `animate --clip` writes one picture a frame and uploads the control nets alone: 16 entries
/// of 12 bytes (ten cubic points, six normal-net entries) per coarse triangle.
#[test]
fn animate_plays_a_clip_uploading_the_nets() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    let o = tessella(&[
        "animate",
        SAMPLE,
        "--clip",
        "wave",
        "-o",
        s(&frames),
        "--fps",
        "4",
        "--frames",
        "3",
        "--size",
        "64x64",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let triangles = poser().model().triangles.len() as u64;
    let nets = triangles * 16 * 12;
    assert!(
        stdout(&o).contains(&format!("{nets} bytes uploaded per frame")),
        "{}",
        stdout(&o)
    );
    let pictures: Vec<_> = (0..3)
        .map(|k| {
            image::open(frames.join(format!("frame_{k:03}.png")))
                .unwrap()
                .to_rgba8()
        })
        .collect();
    assert_ne!(pictures[0], pictures[2], "the clip does not move");
    let o = tessella(&["animate", SAMPLE, "--clip", "dance", "-o", s(&frames)]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("dance"), "{}", stderr(&o));
}

/// `--skinning gpu`: the GPU skins the creature and builds its nets from the frame's deform
/// matrices, so a frame uploads 64 bytes a joint matrix and 4 a morph weight (the sample: one
/// skin of 7 joints, one morph target), and draws what the CPU's poses draw.
#[test]
fn animate_with_gpu_skinning_uploads_the_matrices_and_draws_the_same_frames() {
    let dir = tempfile::tempdir().unwrap();
    let run = |skinning: &str| {
        let frames = dir.path().join(skinning);
        let o = tessella(&[
            "animate",
            SAMPLE,
            "--clip",
            "wave",
            "-o",
            s(&frames),
            "--fps",
            "6",
            "--frames",
            "4",
            "--size",
            "96x96",
            "--skinning",
            skinning,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let pictures: Vec<_> = (0..4)
            .map(|k| {
                image::open(frames.join(format!("frame_{k:03}.png")))
                    .unwrap()
                    .to_rgba8()
            })
            .collect();
        (stdout(&o), pictures)
    };
    let model = poser();
    let joints: usize = model.model().skins.iter().map(|s| s.joints.len()).sum();
    let weights: usize = model
        .model()
        .instances
        .iter()
        .map(|i| i.targets.len())
        .sum();
    assert!(joints > 0 && weights > 0, "the sample skins and morphs");
    let expected = 64 * joints + 4 * weights;
    let (said, gpu) = run("gpu");
    assert!(
        said.contains(&format!("{expected} bytes uploaded per frame")),
        "{said}"
    );
    let (_, cpu) = run("cpu");
    for (k, (a, b)) in cpu.iter().zip(&gpu).enumerate() {
        let off = a
            .pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 8))
            .count();
        // Float rounding may move a silhouette pixel or two; a wrong pose moves hundreds.
        assert!(
            off <= 6,
            "frame {k}: {off} pixels differ between CPU and GPU skinning"
        );
    }
    assert_ne!(gpu[0], gpu[3], "the GPU frames do not move");
}

/// `animate --alpha` reaches the surface: Phong frames at α 0.2 are not those at 0.75, and
/// 0.75 draws what no `--alpha` draws (the default).
#[test]
fn animate_uses_the_alpha_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let frame = |name: &str, alpha: &[&str]| {
        let frames = dir.path().join(name);
        let mut args = vec![
            "animate",
            SAMPLE,
            "--clip",
            "wave",
            "-o",
            s(&frames),
            "--fps",
            "2",
            "--frames",
            "2",
            "--size",
            "96x96",
            "--scheme",
            "phong",
            "--level",
            "8",
        ];
        args.extend(alpha.iter().copied());
        let o = tessella(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        image::open(frames.join("frame_001.png"))
            .unwrap()
            .to_rgba8()
    };
    let low = frame("low", &["--alpha", "0.2"]);
    let given = frame("given", &["--alpha", "0.75"]);
    let default = frame("default", &[]);
    let differing = low
        .pixels()
        .zip(given.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differing > 20,
        "only {differing} pixels differ between α 0.2 and 0.75"
    );
    assert_eq!(given, default, "--alpha 0.75 is the default");
}
