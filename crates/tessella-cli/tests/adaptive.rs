//! `tessella refine` with tessellator spacings, fractional levels, LOD functions and
//! `--write-origin`, end to end: counts against the core library, the origin properties
//! against the refined positions, bad levels refused with a message and no file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tessella_core::refine::{Camera, Levels, Lod, Plan, Spacing};
use tessella_core::{samples, RefineOptions, Scheme};

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write_sample(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(format!("{name}.ply"));
    let mesh = samples::by_name(name).unwrap();
    tessella_io::write_mesh(&path, (&mesh).into(), &Default::default()).unwrap();
    path
}

/// The vertex rows and face count of an ascii PLY.
fn ascii_ply(path: &Path) -> (Vec<String>, Vec<Vec<f64>>, usize) {
    let text = std::fs::read_to_string(path).unwrap();
    let (header, body) = text.split_once("end_header\n").unwrap();
    let count = |el: &str| -> usize {
        header
            .lines()
            .find_map(|l| l.strip_prefix(&format!("element {el} ")))
            .unwrap()
            .parse()
            .unwrap()
    };
    let props: Vec<String> = header
        .lines()
        .filter(|l| l.starts_with("property ") && !l.contains("list"))
        .map(|l| l.rsplit(' ').next().unwrap().to_string())
        .collect();
    let nv = count("vertex");
    let rows = body
        .lines()
        .take(nv)
        .map(|l| l.split(' ').map(|x| x.parse().unwrap()).collect())
        .collect();
    (props, rows, count("face"))
}

#[test]
fn fractional_odd_level_matches_the_library_and_writes_origin() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "creature");
    let mesh = tessella_io::read_mesh(&input).unwrap();
    for soup in [false, true] {
        let out = dir.path().join("out.ply");
        let mut args = vec![
            "refine",
            s(&input),
            "-o",
            s(&out),
            "--spacing",
            "fractional-odd",
            "--level",
            "5.5",
            "--write-origin",
            "--ply-ascii",
            "--backend",
            "cpu",
        ];
        if soup {
            args.push("--soup");
        }
        let o = tessella(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let options = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::Uniform(5.5))
            .with_weld(!soup);
        let plan = Plan::new(&mesh, &options).unwrap();
        let (props, rows, faces) = ascii_ply(&out);
        assert_eq!(faces, plan.triangle_count());
        assert_eq!(rows.len(), plan.vertex_count());
        assert_eq!(
            &props[props.len() - 4..],
            ["face", "bary1", "bary2", "bary3"]
        );
        let (origin_faces, bary) = plan.origin();
        for (v, row) in rows.iter().enumerate() {
            let n = row.len();
            assert_eq!(row[n - 4] as u32, origin_faces[v]);
            for c in 0..3 {
                assert_eq!(row[n - 3 + c] as f32, bary[v][c]);
            }
            // The position is the surface at the origin: a corner's is the coarse vertex.
            if let Some(c) = bary[v].iter().position(|&x| x == 1.0) {
                let t = mesh.triangles()[origin_faces[v] as usize];
                assert_eq!(
                    [row[0] as f32, row[1] as f32, row[2] as f32],
                    mesh.positions()[t[c] as usize]
                );
            }
        }
    }
}

#[test]
fn lod_functions_refine_and_agree_with_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "icosphere");
    let mesh = tessella_io::read_mesh(&input).unwrap();
    let camera = "0,0,3,0,0,0,45";
    for (lod, spacing) in [
        ("tolerance:0.002", "grid"),
        ("tolerance:0.002", "fractional-even"),
        ("screen:12", "fractional-odd"),
        ("distance:2,4,12", "equal"),
        ("distance:2,4,12", "grid"),
    ] {
        let out = dir.path().join("lod.ply");
        let o = tessella(&[
            "refine",
            s(&input),
            "-o",
            s(&out),
            "--lod",
            lod,
            "--spacing",
            spacing,
            "--camera",
            camera,
            "--size",
            "640x480",
            "--backend",
            "cpu",
        ]);
        assert!(o.status.success(), "{lod} {spacing}: {}", stderr(&o));
        let read = tessella_io::read_mesh(&out).unwrap();
        let lod = Lod::parse(lod, Some(Camera::parse(camera).unwrap()), Some([640, 480])).unwrap();
        let options = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(spacing.parse().unwrap())
            .with_levels(Levels::Lod(lod));
        let plan = Plan::new(&mesh, &options).unwrap();
        assert_eq!(read.face_count(), plan.triangle_count(), "{spacing}");
    }
}

