//! GL output checked against the CPU refinement of the same mesh and options, point by point
//! and triangle by triangle (feature `testing`: this crate's tests, not the library's API).

use crate::refine::GlRefined;
use std::collections::HashMap;
use tessella_core::refine::Plan;
use tessella_core::{Mesh, RefineOptions, RefinedMesh};

/// How GL output compares with the CPU (feature `testing`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    pub triangles: usize,
    /// Largest position difference over the mesh's bounding-box diagonal.
    pub max_position_error: f32,
    /// Largest difference of unit normals.
    pub max_normal_error: f32,
}

fn key(face: u32, l: [f32; 3]) -> (u32, [i64; 3]) {
    // Tessellator coordinates are multiples of 2^-16, exact in f32.
    (face, l.map(|x| (x as f64 * 65536.0).round() as i64))
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Compares GL output with the CPU refinement of the same `mesh` and `options`: every GL vertex
/// must be a point of the CPU pattern of its face (same barycentric origin), the triangles must
/// be the CPU's (same corners, same winding, each once), positions within
/// `tolerance × diagonal` and normals within `normal_tolerance` (feature `testing`).
pub fn compare(
    mesh: &Mesh,
    options: &RefineOptions,
    gl: &GlRefined,
    tolerance: f32,
    normal_tolerance: f32,
) -> Result<Comparison, String> {
    let (plan, frame) =
        Plan::with_frame(mesh, &options.clone().with_weld(false)).map_err(|e| e.to_string())?;
    let mut cpu = RefinedMesh::default();
    plan.refine_into(&frame, &mut cpu, &|_| {})
        .map_err(|e| e.to_string())?;
    let (faces, bary) = plan.origin();
    let index: HashMap<_, u32> = faces
        .iter()
        .zip(&bary)
        .enumerate()
        .map(|(i, (&f, &l))| (key(f, l), i as u32))
        .collect();
    if gl.triangle_count() != cpu.triangles.len() {
        return Err(format!(
            "GL made {} triangles, the CPU {}",
            gl.triangle_count(),
            cpu.triangles.len()
        ));
    }
    let diag = mesh.diagonal();
    let (mut max_p, mut max_n) = (0.0f32, 0.0f32);
    let mut gl_tris = Vec::with_capacity(gl.triangle_count());
    for t in 0..gl.triangle_count() {
        let mut tri = [0u32; 3];
        for (c, slot) in tri.iter_mut().enumerate() {
            let v = 3 * t + c;
            let i = *index.get(&key(gl.faces[v], gl.coords[v])).ok_or_else(|| {
                format!(
                    "GL vertex {v} (face {}, l = {:?}) is no point of the CPU pattern",
                    gl.faces[v], gl.coords[v]
                )
            })? as usize;
            let dp = dist(gl.positions[v], cpu.positions[i]) / diag;
            if dp.is_nan() || dp > tolerance {
                return Err(format!(
                    "GL vertex {v} (face {}, l = {:?}) at {:?}, CPU at {:?}: {dp} diagonals apart",
                    gl.faces[v], gl.coords[v], gl.positions[v], cpu.positions[i]
                ));
            }
            let dn = dist(gl.normals[v], cpu.normals[i]);
            if dn.is_nan() || dn > normal_tolerance {
                return Err(format!(
                    "GL vertex {v} (face {}, l = {:?}) normal {:?}, CPU {:?}: |d| = {dn}",
                    gl.faces[v], gl.coords[v], gl.normals[v], cpu.normals[i]
                ));
            }
            max_p = max_p.max(dp);
            max_n = max_n.max(dn);
            *slot = i as u32;
        }
        gl_tris.push(rotate(tri));
    }
    let mut cpu_tris: Vec<[u32; 3]> = cpu.triangles.iter().map(|&t| rotate(t)).collect();
    gl_tris.sort_unstable();
    cpu_tris.sort_unstable();
    if let Some((a, b)) = gl_tris.iter().zip(&cpu_tris).find(|(a, b)| a != b) {
        return Err(format!(
            "the triangles differ: GL has {a:?} where the CPU has {b:?} (CPU vertex indices)"
        ));
    }
    Ok(Comparison {
        triangles: gl_tris.len(),
        max_position_error: max_p,
        max_normal_error: max_n,
    })
}

/// The rotation of `t` that starts with its smallest index (winding kept).
fn rotate(t: [u32; 3]) -> [u32; 3] {
    let m = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
    [t[m], t[(m + 1) % 3], t[(m + 2) % 3]]
}
