//! `--clip NAME|INDEX --time SECONDS`: a glTF file's animation posed before refining or
//! drawing (morph targets, then skinning; `tessella_core::animation::Poser`).

use crate::args::PoseFlags;
use anyhow::Context;
use std::path::Path;
use tessella_core::animation::Poser;
use tessella_core::Mesh;
use tessella_io::RawMesh;

/// The animation of `path`, checked (skins, weights, samplers, clips).
pub fn load(path: &Path) -> anyhow::Result<Poser> {
    let model = tessella_io::read_animated(path)?;
    Poser::new(model).with_context(|| format!("cannot animate {}", path.display()))
}

/// `path`'s mesh as [`super::tags::read`] gives it (the file's tags and fields kept), posed by
/// `flags` when they name a clip.
pub fn read(path: &Path, flags: &PoseFlags) -> anyhow::Result<(RawMesh, Mesh)> {
    let Some(clip) = &flags.clip else {
        return super::tags::read(path);
    };
    let poser = load(path)?;
    let what = || format!("cannot pose {}", path.display());
    let index = poser.clip_index(clip).with_context(what)?;
    let mesh = poser.mesh(Some(index), flags.time).with_context(what)?;
    let mut raw = tessella_io::read_raw(path)?;
    if raw.positions.len() != mesh.vertex_count() {
        anyhow::bail!(
            "{}: the posed mesh has {} vertices but the file's mesh has {}; cannot pose it",
            path.display(),
            mesh.vertex_count(),
            raw.positions.len()
        );
    }
    raw.positions = mesh.positions().to_vec();
    raw.normals = poser.has_normals().then(|| mesh.normals().to_vec());
    Ok((raw, mesh))
}
