//! Writes a labelled flat / Phong / PN / PNG1 comparison of the tetrahedron:
//! `cargo run -p tessella-view --example compare -- OUT.png [level]`.

use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{render_compare, save_png, RenderOptions};

fn main() {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "compare.png".into());
    let level = args.next().and_then(|l| l.parse().ok()).unwrap_or(16);
    let run = || -> Result<(), tessella_gpu::GpuError> {
        let ctx = GpuContext::new(AdapterChoice::Auto)?;
        let panels: Vec<(String, RefineOptions)> =
            [Scheme::Flat, Scheme::PHONG, Scheme::Pn, Scheme::Png1]
                .map(|s| (s.name().to_string(), RefineOptions::new(s, level)))
                .to_vec();
        let options = RenderOptions {
            size: (4 * 256 + 3 * 2, 256),
            wireframe: true,
            ..Default::default()
        };
        let picture = render_compare(&ctx, &samples::tetrahedron(), &panels, &options)?;
        save_png(&picture, std::path::Path::new(&out))
    };
    if let Err(e) = run() {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