#[test]
fn fractional_grid_level_geomorphs_as_the_library_does() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "icosphere");
    let mesh = tessella_io::read_mesh(&input).unwrap();
    let out = dir.path().join("out.ply");
    let args = [
        "refine",
        s(&input),
        "-o",
        s(&out),
        "--level",
        "5.5",
        "--ply-ascii",
        "--backend",
        "cpu",
    ];
    let o = tessella(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    // The grid of 6 segments, its points halfway between the surface and level 5's flat one.
    let (_, rows, faces) = ascii_ply(&out);
    assert_eq!(faces, mesh.face_count() * 36);
    let options = RefineOptions::new(Scheme::Pn, 1).with_levels(Levels::Uniform(5.5));
    let lib = tessella_core::refine(&mesh, &options).unwrap();
    let six = tessella_core::refine(&mesh, &RefineOptions::new(Scheme::Pn, 6)).unwrap();
    assert_eq!(rows.len(), lib.positions.len());
    let mut moved = 0.0f64;
    for (row, (p, q)) in rows.iter().zip(lib.positions.iter().zip(&six.positions)) {
        for c in 0..3 {
            assert!((row[c] - p[c] as f64).abs() < 1e-5, "{row:?} {p:?}");
            moved = moved.max((p[c] - q[c]).abs() as f64);
        }
    }
    assert!(moved > 1e-4, "level 5.5 is not level 6: {moved}");
}

#[test]
fn bad_levels_are_refused_with_a_message_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "icosphere");
    let out = dir.path().join("bad.ply");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--level", "-2"], "finite number above 0"),
        (vec!["--level", "NaN"], "finite number above 0"),
        (
            vec!["--level", "inf", "--spacing", "fractional-odd"],
            "finite number above 0",
        ),
        (vec!["--lod", "tolerance:0"], "above 0"),
        (vec!["--lod", "tolerance:-1"], "above 0"),
        (vec!["--lod", "screen:4", "--size", "100x100"], "camera"),
        (
            vec![
                "--lod",
                "screen:4",
                "--camera",
                "0,0,3,0,0,0,0",
                "--size",
                "100x100",
            ],
            "field of view",
        ),
        (
            vec!["--lod", "distance:1,2,8", "--camera", "0,0,0,0,0,0,45"],
            "same point",
        ),
        (vec!["--lod", "wobbly:3"], "expected tolerance"),
        (vec!["--camera", "0,0,3,0,0,0,45"], "add a lod"),
        // In memory (--in-memory) the output is capped by --max-memory; streamed (welded or
        // soup) it is not, but 32-bit indices still bound it.
        (
            vec!["--level", "100000", "--max-memory", "1MiB", "--in-memory"],
            "without --in-memory the CPU writes it piece by piece",
        ),
        (
            vec!["--level", "100000", "--max-memory", "1MiB", "--soup"],
            "32-bit indices",
        ),
        (
            vec!["--level", "100000", "--max-memory", "1MiB"],
            "32-bit indices",
        ),
        (
            vec![
                "--level",
                "1e30",
                "--spacing",
                "equal",
                "--max-memory",
                "1KiB",
                "--in-memory",
            ],
            "limit",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["refine", s(&input), "-o", s(&out), "--backend", "cpu"];
        args.extend(extra.iter().copied());
        let o = tessella(&args);
        assert!(!o.status.success(), "{extra:?} succeeded");
        let e = stderr(&o);
        assert!(e.contains(needle), "{extra:?}: {e}");
        assert!(!e.contains("panicked"), "{extra:?}: {e}");
        assert!(!out.exists(), "{extra:?} left a file");
    }
    // --write-origin needs PLY.
    let obj = dir.path().join("x.obj");
    let o = tessella(&["refine", s(&input), "-o", s(&obj), "--write-origin"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains(".ply"));
    // Above the tessellator's maximum: clamped, as the hardware does.
    let o = tessella(&[
        "refine",
        s(&input),
        "-o",
        s(&out),
        "--spacing",
        "equal",
        "--level",
        "500",
        "--backend",
        "cpu",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("levels up to 64"), "{}", stderr(&o));
}

#[test]
fn the_fly_in_uploads_the_same_coarse_bytes_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sample(dir.path(), "creature");
    let out = dir.path().join("frames");
    let o = tessella(&[
        "animate",
        s(&input),
        "-o",
        s(&out),
        "--fly-in",
        "--frames",
        "3",
        "--size",
        "96x72",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        assert!(out.join(format!("frame_{k:03}.png")).is_file(), "frame {k}");
    }
    // 320 triangles: a 96-byte record and four 4-byte instances each.
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(&format!("{} bytes of levels uploaded per frame", 320 * 112)),
        "{text}"
    );
}
