//! A `tessella refine` killed (SIGKILL: no clean-up runs) while it writes leaves nothing in the
//! output folder, streamed or in memory: the file has no name until it is whole (Linux).

#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};
use tessella_core::samples;

/// Whether process `pid` holds a file open in `dir` (an unnamed one reads as `dir/#N (deleted)`).
fn writes_in(pid: u32, dir: &Path) -> bool {
    let Ok(fds) = std::fs::read_dir(format!("/proc/{pid}/fd")) else {
        return false;
    };
    fds.flatten()
        .filter_map(|fd| std::fs::read_link(fd.path()).ok())
        .any(|target| target.starts_with(dir))
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_refine_killed_while_writing_leaves_nothing() {
    let input_dir = tempfile::tempdir().unwrap();
    let input = input_dir.path().join("sphere.ply");
    let mesh = samples::icosphere_4k();
    tessella_io::write_mesh(&input, (&mesh).into(), &Default::default()).unwrap();
    for mode in ["--max-memory=8MiB", "--in-memory"] {
        let out = tempfile::tempdir().unwrap();
        let out_dir = out.path().canonicalize().unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_tessella"))
            .args(["refine", input.to_str().unwrap(), "-o"])
            .arg(out_dir.join("fine.ply"))
            .args(["--level", "64", "--backend", "cpu", mode])
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while !writes_in(child.id(), &out_dir) && start.elapsed() < Duration::from_secs(120) {
            assert!(
                child.try_wait().unwrap().is_none(),
                "{mode}: finished first"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        assert!(
            writes_in(child.id(), &out_dir),
            "{mode}: never started writing"
        );
        child.kill().unwrap();
        child.wait().unwrap();
        assert_eq!(names(&out_dir), Vec::<String>::new(), "{mode}");
    }
}
