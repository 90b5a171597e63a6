//! `tessella refine`: file in, refined file out.

pub use super::refined::Refined;
use super::tags;
use crate::args::RefineArgs;
use crate::progress;
use std::time::Instant;
use tessella_core::displace::{DisplaceFrame, Displacement};
use tessella_core::refine::Ask;
use tessella_core::{RefineOptions, RefinedMesh, Refiner};
use tessella_io::{Durability, Format, MeshView, WriteOptions};

pub fn run(args: &RefineArgs) -> anyhow::Result<()> {
    let done = refine_file(args, true, Durability::Synced)?;
    eprintln!(
        "{} -> {}: {} triangles -> {} vertices, {} triangles ({}) in {:.1} ms",
        args.input.display(),
        args.output.display(),
        done.input_triangles,
        done.vertices,
        done.triangles,
        done.what,
        done.refine_seconds * 1e3
    );
    if let (true, Some(mesh)) = (args.report, &done.mesh) {
        let report = tessella_core::quality::report(mesh, &done.options)?;
        super::info::print_quality(&[super::info::QualityRow::Measured(report)]);
    }
    Ok(())
}

/// Refines `args.input` into `args.output`; `bars`: show progress bars (on a terminal);
/// `durability`: whether the output is flushed to the disk before it gets its name.
pub fn refine_file(
    args: &RefineArgs,
    bars: bool,
    durability: Durability,
) -> anyhow::Result<Refined> {
    // Refuse an unknown output format, or an output that is the input, before doing any work.
    Format::from_path(&args.output)?;
    if same_file(&args.input, &args.output) {
        anyhow::bail!(
            "the output {} is the input file {}; refusing to replace it, give another output path",
            args.output.display(),
            args.input.display()
        );
    }
    let scene = super::refine_scene::applies(args);
    if args.max_edge.is_some() && !scene {
        anyhow::bail!("--max-edge chooses a level per glTF primitive; it needs a .gltf or .glb input and output, without --flatten or --clip");
    }
    if !scene && (args.joint_sets != "input" || args.tangents != "recomputed") {
        anyhow::bail!("--joint-sets and --tangents shape a glTF scene's refined primitives; they need a .gltf or .glb input and output, without --flatten or --clip");
    }
    if scene {
        return super::refine_scene::refine(args, options(args)?, durability);
    }
    let (mut raw, mesh) = super::pose::read(&args.input, &args.pose)?;
    let mut options = options(args)?;
    let scheme = options.scheme;
    if args.write_origin && !matches!(Format::from_path(&args.output)?, Format::Ply) {
        anyhow::bail!(
            "--write-origin writes PLY vertex properties; give an output ending in .ply, not {}",
            args.output.display()
        );
    }
    let asks = [
        args.displace.is_some().then_some(Ask::Displace),
        args.write_origin.then_some(Ask::Origin),
        (args.backend == tessella_core::Backend::Gl).then_some(Ask::GlBackend),
    ];
    super::options::refuse_conflicts(&options, asks.into_iter().flatten())?;
    if let Some(tags) = tags::gather(&raw, &mesh, scheme, &args.tags)? {
        options = options.with_tags(tags);
    }
    // Per-vertex fields (PLY vertex properties, glTF `_NAME` attributes) go through
    // refinement with the coarse faces' shape functions.
    let fields = kept_fields(std::mem::take(&mut raw.vertex_scalars), &args.output);
    drop(raw);

    if streams(args) {
        return stream::refine(args, mesh, options, &fields, bars, durability);
    }
    let start = Instant::now();
    let refiner = Refiner::new(&mesh, &options).map_err(|e| {
        // Only this path holds the whole output: say which one does not.
        let hint = match e {
            tessella_core::RefineError::TooLarge { .. } => match args.backend {
                tessella_core::Backend::Auto | tessella_core::Backend::Cpu => {
                    "; without --in-memory the CPU writes it piece by piece, within --max-memory"
                }
                _ => "; --backend cpu writes it piece by piece, within --max-memory",
            },
            _ => "",
        };
        anyhow::Error::new(e).context(format!("cannot refine {}{hint}", args.input.display()))
    })?;
    let backend = backend::choose(args, &mesh, refiner.plan().vertex_count() as u64)?;
    // Adaptive and tessellator plans too: the GPU compute path writes the CPU's layout.
    let refined = if args.backend == tessella_core::Backend::Gl {
        super::refine_gl::refine(&mesh, &options)?
    } else {
        backend::refine(&backend, args, &refiner)?
    };
    let elapsed = start.elapsed();

    let fields = refine_fields(&mesh, refiner.plan(), &fields)?;
    let scalars: Vec<(&str, &[f32])> = fields
        .iter()
        .map(|(n, v)| (n.as_str(), v.as_slice()))
        .collect();
    if args.write_origin {
        let (faces, bary) = refiner.plan().origin();
        tessella_io::ply::write_file_with(
            &args.output,
            MeshView::from(&refined),
            &scalars,
            Some(tessella_io::ply::Origin {
                faces: &faces,
                bary: &bary,
            }),
            args.ply_ascii,
        )?;
    } else {
        tessella_io::write_mesh_with_scalars(
            &args.output,
            MeshView::from(&refined),
            &scalars,
            &WriteOptions {
                ply_ascii: args.ply_ascii,
                durability,
            },
        )?;
    }
    let what = describe(&options, refiner.plan());
    let (vertices, triangles) = (refined.positions.len(), refined.triangles.len());
    drop((refined, refiner));
    Ok(Refined {
        what,
        input_triangles: mesh.face_count(),
        vertices: vertices as u64,
        triangles: triangles as u64,
        refine_seconds: elapsed.as_secs_f64(),
        streamed: false,
        mesh: Some(mesh),
        options,
    })
}

