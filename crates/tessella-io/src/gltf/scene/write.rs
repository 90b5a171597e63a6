//! Writing a refined scene: a GLB, or a `.gltf` with its `.bin`, both atomically; images named
//! by relative URI copied beside the output.

use super::RefinedScene;
use crate::{Durability, IoError};
use serde_json::Value;
use std::path::Path;

/// The GLB container of `json` and its buffer `bin` (glTF 2.0 section 4.4).
pub(super) fn glb_bytes(json: &Value, bin: &[u8]) -> std::io::Result<Vec<u8>> {
    let head = glb_head(json, bin.len())?;
    let mut out = Vec::with_capacity(head.len() + bin.len().next_multiple_of(4));
    out.extend_from_slice(&head);
    out.extend_from_slice(bin);
    out.resize(out.len().next_multiple_of(4), 0);
    Ok(out)
}

/// Writes the GLB container of `json` and `bin` to `out` without gathering it first.
fn write_glb(out: &mut dyn std::io::Write, json: &Value, bin: &[u8]) -> std::io::Result<()> {
    out.write_all(&glb_head(json, bin.len())?)?;
    out.write_all(bin)?;
    out.write_all(&[0; 3][..bin.len().next_multiple_of(4) - bin.len()])
}

/// Everything of a GLB before its buffer's bytes: the header, the JSON chunk and the BIN
/// chunk's header (none when the buffer is empty).
fn glb_head(json: &Value, bin_len: usize) -> std::io::Result<Vec<u8>> {
    let mut text = serde_json::to_vec(json).map_err(std::io::Error::other)?;
    text.resize(text.len().next_multiple_of(4), b' ');
    let padded = bin_len.next_multiple_of(4);
    let chunks = 8 + text.len() + if bin_len == 0 { 0 } else { 8 + padded };
    let total = u32::try_from(12 + chunks).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "a GLB file holds at most 4 GiB, this scene needs {} bytes; write .gltf instead",
                12 + chunks
            ),
        )
    })?;
    let mut out = Vec::with_capacity(28 + text.len());
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    if bin_len > 0 {
        out.extend_from_slice(&(padded as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
    }
    Ok(out)
}

pub(super) fn write(
    scene: &RefinedScene,
    path: &Path,
    durability: Durability,
) -> Result<Vec<String>, IoError> {
    let format = crate::Format::from_path(path)?;
    let failed = |source| IoError::Write {
        path: path.to_path_buf(),
        source,
    };
    let folder = path.parent().unwrap_or(Path::new(""));
    let warnings = copy_images(scene, folder);
    match format {
        crate::Format::Glb => {
            crate::write_atomic_with(path, durability, |w| write_glb(w, &scene.json, &scene.bin))?;
        }
        crate::Format::Gltf => {
            let mut json = scene.json.clone();
            if !scene.bin.is_empty() {
                let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
                let name = format!("{stem}.bin");
                crate::write_atomic_with(&folder.join(&name), durability, |w| {
                    w.write_all(&scene.bin)
                })?;
                json["buffers"][0]["uri"] = encode_uri(&name).into();
            }
            let text =
                serde_json::to_vec_pretty(&json).map_err(|e| failed(std::io::Error::other(e)))?;
            crate::write_atomic_with(path, durability, |w| w.write_all(&text))?;
        }
        _ => {
            return Err(IoError::BadMesh {
                path: path.to_path_buf(),
                message: "a glTF scene is written as .glb or .gltf".into(),
            })
        }
    }
    Ok(warnings)
}

/// Copies each image named by a relative URI from the source's folder into `folder` (when that
/// is another folder); a missing image is a warning, never an error.
fn copy_images(scene: &RefinedScene, folder: &Path) -> Vec<String> {
    let mut warnings = Vec::new();
    let same = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    let images = scene.json.get("images").and_then(Value::as_array);
    for (i, image) in images.into_iter().flatten().enumerate() {
        let Some(uri) = image.get("uri").and_then(Value::as_str) else {
            continue;
        };
        if uri.starts_with("data:") || uri.contains("://") {
            continue;
        }
        let relative = super::super::data::percent_decode(uri);
        if Path::new(&relative).has_root() || relative.split(['/', '\\']).any(|c| c == "..") {
            warnings.push(format!(
                "image {i}: {uri:?} is not a path inside the input's folder; not copied"
            ));
            continue;
        }
        let from = scene.source_folder.join(&relative);
        let to = folder.join(&relative);
        if !from.is_file() {
            warnings.push(format!(
                "image {i}: {} is missing; the output names it all the same",
                from.display()
            ));
            continue;
        }
        if to.exists() && same(&from, &to) {
            continue;
        }
        let copied = to
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .and_then(|()| std::fs::copy(&from, &to).map(|_| ()));
        if let Err(e) = copied {
            warnings.push(format!(
                "image {i}: cannot copy {} to {}: {e}",
                from.display(),
                to.display()
            ));
        }
    }
    warnings
}

/// A file name as a URI: `%XX` for every byte outside the unreserved set.
fn encode_uri(name: &str) -> String {
    name.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}
