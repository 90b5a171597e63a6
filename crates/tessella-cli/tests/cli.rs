//! The `tessella` binary end to end: exit codes, messages, files left behind.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tessella_core::{samples, Mesh, Pattern};

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Writes a bundled sample as PLY (which keeps vertex order, so outputs can be compared by index).
fn write_sample(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(format!("{name}.ply"));
    let mesh = samples::by_name(name).unwrap();
    tessella_io::write_mesh(&path, (&mesh).into(), &Default::default()).unwrap();
    path
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn refine_writes_every_format_with_the_expected_counts() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "icosphere");
    let coarse = tessella_io::read_mesh(&input).unwrap();
    for (ext, scheme) in [
        ("ply", "flat"),
        ("ply", "phong"),
        ("glb", "pn"),
        ("gltf", "pn"),
        ("obj", "pn"),
    ] {
        let output = dir.path().join(format!("out.{ext}"));
        let o = tessella(&[
            "refine",
            s(&input),
            "-o",
            s(&output),
            "--scheme",
            scheme,
            "--level",
            "5",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let refined: Mesh = tessella_io::read_mesh(&output).unwrap();
        let topo = coarse.topology();
        let n = 5;
        assert_eq!(refined.face_count(), coarse.face_count() * n * n);
        let expected = coarse.vertex_count()
            + topo.edges.len() * (n - 1)
            + coarse.face_count() * (n - 1) * (n - 2) / 2;
        assert_eq!(refined.vertex_count(), expected, "{ext}");
        // The coarse corners come first and are reproduced exactly (OBJ readers renumber
        // vertices in order of first use, so check those as a set).
        if ext == "obj" {
            let have: std::collections::HashSet<[u32; 3]> = refined
                .positions()
                .iter()
                .map(|p| p.map(f32::to_bits))
                .collect();
            assert!(coarse
                .positions()
                .iter()
                .all(|p| have.contains(&p.map(f32::to_bits))));
        } else {
            assert_eq!(
                &refined.positions()[..coarse.vertex_count()],
                coarse.positions()
            );
        }
    }
}

#[test]
fn soup_gives_every_patch_its_own_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "tetrahedron");
    let output = dir.path().join("soup.ply");
    let o = tessella(&[
        "refine",
        s(&input),
        "-o",
        s(&output),
        "--level",
        "3",
        "--soup",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let refined = tessella_io::read_mesh(&output).unwrap();
    assert_eq!(refined.vertex_count() as u64, 4 * Pattern::point_count(3));
}

#[test]
fn bad_input_fails_cleanly_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let good = write_sample(dir.path(), "icosphere");
    let broken = dir.path().join("broken.obj");
    std::fs::write(&broken, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let nan = dir.path().join("nan.obj");
    std::fs::write(&nan, "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let degenerate = dir.path().join("degenerate.obj");
    std::fs::write(&degenerate, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let zero_normal = dir.path().join("zero-normal.obj");
    std::fs::write(
        &zero_normal,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nvn 0 0 1\nf 1//1 2//2 3//2\n",
    )
    .unwrap();
    let garbage = dir.path().join("garbage.ply");
    std::fs::write(&garbage, "this is not a ply file").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec![s(&broken).into()], "vertex"),
        (vec![s(&nan).into()], "non-finite"),
        (vec![s(&degenerate).into()], "zero area"),
        (vec![s(&zero_normal).into()], "zero-length normal"),
        (vec![s(&garbage).into()], "garbage.ply"),
        (
            vec![s(&dir.path().join("missing.obj")).into()],
            "missing.obj",
        ),
        (
            vec![s(&good).into(), "--level".into(), "0".into()],
            "must be a finite number above 0 (segments per coarse edge), got 0",
        ),
        // Streamed outputs (welded or soup) have no size cap, only the 32-bit index range.
        (
            vec![s(&good).into(), "--level".into(), "200000".into()],
            "32-bit indices",
        ),
        (
            vec![
                s(&good).into(),
                "--level".into(),
                "200000".into(),
                "--soup".into(),
            ],
            "32-bit indices",
        ),
        // Outputs made in memory (here asked for; adaptive, displaced, ...) are capped by
        // --max-memory.
        (
            vec![
                s(&good).into(),
                "--level".into(),
                "64".into(),
                "--in-memory".into(),
                "--max-memory".into(),
                "1MiB".into(),
            ],
            "limit",
        ),
        (
            vec![
                s(&good).into(),
                "--scheme".into(),
                "phong".into(),
                "--alpha".into(),
                "NaN".into(),
            ],
            "alpha",
        ),
    ];
    for (case, (extra, needle)) in cases.into_iter().enumerate() {
        let output = dir.path().join(format!("out{case}.ply"));
        let mut args = vec!["refine".to_string()];
        args.extend(extra);
        args.extend(["-o".into(), s(&output).into()]);
        let o = tessella(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert!(!o.status.success(), "case {case} succeeded");
        assert!(
            err.contains(needle),
            "case {case}: {err:?} lacks {needle:?}"
        );
        assert!(!err.contains("panicked"), "case {case} panicked: {err}");
        assert!(!output.exists(), "case {case} left {}", output.display());
    }
    // Nothing but the inputs (no temporary files) is left in the folder.
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 6, "{left:?}");
}

#[test]
fn unknown_output_extension_is_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "icosphere");
    let o = tessella(&["refine", s(&input), "-o", s(&dir.path().join("out.xyz"))]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("xyz"), "{}", stderr(&o));
}

