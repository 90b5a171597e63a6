//! A heated torus coloured by temperature: the faceted order-1 boundary (flat triangles,
//! T linear per triangle) next to the second-order surface refined with `quadratic` (mid-edge
//! nodes on the true torus, T through the 6-node shape functions), one colour bar for both.
//! Drawn by tessella's own renderer (the field interpolated in the vertex shader):
//! `cargo run -p tessella-view --example fem_temperature -- docs/images/fem-temperature.png`.

use std::collections::HashMap;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{colormap, font, render, save_png, Colormap, FieldColors, RenderOptions};

const MAJOR: f32 = 1.0;
const MINOR: f32 = 0.4;

/// The point of the torus nearest to `p` (around the tube's centre circle).
fn project(p: [f32; 3]) -> [f32; 3] {
    let u = p[1].atan2(p[0]);
    let c = [MAJOR * u.cos(), MAJOR * u.sin(), 0.0];
    let d = [p[0] - c[0], p[1] - c[1], p[2]];
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [0, 1, 2].map(|k| c[k] + MINOR * d[k] / n)
}

/// A heater on the outer equator: 20 °C far away, 100 °C at the heater.
fn temperature(p: [f32; 3]) -> f32 {
    let d2 = (p[0] - 1.4).powi(2) + p[1].powi(2) + p[2].powi(2);
    20.0 + 80.0 * (-d2 / 0.3).exp()
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "fem-temperature.png".into());
    let coarse = samples::torus(MAJOR, MINOR, 12, 6);
    // Order 2: one mid-edge node per edge, on the true surface.
    let mut positions = coarse.positions().to_vec();
    let mut mids_of: HashMap<(u32, u32), u32> = HashMap::new();
    let mids: Vec<[u32; 3]> = coarse
        .triangles()
        .iter()
        .map(|t| {
            [0, 1, 2].map(|k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *mids_of.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (pa, pb) = (positions[a as usize], positions[b as usize]);
                    positions.push(project([0, 1, 2].map(|c| (pa[c] + pb[c]) / 2.0)));
                    positions.len() as u32 - 1
                })
            })
        })
        .collect();
    let p2 = Mesh::new(positions.clone(), None, None, coarse.triangles().to_vec())
        .and_then(|m| m.with_mid_nodes(mids))
        .expect("a valid second-order torus");
    // Order 1, faceted: every triangle its own three corners with the face normal.
    let corners: Vec<[f32; 3]> = coarse
        .triangles()
        .iter()
        .flat_map(|t| t.map(|v| coarse.positions()[v as usize]))
        .collect();
    let facets: Vec<[u32; 3]> = (0..coarse.face_count() as u32)
        .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
        .collect();
    let faceted = Mesh::new(corners, None, None, facets).expect("a valid faceted torus");
    let field = |mesh: &Mesh| FieldColors {
        name: "T (C)".into(),
        values: mesh.positions().iter().map(|&p| temperature(p)).collect(),
        colormap: Colormap::Viridis,
        range: Some([20.0, 100.0]),
    };
    let (w, h) = (460, 400);
    let view = |mesh: &Mesh| RenderOptions {
        size: (w + colormap::bar_width(h), h),
        yaw: 55.0,
        pitch: 40.0,
        zoom: 1.0,
        field: Some(field(mesh)),
        ..RenderOptions::default()
    };
    let run = || -> Result<(), tessella_gpu::GpuError> {
        let ctx = GpuContext::new(AdapterChoice::Auto)?;
        let left = render(
            &ctx,
            &faceted,
            &RefineOptions::new(Scheme::Flat, 1),
            &view(&faceted),
        )?;
        let right = render(
            &ctx,
            &p2,
            &RefineOptions::new(Scheme::Quadratic, 8),
            &view(&p2),
        )?;
        // The panels without their bars, one bar for both (the same range).
        let crop = |img: &image::RgbaImage| image::imageops::crop_imm(img, 0, 0, w, h).to_image();
        let row = font::side_by_side(
            &[crop(&left), crop(&right)],
            &["order 1 faceted", "order 2 quadratic"],
        );
        let bar = colormap::color_bar(&field(&p2), h, [255, 255, 255, 255]);
        save_png(&colormap::with_bar(&row, &bar), std::path::Path::new(&out))
    };
    if let Err(e) = run() {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
