//! `tessella render`: a picture of the refined surface, drawn as the GMR paper does (one
//! instanced refinement pattern per coarse triangle, evaluated in the vertex shader).

use super::{gpu, tags};
use crate::args::RenderArgs;
use anyhow::Context;
use tessella_core::RefineOptions;
use tessella_view::{render, render_compare, save_png, RenderOptions};

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let (raw, mesh) = tags::read(&args.input)?;
    let displacement = super::displace::parse(args.displace.as_deref())?;
    let options_for = |scheme: crate::args::SchemeArg| -> anyhow::Result<RefineOptions> {
        let scheme = scheme.scheme(args.alpha);
        let mut options = RefineOptions::new(scheme, args.level);
        options.normals = args.normals.map(Into::into);
        if let Some(tags) = tags::gather(&raw, &mesh, scheme, &args.tags)? {
            options = options.with_tags(tags);
        }
        Ok(options)
    };
    let view = RenderOptions {
        size: args.size,
        yaw: args.yaw,
        pitch: args.pitch,
        zoom: args.zoom,
        wireframe: args.wireframe,
        displacement,
        ..RenderOptions::default()
    };
    let ctx = gpu::render_context()?;
    let picture = if args.compare.is_empty() {
        render(&ctx, &mesh, &options_for(args.scheme)?, &view)?
    } else {
        let panels = args
            .compare
            .iter()
            .map(|&s| Ok((options_for(s)?.scheme.name().to_string(), options_for(s)?)))
            .collect::<anyhow::Result<Vec<_>>>()?;
        render_compare(&ctx, &mesh, &panels, &view)?
    };
    save_png(&picture, &args.output)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    eprintln!(
        "{} -> {} ({}x{}, level {}, {})",
        args.input.display(),
        args.output.display(),
        picture.width(),
        picture.height(),
        args.level,
        ctx.adapter_label()
    );
    Ok(())
}
