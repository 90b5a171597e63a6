//! The wireframe stays readable on dense meshes: coarse edges bold and dark, the pattern's own
//! edges thin and light. Measured on the picture: where the CPU's refined mesh, projected with
//! the picture's own camera, puts coarse and refined edges, and how much darker those pixels
//! are than in the same picture without the wireframe.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

use common::ctx;
use image::RgbaImage;
use tessella_core::pattern::PointClass;
use tessella_core::{refine, samples, Mesh, RefineOptions, Scheme};
use tessella_view::{render, scene_uniforms, RenderOptions};

/// Rec. 709 luma of an sRGB pixel, 0..255.
fn luma(p: &image::Rgba<u8>) -> f64 {
    0.2126 * p.0[0] as f64 + 0.7152 * p.0[1] as f64 + 0.0722 * p.0[2] as f64
}

/// Pixels that are not the white background.
fn silhouette(image: &RgbaImage) -> usize {
    image.pixels().filter(|p| p.0[..3] != [255; 3]).count()
}

/// Fraction of the silhouette's pixels that are dark (every channel below 60).
fn dark_fraction(image: &RgbaImage) -> f64 {
    let dark = image
        .pixels()
        .filter(|p| p.0[..3] != [255; 3] && p.0[..3].iter().all(|&c| c < 60))
        .count();
    dark as f64 / silhouette(image) as f64
}

/// Mean darkening (luma of `plain` minus luma of `wire`) at the pixels under the midpoints of
/// coarse edges and of the pattern's other edges that face the camera: `(coarse, refined)`.
/// Edges come from the CPU's soup output (straight segments between refined vertices, as the
/// renderer draws them) and are projected with the picture's camera.
fn edge_darkening(
    mesh: &Mesh,
    options: &RefineOptions,
    view: &RenderOptions,
    plain: &RgbaImage,
    wire: &RgbaImage,
) -> (f64, f64) {
    let out = refine(mesh, &options.clone().with_weld(false)).unwrap();
    let pattern = tessella_core::Pattern::uniform(
        options.uniform_grid_level().expect("a uniform grid level"),
    );
    let per_face = pattern.points.len();
    let u = scene_uniforms(mesh, view, 0.0);
    let vp = glam::Mat4::from_cols_array_2d(&u.view_proj);
    let eye = glam::Vec3::from_slice(&u.eye[..3]);
    let (w, h) = view.size;
    // The coarse edge a pattern point lies on (corners lie on two).
    let on_edge = |p: u32, k: u8| match pattern.classes[p as usize] {
        PointClass::Corner { corner } => corner == k || corner == (k + 1) % 3,
        PointClass::Edge { edge, .. } => edge == k,
        PointClass::Interior { .. } => false,
    };
    let (mut coarse, mut refined) = (Vec::new(), Vec::new());
    for f in 0..mesh.face_count() {
        for t in &pattern.triangles {
            for c in 0..3 {
                let (a, b) = (t[c], t[(c + 1) % 3]);
                let is_coarse = (0..3).any(|k| on_edge(a, k) && on_edge(b, k));
                let at = |p: u32| glam::Vec3::from(out.positions[f * per_face + p as usize]);
                let normal = |p: u32| glam::Vec3::from(out.normals[f * per_face + p as usize]);
                let mid = 0.5 * (at(a) + at(b));
                let n = (normal(a) + normal(b)).normalize();
                // Clearly facing the camera (the sphere is convex: then it is visible).
                if n.dot((eye - mid).normalize()) < 0.5 {
                    continue;
                }
                let clip = vp * mid.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                let x = ((ndc.x + 1.0) * 0.5 * w as f32) as u32;
                let y = ((1.0 - ndc.y) * 0.5 * h as f32) as u32;
                if x >= w || y >= h {
                    continue;
                }
                let d = luma(plain.get_pixel(x, y)) - luma(wire.get_pixel(x, y));
                if is_coarse {
                    coarse.push(d);
                } else {
                    refined.push(d);
                }
            }
        }
    }
    let mean = |v: &[f64]| {
        assert!(v.len() > 50, "only {} edge samples", v.len());
        v.iter().sum::<f64>() / v.len() as f64
    };
    (mean(&coarse), mean(&refined))
}

fn pictures(mesh: &Mesh, refine: &RefineOptions, view: &RenderOptions) -> (RgbaImage, RgbaImage) {
    let plain = render(ctx(), mesh, refine, view).unwrap();
    let wire = render(
        ctx(),
        mesh,
        refine,
        &RenderOptions {
            wireframe: true,
            ..view.clone()
        },
    )
    .unwrap();
    (plain, wire)
}

#[test]
fn dense_mesh_wireframe_is_not_a_black_silhouette() {
    // 5120 coarse triangles at level 4: 82k pattern triangles of a few pixels each.
    let mesh = samples::icosphere_4k();
    let refine = RefineOptions::new(Scheme::Pn, 4);
    let view = RenderOptions {
        size: (600, 600),
        ..Default::default()
    };
    let (plain, wire) = pictures(&mesh, &refine, &view);
    let (dp, dw) = (dark_fraction(&plain), dark_fraction(&wire));
    eprintln!("dark fraction inside the silhouette: plain {dp:.3}, wireframe {dw:.3}");
    assert!(dp < 0.01, "the plain surface is dark: {dp}");
    assert!(dw < 0.25, "{:.0}% of the silhouette is dark", 100.0 * dw);
    let (coarse, refined) = edge_darkening(&mesh, &refine, &view, &plain, &wire);
    eprintln!("darkening: coarse edges {coarse:.1}, refined edges {refined:.1}");
    // The coarse net is drawn (clearly darker than the surface there) and darker than the
    // refined edges, which on triangles this small fade to (almost) nothing.
    assert!(coarse > 40.0, "coarse edges barely drawn: {coarse}");
    assert!(
        coarse > refined + 30.0,
        "coarse {coarse} vs refined {refined}"
    );
}

#[test]
fn coarse_edges_are_darker_than_the_visible_refined_edges() {
    // 320 coarse triangles at level 4: pattern triangles big enough for their edges to show.
    let mesh = samples::icosphere(2);
    let refine = RefineOptions::new(Scheme::Pn, 4);
    let view = RenderOptions {
        size: (400, 400),
        ..Default::default()
    };
    let (plain, wire) = pictures(&mesh, &refine, &view);
    let (coarse, refined) = edge_darkening(&mesh, &refine, &view, &plain, &wire);
    eprintln!("darkening: coarse edges {coarse:.1}, refined edges {refined:.1}");
    assert!(refined > 8.0, "refined edges not drawn: {refined}");
    assert!(
        coarse > 1.5 * refined + 20.0,
        "coarse {coarse} vs refined {refined}"
    );
    let dw = dark_fraction(&wire);
    assert!(dw < 0.15, "{:.0}% of the silhouette is dark", 100.0 * dw);
}
