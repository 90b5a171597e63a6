//! The coarse input: positions, unit normals, optional UVs and counter-clockwise triangles.
//!
//! A [`Mesh`] is validated when it is built ([`Mesh::new`]): every later stage may assume finite
//! coordinates, indices in range, no degenerate triangles and unit normals. Normals missing from
//! the input are computed, each vertex's the angle-weighted sum of its triangles' normals.
//!
//! A *vertex* is one (position, normal, uv) combination: a file that gives one position two
//! normals (a hard edge) has two vertices there. Refined output shares exactly what the input
//! shares: two triangles that use the same vertex index share their refined edge.

mod normals;
pub mod quadratic;
pub mod topology;

use crate::error::MeshError;
use glam::Vec3;

pub use quadratic::NO_MID;
pub use topology::{Topology, TopologyReport};

/// A validated triangle mesh. Build it with [`Mesh::new`]; fields are read-only afterwards.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    triangles: Vec<[u32; 3]>,
    normals_computed: bool,
    /// Second-order faces: per face, the mid-edge nodes of edges 0-1, 1-2, 2-0 (indices into
    /// the positions), or [`NO_MID`] for a linear face ([`Mesh::with_mid_nodes`]).
    mid_nodes: Option<Vec<[u32; 3]>>,
}

impl Mesh {
    /// Validates the arrays and builds a mesh.
    ///
    /// - `positions`: #V points.
    /// - `normals`: #V normals or `None` to compute them (each vertex's the angle-weighted sum
    ///   of its triangles' normals).
    ///   Given normals are normalised; a zero or non-finite one is an error.
    /// - `uvs`: #V texture coordinates or `None`.
    /// - `triangles`: #F corner indices, counter-clockwise seen from the side the normals face.
    ///
    /// ```
    /// use tessella_core::Mesh;
    /// let mesh = Mesh::new(
    ///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    ///     None,
    ///     None,
    ///     vec![[0, 1, 2]],
    /// )?;
    /// assert_eq!(mesh.normals()[0], [0.0, 0.0, 1.0]);
    /// # Ok::<(), tessella_core::MeshError>(())
    /// ```
    pub fn new(
        positions: Vec<[f32; 3]>,
        normals: Option<Vec<[f32; 3]>>,
        uvs: Option<Vec<[f32; 2]>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        let count = positions.len();
        if count > u32::MAX as usize {
            return Err(MeshError::TooManyVertices {
                count,
                max: u32::MAX as usize,
            });
        }
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        check_finite(&positions)?;
        for (face, t) in triangles.iter().enumerate() {
            for &index in t {
                if index as usize >= count {
                    return Err(MeshError::IndexOutOfRange { face, index, count });
                }
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                let index = if t[0] == t[1] || t[0] == t[2] {
                    t[0]
                } else {
                    t[1]
                };
                return Err(MeshError::RepeatedIndex {
                    face,
                    index,
                    indices: *t,
                });
            }
            if has_zero_area(&positions, *t) {
                return Err(MeshError::ZeroArea { face });
            }
        }
        if let Some(uvs) = &uvs {
            check_count("uvs", uvs.len(), count)?;
            for (vertex, uv) in uvs.iter().enumerate() {
                if !uv.iter().all(|c| c.is_finite()) {
                    return Err(MeshError::NonFiniteUv { vertex, value: *uv });
                }
            }
        }
        let (normals, normals_computed) = match normals {
            Some(given) => {
                check_count("normals", given.len(), count)?;
                (normals::normalized(given)?, false)
            }
            None => (normals::angle_weighted(&positions, &triangles), true),
        };
        Ok(Mesh {
            positions,
            normals,
            uvs,
            triangles,
            normals_computed,
            mid_nodes: None,
        })
    }

