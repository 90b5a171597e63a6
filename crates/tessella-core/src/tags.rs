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
//! - [`Tags::from_json`]: a sidecar file, format below.
//! - [`Tags::from_ply`]: PLY properties as plain data (vertex `tension`, `sharpness`, `bias`,
//!   optional `crease_x/y/z`; `edge` elements with `vertex1`, `vertex2`, `sharpness`, optional
//!   `kappa`).
//!
//! # Sidecar JSON
//!
//! ```json
//! {
//!   "edges": [ { "vertices": [0, 1], "sharpness": 1.0, "kappa": 0.0 } ],
//!   "vertices": [
//!     { "index": 1, "tension": 0.0, "sharpness": 0.5, "bias": 0.0, "crease": [0.0, 1.0, 0.0] }
//!   ]
//! }
//! ```
//!
//! Both lists are optional, and so is every field but `vertices` / `index` (missing numbers are
//! 0). Indices are vertex indices of the mesh the tags go with.
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
//! use tessella_core::{samples, tags::Tags};
//! let mesh = samples::tetrahedron();
//! let tags = Tags::from_json(&mesh, r#"{"edges": [{"vertices": [0, 1], "sharpness": 1}]}"#)?;
//! assert_eq!(tags.edge_count(), 1);
//! assert!(Tags::from_json(&mesh, r#"{"edges": [{"vertices": [0, 9]}]}"#).is_err());
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonFile {
    #[serde(default)]
    edges: Vec<JsonEdge>,
    #[serde(default)]
    vertices: Vec<JsonVertex>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonEdge {
    vertices: [u32; 2],
    #[serde(default)]
    sharpness: f32,
    #[serde(default)]
    kappa: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonVertex {
    index: u32,
    #[serde(flatten)]
    tag: VertexTag,
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

    /// Tags vertex `v` of `mesh` (replacing an earlier tag at its position).
    pub fn set_vertex(&mut self, mesh: &Mesh, v: u32, tag: VertexTag) -> Result<(), TagError> {
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
        let pid = position_ids(mesh.positions())[v as usize];
        self.vertices.insert(pid, tag);
        Ok(())
    }

    /// Tags the edge between vertices `a` and `b` of `mesh`; it must be an edge with exactly two
    /// faces (by position).
    pub fn set_edge(
        &mut self,
        mesh: &Mesh,
        [a, b]: [u32; 2],
        tag: EdgeTag,
    ) -> Result<(), TagError> {
        let topo = mesh.topology();
        self.set_edge_in(mesh, &topo, [a, b], tag)
    }

    fn set_edge_in(
        &mut self,
        mesh: &Mesh,
        topo: &Topology,
        [a, b]: [u32; 2],
        tag: EdgeTag,
    ) -> Result<(), TagError> {
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
        let (pa, pb) = (topo.position_ids[a as usize], topo.position_ids[b as usize]);
        let faces = edge_faces(mesh, topo, pa, pb);
        match faces {
            0 => return Err(TagError::NotAnEdge { a, b }),
            2 => {}
            _ => return Err(TagError::BoundaryEdge { a, b }),
        }
        self.edges.insert([pa.min(pb), pa.max(pb)], tag);
        Ok(())
    }

    /// Tags from a sidecar JSON file's text (format in the module docs).
    pub fn from_json(mesh: &Mesh, text: &str) -> Result<Tags, TagError> {
        let file: JsonFile =
            serde_json::from_str(text).map_err(|e| TagError::Json(e.to_string()))?;
        let topo = mesh.topology();
        let mut tags = Tags::new();
        for e in file.edges {
            let tag = EdgeTag {
                sharpness: e.sharpness,
                kappa: e.kappa,
            };
            tags.set_edge_in(mesh, &topo, e.vertices, tag)?;
        }
        for v in file.vertices {
            tags.set_vertex(mesh, v.index, v.tag)?;
        }
        Ok(tags)
    }

    /// Tags from PLY properties given as plain data: per-vertex scalar columns by name
    /// (`tension`, `sharpness`, `bias`, `crease_x`, `crease_y`, `crease_z`; others are ignored)
    /// and `edge` elements as `([vertex1, vertex2], properties)` with `sharpness` and optional
    /// `kappa`. A vertex column must have one value per vertex.
    pub fn from_ply(
        mesh: &Mesh,
        vertex: &BTreeMap<String, Vec<f32>>,
        edges: &[([u32; 2], BTreeMap<String, f32>)],
    ) -> Result<Tags, TagError> {
        let n = mesh.vertex_count();
        let column = |name: &str| -> Result<Option<&Vec<f32>>, TagError> {
            match vertex.get(name) {
                Some(c) if c.len() != n => Err(TagError::OutOfRange {
                    what: format!("PLY vertex property '{name}' count"),
                    value: c.len() as f32,
                    range: "exactly one value per vertex",
                }),
                other => Ok(other),
            }
        };
        let cols = [
            "tension",
            "sharpness",
            "bias",
            "crease_x",
            "crease_y",
            "crease_z",
        ]
        .map(column);
        let mut c: [Option<&Vec<f32>>; 6] = [None; 6];
        for (slot, col) in c.iter_mut().zip(cols) {
            *slot = col?;
        }
        let mut tags = Tags::new();
        let get = |col: Option<&Vec<f32>>, v: usize| col.map_or(0.0, |c| c[v]);
        for v in 0..n {
            let tag = VertexTag {
                tension: get(c[0], v),
                sharpness: get(c[1], v),
                bias: get(c[2], v),
                crease: [get(c[3], v), get(c[4], v), get(c[5], v)],
            };
            if tag != VertexTag::default() {
                tags.set_vertex(mesh, v as u32, tag)?;
            }
        }
        let topo = mesh.topology();
        for (ends, props) in edges {
            let tag = EdgeTag {
                sharpness: props.get("sharpness").copied().unwrap_or(0.0),
                kappa: props.get("kappa").copied().unwrap_or(0.0),
            };
            tags.set_edge_in(mesh, &topo, *ends, tag)?;
        }
        Ok(tags)
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

/// Number of faces on the edge between positions `a` and `b` (0: not an edge).
fn edge_faces(mesh: &Mesh, topo: &Topology, a: u32, b: u32) -> usize {
    mesh.triangles()
        .iter()
        .filter(|t| {
            (0..3).any(|k| {
                let (x, y) = (
                    topo.position_ids[t[k] as usize],
                    topo.position_ids[t[(k + 1) % 3] as usize],
                );
                (x, y) == (a, b) || (x, y) == (b, a)
            })
        })
        .count()
}

fn face_normal(mesh: &Mesh, f: usize) -> Vec3 {
    let [a, b, c] = mesh.corner_positions(f);
    (b - a).cross(c - a).normalize_or_zero()
}