/// Scheme and level, as messages give them.
fn describe(options: &RefineOptions, plan: &tessella_core::refine::Plan) -> String {
    let level = match options.uniform_grid_level() {
        Some(n) => format!("level {n}"),
        None => format!(
            "{} spacing, levels up to {}",
            options.spacing,
            plan.layout().level
        ),
    };
    format!("{}, {level}", options.scheme.name())
}

/// Whether this refinement is written piece by piece (bounded memory, any size): every CPU
/// refinement, uniform or adaptive, welded or not, displaced or not, with per-vertex fields
/// and origins or without, to a format the streamed writer knows. The GPU backends (and
/// `--in-memory`) refine the whole mesh in memory, within `--max-memory`.
fn streams(args: &RefineArgs) -> bool {
    let cpu = matches!(
        args.backend,
        tessella_core::Backend::Auto | tessella_core::Backend::Cpu
    );
    let format = Format::from_path(&args.output).ok();
    cpu && !args.in_memory && format.is_some()
}

/// The streamed path: `--max-memory` is the working set, not a cap on the output.
mod stream {
    use super::Refined;
    use crate::args::RefineArgs;
    use crate::progress;
    use anyhow::Context;
    use std::time::Instant;
    use tessella_core::refine::Plan;
    use tessella_core::{Mesh, RefineOptions};
    use tessella_io::stream::expected_bytes;
    use tessella_io::{write_streamed, RefinedSource, WriteOptions};

    pub fn refine(
        args: &RefineArgs,
        mesh: Mesh,
        mut options: RefineOptions,
        fields: &[(String, Vec<f32>)],
        bars: bool,
        durability: tessella_io::Durability,
    ) -> anyhow::Result<Refined> {
        options.max_output_bytes = u64::MAX;
        let start = Instant::now();
        let (plan, frame) = Plan::with_frame(&mesh, &options)
            .with_context(|| format!("cannot refine {}", args.input.display()))?;
        let displacement = super::super::displace::parse(args.displace.as_deref())?;
        let mut source = RefinedSource::new(&plan, &frame, args.max_memory);
        if displacement.is_some() {
            source = source.displaced(&displacement)?;
        }
        source = source.with_fields(fields)?;
        if args.write_origin {
            source = source.with_origin();
        }
        let write = WriteOptions {
            ply_ascii: args.ply_ascii,
            durability,
        };
        let total = expected_bytes(&args.output, &source, &write)?;
        let bar = match bars {
            true => progress::byte_bar(total, "writing"),
            false => indicatif::ProgressBar::hidden(),
        };
        write_streamed(&args.output, &source, &write, &|n| bar.inc(n))?;
        bar.finish_and_clear();
        options.max_output_bytes = args.max_memory;
        Ok(Refined {
            what: super::describe(&options, &plan),
            input_triangles: mesh.face_count(),
            vertices: plan.vertex_count() as u64,
            triangles: plan.triangle_count() as u64,
            refine_seconds: start.elapsed().as_secs_f64(),
            streamed: true,
            mesh: Some(mesh),
            options,
        })
    }
}

