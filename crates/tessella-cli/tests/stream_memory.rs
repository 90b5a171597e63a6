//! A streamed refinement whose file is many times its memory budget: the child's peak memory
//! (getrusage of the finished child) beyond what the binary takes to start stays far below the
//! file's size, and the file has the bytes of the in-memory refinement and writer. Alone in its
//! test binary, so no other test's child counts towards the peak.

use std::process::Command;
use tessella_core::refine::Spacing;
use tessella_core::{refine, samples, RefineOptions, Scheme};

/// The largest resident size of any finished child of this process, in bytes (Linux: KiB).
fn children_peak_bytes() -> u64 {
    // SAFETY: getrusage only writes the struct it is given.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let rc = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(rc, 0);
    usage.ru_maxrss as u64 * 1024
}

/// `tessella refine INPUT -o OUTPUT --level L --backend cpu` with `extra` arguments.
fn refine_cli(input: &std::path::Path, output: &std::path::Path, level: u32, extra: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args([
            "refine",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ])
        .args(["--level", &level.to_string(), "--backend", "cpu"])
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
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
    let level = 24;
    // Welded (corners, edges, interiors), soup (whole faces) and an adaptive plan (a
    // tessellator spacing: tiles of several sizes), all streamed; measured before any
    // in-memory run below raises the children's peak.
    let layouts: [(&str, &[&str]); 3] = [
        ("welded", &[]),
        ("soup", &["--soup"]),
        ("adaptive", &["--spacing", "fractional-odd"]),
    ];
    let mut smallest = u64::MAX;
    for (name, extra) in layouts {
        let output = dir.path().join(format!("{name}.ply"));
        refine_cli(
            &input,
            &output,
            level,
            &[&["--max-memory", "8MiB"], extra].concat(),
        );
        smallest = smallest.min(std::fs::metadata(&output).unwrap().len());
    }
    let peak = children_peak_bytes();
    assert!(smallest > 60 << 20, "a file is {smallest} bytes");
    // The whole output in memory would need more than the file; the stream holds pieces.
    assert!(
        peak - startup < smallest / 3,
        "peak {peak} bytes ({startup} to start) for files of {smallest} and more"
    );

    for (name, extra) in layouts {
        // The same refinement whole, in memory, by the ordinary writer.
        let want = dir.path().join(format!("{name}-whole.ply"));
        refine_cli(&input, &want, level, &[&["--in-memory"], extra].concat());
        // And this process's own refinement of the mesh as read from the file (reading
        // normalises the normals again: the last bit can move), through the library's writer.
        let mesh = tessella_io::read_mesh(&input).unwrap();
        let options = match name {
            "adaptive" => RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(Spacing::FractionalOdd)
                .with_uniform_level(level as f64),
            _ => RefineOptions::new(Scheme::Pn, level).with_weld(name == "welded"),
        };
        let whole = refine(&mesh, &options).unwrap();
        let library = dir.path().join(format!("{name}-library.ply"));
        tessella_io::write_mesh(&library, (&whole).into(), &Default::default()).unwrap();
        assert!(
            std::fs::read(&library).unwrap() == std::fs::read(&want).unwrap(),
            "{name}"
        );
        let (a, b) = (
            std::fs::read(&want).unwrap(),
            std::fs::read(dir.path().join(format!("{name}.ply"))).unwrap(),
        );
        let first = a.iter().zip(&b).position(|(x, y)| x != y);
        assert!(
            a == b,
            "{name}: {} vs {} bytes, first difference at {first:?}",
            b.len(),
            a.len()
        );
    }
}
