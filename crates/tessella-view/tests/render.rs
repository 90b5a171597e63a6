//! The render path: pictures compared with checked-in references (a missing reference fails),
//! plus properties that hold whatever the references say: PN silhouettes are rounder than flat
//! ones, the wireframe draws the pattern, panels line up, animation uploads only the nets.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

use common::ctx;
use image::RgbaImage;
use std::path::PathBuf;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::Displacement;
use tessella_view::animate::{render_twist, twist};
use tessella_view::{render, render_compare, save_png, RenderOptions};

const SIZE: (u32, u32) = (128, 128);

fn options() -> RenderOptions {
    RenderOptions {
        size: SIZE,
        ..Default::default()
    }
}

fn reference_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference")
}

/// Compares `image` with `tests/reference/<name>.png`: each channel within 12 levels, except
/// for at most 1% of pixels (anti-aliased edges may round differently between drivers).
/// `TESSELLA_BLESS=1` writes the reference instead; a missing reference is a failure.
fn assert_matches_reference(image: &RgbaImage, name: &str) {
    let path = reference_dir().join(format!("{name}.png"));
    if std::env::var("TESSELLA_BLESS").as_deref() == Ok("1") {
        save_png(image, &path).unwrap();
        return;
    }
    let reference = match image::open(&path) {
        Ok(r) => r.to_rgba8(),
        Err(e) => panic!(
            "reference picture {} is missing or unreadable ({e}); look at the output, then create \
             it with: TESSELLA_BLESS=1 cargo test -p tessella-view --test render",
            path.display()
        ),
    };
    assert_eq!(
        reference.dimensions(),
        image.dimensions(),
        "{name}: size differs"
    );
    let bad = image
        .pixels()
        .zip(reference.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 12))
        .count();
    let allowed = (image.width() * image.height()) as usize / 100;
    if bad > allowed {
        let out = std::env::temp_dir().join(format!("tessella-{name}-actual.png"));
        let saved = match save_png(image, &out) {
            Ok(()) => format!("actual picture: {}", out.display()),
            Err(e) => format!("the actual picture could not be saved: {e}"),
        };
        panic!("{name}: {bad} pixels differ from the reference (allowed {allowed}); {saved}");
    }
}

/// Pixels that are not the white background.
fn coverage(image: &RgbaImage) -> Vec<(u32, u32)> {
    image
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0[..3] != [255, 255, 255])
        .map(|(x, y, _)| (x, y))
        .collect()
}

/// Relative spread of the silhouette's distance from the coverage centroid: 0 for a disc.
fn silhouette_roughness(image: &RgbaImage) -> f64 {
    let covered = coverage(image);
    let inside = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < image.width() as i64
            && y < image.height() as i64
            && image.get_pixel(x as u32, y as u32).0[..3] != [255, 255, 255]
    };
    let n = covered.len() as f64;
    let cx = covered.iter().map(|p| p.0 as f64).sum::<f64>() / n;
    let cy = covered.iter().map(|p| p.1 as f64).sum::<f64>() / n;
    let radii: Vec<f64> = covered
        .iter()
        .filter(|&&(x, y)| {
            let (x, y) = (x as i64, y as i64);
            !(inside(x - 1, y) && inside(x + 1, y) && inside(x, y - 1) && inside(x, y + 1))
        })
        .map(|&(x, y)| ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt())
        .collect();
    let mean = radii.iter().sum::<f64>() / radii.len() as f64;
    let var = radii.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / radii.len() as f64;
    var.sqrt() / mean
}

#[test]
fn icosahedron_flat_vs_pn_matches_references_and_pn_is_rounder() {
    let mesh = samples::icosphere(0);
    let opts = RenderOptions {
        yaw: 0.0,
        pitch: 0.0,
        ..options()
    };
    let flat = render(ctx(), &mesh, &RefineOptions::new(Scheme::Flat, 8), &opts).unwrap();
    let pn = render(ctx(), &mesh, &RefineOptions::new(Scheme::Pn, 8), &opts).unwrap();
    assert_matches_reference(&flat, "icosahedron_flat");
    assert_matches_reference(&pn, "icosahedron_pn");
    // The papers' point: curved patches turn the polygonal outline into a rounder one.
    let (rf, rp) = (silhouette_roughness(&flat), silhouette_roughness(&pn));
    assert!(
        rp < 0.7 * rf,
        "PN silhouette roughness {rp} not clearly below flat {rf}"
    );
    // Both cover a substantial, centred part of the picture.
    for img in [&flat, &pn] {
        let c = coverage(img).len();
        assert!(c > 2000 && c < 128 * 128 * 3 / 4, "coverage {c}");
    }
}

