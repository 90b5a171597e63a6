//! Tessellator spacings and adaptive levels in the instanced renderer: one draw per distinct
//! pattern, the faces of each as instances. The picture is compared with the CPU's refinement of
//! the same plan drawn as a plain vertex buffer (`PatternRenderer::draw_refined`, no stencil on
//! the GPU): the two must cover the same pixels with the same colours, up to rasterisation.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;
mod pixels;

use common::ctx;
use image::RgbaImage;
use pixels::{crack_pixels, MAGENTA};
use std::sync::Arc;
use tessella_core::refine::{Levels, Plan, Spacing, Surface, SurfaceOptions};
use tessella_core::Named;
use tessella_core::{refine, samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{AdaptiveRenderer, Displacement, PatternRenderer};
use tessella_view::{scene_uniforms, Appearance, RenderOptions, Target};
use wgpu::util::DeviceExt;

fn view() -> RenderOptions {
    RenderOptions {
        size: (160, 160),
        ..Default::default()
    }
}

/// The instanced picture and the CPU-refined picture of `options`, and the renderer's draws.
fn both(mesh: &Mesh, options: &RefineOptions) -> (RgbaImage, RgbaImage, usize) {
    let plan = Plan::new(mesh, options).unwrap();
    let frame = plan.frame(mesh).unwrap();
    let look = Appearance::new(ctx(), Target::FORMATS);
    let renderer =
        PatternRenderer::new(ctx(), &plan, &frame, &look.shading(), &Displacement::None).unwrap();
    look.set_uniforms(&scene_uniforms(mesh, &view(), 0.0));
    let target = Target::new(ctx(), view().size).unwrap();
    target
        .draw(ctx(), [255; 4], |pass| look.draw(pass, &renderer))
        .unwrap();
    let instanced = target.read(ctx()).unwrap();

    let cpu = refine(mesh, options).unwrap();
    let vertices: Vec<f32> = cpu
        .positions
        .iter()
        .zip(&cpu.normals)
        .flat_map(|(p, n)| p.iter().chain(n).copied())
        .collect();
    let indices: Vec<u32> = cpu.triangles.iter().flatten().copied().collect();
    let init = |contents: &[u8], usage| {
        ctx()
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents,
                usage,
            })
    };
    let vb = init(bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
    let ib = init(bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
    target
        .draw(ctx(), [255; 4], |pass| {
            renderer.draw_refined(
                pass,
                look.group(),
                vb.slice(..),
                ib.slice(..),
                wgpu::IndexFormat::Uint32,
                indices.len() as u32,
            )
        })
        .unwrap();
    let reference = target.read(ctx()).unwrap();
    (instanced, reference, renderer.draw_count())
}

fn differing(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 12))
        .count()
}

fn covered(a: &RgbaImage) -> usize {
    a.pixels().filter(|p| p.0[..3] != [255; 3]).count()
}

#[test]
fn tessellator_spacings_draw_the_cpu_surface() {
    let mesh = samples::icosphere(1);
    // The tolerance tells patterns apart: levels 2.5 and 3.5 differ in far more pixels.
    let at = |level| {
        let options = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::Uniform(level));
        both(&mesh, &options).0
    };
    let apart = differing(&at(2.5), &at(3.5));
    assert!(
        apart > 200,
        "levels 2.5 and 3.5 differ in only {apart} pixels"
    );
    for spacing in [
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        for level in [1.0, 2.5, 5.5, 63.9, 500.0] {
            let options = RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(Levels::Uniform(level));
            let (instanced, reference, draws) = both(&mesh, &options);
            let what = format!("{spacing:?} level {level}");
            // Uniform levels: one pattern, one draw.
            assert_eq!(draws, 1, "{what}");
            assert!(covered(&reference) > 5000, "{what}: blank reference");
            let d = differing(&instanced, &reference);
            assert!(d <= 40, "{what}: {d} pixels differ from the CPU's surface");
        }
    }
}

#[test]
fn per_edge_levels_draw_one_pattern_per_tile() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 1)).unwrap();
    let edges = plan.topology().edges.len();
    // Levels varying edge by edge (1..8), fractional.
    let levels: Arc<[f32]> = (0..edges)
        .map(|e| 1.0 + (e * 37 % 71) as f32 / 10.0)
        .collect();
    for spacing in [
        Spacing::Grid,
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        let options = RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(spacing)
            .with_levels(Levels::PerEdge {
                edges: levels.clone(),
                faces: None,
            });
        let (instanced, reference, draws) = both(&mesh, &options);
        let what = format!("{spacing:?}");
        assert!(draws > 1, "{what}: {draws} draws");
        assert!(covered(&reference) > 5000, "{what}: blank reference");
        let d = differing(&instanced, &reference);
        assert!(d <= 40, "{what}: {d} pixels differ from the CPU's surface");
    }
}

