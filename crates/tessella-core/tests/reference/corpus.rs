//! The meshes the acceptance tests run on: the crate's small samples plus meshes made here
//! (a randomly perturbed closed mesh, a planar grid), all small so every level 1..=32 is cheap.

use glam::DVec3;
use tessella_core::{samples, Mesh};

/// A tiny deterministic generator (Knuth's MMIX LCG): the same meshes on every run and machine.
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Lcg {
        Lcg(seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407))
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform in the cube `[-1, 1)³`.
    pub fn vec(&mut self) -> DVec3 {
        DVec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        )
    }
}

fn f3(p: DVec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

/// The icosahedron subdivided once (80 faces, closed, genus 0) with every vertex moved by up to
/// 15% of the radius and every normal tilted by up to about 17° from the radial direction at
/// random: a closed mesh with shared (one per vertex) normals that are not the surface's.
pub fn perturbed_sphere(seed: u64) -> Mesh {
    let base = samples::icosphere(1);
    let mut rng = Lcg::new(seed);
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for &p in base.positions() {
        let d = super::d3(p);
        let moved = d * rng.range(0.85, 1.15) + 0.05 * rng.vec();
        positions.push(f3(moved));
        normals.push(f3((d + 0.3 * rng.vec()).normalize()));
    }
    Mesh::new(positions, Some(normals), None, base.triangles().to_vec())
        .expect("perturbed sphere is valid")
}

/// The closed meshes with one normal per vertex that the sweeps run on, named, with their Euler
/// characteristic (2 for the sphere-like ones, 0 for the torus).
pub fn closed_meshes() -> Vec<(&'static str, Mesh, i64)> {
    vec![
        ("tetrahedron", samples::tetrahedron(), 2),
        ("icosphere(1)", samples::icosphere(1), 2),
        ("torus", samples::torus(1.0, 0.4, 8, 6), 0),
        ("creature", samples::creature(), 2),
        ("perturbed sphere", perturbed_sphere(7), 2),
    ]
}

/// A `cols × rows` grid of unit squares in the plane `z = 0`, each split in two CCW triangles,
/// with the interior grid points jittered in x and y; every normal is `(0, 0, 1)`.
pub fn planar_grid(cols: u32, rows: u32, seed: u64) -> Mesh {
    let mut rng = Lcg::new(seed);
    let mut positions = Vec::new();
    for j in 0..=rows {
        for i in 0..=cols {
            let inner = i > 0 && j > 0 && i < cols && j < rows;
            let (dx, dy) = if inner {
                (rng.range(-0.3, 0.3), rng.range(-0.3, 0.3))
            } else {
                (0.0, 0.0)
            };
            positions.push([(i as f64 + dx) as f32, (j as f64 + dy) as f32, 0.0]);
        }
    }
    let id = |i: u32, j: u32| j * (cols + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..rows {
        for i in 0..cols {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let normals = vec![[0.0, 0.0, 1.0]; positions.len()];
    Mesh::new(positions, Some(normals), None, triangles).expect("grid is valid")
}
