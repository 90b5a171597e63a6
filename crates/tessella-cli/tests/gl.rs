//! `tessella refine --backend gl` against `--backend cpu` with the same scheme, spacing, levels
//! and normals: the same triangle count and every GL vertex within 1e-5 of the bounding-box
//! diagonal of a CPU vertex with a normal within 1e-4 (the GL output is unwelded: compared with
//! the CPU's `--soup`, as sets). Needs an EGL driver with OpenGL 4.3 (CI: Mesa's llvmpipe).
#![cfg(feature = "gl")]

use std::path::Path;
use std::process::{Command, Output};
use tessella_core::samples;

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn gl_backend_output_equals_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ico.ply");
    let mesh = samples::icosphere(0);
    tessella_io::write_mesh(&input, (&mesh).into(), &Default::default()).unwrap();
    let diag = mesh.diagonal();
    let cases: &[&[&str]] = &[
        &["--scheme", "flat", "--spacing", "equal", "--level", "3"],
        &[
            "--scheme",
            "phong",
            "--spacing",
            "fractional-odd",
            "--level",
            "3.5",
        ],
        &[
            "--scheme",
            "pn",
            "--spacing",
            "fractional-even",
            "--level",
            "4.2",
        ],
        &[
            "--scheme",
            "pn",
            "--normals",
            "real",
            "--spacing",
            "equal",
            "--level",
            "4",
        ],
        &[
            "--scheme",
            "png1",
            "--spacing",
            "fractional-odd",
            "--level",
            "2.7",
        ],
        &[
            "--scheme",
            "pn",
            "--spacing",
            "fractional-odd",
            "--lod",
            "tolerance:0.003",
        ],
        &[
            "--scheme",
            "png1",
            "--spacing",
            "equal",
            "--lod",
            "tolerance:0.003",
        ],
    ];
    for case in cases {
        let run = |backend: &str| {
            let out = dir.path().join(format!("{backend}.ply"));
            let mut a = vec![
                "refine",
                s(&input),
                "-o",
                s(&out),
                "--backend",
                backend,
                "--soup",
            ];
            a.extend_from_slice(case);
            let o = tessella(&a);
            assert!(
                o.status.success(),
                "{backend} {case:?}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            tessella_io::read_mesh(&out).unwrap()
        };
        let (cpu, gl) = (run("cpu"), run("gl"));
        assert_eq!(
            cpu.face_count(),
            gl.face_count(),
            "{case:?}: triangle count"
        );
        for (i, (p, n)) in gl.positions().iter().zip(gl.normals()).enumerate() {
            // Where faces meet, the soup has one copy per face, each with its face's normal
            // (real normals differ across edges): some copy must match both.
            let near: Vec<usize> = (0..cpu.positions().len())
                .filter(|&j| dist(*p, cpu.positions()[j]) <= 1e-5 * diag)
                .collect();
            assert!(
                !near.is_empty(),
                "{case:?}: GL vertex {i} {p:?} is on no CPU vertex"
            );
            assert!(
                near.iter().any(|&j| dist(*n, cpu.normals()[j]) <= 1e-4),
                "{case:?}: GL vertex {i} normal {n:?}, CPU normals there {:?}",
                near.iter().map(|&j| cpu.normals()[j]).collect::<Vec<_>>()
            );
        }
    }
}

