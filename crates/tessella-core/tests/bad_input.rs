//! Bad input through the public API gets a typed error that names the problem, never a panic.

mod reference;

use reference::undirected_edges;
use std::panic::{catch_unwind, AssertUnwindSafe};
use tessella_core::refine::Levels;
use tessella_core::{
    refine, samples, Mesh, MeshError, RefineError, RefineOptions, RefinedMesh, Refiner, Scheme,
};

/// Runs `f`, failing the test (instead of unwinding through it) if it panics.
fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| panic!("{what} panicked"))
}

fn try_refine(mesh: &Mesh, options: &RefineOptions) -> Result<RefinedMesh, RefineError> {
    no_panic(&format!("refine with {options:?}"), || {
        refine(mesh, options)
    })
}

/// Bytes of a refined mesh without UVs: 12 per position, 12 per normal, 12 per triangle.
fn output_bytes(mesh: &Mesh, level: u64, weld: bool) -> (u64, u64, u64) {
    let (v, e, f) = (
        mesh.vertex_count() as u64,
        undirected_edges(mesh.triangles()) as u64,
        mesh.face_count() as u64,
    );
    let vertices = if weld {
        v + e * (level - 1) + f * (level - 1) * (level - 2) / 2
    } else {
        f * (level + 1) * (level + 2) / 2
    };
    let triangles = f * level * level;
    (vertices, triangles, vertices * 24 + triangles * 12)
}

/// `bytes` as messages write it: one decimal and a binary unit (`1.5 GiB`).
fn human(bytes: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < units.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", units[unit])
}

#[test]
fn level_zero_is_refused() {
    let mesh = samples::tetrahedron();
    for weld in [true, false] {
        let options = RefineOptions::new(Scheme::Pn, 0).with_weld(weld);
        assert_eq!(
            try_refine(&mesh, &options).unwrap_err(),
            RefineError::LevelZero
        );
        let refiner = no_panic("Refiner::new at level 0", || Refiner::new(&mesh, &options));
        assert!(matches!(refiner, Err(RefineError::LevelZero)));
        let message = RefineError::LevelZero.to_string();
        assert!(message.contains("1 or more"), "{message}");
    }
}

#[test]
fn absurd_level_is_refused_with_its_size() {
    let mesh = samples::icosphere(2);
    let level = 100_000;
    for weld in [true, false] {
        let options = RefineOptions::new(Scheme::Pn, level).with_weld(weld);
        let (vertices, triangles, bytes) = output_bytes(&mesh, level as u64, weld);
        match try_refine(&mesh, &options) {
            Err(error @ RefineError::TooLarge { .. }) => {
                let RefineError::TooLarge {
                    level: l,
                    vertices: v,
                    triangles: t,
                    bytes: b,
                    limit,
                    ..
                } = error.clone()
                else {
                    unreachable!()
                };
                assert_eq!((l, v, t, b), (level, vertices, triangles, bytes));
                assert_eq!(limit, options.max_output_bytes);
                let message = error.to_string();
                println!("{message}");
                assert!(
                    message.contains(&human(bytes)),
                    "{message} lacks {}",
                    human(bytes)
                );
                assert!(message.contains(&human(limit)), "{message}");
                assert!(message.contains("100000"), "{message}");
                assert!(message.contains("lower level"), "{message}");
            }
            other => panic!("weld {weld}: expected TooLarge, got {other:?}"),
        }
    }
}

#[test]
fn the_size_limit_is_exact() {
    // Tetrahedron at level 2, welded: 4 + 6 = 10 vertices, 16 triangles,
    // 10 × 24 + 16 × 12 = 432 bytes.
    let mesh = samples::tetrahedron();
    let (_, _, bytes) = output_bytes(&mesh, 2, true);
    assert_eq!(bytes, 432);
    let mut options = RefineOptions::new(Scheme::Pn, 2);
    options.max_output_bytes = bytes - 1;
    match try_refine(&mesh, &options) {
        Err(RefineError::TooLarge {
            bytes: b, limit, ..
        }) => assert_eq!((b, limit), (432, 431)),
        other => panic!("expected TooLarge, got {other:?}"),
    }
    options.max_output_bytes = bytes;
    let out = try_refine(&mesh, &options).expect("exactly at the limit is allowed");
    assert_eq!(out.byte_size(), bytes);
    // A tiny limit refuses even level 1.
    options.levels = Levels::Uniform(1.0);
    options.max_output_bytes = 10;
    assert!(matches!(
        try_refine(&mesh, &options),
        Err(RefineError::TooLarge { .. })
    ));
}

#[test]
fn more_vertices_than_u32_indices_is_refused() {
    // Level 6000 on 320 faces: 162 + 480 × 5999 + 320 × 5999 × 5998 / 2 ≈ 5.76e9 vertices, more
    // than u32 indices reach. With no size limit, the index range is what refuses it.
    let mesh = samples::icosphere(2);
    let mut options = RefineOptions::new(Scheme::Flat, 6000);
    options.max_output_bytes = u64::MAX;
    let (vertices, _, _) = output_bytes(&mesh, 6000, true);
    assert!(vertices > u32::MAX as u64);
    assert_eq!(
        try_refine(&mesh, &options).unwrap_err(),
        RefineError::IndexOverflow {
            level: 6000,
            vertices
        }
    );
}

