//! Shape tags: creases and per-vertex shape parameters for the scalar-tagged PN scheme (GMR
//! Appendix B) and sharp edges for PNG1 (section 3.4).
//!
//! Tags are keyed by *position* (the lowest vertex index at a position, see
//! [`crate::mesh::topology::position_ids`]), so a tag set on one copy of a split vertex applies to
//! every copy, and an edge tag applies to the edge between two positions whichever vertices the
//! two sides use.
//!
//! # Where tags come from
//!
//! - [`Tags::from_split_normals`]: edges whose two sides use different normals (hard edges in
//!   the file) become creases (sharpness 1), and vertices on exactly one crease get a crease
//!   direction `Δ` and sharpness that reproduce the file's two normals.
//! - [`Tags::from_crease_angle`]: the same for edges whose two faces bend by more than an angle.
//! - [`Tags::set_vertex`], [`Tags::set_edge`] for one tag, [`TagBuilder`] for many: tags by
//!   vertex index, checked against the mesh. Files (a sidecar JSON, PLY properties) are read by
//!   `tessella_io::tags`, which also layers all these sources the way the CLI and the Python
//!   package use them.
//!
//! # What the numbers mean
//!
//! - Edge `sharpness` `δ ∈ [0, 1]`: how much of a crease the edge is (GMR Appendix B); for PNG1
//!   any `δ > 0` makes the edge sharp. `kappa`: PNG1's crease displacement `κ` (along the
//!   triangle normal, in model units; the paper uses -0.1, -0.2).
//! - Vertex `tension` `θ` (0: PN's thirds; positive pulls the edge points towards the vertex),
//!   `sharpness` `σ ∈ [-1, 1]` (how far the two sides' normals tilt by `±Δ`; negative for a
//!   valley), `bias` `β` (shifts the crease along `Δ`), `crease` `Δ`: a vector across the crease,
//!   in the tangent plane, pointing into the side whose normal tilts towards it.
//!
//! ```
//! use tessella_core::{samples, tags::{EdgeTag, TagBuilder}};
//! let mesh = samples::tetrahedron();
//! let mut tags = TagBuilder::new(&mesh);
//! tags.set_edge([0, 1], EdgeTag { sharpness: 1.0, kappa: 0.0 })?;
//! assert!(tags.set_edge([0, 9], EdgeTag::default()).is_err());
//! let tags = tags.finish();
//! assert_eq!(tags.edge_count(), 1);
//! # Ok::<(), tessella_core::tags::TagError>(())
//! ```

pub use crate::error::TagError;

use crate::mesh::topology::{across_edge, position_ids, NO_NEIGHBOR};
use crate::mesh::{Mesh, Topology};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

/// Per-vertex shape parameters (GMR Appendix B); all zero is plain PN.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct VertexTag {
    /// Tension `θ`.
    pub tension: f32,
    /// Sharpness `σ` in `[-1, 1]`.
    pub sharpness: f32,
    /// Bias `β`.
    pub bias: f32,
    /// Crease direction `Δ` (zero: no crease through the vertex).
    pub crease: [f32; 3],
}

impl VertexTag {
    /// True when the vertex carries a crease direction.
    pub fn has_crease(&self) -> bool {
        self.crease != [0.0; 3]
    }
}

/// Per-edge tags.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct EdgeTag {
    /// Crease amount `δ` in `[0, 1]` (scalar-tagged PN); `> 0` is sharp for PNG1.
    pub sharpness: f32,
    /// PNG1's crease displacement `κ`.
    pub kappa: f32,
}

/// Tags of one mesh, keyed by position (see the module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tags {
    vertices: BTreeMap<u32, VertexTag>,
    edges: BTreeMap<[u32; 2], EdgeTag>,
}

fn finite(what: impl Fn() -> String, value: f32) -> Result<(), TagError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(TagError::NotFinite {
            what: what(),
            value,
        })
    }
}

impl Tags {
    /// No tags.
    pub fn new() -> Tags {
        Tags::default()
    }

    /// Adds `other`'s tags; where both tag the same vertex or edge, `other` wins. Lets tags from
    /// several sources (split normals, a crease angle, a file) be layered.
    pub fn merge(&mut self, other: Tags) {
        self.vertices.extend(other.vertices);
        self.edges.extend(other.edges);
    }

