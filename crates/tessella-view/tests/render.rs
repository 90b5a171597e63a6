//! The render path: pictures compared with checked-in references (a missing reference fails),
//! plus properties that hold whatever the references say: PN silhouettes are rounder than flat
//! ones, the wireframe draws the pattern, panels line up, animation uploads only the nets.

mod common;

use common::ctx;
use image::RgbaImage;
use std::path::PathBuf;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::animate::{render_twist, twist};
use tessella_gpu::{render, render_compare, save_png, Displacement, RenderOptions};

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
             it with: TESSELLA_BLESS=1 cargo test -p tessella-gpu --test render",
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
        let _ = save_png(image, &out);
        panic!("{name}: {bad} pixels differ from the reference (allowed {allowed}); actual picture: {}", out.display());
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
    let small = RenderOptions {
        size: (64, 64),
        ..Default::default()
    };
    let out = render_compare(ctx(), &mesh, &panels, &small).unwrap();
    assert_eq!(out.dimensions(), (3 * 64 + 2 * 2, 64));
    // Each panel equals the single render (outside its label box at the top).
    for (i, (_, refine)) in panels.iter().enumerate() {
        let single = render(ctx(), &mesh, refine, &small).unwrap();
        for y in 20..64 {
            for x in 0..64 {
                assert_eq!(out.get_pixel(i as u32 * 66 + x, y), single.get_pixel(x, y));
            }
        }
    }
    assert!(render_compare(ctx(), &mesh, &[], &small).is_err());
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
fn twist_animation_uploads_only_the_nets() {
    let mesh: Mesh = samples::creature();
    let refine = RefineOptions::new(Scheme::Pn, 16);
    let dir = tempfile::tempdir().unwrap();
    let small = RenderOptions {
        size: (64, 64),
        ..Default::default()
    };
    let stats = render_twist(ctx(), &mesh, &refine, &small, 3, 60.0, dir.path()).unwrap();
    assert_eq!(stats.paths.len(), 3);
    // Nets: K = 10 points + 6 normal-net entries per coarse triangle, 12 bytes each.
    assert_eq!(stats.bytes_per_frame, mesh.face_count() as u64 * 16 * 12);
    assert!(stats.bytes_per_frame * 20 < stats.refined_bytes_per_frame);
    let frames: Vec<RgbaImage> = stats
        .paths
        .iter()
        .map(|p| image::open(p).unwrap().to_rgba8())
        .collect();
    assert_ne!(frames[0], frames[1], "the mesh did not move between frames");
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
