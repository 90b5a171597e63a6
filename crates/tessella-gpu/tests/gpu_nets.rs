//! Control nets built on the GPU from coarse vertices in the caller's buffers
//! (`GpuNetBuilder`): equal to the CPU's nets, evaluated and drawn as the CPU's, and refused
//! where the input or the consumer cannot take them.
mod common;

use common::{
    ctx, dist, pixels, read_vec3s, torus_with_uvs, worst_relative, PlainShading, FORMATS,
};
use tessella_core::refine::{Evaluator, Plan, Spacing, Surface, SurfaceOptions};
use tessella_core::{samples, Mesh, NormalMode, PatchNets, RefineOptions, Scheme};
use tessella_gpu::{
    AdaptiveRenderer, CoarseInput, CoarseStream, Displacement, GpuContext, GpuError, GpuEvaluator,
    GpuNetBuilder, GpuOutput, GpuRefineOptions, NetsTarget, PatternRenderer,
};

/// The engine's vertex: 9 words (36 bytes), the normal before the position, padding between
/// filled with a value that would show if it were read.
const STRIDE: u32 = 36;
const NORMAL_FIRST: u32 = 4;
const POSITION_FIRST: u32 = 20;
const PAD: f32 = 1.0e30;
/// Written into the targets before a build: a net entry left unwritten shows.
const SENTINEL: f32 = -7777.0;

/// The caller's buffer of coarse vertices, interleaved as [`STRIDE`] says, from byte `offset`.
fn engine_buffer(
    ctx: &GpuContext,
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    offset: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut words = vec![PAD; offset as usize / 4];
    for (p, n) in positions.iter().zip(normals) {
        words.extend([PAD, n[0], n[1], n[2], PAD, p[0], p[1], p[2], PAD]);
    }
    ctx.buffer_init("engine vertices", bytemuck::cast_slice(&words), usage)
}

/// The two streams of [`engine_buffer`]'s layout.
fn input(buffer: &wgpu::Buffer, offset: u64) -> CoarseInput<'_> {
    CoarseInput {
        positions: CoarseStream {
            buffer,
            offset,
            stride: STRIDE,
            first: POSITION_FIRST,
        },
        normals: CoarseStream {
            buffer,
            offset,
            stride: STRIDE,
            first: NORMAL_FIRST,
        },
    }
}

/// The storage-buffer offset alignment: a legal, non-zero offset.
fn aligned_offset(ctx: &GpuContext) -> u64 {
    u64::from(ctx.limits.min_storage_buffer_offset_alignment.max(4))
}

/// `mesh` twisted (positions and normals), with its normals scaled by 3 (the GPU normalises
/// them as `Mesh` does): what an engine's skinning hands over.
fn deformed(mesh: &Mesh, degrees: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let (p, n) = samples::twist(mesh, degrees);
    (p, n.iter().map(|v| v.map(|c| 3.0 * c)).collect())
}

/// Nets buffers of `faces` patches of the cubic basis, filled with [`SENTINEL`], readable.
fn target_buffers(ctx: &GpuContext, faces: usize) -> (wgpu::Buffer, wgpu::Buffer) {
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let filled = |label, floats: usize| {
        ctx.buffer_init(label, bytemuck::cast_slice(&vec![SENTINEL; floats]), usage)
    };
    (
        filled("points", faces * 10 * 3),
        filled("normals", faces * 6 * 3),
    )
}

/// Builds the nets of `scheme`/`mode` for `mesh` deformed, on the GPU from the engine's
/// buffer and on the CPU from the same vertices; returns (GPU, CPU).
fn both_nets(mesh: &Mesh, scheme: Scheme, mode: NormalMode) -> (PatchNets, PatchNets) {
    let ctx = ctx();
    let surface = Surface::new(mesh, &SurfaceOptions::new(scheme).with_normals(mode)).unwrap();
    let (positions, normals) = deformed(mesh, 50.0);
    let moved = Mesh::new(
        positions.clone(),
        Some(normals.clone()),
        None,
        mesh.triangles().to_vec(),
    )
    .unwrap();
    let cpu = surface.frame(&moved).unwrap().nets().clone();
    let offset = aligned_offset(ctx);
    let buffer = engine_buffer(
        ctx,
        &positions,
        &normals,
        offset,
        wgpu::BufferUsages::STORAGE,
    );
    let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
    let faces = surface.face_count();
    let (points, nets_normals) = target_buffers(ctx, faces);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    builder
        .record(
            &mut encoder,
            input(&buffer, offset),
            NetsTarget::new(&points, &nets_normals, faces, mode),
        )
        .unwrap();
    ctx.submit_and_wait(encoder).unwrap();
    let gpu = PatchNets {
        basis: cpu.basis,
        normal_mode: mode,
        points: read_vec3s(ctx, &points),
        normals: read_vec3s(ctx, &nets_normals),
    };
    (gpu, cpu)
}

