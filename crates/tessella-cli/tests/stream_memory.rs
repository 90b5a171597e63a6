//! A streamed refinement whose file is many times its memory budget: the child's peak memory
//! (getrusage of the finished child) beyond what the binary takes to start stays far below the
//! file's size, and the file has the bytes of the in-memory refinement and writer. Alone in its
//! test binary, so no other test's child counts towards the peak.

use std::process::Command;
use tessella_core::{refine, samples, RefineOptions, Scheme};

/// The largest resident size of any finished child of this process, in bytes (Linux: KiB).
fn children_peak_bytes() -> u64 {
    // SAFETY: getrusage only writes the struct it is given.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let rc = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(rc, 0);
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn a_streamed_file_many_times_the_budget_is_written_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.ply");
    let mesh = samples::icosphere_4k();
    tessella_io::write_mesh(&input, (&mesh).into(), &Default::default()).unwrap();
    // What the binary takes just to start (its pages, the libraries, the relocations), so the
    // check below measures the refinement, not how much code is linked in (winit's, say).
    let o = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .arg("--version")
        .output()
        .unwrap();
    assert!(o.status.success());
    let startup = children_peak_bytes();
    let output = dir.path().join("fine.ply");
    let level = 24;
    let o = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args([
            "refine",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ])
        .args([
            "--level",
            &level.to_string(),
            "--max-memory",
            "8MiB",
            "--backend",
            "cpu",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let peak = children_peak_bytes();
    let size = std::fs::metadata(&output).unwrap().len();
    assert!(size > 60 << 20, "the file is {size} bytes");
    // The whole output in memory would need more than the file; the stream holds pieces.
    assert!(
        peak - startup < size / 3,
        "peak {peak} bytes ({startup} to start) for a file of {size}"
    );

    // The same refinement whole, in memory, by the ordinary writer.
    let want = dir.path().join("whole.ply");
    let o = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args([
            "refine",
            input.to_str().unwrap(),
            "-o",
            want.to_str().unwrap(),
        ])
        .args([
            "--level",
            &level.to_string(),
            "--in-memory",
            "--backend",
            "cpu",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // And this process's own refinement of the mesh as read from the file (reading
    // normalises the normals again: the last bit can move), through the library's writer.
    let mesh = tessella_io::read_mesh(&input).unwrap();
    let whole = refine(&mesh, &RefineOptions::new(Scheme::Pn, level)).unwrap();
    let library = dir.path().join("library.ply");
    tessella_io::write_mesh(&library, (&whole).into(), &Default::default()).unwrap();
    assert!(std::fs::read(&library).unwrap() == std::fs::read(&want).unwrap());
    let (a, b) = (
        std::fs::read(&want).unwrap(),
        std::fs::read(&output).unwrap(),
    );
    let first = a.iter().zip(&b).position(|(x, y)| x != y);
    assert!(
        a == b,
        "{} vs {} bytes, first difference at {first:?}",
        b.len(),
        a.len()
    );
}
