//! The low-level parts every glTF reader of this crate shares: where a `.gltf` file's
//! external buffers come from, the GLB header check, URIs, accessor bounds, and how a
//! primitive's index list becomes triangles. No reader is defined here, so the scene reader
//! ([`super::scene`]) and the merged readers ([`super::read`], [`super::read_animated`]) import
//! it without importing each other.

use crate::IoError;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use gltf::Accessor;
use std::path::Path;

/// Where a `.gltf` file's external buffers (relative URIs) come from.
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum Buffers<'a> {
    /// Files in the folder of the `.gltf` file's path.
    Folder,
    /// Only these (relative URI, bytes) pairs: the file system is never touched (the browser
    /// has none).
    Given(&'a [(&'a str, &'a [u8])]),
}

/// Checks the 12-byte GLB header's total length before the `gltf` crate reads it: that crate
/// subtracts the header size from the declared length unchecked (an overflow panic in debug
/// builds for a declared length under 12; found by `fuzz/fuzz_targets/gltf.rs`).
pub(super) fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let Some(length) = bytes.get(8..12) else {
        return Err(format!(
            "the GLB header is cut short ({} of 12 bytes)",
            bytes.len()
        ));
    };
    let length = u32::from_le_bytes([length[0], length[1], length[2], length[3]]);
    if length < 12 {
        return Err(format!(
            "the GLB header declares a total length of {length} bytes, less than the header itself"
        ));
    }
    Ok(())
}

/// Turns a primitive's index list into triangles (glTF 2.0 spec, section 3.7.2.1 "Topology
/// Types").
pub(super) fn assemble(mode: Mode, corners: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    let v = corners;
    Ok(match mode {
        Mode::Triangles => {
            if !v.len().is_multiple_of(3) {
                return Err(format!(
                    "TRIANGLES with {} indices, not a multiple of 3",
                    v.len()
                ));
            }
            v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        }
        // p_i = {v_i, v_(i+(1+i%2)), v_(i+(2-i%2))}
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .map(|i| [v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]])
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect(),
        // p_i = {v_(i+1), v_(i+2), v_0}
        Mode::TriangleFan => (0..v.len().saturating_sub(2))
            .map(|i| [v[i + 1], v[i + 2], v[0]])
            .collect(),
        _ => Vec::new(),
    })
}

/// Checks an accessor's type and that all its elements lie inside its buffer data, so the
/// `gltf` reader never indexes past the end of a slice (nor meets an empty accessor or a stride
/// shorter than an element, on which it panics). Sparse accessors (whose indices and values are
/// checked the same way) and accessors without a buffer view (zeros, unless sparse) are refused
/// unless `sparse`.
pub(super) fn check_accessor(
    accessor: &Accessor,
    dimensions: Dimensions,
    types: &[DataType],
    buffers: &[Vec<u8>],
    sparse: bool,
) -> Result<(), String> {
    let index = accessor.index();
    if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
        return Err(format!(
            "accessor {index} is {:?} {:?}; expected {dimensions:?} of {types:?}",
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    if accessor.count() == 0 {
        return Err(format!("accessor {index} has no elements"));
    }
    let element = accessor.size();
    let sparse_part = accessor.sparse();
    if sparse_part.is_some() && !sparse {
        return Err(format!("accessor {index} is sparse"));
    }
    match accessor.view() {
        Some(view) => check_elements(
            &format!("accessor {index}"),
            view,
            accessor.offset(),
            accessor.count(),
            element,
            buffers,
        )?,
        // An accessor without a view is zeros, with sparse values on top if it has them
        // (accepted with `sparse`, the scene reader's).
        None if sparse_part.is_some() || sparse => {}
        None => return Err(format!("accessor {index} has no bufferView")),
    }
    let Some(sparse_part) = sparse_part else {
        return Ok(());
    };
    let count = sparse_part.count();
    if count == 0 || count > accessor.count() {
        return Err(format!(
            "accessor {index} has {count} sparse values for {} elements",
            accessor.count()
        ));
    }
    let indices = sparse_part.indices();
    let what = format!("accessor {index}'s sparse indices");
    check_elements(
        &what,
        indices.view(),
        indices.offset(),
        count,
        index_size(indices.index_type()),
        buffers,
    )?;
    let values = sparse_part.values();
    let what = format!("accessor {index}'s sparse values");
    check_elements(
        &what,
        values.view(),
        values.offset(),
        count,
        element,
        buffers,
    )
}

fn index_size(index_type: gltf::accessor::sparse::IndexType) -> usize {
    use gltf::accessor::sparse::IndexType;
    match index_type {
        IndexType::U8 => 1,
        IndexType::U16 => 2,
        IndexType::U32 => 4,
    }
}

/// Checks that `count` elements of `element` bytes from `offset` lie in `view` and `view` in
/// its buffer.
fn check_elements(
    what: &str,
    view: gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    element: usize,
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    let data = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > data) {
        return Err(format!(
            "bufferView {} reaches past the end of buffer {}",
            view.index(),
            view.buffer().index()
        ));
    }
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(format!(
            "{what} has {element}-byte elements but bufferView {} has a byteStride of {stride}",
            view.index()
        ));
    }
    if let Some(last) = count.checked_sub(1) {
        let end = stride
            .checked_mul(last)
            .and_then(|x| x.checked_add(element))
            .and_then(|x| x.checked_add(offset));
        if end.is_none_or(|end| end > view.length()) {
            return Err(format!(
                "{what} ({count} elements) reaches past the end of bufferView {}",
                view.index()
            ));
        }
    }
    Ok(())
}

