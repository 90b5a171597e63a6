//! Scalar-tagged PN (GMR Appendix B): zero tags give PN; a creased edge stays watertight and
//! sharp by the amount the tags ask for.

use glam::{DVec3, Vec3};
use tessella_core::basis::Basis;
use tessella_core::scheme::{build_nets, NormalMode, PatchNets};
use tessella_core::tags::{EdgeTag, Tags, VertexTag};
use tessella_core::{samples, Mesh, RefineError, RefineOptions, Scheme, TagError};

#[test]
fn zero_tags_equal_pn_to_rounding() {
    for mesh in [
        samples::creature(),
        samples::tetrahedron(),
        samples::hard_cube(),
    ] {
        let scale = mesh.diagonal();
        for tags in [None, Some(Tags::new())] {
            let mut st = RefineOptions::new(Scheme::ScalarTagged, 6);
            if let Some(t) = tags.clone() {
                st = st.with_tags(t);
            }
            let a = tessella_core::refine(&mesh, &st).unwrap();
            let b = tessella_core::refine(&mesh, &RefineOptions::new(Scheme::Pn, 6)).unwrap();
            let worst = a
                .positions
                .iter()
                .zip(&b.positions)
                .map(|(x, y)| (Vec3::from(*x) - Vec3::from(*y)).length())
                .fold(0.0f32, f32::max);
            assert!(worst <= 1e-6 * scale, "ST differs from PN by {worst}");
            for (x, y) in a.normals.iter().zip(&b.normals) {
                assert!((Vec3::from(*x) - Vec3::from(*y)).length() <= 1e-5);
            }
        }
    }
}

/// A flat strip in the z = 0 plane, crease along the x axis (vertices 0, 1, 2 at y = 0), side
/// `+y` (vertices 3, 4, 5) and side `-y` (6, 7, 8). Normals +z.
fn strip() -> Mesh {
    let mut p = vec![];
    for y in [0.0f32, 1.0, -1.0] {
        for x in [0.0f32, 1.0, 2.0] {
            p.push([x, y, 0.0]);
        }
    }
    let t = vec![
        [0, 1, 4],
        [0, 4, 3],
        [1, 2, 5],
        [1, 5, 4],
        [0, 7, 1],
        [0, 6, 7],
        [1, 8, 2],
        [1, 7, 8],
    ];
    Mesh::new(p, Some(vec![[0.0, 0.0, 1.0]; 9]), None, t).unwrap()
}

