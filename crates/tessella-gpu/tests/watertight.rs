//! Bitwise watertight soup on the GPU: a vertex on a shared coarse edge (or corner) has the same
//! bits in both faces' blocks, because the compute path evaluates edge points from the edge's
//! own control points in canonical order (`canonical_edge` in eval.wgsl). Without it the two
//! faces sum their whole stencil rows in their own corner order and differ in the last bits.

mod common;

use common::ctx;
use std::collections::HashMap;
use tessella_core::pattern::{Pattern, PointClass};
use tessella_core::Named;
use tessella_core::{samples, Mesh, NormalMode, RefineOptions, RefinedMesh, Refiner, Scheme};
use tessella_gpu::gpu_refine;

/// Pairs of soup vertex indices that are the same point of the surface: the two copies of every
/// point inside a shared coarse edge, and every copy of a corner against its first copy.
fn twins(mesh: &Mesh, level: u32) -> Vec<(usize, usize)> {
    let pattern = Pattern::uniform(level);
    let per_face = pattern.points.len();
    let mut edge_point = HashMap::new();
    let mut corner_point = [0; 3];
    for (p, class) in pattern.classes.iter().enumerate() {
        match *class {
            PointClass::Edge { edge, step } => {
                edge_point.insert((edge as usize, step), p);
            }
            PointClass::Corner { corner } => corner_point[corner as usize] = p,
            PointClass::Interior { .. } => {}
        }
    }
    let tris = mesh.triangles();
    let mut half_edges = HashMap::new();
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            half_edges.insert((t[k], t[(k + 1) % 3]), (f, k));
        }
    }
    let mut pairs = Vec::new();
    let mut first_copy = HashMap::new();
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let first = *first_copy
                .entry(a)
                .or_insert(f * per_face + corner_point[k]);
            pairs.push((first, f * per_face + corner_point[k]));
            let Some(&(g, kg)) = half_edges.get(&(b, a)) else {
                continue;
            };
            if g < f {
                continue;
            }
            for s in 1..level {
                let p = edge_point[&(k, s)];
                let q = edge_point[&(kg, level - s)];
                pairs.push((f * per_face + p, g * per_face + q));
            }
        }
    }
    pairs
}

/// Twin pairs whose positions (or normals) differ in any bit.
fn differing(out: &RefinedMesh, pairs: &[(usize, usize)]) -> (usize, usize) {
    let bits = |v: [f32; 3]| v.map(f32::to_bits);
    let positions = pairs
        .iter()
        .filter(|&&(a, b)| bits(out.positions[a]) != bits(out.positions[b]))
        .count();
    let normals = pairs
        .iter()
        .filter(|&&(a, b)| bits(out.normals[a]) != bits(out.normals[b]))
        .count();
    (positions, normals)
}

#[test]
fn gpu_soup_edge_vertices_equal_their_twins_bit_for_bit() {
    let mesh = samples::icosphere(1);
    assert_eq!(mesh.face_count(), 80);
    let cases = [
        (Scheme::Pn, 7, None),
        (Scheme::Pn, 7, Some(NormalMode::Linear)),
        (Scheme::Pn, 16, None),
        (Scheme::Png1, 7, None),
        (Scheme::PHONG, 5, None),
        (Scheme::Flat, 3, None),
        (Scheme::PnAen, 7, None),
    ];
    for (scheme, level, mode) in cases {
        let mut options = RefineOptions::new(scheme, level).with_weld(false);
        options.normals = mode;
        let refiner = Refiner::new(&mesh, &options).unwrap();
        let gpu = gpu_refine(ctx(), &refiner).unwrap();
        let pairs = twins(&mesh, level);
        // 120 shared edges with level - 1 points each, 240 corner copies.
        assert_eq!(pairs.len(), 120 * (level as usize - 1) + 240);
        let (positions, normals) = differing(&gpu, &pairs);
        let what = format!("{} level {level} {mode:?}", scheme.name());
        assert_eq!(positions, 0, "{what}: {positions} twin positions differ");
        // Net normals are canonical too. PNG1's smoothed normal net is built per face (its
        // edge entries are not shared), so there the GPU may differ only where the CPU does.
        let (_, cpu_normals) = differing(&refiner.refine(), &pairs);
        if scheme == Scheme::Png1 {
            assert!(
                normals <= cpu_normals,
                "{what}: {normals} vs cpu {cpu_normals}"
            );
        } else {
            assert_eq!(normals, 0, "{what}: {normals} twin normals differ");
        }
    }
}

