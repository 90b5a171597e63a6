//! Pictures coloured by a field, on the software adapter: a vertical square facing a
//! horizontal camera, with T = y (up on the screen). Every surface pixel's colour is mapped back
//! through the colormap (by chromaticity, since lighting scales the colour) and must be
//! ordered as the field: higher on the screen, higher T, spanning the range. The colour bar
//! beside the surface runs from the colormap's high end (top) to its low end (bottom).

use image::RgbaImage;
use tessella_core::{Mesh, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{colormap, render, render_compare, Colormap, FieldColors, RenderOptions};

/// A square in the plane z = 0, `n`×`n` quads, facing +z (the camera at yaw 0).
fn square(n: u32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push([
                -1.0 + 2.0 * i as f32 / n as f32,
                -1.0 + 2.0 * j as f32 / n as f32,
                0.0,
            ]);
        }
    }
    let mut triangles = Vec::new();
    let at = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh::new(positions, None, None, triangles).unwrap()
}

fn linear(c: u8) -> f64 {
    let c = c as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn direction(rgb: [u8; 3]) -> [f64; 3] {
    let v = rgb.map(linear);
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-12);
    v.map(|x| x / n)
}

/// The colormap position whose colour has the chromaticity nearest to `rgb`'s.
fn invert(map: Colormap, rgb: [u8; 3]) -> f64 {
    let d = direction(rgb);
    (0..=1000)
        .map(|k| k as f64 / 1000.0)
        .max_by(|&a, &b| {
            let dot = |t: f64| {
                let e = direction(map.color(t as f32));
                d[0] * e[0] + d[1] * e[1] + d[2] * e[2]
            };
            dot(a).total_cmp(&dot(b))
        })
        .unwrap()
}

fn ctx() -> GpuContext {
    GpuContext::new(AdapterChoice::Software).expect("a software adapter")
}

fn options(mesh: &Mesh, map: Colormap, range: Option<[f32; 2]>) -> RenderOptions {
    RenderOptions {
        size: (420, 320),
        yaw: 0.0,
        pitch: 0.0,
        field: Some(FieldColors {
            name: "T".into(),
            values: mesh.positions().iter().map(|p| p[1]).collect(),
            colormap: map,
            range,
        }),
        ..RenderOptions::default()
    }
}

/// T read back along the picture's middle column of the surface, top to bottom.
fn column(picture: &RgbaImage, x: u32, map: Colormap) -> Vec<(u32, f64)> {
    let white = image::Rgba([255, 255, 255, 255]);
    let rows: Vec<u32> = (0..picture.height())
        .filter(|&y| *picture.get_pixel(x, y) != white)
        .collect();
    assert!(rows.len() > 60, "the square covers {} rows", rows.len());
    // Away from the antialiased silhouette.
    rows[3..rows.len() - 3]
        .iter()
        .map(|&y| {
            let p = picture.get_pixel(x, y).0;
            (y, invert(map, [p[0], p[1], p[2]]))
        })
        .collect()
}

fn check_bar(picture: &RgbaImage, map: Colormap) {
    let bar = colormap::bar_width(picture.height());
    let view = picture.width() - bar;
    // The bar's middle column (the bar is 14 scale-pixels wide from 4 in; scale 1 here).
    let x = view + 4 + 7;
    let white = [255, 255, 255];
    let colored: Vec<[u8; 3]> = (0..picture.height())
        .map(|y| {
            let p = picture.get_pixel(x, y).0;
            [p[0], p[1], p[2]]
        })
        .filter(|&p| p != white)
        .collect();
    assert!(colored.len() > 200, "{} bar pixels", colored.len());
    assert_eq!(colored[0], map.color(1.0), "the bar's top is the high end");
    assert_eq!(
        *colored.last().unwrap(),
        map.color(0.0),
        "the bar's bottom is the low end"
    );
}

#[test]
fn surface_colours_follow_the_field_and_the_bar_shows_the_range() {
    let ctx = ctx();
    let mesh = square(4);
    for map in [Colormap::Viridis, Colormap::Coolwarm] {
        let opts = options(&mesh, map, None);
        let picture = render(&ctx, &mesh, &RefineOptions::new(Scheme::Flat, 4), &opts).unwrap();
        assert_eq!(picture.dimensions(), (420, 320));
        let view = 420 - colormap::bar_width(320);
        let values = column(&picture, view / 2, map);
        // Ordered as the field: T grows upwards (row numbers grow downwards).
        for w in values.windows(2) {
            assert!(
                w[1].1 <= w[0].1 + 0.02,
                "{map:?}: row {} has T {:.3}, row {} below it {:.3}",
                w[0].0,
                w[0].1,
                w[1].0,
                w[1].1
            );
        }
        let (top, bottom) = (values[0].1, values.last().unwrap().1);
        assert!(top > 0.95 && bottom < 0.05, "{map:?}: {top} .. {bottom}");
        // The middle of the square (T = 0) is the middle of the colormap.
        let middle = values[values.len() / 2].1;
        assert!((middle - 0.5).abs() < 0.05, "{map:?}: middle {middle}");
        check_bar(&picture, map);
        if map == Colormap::Viridis {
            std::fs::create_dir_all(env!("CARGO_TARGET_TMPDIR")).ok();
            let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("field_square.png");
            picture.save(&path).unwrap();
        }
    }
}

#[test]
fn a_given_range_clamps_and_compare_panels_share_one_bar() {
    let ctx = ctx();
    let mesh = square(4);
    // Range [0, 1]: the lower half of the square (T < 0) is the low end's colour.
    let opts = options(&mesh, Colormap::Viridis, Some([0.0, 1.0]));
    let panels = vec![
        ("flat".to_string(), RefineOptions::new(Scheme::Flat, 2)),
        ("pn".to_string(), RefineOptions::new(Scheme::Pn, 6)),
    ];
    let picture = render_compare(&ctx, &mesh, &panels, &opts).unwrap();
    assert_eq!(picture.dimensions(), (420, 320));
    let view = 420 - colormap::bar_width(320);
    let panel = tessella_view::panel_widths(view, 2).unwrap()[0];
    let values = column(&picture, panel / 2, Colormap::Viridis);
    let lower = &values[values.len() * 3 / 5..];
    assert!(lower.iter().all(|&(_, t)| t < 0.03), "{lower:?}");
    assert!(values[0].1 > 0.9, "top {}", values[0].1);
    check_bar(&picture, Colormap::Viridis);
}

#[test]
fn a_field_of_the_wrong_length_is_an_error_naming_it() {
    let ctx = ctx();
    let mesh = square(2);
    let mut opts = options(&mesh, Colormap::Viridis, None);
    opts.field.as_mut().unwrap().values.pop();
    let err = render(&ctx, &mesh, &RefineOptions::new(Scheme::Flat, 2), &opts)
        .unwrap_err()
        .to_string();
    assert!(err.contains("field \"T\" has 8 values"), "{err}");
}
