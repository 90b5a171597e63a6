//! A file made by another tool: three.js r187's `GLTFExporter` wrote `fixtures/three/skinned.gltf`
//! (a skinned, morphing cylinder under a transformed parent, a LINEAR/STEP clip) and three.js
//! posed it itself (`SkinnedMesh.getVertexPosition`, in scene space) into
//! `fixtures/three/skinned-poses.json` (`fixtures/three/make.mjs` made both). tessella reads the
//! file and poses it the same, within 1e-6 of the bounding box's diagonal.

use std::path::Path;
use tessella_core::animation::Poser;

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/three")
        .join(name)
}

fn points(value: &serde_json::Value) -> Vec<[f32; 3]> {
    value
        .as_array()
        .expect("an array of points")
        .iter()
        .map(|p| {
            let p = p.as_array().expect("a point");
            [0, 1, 2].map(|k| p[k].as_f64().expect("a number") as f32)
        })
        .collect()
}

fn diagonal(points: &[[f32; 3]]) -> f32 {
    let (lo, hi) = tessella_core::mesh::bounds(points);
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt()
}

fn assert_close(got: &[[f32; 3]], want: &[[f32; 3]], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: vertex count");
    let tolerance = 1e-6 * diagonal(want);
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let d = (0..3).map(|k| (g[k] - w[k]).abs()).fold(0.0, f32::max);
        assert!(
            d <= tolerance,
            "{what}: vertex {i} at {g:?}, three.js has {w:?} ({d} > {tolerance})"
        );
    }
}

#[test]
fn a_three_js_export_poses_as_three_js_poses_it() {
    let expected: serde_json::Value =
        serde_json::from_slice(&std::fs::read(fixture("skinned-poses.json")).unwrap()).unwrap();
    let model = tessella_io::read_animated(&fixture("skinned.gltf")).unwrap();
    assert_eq!(model.instances.len(), 1);
    assert_eq!(
        model.instances[0].node as u64,
        expected["mesh_node"].as_u64().unwrap()
    );
    let poser = Poser::new(model).unwrap();
    let clip = poser
        .clip_index(expected["clip"].as_str().unwrap())
        .unwrap();

    // No clip: the rest pose three.js binds the skin in.
    let (rest, _) = poser.pose(None, 0.0).unwrap();
    assert_close(&rest, &points(&expected["bind_positions"]), "bind pose");

    let times = expected["times"].as_array().unwrap();
    let poses = expected["positions"].as_array().unwrap();
    assert_eq!(times.len(), poses.len());
    let mut moved = 0.0f32;
    for (t, want) in times.iter().zip(poses) {
        let t = t.as_f64().unwrap() as f32;
        let want = points(want);
        let (got, _) = poser.pose(Some(clip), t).unwrap();
        assert_close(&got, &want, &format!("t = {t}"));
        for (a, b) in want.iter().zip(&rest) {
            moved = moved.max((0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max));
        }
    }
    // The clip really moves the mesh (the comparison is not of two rest poses).
    assert!(moved > 1.0, "{moved}");
}