/// The input's per-vertex fields, by name, or none, with a note, when `output`'s format
/// cannot hold them.
fn kept_fields(
    fields: std::collections::BTreeMap<String, Vec<f32>>,
    output: &std::path::Path,
) -> Vec<(String, Vec<f32>)> {
    if !fields.is_empty() && !tessella_io::holds_vertex_scalars(output) {
        let names: Vec<&str> = fields.keys().map(String::as_str).collect();
        eprintln!(
            "note: {} cannot hold per-vertex fields; {} not written (write .ply, .gltf or .glb to keep them)",
            output.display(),
            names.join(", ")
        );
        return Vec::new();
    }
    fields.into_iter().collect()
}

/// The fields at the refined vertices (`fields::interpolate_point_data`: linear on each
/// coarse face).
fn refine_fields(
    mesh: &tessella_core::Mesh,
    plan: &tessella_core::refine::Plan,
    fields: &[(String, Vec<f32>)],
) -> anyhow::Result<Vec<(String, Vec<f32>)>> {
    fields
        .iter()
        .map(|(name, values)| {
            let refined =
                tessella_core::fields::interpolate_point_data(mesh, plan, name, values, 1)?;
            Ok((name.clone(), refined))
        })
        .collect()
}

/// Whether writing `output` would replace `input`, however the two are spelled: `./`, `..`,
/// symbolic links (to the file or to a folder on its path) and, on Unix, hard links. The output
/// need not exist yet: then its folder is resolved and its name compared.
pub fn same_file(input: &std::path::Path, output: &std::path::Path) -> bool {
    let Ok(input) = std::fs::canonicalize(input) else {
        // An input that cannot be resolved cannot be read either; reading says why.
        return false;
    };
    // The same file by device and inode (hard links included), where the system says so.
    #[cfg(unix)]
    if let (Ok(a), Ok(b)) = (std::fs::metadata(&input), std::fs::metadata(output)) {
        use std::os::unix::fs::MetadataExt;
        if (a.dev(), a.ino()) == (b.dev(), b.ino()) {
            return true;
        }
    }
    let resolved = std::fs::canonicalize(output).or_else(|_| {
        let folder = match output.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => std::path::Path::new("."),
        };
        let name = output.file_name().ok_or(std::io::ErrorKind::NotFound)?;
        std::fs::canonicalize(folder).map(|f| f.join(name))
    });
    resolved.is_ok_and(|output| output == input)
}

/// The options from `--scheme`, `--alpha`, `--level`, `--spacing`, `--lod`, `--camera`,
/// `--size`, `--normals`, `--soup` and `--max-memory`, in the core's text form. A fractional
/// grid level geomorphs (docs/formulas.md, "Geomorphing grid patterns").
fn options(args: &RefineArgs) -> anyhow::Result<RefineOptions> {
    super::options::Flags {
        shape: args.shape,
        level: args.level,
        spacing: args.spacing,
        lod: args.lod.lod.as_deref(),
        camera: args.lod.camera.clone(),
        size: args.size,
        soup: args.soup,
        max_memory: Some(args.max_memory),
    }
    .parse()
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
    use crate::args::RefineArgs;
    use anyhow::Context;
    use tessella_core::{Mesh, RefinedMesh, Refiner};
    use tessella_gpu::{gpu_refine_with, Displacement, GpuContext, GpuRefineOptions};

    pub struct Backend {
        ctx: Option<GpuContext>,
        displacement: Displacement,
    }

    /// `vertices`: the plan's count, the one size estimate (`auto` opens no device for small
    /// outputs: the CPU will be faster than the probe).
    pub fn choose(args: &RefineArgs, mesh: &Mesh, vertices: u64) -> anyhow::Result<Backend> {
        let displacement = super::super::displace::parse(args.displace.as_deref())?;
        displacement.validate(mesh.uvs().is_some())?;
        let ctx = gpu::context_for(args.backend, vertices)?;
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
                ..Default::default()
            };
            gpu_refine_with(ctx, refiner, &gpu_options)
        });
        let cpu = || super::refine_cpu(refiner, displacement);
        match on_gpu {
            Some(Ok(refined)) => Ok(refined),
            Some(Err(e)) if args.backend.falls_back() => {
                // One line: wgpu's validation reports span several.
                let reason = e.to_string();
                let first = reason.lines().next().unwrap_or("unknown error").trim();
                eprintln!("note: the GPU failed ({first}); refining on the CPU");
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

    pub fn choose(args: &RefineArgs, mesh: &Mesh, _vertices: u64) -> anyhow::Result<Backend> {
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