#[test]
fn gpu_nets_equal_the_cpu_nets_within_1e_6_relative() {
    // Split normals on the upper half (hard edges), shared on the lower; and the hard cube,
    // where every edge is a seam.
    let meshes = [
        ("half-faceted icosphere", samples::half_faceted_icosphere(1)),
        ("hard cube", samples::hard_cube()),
    ];
    let cases = [
        (Scheme::Flat, NormalMode::Linear),
        (Scheme::PHONG, NormalMode::Linear),
        (Scheme::PHONG, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Linear),
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
        (Scheme::PnAen, NormalMode::Quadratic),
        (Scheme::PnAen, NormalMode::Linear),
    ];
    for (name, mesh) in &meshes {
        for (scheme, mode) in cases {
            let (gpu, cpu) = both_nets(mesh, scheme, mode);
            let what = format!("{name}, {} with {mode:?} normals", scheme.name());
            let points = worst_relative(&gpu.points, &cpu.points);
            let normals = worst_relative(&gpu.normals, &cpu.normals);
            assert!(
                points <= 1e-6,
                "{what}: control points differ by {points:e}"
            );
            assert!(normals <= 1e-6, "{what}: normal nets differ by {normals:e}");
        }
    }
}

#[test]
fn pn_aen_on_the_gpu_reads_the_other_sides_normals() {
    // Where the normals split, PN-AEN's edges are not PN's: the GPU's PN-AEN nets match the
    // CPU's PN-AEN (above), and here differ from PN's, so the neighbour table is used.
    let mesh = samples::hard_cube();
    let (aen, _) = both_nets(&mesh, Scheme::PnAen, NormalMode::Quadratic);
    let (_, pn) = both_nets(&mesh, Scheme::Pn, NormalMode::Quadratic);
    let apart = worst_relative(&aen.points, &pn.points);
    assert!(apart > 1e-2, "PN-AEN's nets equal PN's ({apart:e})");
}

#[test]
fn a_frame_of_gpu_nets_uploads_nothing_until_the_layout_changes() {
    let ctx = ctx();
    let mesh = samples::icosphere(1);
    let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn)).unwrap();
    let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
    let offset = aligned_offset(ctx);
    let buffer = engine_buffer(
        ctx,
        mesh.positions(),
        mesh.normals(),
        offset,
        wgpu::BufferUsages::STORAGE,
    );
    let faces = surface.face_count();
    let (points, normals) = target_buffers(ctx, faces);
    let target = NetsTarget::new(&points, &normals, faces, NormalMode::Quadratic);
    // The same buffer again, from another offset: the uniform holds the layout, not the
    // offset. Then tightly packed arrays, one buffer each: a new layout.
    let positions = ctx.buffer_init(
        "positions",
        bytemuck::cast_slice(mesh.positions()),
        wgpu::BufferUsages::STORAGE,
    );
    let normals_only = ctx.buffer_init(
        "normals",
        bytemuck::cast_slice(mesh.normals()),
        wgpu::BufferUsages::STORAGE,
    );
    let packed = |buffer| CoarseStream {
        buffer,
        offset: 0,
        stride: 12,
        first: 0,
    };
    let packed = CoarseInput {
        positions: packed(&positions),
        normals: packed(&normals_only),
    };
    let mut written = Vec::new();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    for input in [
        input(&buffer, offset),
        input(&buffer, offset),
        input(&buffer, 0),
        packed,
        packed,
    ] {
        written.push(builder.record(&mut encoder, input, target).unwrap());
    }
    ctx.submit_and_wait(encoder).unwrap();
    // The first frame writes the 48-byte uniform; the same layout again writes nothing; a
    // new layout writes it again.
    assert_eq!(written, [48, 0, 0, 48, 0]);
    // And the packed input's nets are the mesh's.
    let cpu = surface.frame(&mesh).unwrap().nets().clone();
    let gpu_points = read_vec3s(ctx, &points);
    assert!(worst_relative(&gpu_points, &cpu.points) <= 1e-6);
}