#[test]
fn the_compute_path_refines_adaptive_plans_like_the_cpu() {
    // Detailed comparisons live in tessella-gpu's tests/adaptive.rs; here the picture's plan.
    let mesh = samples::icosphere(0);
    let options = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_levels(Levels::Uniform(3.5));
    let refiner = tessella_core::Refiner::new(&mesh, &options).unwrap();
    let gpu = tessella_gpu::gpu_refine(ctx(), &refiner).unwrap();
    let cpu = refiner.refine();
    assert_eq!(gpu.triangles, cpu.triangles);
    assert_eq!(gpu.positions.len(), cpu.positions.len());
}

/// The picture `AdaptiveRenderer` draws of `mesh` with per-edge `levels`, and its draw count.
fn live(
    mesh: &Mesh,
    scheme: Scheme,
    spacing: Spacing,
    levels: &[f32],
    view: &RenderOptions,
) -> (RgbaImage, usize) {
    let surface = Surface::new(mesh, &SurfaceOptions::new(scheme)).unwrap();
    let frame = surface.frame(mesh).unwrap();
    let look = Appearance::new(ctx(), Target::FORMATS);
    let mut renderer =
        AdaptiveRenderer::new(ctx(), &surface, &frame, &look.shading(), spacing).unwrap();
    renderer.set_levels(levels, None).unwrap();
    look.set_uniforms(&scene_uniforms(mesh, view, 0.0));
    let target = Target::new(ctx(), view.size).unwrap();
    target
        .draw(ctx(), [255; 4], |pass| look.draw(pass, &renderer))
        .unwrap();
    (target.read(ctx()).unwrap(), renderer.draw_count())
}

#[test]
fn levels_set_per_frame_draw_the_cpu_surface() {
    let mesh = samples::icosphere(1);
    let edges = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 1))
        .unwrap()
        .topology()
        .edges
        .len();
    let varying: Vec<f32> = (0..edges)
        .map(|e| 1.0 + (e * 37 % 71) as f32 / 10.0)
        .collect();
    for scheme in [Scheme::Pn, Scheme::Png1] {
        for &spacing in Spacing::ALL {
            for levels in [vec![5.5; edges], vec![2.0; edges], varying.clone()] {
                let options = RefineOptions::new(scheme, 1)
                    .with_spacing(spacing)
                    .with_levels(Levels::PerEdge {
                        edges: levels.clone().into(),
                        faces: None,
                    });
                let (_, reference, _) = both(&mesh, &options);
                let (picture, draws) = live(&mesh, scheme, spacing, &levels, &view());
                let what = format!("{} {spacing:?} levels {:?}..", scheme.name(), &levels[..3]);
                assert!(draws >= 1, "{what}");
                assert!(covered(&reference) > 5000, "{what}: blank reference");
                let d = differing(&picture, &reference);
                assert!(d <= 40, "{what}: {d} pixels differ from the CPU's surface");
            }
        }
    }
    // The comparison sees a wrong level: 5.5 against 2.5 differs in far more pixels.
    let options = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_levels(Levels::Uniform(2.5));
    let (_, reference, _) = both(&mesh, &options);
    let (picture, _) = live(
        &mesh,
        Scheme::Pn,
        Spacing::FractionalOdd,
        &vec![5.5; edges],
        &view(),
    );
    let d = differing(&picture, &reference);
    assert!(d > 200, "{d}");
}

#[test]
fn levels_set_per_frame_leave_no_cracks_and_upload_only_coarse_data() {
    let mesh = samples::icosphere(1);
    let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn)).unwrap();
    let edges = surface.topology().edges.len();
    let view = RenderOptions {
        size: (256, 256),
        yaw: 23.0,
        pitch: 17.0,
        back_color: Some(MAGENTA),
        ..Default::default()
    };
    let frame = surface.frame(&mesh).unwrap();
    for &spacing in Spacing::ALL {
        let look = Appearance::new(ctx(), Target::FORMATS);
        let mut renderer =
            AdaptiveRenderer::new(ctx(), &surface, &frame, &look.shading(), spacing).unwrap();
        let mut uploads = Vec::new();
        for step in 0..4 {
            // Levels that differ edge by edge and change every frame, low to high.
            let levels: Vec<f32> = (0..edges)
                .map(|e| 1.5 + ((e * 29 + step * 11) % 53) as f32 * (0.2 + step as f32 * 0.35))
                .collect();
            uploads.push(renderer.set_levels(&levels, None).unwrap());
            look.set_uniforms(&scene_uniforms(&mesh, &view, 0.0));
            let target = Target::new(ctx(), view.size).unwrap();
            target
                .draw(ctx(), [255; 4], |pass| look.draw(pass, &renderer))
                .unwrap();
            let picture = target.read(ctx()).unwrap();
            let magenta = crack_pixels(&picture);
            assert_eq!(magenta, 0, "{spacing:?} step {step}: crack pixels");
            assert!(covered(&picture) > 10_000, "{spacing:?}: blank");
        }
        // The upload is one record per face and an instance per face and part: the same bytes
        // whatever the levels (up to 66.5 here, over the maxima: clamped), at most 112 bytes a
        // face.
        let faces = mesh.face_count() as u64;
        assert!(
            uploads.iter().all(|&b| b == uploads[0]),
            "{spacing:?} {uploads:?}"
        );
        assert!(uploads[0] <= faces * 112, "{spacing:?} {uploads:?}");
    }
}
