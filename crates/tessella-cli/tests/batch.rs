//! `tessella batch` end to end: broken files reported and the batch going on, outputs equal to
//! `tessella refine`'s with counts from the layout's formula, exit codes, and a batch killed
//! half-way that resumes without redoing anything.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tessella_core::samples;

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A folder of good meshes (in a subfolder too) and broken ones; returns the good names.
fn folder(dir: &Path, copies: usize) -> Vec<(String, tessella_core::Mesh)> {
    let mut good = Vec::new();
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    for i in 0..copies {
        for name in ["icosphere", "torus", "creature"] {
            let mesh = samples::by_name(name).unwrap();
            let file = if i % 2 == 0 {
                format!("{name}-{i}.ply")
            } else {
                format!("sub/{name}-{i}.obj")
            };
            tessella_io::write_mesh(&dir.join(&file), (&mesh).into(), &Default::default()).unwrap();
            good.push((file, mesh));
        }
    }
    std::fs::write(dir.join("garbage.obj"), "this is not a mesh\n").unwrap();
    std::fs::write(
        dir.join("sub/truncated.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("notes.txt"),
        "not a mesh extension: not an input\n",
    )
    .unwrap();
    good
}

fn manifest(out: &Path) -> Vec<Value> {
    std::fs::read_to_string(out.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(temporaries(&path));
        } else if path.to_string_lossy().contains(".tessella-") {
            out.push(path);
        }
    }
    out
}

#[test]
fn broken_files_are_reported_and_the_good_ones_match_refine() {
    let dir = tempfile::tempdir().unwrap();
    let (input, out) = (dir.path().join("in"), dir.path().join("out"));
    let good = folder(&input, 2);
    let level = 3u64;
    let o = tessella(&[
        "batch",
        s(&input),
        "-o",
        s(&out),
        "--level",
        "3",
        "--scheme",
        "pn",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("garbage.obj") && stderr.contains("truncated.ply"),
        "{stderr}"
    );
    let rows = manifest(&out);
    assert_eq!(rows.len(), good.len() + 2, "one row per input: {rows:?}");
    for row in &rows {
        let input_name = row["input"].as_str().unwrap();
        if input_name.contains("garbage") || input_name.contains("truncated") {
            assert_eq!(row["status"], "failed");
            assert!(row["error"].as_str().unwrap().contains(input_name));
        } else {
            assert_eq!(row["status"], "ok", "{row}");
        }
    }
    for (file, mesh) in &good {
        let output = out.join(Path::new(file).with_extension("ply"));
        // The single-file command with the same options writes the same bytes.
        let single = dir.path().join("single.ply");
        let o = tessella(&[
            "refine",
            s(&input.join(file)),
            "-o",
            s(&single),
            "--level",
            "3",
        ]);
        assert!(o.status.success());
        assert_eq!(
            std::fs::read(&output).unwrap(),
            std::fs::read(&single).unwrap(),
            "{file}"
        );
        // Counts from the welded layout's formula: V + E(N-1) + F(N-1)(N-2)/2 vertices.
        let row = rows
            .iter()
            .find(|r| r["output"].as_str() == Some(s(&output)))
            .unwrap();
        let (v, f) = (mesh.vertex_count() as u64, mesh.face_count() as u64);
        let e = mesh.topology().edges.len() as u64;
        let want = v + e * (level - 1) + f * (level - 1) * (level - 2) / 2;
        assert_eq!(row["vertices"].as_u64(), Some(want), "{file}");
        assert_eq!(row["triangles"].as_u64(), Some(f * level * level), "{file}");
    }
    assert!(temporaries(&out).is_empty());
}

#[test]
fn usage_errors_exit_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let (input, out) = (dir.path().join("in"), dir.path().join("out"));
    folder(&input, 1);
    let a_file = input.join("garbage.obj");
    let cases: [&[&str]; 5] = [
        &["batch", "/no/such/folder", "-o", s(&out)],
        &["batch", s(&input), "-o", s(&out), "--format", "fbx"],
        &[
            "batch",
            s(&input),
            "-o",
            s(&out),
            "--format",
            "stl",
            "--write-origin",
        ],
        &["batch", &format!("{}/*.nothing", s(&input)), "-o", s(&out)],
        &["batch", s(&input), "-o", s(&a_file)],
    ];
    for args in cases {
        let o = tessella(args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
    }
    // A glob of good files only: exit 0, and --force redoes what exists.
    let pattern = format!("{}/*.ply", s(&input));
    for extra in [None, Some("--force")] {
        let mut args = vec!["batch", &pattern, "-o", s(&out), "--level", "2"];
        args.extend(extra);
        let o = tessella(&args);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let rows = manifest(&out);
        // The first run refines; the second redoes it all, for --force.
        assert!(rows.iter().all(|r| r["status"] == "ok"), "{rows:?}");
    }
}

#[test]
fn a_killed_batch_resumes_without_redoing_anything() {
    let dir = tempfile::tempdir().unwrap();
    let (input, out) = (dir.path().join("in"), dir.path().join("out"));
    let good = folder(&input, 6);
    // One file at a time and a level that takes a while, so the kill lands half-way.
    let args = [
        "batch",
        s(&input),
        "-o",
        s(&out),
        "--level",
        "40",
        "-j",
        "1",
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let ok_rows = |out: &Path| -> usize {
        std::fs::read_to_string(out.join("manifest.jsonl"))
            .map(|t| t.lines().filter(|l| l.contains("\"ok\"")).count())
            .unwrap_or(0)
    };
    let start = std::time::Instant::now();
    while ok_rows(&out) < 3 && start.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL: no clean-up runs
    child.wait().unwrap();
    let done_before = ok_rows(&out);
    assert!(
        done_before >= 3 && done_before < good.len(),
        "killed after {done_before} files"
    );
    // What the first run finished, with its modification times.
    let finished: Vec<(PathBuf, std::time::SystemTime)> = good
        .iter()
        .map(|(file, _)| out.join(Path::new(file).with_extension("ply")))
        .filter(|p| p.exists())
        .map(|p| {
            let t = std::fs::metadata(&p).unwrap().modified().unwrap();
            (p, t)
        })
        .collect();
    assert!(finished.len() >= done_before);

    let o = tessella(&args);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for (path, mtime) in &finished {
        assert_eq!(
            std::fs::metadata(path).unwrap().modified().unwrap(),
            *mtime,
            "{path:?} redone"
        );
    }
    let rows = manifest(&out);
    assert_eq!(rows.len(), good.len() + 2);
    let redone = rows.iter().filter(|r| r["status"] == "ok").count();
    let skipped = rows.iter().filter(|r| r["status"] == "skipped").count();
    assert_eq!(skipped, finished.len(), "what was there is skipped");
    assert_eq!(
        redone + skipped,
        good.len(),
        "only the missing files were refined"
    );
    // The carried rows keep the counts of the run that made them.
    let carried = rows.iter().filter(|r| r["status"] == "skipped");
    assert!(
        carried
            .filter(|r| r["triangles"].as_u64().is_some())
            .count()
            >= done_before
    );
    for (file, mesh) in &good {
        let path = out.join(Path::new(file).with_extension("ply"));
        let back = tessella_io::read_mesh(&path).unwrap();
        assert_eq!(
            back.face_count(),
            mesh.face_count() * 1600,
            "{file} complete"
        );
    }
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
}
