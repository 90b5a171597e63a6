//! The render path's displacement against the CPU's: a displaced hard cube drawn with the
//! instanced pattern (displacement in the vertex shader, one coarse face per instance) looks
//! like the CPU's displaced, welded (closed) refined mesh drawn triangle by triangle. Before
//! the shared direction on hard edges, every instance moved its rim along its own face normal
//! and the cube's edges opened.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

use common::ctx;
use image::RgbaImage;
use tessella_core::displace::{DisplaceFrame, Displacement};
use tessella_core::refine::Plan;
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme};
use tessella_gpu::PatternRenderer;
use tessella_view::{scene_uniforms, Appearance, RenderOptions, RenderUniforms, Target};

const SIZE: (u32, u32) = (160, 160);

/// `mesh` refined with `refine` and displaced by `displacement` in the vertex shader, seen
/// through `uniforms`.
fn draw(
    mesh: &Mesh,
    refine: &RefineOptions,
    displacement: &Displacement,
    uniforms: &RenderUniforms,
) -> RgbaImage {
    let plan = Plan::new(mesh, refine).unwrap();
    let frame = plan.frame(mesh).unwrap();
    let look = Appearance::new(ctx(), Target::FORMATS);
    let renderer =
        PatternRenderer::new(ctx(), &plan, &frame, &look.shading(), displacement).unwrap();
    look.set_uniforms(uniforms);
    let target = Target::new(ctx(), SIZE).unwrap();
    target
        .draw(ctx(), [255, 255, 255, 255], |pass| {
            look.draw(pass, &renderer)
        })
        .unwrap();
    target.read(ctx()).unwrap()
}

/// Pixels whose colour differs by more than 24 levels in some channel.
fn differing(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count()
}

#[test]
fn instanced_displacement_draws_the_cpus_closed_surface() {
    let d = Displacement::Sine {
        amplitude: 0.15,
        frequency: 6.0,
    };
    for (name, mesh) in [
        ("hard cube", samples::hard_cube()),
        ("half-faceted icosphere", samples::half_faceted_icosphere(1)),
    ] {
        let refine = RefineOptions::new(Scheme::PnAen, 8);
        // The CPU's displaced welded output, as a coarse mesh drawn flat at level 1: exactly
        // its triangles.
        let refiner = Refiner::new(&mesh, &refine).unwrap();
        let mut cpu = refiner.refine();
        let frame = DisplaceFrame::new(&mesh, refiner.topology(), refiner.layout());
        d.apply(&mut cpu, &frame).unwrap();
        let cpu_mesh = Mesh::new(cpu.positions, Some(cpu.normals), None, cpu.triangles).unwrap();
        for (yaw, pitch) in [(35.0, 25.0), (-120.0, -30.0)] {
            // One camera for both pictures, facet shading (flags.z) in both.
            let view = RenderOptions {
                size: SIZE,
                yaw,
                pitch,
                displacement: d.clone(),
                ..Default::default()
            };
            let uniforms = scene_uniforms(&mesh, &view, d.reach());
            assert_eq!(uniforms.flags[2], 1, "facet normals for displaced surfaces");
            let instanced = draw(&mesh, &refine, &d, &uniforms);
            let flat = RefineOptions::new(Scheme::Flat, 1);
            let reference = draw(&cpu_mesh, &flat, &Displacement::None, &uniforms);
            let covered = reference
                .pixels()
                .filter(|p| p.0[..3] != [255, 255, 255])
                .count();
            assert!(
                covered > 4000,
                "{name}: the surface covers only {covered} pixels"
            );
            let off = differing(&instanced, &reference);
            // Rasterisation of the same triangles may round differently at a few edges.
            assert!(
                off <= 40,
                "{name} yaw {yaw} pitch {pitch}: {off} pixels differ from the CPU's surface"
            );
        }
    }
}
