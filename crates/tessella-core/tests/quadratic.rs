//! Second-order (6-node) triangles and fields through refinement, checked against independent
//! f64 evaluations of the 6-node shape functions written here.

use glam::DVec3;
use std::collections::HashMap;
use tessella_core::fields::{copy_cell_data, interpolate_point_data, triangle_faces, FieldError};
use tessella_core::refine::{Levels, Spacing, NO_FACE};
use tessella_core::{samples, Mesh, MeshError, RefineOptions, Refiner, Scheme};

/// The 6-node shape functions, written out again (not the crate's).
fn n6(l: [f64; 3]) -> [f64; 6] {
    let [a, b, c] = l;
    [
        a * (2.0 * a - 1.0),
        b * (2.0 * b - 1.0),
        c * (2.0 * c - 1.0),
        4.0 * a * b,
        4.0 * b * c,
        4.0 * c * a,
    ]
}

fn p(v: [f32; 3]) -> DVec3 {
    DVec3::from(v.map(f64::from))
}

/// Positions, corner triangles, mid-edge nodes.
type P2Arrays = (Vec<[f32; 3]>, Vec<[u32; 3]>, Vec<[u32; 3]>);

/// A P2 mesh: `mesh`'s triangles with one mid node per edge, placed by `place(a, b)` (shared by
/// both faces of an edge), appended after the mesh's vertices. Returns the positions, corner
/// triangles and mid nodes.
fn with_mids(mesh: &Mesh, place: impl Fn(DVec3, DVec3) -> DVec3) -> P2Arrays {
    let mut pos = mesh.positions().to_vec();
    let mut at: HashMap<(u32, u32), u32> = HashMap::new();
    let mids = mesh
        .triangles()
        .iter()
        .map(|t| {
            std::array::from_fn(|k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *at.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let m = place(p(pos[a as usize]), p(pos[b as usize]));
                    pos.push(m.as_vec3().into());
                    pos.len() as u32 - 1
                })
            })
        })
        .collect();
    (pos, mesh.triangles().to_vec(), mids)
}

/// The icosphere's P2 mesh: corners and mid-edge nodes on the unit sphere.
fn p2_sphere(sub: u32) -> Mesh {
    let (pos, tris, mids) = with_mids(&samples::icosphere(sub), |a, b| (a + b).normalize());
    Mesh::new(pos, None, None, tris)
        .unwrap()
        .with_mid_nodes(mids)
        .unwrap()
}

fn nodes(mesh: &Mesh, f: usize) -> [DVec3; 6] {
    let t = mesh.triangles()[f];
    let m = mesh.face_mid_nodes(f).expect("second order");
    [t[0], t[1], t[2], m[0], m[1], m[2]].map(|i| p(mesh.positions()[i as usize]))
}

fn map(nodes: &[DVec3; 6], l: [f64; 3]) -> DVec3 {
    nodes.iter().zip(n6(l)).map(|(x, w)| *x * w).sum()
}

/// Du × Dv by central differences of the f64 map (independent of the crate's derivatives).
fn normal(nodes: &[DVec3; 6], l: [f64; 3]) -> DVec3 {
    let h = 1e-5;
    let at = |du: f64, dv: f64| map(nodes, [l[0] - du - dv, l[1] + du, l[2] + dv]);
    let du = (at(h, 0.0) - at(-h, 0.0)) / (2.0 * h);
    let dv = (at(0.0, h) - at(0.0, -h)) / (2.0 * h);
    du.cross(dv).normalize()
}