#[test]
fn the_evaluator_evaluates_gpu_nets_as_it_evaluates_cpu_nets() {
    let ctx = ctx();
    for (mesh, scheme, level) in [
        (samples::half_faceted_icosphere(1), Scheme::PnAen, 4),
        (torus_with_uvs(), Scheme::PHONG, 3),
    ] {
        let plan = Plan::new(&mesh, &RefineOptions::new(scheme, level)).unwrap();
        let (positions, normals) = deformed(&mesh, 40.0);
        let mut frame = plan.frame(&mesh).unwrap();
        plan.update(&mut frame, &positions, Some(&normals)).unwrap();
        let mut cpu_nets = GpuEvaluator::new(ctx, &plan).unwrap();
        cpu_nets.evaluate(&plan, &frame, GpuOutput::Own).unwrap();
        let want = cpu_nets.read_back().unwrap();

        let offset = aligned_offset(ctx);
        let buffer = engine_buffer(
            ctx,
            &positions,
            &normals,
            offset,
            wgpu::BufferUsages::STORAGE,
        );
        let builder = GpuNetBuilder::new(ctx, plan.surface()).unwrap();
        let mut gpu_nets = GpuEvaluator::new(ctx, &plan).unwrap();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        builder
            .record(
                &mut encoder,
                input(&buffer, offset),
                gpu_nets.nets_target().unwrap(),
            )
            .unwrap();
        if plan.has_uvs() {
            // The builder writes positions and normals; the UVs are written once.
            let refused = gpu_nets.record_built(&mut encoder, &plan, GpuOutput::Own);
            assert!(
                matches!(&refused, Err(GpuError::BadOption(m)) if m.contains("write_uvs")),
                "{refused:?}"
            );
            let uvs = mesh.uvs().unwrap();
            assert_eq!(
                gpu_nets.write_uvs(&plan, uvs).unwrap(),
                uvs.len() as u64 * 8
            );
        }
        gpu_nets
            .record_built(&mut encoder, &plan, GpuOutput::Own)
            .unwrap();
        ctx.submit_and_wait(encoder).unwrap();
        assert_eq!(gpu_nets.uploaded_bytes(), 0);
        let got = gpu_nets.read_back().unwrap();
        assert_eq!(got.len(), want.len());
        // Positions, normals (and UVs) interleaved: within 1e-5 of the mesh's size.
        let tol = 1e-5 * mesh.diagonal().max(1.0);
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                (g - w).abs() <= tol,
                "{}: float {i}: {g} (GPU nets) vs {w} (CPU nets)",
                scheme.name()
            );
        }
        // The deformation shows: the rest mesh's vertices are not the output.
        let rest = {
            let mut e = GpuEvaluator::new(ctx, &plan).unwrap();
            e.evaluate(&plan, &plan.frame(&mesh).unwrap(), GpuOutput::Own)
                .unwrap();
            e.read_back().unwrap()
        };
        let moved = got
            .iter()
            .zip(&rest)
            .filter(|(a, b)| (*a - *b).abs() > 1e-3);
        assert!(moved.count() > got.len() / 4);
    }
}

/// Pixels whose colour differs by more than 2 in a channel.
fn differing(a: &[[u8; 4]], b: &[[u8; 4]]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.iter().zip(y.iter()).any(|(p, q)| p.abs_diff(*q) > 2))
        .count()
}

#[test]
fn the_pattern_renderer_draws_gpu_nets_as_it_draws_cpu_nets() {
    let ctx = ctx();
    let plain = PlainShading::new(ctx, FORMATS);
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 6)).unwrap();
    let rest = plan.frame(&mesh).unwrap();
    let (positions, normals) = deformed(&mesh, 90.0);
    let mut moved = rest.clone();
    plan.update(&mut moved, &positions, Some(&normals)).unwrap();
    let none = Displacement::None;
    let cpu = PatternRenderer::new(ctx, &plan, &moved, &plain.shading(), &none).unwrap();
    // Made from the rest frame; the builder moves it.
    let gpu = PatternRenderer::new(ctx, &plan, &rest, &plain.shading(), &none).unwrap();
    let before = pixels(ctx, |pass| gpu.draw(pass, &plain.group));
    let offset = aligned_offset(ctx);
    let buffer = engine_buffer(
        ctx,
        &positions,
        &normals,
        offset,
        wgpu::BufferUsages::STORAGE,
    );
    let builder = GpuNetBuilder::new(ctx, plan.surface()).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    builder
        .record(
            &mut encoder,
            input(&buffer, offset),
            gpu.nets_target().unwrap(),
        )
        .unwrap();
    ctx.submit_and_wait(encoder).unwrap();
    let want = pixels(ctx, |pass| cpu.draw(pass, &plain.group));
    let got = pixels(ctx, |pass| gpu.draw(pass, &plain.group));
    let covered = want.iter().filter(|p| p[3] != 0).count();
    assert!(covered > 600, "the picture covers {covered} pixels");
    // The twist changes the picture; the GPU-built nets give the CPU nets' picture.
    assert!(differing(&before, &want) > 50);
    let off = differing(&got, &want);
    assert!(off <= 4, "{off} pixels differ from the CPU nets' picture");
}

