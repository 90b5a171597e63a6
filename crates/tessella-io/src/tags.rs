//! Shape tags from files, and the one way tag sources are layered (the CLI and the Python
//! package both call [`gather`]).
//!
//! The tags themselves, their meaning and their checks are [`tessella_core::tags`]; this module
//! reads them from a sidecar JSON ([`from_json`]) and from PLY properties ([`from_ply`]), in time
//! linear in the mesh and the number of tags.
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
//! 0); unknown fields are refused. Indices are vertex indices of the mesh the tags go with.
//!
//! # PLY properties
//!
//! Vertex properties `tension`, `sharpness`, `bias` and `crease_x`, `crease_y`, `crease_z`
//! (others are ignored; missing ones are 0), and an `edge` element with `vertex1`, `vertex2`,
//! `sharpness` and optional `kappa` ([`crate::ply`] reads them into [`RawMesh::vertex_scalars`]
//! and [`RawMesh::edges`]).
//!
//! # Layering
//!
//! [`gather`] merges, later sources overriding earlier ones where both tag a vertex or edge:
//!
//! 1. for the scalar-tagged scheme, the mesh's split normals ([`Tags::from_split_normals`]);
//! 2. a crease angle ([`Tags::from_crease_angle`]);
//! 3. the mesh file's PLY properties;
//! 4. a sidecar JSON (text or a file).
//!
//! ```
//! use tessella_core::{samples, Scheme};
//! use tessella_io::tags::{self, JsonSource, TagSources};
//! let mesh = samples::tetrahedron();
//! let text = r#"{"edges": [{"vertices": [0, 1], "sharpness": 1}]}"#;
//! let tags = tags::from_json(&mesh, text)?;
//! assert_eq!(tags.edge_count(), 1);
//! assert!(tags::from_json(&mesh, r#"{"edges": [{"vertices": [0, 9]}]}"#).is_err());
//!
//! let sources = TagSources {
//!     json: Some(JsonSource::Text { text, origin: "in the example" }),
//!     ..TagSources::default()
//! };
//! let layered = tags::gather(&mesh, Scheme::Png1, &sources)?.expect("one edge is tagged");
//! assert_eq!(layered, tags);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::{RawEdge, RawMesh};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tessella_core::tags::{EdgeTag, TagBuilder, TagError, Tags, VertexTag};
use tessella_core::{Mesh, Scheme};
use thiserror::Error;

/// Why sidecar JSON gives no tags.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum JsonTagError {
    /// Not JSON, or not the format in the module docs.
    #[error("tags JSON: {0}")]
    Json(String),
    /// Well formed, but the tags do not fit the mesh.
    #[error(transparent)]
    Tag(#[from] TagError),
}

/// Why [`gather`] gives no tags; the message names the source.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum TagSourceError {
    /// The crease angle is out of range (the message names the crease angle).
    #[error("{0}")]
    CreaseAngle(TagError),
    /// The mesh file's PLY properties are bad tags.
    #[error("bad tags in the PLY file: {0}")]
    Ply(TagError),
    /// The operating system refused to read the sidecar file.
    #[error("cannot read tags from {path}: {error}", path = path.display())]
    Read {
        path: PathBuf,
        error: std::io::Error,
    },
    /// The sidecar JSON is malformed or its tags do not fit the mesh; `origin` says where it
    /// came from (`"in tags.json"`).
    #[error("bad tags {origin}: {error}")]
    Json { origin: String, error: JsonTagError },
}

/// A sidecar tags file as data (format in the module docs): what [`from_json`] reads and
/// [`TagFile::to_json`] writes, keyed by the mesh's vertex indices. The interactive viewer
/// edits one and saves it for the CLI.
///
/// ```
/// use tessella_io::tags::{TagFile, TagFileEdge};
/// let mut file = TagFile::default();
/// file.edges.push(TagFileEdge { vertices: [0, 1], sharpness: 1.0, kappa: 0.0 });
/// let text = file.to_json();
/// assert_eq!(TagFile::parse(&text)?, file);
/// let mesh = tessella_core::samples::tetrahedron();
/// assert_eq!(tessella_io::tags::from_json(&mesh, &text)?.edge_count(), 1);
/// # Ok::<(), tessella_io::tags::JsonTagError>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TagFile {
    #[serde(default)]
    pub edges: Vec<TagFileEdge>,
    #[serde(default)]
    pub vertices: Vec<TagFileVertex>,
}

/// One edge of a [`TagFile`]: its two vertex indices and tags.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TagFileEdge {
    pub vertices: [u32; 2],
    #[serde(default)]
    pub sharpness: f32,
    #[serde(default)]
    pub kappa: f32,
}

/// One vertex of a [`TagFile`]: its index and tags.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TagFileVertex {
    pub index: u32,
    #[serde(flatten)]
    pub tag: VertexTag,
}

impl TagFile {
    /// Reads the JSON text (no check against a mesh: [`TagFile::tags`] does that).
    pub fn parse(text: &str) -> Result<TagFile, JsonTagError> {
        serde_json::from_str(text).map_err(|e| JsonTagError::Json(e.to_string()))
    }

