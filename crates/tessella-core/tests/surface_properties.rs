//! Properties of the refined surface that hold whatever the exact formulas: welded output of a
//! closed mesh is a closed manifold of the same Euler characteristic; PN and Phong keep a plane
//! flat; with a sphere's normals they come closer to the sphere than the flat triangles; UVs are
//! interpolated linearly.

mod reference;

use glam::DVec3;
use reference::corpus::{closed_meshes, perturbed_sphere, planar_grid, Lcg};
use reference::{angle, closed_manifold, d3, diagonal, occurrences, undirected_edges};
use tessella_core::{refine, samples, Mesh, NormalMode, Pattern, RefineOptions, Scheme};

/// Levels the 320-face creature runs at (the smaller meshes run at every level 1..=32).
const CREATURE_LEVELS: [u32; 8] = [1, 2, 3, 4, 5, 8, 16, 32];

#[test]
fn welded_output_is_a_closed_manifold_with_the_input_euler_characteristic() {
    for (name, mesh, expected_euler) in closed_meshes() {
        // The input itself, by vertex index (these meshes have one normal per position).
        let input = closed_manifold(mesh.vertex_count(), mesh.triangles())
            .unwrap_or_else(|e| panic!("{name}: input is not a closed manifold: {e}"));
        assert_eq!(
            input.euler, expected_euler,
            "{name}: input Euler characteristic"
        );
        let (v, e, f) = (
            mesh.vertex_count(),
            undirected_edges(mesh.triangles()),
            mesh.face_count(),
        );
        assert_eq!(e, input.edges);
        let levels: Vec<u32> = if name == "creature" {
            CREATURE_LEVELS.to_vec()
        } else {
            (1..=32).collect()
        };
        for level in levels {
            let n = level as usize;
            let out = refine(&mesh, &RefineOptions::new(Scheme::Pn, level)).unwrap();
            let what = format!("{name} at level {level}");
            // V + E(N-1) + F(N-1)(N-2)/2 vertices, F·N² triangles.
            let vertices = v + e * (n - 1) + f * (n - 1) * n.saturating_sub(2) / 2;
            assert_eq!(out.positions.len(), vertices, "{what}: vertex count");
            assert_eq!(out.triangles.len(), f * n * n, "{what}: triangle count");
            let m = closed_manifold(out.positions.len(), &out.triangles)
                .unwrap_or_else(|err| panic!("{what}: output is not a closed manifold: {err}"));
            assert_eq!(m.euler, input.euler, "{what}: Euler characteristic {m:?}");
            // Every small edge is either part of a coarse edge (N per coarse edge) or inside a
            // coarse face (3 N (N-1) / 2 per face).
            assert_eq!(
                m.edges,
                e * n + f * 3 * n * (n - 1) / 2,
                "{what}: edge count"
            );
        }
    }
}

#[test]
fn soup_output_has_one_copy_of_the_pattern_per_face() {
    // Soup output: F (N+1)(N+2)/2 vertices, F N² triangles, and no vertex shared between faces.
    let mesh = samples::icosphere(1);
    for level in [1, 2, 3, 7, 16] {
        let n = level as usize;
        let out = refine(
            &mesh,
            &RefineOptions::new(Scheme::Pn, level).with_weld(false),
        )
        .unwrap();
        let per_face = (n + 1) * (n + 2) / 2;
        assert_eq!(out.positions.len(), mesh.face_count() * per_face);
        assert_eq!(out.triangles.len(), mesh.face_count() * n * n);
        let mut owner = vec![usize::MAX; out.positions.len()];
        for occ in occurrences(&out, mesh.face_count(), &Pattern::uniform(level)) {
            assert!(
                owner[occ.vertex] == usize::MAX || owner[occ.vertex] == occ.face,
                "level {level}: vertex {} is shared by faces {} and {}",
                occ.vertex,
                owner[occ.vertex],
                occ.face
            );
            owner[occ.vertex] = occ.face;
        }
    }
}

