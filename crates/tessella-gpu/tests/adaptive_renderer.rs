//! `AdaptiveRenderer`: levels set per frame, parts built once. Its vertex shader's points are
//! read back (`capture`, the same WGSL in a compute pass) and compared with the CPU's adaptive
//! refinement of the same levels, point by point, and every shared coarse-edge point is checked
//! bit for bit between the two faces that draw it.

mod common;

use common::{ctx, PlainShading};
use std::collections::HashMap;
use tessella_core::refine::{canonical, Levels, Plan, Spacing, Surface};
use tessella_core::Named;
use tessella_core::{samples, Mesh, NormalMode, RefineOptions, Scheme};
use tessella_gpu::{AdaptiveRenderer, CapturedTriangles, TargetFormats};

/// The capture reads the points back; the shading only completes the pipeline.
fn plain() -> PlainShading {
    PlainShading::new(
        ctx(),
        TargetFormats {
            color: wgpu::TextureFormat::Rgba8UnormSrgb,
            depth: None,
            samples: 1,
        },
    )
}

/// Per-edge levels in `[1, 1 + spread]`, fractional, different edge by edge.
fn levels(edges: usize, spread: f32, seed: usize) -> Vec<f32> {
    (0..edges)
        .map(|e| 1.0 + ((e * 37 + seed * 13) % 71) as f32 / 70.0 * spread)
        .collect()
}

fn capture(
    mesh: &Mesh,
    options: &RefineOptions,
    spacing: Spacing,
    lv: &[f32],
) -> CapturedTriangles {
    // The surface alone: the options' level and levels play no part.
    let surface = Surface::new(mesh, &options.surface_options()).unwrap();
    let frame = surface.frame(mesh).unwrap();
    let mut r =
        AdaptiveRenderer::new(ctx(), &surface, &frame, &plain().shading(), spacing).unwrap();
    r.set_levels(lv, None).unwrap();
    let c = r.capture().unwrap();
    assert_eq!(c.positions.len() as u64, 3 * r.triangle_count());
    c
}

/// Largest distance between a captured point and the CPU's point of the same face and
/// barycentric coordinates (every captured point must have one; a GPU's division may round the
/// barycentrics differently from the CPU's in the last bit).
fn worst_against(c: &CapturedTriangles, cpu_plan: &Plan, cpu: &tessella_core::RefinedMesh) -> f32 {
    let (faces, bary) = cpu_plan.origin();
    let mut by_face: Vec<Vec<([f32; 3], [f32; 3])>> = vec![Vec::new(); cpu_plan.face_count()];
    for i in 0..faces.len() {
        by_face[faces[i] as usize].push((bary[i], cpu.positions[i]));
    }
    let mut worst = 0.0f32;
    for (i, (&p, &l)) in c.positions.iter().zip(&c.barycentric).enumerate() {
        let f = c.faces[i / 3];
        let (d, q) = by_face[f as usize]
            .iter()
            .map(|(m, q)| (common::dist(l, *m), q))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .expect("the face has points");
        assert!(d < 1e-6, "face {f} point {l:?} is not the CPU's");
        worst = worst.max(common::dist(p, *q));
    }
    worst
}

/// [`worst_against`] the CPU's soup refinement with per-edge levels `lv`, and how many points
/// were compared.
fn against_cpu(mesh: &Mesh, options: &RefineOptions, spacing: Spacing, lv: &[f32]) -> (f32, usize) {
    let cpu_options = options
        .clone()
        .with_spacing(spacing)
        .with_weld(false)
        .with_levels(Levels::PerEdge {
            edges: lv.to_vec().into(),
            faces: None,
        });
    let plan = Plan::new(mesh, &cpu_options).unwrap();
    let out = tessella_core::refine(mesh, &cpu_options).unwrap();
    let c = capture(mesh, options, spacing, lv);
    (worst_against(&c, &plan, &out), c.positions.len())
}

#[test]
fn the_renderer_draws_the_cpus_points() {
    for (mesh, scheme, normals) in [
        (samples::icosphere(1), Scheme::Pn, NormalMode::Quadratic),
        (samples::creature(), Scheme::Pn, NormalMode::Real),
        (samples::icosphere(1), Scheme::Png1, NormalMode::Quadratic),
        (
            samples::torus(1.0, 0.4, 10, 6),
            Scheme::PHONG,
            NormalMode::Linear,
        ),
    ] {
        let options = RefineOptions::new(scheme, 1).with_normals(normals);
        let edges = Plan::new(&mesh, &options).unwrap().topology().edges.len();
        let diag = mesh.diagonal();
        for &spacing in Spacing::ALL {
            for (seed, spread) in [(1, 6.0), (2, 13.0)] {
                let lv = levels(edges, spread, seed);
                let (worst, n) = against_cpu(&mesh, &options, spacing, &lv);
                assert!(n > 1000);
                assert!(
                    worst <= 2e-6 * diag,
                    "{} {spacing:?}: a point {worst} from the CPU's",
                    scheme.name()
                );
            }
        }
    }
}