#[test]
fn non_finite_phong_alpha_is_refused() {
    let mesh = samples::tetrahedron();
    for alpha in [f32::NAN, f32::INFINITY] {
        let error = try_refine(&mesh, &RefineOptions::new(Scheme::Phong { alpha }, 2)).unwrap_err();
        assert!(matches!(error, RefineError::BadAlpha(a) if a.to_bits() == alpha.to_bits()));
    }
}

fn triangle() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    (
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [1, 3, 2]],
    )
}

fn try_mesh(
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    triangles: Vec<[u32; 3]>,
) -> Result<Mesh, MeshError> {
    no_panic("Mesh::new", || {
        Mesh::new(positions, normals, uvs, triangles)
    })
}

/// Asserts `result` is an error whose message names `needle`.
fn says(result: Result<Mesh, MeshError>, needle: &str) -> MeshError {
    let error = result.expect_err("bad input must be refused");
    let message = error.to_string();
    assert!(
        message.contains(needle),
        "`{message}` does not mention {needle}"
    );
    error
}

#[test]
fn bad_meshes_get_the_matching_error() {
    let (p, t) = triangle();
    let up = vec![[0.0, 0.0, 1.0]; 4];

    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut q = p.clone();
        q[3][1] = bad;
        let e = says(try_mesh(q, None, None, t.clone()), "vertex 3");
        assert!(matches!(e, MeshError::NonFinitePosition { vertex: 3, .. }));
    }

    let e = says(
        try_mesh(p.clone(), None, None, vec![[0, 1, 2], [1, 4, 2]]),
        "vertex 4",
    );
    assert_eq!(
        e,
        MeshError::IndexOutOfRange {
            face: 1,
            index: 4,
            count: 4
        }
    );

    let mut zero = up.clone();
    zero[2] = [0.0, 0.0, 0.0];
    let e = says(try_mesh(p.clone(), Some(zero), None, t.clone()), "vertex 2");
    assert_eq!(e, MeshError::ZeroNormal { vertex: 2 });

    let mut nan_normal = up.clone();
    nan_normal[1] = [0.0, f32::NAN, 1.0];
    let e = says(
        try_mesh(p.clone(), Some(nan_normal), None, t.clone()),
        "vertex 1",
    );
    assert!(matches!(e, MeshError::NonFiniteNormal { vertex: 1, .. }));

    // Degenerate triangles: a repeated index, and three distinct but collinear corners, and two
    // distinct vertices at the same position.
    let e = says(
        try_mesh(p.clone(), None, None, vec![[0, 1, 2], [3, 2, 3]]),
        "triangle 1",
    );
    assert!(matches!(
        e,
        MeshError::RepeatedIndex {
            face: 1,
            index: 3,
            ..
        }
    ));
    let collinear = vec![
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [0.0, 1.0, 0.0],
    ];
    let e = says(
        try_mesh(collinear, None, None, vec![[0, 1, 3], [0, 2, 1]]),
        "triangle 1",
    );
    assert_eq!(e, MeshError::ZeroArea { face: 1 });
    let mut coincident = p.clone();
    coincident[3] = coincident[1];
    let e = says(try_mesh(coincident, None, None, t.clone()), "triangle 1");
    assert_eq!(e, MeshError::ZeroArea { face: 1 });

    assert_eq!(
        try_mesh(p.clone(), None, None, vec![]).unwrap_err(),
        MeshError::NoTriangles
    );

    let e = says(
        try_mesh(p.clone(), Some(up[..3].to_vec()), None, t.clone()),
        "normals",
    );
    assert_eq!(
        e,
        MeshError::AttributeCount {
            what: "normals",
            got: 3,
            expected: 4
        }
    );
    let e = says(
        try_mesh(p.clone(), None, Some(vec![[0.0; 2]; 5]), t.clone()),
        "uvs",
    );
    assert_eq!(
        e,
        MeshError::AttributeCount {
            what: "uvs",
            got: 5,
            expected: 4
        }
    );
    let mut uvs = vec![[0.5f32; 2]; 4];
    uvs[0][1] = f32::NAN;
    let e = says(try_mesh(p.clone(), None, Some(uvs), t.clone()), "vertex 0");
    assert!(matches!(e, MeshError::NonFiniteUv { vertex: 0, .. }));

    // The good mesh itself is accepted and refines.
    let mesh = try_mesh(p, Some(up), None, t).unwrap();
    assert!(try_refine(&mesh, &RefineOptions::new(Scheme::Pn, 3)).is_ok());
}

#[test]
fn open_and_split_meshes_refine_without_panicking() {
    // Not errors, but the edge cases of the welded layout: a single triangle (all boundary), a
    // mesh with a vertex no triangle uses, and the hard cube's split normals.
    let single = Mesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [5.0, 5.0, 5.0],
        ],
        None,
        None,
        vec![[0, 1, 2]],
    )
    .unwrap();
    for mesh in [single, samples::hard_cube()] {
        for scheme in [Scheme::Flat, Scheme::PHONG, Scheme::Pn] {
            for level in [1, 2, 5] {
                for weld in [true, false] {
                    let options = RefineOptions::new(scheme, level).with_weld(weld);
                    let out = try_refine(&mesh, &options).unwrap();
                    assert!(out.positions.iter().flatten().all(|c| c.is_finite()));
                    assert!(out.normals.iter().all(|n| ((n[0] * n[0]
                        + n[1] * n[1]
                        + n[2] * n[2])
                        - 1.0)
                        .abs()
                        < 1e-5));
                }
            }
        }
    }
}
