//! Pixel cracks in the instanced renderer. Back faces are painted magenta: on a closed, outward
//! surface the first surface a ray meets faces it, so a magenta pixel is the inside seen through
//! a crack between two coarse triangles. The renderer evaluates shared-edge points canonically
//! (eval.wgsl's `tessella_edge_point`), so PN on a closed smooth mesh shows none at any level; PN on
//! a cube with split normals really opens at its hard edges, and the count sees it.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

mod pixels;

use common::ctx;
use pixels::crack_pixels;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_view::{render, RenderOptions};

use pixels::MAGENTA;

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
