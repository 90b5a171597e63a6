//! `tessella animate`: a deforming coarse mesh (a twist, or a glTF clip's skinning and morph
//! targets), re-uploading only its control nets per frame.

use super::{gpu, tags};
use crate::args::{AnimateArgs, SkinningArg};
use anyhow::Context;
use tessella_core::refine::Spacing;
use tessella_core::RefineOptions;
use tessella_view::{animate, RenderOptions};

pub fn run(args: &AnimateArgs) -> anyhow::Result<()> {
    let (_, mesh) = tags::read(&args.input)?;
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    let ctx = gpu::render_context()?;
    let options = RefineOptions::new(args.scheme.scheme(args.alpha), args.level);
    let view = RenderOptions {
        size: args.size,
        ..RenderOptions::default()
    };
    if args.fly_in {
        let refine = RefineOptions::new(args.scheme.scheme(args.alpha), 1)
            .with_spacing(Spacing::FractionalOdd);
        let view = RenderOptions {
            wireframe: true,
            pitch: 15.0,
            ..view
        };
        let stats = animate::render_fly_in(
            &ctx,
            &mesh,
            &refine,
            &view,
            args.frames,
            (0.8, 2.5),
            args.pixels,
            &args.output,
        )?;
        println!(
            "{} frames in {}: zoom {:.2} -> {:.2}, largest level {:.1} -> {:.1}, {} bytes of levels uploaded per frame, triangles {}",
            args.frames,
            args.output.display(),
            stats.zooms[0],
            stats.zooms.last().copied().unwrap_or_default(),
            stats.max_levels[0],
            stats.max_levels.last().copied().unwrap_or_default(),
            stats.upload_bytes.iter().max().copied().unwrap_or_default(),
            stats
                .triangles
                .iter()
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
        return Ok(());
    }
    let stats = match &args.clip {
        Some(clip) => {
            let poser = super::pose::load(&args.input)?;
            let index = poser
                .clip_index(clip)
                .with_context(|| format!("cannot play {}", args.input.display()))?;
            let skinning = match args.skinning {
                SkinningArg::Cpu => animate::Skinning::Cpu,
                SkinningArg::Gpu => animate::Skinning::Gpu,
            };
            let play = animate::ClipFrames {
                clip: index,
                frames: args.frames,
                fps: args.fps,
                skinning,
            };
            let stats = animate::render_clip(&ctx, &poser, &options, &view, &play, &args.output)?;
            let what = match args.skinning {
                SkinningArg::Cpu => "control nets",
                SkinningArg::Gpu => {
                    "deform matrices and morph weights; skinned and nets built on the GPU"
                }
            };
            report(args, &stats, what);
            return Ok(());
        }
        None => animate::render_twist(
            &ctx,
            &mesh,
            &options,
            &view,
            args.frames,
            args.twist,
            &args.output,
        )?,
    };
    report(args, &stats, "control nets");
    Ok(())
}

/// The frames written and what each uploaded (`what`), against a refined vertex buffer.
fn report(args: &AnimateArgs, stats: &animate::AnimationStats, what: &str) {
    println!(
        "{} frames in {}: {} bytes uploaded per frame ({what}) instead of {} for a refined vertex buffer ({:.1}x less)",
        stats.frames,
        args.output.display(),
        stats.bytes_per_frame,
        stats.refined_bytes_per_frame,
        stats.refined_bytes_per_frame as f64 / stats.bytes_per_frame.max(1) as f64
    );
}
