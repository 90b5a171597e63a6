//! The CLI's tag arguments, handed to [`tessella_io::tags::gather`], which layers the sources
//! (hard edges in the file, a crease angle, PLY properties, a sidecar JSON) for the CLI and
//! Python alike.

use crate::args::TagArgs;
use anyhow::Context;
use tessella_core::{Mesh, Scheme, Tags};
use tessella_io::tags::{JsonSource, TagSources};
use tessella_io::RawMesh;

/// The tags for `scheme` on `mesh` (read from `raw`), or `None` when nothing is tagged.
pub fn gather(
    raw: &RawMesh,
    mesh: &Mesh,
    scheme: Scheme,
    args: &TagArgs,
) -> anyhow::Result<Option<Tags>> {
    let sources = TagSources {
        crease_angle: args.crease_angle,
        file: Some(raw),
        json: args.file.as_deref().map(JsonSource::File),
    };
    Ok(tessella_io::tags::gather(mesh, scheme, &sources)?)
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
