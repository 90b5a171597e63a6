//! Small meshes the project generates itself: test inputs, benchmark inputs and the bundled
//! sample files (`tessella samples` writes them).

use crate::mesh::Mesh;
use std::collections::HashMap;

mod animated;

pub use animated::animated_creature;
use std::f32::consts::PI;

/// Names of the bundled samples, in the order [`by_name`] knows them.
pub const NAMES: [&str; 6] = [
    "icosphere",
    "torus",
    "tetrahedron",
    "hard-cube",
    "creature",
    "icosphere-4k",
];

/// A bundled sample by name (see [`NAMES`]).
pub fn by_name(name: &str) -> Option<Mesh> {
    Some(match name {
        "icosphere" => icosphere(1),
        "torus" => torus(1.0, 0.4, 12, 8),
        "tetrahedron" => tetrahedron(),
        "hard-cube" => hard_cube(),
        "creature" => creature(),
        "icosphere-4k" => icosphere_4k(),
        _ => return None,
    })
}

/// The unit icosahedron subdivided `subdivisions` times (`20 · 4^s` triangles), vertices on the
/// unit sphere, normals equal to positions (the sphere's exact normals).
pub fn icosphere(subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<[f32; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| normalize(p))
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<[f32; 3]>| {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (pa, pb) = (positions[a as usize], positions[b as usize]);
                positions.push(normalize([pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]]));
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let normals = positions.clone();
    Mesh::new(positions, Some(normals), None, triangles).expect("icosphere is valid")
}

/// About 4k triangles: the benchmark mesh (an icosphere of 5120 triangles).
pub fn icosphere_4k() -> Mesh {
    icosphere(4)
}

/// A torus around +Z with tube centre radius `major` and tube radius `minor`, `around × tube`
/// quads split into triangles, with exact normals and UVs.
pub fn torus(major: f32, minor: f32, around: u32, tube: u32) -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..around {
        let u = i as f32 / around as f32 * 2.0 * PI;
        for j in 0..tube {
            let v = j as f32 / tube as f32 * 2.0 * PI;
            let n = [u.cos() * v.cos(), u.sin() * v.cos(), v.sin()];
            positions.push([
                (major + minor * v.cos()) * u.cos(),
                (major + minor * v.cos()) * u.sin(),
                minor * v.sin(),
            ]);
            normals.push(n);
            uvs.push([i as f32 / around as f32, j as f32 / tube as f32]);
        }
    }
    let id = |i: u32, j: u32| (i % around) * tube + (j % tube);
    let mut triangles = Vec::new();
    for i in 0..around {
        for j in 0..tube {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    // UVs wrap, so they are not per-vertex continuous on the seam; keep positions shared and
    // drop UVs here: the torus is the closed genus-1 test surface.
    let _ = uvs;
    Mesh::new(positions, Some(normals), None, triangles).expect("torus is valid")
}

/// A regular tetrahedron with centroid normals (PNG1 paper, Figure 10): the coarsest closed
/// mesh, where PN and PNG1 differ most.
pub fn tetrahedron() -> Mesh {
    let positions = vec![
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let normals = positions.iter().map(|&p| normalize(p)).collect();
    let triangles = vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
    Mesh::new(positions, Some(normals), None, triangles).expect("tetrahedron is valid")
}

/// A unit cube with hard edges: each face has its own four vertices with the face normal, so
/// every corner position carries three normals (split normals).
pub fn hard_cube() -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = unit(axis, sign);
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = positions.len() as u32;
            for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign;
                p[a] = s;
                p[b] = t;
                positions.push(p);
                normals.push(n);
            }
            // (a, b, axis) is right-handed, so the quad is counter-clockwise seen from +axis.
            if sign > 0.0 {
                triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
            } else {
                triangles.extend([[base, base + 2, base + 1], [base, base + 3, base + 2]]);
            }
        }
    }
    Mesh::new(positions, Some(normals), None, triangles).expect("cube is valid")
}