#[test]
fn pattern_json_matches_the_uniform_pattern() {
    let o = tessella(&["pattern", "--level", "3"]);
    assert!(o.status.success());
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["level"], 3);
    assert_eq!(json["points"].as_array().unwrap().len(), 10);
    assert_eq!(json["triangles"].as_array().unwrap().len(), 9);
    // Point (i, j) = (1, 1) of level 3 is the centre (1/3, 1/3, 1/3).
    let centre = &json["points"][Pattern::index(3, 1, 1) as usize];
    for k in 0..3 {
        assert!((centre[k].as_f64().unwrap() - 1.0 / 3.0).abs() < 1e-15);
    }
    assert!(!tessella(&["pattern", "--level", "0"]).status.success());
}

#[test]
fn info_reports_split_normals_and_degenerate_faces() {
    let dir = tempfile::tempdir().unwrap();
    let cube = write_sample(dir.path(), "hard-cube");
    let o = tessella(&["info", s(&cube), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["topology"]["split_normal_positions"], 8);
    assert_eq!(json["topology"]["euler_characteristic"], 2);
    assert!(json["problem"].is_null());

    let bad = dir.path().join("bad.obj");
    std::fs::write(
        &bad,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n",
    )
    .unwrap();
    let o = tessella(&["info", s(&bad), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["degenerate_triangles"], 1);
    assert_eq!(json["topology"]["boundary_edges"], 3);
    assert!(json["problem"].as_str().unwrap().contains("zero area"));
}

#[test]
fn help_explains_levels_and_schemes() {
    let o = tessella(&["refine", "--help"]);
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in ["--level", "--scheme", "phong", "pn", "--soup", "--normals"] {
        assert!(text.contains(needle), "help lacks {needle}");
    }
}

#[test]
fn neighbour_and_tag_schemes_refine_and_bad_tags_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let creature = write_sample(dir.path(), "creature");
    for scheme in ["png1", "pn-aen", "st"] {
        let output = dir.path().join(format!("{scheme}.ply"));
        let o = tessella(&[
            "refine",
            s(&creature),
            "-o",
            s(&output),
            "--scheme",
            scheme,
            "--level",
            "4",
            "--crease-angle",
            "80",
        ]);
        assert!(o.status.success(), "{scheme}: {}", stderr(&o));
        assert!(output.exists());
    }
    let tags = dir.path().join("tags.json");
    std::fs::write(
        &tags,
        r#"{"edges": [{"vertices": [0, 100000], "sharpness": 1}]}"#,
    )
    .unwrap();
    let output = dir.path().join("tagged.ply");
    let o = tessella(&[
        "refine",
        s(&creature),
        "-o",
        s(&output),
        "--scheme",
        "st",
        "--tags",
        s(&tags),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("tags.json"), "{}", stderr(&o));
    assert!(!output.exists());
}

#[test]
fn quality_report_shows_png1_closing_the_g1_gap() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = write_sample(dir.path(), "icosphere");
    let o = tessella(&["info", s(&sphere), "--quality", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = json["quality"].as_array().unwrap();
    let jump = |name: &str| {
        rows.iter().find(|r| r["scheme"] == name).unwrap()["normal_jump_max_deg"]
            .as_f64()
            .unwrap()
    };
    assert!(jump("png1") < 0.01, "png1 {}", jump("png1"));
    assert!(jump("pn") > 1.0, "pn {}", jump("pn"));
}

#[test]
fn render_writes_a_picture_of_the_requested_size() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = write_sample(dir.path(), "icosphere");
    let picture = dir.path().join("sphere.png");
    let o = tessella(&[
        "render",
        s(&sphere),
        "-o",
        s(&picture),
        "--size",
        "96x64",
        "--level",
        "4",
        "--compare",
        "flat,pn",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&picture).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // Width and height in the IHDR chunk: --size is the whole picture, both panels included.
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((width, height), (96, 64));
    assert!(!stderr(&o).contains("XDG_RUNTIME_DIR"), "{}", stderr(&o));

    let bad = dir.path().join("bad.png");
    let extras: [&[&str]; 5] = [
        &["--displace", "wobble:1"],
        &["--size", "0x10"],
        &["--size", "0x0"],
        &["--level", "0"],
        // Ten panels do not fit 12 pixels.
        &[
            "--size",
            "12x12",
            "--compare",
            "flat,pn,png1,phong,pn,flat,pn,png1,phong,pn",
        ],
    ];
    for extra in extras {
        let mut args = vec!["render", s(&sphere), "-o", s(&bad)];
        args.extend(extra);
        let o = tessella(&args);
        assert!(!o.status.success(), "{extra:?}");
        assert!(!bad.exists(), "{extra:?} left a file");
    }
}

#[test]
fn gpu_refinement_matches_the_cpu_and_displacement_moves_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = write_sample(dir.path(), "icosphere");
    let cpu = dir.path().join("cpu.ply");
    let gpu = dir.path().join("gpu.ply");
    let bumpy = dir.path().join("bumpy.ply");
    for (out, backend, extra) in [
        (&cpu, "cpu", None),
        (&gpu, "gpu", None),
        (&bumpy, "cpu", Some("sine:0.05,20")),
    ] {
        let mut args = vec![
            "refine",
            s(&sphere),
            "-o",
            s(out),
            "--level",
            "6",
            "--backend",
            backend,
        ];
        if let Some(spec) = extra {
            args.extend(["--displace", spec]);
        }
        let o = tessella(&args);
        assert!(o.status.success(), "{backend}: {}", stderr(&o));
    }
    let (a, b, c) = (
        tessella_io::read_mesh(&cpu).unwrap(),
        tessella_io::read_mesh(&gpu).unwrap(),
        tessella_io::read_mesh(&bumpy).unwrap(),
    );
    assert_eq!(a.triangles(), b.triangles());
    for (p, q) in a.positions().iter().zip(b.positions()) {
        for k in 0..3 {
            assert!((p[k] - q[k]).abs() < 2e-5, "{p:?} vs {q:?}");
        }
    }
    // Sine displacement a·sin(f|P|) along the normal: the points move off the PN surface, by at
    // most the amplitude, and the welded layout is kept.
    assert_eq!(a.triangles(), c.triangles());
    let moved = a
        .positions()
        .iter()
        .zip(c.positions())
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f32>().sqrt());
    let largest = moved.fold(0.0, f32::max);
    assert!(largest > 0.01 && largest <= 0.05 + 1e-5, "{largest}");
}

#[test]
fn demo_tables_every_sample_and_scheme() {
    let o = tessella(&["demo", "--level", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    for name in ["icosphere", "torus", "tetrahedron", "hard-cube", "creature"] {
        for scheme in ["flat", "phong", "pn", "pn-aen", "st", "png1"] {
            assert!(
                table.contains(&format!("| {name} | {scheme} |")),
                "{name} {scheme} missing:\n{table}"
            );
        }
    }
    // The flat rows sit on the coarse mesh; the curved ones bulge away from it.
    assert!(
        table.contains("| icosphere | flat | 80 | 162 | 320 |"),
        "{table}"
    );
}

/// `tessella samples` writes the animated sample, and the repository's copy is exactly what it
/// writes: its bytes come from the generator, not from elsewhere.
#[test]
fn samples_writes_the_repositorys_animated_sample_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let out = tessella(&["samples", "-o", s(dir.path())]);
    assert!(out.status.success(), "{}", stderr(&out));
    let written = std::fs::read(dir.path().join("animated-creature.glb")).unwrap();
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/animated-creature.glb");
    assert!(
        written == std::fs::read(&bundled).unwrap(),
        "samples/animated-creature.glb differs from what `tessella samples` writes; regenerate it"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("3 clips (wave, hop, breathe)"));
    for scene in ["scene.glb", "scene-quantized.glb"] {
        let written = std::fs::read(dir.path().join(scene)).unwrap();
        let bundled = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../samples")
            .join(scene);
        assert!(
            written == std::fs::read(&bundled).unwrap(),
            "samples/{scene} differs from what `tessella samples` writes; regenerate it"
        );
    }
}
