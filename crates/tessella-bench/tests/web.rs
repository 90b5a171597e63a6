//! The web page's benchmark report on lavapipe: its configuration is checked before anything
//! runs, and its rows count what the papers count (pattern points, welded refined vertices)
//! and show both Figure 7 paths drew the same surface.

use serde_json::{json, Value};
use tessella_bench::gpu::mesh_with_faces;
use tessella_bench::web::{run, BenchConfig};
use tessella_core::{Pattern, RefineOptions, Refiner, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};

fn ctx() -> GpuContext {
    GpuContext::new(AdapterChoice::Software).expect("a software adapter")
}

#[test]
fn bad_configurations_are_refused_by_name() {
    for (config, words) in [
        (json!({"faces": [0]}), "0 coarse triangles"),
        (json!({"levels": [8, 999]}), "level 999"),
        (json!({"frames": 0}), "frames 0"),
        (json!({"size": [0, 10]}), "size 0x10"),
        (json!({"parts": ["figure8"]}), "unknown part"),
        (json!({"scheme": "loop"}), "scheme"),
        (json!({"movingTop": 1000}), "movingTop"),
        (json!({"levls": [8]}), "unknown field"),
        // Each field in range, the whole far too much to draw.
        (
            json!({"faces": [100000], "levels": [256], "frames": 1000}),
            "triangles to draw in all",
        ),
    ] {
        let e = BenchConfig::from_json(&config).unwrap_err().to_string();
        assert!(
            e.starts_with("bench: ") && e.contains(words),
            "{config}: {e}"
        );
    }
    assert_eq!(
        BenchConfig::from_json(&Value::Null).unwrap(),
        BenchConfig::default()
    );
    let d = BenchConfig::default();
    assert_eq!((d.faces, d.levels), (vec![10, 100, 1000], vec![64, 128]));
}

#[test]
fn the_report_counts_what_the_papers_count() {
    let config = BenchConfig::from_json(&json!({
        "faces": [10, 40], "levels": [8], "frames": 2, "size": [96, 96],
        "schemeFaces": [20], "schemeLevels": [4, 5], "movingTop": 6
    }))
    .unwrap();
    let report = pollster::block_on(run(&ctx(), &config)).unwrap();
    assert!(report["adapter"].as_str().unwrap().contains("software"));
    let rows = report["figure7"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for (row, faces) in rows.iter().zip([10, 40]) {
        assert_eq!(row["faces"], faces);
        // One triangle's (N+1)(N+2)/2 points, whatever the mesh.
        assert_eq!(row["patternVertices"], Pattern::point_count(8));
        let welded = Refiner::new(
            &mesh_with_faces(faces).unwrap(),
            &RefineOptions::new(Scheme::Pn, 8),
        )
        .unwrap()
        .layout()
        .vertex_count;
        assert_eq!(row["staticVertices"], welded);
        // At least a position per vertex and three 16-bit indices per triangle.
        let static_bytes = row["staticBytes"].as_u64().unwrap();
        assert!(static_bytes >= welded * 12 + faces as u64 * 64 * 6);
        let (p, s) = (
            row["patternMs"].as_f64().unwrap(),
            row["staticMs"].as_f64().unwrap(),
        );
        assert!(p > 0.0 && s > 0.0);
        assert!((row["frameRatio"].as_f64().unwrap() - p / s).abs() < 1e-9);
        let footprint = row["patternBytes"].as_f64().unwrap() / static_bytes as f64;
        assert!((row["footprintRatio"].as_f64().unwrap() - footprint).abs() < 1e-12);
        let differ = row["picturesDiffer"].as_f64().unwrap();
        assert!(
            differ < 0.02,
            "the two paths drew different pictures: {differ}"
        );
    }
    // The pattern is shared: more coarse triangles grow the static buffer four-fold, the
    // pattern's part not at all.
    let bytes = |i: usize, k: &str| rows[i][k].as_u64().unwrap() as f64;
    assert!(bytes(1, "staticBytes") > 3.5 * bytes(0, "staticBytes"));
    assert!(bytes(1, "patternBytes") < 2.0 * bytes(0, "patternBytes"));
    let schemes = report["schemes"].as_array().unwrap();
    assert_eq!(schemes.len(), 2);
    for row in schemes {
        for k in ["flatMs", "pnMs", "png1Ms", "pnOverFlat", "png1RateOverPn"] {
            assert!(row[k].as_f64().unwrap() > 0.0, "{k} in {row}");
        }
    }
    let moving = report["moving"].as_array().unwrap();
    assert_eq!(moving.len(), 2);
    assert!(moving
        .iter()
        .all(|r| r["adaptiveMs"].as_f64().unwrap() > 0.0));
    let markdown = report["markdown"].as_str().unwrap();
    for heading in ["## Figure 7", "## Schemes", "## Levels moving"] {
        assert!(markdown.contains(heading), "{heading} missing:\n{markdown}");
    }
    // Three tables, each a header line and two rows.
    assert_eq!(
        markdown.lines().filter(|l| l.starts_with("| ")).count(),
        3 * (1 + 2)
    );
}

#[test]
fn only_the_parts_asked_for_run() {
    let config = BenchConfig::from_json(&json!({
        "faces": [10], "levels": [4], "frames": 1, "size": [32, 32], "parts": ["figure7"]
    }))
    .unwrap();
    let report = pollster::block_on(run(&ctx(), &config)).unwrap();
    assert_eq!(report["figure7"].as_array().unwrap().len(), 1);
    assert!(report["schemes"].as_array().unwrap().is_empty());
    assert!(report["moving"].as_array().unwrap().is_empty());
}
