//! The fly-in: the camera moves towards the mesh with screen-size levels and fractional-odd
//! spacing, so levels grow with every frame and points move continuously. Measured on the
//! pictures: neighbouring frames differ little, the first and last a lot; and on the plans:
//! the triangle count grows monotonically.

use image::RgbaImage;
use tessella_core::refine::Spacing;
use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{animate, RenderOptions};

/// Mean absolute channel difference per pixel (0..255).
fn mean_diff(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let sum: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    sum as f64 / a.as_raw().len() as f64
}

#[test]
fn a_fly_in_changes_smoothly_and_refines_more_and_more() {
    let ctx = GpuContext::new(AdapterChoice::Software).expect("a software adapter");
    let dir = std::env::temp_dir().join(format!("tessella-fly-in-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = samples::torus(1.0, 0.35, 12, 8);
    let refine = RefineOptions::new(Scheme::Pn, 1).with_spacing(Spacing::FractionalOdd);
    let view = RenderOptions {
        size: (128, 96),
        pitch: 15.0,
        wireframe: true,
        ..Default::default()
    };
    let frames = 12;
    let stats =
        animate::render_fly_in(&ctx, &mesh, &refine, &view, frames, (0.8, 2.2), 6.0, &dir).unwrap();
    assert_eq!(stats.paths.len(), frames as usize);
    for w in stats.triangles.windows(2) {
        assert!(w[1] >= w[0], "triangle counts fall: {:?}", stats.triangles);
    }
    // Every frame uploads the same coarse data for its levels: a record per face and an
    // instance per face and part, at most 112 bytes per face.
    let faces = mesh.face_count() as u64;
    assert!(stats
        .upload_bytes
        .iter()
        .all(|&b| b == stats.upload_bytes[0]));
    assert!(
        stats.upload_bytes[0] <= 112 * faces,
        "{:?}",
        stats.upload_bytes
    );
    let (first, last) = (stats.triangles[0], *stats.triangles.last().unwrap());
    assert!(last > 3 * first, "triangles {first} -> {last}");
    let pictures: Vec<RgbaImage> = stats
        .paths
        .iter()
        .map(|p| image::open(p).unwrap().to_rgba8())
        .collect();
    let steps: Vec<f64> = pictures
        .windows(2)
        .map(|w| mean_diff(&w[0], &w[1]))
        .collect();
    let whole = mean_diff(&pictures[0], &pictures[frames as usize - 1]);
    let largest = steps.iter().cloned().fold(0.0, f64::max);
    // A step moves the camera by 1/11 of the way: its pictures differ far less than the ends.
    assert!(whole > 20.0, "first and last frames differ by only {whole}");
    assert!(
        largest < whole / 3.0,
        "a step differs by {largest} (steps {steps:?}), the whole fly-in by {whole}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
