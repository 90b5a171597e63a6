//! A context compiles each kind of pipeline once: a second renderer or evaluator of the same
//! kind reuses it (an engine draws many meshes), another variant compiles its own, and what
//! the reused pipelines compute is still right.

mod common;

use common::{assert_same, ctx, PlainShading};
use tessella_core::refine::Spacing;
use tessella_core::{samples, NormalMode, RefineOptions, Refiner, Scheme};
use tessella_gpu::{gpu_refine, AdaptiveRenderer, GpuContext, PatternRenderer, TargetFormats};

#[test]
fn pipelines_are_compiled_once_per_kind_and_variant() {
    // A context of its own, so the count is this test's alone.
    let ctx = GpuContext::from_device(ctx().device.clone(), ctx().queue.clone());
    assert_eq!(ctx.cached_pipelines(), 0);
    let formats = TargetFormats {
        color: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth: Some(wgpu::TextureFormat::Depth32Float),
        samples: 1,
    };
    let plain = PlainShading::new(&ctx, formats);
    let torus = samples::torus(1.0, 0.35, 12, 8);
    let sphere = samples::icosphere(1);
    let renderers = |mesh, scheme, normals| {
        let opts = RefineOptions::new(scheme, 5).with_normals(normals);
        let refiner = Refiner::new(mesh, &opts).unwrap();
        let plan = refiner.plan();
        let frame = plan.frame(mesh).unwrap();
        PatternRenderer::new(&ctx, plan, &frame, &plain.shading(), &Default::default()).unwrap();
        AdaptiveRenderer::new(
            &ctx,
            plan.surface(),
            &frame,
            &plain.shading(),
            Spacing::FractionalOdd,
        )
        .unwrap();
        ctx.cached_pipelines()
    };
    let first = renderers(&torus, Scheme::Pn, NormalMode::Quadratic);
    assert_eq!(first, 2, "one pattern and one adaptive bundle");
    // Another mesh of the same kind: nothing new.
    assert_eq!(renderers(&sphere, Scheme::Pn, NormalMode::Quadratic), 2);
    // Another normal mode is another variant of both.
    assert_eq!(renderers(&sphere, Scheme::Pn, NormalMode::Real), 4);
    // PNG1 shares the pattern renderer's (its basis is a stencil there), not the adaptive one.
    assert_eq!(renderers(&sphere, Scheme::Png1, NormalMode::Real), 5);

    // Evaluators: two meshes, one compiled kernel pair, both right.
    for mesh in [&torus, &sphere] {
        let refiner = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
        let gpu = gpu_refine(&ctx, &refiner).unwrap();
        assert_same(&refiner.refine(), &gpu, mesh, 0.0, "cached kernels");
    }
    assert_eq!(ctx.cached_pipelines(), 6);
}
