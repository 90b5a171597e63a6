//! `tessella refine`: file in, refined file out.

use super::tags;
use crate::args::RefineArgs;
use crate::progress;
use anyhow::Context;
use std::time::Instant;
use tessella_core::displace::{DisplaceFrame, Displacement};
use tessella_core::{RefineOptions, RefinedMesh, Refiner};
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

    let backend = backend::choose(args, &mesh)?;

    let start = Instant::now();
    let refiner = Refiner::new(&mesh, &options)
        .with_context(|| format!("cannot refine {}", args.input.display()))?;
    let refined = backend::refine(&backend, args, &refiner)?;
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

/// The CPU refinement, with a progress bar, then the displacement (shared directions on hard
/// edges, so they stay closed).
fn refine_cpu(refiner: &Refiner, displacement: &Displacement) -> anyhow::Result<RefinedMesh> {
    let bar = progress::bar(refiner.progress_total(), "refining");
    let mut out = RefinedMesh::default();
    refiner.refine_into(&mut out, &|done| bar.inc(done));
    bar.finish_and_clear();
    if displacement.is_some() {
        let frame = DisplaceFrame::new(refiner.mesh(), refiner.topology(), refiner.layout());
        displacement.apply(&mut out, &frame)?;
    }
    Ok(out)
}

/// Where refinement runs: the GPU when built with the `gpu` feature and asked for (or found,
/// for `auto`), the CPU otherwise.
#[cfg(feature = "gpu")]
mod backend {
    use super::super::gpu;
    use crate::args::{BackendArg, RefineArgs};
    use anyhow::Context;
    use tessella_core::{Mesh, RefinedMesh, Refiner};
    use tessella_gpu::{gpu_refine_with, Displacement, GpuContext, GpuRefineOptions};

    pub struct Backend {
        ctx: Option<GpuContext>,
        displacement: Displacement,
    }

    pub fn choose(args: &RefineArgs, mesh: &Mesh) -> anyhow::Result<Backend> {
        let displacement = super::super::displace::parse(args.displace.as_deref())?;
        displacement.validate(mesh.uvs().is_some())?;
        let ctx = gpu::context_for(args.backend)?;
        Ok(Backend { ctx, displacement })
    }

    pub fn refine(
        backend: &Backend,
        args: &RefineArgs,
        refiner: &Refiner,
    ) -> anyhow::Result<RefinedMesh> {
        let displacement = &backend.displacement;
        let on_gpu = backend.ctx.as_ref().map(|ctx| {
            let gpu_options = GpuRefineOptions {
                displacement: displacement.clone(),
                max_chunk_items: None,
            };
            gpu_refine_with(ctx, refiner, &gpu_options)
        });
        let cpu = || super::refine_cpu(refiner, displacement);
        match on_gpu {
            Some(Ok(refined)) => Ok(refined),
            Some(Err(e)) if args.backend == BackendArg::Auto => {
                eprintln!("note: the GPU failed ({e}); refining on the CPU");
                cpu()
            }
            Some(Err(e)) => Err(e).context("GPU refinement failed"),
            None => cpu(),
        }
    }
}

/// Without the `gpu` feature: the CPU, and a clear error for what needs the GPU.
#[cfg(not(feature = "gpu"))]
mod backend {
    use crate::args::{BackendArg, RefineArgs};
    use tessella_core::displace::Displacement;
    use tessella_core::{Mesh, RefinedMesh, Refiner};

    pub struct Backend {
        displacement: Displacement,
    }

    pub fn choose(args: &RefineArgs, mesh: &Mesh) -> anyhow::Result<Backend> {
        if args.backend == BackendArg::Gpu {
            return Err(super::super::no_gpu("--backend gpu"));
        }
        let displacement = super::super::displace::parse(args.displace.as_deref())?;
        displacement.validate(mesh.uvs().is_some())?;
        Ok(Backend { displacement })
    }

    pub fn refine(
        backend: &Backend,
        _args: &RefineArgs,
        refiner: &Refiner,
    ) -> anyhow::Result<RefinedMesh> {
        super::refine_cpu(refiner, &backend.displacement)
    }
}
