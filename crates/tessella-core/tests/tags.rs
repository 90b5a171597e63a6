//! Where tags come from (split normals, crease angle, the validated setters) and how bad tags
//! are refused. Tags from files are tested in `tessella-io`.

use tessella_core::mesh::topology::position_ids;
use tessella_core::tags::{EdgeTag, TagBuilder, TagError, Tags, VertexTag};
use tessella_core::{samples, Mesh};

#[test]
fn split_normals_and_crease_angle_find_the_cube_edges() {
    let cube = samples::hard_cube();
    let split = Tags::from_split_normals(&cube);
    assert_eq!(
        split.edge_count(),
        12,
        "the cube's 12 edges, not the face diagonals"
    );
    // Corners carry three creases: no single crease direction fits them.
    assert_eq!(split.vertex_count(), 0);
    assert_eq!(
        Tags::from_crease_angle(&cube, 30.0).unwrap().edge_count(),
        12
    );
    assert_eq!(
        Tags::from_crease_angle(&cube, 100.0).unwrap().edge_count(),
        0
    );
    assert!(Tags::from_split_normals(&samples::icosphere(1)).is_empty());
    for bad in [f32::NAN, -1.0, 200.0] {
        assert!(matches!(
            Tags::from_crease_angle(&cube, bad),
            Err(TagError::BadAngle(_))
        ));
    }
}

/// A roof: two planes meeting along the x axis at a ridge, each side with its own normals at
/// the ridge vertices (split normals), so the file's hard edge is one crease.
fn roof() -> Mesh {
    let s = 0.6f32; // slope
    let mut p = vec![];
    let mut n = vec![];
    let up = |sign: f32| {
        let l = (1.0 + s * s).sqrt();
        [0.0, sign * s / l, 1.0 / l]
    };
    for x in [0.0f32, 1.0, 2.0] {
        p.push([x, 0.0, 0.0]); // ridge, +y side copy: 0, 1, 2
        n.push(up(1.0));
    }
    for x in [0.0f32, 1.0, 2.0] {
        p.push([x, 1.0, -s]); // +y side: 3, 4, 5
        n.push(up(1.0));
    }
    for x in [0.0f32, 1.0, 2.0] {
        p.push([x, 0.0, 0.0]); // ridge, -y side copy: 6, 7, 8
        n.push(up(-1.0));
    }
    for x in [0.0f32, 1.0, 2.0] {
        p.push([x, -1.0, -s]); // -y side: 9, 10, 11
        n.push(up(-1.0));
    }
    let t = vec![
        [0, 1, 4],
        [0, 4, 3],
        [1, 2, 5],
        [1, 5, 4],
        [6, 10, 7],
        [6, 9, 10],
        [7, 11, 8],
        [7, 10, 11],
    ];
    Mesh::new(p, Some(n), None, t).unwrap()
}

#[test]
fn split_normals_give_a_crease_that_reproduces_both_normals() {
    let mesh = roof();
    let tags = Tags::from_split_normals(&mesh);
    assert_eq!(tags.edge_count(), 2);
    let pid = position_ids(mesh.positions());
    let tag = tags.vertex(pid[1]);
    assert!(tag.has_crease());
    let mean = glam::Vec3::Z; // the mean of the two side normals
    let delta = glam::Vec3::from(tag.crease);
    // Vertex 1's faces lie on +y, vertex 7's on -y. A face is on the + side when the crease
    // vector points into it; its normal is then normalize(N̄ + σΔ), else normalize(N̄ - σΔ).
    for (v, face_y) in [(1usize, 1.0f32), (7, -1.0)] {
        let side = (delta.y * face_y).signum();
        let got = (mean + side * tag.sharpness * delta).normalize();
        let want = glam::Vec3::from(mesh.normals()[v]);
        assert!(
            got.angle_between(want) < 1e-5,
            "vertex {v}: {got} vs {want}"
        );
    }
    // The same crease from the dihedral angle (the roof bends by 2 atan(0.6) ≈ 62°).
    let welded = Mesh::new(
        mesh.positions().to_vec(),
        None,
        None,
        mesh.triangles().to_vec(),
    )
    .unwrap();
    assert_eq!(
        Tags::from_crease_angle(&welded, 45.0).unwrap().edge_count(),
        2
    );
    assert_eq!(
        Tags::from_crease_angle(&welded, 70.0).unwrap().edge_count(),
        0
    );
}