pub(super) fn load_uri(
    path: &Path,
    uri: &str,
    format: &'static str,
    external: Buffers<'_>,
) -> Result<Vec<u8>, IoError> {
    use base64::Engine;
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, payload) = rest.split_once(',').unwrap_or((rest, ""));
        if !header.ends_with(";base64") {
            // Plain data: the bytes themselves, `%XX`-escaped (RFC 2397).
            return Ok(percent_decode_bytes(payload));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| IoError::Parse {
                path: path.to_path_buf(),
                format,
                message: format!("bad base64 in a data: URI: {e}"),
            });
    }
    if uri.contains("://") {
        return Err(IoError::Unsupported {
            path: path.to_path_buf(),
            format,
            message: format!("buffer URI {uri:?} is not a data: URI or a relative file path"),
        });
    }
    let relative = percent_decode(uri);
    let unsupported = |message: String| IoError::Unsupported {
        path: path.to_path_buf(),
        format,
        message,
    };
    if Path::new(&relative).has_root() || relative.starts_with('\\') || relative.contains(':') {
        return Err(unsupported(format!(
            "buffer URI {uri:?} is not a data: URI or a relative file path"
        )));
    }
    if let Buffers::Given(given) = external {
        return match given
            .iter()
            .find(|(name, _)| *name == relative || *name == uri)
        {
            Some((_, data)) => Ok(data.to_vec()),
            None => Err(IoError::Parse {
                path: path.to_path_buf(),
                format,
                message: format!(
                    "buffer URI {uri:?} names a file beside the glTF file, and none of that \
                     name was given with it (pass its bytes along, or use a GLB or data: URI)"
                ),
            }),
        };
    }
    let file = path.parent().unwrap_or(Path::new("")).join(relative);
    let cannot_read = |source| IoError::Read {
        path: file.clone(),
        source,
    };
    // Only regular files: a device or a pipe could block or never end.
    let metadata = std::fs::metadata(&file).map_err(cannot_read)?;
    if !metadata.is_file() {
        return Err(unsupported(format!(
            "buffer file {} is not a regular file",
            file.display()
        )));
    }
    std::fs::read(&file).map_err(cannot_read)
}

/// Decodes `%XX` escapes of a relative URI (glTF 2.0 spec, section 3.1 "URIs").
pub(super) fn percent_decode(uri: &str) -> String {
    String::from_utf8_lossy(&percent_decode_bytes(uri)).into_owned()
}

/// The bytes `%XX` escapes stand for.
fn percent_decode_bytes(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                out.push(byte);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    out
}
