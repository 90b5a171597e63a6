//! `tessella render --backend gl`: the picture drawn by the OpenGL 4 tessellation stages
//! (tessella-gl) through tessella-view's camera (the same yaw, pitch, zoom and size framing as
//! the wgpu picture), coloured by normal (`0.5 n + 0.5`, van Veen's pictures) rather than
//! Blinn-Phong; `--wireframe` draws the pattern's edges over the surface, `--compare` labelled
//! panels side by side (tessella-view's panel widths and font).

#[cfg(feature = "gl")]
use tessella_core::refine::{Levels, Spacing};
use tessella_core::{Mesh, RefineOptions};
use tessella_view::{RenderOptions, RgbaImage};

/// Renders one picture per `(label, options)`: a single unlabelled picture when `panels` has
/// one entry and `compare` is false. `render` has refused displacement (the GL tessellator has
/// no displacement stage), so `view.displacement` is not read.
#[cfg(feature = "gl")]
pub fn render(
    mesh: &Mesh,
    panels: &[(String, RefineOptions)],
    compare: bool,
    view: &RenderOptions,
) -> anyhow::Result<(RgbaImage, String)> {
    use anyhow::Context;
    use tessella_gl::{gl_clip_from_zero_to_one, DrawMode, GlContext, GlTessellator};
    view.validate()?;
    let panels: Vec<(String, RefineOptions)> = panels
        .iter()
        .map(|(l, o)| Ok((l.clone(), hardware(o)?)))
        .collect::<anyhow::Result<_>>()?;
    let widths = if compare {
        tessella_view::panel_widths(view.size.0, panels.len()).ok_or_else(|| {
            anyhow::anyhow!(
                "a picture {} pixels wide has no room for {} panels",
                view.size.0,
                panels.len()
            )
        })?
    } else {
        vec![view.size.0]
    };
    let ctx = GlContext::new()?;
    let mut gl = GlTessellator::new(&ctx)?;
    let mode = if view.wireframe {
        DrawMode::FillAndLines
    } else {
        DrawMode::Fill
    };
    let mut pictures = Vec::new();
    for ((_, options), &w) in panels.iter().zip(&widths) {
        let panel = RenderOptions {
            size: (w, view.size.1),
            ..view.clone()
        };
        let vp = tessella_view::scene_uniforms(mesh, &panel, 0.0).view_proj;
        let prepared = gl.prepare(mesh, options, None)?;
        for note in &prepared.notes {
            eprintln!("note: {note}");
        }
        let (w, h) = (w as i32, view.size.1 as i32);
        let pixels = gl
            .draw(&prepared, &gl_clip_from_zero_to_one(vp), w, h, mode)
            .with_context(|| format!("GL drawing on {} failed", ctx.info().renderer))?;
        pictures.push(flip(pixels, w as u32, h as u32));
    }
    let picture = if compare {
        let labels: Vec<&str> = panels.iter().map(|(l, _)| l.as_str()).collect();
        tessella_view::font::side_by_side(&pictures, &labels)
    } else {
        pictures.remove(0)
    };
    Ok((picture, format!("GL: {}", ctx.info().renderer)))
}

/// GL reads rows from the bottom up; pictures go top down.
#[cfg(feature = "gl")]
fn flip(pixels: Vec<u8>, w: u32, h: u32) -> RgbaImage {
    let row = w as usize * 4;
    let mut out = Vec::with_capacity(pixels.len());
    for y in (0..h as usize).rev() {
        out.extend_from_slice(&pixels[y * row..(y + 1) * row]);
    }
    RgbaImage::from_raw(w, h, out).expect("the read-back has the picture's size")
}

/// The hardware tessellator draws equal / fractional spacing: a whole `--level` on the default
/// grid is drawn with equal spacing at that level (the same segments per edge).
#[cfg(feature = "gl")]
fn hardware(options: &RefineOptions) -> anyhow::Result<RefineOptions> {
    if let Some(level) = options.uniform_grid_level() {
        return Ok(options
            .clone()
            .with_spacing(Spacing::Equal)
            .with_levels(Levels::Uniform(level as f32)));
    }
    Ok(options.clone())
}

/// Without the `gl` feature: a clear error.
#[cfg(not(feature = "gl"))]
pub fn render(
    _mesh: &Mesh,
    _panels: &[(String, RefineOptions)],
    _compare: bool,
    _view: &RenderOptions,
) -> anyhow::Result<(RgbaImage, String)> {
    anyhow::bail!(
        "render --backend gl needs the `gl` feature, and this tessella was built without it; \
         rebuild with it (cargo build -p tessella-cli --features gl)"
    )
}
