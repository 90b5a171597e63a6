//! The caller's shading: what tessella-gpu's renderers hand it (`TessellaVertex`), how its
//! pipelines are cached, and what a broken one gives.
mod common;

use common::{ctx, pixels, PlainShading, FORMATS, SIZE};
use std::collections::BTreeSet;
use tessella_core::refine::{Plan, Spacing};
use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{AdaptiveRenderer, GpuContext, GpuError, PatternRenderer, Shading, UNIFORM};

/// A shading that writes what it was handed: red `face + 1` (0 for `TESSELLA_NO_FACE`),
/// green and blue the barycentric `l.x`, `l.y` of the coarse triangle, alpha 255 · `scale`
/// from its own uniform in group 1, so the caller's binding is read too.
const IDS_WGSL: &str = "
@group(1) @binding(0) var<uniform> scale: vec4<f32>;
struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) face: u32,
    @location(1) l: vec3<f32>,
}
fn shade_vertex(v: TessellaVertex) -> VsOut {
    let face = select(v.face + 1u, 0u, v.face == TESSELLA_NO_FACE);
    return VsOut(vec4<f32>(0.8 * v.position.xy, 0.5, 1.0), face, v.l);
}
@fragment fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(f32(in.face) / 255.0, in.l.x, in.l.y, scale.x);
}";

struct IdShading {
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
}

impl IdShading {
    fn new(ctx: &GpuContext) -> IdShading {
        let stage = wgpu::ShaderStages::FRAGMENT;
        let layout = ctx.buffer_layout("ids", &[(stage, UNIFORM)]);
        let scale = ctx.buffer_init(
            "scale",
            bytemuck::cast_slice(&[1.0f32, 0.0, 0.0, 0.0]),
            wgpu::BufferUsages::UNIFORM,
        );
        let group = ctx.buffer_group("ids", &layout, &[&scale]);
        IdShading { layout, group }
    }

    fn shading(&self) -> Shading<'_> {
        Shading {
            wgsl: IDS_WGSL,
            layout: &self.layout,
            formats: FORMATS,
        }
    }
}