    /// Vertex positions, #V.
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }
    /// Unit vertex normals, #V.
    pub fn normals(&self) -> &[[f32; 3]] {
        &self.normals
    }
    /// Texture coordinates, #V, when the input had them.
    pub fn uvs(&self) -> Option<&[[f32; 2]]> {
        self.uvs.as_deref()
    }
    /// Counter-clockwise triangles, #F.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }
    /// True when the normals were computed because the input had none.
    pub fn normals_computed(&self) -> bool {
        self.normals_computed
    }
    /// The three corner positions of face `f`.
    pub fn corner_positions(&self, f: usize) -> [Vec3; 3] {
        self.triangles[f].map(|i| Vec3::from(self.positions[i as usize]))
    }
    /// The three corner normals of face `f`.
    pub fn corner_normals(&self, f: usize) -> [Vec3; 3] {
        self.triangles[f].map(|i| Vec3::from(self.normals[i as usize]))
    }
    /// Axis-aligned bounds `(min, max)` of the positions.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        bounds(&self.positions)
    }
    /// Length of the bounding box's diagonal: the scale tolerances are measured against.
    pub fn diagonal(&self) -> f32 {
        let (lo, hi) = self.bounds();
        (Vec3::from(hi) - Vec3::from(lo)).length()
    }
    /// Edge adjacency, boundary and non-manifold edges, split normals (computed on demand).
    pub fn topology(&self) -> Topology {
        Topology::new(self)
    }

    /// Moves the vertices of this mesh: the same triangles (and UVs) with new `positions` and,
    /// optionally, new `normals` — one frame of a deforming mesh.
    ///
    /// The new data is checked as [`Mesh::new`] checks it (one position per vertex, finite,
    /// no triangle of zero area; given normals finite and non-zero, then normalised). Without
    /// `normals`, they are recomputed angle-weighted, as [`Mesh::new`] does (smooth across
    /// split vertices: pass normals to keep hard edges). On error `self` is left unchanged.
    ///
    /// ```
    /// use tessella_core::{samples, MeshError};
    /// let mut mesh = samples::icosphere(1);
    /// let bigger: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| 2.0 * c)).collect();
    /// mesh.update(&bigger, None)?;
    /// assert_eq!(mesh.positions()[0], bigger[0]);
    /// let mut bad = bigger.clone();
    /// bad[3][1] = f32::NAN;
    /// assert!(matches!(mesh.update(&bad, None), Err(MeshError::NonFinitePosition { vertex: 3, .. })));
    /// assert_eq!(mesh.positions()[3], bigger[3]); // untouched
    /// # Ok::<(), MeshError>(())
    /// ```
    pub fn update(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<(), MeshError> {
        let count = self.positions.len();
        check_count("positions", positions.len(), count)?;
        check_finite(positions)?;
        if let Some(face) = self
            .triangles
            .iter()
            .position(|&t| has_zero_area(positions, t))
        {
            return Err(MeshError::ZeroArea { face });
        }
        if let Some(mids) = &self.mid_nodes {
            quadratic::check_inverted(positions, &self.triangles, mids)?;
        }
        let new_normals = match normals {
            Some(given) => {
                check_count("normals", given.len(), count)?;
                normals::normalized(given.to_vec())?
            }
            None => normals::angle_weighted(positions, &self.triangles),
        };
        self.positions.copy_from_slice(positions);
        self.normals = new_normals;
        self.normals_computed = normals.is_none();
        Ok(())
    }
}

/// Coordinates up to this magnitude refine without overflow: control points are sums of a few
/// multiples of positions, and normals come from products of their differences.
pub const MAX_COORDINATE: f32 = 1e15;

/// `MeshError::AttributeCount` unless there are `got` of `what` for the mesh's `expected`
/// vertices.
fn check_count(what: &'static str, got: usize, expected: usize) -> Result<(), MeshError> {
    if got != expected {
        return Err(MeshError::AttributeCount {
            what,
            got,
            expected,
        });
    }
    Ok(())
}

/// The first non-finite or too large position, as an error.
fn check_finite(positions: &[[f32; 3]]) -> Result<(), MeshError> {
    if let Some(vertex) = positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(MeshError::NonFinitePosition {
            vertex,
            value: positions[vertex],
        });
    }
    match positions
        .iter()
        .position(|p| p.iter().any(|c| c.abs() > MAX_COORDINATE))
    {
        Some(vertex) => Err(MeshError::PositionTooLarge {
            vertex,
            value: positions[vertex],
            max: MAX_COORDINATE,
        }),
        None => Ok(()),
    }
}