    /// True when nothing is tagged.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.edges.is_empty()
    }
    /// Number of tagged edges.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }
    /// Number of tagged positions.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// The tag of position `pid` (zero when untagged).
    pub fn vertex(&self, pid: u32) -> VertexTag {
        self.vertices.get(&pid).copied().unwrap_or_default()
    }
    /// The tag of the edge between positions `a` and `b` (zero when untagged).
    pub fn edge(&self, a: u32, b: u32) -> EdgeTag {
        self.edges
            .get(&[a.min(b), a.max(b)])
            .copied()
            .unwrap_or_default()
    }

    /// Tags vertex `v` of `mesh` (replacing an earlier tag at its position). Finding the
    /// position costs a pass over the vertices; [`TagBuilder`] sets many tags in linear time.
    pub fn set_vertex(&mut self, mesh: &Mesh, v: u32, tag: VertexTag) -> Result<(), TagError> {
        check_vertex(mesh, v, &tag)?;
        self.vertices.insert(position_id(mesh.positions(), v), tag);
        Ok(())
    }

    /// Tags the edge between vertices `a` and `b` of `mesh`; it must be an edge with exactly two
    /// faces (by position). Finding its faces costs a pass over the mesh; [`TagBuilder`] sets
    /// many tags in linear time.
    pub fn set_edge(&mut self, mesh: &Mesh, ends: [u32; 2], tag: EdgeTag) -> Result<(), TagError> {
        let mut one = TagBuilder::new(mesh);
        one.set_edge(ends, tag)?;
        self.merge(one.finish());
        Ok(())
    }

    /// Creases where the file splits normals: every edge (by position) whose two faces use
    /// different normals at either end gets sharpness 1; vertices on exactly one crease get a
    /// crease direction reproducing the two sides' normals (see [`Tags::from_crease_angle`]).
    pub fn from_split_normals(mesh: &Mesh) -> Tags {
        let normal = |v: u32| mesh.normals()[v as usize];
        Tags::creases_where(mesh, |topo, f, k| {
            let t = mesh.triangles()[f];
            across_edge(mesh, topo, f, k).is_some_and(|x| {
                normal(x.at_a) != normal(t[k]) || normal(x.at_b) != normal(t[(k + 1) % 3])
            })
        })
    }

    /// Creases where adjacent faces bend by more than `degrees` (their unit normals differ by
    /// more than that angle), sharpness 1; vertices on exactly one crease get a crease direction.
    pub fn from_crease_angle(mesh: &Mesh, degrees: f32) -> Result<Tags, TagError> {
        if !degrees.is_finite() || !(0.0..=180.0).contains(&degrees) {
            return Err(TagError::BadAngle(degrees));
        }
        let cos = degrees.to_radians().cos();
        Ok(Tags::creases_where(mesh, |topo, f, k| {
            let g = topo.neighbors[f][k];
            g != NO_NEIGHBOR
                && (g as usize) > f
                && face_normal(mesh, f).dot(face_normal(mesh, g as usize)) < cos
        }))
    }

    /// Full creases (sharpness 1) on every edge `k` of face `f` for which `is_crease` holds,
    /// keyed by position, plus the crease directions at their vertices.
    fn creases_where(mesh: &Mesh, is_crease: impl Fn(&Topology, usize, usize) -> bool) -> Tags {
        let topo = mesh.topology();
        let mut tags = Tags::new();
        for f in 0..mesh.face_count() {
            let t = mesh.triangles()[f];
            for k in 0..3 {
                if is_crease(&topo, f, k) {
                    let a = topo.position_ids[t[k] as usize];
                    let b = topo.position_ids[t[(k + 1) % 3] as usize];
                    let tag = EdgeTag {
                        sharpness: 1.0,
                        kappa: 0.0,
                    };
                    tags.edges.insert([a.min(b), a.max(b)], tag);
                }
            }
        }
        tags.add_crease_directions(mesh, &topo);
        tags
    }

    /// For positions with exactly two creased edges: `Δ` across the crease in the tangent plane
    /// and `σ = ±1` so that `normalize(N̄ ± σΔ)` gives the mean normal of each side's faces
    /// (`N̄` the mean of the two), `σ < 0` for a valley.
    fn add_crease_directions(&mut self, mesh: &Mesh, topo: &Topology) {
        let mut creased: HashMap<u32, Vec<u32>> = HashMap::new();
        for [a, b] in self.edges.keys().copied() {
            creased.entry(a).or_default().push(b);
            creased.entry(b).or_default().push(a);
        }
        let pos = |pid: u32| Vec3::from(mesh.positions()[pid as usize]);
        let mut around: HashMap<u32, Vec<usize>> = HashMap::new();
        for (f, t) in mesh.triangles().iter().enumerate() {
            for &v in t {
                let p = topo.position_ids[v as usize];
                if creased.contains_key(&p) {
                    around.entry(p).or_default().push(f);
                }
            }
        }
        for (&p, ends) in &creased {
            if ends.len() != 2 {
                continue;
            }
            let here = pos(p);
            let along = (pos(ends[1]) - pos(ends[0])).normalize_or_zero();
            // Faces around the position, split by the plane through the crease.
            let (mut sum_a, mut sum_b, mut sum) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
            let faces = &around[&p];
            for &f in faces {
                sum += face_normal(mesh, f);
            }
            let across = sum.normalize_or_zero().cross(along).normalize_or_zero();
            for &f in faces {
                let [a, b, c] = mesh.corner_positions(f);
                let side = ((a + b + c) / 3.0 - here).dot(across);
                if side >= 0.0 {
                    sum_a += face_normal(mesh, f);
                } else {
                    sum_b += face_normal(mesh, f);
                }
            }
            let (na, nb) = (sum_a.normalize_or_zero(), sum_b.normalize_or_zero());
            let mean = (na + nb).normalize_or_zero();
            if na == Vec3::ZERO || nb == Vec3::ZERO || mean == Vec3::ZERO {
                continue;
            }
            // n / (n . N̄) = N̄ + t: t is the tangential offset that tilts N̄ onto n.
            let offset = na / na.dot(mean) - mean;
            let (crease, sharpness) = if offset.dot(across) >= 0.0 {
                (offset, 1.0)
            } else {
                (-offset, -1.0)
            };
            if crease.length() > 1e-6 && crease.is_finite() {
                self.vertices.insert(
                    p,
                    VertexTag {
                        crease: crease.into(),
                        sharpness,
                        ..Default::default()
                    },
                );
            }
        }
    }

    /// Checks the scalar-tagged scheme's restrictions (GMR Appendix B): at most one crease (two
    /// creased edges) through a vertex, at most two vertices with a crease direction per
    /// triangle.
    pub fn validate_scalar_tagged(&self, mesh: &Mesh, topo: &Topology) -> Result<(), TagError> {
        let mut count: HashMap<u32, usize> = HashMap::new();
        for (&[a, b], tag) in &self.edges {
            if tag.sharpness > 0.0 {
                *count.entry(a).or_default() += 1;
                *count.entry(b).or_default() += 1;
            }
        }
        if let Some((&vertex, &count)) = count.iter().filter(|(_, &c)| c > 2).min() {
            return Err(TagError::TooManyCreases { vertex, count });
        }
        for (face, t) in mesh.triangles().iter().enumerate() {
            let count = t
                .iter()
                .filter(|&&v| self.vertex(topo.position_ids[v as usize]).has_crease())
                .count();
            if count > 2 {
                return Err(TagError::TooManyCreasedVertices { face, count });
            }
        }
        Ok(())
    }
}