#[test]
fn p2_surface_is_the_elements_own_map_welded_and_soup() {
    let mesh = p2_sphere(1);
    let diag = mesh.diagonal() as f64;
    for weld in [true, false] {
        for level in [1, 2, 5, 8] {
            let opts = RefineOptions::new(Scheme::Quadratic, level).with_weld(weld);
            let refiner = Refiner::new(&mesh, &opts).unwrap();
            let out = refiner.refine();
            let (faces, bary) = refiner.plan().origin();
            let mut worst: f64 = 0.0;
            let mut worst_normal: f64 = 0.0;
            let mut unused = 0;
            for (v, (&f, l)) in faces.iter().zip(&bary).enumerate() {
                if f == NO_FACE {
                    unused += 1; // a mid-edge node: kept, unused, at its own position
                    assert_eq!(out.positions[v], mesh.positions()[v]);
                    continue;
                }
                let nd = nodes(&mesh, f as usize);
                let l = l.map(f64::from);
                worst = worst.max((p(out.positions[v]) - map(&nd, l)).length());
                let angle = p(out.normals[v]).angle_between(normal(&nd, l));
                worst_normal = worst_normal.max(angle);
            }
            assert!(
                worst <= 1e-6 * diag,
                "weld {weld} level {level}: {worst:e} from the 6-node map"
            );
            assert!(
                worst_normal < 1e-4,
                "weld {weld} level {level}: normals {worst_normal} rad off Du x Dv"
            );
            let mids = mesh.vertex_count() - samples::icosphere(1).vertex_count();
            assert_eq!(unused, if weld { mids } else { 0 });
        }
    }
}

#[test]
fn isoparametric_nodes_are_hit_and_the_surface_is_not_flat_or_pn() {
    let mesh = p2_sphere(0);
    let diag = mesh.diagonal() as f64;
    let opts = RefineOptions::new(Scheme::Quadratic, 2).with_weld(false);
    let refiner = Refiner::new(&mesh, &opts).unwrap();
    let out = refiner.refine();
    let (faces, bary) = refiner.plan().origin();
    let mut hits = 0;
    for (v, (&f, l)) in faces.iter().zip(&bary).enumerate() {
        let t = mesh.triangles()[f as usize];
        let m = mesh.face_mid_nodes(f as usize).unwrap();
        let node = match *l {
            [1.0, 0.0, 0.0] => t[0],
            [0.0, 1.0, 0.0] => t[1],
            [0.0, 0.0, 1.0] => t[2],
            [0.5, 0.5, 0.0] => m[0],
            [0.0, 0.5, 0.5] => m[1],
            [0.5, 0.0, 0.5] => m[2],
            _ => continue,
        };
        hits += 1;
        let d = (p(out.positions[v]) - p(mesh.positions()[node as usize])).length();
        assert!(d <= 1e-6 * diag, "node {node}: {d:e}");
        // On the sphere: every node is at radius 1.
        assert!((p(out.positions[v]).length() - 1.0).abs() < 1e-6);
    }
    assert_eq!(hits, 6 * mesh.face_count());
    // Flat and PN put the edge midpoints elsewhere: the scheme really reads the mid nodes.
    for other in [Scheme::Flat, Scheme::Pn] {
        let o =
            tessella_core::refine(&mesh, &RefineOptions::new(other, 2).with_weld(false)).unwrap();
        let most = o
            .positions
            .iter()
            .zip(&out.positions)
            .map(|(a, b)| (p(*a) - p(*b)).length())
            .fold(0.0, f64::max);
        assert!(most > 1e-3, "{other:?} agrees with quadratic");
    }
}

