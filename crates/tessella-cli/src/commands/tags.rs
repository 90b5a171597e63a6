//! Gathering tags from their sources, later ones overriding earlier ones: hard edges in the
//! file, a crease angle, PLY properties, a sidecar JSON.

use crate::args::TagArgs;
use anyhow::Context;
use tessella_core::{Mesh, Scheme, Tags};
use tessella_io::RawMesh;

/// The tags for `scheme` on `mesh` (read from `raw`), or `None` when nothing is tagged.
pub fn gather(
    raw: &RawMesh,
    mesh: &Mesh,
    scheme: Scheme,
    args: &TagArgs,
) -> anyhow::Result<Option<Tags>> {
    let mut tags = Tags::new();
    if scheme == Scheme::ScalarTagged {
        tags.merge(Tags::from_split_normals(mesh));
    }
    if let Some(degrees) = args.crease_angle {
        tags.merge(Tags::from_crease_angle(mesh, degrees)?);
    }
    if !raw.vertex_scalars.is_empty() || !raw.edges.is_empty() {
        let edges: Vec<_> = raw
            .edges
            .iter()
            .map(|e| (e.vertices, e.scalars.clone()))
            .collect();
        tags.merge(
            Tags::from_ply(mesh, &raw.vertex_scalars, &edges)
                .context("bad tags in the PLY file")?,
        );
    }
    if let Some(path) = &args.file {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read tags from {}", path.display()))?;
        tags.merge(
            Tags::from_json(mesh, &text)
                .with_context(|| format!("bad tags in {}", path.display()))?,
        );
    }
    Ok((!tags.is_empty()).then_some(tags))
}

/// Reads a mesh file keeping what tags need.
pub fn read(path: &std::path::Path) -> anyhow::Result<(RawMesh, Mesh)> {
    let raw = tessella_io::read_raw(path)?;
    let mesh = Mesh::new(
        raw.positions.clone(),
        raw.normals.clone(),
        raw.uvs.clone(),
        raw.triangles.clone(),
    )
    .with_context(|| format!("cannot use {}", path.display()))?;
    Ok((raw, mesh))
}