/// Checks a vertex tag's index and numbers.
fn check_vertex(mesh: &Mesh, v: u32, tag: &VertexTag) -> Result<(), TagError> {
    let count = mesh.vertex_count();
    if v as usize >= count {
        return Err(TagError::UnknownVertex {
            what: "vertex tag".into(),
            vertex: v,
            count,
        });
    }
    let name = |field: &'static str| move || format!("vertex {v} {field}");
    finite(name("tension"), tag.tension)?;
    finite(name("sharpness"), tag.sharpness)?;
    finite(name("bias"), tag.bias)?;
    for c in tag.crease {
        finite(name("crease"), c)?;
    }
    if !(-1.0..=1.0).contains(&tag.sharpness) {
        return Err(TagError::OutOfRange {
            what: format!("vertex {v} sharpness"),
            value: tag.sharpness,
            range: "-1..=1",
        });
    }
    Ok(())
}

/// Checks an edge tag's indices and numbers (not yet that it is an edge).
fn check_edge(mesh: &Mesh, [a, b]: [u32; 2], tag: &EdgeTag) -> Result<(), TagError> {
    let count = mesh.vertex_count();
    for v in [a, b] {
        if v as usize >= count {
            return Err(TagError::UnknownVertex {
                what: "edge tag".into(),
                vertex: v,
                count,
            });
        }
    }
    finite(|| format!("edge {a}-{b} sharpness"), tag.sharpness)?;
    finite(|| format!("edge {a}-{b} kappa"), tag.kappa)?;
    if !(0.0..=1.0).contains(&tag.sharpness) {
        return Err(TagError::OutOfRange {
            what: format!("edge {a}-{b} sharpness"),
            value: tag.sharpness,
            range: "0..=1",
        });
    }
    Ok(())
}

/// The position id of vertex `v` (the lowest index with its position, as [`position_ids`]),
/// found by one scan.
fn position_id(positions: &[[f32; 3]], v: u32) -> u32 {
    let key = |p: &[f32; 3]| p.map(|c| (c + 0.0).to_bits());
    let own = key(&positions[v as usize]);
    positions[..v as usize]
        .iter()
        .position(|p| key(p) == own)
        .map_or(v, |i| i as u32)
}