#[test]
fn torus_with_wireframe_matches_reference_and_draws_the_pattern() {
    let mesh = samples::torus(1.0, 0.4, 8, 5);
    let refine = RefineOptions::new(Scheme::Pn, 3);
    let plain = render(ctx(), &mesh, &refine, &options()).unwrap();
    let wire = render(
        ctx(),
        &mesh,
        &refine,
        &RenderOptions {
            wireframe: true,
            ..options()
        },
    )
    .unwrap();
    assert_matches_reference(&wire, "torus_pn_wireframe");
    let dark = |img: &RgbaImage| {
        img.pixels()
            .filter(|p| p.0[..3].iter().all(|&c| c < 60))
            .count()
    };
    assert!(
        dark(&wire) > dark(&plain) + 200,
        "wireframe adds no lines: {} vs {}",
        dark(&wire),
        dark(&plain)
    );
}

#[test]
fn displacement_matches_references_and_changes_the_picture() {
    // Sine of |P| needs a surface whose distance from the origin varies: the torus.
    let cases = [
        (
            "torus_pn_sine",
            samples::torus(1.0, 0.4, 8, 5),
            Displacement::Sine {
                amplitude: 0.04,
                frequency: 40.0,
            },
        ),
        (
            "icosphere_pn_perlin",
            samples::icosphere(1),
            Displacement::Perlin {
                amplitude: 0.15,
                frequency: 4.0,
                seed: 3,
            },
        ),
    ];
    for (name, mesh, displacement) in cases {
        let refine = RefineOptions::new(Scheme::Pn, 24);
        let smooth = render(ctx(), &mesh, &refine, &options()).unwrap();
        let bumpy = RenderOptions {
            displacement,
            ..options()
        };
        let displaced = render(ctx(), &mesh, &refine, &bumpy).unwrap();
        assert_matches_reference(&displaced, name);
        let differing = smooth
            .pixels()
            .zip(displaced.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differing > 1000,
            "{name}: displacement changed only {differing} pixels"
        );
    }
}