#[test]
fn the_adaptive_renderer_draws_gpu_nets_as_it_draws_cpu_nets() {
    let ctx = ctx();
    let plain = PlainShading::new(ctx, FORMATS);
    let mesh = samples::half_faceted_icosphere(1);
    let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::PnAen)).unwrap();
    let rest = surface.frame(&mesh).unwrap();
    let (positions, normals) = deformed(&mesh, 60.0);
    let mut moved = rest.clone();
    surface
        .update(&mut moved, &positions, Some(&normals))
        .unwrap();
    let levels: Vec<f32> = (0..surface.topology().edges.len())
        .map(|e| 2.0 + (e % 5) as f32)
        .collect();
    let shading = plain.shading();
    let spacing = Spacing::FractionalOdd;
    let mut cpu = AdaptiveRenderer::new(ctx, &surface, &moved, &shading, spacing).unwrap();
    let mut gpu = AdaptiveRenderer::new(ctx, &surface, &rest, &shading, spacing).unwrap();
    cpu.set_levels(&levels, None).unwrap();
    gpu.set_levels(&levels, None).unwrap();
    let offset = aligned_offset(ctx);
    let buffer = engine_buffer(
        ctx,
        &positions,
        &normals,
        offset,
        wgpu::BufferUsages::STORAGE,
    );
    let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    builder
        .record(&mut encoder, input(&buffer, offset), gpu.nets_target())
        .unwrap();
    ctx.submit_and_wait(encoder).unwrap();
    let want = cpu.capture().unwrap();
    let got = gpu.capture().unwrap();
    assert_eq!(got.faces, want.faces);
    assert!(!got.positions.is_empty());
    let tol = 1e-5 * mesh.diagonal();
    for (i, (g, w)) in got.positions.iter().zip(&want.positions).enumerate() {
        assert!(dist(*g, *w) <= tol, "vertex {i}: {g:?} vs {w:?}");
    }
    for (i, (g, w)) in got.normals.iter().zip(&want.normals).enumerate() {
        assert!(dist(*g, *w) <= 1e-4, "normal {i}: {g:?} vs {w:?}");
    }
}

/// The message of a `BadOption`, or a panic naming what came instead.
fn bad_option<T: std::fmt::Debug>(result: Result<T, GpuError>) -> String {
    match result {
        Err(GpuError::BadOption(m)) => m,
        other => panic!("expected BadOption, got {other:?}"),
    }
}