#[test]
fn mixed_linear_and_quadratic_faces() {
    // Two triangles over the unit square; face 0 second order with bulging outer edges and a
    // straight shared diagonal, face 1 linear.
    let pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.0, 0.2],  // mid 0-1, bulging
        [1.0, 0.5, -0.1], // mid 1-2, bulging
        [0.5, 0.5, 0.0],  // mid 2-0 = the diagonal's midpoint
    ];
    let tris = vec![[0, 1, 2], [0, 2, 3]];
    let mids = vec![[4, 5, 6], [u32::MAX; 3]];
    let mesh = Mesh::new(pos.clone(), None, None, tris.clone())
        .unwrap()
        .with_mid_nodes(mids)
        .unwrap();
    assert!(mesh.is_quadratic() && mesh.face_mid_nodes(1).is_none());
    let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Quadratic, 6)).unwrap();
    let out = refiner.refine();
    let (faces, bary) = refiner.plan().origin();
    for (v, (&f, l)) in faces.iter().zip(&bary).enumerate() {
        let l = l.map(f64::from);
        let want = match f {
            0 => map(&nodes(&mesh, 0), l),
            1 => (0..3)
                .map(|i| p(pos[tris[1][i] as usize]) * l[i])
                .sum::<DVec3>(),
            _ => p(pos[v]),
        };
        assert!((p(out.positions[v]) - want).length() < 1e-6, "vertex {v}");
    }
    // A linear neighbour with a curved shared edge is refused, naming both faces.
    let mut bent = pos;
    bent[6] = [0.5, 0.5, 0.1];
    let err = Mesh::new(bent, None, None, tris)
        .unwrap()
        .with_mid_nodes(vec![[4, 5, 6], [u32::MAX; 3]])
        .unwrap_err();
    assert!(
        matches!(err, MeshError::MidNodeMismatch { faces: [0, 1], .. }),
        "{err}"
    );
    assert!(err.to_string().contains("face 1 is linear"), "{err}");
}

#[test]
fn bad_second_order_input_is_refused_naming_the_element() {
    let base = samples::icosphere(0);
    let (pos, tris, mids) = with_mids(&base, |a, b| (a + b).normalize());
    let mesh = || Mesh::new(pos.clone(), None, None, tris.clone()).unwrap();
    // Neighbours naming different mid nodes at different positions.
    let mut pos2 = pos.clone();
    let extra = pos2.len() as u32;
    pos2.push([9.0, 9.0, 9.0]);
    let mut bad = mids.clone();
    // face 0's edge 0-1 is shared with some other face g; give face 0 its own node there.
    bad[0][0] = extra;
    let err = Mesh::new(pos2, None, None, tris.clone())
        .unwrap()
        .with_mid_nodes(bad)
        .unwrap_err();
    let MeshError::MidNodeMismatch { faces, edge, .. } = &err else {
        panic!("{err}")
    };
    assert!(faces.contains(&0), "{err}");
    let t0 = tris[0];
    assert_eq!(
        [edge[0].min(edge[1]), edge[0].max(edge[1])],
        [t0[0].min(t0[1]), t0[0].max(t0[1])]
    );
    // An inverted element: face 3's mid node of edge 0-1 pulled far across the triangle.
    let mut pos3 = pos.clone();
    let m = mids[3][0] as usize;
    let t = tris[3];
    let [a, b, c] = t.map(|i| p(pos[i as usize]));
    pos3[m] = (0.5 * (a + b) + 3.0 * (c - 0.5 * (a + b))).as_vec3().into();
    let err = Mesh::new(pos3, None, None, tris.clone())
        .unwrap()
        .with_mid_nodes(mids.clone())
        .unwrap_err();
    assert!(matches!(err, MeshError::InvertedElement { .. }), "{err}");
    assert!(err.to_string().contains("inverted"), "{err}");
    // Mid nodes listed in the wrong order fold the element too.
    let mut swapped = mids.clone();
    swapped[5] = [mids[5][1], mids[5][2], mids[5][0]];
    let err = mesh().with_mid_nodes(swapped);
    assert!(err.is_err(), "rotated mid nodes accepted");
    // Partial, out of range, a corner, wrong count.
    let mut partial = mids.clone();
    partial[2][1] = u32::MAX;
    assert!(matches!(
        mesh().with_mid_nodes(partial),
        Err(MeshError::BadMidNode { face: 2, .. })
    ));
    let mut out_of_range = mids.clone();
    out_of_range[4] = [999, 1000, 1001];
    assert!(matches!(
        mesh().with_mid_nodes(out_of_range),
        Err(MeshError::BadMidNode { face: 4, .. })
    ));
    let mut corner = mids.clone();
    corner[7][0] = tris[7][2];
    assert!(matches!(
        mesh().with_mid_nodes(corner),
        Err(MeshError::BadMidNode { face: 7, .. })
    ));
    assert!(matches!(
        mesh().with_mid_nodes(mids[1..].to_vec()),
        Err(MeshError::MidNodeCount { .. })
    ));
    // Moving a good mesh into an inverted shape is refused by update, the mesh unchanged.
    let mut good = mesh().with_mid_nodes(mids.clone()).unwrap();
    let mut moved = pos.clone();
    moved[m] = (0.5 * (a + b) + 3.0 * (c - 0.5 * (a + b))).as_vec3().into();
    assert!(matches!(
        good.update(&moved, None),
        Err(MeshError::InvertedElement { face: 3, .. })
    ));
    assert_eq!(good.positions(), &pos[..]);
}

