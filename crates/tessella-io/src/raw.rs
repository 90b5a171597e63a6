//! What a file holds before validation ([`RawMesh`]) and what a writer takes ([`MeshView`]).

use crate::IoError;
use std::collections::BTreeMap;
use std::path::Path;
use tessella_core::{Mesh, RefinedMesh};

/// The contents of a mesh file, before [`tessella_core::Mesh::new`] validates them.
///
/// All per-vertex arrays have `positions.len()` entries and every index is below it (the readers
/// check this); geometry (degenerate triangles, zero normals) is not checked yet.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawMesh {
    pub positions: Vec<[f32; 3]>,
    /// Per-vertex normals as stored (not normalised), `None` when the file has none.
    pub normals: Option<Vec<[f32; 3]>>,
    /// Per-vertex texture coordinates, origin at the image's bottom-left (OBJ/PLY convention).
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Extra scalar vertex properties of a PLY file by name (e.g. `tension`, `sharpness`).
    pub vertex_scalars: BTreeMap<String, Vec<f32>>,
    /// The PLY `edge` element, when present.
    pub edges: Vec<RawEdge>,
}

/// One entry of a PLY `edge` element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawEdge {
    /// `vertex1`, `vertex2`.
    pub vertices: [u32; 2],
    /// The edge's other scalar properties by name (e.g. `sharpness`).
    pub scalars: BTreeMap<String, f32>,
}

/// Borrowed arrays of a triangle mesh to write. Build one from a [`Mesh`] or a [`RefinedMesh`]
/// with `MeshView::from(&mesh)`, or fill the fields yourself.
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    pub positions: &'a [[f32; 3]],
    pub normals: Option<&'a [[f32; 3]]>,
    pub uvs: Option<&'a [[f32; 2]]>,
    pub triangles: &'a [[u32; 3]],
}

impl<'a> From<&'a Mesh> for MeshView<'a> {
    fn from(mesh: &'a Mesh) -> Self {
        MeshView {
            positions: mesh.positions(),
            normals: Some(mesh.normals()),
            uvs: mesh.uvs(),
            triangles: mesh.triangles(),
        }
    }
}

impl<'a> From<&'a RefinedMesh> for MeshView<'a> {
    fn from(mesh: &'a RefinedMesh) -> Self {
        MeshView {
            positions: &mesh.positions,
            normals: (!mesh.normals.is_empty()).then_some(&mesh.normals[..]),
            uvs: mesh.uvs.as_deref(),
            triangles: &mesh.triangles,
        }
    }
}

impl MeshView<'_> {
    /// Checks that the arrays fit together, so writers never emit a file that cannot be read.
    pub(crate) fn check(&self, path: &Path) -> Result<(), IoError> {
        let bad = |message: String| IoError::BadMesh {
            path: path.to_path_buf(),
            message,
        };
        let count = self.positions.len();
        if self.triangles.is_empty() {
            return Err(bad("it has no triangles".into()));
        }
        if count > u32::MAX as usize {
            return Err(bad(format!(
                "it has {count} vertices; at most 4294967295 fit 32-bit indices"
            )));
        }
        if let Some(normals) = self.normals {
            if normals.len() != count {
                return Err(bad(format!(
                    "{} normals for {count} positions",
                    normals.len()
                )));
            }
        }
        if let Some(uvs) = self.uvs {
            if uvs.len() != count {
                return Err(bad(format!("{} uvs for {count} positions", uvs.len())));
            }
        }
        if let Some(vertex) = self
            .positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(bad(format!(
                "vertex {vertex} has a non-finite position {:?}",
                self.positions[vertex]
            )));
        }
        for (face, t) in self.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= count) {
                return Err(IoError::IndexOutOfRange {
                    path: path.to_path_buf(),
                    what: "triangle",
                    item: face,
                    index: index.into(),
                    count,
                });
            }
        }
        Ok(())
    }
}

impl RawMesh {
    /// The checks every reader ends with: some triangles, attribute counts, indices in range.
    pub(crate) fn check(&self, path: &Path, format: &'static str) -> Result<(), IoError> {
        if self.triangles.is_empty() {
            return Err(IoError::NoTriangles {
                path: path.to_path_buf(),
            });
        }
        let count = self.positions.len();
        let counts = [
            ("normals", self.normals.as_ref().map(Vec::len)),
            ("uvs", self.uvs.as_ref().map(Vec::len)),
        ];
        let scalars = self
            .vertex_scalars
            .iter()
            .map(|(name, v)| (name.as_str(), Some(v.len())));
        for (what, len) in counts.into_iter().chain(scalars) {
            if let Some(len) = len.filter(|&len| len != count) {
                return Err(IoError::Parse {
                    path: path.to_path_buf(),
                    format,
                    message: format!("{len} {what} for {count} vertices"),
                });
            }
        }
        let out_of_range = |what, item, index: u32| IoError::IndexOutOfRange {
            path: path.to_path_buf(),
            what,
            item,
            index: index.into(),
            count,
        };
        for (face, t) in self.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= count) {
                return Err(out_of_range("triangle", face, index));
            }
        }
        for (edge, e) in self.edges.iter().enumerate() {
            if let Some(&index) = e.vertices.iter().find(|&&i| i as usize >= count) {
                return Err(out_of_range("edge", edge, index));
            }
        }
        Ok(())
    }
}
