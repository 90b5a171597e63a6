//! What the test files share: the examples' binaries and running a command whose log must be
//! clean.

use std::path::{Path, PathBuf};
use std::process::Command;

/// An example's binary: `cargo test` builds the examples into `<target>/<profile>/examples`
/// (`CARGO_TARGET_TMPDIR` is `<target>/tmp`).
pub fn example(name: &str) -> PathBuf {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("..");
    let profile = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let bin = target.join(profile).join("examples").join(name);
    assert!(
        bin.exists(),
        "{} is missing (cargo test builds it)",
        bin.display()
    );
    bin
}

/// Runs `cmd`, which must succeed without an `ERROR` line in its log (Bevy logs wgpu
/// validation errors and shader errors and draws on: a picture is not enough, the log must be
/// clean too); returns its stdout and stderr.
pub fn run(mut cmd: Command) -> (String, String) {
    let out = cmd.output().expect("the command starts");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{cmd:?} failed:\n{stdout}\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("ERROR")).collect();
    assert!(
        errors.is_empty(),
        "{cmd:?} logged errors:\n{}",
        errors.join("\n")
    );
    (stdout, stderr)
}