#[test]
fn bad_input_and_consumers_that_cannot_take_gpu_nets_are_refused() {
    let ctx = ctx();
    let mesh = samples::icosphere(1);
    let n = mesh.vertex_count();
    let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn)).unwrap();
    let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
    let faces = surface.face_count();
    let (points, normals) = target_buffers(ctx, faces);
    let target = NetsTarget::new(&points, &normals, faces, NormalMode::Quadratic);
    let offset = aligned_offset(ctx);
    let storage = wgpu::BufferUsages::STORAGE;
    let record = |input: CoarseInput<'_>, target: NetsTarget<'_>| {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        builder.record(&mut encoder, input, target)
    };
    let good = engine_buffer(ctx, mesh.positions(), mesh.normals(), offset, storage);
    assert_eq!(record(input(&good, offset), target).unwrap(), 48);

    // A buffer the shaders cannot read.
    let vertex_only = engine_buffer(
        ctx,
        mesh.positions(),
        mesh.normals(),
        offset,
        wgpu::BufferUsages::VERTEX,
    );
    let m = bad_option(record(input(&vertex_only, offset), target));
    assert!(m.contains("lacks STORAGE"), "{m}");
    // One vertex short.
    let short = engine_buffer(
        ctx,
        &mesh.positions()[..n - 1],
        &mesh.normals()[..n - 1],
        offset,
        storage,
    );
    let m = bad_option(record(input(&short, offset), target));
    assert!(m.contains(&format!("{n} vertices need")), "{m}");
    // An offset off the device's alignment.
    let m = bad_option(record(input(&good, offset + 4), target));
    assert!(m.contains("alignment"), "{m}");
    // A target of another mesh (another vertex and face count), another normal net.
    let other = Plan::new(&samples::icosphere(2), &RefineOptions::new(Scheme::Pn, 2)).unwrap();
    let evaluator = GpuEvaluator::new(ctx, &other).unwrap();
    let m = bad_option(record(
        input(&good, offset),
        evaluator.nets_target().unwrap(),
    ));
    assert!(m.contains("patches"), "{m}");
    let linear = NetsTarget::new(&points, &normals, faces, NormalMode::Linear);
    let m = bad_option(record(input(&good, offset), linear));
    assert!(m.contains("Linear normals"), "{m}");
    // A target buffer the builder cannot write.
    let unwritable = ctx.buffer_init(
        "unwritable",
        &vec![0; points.size() as usize],
        wgpu::BufferUsages::COPY_SRC,
    );
    let m = bad_option(record(
        input(&good, offset),
        NetsTarget::new(&unwritable, &normals, faces, NormalMode::Quadratic),
    ));
    assert!(m.contains("lacks STORAGE"), "{m}");

    // Schemes whose nets stay on the CPU, which `builds` names up front (an engine picks its
    // posing path with it), and those it builds.
    for scheme in [
        Scheme::Flat,
        Scheme::Phong { alpha: 0.75 },
        Scheme::Pn,
        Scheme::PnAen,
    ] {
        assert!(GpuNetBuilder::builds(&scheme), "{}", scheme.name());
    }
    for scheme in [Scheme::Png1, Scheme::ScalarTagged] {
        assert!(!GpuNetBuilder::builds(&scheme), "{}", scheme.name());
        let s = Surface::new(&mesh, &SurfaceOptions::new(scheme)).unwrap();
        let m = bad_option(GpuNetBuilder::new(ctx, &s));
        assert!(
            m.contains(&format!("'{}' nets are built on the CPU", scheme.name()))
                && m.contains("flat, phong, pn and pn-aen"),
            "{m}"
        );
    }

    // Displacement needs per-face records from a CPU frame.
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let plain = PlainShading::new(ctx, FORMATS);
    let sine = Displacement::Sine {
        amplitude: 0.05,
        frequency: 4.0,
    };
    let displaced = PatternRenderer::new(ctx, &plan, &frame, &plain.shading(), &sine).unwrap();
    let m = bad_option(displaced.nets_target());
    assert!(m.contains("displaced pattern renderer"), "{m}");
    let options = GpuRefineOptions {
        displacement: sine,
        ..Default::default()
    };
    let displaced = GpuEvaluator::with_options(ctx, &plan, &options).unwrap();
    let m = bad_option(displaced.nets_target());
    assert!(m.contains("displaced GPU evaluator"), "{m}");
    // Without displacement the same renderer takes them.
    let plain_renderer =
        PatternRenderer::new(ctx, &plan, &frame, &plain.shading(), &Displacement::None).unwrap();
    assert_eq!(
        record(input(&good, offset), plain_renderer.nets_target().unwrap()).unwrap(),
        0
    );
    // As does the engine's own patch group.
    let vertex = wgpu::ShaderStages::VERTEX;
    let bindings = tessella_gpu::PatchBindings::new(ctx, &plan, &frame, 0, vertex).unwrap();
    assert_eq!(
        record(input(&good, offset), bindings.nets_target()).unwrap(),
        0
    );
}

#[test]
fn nets_over_one_binding_are_too_large() {
    // A device whose storage bindings hold 1 KiB: the icosphere's triangles fit (960 bytes),
    // its 80 patches' control points (9600 bytes) do not.
    let mut small = ctx().clone();
    small.limits.max_storage_buffer_binding_size = 1024;
    let mesh = samples::icosphere(1);
    let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn)).unwrap();
    let builder = GpuNetBuilder::new(&small, &surface).unwrap();
    let faces = surface.face_count();
    let (points, normals) = target_buffers(&small, faces);
    let offset = aligned_offset(&small);
    let buffer = engine_buffer(
        &small,
        mesh.positions(),
        mesh.normals(),
        offset,
        wgpu::BufferUsages::STORAGE,
    );
    let mut encoder = small.device.create_command_encoder(&Default::default());
    let result = builder.record(
        &mut encoder,
        input(&buffer, offset),
        NetsTarget::new(&points, &normals, faces, NormalMode::Quadratic),
    );
    match result {
        Err(GpuError::TooLarge { what, bytes, limit }) => {
            assert!(what.contains("control nets"), "{what}");
            assert_eq!((bytes, limit), (faces as u64 * 120, 1024));
        }
        other => panic!("expected TooLarge, got {other:?}"),
    }
}
