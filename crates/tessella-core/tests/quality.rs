//! The quality report tells the schemes apart on what they promise: PNG1 has no normal jump,
//! PN-AEN no gap at split normals, flat no distance from the coarse mesh.

use glam::{DVec3, Vec3};
use tessella_core::{quality, samples, Mesh, RefineOptions, Scheme};

/// Every face its own vertices, normals tilted per face: every edge is a hard edge.
fn split_sphere() -> Mesh {
    let base = samples::icosphere(1);
    let (mut p, mut n, mut t) = (vec![], vec![], vec![]);
    for (f, tri) in base.triangles().iter().enumerate() {
        let start = p.len() as u32;
        for (c, &v) in tri.iter().enumerate() {
            let x = base.positions()[v as usize];
            p.push(x);
            let phase = (f * 3 + c) as f64;
            let tilt = DVec3::new(phase.cos(), (1.3 * phase).sin(), (0.7 * phase).cos()) * 0.3;
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

#[test]
fn normal_jump_separates_png1_from_pn() {
    let mesh = samples::creature();
    let opts = RefineOptions::new(Scheme::Pn, 4);
    let r = quality::compare(&mesh, &opts, &[Scheme::Pn, Scheme::Png1, Scheme::Flat]).unwrap();
    let (pn, png1, flat) = (&r[0], &r[1], &r[2]);
    assert_eq!(pn.edges_checked, mesh.topology().report.edges);
    assert_eq!(png1.scheme, "png1");
    // PNG1's nets are stored in f32: G1 up to that rounding.
    assert!(png1.normal_jump_max_deg < 0.05, "{png1:?}");
    assert!(pn.normal_jump_max_deg > 2.0, "{pn:?}");
    assert!(pn.normal_jump_mean_deg > 10.0 * png1.normal_jump_mean_deg);
    // Flat: the dihedral angles of the coarse mesh itself.
    assert!(flat.normal_jump_max_deg > pn.normal_jump_max_deg);
    for x in &r {
        assert!(x.gap_max_relative < 1e-6, "{x:?}");
    }
    assert!(flat.distance_max_relative < 1e-6);
    assert!(pn.distance_max > 0.0 && png1.distance_max > 0.0);
    let json = serde_json::to_string(png1).unwrap();
    assert!(json.contains("\"normal_jump_max_deg\""));
}

#[test]
fn gap_separates_pn_aen_from_pn_at_split_normals() {
    let mesh = split_sphere();
    let opts = RefineOptions::new(Scheme::Pn, 3);
    let r = quality::compare(&mesh, &opts, &[Scheme::Pn, Scheme::PnAen]).unwrap();
    assert!(r[0].gap_max_relative > 1e-2, "{:?}", r[0]);
    assert!(r[1].gap_max_relative < 1e-6, "{:?}", r[1]);
}

#[test]
fn distance_matches_the_refined_output() {
    // The report's largest distance (f64 on the nets) equals the refiner's output measured
    // against the flat triangles at the same pattern points.
    let mesh = samples::tetrahedron();
    let level = 6;
    for scheme in [Scheme::Pn, Scheme::Png1, Scheme::PHONG] {
        let opts = RefineOptions::new(scheme, level).with_weld(false);
        let out = tessella_core::refine(&mesh, &opts).unwrap();
        let pattern = tessella_core::Pattern::uniform(level);
        let np = pattern.points.len();
        let mut worst = 0.0f64;
        for f in 0..mesh.face_count() {
            let c = mesh.corner_positions(f).map(|v| v.as_dvec3());
            for (p, l) in pattern.points.iter().enumerate() {
                let flat = l[0] * c[0] + l[1] * c[1] + l[2] * c[2];
                let got = Vec3::from(out.positions[f * np + p]).as_dvec3();
                worst = worst.max((got - flat).length());
            }
        }
        let r = quality::report(&mesh, &opts).unwrap();
        assert!(
            (r.distance_max - worst).abs() < 1e-5,
            "{scheme:?}: {} vs {worst}",
            r.distance_max
        );
        assert!(
            worst > 0.05,
            "{scheme:?} should bulge out of the tetrahedron"
        );
    }
}

#[test]
fn bad_options_are_errors() {
    let mesh = samples::tetrahedron();
    assert!(quality::report(&mesh, &RefineOptions::new(Scheme::Pn, 0)).is_err());
    let bad = RefineOptions::new(Scheme::Phong { alpha: f32::NAN }, 2);
    assert!(quality::report(&mesh, &bad).is_err());
}
