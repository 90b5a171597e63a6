//! The screen-size LOD picture in the README: a row of spheres seen in perspective along the
//! row, each coarse edge refined to about 18 pixels per segment (`Lod::Screen` with the
//! picture's own camera, fractional-odd spacing): near spheres get many segments, far ones few,
//! and neighbouring faces with different levels still share every edge point.
//!
//! `cargo run -p tessella-view --example lod_screen -- docs/images/lod-screen.png`

use tessella_core::refine::{Levels, Lod, Plan, Spacing};
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{lod_camera, render, save_png, RenderOptions};

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "lod-screen.png".into());
    let run = || -> Result<(), Box<dyn std::error::Error>> {
        // Seven unit spheres along X, 2.6 apart.
        let ball = samples::icosphere(1);
        let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..7 {
            let base = positions.len() as u32;
            let dx = 2.6 * i as f32;
            positions.extend(ball.positions().iter().map(|p| [p[0] + dx, p[1], p[2]]));
            normals.extend_from_slice(ball.normals());
            triangles.extend(ball.triangles().iter().map(|t| t.map(|v| v + base)));
        }
        let mesh = Mesh::new(positions, Some(normals), None, triangles)?;
        let view = RenderOptions {
            size: (960, 480),
            yaw: 68.0,
            pitch: 12.0,
            zoom: 3.4,
            wireframe: true,
            color: [170, 200, 235],
            ..Default::default()
        };
        let lod = Lod::Screen {
            pixels: 18.0,
            camera: lod_camera(&mesh, &view),
            size: [view.size.0, view.size.1],
        };
        let options = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::Lod(lod));
        let plan = Plan::new(&mesh, &options)?;
        let tiling = plan.tiling().expect("screen levels make an adaptive plan");
        let (lo, hi) = tiling
            .edge_levels
            .iter()
            .fold((f32::MAX, 0.0f32), |(a, b), &x| (a.min(x), b.max(x)));
        println!(
            "{} coarse triangles -> {} refined, {} distinct patterns, edge levels {lo:.2} to {hi:.2}",
            mesh.face_count(),
            plan.triangle_count(),
            tiling.tiles.len()
        );
        let ctx = GpuContext::new(AdapterChoice::Auto)?;
        let picture = render(&ctx, &mesh, &options, &view)?;
        save_png(&picture, std::path::Path::new(&out))?;
        println!("{out}");
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("lod_screen: {e}");
        std::process::exit(1);
    }
}