    /// The JSON text, in the format [`from_json`] and `tessella refine --tags` read.
    pub fn to_json(&self) -> String {
        // Plain data of numbers and arrays: serialising cannot fail (non-finite numbers are
        // written as null, which `parse` then refuses).
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The tags these entries set on `mesh`, checked.
    pub fn tags(&self, mesh: &Mesh) -> Result<Tags, JsonTagError> {
        let mut tags = TagBuilder::new(mesh);
        for e in &self.edges {
            let tag = EdgeTag {
                sharpness: e.sharpness,
                kappa: e.kappa,
            };
            tags.set_edge(e.vertices, tag)?;
        }
        for v in &self.vertices {
            tags.set_vertex(v.index, v.tag)?;
        }
        Ok(tags.finish())
    }
}

/// Tags from a sidecar JSON file's text (format in the module docs).
pub fn from_json(mesh: &Mesh, text: &str) -> Result<Tags, JsonTagError> {
    TagFile::parse(text)?.tags(mesh)
}

/// Vertex property names that are tags, in [`VertexTag`] order.
const VERTEX_COLUMNS: [&str; 6] = [
    "tension",
    "sharpness",
    "bias",
    "crease_x",
    "crease_y",
    "crease_z",
];

/// Tags from PLY properties: per-vertex scalar columns by name (see the module docs; other
/// names are ignored, a tag column must have one value per vertex) and `edge` elements with
/// `sharpness` and optional `kappa`. Vertices whose tags are all zero stay untagged.
pub fn from_ply(
    mesh: &Mesh,
    vertex: &BTreeMap<String, Vec<f32>>,
    edges: &[RawEdge],
) -> Result<Tags, TagError> {
    let n = mesh.vertex_count();
    let mut columns: [Option<&[f32]>; 6] = [None; 6];
    for (slot, name) in columns.iter_mut().zip(VERTEX_COLUMNS) {
        match vertex.get(name) {
            Some(c) if c.len() != n => {
                return Err(TagError::OutOfRange {
                    what: format!("PLY vertex property '{name}' count"),
                    value: c.len() as f32,
                    range: "exactly one value per vertex",
                })
            }
            other => *slot = other.map(Vec::as_slice),
        }
    }
    let mut tags = TagBuilder::new(mesh);
    if columns.iter().any(Option::is_some) {
        let get = |col: Option<&[f32]>, v: usize| col.map_or(0.0, |c| c[v]);
        for v in 0..n {
            let tag = VertexTag {
                tension: get(columns[0], v),
                sharpness: get(columns[1], v),
                bias: get(columns[2], v),
                crease: [get(columns[3], v), get(columns[4], v), get(columns[5], v)],
            };
            if tag != VertexTag::default() {
                tags.set_vertex(v as u32, tag)?;
            }
        }
    }
    for e in edges {
        let tag = EdgeTag {
            sharpness: e.scalars.get("sharpness").copied().unwrap_or(0.0),
            kappa: e.scalars.get("kappa").copied().unwrap_or(0.0),
        };
        tags.set_edge(e.vertices, tag)?;
    }
    Ok(tags.finish())
}

/// A sidecar JSON for [`gather`].
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum JsonSource<'a> {
    /// JSON text, and how messages name where it came from (`"in the tags dict"`).
    Text { text: &'a str, origin: &'a str },
    /// A JSON file, read by [`gather`].
    File(&'a Path),
}

/// The tag sources [`gather`] layers, besides the split normals it finds itself.
#[derive(Debug, Clone, Copy, Default)]
pub struct TagSources<'a> {
    /// Crease every edge whose two faces bend by more than this many degrees.
    pub crease_angle: Option<f32>,
    /// The mesh file as read, for its PLY vertex properties and `edge` element (other formats
    /// carry none).
    pub file: Option<&'a RawMesh>,
    /// A sidecar JSON.
    pub json: Option<JsonSource<'a>>,
}

/// The tags `scheme` gets on `mesh`, layered as the module docs say, or `None` when nothing is
/// tagged.
pub fn gather(
    mesh: &Mesh,
    scheme: Scheme,
    sources: &TagSources,
) -> Result<Option<Tags>, TagSourceError> {
    let mut tags = Tags::new();
    if scheme == Scheme::ScalarTagged {
        tags.merge(Tags::from_split_normals(mesh));
    }
    if let Some(degrees) = sources.crease_angle {
        tags.merge(Tags::from_crease_angle(mesh, degrees).map_err(TagSourceError::CreaseAngle)?);
    }
    if let Some(raw) = sources.file {
        if !raw.vertex_scalars.is_empty() || !raw.edges.is_empty() {
            tags.merge(
                from_ply(mesh, &raw.vertex_scalars, &raw.edges).map_err(TagSourceError::Ply)?,
            );
        }
    }
    match sources.json {
        None => {}
        Some(JsonSource::Text { text, origin }) => {
            tags.merge(from_json(mesh, text).map_err(|error| TagSourceError::Json {
                origin: origin.to_string(),
                error,
            })?);
        }
        Some(JsonSource::File(path)) => {
            let text = std::fs::read_to_string(path).map_err(|error| TagSourceError::Read {
                path: path.to_path_buf(),
                error,
            })?;
            tags.merge(
                from_json(mesh, &text).map_err(|error| TagSourceError::Json {
                    origin: format!("in {}", path.display()),
                    error,
                })?,
            );
        }
    }
    Ok((!tags.is_empty()).then_some(tags))
}