fn eval(nets: &PatchNets, f: usize, l: [f64; 3]) -> (DVec3, DVec3) {
    let w = Basis::Cubic.weights(l);
    let (mut p, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (k, c) in nets.patch_points(f).iter().enumerate() {
        let c = Vec3::from(*c).as_dvec3();
        p += w.value[k] * c;
        du += w.du[k] * c;
        dv += w.dv[k] * c;
    }
    (p, du.cross(dv).normalize())
}

#[test]
fn creased_edge_is_watertight_and_sharp_by_the_requested_amount() {
    let mesh = strip();
    let sigma = 0.6f32;
    let mut tags = Tags::new();
    for e in [[0, 1], [1, 2]] {
        tags.set_edge(
            &mesh,
            e,
            EdgeTag {
                sharpness: 1.0,
                kappa: 0.0,
            },
        )
        .unwrap();
    }
    let crease = VertexTag {
        sharpness: sigma,
        crease: [0.0, 1.0, 0.0],
        ..Default::default()
    };
    tags.set_vertex(&mesh, 1, crease).unwrap();
    let topo = mesh.topology();
    let nets = build_nets(
        &mesh,
        Some(&topo),
        &Scheme::ScalarTagged,
        NormalMode::Real,
        Some(&tags),
    )
    .unwrap();

    // Expected side normals at vertex 1, from GMR Appendix B directly.
    let n = DVec3::Z;
    let delta = DVec3::Y;
    let s = sigma as f64;
    let x = |side: f64| ((1.0 - s) * n + (n + side * s * delta).normalize()).normalize();
    let (xp, xm) = (x(1.0), x(-1.0));
    let requested = xp.angle_between(xm);
    assert!(requested > 0.5);

    // Face 2 = (1, 2, 5) lies on +y, face 6 = (1, 8, 2) on -y; vertex 1 is corner 0 of both.
    let (_, np) = eval(&nets, 2, [1.0, 0.0, 0.0]);
    let (_, nm) = eval(&nets, 6, [1.0, 0.0, 0.0]);
    assert!(np.angle_between(xp) < 1e-6, "+ side normal {np} vs {xp}");
    assert!(nm.angle_between(xm) < 1e-6, "- side normal {nm} vs {xm}");
    assert!((np.angle_between(nm) - requested).abs() < 1e-6);

    // Along the creased edge 1 -> 2 both sides meet (watertight) at a clear angle.
    for i in 0..=20 {
        let t = i as f64 / 20.0;
        let (pp, np) = eval(&nets, 2, [1.0 - t, t, 0.0]); // face (1, 2, 5)
        let (pm, nm) = eval(&nets, 6, [1.0 - t, 0.0, t]); // face (1, 8, 2)
        assert!((pp - pm).length() < 1e-6, "gap at t = {t}: {pp} vs {pm}");
        if t < 0.5 {
            assert!(np.angle_between(nm) > 0.3 * requested, "t = {t}: no crease");
        }
    }
    // Untagged strip: the same edge is smooth (flat, normals +z on both sides).
    let plain = build_nets(
        &mesh,
        Some(&topo),
        &Scheme::ScalarTagged,
        NormalMode::Real,
        None,
    )
    .unwrap();
    let (_, a) = eval(&plain, 2, [0.5, 0.5, 0.0]);
    let (_, b) = eval(&plain, 6, [0.5, 0.0, 0.5]);
    assert!(a.angle_between(b) < 1e-6);
}

#[test]
fn tension_pulls_edge_points_and_refines_through_options() {
    let mesh = samples::tetrahedron();
    let mut tags = Tags::new();
    let tense = VertexTag {
        tension: 0.5,
        ..Default::default()
    };
    tags.set_vertex(&mesh, 0, tense).unwrap();
    let opts = RefineOptions::new(Scheme::ScalarTagged, 4).with_tags(tags);
    let a = tessella_core::refine(&mesh, &opts).unwrap();
    let b = tessella_core::refine(&mesh, &RefineOptions::new(Scheme::Pn, 4)).unwrap();
    assert_eq!(a.positions.len(), b.positions.len());
    assert!(a.positions.iter().all(|p| p.iter().all(|c| c.is_finite())));
    assert_ne!(a.positions, b.positions, "tension must change the surface");
}

#[test]
fn scalar_tagged_restrictions_are_typed_errors() {
    let mesh = samples::tetrahedron();
    // Three creased edges through vertex 0: more than one crease.
    let mut tags = Tags::new();
    for e in [[0, 1], [0, 2], [0, 3]] {
        tags.set_edge(
            &mesh,
            e,
            EdgeTag {
                sharpness: 1.0,
                kappa: 0.0,
            },
        )
        .unwrap();
    }
    let err = tessella_core::refine(
        &mesh,
        &RefineOptions::new(Scheme::ScalarTagged, 2).with_tags(tags.clone()),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            RefineError::Tags(TagError::TooManyCreases {
                vertex: 0,
                count: 3
            })
        ),
        "{err}"
    );
    // PNG1 takes any number of sharp edges.
    assert!(
        tessella_core::refine(&mesh, &RefineOptions::new(Scheme::Png1, 2).with_tags(tags)).is_ok()
    );

    // Three vertices of one triangle with crease directions.
    let mut tags = Tags::new();
    for v in 0..3 {
        let tag = VertexTag {
            sharpness: 0.5,
            crease: [1.0, 0.0, 0.0],
            ..Default::default()
        };
        tags.set_vertex(&mesh, v, tag).unwrap();
    }
    let err = tessella_core::refine(
        &mesh,
        &RefineOptions::new(Scheme::ScalarTagged, 2).with_tags(tags),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            RefineError::Tags(TagError::TooManyCreasedVertices { count: 3, .. })
        ),
        "{err}"
    );
    assert!(err.to_string().contains("at most 2"));
}
