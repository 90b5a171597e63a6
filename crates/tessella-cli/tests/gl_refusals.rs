//! What `render --backend gl` cannot do is refused with a message, and no picture is written.

use std::process::Command;

#[test]
fn gl_render_refuses_color_by() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    // A tetrahedron with a per-vertex field T.
    let input = dir.path().join("tet.ply");
    std::fs::write(
        &input,
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty float T\nelement face 4\nproperty list uchar int vertex_indices\n\
         end_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    )
    .unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .arg("render")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .args(["--backend", "gl", "--color-by", "T"])
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("--color-by is not supported with --backend gl"),
        "{err}"
    );
    assert!(!out.exists());
}
