//! `tessella refine`: file in, refined file out.

use crate::args::{BackendArg, RefineArgs};
use crate::progress;
use anyhow::{bail, Context};
use std::time::Instant;
use tessella_core::{RefineOptions, RefinedMesh, Refiner};
use tessella_io::{read_mesh, write_mesh, Format, MeshView, WriteOptions};

pub fn run(args: &RefineArgs) -> anyhow::Result<()> {
    // Refuse an unwritable output format before doing any work.
    let format = Format::from_path(&args.output)?;
    if format == Format::Stl {
        bail!("cannot write {}: STL is read-only here (it has no shared vertices or normals); use .obj, .ply, .gltf or .glb", args.output.display());
    }
    let mesh = read_mesh(&args.input)?;
    let mut options =
        RefineOptions::new(args.scheme.scheme(args.alpha), args.level).with_weld(!args.soup);
    options.normals = args.normals.map(Into::into);
    options.max_output_bytes = args.max_memory;

    let start = Instant::now();
    let refiner = Refiner::new(&mesh, &options)
        .with_context(|| format!("cannot refine {}", args.input.display()))?;
    let refined = match args.backend {
        BackendArg::Auto | BackendArg::Cpu => refine_cpu(&refiner),
        BackendArg::Gpu => bail!("the GPU backend is not part of this build; use --backend cpu"),
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
    Ok(())
}

fn refine_cpu(refiner: &Refiner) -> RefinedMesh {
    let bar = progress::bar(refiner.progress_total(), "refining");
    let mut out = RefinedMesh::default();
    refiner.refine_into(&mut out, &|done| bar.inc(done));
    bar.finish_and_clear();
    out
}