/// The twin pairs of an adaptive plan's soup: each face's block starts at its face offset; a
/// point at step `s` of a shared edge (from the face's corner `k`) is step `n − s` on the other
/// face, whose tile has the same `n − 1` points on that edge.
fn adaptive_twins(mesh: &Mesh, plan: &tessella_core::refine::Plan) -> Vec<(usize, usize)> {
    let tiling = plan.tiling().expect("an adaptive plan");
    let tris = mesh.triangles();
    let mut half_edges = HashMap::new();
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            half_edges.insert((t[k], t[(k + 1) % 3]), (f, k));
        }
    }
    let slot = |f: usize, p: u32| tiling.face_offset[f] as usize + p as usize;
    let mut pairs = Vec::new();
    let mut first_copy = HashMap::new();
    for (f, t) in tris.iter().enumerate() {
        let tile = tiling.tile(f);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let here = slot(f, tile.corners[k]);
            let first = *first_copy.entry(a).or_insert(here);
            pairs.push((first, here));
            let Some(&(g, kg)) = half_edges.get(&(b, a)) else {
                continue;
            };
            if g < f {
                continue;
            }
            let (mine, theirs) = (&tile.edges[k], &tiling.tile(g).edges[kg]);
            assert_eq!(
                mine.len(),
                theirs.len(),
                "faces {f} and {g} disagree on an edge"
            );
            let m = mine.len();
            for s in 0..m {
                pairs.push((slot(f, mine[s]), slot(g, theirs[m - 1 - s])));
            }
        }
    }
    pairs
}

#[test]
fn gpu_adaptive_soup_edge_vertices_equal_their_twins_bit_for_bit() {
    use std::sync::Arc;
    use tessella_core::refine::{Levels, Spacing};
    let mesh = samples::icosphere(1);
    let plan = tessella_core::refine::Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 1)).unwrap();
    let edges = plan.topology().edges.len();
    for &spacing in Spacing::ALL {
        // Per-edge levels from 1 to 9 (integers for the grid, whose fractions geomorph).
        let levels: Arc<[f32]> = (0..edges)
            .map(|e| {
                let x = 1.0 + (e * 37 % 81) as f32 / 10.0;
                if spacing == Spacing::Grid {
                    x.round()
                } else {
                    x
                }
            })
            .collect();
        for scheme in [Scheme::Pn, Scheme::Png1] {
            let options = RefineOptions::new(scheme, 1)
                .with_weld(false)
                .with_spacing(spacing)
                .with_levels(Levels::PerEdge {
                    edges: levels.clone(),
                    faces: None,
                });
            let refiner = Refiner::new(&mesh, &options).unwrap();
            let gpu = gpu_refine(ctx(), &refiner).unwrap();
            let pairs = adaptive_twins(&mesh, refiner.plan());
            assert!(pairs.len() > 240 + 120, "{spacing}: {} pairs", pairs.len());
            let (positions, normals) = differing(&gpu, &pairs);
            let what = format!("{} {spacing}", scheme.name());
            assert_eq!(positions, 0, "{what}: {positions} twin positions differ");
            let (_, cpu_normals) = differing(&refiner.refine(), &pairs);
            if scheme == Scheme::Png1 {
                assert!(
                    normals <= cpu_normals,
                    "{what}: {normals} vs cpu {cpu_normals}"
                );
            } else {
                assert_eq!(normals, 0, "{what}: {normals} twin normals differ");
            }
        }
    }
}