/// Sets many tags on one mesh with the checks of [`Tags::set_vertex`] and [`Tags::set_edge`],
/// each in constant time (for meshes of bounded valence): the position ids are found once, and
/// the faces around each position once, on the first edge tag. Tags for a mesh of `V` vertices
/// and `F` faces cost `O(V + F)` plus `O(1)` a tag.
///
/// ```
/// use tessella_core::{samples, tags::{TagBuilder, TagError, VertexTag}};
/// let mesh = samples::tetrahedron();
/// let mut tags = TagBuilder::new(&mesh);
/// tags.set_vertex(2, VertexTag { tension: 0.5, ..Default::default() })?;
/// let bad = VertexTag { sharpness: 2.0, ..Default::default() };
/// assert!(matches!(tags.set_vertex(1, bad), Err(TagError::OutOfRange { .. })));
/// assert_eq!(tags.finish().vertex_count(), 1);
/// # Ok::<(), TagError>(())
/// ```
#[derive(Debug)]
pub struct TagBuilder<'m> {
    mesh: &'m Mesh,
    position_ids: Vec<u32>,
    /// Faces around each position id, compressed rows: the faces at position `p` are
    /// `faces[start[p]..start[p + 1]]`. Built on the first edge tag.
    faces_at: Option<(Vec<u32>, Vec<u32>)>,
    tags: Tags,
}

impl<'m> TagBuilder<'m> {
    /// No tags yet, for `mesh`.
    pub fn new(mesh: &'m Mesh) -> TagBuilder<'m> {
        TagBuilder {
            mesh,
            position_ids: position_ids(mesh.positions()),
            faces_at: None,
            tags: Tags::new(),
        }
    }

    /// Tags vertex `v` (replacing an earlier tag at its position); see [`Tags::set_vertex`].
    pub fn set_vertex(&mut self, v: u32, tag: VertexTag) -> Result<(), TagError> {
        check_vertex(self.mesh, v, &tag)?;
        self.tags
            .vertices
            .insert(self.position_ids[v as usize], tag);
        Ok(())
    }

    /// Tags the edge between vertices `a` and `b`; see [`Tags::set_edge`].
    pub fn set_edge(&mut self, [a, b]: [u32; 2], tag: EdgeTag) -> Result<(), TagError> {
        check_edge(self.mesh, [a, b], &tag)?;
        let (pa, pb) = (self.position_ids[a as usize], self.position_ids[b as usize]);
        match self.edge_faces(pa, pb) {
            0 => return Err(TagError::NotAnEdge { a, b }),
            2 => {}
            _ => return Err(TagError::BoundaryEdge { a, b }),
        }
        self.tags.edges.insert([pa.min(pb), pa.max(pb)], tag);
        Ok(())
    }

    /// The tags set so far.
    pub fn finish(self) -> Tags {
        self.tags
    }

    /// Number of faces on the edge between positions `pa` and `pb` (0: not an edge).
    fn edge_faces(&mut self, pa: u32, pb: u32) -> usize {
        if pa == pb {
            return 0;
        }
        let (mesh, ids) = (self.mesh, &self.position_ids);
        let (start, faces) = self.faces_at.get_or_insert_with(|| {
            let mut start = vec![0u32; ids.len() + 1];
            for t in mesh.triangles() {
                for &v in t {
                    start[ids[v as usize] as usize + 1] += 1;
                }
            }
            for p in 0..ids.len() {
                start[p + 1] += start[p];
            }
            let mut next = start.clone();
            let mut faces = vec![0u32; start[ids.len()] as usize];
            for (f, t) in mesh.triangles().iter().enumerate() {
                for &v in t {
                    let slot = &mut next[ids[v as usize] as usize];
                    faces[*slot as usize] = f as u32;
                    *slot += 1;
                }
            }
            (start, faces)
        });
        let around = &faces[start[pa as usize] as usize..start[pa as usize + 1] as usize];
        // Corners of a triangle are distinct positions (Mesh::new refuses zero area), so a face
        // at `pa` that has `pb` has the edge.
        around
            .iter()
            .filter(|&&f| {
                mesh.triangles()[f as usize]
                    .iter()
                    .any(|&v| ids[v as usize] == pb)
            })
            .count()
    }
}

fn face_normal(mesh: &Mesh, f: usize) -> Vec3 {
    let [a, b, c] = mesh.corner_positions(f);
    (b - a).cross(c - a).normalize_or_zero()
}
