//! Property tests on random valid meshes and random options (proptest):
//! - random open patches (height fields over a jittered grid, random diagonals) and random
//!   closed meshes (octahedra with random radii), with random unit normals or none;
//! - every scheme: finite output, welded counts as the layout formula says (corners + (L-1) per
//!   edge + (L-1)(L-2)/2 per face), watertight exactly where the input is, winding kept;
//! - random options (any scheme, alpha, level, normal mode, weld, size cap): an error or a
//!   valid result, never a panic.
//!
//! Case counts: 64 per mesh property, 256 for random options (`PROPTEST_CASES` overrides).
use proptest::prelude::*;
use std::collections::HashSet;
use tessella_core::{refine, Mesh, Named, NormalMode, RefineOptions, Scheme};

/// A height field over a `w` x `h` grid with jitter, triangulated with random diagonals.
fn patch() -> impl Strategy<Value = Mesh> {
    (2usize..6, 2usize..6).prop_flat_map(|(w, h)| {
        let n = w * h;
        (
            prop::collection::vec((-0.3f32..0.3, -0.3f32..0.3, -1.0f32..1.0), n),
            prop::collection::vec(any::<bool>(), (w - 1) * (h - 1)),
            prop::option::of(prop::collection::vec((-0.5f32..0.5, -0.5f32..0.5), n)),
        )
            .prop_map(move |(jitter, diagonals, tilt)| {
                let positions: Vec<[f32; 3]> = (0..n)
                    .map(|i| {
                        let (x, y) = ((i % w) as f32, (i / w) as f32);
                        let (jx, jy, z) = jitter[i];
                        [x + jx, y + jy, z * 0.5]
                    })
                    .collect();
                let mut triangles = Vec::new();
                for y in 0..h - 1 {
                    for x in 0..w - 1 {
                        let a = (y * w + x) as u32;
                        let (b, c, d) = (a + 1, a + w as u32, a + w as u32 + 1);
                        if diagonals[y * (w - 1) + x] {
                            triangles.extend([[a, b, d], [a, d, c]]);
                        } else {
                            triangles.extend([[a, b, c], [b, d, c]]);
                        }
                    }
                }
                // Random unit normals leaning towards +z (the side the faces face).
                let normals = tilt.map(|t| {
                    t.iter()
                        .map(|&(tx, ty)| {
                            let l = (tx * tx + ty * ty + 1.0).sqrt();
                            [tx / l, ty / l, 1.0 / l]
                        })
                        .collect()
                });
                Mesh::new(positions, normals, None, triangles).unwrap()
            })
    })
}

/// An octahedron with random radii per vertex: closed, consistently wound.
fn closed() -> impl Strategy<Value = Mesh> {
    prop::collection::vec(0.5f32..1.5, 6).prop_map(|r| {
        let dirs = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let positions = dirs
            .iter()
            .zip(&r)
            .map(|(d, r)| d.map(|c: f32| c * r))
            .collect();
        let triangles = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        Mesh::new(positions, None, None, triangles).unwrap()
    })
}

fn schemes() -> impl Strategy<Value = Scheme> {
    prop::sample::select(Scheme::ALL.to_vec()).prop_filter("tags or mid nodes", |s| {
        // Schemes that need extra inputs (mid-edge nodes) are left to their own tests.
        !matches!(s.name(), "quadratic")
    })
}

fn edges(mesh: &Mesh) -> HashSet<(u32, u32)> {
    mesh.triangles()
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect()
}

fn area_vector(positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize].map(f64::from));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        for k in 0..3 {
            sum[k] += n[k];
        }
    }
    sum
}

fn check(mesh: &Mesh, scheme: Scheme, level: u32) -> Result<(), TestCaseError> {
    let out = refine(mesh, &RefineOptions::new(scheme, level)).unwrap();
    let l = level as usize;
    let (v, e, f) = (mesh.vertex_count(), edges(mesh).len(), mesh.face_count());
    prop_assert_eq!(out.triangles.len(), f * l * l);
    prop_assert_eq!(
        out.positions.len(),
        v + e * (l - 1) + f * (l - 1) * (l.max(2) - 2) / 2
    );
    prop_assert!(out.positions.iter().flatten().all(|c| c.is_finite()));
    prop_assert!(out.normals.iter().flatten().all(|c| c.is_finite()));
    let n = out.positions.len() as u32;
    prop_assert!(out.triangles.iter().flatten().all(|&i| i < n));
    // Watertight exactly where the input is; winding stays consistent.
    let refined = Mesh::new(
        out.positions.clone(),
        Some(out.normals.clone()),
        None,
        out.triangles.clone(),
    );
    let before = mesh.topology().report;
    {
        let refined = refined.map_err(|e| TestCaseError::fail(format!("refined mesh: {e}")))?;
        let after = refined.topology().report;
        prop_assert_eq!(after.boundary_edges == 0, before.boundary_edges == 0);
        prop_assert_eq!(after.boundary_edges, before.boundary_edges * l);
        prop_assert_eq!(after.inconsistent_edges, 0);
        prop_assert_eq!(after.non_manifold_edges, 0);
    }
    // Flat refinement tiles each coarse triangle: the oriented area is kept exactly (up to
    // rounding), so no refined triangle turned over.
    if scheme == Scheme::Flat {
        let a = area_vector(mesh.positions(), mesh.triangles());
        let b = area_vector(&out.positions, &out.triangles);
        let scale = a.iter().map(|c| c.abs()).sum::<f64>().max(1e-6);
        for k in 0..3 {
            prop_assert!((a[k] - b[k]).abs() < 1e-4 * scale, "{a:?} vs {b:?}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_open_patches_refine_as_the_layout_says(mesh in patch(), scheme in schemes(), level in 1u32..7) {
        check(&mesh, scheme, level)?;
    }

    #[test]
    fn random_closed_meshes_stay_closed(mesh in closed(), scheme in schemes(), level in 1u32..7) {
        check(&mesh, scheme, level)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_options_give_an_error_or_a_valid_result(
        mesh in prop_oneof![patch(), closed()],
        scheme in prop::sample::select(Scheme::ALL.to_vec()),
        alpha in prop_oneof![Just(f32::NAN), Just(f32::INFINITY), -2.0f32..2.0],
        level in 0u32..12,
        normals in prop::option::of(prop::sample::select(NormalMode::ALL.to_vec())),
        weld in any::<bool>(),
        cap in prop_oneof![Just(u64::MAX), 0u64..100_000],
    ) {
        let mut options = RefineOptions::new(scheme.with_alpha(alpha), level).with_weld(weld);
        options.normals = normals;
        options.max_output_bytes = cap;
        let result = std::panic::catch_unwind(|| refine(&mesh, &options));
        prop_assert!(result.is_ok(), "refine panicked");
        if let Ok(Ok(out)) = result {
            prop_assert!(level > 0);
            prop_assert_eq!(out.triangles.len(), mesh.face_count() * (level * level) as usize);
            prop_assert!(out.positions.iter().flatten().all(|c| c.is_finite()));
            let n = out.positions.len() as u32;
            prop_assert!(out.triangles.iter().flatten().all(|&i| i < n));
        }
    }
}
