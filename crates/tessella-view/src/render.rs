//! Offscreen pictures: a multisampled target with readback, drawn by tessella-gpu's
//! [`PatternRenderer`] with this crate's [`Appearance`], framed by [`crate::scene`]'s camera.
//! Blocks (the `blocking` feature).

use crate::appearance::{Appearance, FieldNets};
use crate::colormap;
use crate::scene::{panel_widths, scene_uniforms, RenderOptions};
use crate::target::Target;
use image::RgbaImage;
use tessella_core::refine::Plan;
use tessella_core::{Mesh, RefineOptions};
use tessella_gpu::{GpuContext, GpuError, PatternRenderer};

/// Renders `mesh` refined with `refine` (scheme, level, normals; `weld` does not matter here).
///
/// ```no_run
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gpu::{AdapterChoice, GpuContext};
/// use tessella_view::{render, RenderOptions};
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let picture = render(&ctx, &samples::icosphere(1), &RefineOptions::new(Scheme::Pn, 16),
///                      &RenderOptions { size: (256, 256), ..Default::default() })?;
/// # Ok::<(), tessella_gpu::GpuError>(())
/// ```
pub fn render(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    options.validate()?;
    let Some(field) = &options.field else {
        return render_view(ctx, mesh, refine, options);
    };
    let bar = colormap::color_bar(field, options.size.1, options.background);
    let view = RenderOptions {
        size: (view_width(options, bar.width())?, options.size.1),
        ..options.clone()
    };
    Ok(colormap::with_bar(
        &render_view(ctx, mesh, refine, &view)?,
        &bar,
    ))
}

/// The width left for the surface beside a colour bar `bar` pixels wide.
fn view_width(options: &RenderOptions, bar: u32) -> Result<u32, GpuError> {
    options
        .size
        .0
        .checked_sub(bar)
        .filter(|&w| w > 0)
        .ok_or_else(|| {
            GpuError::BadOption(format!(
                "a picture {} pixels wide has no room beside a {bar}-pixel colour bar",
                options.size.0
            ))
        })
}

/// The picture of the surface alone (a field colours it, the bar is drawn by the caller).
/// `options` were validated by the caller: [`render`] and [`render_compare`] check theirs,
/// then only narrow the picture to a width of at least one pixel.
fn render_view(
    ctx: &GpuContext,
    mesh: &Mesh,
    refine: &RefineOptions,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    let (plan, frame) = Plan::with_frame(mesh, refine)?;
    let mut look = Appearance::new(ctx, Target::FORMATS);
    let renderer =
        PatternRenderer::new(ctx, &plan, &frame, &look.shading(), &options.displacement)?;
    if let Some(field) = &options.field {
        let nets = tessella_core::fields::face_nets(mesh, &field.name, &field.values)
            .map_err(|e| GpuError::BadOption(e.to_string()))?;
        let colormap = field.colormap.samples_f32();
        look.set_field(
            plan.face_count(),
            Some(FieldNets {
                nets: &nets,
                colormap: &colormap,
                range: field.resolved_range(),
            }),
        )?;
    }
    let target = Target::new(ctx, options.size)?;
    look.set_uniforms(&scene_uniforms(
        mesh,
        options,
        renderer.displacement_reach(),
    ));
    target.draw(ctx, options.background, |pass| look.draw(pass, &renderer))?;
    target.read(ctx)
}

/// Renders one panel per `(label, options)` side by side, with the labels drawn on top.
/// `options.size` is the size of the whole picture: the panels share its width (less the
/// separators), the first ones one pixel wider when it does not divide evenly. A width too
/// small for one pixel per panel is an error.
pub fn render_compare(
    ctx: &GpuContext,
    mesh: &Mesh,
    panels: &[(String, RefineOptions)],
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    if panels.is_empty() {
        return Err(GpuError::BadOption(
            "nothing to compare: give at least one panel".into(),
        ));
    }
    options.validate()?;
    let bar = options
        .field
        .as_ref()
        .map(|f| colormap::color_bar(f, options.size.1, options.background));
    let total = match &bar {
        Some(bar) => view_width(options, bar.width())?,
        None => options.size.0,
    };
    let widths = panel_widths(total, panels.len()).ok_or_else(|| {
        GpuError::BadOption(format!(
            "a picture {} pixels wide has no room for {} panels",
            options.size.0,
            panels.len()
        ))
    })?;
    let pictures = panels
        .iter()
        .zip(&widths)
        .map(|((_, refine), &w)| {
            let panel = RenderOptions {
                size: (w, options.size.1),
                ..options.clone()
            };
            render_view(ctx, mesh, refine, &panel)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let labels: Vec<&str> = panels.iter().map(|(l, _)| l.as_str()).collect();
    let row = crate::font::side_by_side(&pictures, &labels);
    Ok(match &bar {
        Some(bar) => colormap::with_bar(&row, bar),
        None => row,
    })
}