/// An icosphere with hard edges on its upper half: faces whose centre lies above `z = 0` get
/// their own three vertices with the face's normal (split normals, like [`hard_cube`]); the
/// others share vertices with the sphere's normals. Along the border a position carries a
/// smooth vertex and several faceted ones.
pub fn half_faceted_icosphere(subdivisions: u32) -> Mesh {
    let sphere = icosphere(subdivisions);
    let mut positions = sphere.positions().to_vec();
    let mut normals = sphere.normals().to_vec();
    let mut triangles = Vec::with_capacity(sphere.face_count());
    for &t in sphere.triangles() {
        let p = t.map(|v| positions[v as usize]);
        if p[0][2] + p[1][2] + p[2][2] <= 0.0 {
            triangles.push(t);
            continue;
        }
        let (a, b) = (sub(p[1], p[0]), sub(p[2], p[0]));
        let n = normalize([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]);
        let base = positions.len() as u32;
        positions.extend(p);
        normals.extend([n; 3]);
        triangles.push([base, base + 1, base + 2]);
    }
    // Drop the smooth vertices only faceted faces used.
    let mut index = vec![u32::MAX; positions.len()];
    let (mut kept_positions, mut kept_normals) = (Vec::new(), Vec::new());
    for t in &mut triangles {
        for v in t.iter_mut() {
            if index[*v as usize] == u32::MAX {
                index[*v as usize] = kept_positions.len() as u32;
                kept_positions.push(positions[*v as usize]);
                kept_normals.push(normals[*v as usize]);
            }
            *v = index[*v as usize];
        }
    }
    Mesh::new(kept_positions, Some(kept_normals), None, triangles)
        .expect("half-faceted icosphere is valid")
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The creature's bumps: direction, height and width of the head, the arms and the legs.
/// Standing along +Y (the usual "up" of viewers), facing +Z.
const CREATURE_BUMPS: [([f32; 3], f32, f32); 5] = [
    ([0.0, 1.0, 0.0], 0.9, 0.35), // head
    ([1.0, 0.2, 0.0], 0.7, 0.25), // arms
    ([-1.0, 0.2, 0.0], 0.7, 0.25),
    ([0.45, -1.0, 0.0], 0.6, 0.3), // legs
    ([-0.45, -1.0, 0.0], 0.6, 0.3),
];

/// Something character-like: an icosphere pushed out into a head, two arms and two legs, with
/// computed normals. Closed, genus 0, 320 triangles.
pub fn creature() -> Mesh {
    creature_on(2)
}

/// [`creature`]'s shape on an icosphere subdivided `subdivisions` times (`20 · 4^s`
/// triangles; 2 is [`creature`]).
pub fn creature_on(subdivisions: u32) -> Mesh {
    let sphere = icosphere(subdivisions);
    let positions: Vec<[f32; 3]> = sphere
        .positions()
        .iter()
        .map(|&p| {
            let mut r = 0.8 - 0.15 * p[2] * p[2];
            for (dir, height, width) in CREATURE_BUMPS {
                let d = normalize(dir);
                let cos = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
                r += height * (-(1.0 - cos) / (width * width)).exp();
            }
            [p[0] * r, p[1] * r, p[2] * r * 0.7]
        })
        .collect();
    Mesh::new(positions, None, None, sphere.triangles().to_vec()).expect("creature is valid")
}

fn normalize(p: [f32; 3]) -> [f32; 3] {
    let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    [p[0] / l, p[1] / l, p[2] / l]
}

fn unit(axis: usize, sign: f32) -> [f32; 3] {
    let mut n = [0.0; 3];
    n[axis] = sign;
    n
}

/// The first `faces` triangles of `mesh` (at least one), vertices compacted with their
/// normals and uvs: an open patch cut from a closed sample, or a mesh with an exact face count.
///
/// ```
/// let sphere = tessella_core::samples::icosphere(1);
/// let patch = tessella_core::samples::first_faces(&sphere, 30);
/// assert_eq!(patch.face_count(), 30);
/// assert!(patch.vertex_count() < sphere.vertex_count());
/// ```
pub fn first_faces(mesh: &Mesh, faces: usize) -> Mesh {
    let mut map = vec![u32::MAX; mesh.vertex_count()];
    let mut kept = Vec::new();
    let triangles = mesh
        .triangles()
        .iter()
        .take(faces.max(1))
        .map(|t| {
            t.map(|v| {
                if map[v as usize] == u32::MAX {
                    map[v as usize] = kept.len() as u32;
                    kept.push(v as usize);
                }
                map[v as usize]
            })
        })
        .collect();
    let pick = |a: &[[f32; 3]]| kept.iter().map(|&v| a[v]).collect::<Vec<_>>();
    let uvs = mesh
        .uvs()
        .map(|uv| kept.iter().map(|&v| uv[v]).collect::<Vec<_>>());
    Mesh::new(
        pick(mesh.positions()),
        Some(pick(mesh.normals())),
        uvs,
        triangles,
    )
    .expect("a subset of a valid mesh's faces is a valid mesh")
}

/// One frame of a twisting deformation, for demos, animations and benchmarks: `mesh`'s
/// positions and normals turned about the vertical (Y) axis through the bounding box's centre,
/// by an angle growing linearly with height from `-degrees/2` at the bottom to `+degrees/2` at
/// the top. Normals turn with their points (exact for a rigid turn, close under the twist's
/// shear; pass them to [`crate::refine::Plan::update`] to keep hard edges).
///
/// ```
/// let mesh = tessella_core::samples::creature();
/// let (p, n) = tessella_core::samples::twist(&mesh, 30.0);
/// assert_eq!((p.len(), n.len()), (mesh.vertex_count(), mesh.vertex_count()));
/// let (p0, _) = tessella_core::samples::twist(&mesh, 0.0);
/// assert_eq!(p0, mesh.positions());
/// ```
pub fn twist(mesh: &Mesh, degrees: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let (lo, hi) = mesh.bounds();
    let height = (hi[1] - lo[1]).max(f32::MIN_POSITIVE);
    let centre = [
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    ];
    let turn = |v: [f32; 3], y: f32, about: [f32; 3]| {
        if degrees == 0.0 {
            return v;
        }
        let a = degrees.to_radians() * (y - centre[1]) / height;
        let (s, c) = a.sin_cos();
        let (x, z) = (v[0] - about[0], v[2] - about[2]);
        [c * x + s * z + about[0], v[1], -s * x + c * z + about[2]]
    };
    let positions = mesh
        .positions()
        .iter()
        .map(|&p| turn(p, p[1], centre))
        .collect();
    let normals = mesh
        .normals()
        .iter()
        .zip(mesh.positions())
        .map(|(&n, p)| turn(n, p[1], [0.0; 3]))
        .collect();
    (positions, normals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_closed_with_expected_euler_characteristic() {
        for name in NAMES {
            let mesh = by_name(name).unwrap();
            let report = mesh.topology().report;
            assert!(report.is_closed_manifold(), "{name}: {report:?}");
            let expected = if name == "torus" { 0 } else { 2 };
            assert_eq!(report.euler_characteristic, expected, "{name}");
            // Outward orientation: the normals agree with the face normals on average.
            let mut agree = 0.0;
            for f in 0..mesh.face_count() {
                let [a, b, c] = mesh.corner_positions(f);
                let n = (b - a).cross(c - a);
                agree += mesh.corner_normals(f).iter().map(|m| m.dot(n)).sum::<f32>();
            }
            assert!(agree > 0.0, "{name} is inside out");
        }
        assert_eq!(hard_cube().topology().report.split_normal_positions, 8);
        assert_eq!(icosphere_4k().face_count(), 5120);
    }
}
