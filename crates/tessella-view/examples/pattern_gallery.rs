//! The pattern gallery in the README: one flat triangle with mixed outer levels, drawn by the
//! instanced renderer with the wireframe, for the grid and the tessellator's equal,
//! fractional-odd and fractional-even spacings side by side.
//!
//! `cargo run -p tessella-view --example pattern_gallery -- docs/images/pattern-gallery.png`

use std::sync::Arc;
use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::Named;
use tessella_core::{Mesh, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{render_compare, save_png, RenderOptions};

/// Outer levels of the triangle's three edges, and the inner minimum.
const OUTER: [f32; 3] = [3.0, 5.4, 8.7];
const INNER: f32 = 6.3;

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "pattern-gallery.png".into());
    let run = || -> Result<(), Box<dyn std::error::Error>> {
        // An equilateral triangle of side 2 centred on the origin, facing the camera.
        let r = 2.0 / 3f32.sqrt();
        let mesh = Mesh::new(
            vec![[-1.0, -r / 2.0, 0.0], [1.0, -r / 2.0, 0.0], [0.0, r, 0.0]],
            Some(vec![[0.0, 0.0, 1.0]; 3]),
            None,
            vec![[0, 1, 2]],
        )?;
        let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Flat, 1))?;
        // Levels per unique edge, in the topology's edge order, matched to corner order.
        let edges: Arc<[f32]> = plan
            .topology()
            .edges
            .iter()
            .map(|&[a, b]| {
                let k = (0..3).find(|&k| [k, (k + 1) % 3] == [a, b] || [(k + 1) % 3, k] == [a, b]);
                OUTER[k.expect("an edge of the triangle") as usize]
            })
            .collect();
        let panels: Vec<(String, RefineOptions)> = Spacing::ALL
            .iter()
            .map(|&spacing| {
                let options = RefineOptions::new(Scheme::Flat, 1)
                    .with_spacing(spacing)
                    .with_levels(Levels::PerEdge {
                        edges: edges.clone(),
                        faces: Some(Arc::from([INNER])),
                    });
                (spacing.name().to_string(), options)
            })
            .collect();
        let options = RenderOptions {
            size: (4 * 360 + 3 * 2, 360),
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.35,
            wireframe: true,
            ..Default::default()
        };
        let ctx = GpuContext::new(AdapterChoice::Auto)?;
        let picture = render_compare(&ctx, &mesh, &panels, &options)?;
        save_png(&picture, std::path::Path::new(&out))?;
        println!(
            "{out} (outer {OUTER:?}, inner {INNER}; {})",
            ctx.adapter_label()
        );
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
