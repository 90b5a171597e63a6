//! `tessella render`: a picture of the refined surface, drawn as the GMR paper does (one
//! instanced refinement pattern per coarse triangle, evaluated in the vertex shader).

use super::{gpu, tags};
use crate::args::{RenderArgs, RenderBackendArg};
use anyhow::Context;
use tessella_core::refine::Ask;
use tessella_core::{Mesh, RefineOptions};
use tessella_view::{lod_camera, render, render_compare, save_png, RenderOptions};

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let (raw, mesh) = super::pose::read(&args.input, &args.pose)?;
    let displacement = super::displace::parse(args.displace.as_deref())?;
    let view = RenderOptions {
        size: args.size,
        yaw: args.view.yaw,
        pitch: args.view.pitch,
        zoom: args.view.zoom,
        wireframe: args.view.wireframe,
        displacement: displacement.clone(),
        ..RenderOptions::default()
    };
    let view = RenderOptions {
        field: field_colors(args, &raw)?,
        ..view
    };
    let levels = levels(args, &mesh, &view)?;
    let asks = [
        displacement.is_some().then_some(Ask::Displace),
        (args.backend == RenderBackendArg::Gl).then_some(Ask::GlBackend),
    ];
    super::options::refuse_conflicts(&levels, asks.into_iter().flatten())?;
    let options_for = |scheme: crate::args::SchemeArg| -> anyhow::Result<RefineOptions> {
        let scheme = scheme.scheme(args.shape.alpha);
        let mut options = RefineOptions {
            scheme,
            ..levels.clone()
        };
        if let Some(tags) = tags::gather(&raw, &mesh, scheme, &args.tags)? {
            options = options.with_tags(tags);
        }
        Ok(options)
    };
    if args.backend == RenderBackendArg::Gl {
        if args.color_by.is_some() {
            anyhow::bail!(
                "--color-by is not supported with --backend gl (it colours by normal); use --backend gpu"
            );
        }
        let panels = if args.compare.is_empty() {
            vec![(String::new(), options_for(args.shape.scheme)?)]
        } else {
            args.compare
                .iter()
                .map(|&s| Ok((options_for(s)?.scheme.name().to_string(), options_for(s)?)))
                .collect::<anyhow::Result<Vec<_>>>()?
        };
        let (picture, device) =
            super::render_gl::render(&mesh, &panels, !args.compare.is_empty(), &view)?;
        save_png(&picture, &args.output)
            .with_context(|| format!("cannot write {}", args.output.display()))?;
        eprintln!(
            "{} -> {} ({}x{}, {device})",
            args.input.display(),
            args.output.display(),
            picture.width(),
            picture.height()
        );
        return Ok(());
    }
    let ctx = gpu::render_context()?;
    let picture = if args.compare.is_empty() {
        render(&ctx, &mesh, &options_for(args.shape.scheme)?, &view)?
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
        "{} -> {} ({}x{}, {} level {}{}, {})",
        args.input.display(),
        args.output.display(),
        picture.width(),
        picture.height(),
        levels.spacing,
        args.level,
        args.lod
            .lod
            .as_deref()
            .map_or(String::new(), |l| format!(", lod {l}")),
        ctx.adapter_label()
    );
    Ok(())
}

/// The field `--color-by` names, read from the input file, with `--colormap` and `--range`.
fn field_colors(
    args: &RenderArgs,
    raw: &tessella_io::RawMesh,
) -> anyhow::Result<Option<tessella_view::FieldColors>> {
    let Some(name) = &args.color_by else {
        return Ok(None);
    };
    let colormap: tessella_view::Colormap = args
        .colormap
        .parse()
        .map_err(|e: String| anyhow::anyhow!("--colormap: {e}"))?;
    let Some(values) = raw.vertex_scalars.get(name) else {
        let have: Vec<&str> = raw.vertex_scalars.keys().map(String::as_str).collect();
        anyhow::bail!(
            "--color-by {name:?}: {} has no such per-vertex field; {}",
            args.input.display(),
            if have.is_empty() {
                "it has none (PLY vertex properties or glTF _NAME attributes)".to_string()
            } else {
                format!("it has {}", have.join(", "))
            }
        );
    };
    Ok(Some(tessella_view::FieldColors {
        name: name.clone(),
        values: values.clone(),
        colormap,
        range: args.range,
    }))
}

/// The options from the flags in the core's text form; the view-dependent LODs see the
/// picture's own camera and size unless `--camera` is given.
fn levels(args: &RenderArgs, mesh: &Mesh, view: &RenderOptions) -> anyhow::Result<RefineOptions> {
    let lod = args.lod.lod.as_deref();
    super::options::Flags {
        shape: args.shape,
        level: args.level,
        spacing: args.spacing,
        lod,
        // A LOD sees `--camera`, else the picture's own camera.
        camera: match (lod, &args.lod.camera) {
            (Some(_), None) => Some(lod_camera(mesh, view).to_string()),
            (_, given) => given.clone(),
        },
        size: lod.map(|_| view.size),
        soup: false,
        max_memory: None,
    }
    .parse()
}
