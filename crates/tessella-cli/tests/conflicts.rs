//! Options that cannot go together (the core's rules, `RefineOptions::conflict`) are refused
//! before any work, with the one sentence every front end words, and nothing is written.

use std::process::Command;

fn refused(args: &[&str], out: &std::path::Path, want: &str) {
    let run = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{args:?} ran");
    assert!(err.contains(want), "{args:?}: {err}");
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
}

#[test]
fn displacement_origins_and_gl_refusals_name_both_flags() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tet.obj");
    std::fs::write(
        &input,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let input = input.to_str().unwrap();
    let ply = dir.path().join("out.ply");
    let png = dir.path().join("out.png");
    let (ply_s, png_s) = (ply.to_str().unwrap(), png.to_str().unwrap());
    let layout = "(displacement follows the uniform grid's output layout, a whole level on the \
                  grid pattern)";
    for (extra, named) in [
        (&["--spacing", "equal"][..], "--spacing"),
        (&["--level", "3.5"][..], "a fractional --level"),
        (&["--lod", "tolerance:0.01"][..], "--lod"),
    ] {
        let want = format!("--displace cannot be combined with {named} {layout}");
        let mut args = vec!["refine", input, "-o", ply_s, "--displace", "sine:0.1,3"];
        args.extend(extra);
        refused(&args, &ply, &want);
        let mut args = vec!["render", input, "-o", png_s, "--displace", "sine:0.1,3"];
        args.extend(extra);
        refused(&args, &png, &want);
    }
    refused(
        &[
            "refine",
            input,
            "-o",
            ply_s,
            "--write-origin",
            "--backend",
            "gl",
            "--spacing",
            "equal",
        ],
        &ply,
        "--write-origin cannot be combined with --backend gl (the GL tessellator does not \
         report origins; the CPU backend does)",
    );
    refused(
        &[
            "refine",
            input,
            "-o",
            ply_s,
            "--displace",
            "sine:0.1,3",
            "--backend",
            "gl",
        ],
        &ply,
        "--displace cannot be combined with --backend gl (the GL tessellator has no \
         displacement stage; the CPU and GPU backends displace)",
    );
}