#[test]
fn gl_backend_refuses_the_grid_with_a_message_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ico.ply");
    tessella_io::write_mesh(&input, (&samples::icosphere(0)).into(), &Default::default()).unwrap();
    let out = dir.path().join("x.ply");
    let o = tessella(&[
        "refine",
        s(&input),
        "-o",
        s(&out),
        "--backend",
        "gl",
        "--level",
        "3",
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("fractional-odd"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists());
}

/// Non-background pixels (the background is white; the surface, shaded or coloured by normal,
/// is darker in some channel).
fn mask(path: &Path) -> (Vec<bool>, (u32, u32)) {
    let img = image::open(path).unwrap().to_rgba8();
    let m = img
        .pixels()
        .map(|p| p.0[..3].iter().any(|&c| c < 200))
        .collect();
    (m, img.dimensions())
}

#[cfg(feature = "gpu")]
#[test]
fn gl_render_has_the_wgpu_silhouette_and_compare_panels_fill_the_size() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("creature.ply");
    tessella_io::write_mesh(&input, (&samples::creature()).into(), &Default::default()).unwrap();
    let view = [
        "--spacing",
        "equal",
        "--level",
        "6",
        "--size",
        "320x240",
        "--yaw",
        "50",
        "--pitch",
        "-15",
        "--zoom",
        "1.3",
    ];
    let mut masks = Vec::new();
    for backend in ["gpu", "gl"] {
        let out = dir.path().join(format!("{backend}.png"));
        let mut argv = vec!["render", s(&input), "-o", s(&out), "--backend", backend];
        argv.extend_from_slice(&view);
        let run = tessella(&argv);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        masks.push(mask(&out));
    }
    let ((a, size_a), (b, size_b)) = (&masks[0], &masks[1]);
    assert_eq!(size_a, &(320, 240));
    assert_eq!(size_b, &(320, 240));
    let covered = b.iter().filter(|&&x| x).count();
    let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
    let fraction = differ as f64 / a.len() as f64;
    // The surface covers a good part of the picture, and the two silhouettes agree but for
    // the edge pixels (wgpu multisamples, GL does not).
    eprintln!(
        "silhouettes: {differ} of {} pixels differ ({covered} covered)",
        a.len()
    );
    assert!(covered > a.len() / 8, "{covered} covered pixels");
    assert!(fraction < 0.01, "{differ} of {} pixels differ", a.len());

    // Compare panels: the requested total size, three panels with separators.
    let out = dir.path().join("compare.png");
    let run = tessella(&[
        "render",
        s(&input),
        "-o",
        s(&out),
        "--backend",
        "gl",
        "--compare",
        "flat,pn,png1",
        "--level",
        "4",
        "--wireframe",
        "--size",
        "301x120",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (301, 120));
    // The separators (tessella-view's dark gap) after panels of (301 - 4) / 3 = 99 pixels.
    for x in [99, 100, 200, 201] {
        assert_eq!(img.get_pixel(x, 119).0, [40, 40, 48, 255], "column {x}");
    }
    // Wireframe lines are near-black over the surface.
    let dark = img
        .pixels()
        .filter(|p| p.0[..3].iter().all(|&c| c < 40))
        .count();
    assert!(dark > 200, "{dark} near-black pixels");
}

#[cfg(feature = "gpu")]
#[test]
fn gl_render_without_a_driver_is_a_clear_error_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ico.ply");
    tessella_io::write_mesh(&input, (&samples::icosphere(0)).into(), &Default::default()).unwrap();
    let out = dir.path().join("x.png");
    // glvnd finds no vendor library: EGL has no display.
    let run = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(["render", s(&input), "-o", s(&out), "--backend", "gl"])
        .env("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/vendor.json")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("no OpenGL 4 driver"), "{err}");
    assert!(err.contains("libegl-mesa0"), "{err}");
    assert!(!out.exists());
}

/// `tessella bench --gl`: both GL tables, a row for the level asked for, positive ratios, and the
/// driver labelled software or hardware.
#[test]
fn bench_gl_prints_the_tessellator_tables() {
    let out = tessella(&["bench", "--gl", "--levels", "2", "--repeat", "1"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("GL driver: "), "{text}");
    assert!(
        text.contains("software") || text.contains("hardware"),
        "{text}"
    );
    let row = |header: &str| -> Vec<String> {
        let at = text
            .find(header)
            .unwrap_or_else(|| panic!("no table {header}: {text}"));
        let line = text[at..]
            .lines()
            .find(|l| l.starts_with("| 2 |"))
            .unwrap_or_else(|| panic!("no level-2 row after {header}: {text}"));
        line.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    };
    // n = 2: 320 faces × 6 triangles on the GL, the grid m = 2: 320 × 4.
    let pattern = row("| n | GL triangles | m |");
    assert_eq!(&pattern[..4], ["2", "1920", "2", "1280"], "{text}");
    let normals = row("| n | triangles | vertices | quadratic GL / CPU |");
    assert_eq!(&normals[..3], ["2", "1920", "5760"], "{text}");
    for cells in [&pattern[4..], &normals[3..]] {
        for c in cells.iter().filter(|c| *c != "—") {
            let x: f64 = c.parse().unwrap_or_else(|_| panic!("'{c}' in {text}"));
            assert!(x > 0.0, "{c} in {text}");
        }
    }
    // The GL ratio columns are always measured.
    assert!(pattern[5].parse::<f64>().unwrap() > 0.0, "{text}");
    assert!(normals[5].parse::<f64>().unwrap() > 0.0, "{text}");
}
