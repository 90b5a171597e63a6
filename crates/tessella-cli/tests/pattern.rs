//! `tessella pattern` with the hardware tessellator spacings and the SVG drawing, end to end.

use std::process::{Command, Output};

fn tessella(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn len(v: &serde_json::Value) -> usize {
    v.as_array().unwrap().len()
}

#[test]
fn equal_three_has_the_hardware_counts() {
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "equal",
        "--level",
        "3",
    ]));
    // Equal spacing, all levels n = 3: (3n² - 1) / 2 = 13 triangles; 9 boundary points, an
    // inner triangle of 3 (a disk with 13 faces and 9 boundary edges has 1 + (13 + 9)/2 = 12).
    assert_eq!(len(&j["triangles"]), 13);
    assert_eq!(len(&j["points"]), 12);
    assert_eq!(j["level"], 3);
    assert_eq!(j["spacing"], "equal");
    assert_eq!(j["culled"], false);
    assert_eq!(j["levels"]["inner"], 3.0);
    // The first point is corner P2 (the edge l1 = 0 starts there).
    assert_eq!(j["points"][0], serde_json::json!([0.0, 1.0, 0.0]));
    // --inner and --outer override --level, in GL order.
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "equal",
        "--level",
        "2",
        "--outer",
        "4,2,2",
    ]));
    assert_eq!(j["levels"]["outer"], serde_json::json!([4.0, 2.0, 2.0]));
    // Four segments on the edge l1 = 0: five points with l1 = 0.
    let on_edge = j["points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p[0] == 0.0)
        .count();
    assert_eq!(on_edge, 5);
}

#[test]
fn levels_above_the_maximum_are_clamped() {
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "equal",
        "--level",
        "1000",
    ]));
    assert_eq!(j["level"], 64);
    assert_eq!(j["levels"]["outer"], serde_json::json!([64.0, 64.0, 64.0]));
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "fractional-odd",
        "--level",
        "inf",
    ]));
    assert_eq!(j["level"], 63);
}

#[test]
fn culled_levels_give_an_empty_pattern_and_a_note() {
    for args in [
        &["pattern", "--spacing", "equal", "--level", "NaN"][..],
        &[
            "pattern",
            "--spacing",
            "fractional-even",
            "--inner",
            "3",
            "--outer=-1,2,3",
        ],
        &[
            "pattern",
            "--spacing",
            "fractional-odd",
            "--inner",
            "3",
            "--outer",
            "2,0,3",
        ],
    ] {
        let o = tessella(args);
        let j = json(&o);
        assert_eq!(j["culled"], true, "{args:?}");
        assert_eq!(len(&j["points"]), 0);
        assert_eq!(len(&j["triangles"]), 0);
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("culls"),
            "{args:?}"
        );
    }
    // A NaN inner level is not culling: it is raised to the minimum.
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "equal",
        "--inner",
        "NaN",
        "--outer",
        "2,2,2",
    ]));
    assert_eq!(j["levels"]["inner"], 1.0);
    assert!(len(&j["triangles"]) > 0);
}

#[test]
fn bad_arguments_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.json");
    let out_s = out.to_str().unwrap();
    for args in [
        &[
            "pattern",
            "--spacing",
            "grid",
            "--level",
            "2.5",
            "-o",
            out_s,
        ][..],
        &["pattern", "--level", "2.5", "-o", out_s],
        &["pattern", "--level", "3", "--inner", "2", "-o", out_s],
        &[
            "pattern",
            "--spacing",
            "equal",
            "--outer",
            "1,2",
            "--inner",
            "2",
            "-o",
            out_s,
        ],
        &["pattern", "--spacing", "equal", "-o", out_s],
        &["pattern", "-o", out_s],
    ] {
        let o = tessella(args);
        assert!(!o.status.success(), "{args:?}");
        assert!(!o.stderr.is_empty());
        assert!(!out.exists(), "{args:?} left a file");
    }
    let o = tessella(&["pattern", "--spacing", "grid", "--level", "2.5"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("whole number"));
    // A whole number written as a float is still a grid level.
    assert_eq!(json(&tessella(&["pattern", "--level", "4.0"]))["level"], 4);
}

#[test]
fn svg_drawings_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("pattern.svg");
    let o = tessella(&[
        "pattern",
        "--spacing",
        "fractional-odd",
        "--inner",
        "2.5",
        "--outer",
        "1.5,3.2,5",
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout.is_empty());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    // One circle per point: compare with the JSON of the same levels.
    let j = json(&tessella(&[
        "pattern",
        "--spacing",
        "fractional-odd",
        "--inner",
        "2.5",
        "--outer",
        "1.5,3.2,5",
    ]));
    assert_eq!(text.matches("<circle").count(), len(&j["points"]));
    assert_eq!(text.matches('Z').count(), len(&j["triangles"]));
    // --svg next to the JSON output; nothing but the two files is left in the folder.
    let json_path = dir.path().join("p.json");
    let svg2 = dir.path().join("grid.svg");
    let o = tessella(&[
        "pattern",
        "--level",
        "3",
        "--svg",
        svg2.to_str().unwrap(),
        "-o",
        json_path.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let grid = std::fs::read_to_string(&svg2).unwrap();
    assert_eq!(grid.matches("<circle").count(), 10);
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    assert_eq!(len(&j["triangles"]), 9);
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["grid.svg", "p.json", "pattern.svg"]);
}