/// Every covered pixel names a face of the mesh and a barycentric point inside it, and many
/// faces are seen: the vertex stage hands the shading each instance's own coarse triangle,
/// from the pattern renderer and the adaptive renderer alike, and the shading's own binding
/// (alpha) is read.
#[test]
fn the_shading_gets_each_points_face_and_barycentric_point() {
    let ctx = ctx();
    let mesh = samples::icosphere(1);
    let faces = mesh.face_count();
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let ids = IdShading::new(ctx);
    let pattern =
        PatternRenderer::new(ctx, &plan, &frame, &ids.shading(), &Default::default()).unwrap();
    let mut adaptive = AdaptiveRenderer::new(
        ctx,
        plan.surface(),
        &frame,
        &ids.shading(),
        Spacing::FractionalOdd,
    )
    .unwrap();
    adaptive
        .set_levels(&vec![3.5; plan.topology().edges.len()], None)
        .unwrap();
    let drawn: [Vec<[u8; 4]>; 3] = [
        pixels(ctx, |pass| pattern.draw(pass, &ids.group)),
        pixels(ctx, |pass| pattern.draw_unrolled(pass, &ids.group)),
        pixels(ctx, |pass| adaptive.draw(pass, &ids.group)),
    ];
    // An already refined vertex buffer: no face (red 0), the same coverage.
    let refined = tessella_core::Refiner::new(&mesh, plan.options())
        .unwrap()
        .refine();
    let vertices: Vec<f32> = refined
        .positions
        .iter()
        .zip(&refined.normals)
        .flat_map(|(p, n)| p.iter().chain(n).copied())
        .collect();
    let indices: Vec<u32> = refined.triangles.iter().flatten().copied().collect();
    let vb = ctx.buffer_init(
        "refined",
        bytemuck::cast_slice(&vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let ib = ctx.buffer_init(
        "refined indices",
        bytemuck::cast_slice(&indices),
        wgpu::BufferUsages::INDEX,
    );
    let fixed = pixels(ctx, |pass| {
        pattern.draw_refined(
            pass,
            &ids.group,
            vb.slice(..),
            ib.slice(..),
            wgpu::IndexFormat::Uint32,
            indices.len() as u32,
        )
    });
    let covered = fixed.iter().filter(|p| p[3] != 0).count();
    assert!(covered > (SIZE * SIZE / 3) as usize, "refined: {covered}");
    assert!(
        fixed.iter().all(|p| p[3] == 0 || p[0] == 0),
        "refined: a face"
    );
    for (what, picture) in ["pattern", "unrolled", "adaptive"].iter().zip(&drawn) {
        let covered: Vec<&[u8; 4]> = picture.iter().filter(|p| p[3] != 0).collect();
        // The unit sphere, scaled by 0.8, covers about half the square.
        assert!(
            covered.len() > (SIZE * SIZE / 3) as usize,
            "{what}: {}",
            covered.len()
        );
        let mut seen = BTreeSet::new();
        for p in covered {
            assert_eq!(p[3], 255, "{what}: the shading's uniform");
            assert!(
                (1..=faces).contains(&(p[0] as usize)),
                "{what}: face {}",
                p[0]
            );
            // l.x + l.y ≤ 1 (up to the bytes' rounding).
            assert!(p[1] as u32 + p[2] as u32 <= 257, "{what}: {p:?}");
            seen.insert(p[0]);
        }
        // The icosphere's 80 faces: about half face the camera along z.
        assert!(seen.len() >= 20, "{what}: {} faces seen", seen.len());
    }
    // The indexed and the unrolled draws cover the same pixels with the same faces.
    let faces_of = |p: &Vec<[u8; 4]>| p.iter().map(|q| q[0]).collect::<Vec<_>>();
    let same = faces_of(&drawn[0])
        .iter()
        .zip(faces_of(&drawn[1]))
        .filter(|(a, b)| **a == *b)
        .count();
    assert!(same as f64 > 0.98 * (SIZE * SIZE) as f64, "{same}");
    assert!(ctx.check().is_ok());
}

/// Pipelines are cached by the shading's WGSL: another layout object with the same entries
/// reuses them (and its bind group draws), other WGSL compiles its own.
#[test]
fn pipelines_are_cached_by_the_shadings_wgsl() {
    let ctx = GpuContext::from_device(ctx().device.clone(), ctx().queue.clone());
    let mesh = samples::icosphere(0);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let first = PlainShading::new(&ctx, FORMATS);
    PatternRenderer::new(&ctx, &plan, &frame, &first.shading(), &Default::default()).unwrap();
    assert_eq!(ctx.cached_pipelines(), 1);
    let again = PlainShading::new(&ctx, FORMATS);
    let renderer =
        PatternRenderer::new(&ctx, &plan, &frame, &again.shading(), &Default::default()).unwrap();
    assert_eq!(
        ctx.cached_pipelines(),
        1,
        "the same WGSL: the same pipelines"
    );
    let drawn = pixels(&ctx, |pass| renderer.draw(pass, &again.group));
    assert!(drawn.iter().any(|p| p[3] == 255));
    let ids = IdShading::new(&ctx);
    PatternRenderer::new(&ctx, &plan, &frame, &ids.shading(), &Default::default()).unwrap();
    assert_eq!(
        ctx.cached_pipelines(),
        2,
        "other WGSL: pipelines of its own"
    );
    assert!(ctx.check().is_ok());
}

/// A shading whose WGSL does not compile, or that leaves out `shade_vertex`, is an error from
/// the renderer's constructor, and the device goes on working.
#[test]
fn a_broken_shading_is_an_error_not_a_panic() {
    let ctx = ctx().with_own_errors();
    let mesh = samples::icosphere(0);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let plain = PlainShading::new(&ctx, FORMATS);
    for wgsl in [
        "fn shade_vertex(v: TessellaVertex) -> VsOut { this is not WGSL }",
        "@fragment fn fs_main() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }",
    ] {
        let broken = Shading {
            wgsl,
            ..plain.shading()
        };
        let err = PatternRenderer::new(&ctx, &plan, &frame, &broken, &Default::default())
            .map(|_| ())
            .unwrap_err();
        assert!(matches!(err, GpuError::Validation(_)), "{err:?}");
        let err = AdaptiveRenderer::new(
            &ctx,
            plan.surface(),
            &frame,
            &broken,
            Spacing::FractionalOdd,
        )
        .map(|_| ())
        .unwrap_err();
        assert!(matches!(err, GpuError::Validation(_)), "{err:?}");
    }
    PatternRenderer::new(&ctx, &plan, &frame, &plain.shading(), &Default::default()).unwrap();
    assert!(ctx.check().is_ok());
}