/// `f(x)` for a field linear in the coordinates, two components.
fn linear_field(x: DVec3) -> [f64; 2] {
    [2.0 * x.x - 3.0 * x.y + 0.5 * x.z + 1.0, -x.x + 4.0 * x.z]
}

#[test]
fn linear_field_is_exact_on_linear_elements() {
    let mesh = samples::icosphere(1);
    let data: Vec<f32> = mesh
        .positions()
        .iter()
        .flat_map(|&x| linear_field(p(x)).map(|v| v as f32))
        .collect();
    for (weld, spacing) in [
        (true, Spacing::Grid),
        (false, Spacing::Grid),
        (true, Spacing::FractionalOdd),
    ] {
        let mut opts = RefineOptions::new(Scheme::Flat, 5)
            .with_weld(weld)
            .with_spacing(spacing);
        if spacing != Spacing::Grid {
            opts = opts.with_levels(Levels::Uniform(4.4));
        }
        let refiner = Refiner::new(&mesh, &opts).unwrap();
        let out = refiner.refine();
        let field = interpolate_point_data(&mesh, refiner.plan(), "F", &data, 2).unwrap();
        assert_eq!(field.len(), 2 * out.positions.len());
        for (x, v) in out.positions.iter().zip(field.chunks(2)) {
            let want = linear_field(p(*x));
            for c in 0..2 {
                assert!(
                    (v[c] as f64 - want[c]).abs() < 2e-6,
                    "{v:?} vs {want:?} at {x:?}"
                );
            }
        }
    }
}

/// A field quadratic in the coordinates.
fn quadratic_field(x: DVec3) -> f64 {
    x.x * x.x - 2.0 * x.y * x.z + 0.5 * x.z * x.z + x.y - 3.0
}

