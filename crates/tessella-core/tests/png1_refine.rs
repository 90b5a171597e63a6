//! PNG1 through the refiner: convergence of the crease across coarse edges on an icosphere with
//! exact normals (PNG1 has none, PN keeps one), and NaN-free evaluation at every pattern point.

use glam::Vec3;
use std::collections::HashMap;
use tessella_core::{
    samples, Basis, NormalMode, Pattern, RefineOptions, RefinedMesh, Scheme, Stencil,
};

/// Largest dihedral angle (radians, between adjacent refined triangles' normals) across coarse
/// edges and inside coarse faces. Triangles are stored face by face, `level²` per coarse face.
fn dihedrals(out: &RefinedMesh, level: u32) -> (f64, f64) {
    let per_face = (level * level) as usize;
    let normal = |t: usize| {
        let [a, b, c] = out.triangles[t].map(|i| Vec3::from(out.positions[i as usize]).as_dvec3());
        (b - a).cross(c - a).normalize()
    };
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in out.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let (mut across, mut inside) = (0.0f64, 0.0f64);
    for tris in edges.values() {
        assert_eq!(tris.len(), 2, "welded icosphere output is closed");
        let (n0, n1) = (normal(tris[0]), normal(tris[1]));
        let angle = n0.cross(n1).length().atan2(n0.dot(n1));
        if tris[0] / per_face != tris[1] / per_face {
            across = across.max(angle);
        } else {
            inside = inside.max(angle);
        }
    }
    (across, inside)
}

#[test]
fn png1_crease_across_coarse_edges_vanishes_like_inside_faces_pn_keeps_one() {
    // One subdivision: 80 triangles, normals exactly the sphere's.
    let mesh = samples::icosphere(1);
    let mut rows = Vec::new();
    for scheme in [Scheme::Png1, Scheme::Pn] {
        for level in [4u32, 8, 16] {
            let out = tessella_core::refine(&mesh, &RefineOptions::new(scheme, level)).unwrap();
            let (across, inside) = dihedrals(&out, level);
            eprintln!(
                "{:>4} level {level:>2}: across coarse edges {:.4}°, inside faces {:.4}°",
                scheme.name(),
                across.to_degrees(),
                inside.to_degrees()
            );
            rows.push((scheme, level, across, inside));
        }
    }
    let png1: Vec<_> = rows.iter().filter(|r| r.0 == Scheme::Png1).collect();
    let pn: Vec<_> = rows.iter().filter(|r| r.0 == Scheme::Pn).collect();
    for w in png1.windows(2) {
        // Halving the step roughly halves both angles (first order), with no floor.
        assert!(
            w[1].2 < 0.6 * w[0].2,
            "PNG1 across-edge angle does not shrink: {w:?}"
        );
        assert!(
            w[1].3 < 0.6 * w[0].3,
            "PNG1 inside angle does not shrink: {w:?}"
        );
    }
    for r in &png1 {
        assert!(
            r.2 < 1.5 * r.3,
            "PNG1 crease across edges {r:?} exceeds the inside angle"
        );
    }
    // PN: the across-edge angle stops shrinking with the inside angle; at level 16 it is
    // dominated by the residual crease.
    let (pn16, png16) = (pn[2], png1[2]);
    assert!(
        pn16.2 > 2.0 * pn16.3,
        "PN shows no residual crease: {pn16:?}"
    );
    assert!(
        pn16.2 > 0.6 * pn[1].2,
        "PN's crease keeps shrinking: {pn:?}"
    );
    assert!(pn16.2 > 2.0 * png16.2);
}

#[test]
fn png1_weights_and_outputs_are_finite_at_every_pattern_point() {
    let mesh = samples::creature();
    for level in 1..=16u32 {
        let pattern = Pattern::uniform(level);
        let stencil = Stencil::new(&pattern, Basis::Png1);
        assert!(
            stencil.weights.iter().all(|w| w.is_finite()),
            "level {level}"
        );
        for (p, l) in pattern.points.iter().enumerate() {
            let row = stencil.row(p);
            let sum: f32 = row[..21].iter().sum();
            assert!(
                (sum - 1.0).abs() < 1e-5,
                "level {level} point {l:?}: weights sum {sum}"
            );
        }
        for mode in [NormalMode::Quadratic, NormalMode::Real, NormalMode::Linear] {
            let opts = RefineOptions::new(Scheme::Png1, level).with_normals(mode);
            for weld in [true, false] {
                let out = tessella_core::refine(&mesh, &opts.clone().with_weld(weld)).unwrap();
                assert!(out.positions.iter().flatten().all(|x| x.is_finite()));
                for n in &out.normals {
                    let len = Vec3::from(*n).length();
                    assert!(
                        (len - 1.0).abs() < 1e-4,
                        "level {level} {mode:?}: normal {n:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn png1_interpolates_corners_and_smoothed_normals_match_real_ones_at_corners_and_midpoints() {
    let mesh = samples::tetrahedron();
    let level = 2; // points: corners and edge midpoints only
    let soup = |mode| {
        let o = RefineOptions::new(Scheme::Png1, level)
            .with_normals(mode)
            .with_weld(false);
        tessella_core::refine(&mesh, &o).unwrap()
    };
    let (smooth, real) = (soup(NormalMode::Quadratic), soup(NormalMode::Real));
    let pattern = Pattern::uniform(level);
    for f in 0..mesh.face_count() {
        for (p, l) in pattern.points.iter().enumerate() {
            let i = f * pattern.points.len() + p;
            let (a, b) = (Vec3::from(smooth.normals[i]), Vec3::from(real.normals[i]));
            assert!(a.angle_between(b) < 1e-4, "face {f} at {l:?}: {a} vs {b}");
            if let Some(c) = l.iter().position(|&x| x == 1.0) {
                let v = mesh.triangles()[f][c] as usize;
                assert_eq!(smooth.positions[i], mesh.positions()[v]);
                // The surface normal at a corner is the vertex normal.
                let n = Vec3::from(mesh.normals()[v]);
                assert!(b.angle_between(n) < 1e-4, "corner normal {b} vs {n}");
            }
        }
    }
}
