//! PN-AEN: split normals no longer open cracks; with shared normals it is PN.

use glam::{DVec3, Vec3};
use std::collections::HashMap;
use tessella_core::{samples, Mesh, Pattern, RefineOptions, RefinedMesh, Scheme};

/// Largest distance between the two sides' refined points along every edge shared by position,
/// from soup output (each face its own pattern points).
fn seam_gap(mesh: &Mesh, out: &RefinedMesh, level: u32) -> f64 {
    let topo = mesh.topology();
    let np = Pattern::point_count(level) as usize;
    let index = |l: [f64; 3]| {
        let n = level as f64;
        Pattern::index(level, (l[1] * n).round() as u32, (l[2] * n).round() as u32) as usize
    };
    let pid = |v: u32| topo.position_ids[v as usize];
    let mut gap = 0.0f64;
    for f in 0..mesh.face_count() {
        for k in 0..3 {
            let g = topo.neighbors[f][k];
            if g == u32::MAX {
                continue;
            }
            let (tf, tg) = (mesh.triangles()[f], mesh.triangles()[g as usize]);
            let ca = (0..3).find(|&c| pid(tg[c]) == pid(tf[k])).unwrap();
            let cb = (0..3)
                .find(|&c| pid(tg[c]) == pid(tf[(k + 1) % 3]))
                .unwrap();
            for s in 0..=level {
                let t = s as f64 / level as f64;
                let (mut lf, mut lg) = ([0.0; 3], [0.0; 3]);
                lf[k] = 1.0 - t;
                lf[(k + 1) % 3] = t;
                lg[ca] = 1.0 - t;
                lg[cb] = t;
                let pf = out.positions[f * np + index(lf)];
                let pg = out.positions[g as usize * np + index(lg)];
                let d = Vec3::from(pf).as_dvec3() - Vec3::from(pg).as_dvec3();
                gap = gap.max(d.length());
            }
        }
    }
    gap
}

/// An icosphere whose every face has its own three vertices, with normals tilted differently
/// per face: every edge is a hard edge.
fn split_sphere() -> Mesh {
    let base = samples::icosphere(1);
    let (mut p, mut n, mut t) = (vec![], vec![], vec![]);
    for (f, tri) in base.triangles().iter().enumerate() {
        let start = p.len() as u32;
        for (c, &v) in tri.iter().enumerate() {
            let x = base.positions()[v as usize];
            p.push(x);
            let phase = (f * 3 + c) as f64;
            let tilt = DVec3::new(phase.sin(), (1.7 * phase).cos(), (2.3 * phase).sin()) * 0.3;
            n.push(
                (DVec3::from(x.map(f64::from)) + tilt)
                    .normalize()
                    .as_vec3()
                    .into(),
            );
        }
        t.push([start, start + 1, start + 2]);
    }
    Mesh::new(p, Some(n), None, t).unwrap()
}

fn soup(mesh: &Mesh, scheme: Scheme, level: u32) -> RefinedMesh {
    tessella_core::refine(mesh, &RefineOptions::new(scheme, level).with_weld(false)).unwrap()
}

#[test]
fn pn_aen_closes_the_cracks_pn_opens_at_split_normals() {
    let mesh = split_sphere();
    let level = 6;
    let aen = seam_gap(&mesh, &soup(&mesh, Scheme::PnAen, level), level);
    let pn = seam_gap(&mesh, &soup(&mesh, Scheme::Pn, level), level);
    eprintln!("largest seam gap: PN {pn:e}, PN-AEN {aen:e}");
    assert!(aen <= 1e-6, "PN-AEN leaves a gap of {aen:e}");
    assert!(pn > 1e-2, "PN should crack here, gap only {pn:e}");
}

#[test]
fn pn_aen_hard_cube_refines_to_a_closed_manifold() {
    let mesh = samples::hard_cube();
    let level = 5;
    let out = soup(&mesh, Scheme::PnAen, level);
    assert!(seam_gap(&mesh, &out, level) <= 1e-6);
    // Weld the soup by position (to 1e-5) and check the surface is closed, genus 0.
    let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
    let mut positions = vec![];
    let key = |p: [f32; 3]| p.map(|c| (c as f64 * 1e5).round() as i64);
    let remap: Vec<u32> = out
        .positions
        .iter()
        .map(|&p| {
            *ids.entry(key(p)).or_insert_with(|| {
                positions.push(p);
                positions.len() as u32 - 1
            })
        })
        .collect();
    let triangles: Vec<[u32; 3]> = out
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    let welded = Mesh::new(positions, None, None, triangles).unwrap();
    let report = welded.topology().report;
    assert!(report.is_closed_manifold(), "{report:?}");
    assert_eq!(report.euler_characteristic, 2);
}

#[test]
fn pn_aen_equals_pn_with_shared_normals() {
    for mesh in [samples::creature(), samples::torus(1.0, 0.4, 12, 8)] {
        for weld in [true, false] {
            let opts = |s| RefineOptions::new(s, 5).with_weld(weld);
            let a = tessella_core::refine(&mesh, &opts(Scheme::PnAen)).unwrap();
            let b = tessella_core::refine(&mesh, &opts(Scheme::Pn)).unwrap();
            assert_eq!(a.triangles, b.triangles);
            for (x, y) in a.positions.iter().zip(&b.positions) {
                assert!((Vec3::from(*x) - Vec3::from(*y)).length() <= 1e-6);
            }
            for (x, y) in a.normals.iter().zip(&b.normals) {
                assert!((Vec3::from(*x) - Vec3::from(*y)).length() <= 1e-6);
            }
        }
    }
}
