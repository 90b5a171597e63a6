//! Pixel cracks in the instanced renderer. Back faces are painted magenta: on a closed, outward
//! surface the first surface a ray meets faces it, so a magenta pixel is the inside seen through
//! a crack between two coarse triangles. The renderer evaluates shared-edge points canonically
//! (eval.wgsl's `canonical_edge`), so PN on a closed smooth mesh shows none at any level; PN on
//! a cube with split normals really opens at its hard edges, and the count sees it.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

use common::ctx;
use image::RgbaImage;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_view::{render, RenderOptions};

const MAGENTA: [u8; 3] = [255, 0, 255];

/// Pixels with a magenta tint (some sample of them saw a back face) inside the silhouette: at
/// least 2 pixels from the white background, since where the rim's front and back triangles
/// meet, depth ties can let a back face win a sample.
fn crack_pixels(image: &RgbaImage) -> usize {
    let (w, h) = image.dimensions();
    let background = |x: i64, y: i64| {
        x < 0
            || y < 0
            || x >= w as i64
            || y >= h as i64
            || image.get_pixel(x as u32, y as u32).0[..3] == [255; 3]
    };
    image
        .enumerate_pixels()
        .filter(|&(x, y, p)| {
            let [r, g, b, _] = p.0.map(i32::from);
            let (x, y) = (x as i64, y as i64);
            r > g + 24
                && b > g + 24
                && (-2..=2).all(|dy| (-2..=2).all(|dx| !background(x + dx, y + dy)))
        })
        .count()
}

fn cracks(mesh: &Mesh, scheme: Scheme, level: u32, yaw: f32, pitch: f32) -> usize {
    let view = RenderOptions {
        size: (256, 256),
        yaw,
        pitch,
        back_color: Some(MAGENTA),
        ..Default::default()
    };
    let picture = render(ctx(), mesh, &RefineOptions::new(scheme, level), &view).unwrap();
    crack_pixels(&picture)
}

#[test]
fn pn_icosphere_shows_no_cracks_at_any_level() {
    let mesh = samples::icosphere(1);
    let mut total = 0;
    for level in [2, 3, 5, 7, 16, 33] {
        for (yaw, pitch) in [(0.0, 0.0), (23.0, 17.0), (61.0, -35.0)] {
            let n = cracks(&mesh, Scheme::Pn, level, yaw, pitch);
            total += n;
            assert_eq!(
                n, 0,
                "level {level}, yaw {yaw}, pitch {pitch}: {n} crack pixels"
            );
        }
    }
    assert_eq!(total, 0);
    // PNG1 and Phong close their edges too.
    for scheme in [Scheme::Png1, Scheme::PHONG] {
        assert_eq!(cracks(&mesh, scheme, 7, 23.0, 17.0), 0, "{}", scheme.name());
    }
}

#[test]
fn a_real_crack_is_counted() {
    // PN with split normals where the faceted half of this sphere meets the smooth half: the
    // two sides of those edges bulge differently and the surface opens.
    let n = cracks(
        &samples::half_faceted_icosphere(1),
        Scheme::Pn,
        8,
        30.0,
        25.0,
    );
    assert!(n > 50, "only {n} crack pixels on the opened cube");
}
