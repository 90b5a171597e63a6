//! `tessella refine`: file in, refined file out.

use super::{gpu, tags};
use crate::args::{BackendArg, RefineArgs};
use crate::progress;
use anyhow::Context;
use std::time::Instant;
use tessella_core::{RefineOptions, RefinedMesh, Refiner};
use tessella_gpu::{gpu_refine_with, Displacement, GpuRefineOptions};
use tessella_io::{write_mesh, Format, MeshView, WriteOptions};

pub fn run(args: &RefineArgs) -> anyhow::Result<()> {
    // Refuse an unknown output format before doing any work.
    Format::from_path(&args.output)?;
    let (raw, mesh) = tags::read(&args.input)?;
    let scheme = args.scheme.scheme(args.alpha);
    let mut options = RefineOptions::new(scheme, args.level).with_weld(!args.soup);
    options.normals = args.normals.map(Into::into);
    options.max_output_bytes = args.max_memory;
    if let Some(tags) = tags::gather(&raw, &mesh, scheme, &args.tags)? {
        options = options.with_tags(tags);
    }
    drop(raw);

    let displacement = gpu::parse_displacement(args.displace.as_deref())?;
    displacement.validate(mesh.uvs().is_some())?;
    let ctx = gpu::context_for(args.backend)?;

    let start = Instant::now();
    let refiner = Refiner::new(&mesh, &options)
        .with_context(|| format!("cannot refine {}", args.input.display()))?;
    let on_gpu = ctx.as_ref().map(|ctx| {
        let gpu_options = GpuRefineOptions {
            displacement: displacement.clone(),
            max_chunk_items: None,
        };
        gpu_refine_with(ctx, &refiner, &gpu_options)
    });
    let refined = match on_gpu {
        Some(Ok(refined)) => refined,
        Some(Err(e)) if args.backend == BackendArg::Auto => {
            eprintln!("note: the GPU failed ({e}); refining on the CPU");
            refine_cpu(&refiner, &displacement)?
        }
        Some(Err(e)) => return Err(e).context("GPU refinement failed"),
        None => refine_cpu(&refiner, &displacement)?,
    };
    let elapsed = start.elapsed();

    write_mesh(
        &args.output,
        MeshView::from(&refined),
        &WriteOptions {
            ply_ascii: args.ply_ascii,
        },
    )?;
    eprintln!(
        "{} -> {}: {} triangles -> {} vertices, {} triangles ({}, level {}) in {:.1} ms",
        args.input.display(),
        args.output.display(),
        mesh.face_count(),
        refined.positions.len(),
        refined.triangles.len(),
        options.scheme.name(),
        options.level,
        elapsed.as_secs_f64() * 1e3
    );
    if args.report {
        let report = tessella_core::quality::report(&mesh, &options)?;
        super::info::print_quality(&[super::info::QualityRow::Measured(report)]);
    }
    Ok(())
}

fn refine_cpu(refiner: &Refiner, displacement: &Displacement) -> anyhow::Result<RefinedMesh> {
    let bar = progress::bar(refiner.progress_total(), "refining");
    let mut out = RefinedMesh::default();
    refiner.refine_into(&mut out, &|done| bar.inc(done));
    bar.finish_and_clear();
    displacement.apply(&mut out)?;
    Ok(out)
}