#[test]
fn builder_checks_values_and_keys_tags_by_position() {
    let mesh = samples::tetrahedron();
    let mut tags = TagBuilder::new(&mesh);
    let edge = EdgeTag {
        sharpness: 0.5,
        kappa: -0.1,
    };
    tags.set_edge([0, 1], edge).unwrap();
    let vertex = VertexTag {
        tension: 0.25,
        sharpness: 1.0,
        crease: [0.0, 1.0, 0.0],
        ..Default::default()
    };
    tags.set_vertex(2, vertex).unwrap();
    assert!(matches!(
        tags.set_vertex(9, VertexTag::default()),
        Err(TagError::UnknownVertex {
            vertex: 9,
            count: 4,
            ..
        })
    ));
    assert!(matches!(
        tags.set_edge([0, 7], EdgeTag::default()),
        Err(TagError::UnknownVertex { vertex: 7, .. })
    ));
    let too_sharp = EdgeTag {
        sharpness: 2.0,
        kappa: 0.0,
    };
    assert!(matches!(
        tags.set_edge([0, 1], too_sharp),
        Err(TagError::OutOfRange { .. })
    ));
    let valley = VertexTag {
        sharpness: -3.0,
        ..Default::default()
    };
    assert!(matches!(
        tags.set_vertex(0, valley),
        Err(TagError::OutOfRange { .. })
    ));
    let nan = VertexTag {
        bias: f32::NAN,
        ..Default::default()
    };
    let err = tags.set_vertex(1, nan).unwrap_err();
    assert!(matches!(err, TagError::NotFinite { .. }));
    assert!(err.to_string().contains("vertex 1 bias"), "{err}");
    assert!(matches!(
        tags.set_edge([3, 3], EdgeTag::default()),
        Err(TagError::NotAnEdge { a: 3, b: 3 })
    ));

    // Refused tags leave nothing behind; the builder and the one-at-a-time setters agree.
    let built = tags.finish();
    assert_eq!(built.edge(1, 0), edge);
    assert_eq!(built.vertex(2), vertex);
    assert_eq!((built.edge_count(), built.vertex_count()), (1, 1));
    let mut one_by_one = Tags::new();
    one_by_one.set_edge(&mesh, [1, 0], edge).unwrap();
    one_by_one.set_vertex(&mesh, 2, vertex).unwrap();
    assert_eq!(one_by_one, built);

    // On a split vertex, every copy reaches the tag of its position.
    let cube = samples::hard_cube();
    let ids = position_ids(cube.positions());
    let copy = (0..cube.vertex_count())
        .find(|&v| ids[v] != v as u32)
        .expect("the hard cube splits its corners");
    let mut tags = TagBuilder::new(&cube);
    tags.set_vertex(copy as u32, vertex).unwrap();
    let tags = tags.finish();
    assert_eq!(tags.vertex(ids[copy]), vertex);
    let mut single = Tags::new();
    single.set_vertex(&cube, copy as u32, vertex).unwrap();
    assert_eq!(single, tags);
}

#[test]
fn boundary_and_non_edges_are_refused() {
    // Two triangles sharing edge 1-2; the other edges are boundary.
    let mesh = Mesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ],
        None,
        None,
        vec![[0, 1, 2], [1, 3, 2]],
    )
    .unwrap();
    let mut tags = Tags::new();
    let sharp = EdgeTag {
        sharpness: 1.0,
        kappa: 0.0,
    };
    assert!(tags.set_edge(&mesh, [1, 2], sharp).is_ok());
    assert_eq!(
        tags.set_edge(&mesh, [0, 1], sharp),
        Err(TagError::BoundaryEdge { a: 0, b: 1 })
    );
    assert_eq!(
        tags.set_edge(&mesh, [0, 3], sharp),
        Err(TagError::NotAnEdge { a: 0, b: 3 })
    );
}