#[test]
fn compare_panels_sit_side_by_side() {
    let mesh = samples::tetrahedron();
    let panels: Vec<(String, RefineOptions)> = [Scheme::Flat, Scheme::Pn, Scheme::Png1]
        .map(|s| (s.name().to_string(), RefineOptions::new(s, 8)))
        .to_vec();
    // `size` is the whole picture: three 64-pixel panels and two 2-pixel separators.
    let whole = RenderOptions {
        size: (3 * 64 + 2 * 2, 64),
        ..Default::default()
    };
    let out = render_compare(ctx(), &mesh, &panels, &whole).unwrap();
    assert_eq!(out.dimensions(), (3 * 64 + 2 * 2, 64));
    let small = RenderOptions {
        size: (64, 64),
        ..Default::default()
    };
    // Each panel equals the single render (outside its label box at the top).
    for (i, (_, refine)) in panels.iter().enumerate() {
        let single = render(ctx(), &mesh, refine, &small).unwrap();
        for y in 20..64 {
            for x in 0..64 {
                assert_eq!(out.get_pixel(i as u32 * 66 + x, y), single.get_pixel(x, y));
            }
        }
    }
    // Sizes that do not divide evenly still come out exactly as asked.
    for size in [(1200, 400), (121, 40), (7, 5)] {
        let out = render_compare(
            ctx(),
            &mesh,
            &panels,
            &RenderOptions {
                size,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(out.dimensions(), size);
    }
    // No room for three panels, or no panels: errors.
    for size in [(6, 40), (0, 40), (100, 0)] {
        let narrow = RenderOptions {
            size,
            ..Default::default()
        };
        assert!(render_compare(ctx(), &mesh, &panels, &narrow).is_err());
    }
    assert!(render_compare(ctx(), &mesh, &[], &small).is_err());
    assert_eq!(
        tessella_view::panel_widths(1200, 3),
        Some(vec![399, 399, 398])
    );
    assert_eq!(tessella_view::panel_widths(5, 3), None);
}

#[test]
fn bad_render_options_are_errors_not_panics() {
    let mesh = samples::tetrahedron();
    let refine = RefineOptions::new(Scheme::Pn, 2);
    for bad in [
        RenderOptions {
            size: (0, 10),
            ..options()
        },
        RenderOptions {
            zoom: 0.0,
            ..options()
        },
        RenderOptions {
            yaw: f32::NAN,
            ..options()
        },
    ] {
        assert!(render(ctx(), &mesh, &refine, &bad).is_err());
    }
    assert!(render(ctx(), &mesh, &RefineOptions::new(Scheme::Pn, 0), &options()).is_err());
}

#[test]
fn twist_animation_moves_the_surface_and_comes_back() {
    let mesh: Mesh = samples::creature();
    let refine = RefineOptions::new(Scheme::Pn, 16);
    let dir = tempfile::tempdir().unwrap();
    let small = RenderOptions {
        size: (64, 64),
        ..Default::default()
    };
    // Angles 60·sin(2πk/4): 0, 60, ~0, -60 degrees.
    let stats = render_twist(ctx(), &mesh, &refine, &small, 4, 60.0, dir.path()).unwrap();
    assert_eq!(stats.paths.len(), 4);
    let frames: Vec<RgbaImage> = stats
        .paths
        .iter()
        .map(|p| image::open(p).unwrap().to_rgba8())
        .collect();
    // Frame 0 is the rest pose: the same picture as rendering the mesh from scratch (a new
    // plan, nets built once), so the per-frame path draws the right surface.
    let rest = render(ctx(), &mesh, &refine, &small).unwrap();
    let differ = |a: &RgbaImage, b: &RgbaImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 12))
            .count()
    };
    assert_eq!(differ(&frames[0], &rest), 0, "frame 0 is not the rest pose");
    // The surface moves, both ways, and frame 2 (angle ~0) is back at rest: each update
    // replaces the nets rather than adding to them.
    assert!(differ(&frames[0], &frames[1]) > 20, "frame 1 did not move");
    assert!(
        differ(&frames[1], &frames[3]) > 20,
        "+60 and -60 degrees look alike"
    );
    assert!(
        differ(&frames[0], &frames[2]) <= 2,
        "frame 2 did not come back to rest"
    );
    // Nets are far smaller than the refined mesh they replace on the bus.
    assert!(stats.bytes_per_frame > 0);
    assert!(stats.bytes_per_frame * 20 < stats.refined_bytes_per_frame);
    // The twist itself: zero angle is the identity, and points keep their height.
    let same = twist(&mesh, 0.0).unwrap();
    assert_eq!(same.positions(), mesh.positions());
    let turned = twist(&mesh, 90.0).unwrap();
    for (a, b) in mesh.positions().iter().zip(turned.positions()) {
        assert_eq!(a[1], b[1]);
        let (ra, rb) = (a[0].hypot(a[2]), b[0].hypot(b[2]));
        assert!((ra - rb).abs() < 1e-5);
    }
}

#[test]
fn a_frame_wgpu_rejects_is_an_error_not_a_blank_picture() {
    let mesh = samples::icosphere(0);
    let plan = tessella_core::refine::Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    // Pipelines for another colour format than the target's: wgpu refuses the draw.
    let wrong = tessella_view::Appearance::new(
        ctx(),
        tessella_gpu::TargetFormats {
            color: wgpu::TextureFormat::Bgra8UnormSrgb,
            ..tessella_view::Target::FORMATS
        },
    );
    let renderer = tessella_gpu::PatternRenderer::new(
        ctx(),
        &plan,
        &frame,
        &wrong.shading(),
        &Displacement::None,
    )
    .unwrap();
    let target = tessella_view::Target::new(ctx(), (16, 16)).unwrap();
    let err = target
        .draw(ctx(), [255; 4], |pass| wrong.draw(pass, &renderer))
        .unwrap_err();
    assert!(
        matches!(err, tessella_gpu::GpuError::Validation(_)),
        "{err:?}"
    );
    // Reported once, to this caller; the next good frame is fine.
    ctx().check().unwrap();
    let look = tessella_view::Appearance::new(ctx(), tessella_view::Target::FORMATS);
    let right = tessella_gpu::PatternRenderer::new(
        ctx(),
        &plan,
        &frame,
        &look.shading(),
        &Displacement::None,
    )
    .unwrap();
    target
        .draw(ctx(), [255; 4], |pass| look.draw(pass, &right))
        .unwrap();
}
