//! Solution fields through refinement: per-vertex arrays (temperature, displacement, stress at
//! the nodes) carried to the refined vertices with each element's own basis, and per-face arrays
//! copied to the refined triangles.
//!
//! A point-data array of width `w` holds `w` values per coarse vertex, vertex-major. A refined
//! vertex that came from face `f` at barycentric `l` ([`Plan::origin`]) gets
//!
//! - linear faces: `Σ l_i d(P_i)` (P1);
//! - second-order faces ([`Mesh::with_mid_nodes`]): `Σ l_i (2 l_i − 1) d(P_i) + Σ 4 l_i l_j d(M_ij)`
//!   (P2, [`crate::mesh::quadratic::shape_functions`]),
//!
//! in f64, rounded once. A coarse vertex no face uses keeps its own value. Cell data of face `f`
//! is copied to each refined triangle of `f` ([`triangle_faces`]).

use crate::mesh::quadratic::shape_functions;
use crate::mesh::Mesh;
use crate::refine::{Plan, NO_FACE};
use thiserror::Error;

/// A field that cannot be carried through refinement: which one, and why.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum FieldError {
    #[error("field {name:?} has width 0; give at least one value per {per}")]
    ZeroWidth { name: String, per: &'static str },
    #[error("field {name:?} has {got} values, but {count} {per}s × width {width} need {expected}")]
    WrongLength {
        name: String,
        got: usize,
        count: usize,
        width: usize,
        expected: usize,
        per: &'static str,
    },
    #[error(
        "field {name:?} has the non-finite value {value} at {per} {index} (component {component})"
    )]
    NonFinite {
        name: String,
        index: usize,
        component: usize,
        value: f32,
        per: &'static str,
    },
}

fn check(
    name: &str,
    data: &[f32],
    width: usize,
    count: usize,
    per: &'static str,
) -> Result<(), FieldError> {
    if width == 0 {
        return Err(FieldError::ZeroWidth {
            name: name.into(),
            per,
        });
    }
    let expected = count * width;
    if data.len() != expected {
        return Err(FieldError::WrongLength {
            name: name.into(),
            got: data.len(),
            count,
            width,
            expected,
            per,
        });
    }
    if let Some(i) = data.iter().position(|x| !x.is_finite()) {
        return Err(FieldError::NonFinite {
            name: name.into(),
            index: i / width,
            component: i % width,
            value: data[i],
            per,
        });
    }
    Ok(())
}

/// Checks point data of `mesh` as [`interpolate_point_data`] does (`mesh.vertex_count() ×
/// width` finite values, width 1 or more), for callers that interpolate it piece by piece
/// with [`interpolate_into`].
pub fn check_point_data(
    mesh: &Mesh,
    name: &str,
    data: &[f32],
    width: usize,
) -> Result<(), FieldError> {
    check(name, data, width, mesh.vertex_count(), "vertex")
}

/// Point data of `mesh` (the plan's first mesh, or any mesh of its topology: mid-edge nodes are
/// read from it) at every refined vertex of `plan`, `width` values each, in output order.
///
/// Errors: width 0, a length other than `mesh.vertex_count() × width`, a NaN or infinity — each
/// naming the field `name`.
pub fn interpolate_point_data(
    mesh: &Mesh,
    plan: &Plan,
    name: &str,
    data: &[f32],
    width: usize,
) -> Result<Vec<f32>, FieldError> {
    check(name, data, width, mesh.vertex_count(), "vertex")?;
    let (faces, bary) = plan.origin();
    Ok(interpolate_with_origin(mesh, &faces, &bary, data, width))
}

/// [`interpolate_point_data`] from an origin already computed (`faces`, `bary` of
/// [`Plan::origin`]), for several fields of one refinement; `data` must have been checked
/// (`mesh.vertex_count() × width` finite values).
pub fn interpolate_with_origin(
    mesh: &Mesh,
    faces: &[u32],
    bary: &[[f32; 3]],
    data: &[f32],
    width: usize,
) -> Vec<f32> {
    let mut out = vec![0.0f32; faces.len() * width];
    interpolate_into(mesh, 0, faces, bary, data, width, &mut out);
    out
}

