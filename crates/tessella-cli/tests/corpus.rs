//! The bad-input corpus (`tests/corpus/`, see `expected.json`) through the binary: every bad file
//! is refused with its message and a non-zero exit, leaves no output (nor a temporary file) and
//! never panics; every good file refines. Also: the output may not be the input, however spelled,
//! and `--alpha` must be finite.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus")
}

fn tessella(args: &[&str], cwd: Option<&Path>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_tessella"));
    command.args(args);
    if let Some(cwd) = cwd {
        command.current_dir(cwd);
    }
    command.output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn manifest() -> Value {
    serde_json::from_str(&std::fs::read_to_string(corpus().join("expected.json")).unwrap()).unwrap()
}

#[test]
fn every_bad_file_fails_cleanly_and_leaves_nothing() {
    let bad = manifest()["bad"].as_object().unwrap().clone();
    assert!(bad.len() >= 40);
    for (name, expected) in bad {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.ply");
        let input = corpus().join("bad").join(&name);
        let o = tessella(
            &[
                "refine",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--level",
                "2",
            ],
            None,
        );
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(err.starts_with("error: "), "{name}: {err}");
        assert!(err.contains(expected.as_str().unwrap()), "{name}: {err}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(left.is_empty(), "{name} left {left:?}");
    }
}

#[test]
fn every_good_file_refines() {
    for (name, counts) in manifest()["good"].as_object().unwrap() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.ply");
        let input = corpus().join("good").join(name);
        let o = tessella(
            &[
                "refine",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--level",
                "2",
            ],
            None,
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let refined = tessella_io::read_raw(&out).unwrap();
        let faces = counts["triangles"].as_u64().unwrap() as usize;
        assert_eq!(refined.triangles.len(), 4 * faces, "{name}");
    }
}

fn checksum(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

#[test]
fn an_output_that_is_the_input_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("mesh.obj");
    std::fs::copy(corpus().join("good/obj-crlf.obj"), &input).unwrap();
    let before = checksum(&input);
    std::os::unix::fs::symlink(&input, dir.path().join("link.obj")).unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::os::unix::fs::symlink(dir.path(), dir.path().join("sub/up")).unwrap();
    std::fs::hard_link(&input, dir.path().join("hard.obj")).unwrap();
    let spellings = [
        ("mesh.obj", "mesh.obj"),
        ("mesh.obj", "./mesh.obj"),
        ("./mesh.obj", "sub/../mesh.obj"),
        ("mesh.obj", "link.obj"),
        ("link.obj", "mesh.obj"),
        ("mesh.obj", "sub/up/mesh.obj"),
        ("mesh.obj", "hard.obj"),
    ];
    for (input_name, output_name) in spellings {
        let o = tessella(
            &["refine", input_name, "-o", output_name, "--level", "2"],
            Some(dir.path()),
        );
        let err = stderr(&o);
        assert_eq!(
            o.status.code(),
            Some(1),
            "{input_name} -> {output_name}: {err}"
        );
        assert!(err.contains("is the input file"), "{err}");
        assert_eq!(
            checksum(&input),
            before,
            "{input_name} -> {output_name} changed the input"
        );
    }
    // The absolute path of the same file too.
    let o = tessella(
        &["refine", input.to_str().unwrap(), "-o", "mesh.obj"],
        Some(dir.path()),
    );
    assert!(stderr(&o).contains("is the input file"), "{}", stderr(&o));
    assert!(dir.path().join("link.obj").is_symlink());
    // A different file beside it is fine.
    let o = tessella(
        &["refine", "mesh.obj", "-o", "./refined.obj", "--level", "2"],
        Some(dir.path()),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(checksum(&input), before);
}

#[test]
fn non_finite_alpha_is_refused_for_every_scheme() {
    let dir = tempfile::tempdir().unwrap();
    let input = corpus().join("good/obj-crlf.obj");
    let out = dir.path().join("out.ply");
    for scheme in ["phong", "pn"] {
        for alpha in ["nan", "inf", "-inf", "NaN"] {
            let o = tessella(
                &[
                    "refine",
                    input.to_str().unwrap(),
                    "-o",
                    out.to_str().unwrap(),
                    "--scheme",
                    scheme,
                    "--alpha",
                    alpha,
                ],
                None,
            );
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{scheme} {alpha}: {err}");
            assert!(err.contains("alpha must be finite"), "{err}");
            assert!(!out.exists());
        }
    }
    let o = tessella(
        &[
            "refine",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--scheme",
            "phong",
            "--alpha",
            "-0.25",
            "--level",
            "2",
        ],
        None,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `--backend auto` opens no GPU for a small output (the CPU is faster than the probe): with
/// the Vulkan loader's debug output switched on, nothing of it appears. `--backend gpu` does
/// open one, and the loader speaks, which shows the check can see a probe.
#[test]
fn auto_opens_no_gpu_for_small_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let input = corpus().join("good/obj-polygons.obj");
    let out = dir.path().join("out.ply");
    let run = |backend: &str| {
        Command::new(env!("CARGO_BIN_EXE_tessella"))
            .args([
                "refine",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--level", "16", "--backend", backend])
            .env("VK_LOADER_DEBUG", "all")
            .output()
            .unwrap()
    };
    let auto = run("auto");
    assert!(auto.status.success(), "{}", stderr(&auto));
    let err = stderr(&auto);
    assert_eq!(
        err.lines().count(),
        1,
        "auto printed more than its summary: {err}"
    );
    assert!(!err.to_lowercase().contains("loader"), "{err}");
    let gpu = run("gpu");
    let err = stderr(&gpu);
    if gpu.status.success() && std::path::Path::new("/usr/share/vulkan/icd.d").is_dir() {
        assert!(err.to_lowercase().contains("loader"), "{err}");
    }
}
