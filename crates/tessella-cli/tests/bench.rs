//! `tessella bench --json`: every section present, counts that follow from the layout, and
//! file sizes that follow from the formats (the rates themselves depend on the machine and are
//! not checked).

use std::process::Command;

#[test]
fn bench_json_has_every_section_with_consistent_counts() {
    let out = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(["bench", "--json", "--levels", "2,4", "--repeat", "1"])
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let num = |v: &serde_json::Value| v.as_f64().unwrap();
    let bw = &report["bandwidth"];
    for key in [
        "fill_bytes_per_s",
        "fill_plain_bytes_per_s",
        "fill_nt_bytes_per_s",
        "fill_plain_one_thread_bytes_per_s",
        "copy_bytes_per_s",
        "copy_nt_bytes_per_s",
        "fresh_fill_bytes_per_s",
    ] {
        assert!(num(&bw[key]) > 1e8, "{key}: {}", bw[key]);
    }
    // The tables divide by the faster of the two fills.
    assert_eq!(
        num(&bw["fill_bytes_per_s"]),
        num(&bw["fill_plain_bytes_per_s"]).max(num(&bw["fill_nt_bytes_per_s"]))
    );
    let faces = report["faces"].as_u64().unwrap();
    assert_eq!(faces, 5120);
    // Welded icosphere: V + E (L - 1) + F (L - 1)(L - 2) / 2 vertices, F L² triangles.
    let (v, e) = (2562u64, 7680u64);
    let vertices = |l: u64| v + e * (l - 1) + faces * (l - 1) * (l - 2) / 2;
    let one_shot = report["one_shot"].as_array().unwrap();
    assert_eq!(one_shot.len(), 2);
    for (row, l) in one_shot.iter().zip([2u64, 4]) {
        assert_eq!(row["vertices"].as_u64().unwrap(), vertices(l));
        assert_eq!(row["triangles"].as_u64().unwrap(), faces * l * l);
        assert_eq!(
            row["output_bytes"].as_u64().unwrap(),
            vertices(l) * 24 + faces * l * l * 12
        );
    }
    let per_frame = report["per_frame"].as_array().unwrap();
    assert_eq!(per_frame.len(), 2 * 5, "five schemes at two levels");
    for row in per_frame {
        let l = row["level"].as_u64().unwrap();
        assert_eq!(row["vertices"].as_u64().unwrap(), vertices(l));
        assert_eq!(row["bytes_per_vertex"].as_u64().unwrap(), 24);
        let rate = num(&row["vertices_per_s"]);
        assert!((num(&row["bytes_per_s"]) - 24.0 * rate).abs() <= 1e-6 * 24.0 * rate);
        if row["scheme"] == "pn" && row["normals"] == "quadratic" {
            assert_eq!(num(&row["vs_pn"]), 1.0);
        }
    }
    // Deforming rows: the bundled icosphere and the creature.
    assert_eq!(report["deforming"].as_array().unwrap().len(), 4);
    // Writers: the level-4 mesh (the largest level up to 32) in five formats.
    assert_eq!(report["write_level"].as_u64().unwrap(), 4);
    let writers = report["writers"].as_array().unwrap();
    let size = |format: &str| {
        writers
            .iter()
            .find(|w| w["format"] == format)
            .unwrap_or_else(|| panic!("no {format} row"))["bytes"]
            .as_u64()
            .unwrap()
    };
    let (nv, nt) = (vertices(4), faces * 16);
    // Binary STL: 80-byte header, count, 50 bytes a triangle.
    assert_eq!(size("STL"), 84 + 50 * nt);
    // Binary PLY: a header, 24 bytes a vertex, 13 a triangle.
    let ply_body = nv * 24 + nt * 13;
    assert!(size("PLY binary") > ply_body && size("PLY binary") < ply_body + 400);
    // GLB: positions, normals, u32 indices, plus a JSON chunk.
    let glb_body = nv * 24 + nt * 12;
    assert!(size("GLB") > glb_body && size("GLB") < glb_body + 2000);
    assert!(size("OBJ") > size("PLY binary") && size("PLY ascii") > size("PLY binary"));
}