#[test]
fn quadratic_field_is_exact_on_p2_elements() {
    // Straight-sided P2 elements (mid nodes at the edge midpoints): the coordinates are linear in
    // l, so a field quadratic in x is quadratic in l, which P2 reproduces; P1 does not.
    let (pos, tris, mids) = with_mids(&samples::icosphere(1), |a, b| 0.5 * (a + b));
    let data: Vec<f32> = pos.iter().map(|&x| quadratic_field(p(x)) as f32).collect();
    let p2 = Mesh::new(pos.clone(), None, None, tris.clone())
        .unwrap()
        .with_mid_nodes(mids)
        .unwrap();
    let p1 = Mesh::new(pos, None, None, tris).unwrap();
    for (mesh, exact) in [(&p2, true), (&p1, false)] {
        let refiner = Refiner::new(mesh, &RefineOptions::new(Scheme::Quadratic, 6)).unwrap();
        let out = refiner.refine();
        let field = interpolate_point_data(mesh, refiner.plan(), "T", &data, 1).unwrap();
        let worst = out
            .positions
            .iter()
            .zip(&field)
            .map(|(x, v)| (*v as f64 - quadratic_field(p(*x))).abs())
            .fold(0.0, f64::max);
        if exact {
            assert!(worst < 3e-6, "P2: {worst:e}");
        } else {
            assert!(worst > 1e-3, "P1 reproduced a quadratic field: {worst:e}");
        }
    }
    // On the curved P2 sphere: the field is the isoparametric interpolant, sum N_k T_k.
    let mesh = p2_sphere(1);
    let data: Vec<f32> = mesh
        .positions()
        .iter()
        .map(|&x| quadratic_field(p(x)) as f32)
        .collect();
    let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Quadratic, 4)).unwrap();
    let field = interpolate_point_data(&mesh, refiner.plan(), "T", &data, 1).unwrap();
    let (faces, bary) = refiner.plan().origin();
    for (v, (&f, l)) in faces.iter().zip(&bary).enumerate() {
        let want = if f == NO_FACE {
            data[v] as f64
        } else {
            let t = mesh.triangles()[f as usize];
            let m = mesh.face_mid_nodes(f as usize).unwrap();
            [t[0], t[1], t[2], m[0], m[1], m[2]]
                .iter()
                .zip(n6(l.map(f64::from)))
                .map(|(&i, w)| w * data[i as usize] as f64)
                .sum()
        };
        assert!((field[v] as f64 - want).abs() < 1e-5, "vertex {v}");
    }
}

#[test]
fn cell_data_follows_each_refined_triangle_to_its_face() {
    let mesh = samples::icosphere(1);
    let data: Vec<f32> = (0..mesh.face_count())
        .flat_map(|f| [f as f32, -(f as f32) * 0.5])
        .collect();
    for opts in [
        RefineOptions::new(Scheme::Pn, 3).with_weld(false),
        RefineOptions::new(Scheme::Pn, 1)
            .with_weld(false)
            .with_spacing(Spacing::FractionalEven)
            .with_levels(Levels::Uniform(3.3)),
    ] {
        let refiner = Refiner::new(&mesh, &opts).unwrap();
        let out = refiner.refine();
        let cells = copy_cell_data(refiner.plan(), "id", &data, 2).unwrap();
        let (faces, _) = refiner.plan().origin();
        assert_eq!(cells.len(), 2 * out.triangles.len());
        // Soup: a triangle's vertices all come from its own face.
        for (t, v) in out.triangles.iter().zip(cells.chunks(2)) {
            let f = faces[t[0] as usize];
            assert!(t.iter().all(|&i| faces[i as usize] == f));
            assert_eq!(v, [f as f32, -(f as f32) * 0.5]);
        }
        assert_eq!(triangle_faces(refiner.plan()).len(), out.triangles.len());
    }
}

#[test]
fn bad_fields_are_refused_naming_the_field() {
    let mesh = samples::icosphere(0);
    let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, 2)).unwrap();
    let plan = refiner.plan();
    let n = mesh.vertex_count();
    let err = interpolate_point_data(&mesh, plan, "T", &vec![0.0; n - 1], 1).unwrap_err();
    assert!(matches!(err, FieldError::WrongLength { .. }));
    assert!(err.to_string().contains("\"T\""), "{err}");
    let mut nan = vec![1.0; 3 * n];
    nan[3 * 4 + 2] = f32::NAN;
    let err = interpolate_point_data(&mesh, plan, "U", &nan, 3).unwrap_err();
    assert!(
        matches!(&err, FieldError::NonFinite { name, index: 4, component: 2, value, per: "vertex" }
            if name == "U" && value.is_nan()),
        "{err:?}"
    );
    assert!(err.to_string().contains("\"U\""), "{err}");
    let err = copy_cell_data(plan, "stress", &[1.0; 5], 1).unwrap_err();
    assert!(err.to_string().contains("\"stress\""), "{err}");
    let err = copy_cell_data(plan, "s", &[], 0).unwrap_err();
    assert!(matches!(err, FieldError::ZeroWidth { .. }));
}
