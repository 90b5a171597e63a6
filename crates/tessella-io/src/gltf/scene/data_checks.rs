//! Checks on the values a scene's accessors hold (after the buffers are loaded): what the
//! structure cannot show, and what would make the refined file invalid if it were copied.
//! Each names the part: floats that are not finite, an index that is the primitive-restart
//! value, joints past their skin, negative weights, animation times that go back.

use super::accessor::{read_f32, read_u32, width};
use gltf::accessor::DataType;
use gltf::Document;

/// Whether `accessor`'s bytes were loaded: it has a view and its buffer's data is there. A
/// buffer without data (no binary chunk, a remote URI) is only an error where geometry is read,
/// and an accessor without a view is zeros the file never wrote; neither is checked here.
fn has_data(accessor: &gltf::Accessor, buffers: &[Vec<u8>]) -> bool {
    let loaded = |view: gltf::buffer::View| {
        buffers
            .get(view.buffer().index())
            .is_some_and(|b| b.len() >= view.offset() + view.length())
    };
    accessor.count() > 0
        && accessor.view().is_some_and(loaded)
        && accessor
            .sparse()
            .is_none_or(|s| loaded(s.indices().view()) && loaded(s.values().view()))
}

/// Runs every check on `document`'s data in `buffers`.
pub(super) fn check(document: &Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    finite_floats(document, buffers)?;
    indices(document, buffers)?;
    skins(document, buffers)?;
    animation_times(document, buffers)
}

/// Every float vector or scalar accessor holds finite values (glTF 2.0 section 3.6.2.2).
/// Positions and normals are left to the mesh checks, which name the vertex.
fn finite_floats(document: &Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    let mut geometry = std::collections::HashSet::new();
    for primitive in document.meshes().flat_map(|m| m.primitives()) {
        for (semantic, accessor) in primitive.attributes() {
            if matches!(
                semantic,
                gltf::Semantic::Positions | gltf::Semantic::Normals
            ) {
                geometry.insert(accessor.index());
            }
        }
        for target in primitive.morph_targets() {
            geometry.extend(
                target
                    .positions()
                    .into_iter()
                    .chain(target.normals())
                    .map(|a| a.index()),
            );
        }
    }
    for accessor in document.accessors() {
        if accessor.data_type() != DataType::F32
            || width(accessor.dimensions()).is_none()
            || geometry.contains(&accessor.index())
            || !has_data(&accessor, buffers)
        {
            continue;
        }
        let values = read_f32(&accessor, buffers)?;
        if let Some(at) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "accessor {} holds {} at component {at}; glTF floats are finite",
                accessor.index(),
                values[at]
            ));
        }
    }
    Ok(())
}

/// No index is its type's largest value, which glTF reserves for primitive restart.
fn indices(document: &Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let Some(accessor) = primitive.indices().filter(|a| has_data(a, buffers)) else {
                continue;
            };
            let restart = match accessor.data_type() {
                DataType::U8 => u8::MAX as u32,
                DataType::U16 => u16::MAX as u32,
                _ => u32::MAX,
            };
            if read_u32(&accessor, buffers)?.contains(&restart) {
                return Err(format!(
                    "mesh {} primitive {}: index {restart} is the primitive-restart value, which glTF forbids",
                    mesh.index(),
                    primitive.index()
                ));
            }
        }
    }
    Ok(())
}

/// The joints of a skinned primitive are joints of every skin its mesh is drawn with, and its
/// weights are not negative.
fn skins(document: &Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    for node in document.nodes() {
        let (Some(skin), Some(mesh)) = (node.skin(), node.mesh()) else {
            continue;
        };
        let joints = skin.joints().count() as u32;
        for primitive in mesh.primitives() {
            for (semantic, accessor) in primitive.attributes() {
                // An empty accessor is refused where it is read, naming its use.
                if !has_data(&accessor, buffers) {
                    continue;
                }
                let part = || format!("mesh {} primitive {}", mesh.index(), primitive.index());
                match semantic {
                    gltf::Semantic::Joints(set) => {
                        if let Some(&j) = read_u32(&accessor, buffers)
                            .map_err(|e| format!("{} JOINTS_{set}: {e}", part()))?
                            .iter()
                            .find(|&&j| j >= joints)
                        {
                            return Err(format!(
                                "{}: JOINTS_{set} names joint {j}, but skin {} (node {}) has {joints}",
                                part(),
                                skin.index(),
                                node.index()
                            ));
                        }
                    }
                    gltf::Semantic::Weights(set) => {
                        if let Some(&w) = read_f32(&accessor, buffers)
                            .map_err(|e| format!("{} WEIGHTS_{set}: {e}", part()))?
                            .iter()
                            .find(|&&w| w < 0.0)
                        {
                            return Err(format!(
                                "{}: WEIGHTS_{set} holds the negative weight {w}",
                                part()
                            ));
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    Ok(())
}

/// Each animation sampler's times are not negative and strictly increase.
fn animation_times(document: &Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    for animation in document.animations() {
        for sampler in animation.samplers() {
            let input = sampler.input();
            if !has_data(&input, buffers) {
                continue;
            }
            let times = read_f32(&input, buffers)?;
            let bad =
                times.first().is_some_and(|&t| t < 0.0) || times.windows(2).any(|w| w[1] <= w[0]);
            if bad {
                return Err(format!(
                    "animation {} sampler {}: its times (accessor {}) must start at 0 or later and strictly increase",
                    animation.index(),
                    sampler.index(),
                    input.index()
                ));
            }
        }
    }
    Ok(())
}