/// True when triangle `t` has no area: a repeated corner, or corners that are collinear or
/// coincide ([`has_zero_area`]). Valid glTF, refused by [`Mesh::new`]. Indices must be in range.
pub fn is_degenerate(positions: &[[f32; 3]], t: [u32; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || has_zero_area(positions, t)
}

/// True when triangle `t`'s corners are collinear or coincide (its cross product is exactly zero
/// in f64). Indices must be in range.
pub fn has_zero_area(positions: &[[f32; 3]], t: [u32; 3]) -> bool {
    let [a, b, c] = t.map(|i| Vec3::from(positions[i as usize]).as_dvec3());
    (b - a).cross(c - a).length_squared() == 0.0
}

/// Axis-aligned bounds of a point set; `([0;3],[0;3])` when it is empty.
pub fn bounds(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    if points.is_empty() {
        return ([0.0; 3], [0.0; 3]);
    }
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in points {
        lo = lo.min(Vec3::from(*p));
        hi = hi.max(Vec3::from(*p));
    }
    (lo.into(), hi.into())
}

/// Bounds that hold every curved patch over `triangles` of a scheme whose control points lie
/// within `reach` longest edges of their flat triangle ([`crate::Scheme::control_reach`]): the
/// union of each triangle's box grown by `reach` times its own longest edge on every side (a
/// patch lies in its control net's convex hull). What an engine culls a pose by without
/// building its nets: the coarse vertices skinned on the CPU, positions only. An index past
/// `points` is an error; no triangles give the empty box at the origin.
pub fn patch_bounds(
    points: &[[f32; 3]],
    triangles: &[[u32; 3]],
    reach: f32,
) -> Result<([f32; 3], [f32; 3]), MeshError> {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (face, t) in triangles.iter().enumerate() {
        let corner = |i: u32| {
            points
                .get(i as usize)
                .map(|p| Vec3::from(*p))
                .ok_or(MeshError::IndexOutOfRange {
                    face,
                    index: i,
                    count: points.len(),
                })
        };
        let [a, b, c] = [corner(t[0])?, corner(t[1])?, corner(t[2])?];
        let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
        let grow = Vec3::splat(reach.abs() * longest);
        lo = lo.min(a.min(b).min(c) - grow);
        hi = hi.max(a.max(b).max(c) + grow);
    }
    if triangles.is_empty() {
        return Ok(([0.0; 3], [0.0; 3]));
    }
    Ok((lo.into(), hi.into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        (
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        )
    }

    #[test]
    fn rejects_bad_input_with_named_problem() {
        let (p, t) = tri();
        let mut nan = p.clone();
        nan[1][2] = f32::NAN;
        assert!(matches!(
            Mesh::new(nan, None, None, t.clone()),
            Err(MeshError::NonFinitePosition { vertex: 1, .. })
        ));
        assert!(matches!(
            Mesh::new(p.clone(), None, None, vec![[0, 1, 3]]),
            Err(MeshError::IndexOutOfRange {
                face: 0,
                index: 3,
                count: 3
            })
        ));
        assert!(matches!(
            Mesh::new(p.clone(), None, None, vec![[0, 1, 1]]),
            Err(MeshError::RepeatedIndex { .. })
        ));
        let collinear = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert!(matches!(
            Mesh::new(collinear, None, None, t.clone()),
            Err(MeshError::ZeroArea { face: 0 })
        ));
        let zero_n = vec![[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(matches!(
            Mesh::new(p.clone(), Some(zero_n), None, t.clone()),
            Err(MeshError::ZeroNormal { vertex: 1 })
        ));
        assert!(matches!(
            Mesh::new(p.clone(), None, None, vec![]),
            Err(MeshError::NoTriangles)
        ));
        assert!(matches!(
            Mesh::new(p, None, Some(vec![[0.0; 2]; 2]), t),
            Err(MeshError::AttributeCount {
                what: "uvs",
                got: 2,
                expected: 3
            })
        ));
    }

    #[test]
    fn given_normals_are_normalised() {
        let (p, t) = tri();
        let mesh = Mesh::new(
            p,
            Some(vec![[0.0, 0.0, 2.0], [0.0, 3.0, 4.0], [1.0, 0.0, 0.0]]),
            None,
            t,
        )
        .unwrap();
        assert_eq!(mesh.normals()[1], [0.0, 0.6, 0.8]);
        assert!(!mesh.normals_computed());
    }
}