/// A drawn point's position and normal bits, and its face.
type Drawn = ([u32; 3], [u32; 3], u32);

#[test]
fn shared_edge_points_are_bit_identical_from_both_faces() {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 7)).unwrap();
    let topology = plan.topology();
    let ids = &topology.position_ids;
    let cases = [
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Png1, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
    ];
    for (spacing, (scheme, normals)) in Spacing::ALL
        .iter()
        .copied()
        .flat_map(|s| cases.map(|c| (s, c)))
    {
        let lv = levels(topology.edges.len(), 9.0, 3);
        let options = RefineOptions::new(scheme, 1).with_normals(normals);
        let c = capture(&mesh, &options, spacing, &lv);
        // Positions are shared. Normals too where the normal net's edge entries come from the
        // edge's own data (PN); "real" normals (Du × Dv) and PNG1's net (mid-edge normals from
        // each face's own patch, equal only up to rounding) are each face's own.
        let same_normals = normals != NormalMode::Real && scheme != Scheme::Png1;
        // Edge points by unique edge and canonical parameter: all copies must agree.
        let mut seen: HashMap<(u32, u32), Drawn> = HashMap::new();
        let (mut shared, mut differ) = (0, 0);
        for (i, (&p, &l)) in c.positions.iter().zip(&c.barycentric).enumerate() {
            let f = c.faces[i / 3] as usize;
            let t = mesh.triangles()[f];
            for k in 0..3 {
                let (a, b) = (l[k], l[(k + 1) % 3]);
                if l[(k + 2) % 3] != 0.0 || a == 0.0 || b == 0.0 {
                    continue;
                }
                let w = if canonical::forward(t, k, ids) { a } else { b };
                let e = topology.face_edges[f][k];
                let bits = (
                    p.map(f32::to_bits),
                    c.normals[i].map(f32::to_bits),
                    f as u32,
                );
                match seen.get(&(e, w.to_bits())) {
                    None => {
                        seen.insert((e, w.to_bits()), bits);
                    }
                    Some(&(q, n, g)) if g != f as u32 => {
                        shared += 1;
                        if q != bits.0 || (same_normals && n != bits.1) {
                            differ += 1;
                        }
                    }
                    Some(_) => {}
                }
            }
        }
        let what = format!("{spacing:?} {} {normals:?}", scheme.name());
        assert!(shared > 1000, "{what}: {shared} shared points");
        assert_eq!(
            differ, 0,
            "{what}: {differ} of {shared} shared points differ"
        );
    }
}

#[test]
fn a_deforming_mesh_with_lod_levels_draws_each_frames_cpu_points() {
    use tessella_core::refine::Lod;
    let mesh = samples::creature();
    let options = RefineOptions::new(Scheme::Pn, 1);
    let surface = Surface::new(&mesh, &options.surface_options()).unwrap();
    let mut frame = surface.frame(&mesh).unwrap();
    let mut r = AdaptiveRenderer::new(
        ctx(),
        &surface,
        &frame,
        &plain().shading(),
        Spacing::FractionalOdd,
    )
    .unwrap();
    let lod = Lod::Distance {
        near: 1.0,
        far: 6.0,
        max: 9.0,
        eye: [0.0, 0.5, 3.0],
    };
    for step in 1..3 {
        // The mesh stretches and moves: new nets, and new levels from the new distances.
        let s = 1.0 + 0.3 * step as f32;
        let moved = Mesh::new(
            mesh.positions()
                .iter()
                .map(|p| [p[0] * s, p[1], p[2] + 0.4 * step as f32])
                .collect(),
            Some(mesh.normals().to_vec()),
            None,
            mesh.triangles().to_vec(),
        )
        .unwrap();
        // The frame moves to the new positions and normals: its nets are rebuilt in place.
        surface
            .update(&mut frame, moved.positions(), Some(moved.normals()))
            .unwrap();
        let nets = r.update(&frame).unwrap();
        assert_eq!(
            nets,
            (frame.nets().points.len() + frame.nets().normals.len()) as u64 * 12
        );
        r.set_lod(&frame, &lod).unwrap();
        let c = r.capture().unwrap();
        // The CPU's soup refinement of the moved mesh with the same LOD.
        let cpu_options = options
            .clone()
            .with_spacing(Spacing::FractionalOdd)
            .with_weld(false)
            .with_levels(Levels::Lod(lod.clone()));
        let cpu_plan = Plan::new(&moved, &cpu_options).unwrap();
        let out = tessella_core::refine(&moved, &cpu_options).unwrap();
        assert_eq!(c.positions.len(), 3 * out.triangles.len(), "step {step}");
        let worst = worst_against(&c, &cpu_plan, &out);
        assert!(worst <= 2e-6 * moved.diagonal(), "step {step}: {worst}");
    }
}
