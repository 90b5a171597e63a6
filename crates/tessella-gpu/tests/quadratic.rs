//! Second-order (6-node) triangles on the GPU: the `quadratic` scheme is one more control-net
//! builder, so the compute path evaluates it unchanged. Checked against the CPU evaluator and
//! against the element's own 6-node map, written out here in f64.

mod common;

use common::{assert_same, ctx};
use glam::DVec3;
use std::collections::HashMap;
use tessella_core::refine::Refiner;
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::gpu_refine;

/// The icosphere with one mid-edge node per edge, on the unit sphere (shared by both faces).
fn p2_sphere() -> Mesh {
    let base = samples::icosphere(1);
    let mut pos = base.positions().to_vec();
    let mut at: HashMap<(u32, u32), u32> = HashMap::new();
    let mids: Vec<[u32; 3]> = base
        .triangles()
        .iter()
        .map(|t| {
            std::array::from_fn(|k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *at.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let m = (DVec3::from(pos[a as usize].map(f64::from))
                        + DVec3::from(pos[b as usize].map(f64::from)))
                    .normalize();
                    pos.push(m.as_vec3().into());
                    pos.len() as u32 - 1
                })
            })
        })
        .collect();
    Mesh::new(pos, None, None, base.triangles().to_vec())
        .unwrap()
        .with_mid_nodes(mids)
        .unwrap()
}

/// The 6-node map at `l` (corner weights l(2l − 1), mid-edge weights 4 l_i l_j).
fn map(nodes: &[DVec3; 6], l: [f64; 3]) -> DVec3 {
    let [a, b, c] = l;
    let w = [
        a * (2.0 * a - 1.0),
        b * (2.0 * b - 1.0),
        c * (2.0 * c - 1.0),
        4.0 * a * b,
        4.0 * b * c,
        4.0 * c * a,
    ];
    nodes.iter().zip(w).map(|(x, w)| *x * w).sum()
}

#[test]
fn quadratic_elements_on_the_gpu_equal_the_cpu_and_the_element_map() {
    let mesh = p2_sphere();
    let diagonal = mesh.diagonal() as f64;
    for weld in [true, false] {
        for level in [1, 3, 6] {
            let options = RefineOptions::new(Scheme::Quadratic, level).with_weld(weld);
            let refiner = Refiner::new(&mesh, &options).unwrap();
            let cpu = refiner.refine();
            let gpu = gpu_refine(ctx(), &refiner).unwrap();
            assert_same(
                &cpu,
                &gpu,
                &mesh,
                0.0,
                &format!("quadratic level {level} weld {weld}"),
            );
            // Every GPU vertex lies on its face's 6-node map at its origin.
            let (faces, bary) = refiner.plan().origin();
            for (v, p) in gpu.positions.iter().enumerate() {
                let f = faces[v];
                if f == tessella_core::refine::NO_FACE {
                    continue; // a mid-edge node: a vertex no triangle uses
                }
                let t = mesh.triangles()[f as usize];
                let m = mesh.face_mid_nodes(f as usize).unwrap();
                let nodes = [t[0], t[1], t[2], m[0], m[1], m[2]]
                    .map(|i| DVec3::from(mesh.positions()[i as usize].map(f64::from)));
                let expected = map(&nodes, bary[v].map(f64::from));
                let err = (DVec3::from(p.map(f64::from)) - expected).length();
                assert!(
                    err <= 1e-6 * diagonal,
                    "vertex {v}: {err} off the element map"
                );
            }
        }
    }
}
