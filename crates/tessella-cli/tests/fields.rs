//! Per-vertex fields through `tessella refine`: PLY vertex properties and glTF `_NAME`
//! attributes are interpolated to the refined vertices and written back. A field linear in the
//! coordinates, refined with the flat scheme (refined points are the faces' barycentric
//! combinations), must equal the same linear function of the refined positions up to f32
//! rounding, in every format pair.

use std::path::Path;
use std::process::{Command, Output};
use tessella_core::samples;
use tessella_io::{read_raw, write_mesh_with_scalars, MeshView};

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// `tessella refine INPUT -o OUTPUT ARGS...`, which must succeed.
fn refine_ok(input: &Path, output: &Path, args: &[&str]) {
    let files = [
        "refine",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ];
    let out = tessella(&[&files[..], args].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn t_of(p: [f32; 3]) -> f64 {
    1.0 + 2.0 * p[0] as f64 - 3.0 * p[1] as f64 + 0.5 * p[2] as f64
}

fn write_input(path: &Path) {
    let mesh = samples::icosphere(1);
    let t: Vec<f32> = mesh.positions().iter().map(|&p| t_of(p) as f32).collect();
    let w: Vec<f32> = mesh.positions().iter().map(|p| p[2]).collect();
    let scalars = [("T", &t[..]), ("height", &w[..])];
    write_mesh_with_scalars(path, MeshView::from(&mesh), &scalars, &Default::default()).unwrap();
}

/// Refines `input` into `output` (flat, level 5) and checks both fields at every vertex.
fn check_round_trip(dir: &Path, input: &str, output: &str, extra: &[&str]) {
    let (input, output) = (dir.join(input), dir.join(output));
    write_input(&input);
    let back = read_raw(&input).unwrap();
    assert_eq!(
        back.vertex_scalars.keys().collect::<Vec<_>>(),
        ["T", "height"],
        "{} keeps the fields",
        input.display()
    );
    refine_ok(
        &input,
        &output,
        &[&["--scheme", "flat", "--level", "5"], extra].concat(),
    );
    let raw = read_raw(&output).unwrap();
    let n = raw.positions.len();
    assert!(n > 162, "refined: {n} vertices");
    let t = &raw.vertex_scalars["T"];
    let h = &raw.vertex_scalars["height"];
    assert_eq!((t.len(), h.len()), (n, n));
    let mut worst = 0f64;
    for (v, p) in raw.positions.iter().enumerate() {
        // |T| ≤ 1 + 2 + 3 + 0.5 on the unit sphere: a few f32 ulps of that.
        worst = worst.max((t[v] as f64 - t_of(*p)).abs());
        assert!(
            (h[v] - p[2]).abs() <= 1e-6,
            "vertex {v}: {} vs z {}",
            h[v],
            p[2]
        );
    }
    assert!(
        worst <= 4e-6,
        "{}: largest error of T {worst}",
        output.display()
    );
}

#[test]
fn linear_field_passes_through_ply_and_gltf() {
    let dir = tempfile::tempdir().unwrap();
    check_round_trip(dir.path(), "in.ply", "out.ply", &[]);
    check_round_trip(
        dir.path(),
        "in2.ply",
        "out2.ply",
        &["--ply-ascii", "--soup"],
    );
    check_round_trip(dir.path(), "in.glb", "out.gltf", &[]);
    check_round_trip(dir.path(), "in3.gltf", "out3.ply", &["--write-origin"]);
    check_round_trip(dir.path(), "in4.ply", "out4.glb", &[]);
}

/// Fields and origins are written piece by piece (here with the smallest budget: many
/// pieces) into the bytes the whole refinement gets in memory, welded and soup, PLY and glTF.
#[test]
fn streamed_fields_and_origins_equal_the_in_memory_files() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    write_input(&input);
    let cases: [(&str, &[&str]); 5] = [
        ("a.ply", &[]),
        ("b.ply", &["--write-origin"]),
        ("c.ply", &["--write-origin", "--soup", "--ply-ascii"]),
        ("d.glb", &[]),
        ("e.gltf", &["--soup"]),
    ];
    for (name, extra) in cases {
        let mut files = Vec::new();
        for how in ["--in-memory", "--max-memory=1MiB"] {
            let output = dir.path().join(format!("{how}-{name}"));
            refine_ok(&input, &output, &[&["--level", "9", how], extra].concat());
            files.push(std::fs::read(&output).unwrap());
        }
        assert!(
            files[0] == files[1],
            "{name} {extra:?}: streamed and in-memory differ"
        );
    }
}

#[test]
fn gltf_names_fields_with_an_underscore() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gltf");
    write_input(&path);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("\"_T\"") && text.contains("\"_height\""),
        "{text}"
    );
}

#[test]
fn formats_without_fields_drop_them_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    write_input(&input);
    let output = dir.path().join("out.obj");
    let out = tessella(&[
        "refine",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--level",
        "2",
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot hold per-vertex fields; T, height not written"),
        "{err}"
    );
    assert!(output.exists());
}

/// `render --color-by`: the field is read from the file; bad names are refused with the
/// available fields, bad colormaps and ranges with what to give.
#[cfg(feature = "gpu")]
#[test]
fn render_colors_by_a_field_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    write_input(&input);
    let png = dir.path().join("t.png");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            input.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            "360x200",
            "--level",
            "4",
        ];
        args.extend(extra);
        tessella(&args)
    };
    let ok = run(&[
        "--color-by",
        "T",
        "--colormap",
        "coolwarm",
        "--compare",
        "flat,pn",
    ]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(png.exists());
    let ok = run(&["--color-by", "height", "--range", "-0.5,0.5"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );

    let err = |o: Output| {
        assert!(!o.status.success());
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let e = err(run(&["--color-by", "pressure"]));
    assert!(
        e.contains("--color-by \"pressure\"")
            && e.contains("has no such per-vertex field; it has T, height"),
        "{e}"
    );
    let e = err(run(&["--color-by", "T", "--colormap", "nope"]));
    assert!(
        e.contains(r#"unknown colormap "nope"; use one of ["viridis", "coolwarm"]"#),
        "{e}"
    );
    let e = err(run(&["--color-by", "T", "--range", "3,1"]));
    assert!(e.contains("MIN < MAX"), "{e}");
    let e = err(run(&["--colormap", "viridis"]));
    assert!(e.contains("--color-by"), "{e}");
}