/// Checks that every output vertex lies on the plane `dot(normal, p) = offset` within `tol`, that
/// every output normal is `normal` within `angle_tol` rad, and that the points are the flat
/// triangles' own (a planar PN or Phong patch with the plane's normals is the flat triangle).
fn assert_stays_planar(
    mesh: &Mesh,
    plane: DVec3,
    offset: f64,
    tol: f64,
    angle_tol: f64,
    what: &str,
) {
    let schemes = [
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
        (Scheme::Phong { alpha: 0.75 }, NormalMode::Linear),
        (Scheme::Phong { alpha: 1.0 }, NormalMode::Real),
    ];
    for (scheme, normals) in schemes {
        for level in 1..=32 {
            let pattern = Pattern::uniform(level);
            for weld in [true, false] {
                let options = RefineOptions::new(scheme, level)
                    .with_normals(normals)
                    .with_weld(weld);
                let out = refine(mesh, &options).unwrap();
                let case = format!("{what}: {scheme:?} {normals:?} level {level} weld {weld}");
                for (p, n) in out.positions.iter().zip(&out.normals) {
                    let off = plane.dot(d3(*p)) - offset;
                    assert!(off.abs() <= tol, "{case}: {p:?} is {off:e} off the plane");
                    let a = angle(d3(*n), plane);
                    assert!(
                        a <= angle_tol,
                        "{case}: normal {n:?} is {a:e} rad off the plane's"
                    );
                }
                for occ in occurrences(&out, mesh.face_count(), &pattern) {
                    let l = pattern.points[occ.point];
                    let t = mesh.triangles()[occ.face].map(|v| d3(mesh.positions()[v as usize]));
                    let flat = l[0] * t[0] + l[1] * t[1] + l[2] * t[2];
                    let err = (d3(out.positions[occ.vertex]) - flat).length();
                    assert!(
                        err <= tol,
                        "{case}: {err:e} from the flat triangle at {l:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn pn_and_phong_keep_a_plane_flat() {
    // A 4×3 grid in z = 0 with jittered inner points, every normal (0, 0, 1).
    let mesh = planar_grid(4, 3, 5);
    assert_stays_planar(&mesh, DVec3::Z, 0.0, 1e-6, 1e-6, "grid in z = 0");
}

#[test]
fn pn_and_phong_keep_a_tilted_plane_flat() {
    // The same grid rotated off every axis, with the rotated normal: coplanar up to the f32
    // rounding of the rotated corners, so the tolerance is relative to the grid's size.
    let grid = planar_grid(4, 3, 9);
    let rotation = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.5, 0.7);
    let normal = rotation * DVec3::Z;
    let shift = DVec3::new(0.5, -2.0, 1.5);
    let f3 = |p: DVec3| [p.x as f32, p.y as f32, p.z as f32];
    let positions: Vec<[f32; 3]> = grid
        .positions()
        .iter()
        .map(|&p| f3(rotation * d3(p) + shift))
        .collect();
    let mesh = Mesh::new(
        positions,
        Some(vec![f3(normal); grid.vertex_count()]),
        None,
        grid.triangles().to_vec(),
    )
    .unwrap();
    let offset = normal.dot(shift);
    let tol = 1e-6 * diagonal(&mesh);
    // Real normals are Du × Dv of the f32 patch, whose corners are off the exact plane by f32
    // rounding (about 1e-7 of their size), so they tilt by a few 1e-6 rad.
    assert_stays_planar(&mesh, normal, offset, tol, 1e-5, "tilted grid");
}

/// `max |‖p‖ - 1|` over the output's vertices, in f64.
fn sphere_deviation(mesh: &Mesh, scheme: Scheme, level: u32) -> f64 {
    let out = refine(mesh, &RefineOptions::new(scheme, level)).unwrap();
    out.positions
        .iter()
        .map(|&p| (d3(p).length() - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn pn_and_phong_come_closer_to_the_sphere_than_flat() {
    for subdivisions in [0, 1] {
        let mesh = samples::icosphere(subdivisions);
        for level in [4, 8, 16] {
            let flat = sphere_deviation(&mesh, Scheme::Flat, level);
            let phong = sphere_deviation(&mesh, Scheme::PHONG, level);
            let pn = sphere_deviation(&mesh, Scheme::Pn, level);
            println!(
                "icosphere({subdivisions}) level {level}: max |‖p‖-1| flat {flat:.3e}, \
                 Phong {phong:.3e}, PN {pn:.3e}"
            );
            assert!(pn < flat, "PN {pn} is not closer than flat {flat}");
            assert!(phong < flat, "Phong {phong} is not closer than flat {flat}");
        }
    }
}

#[test]
fn uvs_are_interpolated_linearly() {
    // The perturbed sphere with a random UV per vertex (shared by every face using the vertex,
    // so the welded edges have one UV from either face).
    let base = perturbed_sphere(21);
    let mut rng = Lcg::new(4);
    let uvs: Vec<[f32; 2]> = (0..base.vertex_count())
        .map(|_| [rng.range(-1.0, 2.0) as f32, rng.range(0.0, 1.0) as f32])
        .collect();
    let mesh = Mesh::new(
        base.positions().to_vec(),
        Some(base.normals().to_vec()),
        Some(uvs.clone()),
        base.triangles().to_vec(),
    )
    .unwrap();
    for level in [1, 2, 3, 4, 5, 8, 13, 32] {
        let pattern = Pattern::uniform(level);
        for weld in [true, false] {
            let out = refine(
                &mesh,
                &RefineOptions::new(Scheme::Pn, level).with_weld(weld),
            )
            .unwrap();
            let out_uvs = out.uvs.as_ref().expect("a mesh with UVs refines with UVs");
            assert_eq!(out_uvs.len(), out.positions.len());
            for occ in occurrences(&out, mesh.face_count(), &pattern) {
                let l = pattern.points[occ.point];
                let corner = mesh.triangles()[occ.face].map(|v| uvs[v as usize]);
                let got = out_uvs[occ.vertex];
                for axis in 0..2 {
                    let expected: f64 = (0..3).map(|c| l[c] * corner[c][axis] as f64).sum();
                    let err = (got[axis] as f64 - expected).abs();
                    assert!(
                        err <= 1e-6,
                        "level {level} weld {weld}: face {} at {l:?}: uv {got:?}, expected \
                         component {axis} = {expected}",
                        occ.face
                    );
                }
                if let Some(c) = l.iter().position(|&x| x == 1.0) {
                    assert_eq!(got, corner[c], "a coarse corner keeps its UV exactly");
                }
            }
        }
    }
    // And no UVs in, no UVs out.
    let out = refine(&base, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    assert!(out.uvs.is_none());
}