/// [`interpolate_with_origin`] for a run of refined vertices that starts at output vertex
/// `first` (a piece of a streamed refinement: [`Plan::write_piece_origin`]), into `out`
/// (`faces.len() × width` values).
pub fn interpolate_into(
    mesh: &Mesh,
    first: usize,
    faces: &[u32],
    bary: &[[f32; 3]],
    data: &[f32],
    width: usize,
    out: &mut [f32],
) {
    let value = |v: u32, c: usize| data[v as usize * width + c] as f64;
    for (i, ((&f, l), dst)) in faces
        .iter()
        .zip(bary)
        .zip(out.chunks_mut(width))
        .enumerate()
    {
        if f == NO_FACE {
            // Only coarse vertices have no face, and they come first: output vertex = input.
            let v = first + i;
            dst.copy_from_slice(&data[v * width..(v + 1) * width]);
            continue;
        }
        let t = mesh.triangles()[f as usize];
        let l = l.map(f64::from);
        match mesh.face_mid_nodes(f as usize) {
            None => {
                for (c, d) in dst.iter_mut().enumerate() {
                    *d = (l[0] * value(t[0], c) + l[1] * value(t[1], c) + l[2] * value(t[2], c))
                        as f32;
                }
            }
            Some(m) => {
                let n = shape_functions(l);
                let nodes = [t[0], t[1], t[2], m[0], m[1], m[2]];
                for (c, d) in dst.iter_mut().enumerate() {
                    *d = nodes
                        .iter()
                        .zip(n)
                        .map(|(&i, w)| w * value(i, c))
                        .sum::<f64>() as f32;
                }
            }
        }
    }
}

/// The coarse face of every refined triangle of `plan`, in output order.
pub fn triangle_faces(plan: &Plan) -> Vec<u32> {
    let mut out = Vec::with_capacity(plan.triangle_count());
    match plan.tiling() {
        Some(tiling) => {
            for (f, w) in tiling.triangle_offset.windows(2).enumerate() {
                out.extend(std::iter::repeat_n(f as u32, (w[1] - w[0]) as usize));
            }
        }
        None => {
            let per = plan.pattern().triangles.len();
            for f in 0..plan.face_count() {
                out.extend(std::iter::repeat_n(f as u32, per));
            }
        }
    }
    debug_assert_eq!(out.len(), plan.triangle_count());
    out
}

/// Cell data (`width` values per coarse face) copied to every refined triangle of `plan`.
///
/// Errors: width 0, a length other than `plan.face_count() × width`, a NaN or infinity — each
/// naming the field `name`.
pub fn copy_cell_data(
    plan: &Plan,
    name: &str,
    data: &[f32],
    width: usize,
) -> Result<Vec<f32>, FieldError> {
    check(name, data, width, plan.face_count(), "face")?;
    let mut out = Vec::with_capacity(plan.triangle_count() * width);
    for f in triangle_faces(plan) {
        let f = f as usize;
        out.extend_from_slice(&data[f * width..(f + 1) * width]);
    }
    Ok(out)
}

/// Point data of `mesh` (one value per vertex) as six values per face, the face's P2 net:
/// its corners' values, then its mid-edge nodes' (edges 0-1, 1-2, 2-0) for second-order faces,
/// the edges' mean values for linear faces (so the P2 shape functions give the P1
/// interpolation there). `Σ N_k(l) net_k` is then [`interpolate_point_data`]'s value at `l`
/// for either kind of face: renderers interpolate it per pattern point from coarse data only.
///
/// Errors: as [`interpolate_point_data`] with width 1.
pub fn face_nets(mesh: &Mesh, name: &str, data: &[f32]) -> Result<Vec<f32>, FieldError> {
    check(name, data, 1, mesh.vertex_count(), "vertex")?;
    let mut out = Vec::with_capacity(mesh.face_count() * 6);
    for (f, t) in mesh.triangles().iter().enumerate() {
        let c = t.map(|v| data[v as usize]);
        out.extend(c);
        match mesh.face_mid_nodes(f) {
            Some(m) => out.extend(m.map(|v| data[v as usize])),
            None => out.extend(
                [0, 1, 2].map(|k| ((f64::from(c[k]) + f64::from(c[(k + 1) % 3])) / 2.0) as f32),
            ),
        }
    }
    Ok(out)
}
