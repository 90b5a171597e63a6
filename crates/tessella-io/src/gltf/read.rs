//! Reads every triangle primitive the default scene shows, in world space.
//!
//! Meshes are taken from the default scene (or the first scene) with each node's world transform
//! applied to positions and normals; a mesh used by two nodes appears twice, and a mirroring
//! transform flips the triangles' winding back to counter-clockwise. A file without scenes has
//! its meshes read as stored. Primitives are merged with offset indices and are not welded to
//! each other. Zero-area triangles (a repeated corner, corners on a line) are left out: they
//! draw nothing, and the core's mesh refuses them ([`super::scene`] keeps them, refined flat). Modes TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN are read (strip triangles with a
//! repeated index, used to stitch strips, are dropped); points and lines are skipped.
//!
//! Attributes: POSITION (f32), NORMAL (f32), TEXCOORD_0 (f32 or normalised u8/u16), indices
//! (u8/u16/u32) or none. If any primitive lacks NORMAL (or TEXCOORD_0), the merged mesh has no
//! normals (uvs), since they cannot be mixed; the core then computes normals. Sparse accessors,
//! accessors without a buffer view and buffers behind `http:`-style URIs are refused.
//! Float `SCALAR` attributes `_NAME` go to [`RawMesh::vertex_scalars`] as `NAME` when every
//! primitive has them; other application-specific attributes are ignored.
//!
//! The parsing ([`open`]), accessor checks ([`check_accessor`]), primitive reading
//! ([`read_primitive`]) and scene walk ([`scene_nodes`]) are shared with
//! [`super::read_animated`], which accepts sparse accessors.

use super::flip_v;
use crate::{IoError, RawMesh};
use glam::{Mat3, Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use gltf::{Accessor, Document};
use std::path::Path;

/// Reads a `.gltf` or `.glb` file held in memory; external buffers are read from `path`'s folder.
pub fn read(path: &Path, bytes: &[u8], format: &'static str) -> Result<RawMesh, IoError> {
    read_with(path, bytes, format, Buffers::Folder)
}

/// Where a `.gltf` file's external buffers (relative URIs) come from.
#[derive(Debug, Clone, Copy)]
pub enum Buffers<'a> {
    /// Files in the folder of the `.gltf` file's path.
    Folder,
    /// Only these (relative URI, bytes) pairs: the file system is never touched (the browser
    /// has none).
    Given(&'a [(&'a str, &'a [u8])]),
}

/// [`read`] with external buffers from `buffers`.
pub fn read_with(
    path: &Path,
    bytes: &[u8],
    format: &'static str,
    buffers: Buffers<'_>,
) -> Result<RawMesh, IoError> {
    let ctx = Context { path, format };
    let (document, buffers) = open(path, bytes, format, buffers)?;
    let mut raw = RawMesh::default();
    let (mut normals, mut uvs) = (Some(Vec::new()), Some(Vec::new()));
    // Extra scalar attributes `_NAME`: values so far and the primitives that had them.
    let mut extras: std::collections::BTreeMap<String, (Vec<f32>, usize)> = Default::default();
    let mut primitives = 0usize;
    for (mesh, transform) in instances(&document).map_err(|m| ctx.parse(m))? {
        for primitive in mesh.primitives() {
            let what = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            let Some(Primitive {
                positions,
                normals: prim_normals,
                uvs: prim_uvs,
                mut triangles,
            }) = read_primitive(ctx, &primitive, &what, &buffers, false)?
            else {
                continue;
            };
            let n = positions.len();
            let base = raw.positions.len();
            if base + n > u32::MAX as usize {
                return Err(ctx.parse("more than 4294967295 vertices in all".into()));
            }
            let base = base as u32;
            let (positions, prim_normals) =
                apply(transform, positions, prim_normals, &mut triangles);
            raw.positions.extend(positions);
            raw.triangles
                .extend(triangles.iter().map(|t| t.map(|i| i + base)));
            merge_attribute(&mut normals, prim_normals);
            merge_attribute(&mut uvs, prim_uvs);
            for (semantic, accessor) in primitive.attributes() {
                let gltf::Semantic::Extras(name) = semantic else {
                    continue;
                };
                if accessor.dimensions() != Dimensions::Scalar
                    || accessor.data_type() != DataType::F32
                {
                    continue; // not a scalar field (application data of another kind)
                }
                check_accessor(
                    &accessor,
                    Dimensions::Scalar,
                    &[DataType::F32],
                    &buffers,
                    false,
                )
                .map_err(|m| ctx.unsupported(format!("{what} _{name}: {m}")))?;
                let values: Vec<f32> = gltf::accessor::Iter::<f32>::new(accessor, |b| {
                    buffers.get(b.index()).map(Vec::as_slice)
                })
                .map(Iterator::collect)
                .unwrap_or_default();
                if values.len() != n {
                    return Err(ctx.parse(format!(
                        "{what} has {} _{name} values for {n} positions",
                        values.len()
                    )));
                }
                let entry = extras.entry(name).or_default();
                if entry.1 == primitives {
                    entry.0.extend(values);
                    entry.1 += 1;
                }
            }
            primitives += 1;
        }
    }
    raw.normals = normals;
    raw.uvs = uvs;
    raw.vertex_scalars = extras
        .into_iter()
        .filter(|(_, (_, seen))| *seen == primitives)
        .map(|(name, (values, _))| (name, values))
        .collect();
    raw.check(path, format)?;
    Ok(raw)
}

/// The file and format that errors name.
#[derive(Clone, Copy)]
pub(super) struct Context<'a> {
    pub path: &'a Path,
    pub format: &'static str,
}

impl Context<'_> {
    pub fn parse(self, message: String) -> IoError {
        IoError::Parse {
            path: self.path.to_path_buf(),
            format: self.format,
            message,
        }
    }

    pub fn unsupported(self, message: String) -> IoError {
        IoError::Unsupported {
            path: self.path.to_path_buf(),
            format: self.format,
            message,
        }
    }
}

/// Parses and validates a `.gltf` or `.glb` file and loads its buffers: the scene reader's
/// one way of reading ([`super::scene::Scene`]), so every reader accepts the same extensions
/// and decodes `EXT_meshopt_compression` alike.
pub(super) fn open(
    path: &Path,
    bytes: &[u8],
    format: &'static str,
    buffers: Buffers<'_>,
) -> Result<(Document, Vec<Vec<u8>>), IoError> {
    let scene = super::scene::read_for_readers(path, bytes, format, buffers)?;
    Ok(scene)
}

/// One triangle primitive's vertices and its triangles (indices local to the primitive).
pub(super) struct Primitive {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
    /// TEXCOORD_0, flipped to the OBJ/PLY convention ([`flip_v`]).
    pub uvs: Option<Vec<[f32; 2]>>,
    pub triangles: Vec<[u32; 3]>,
}

/// Reads a primitive's POSITION, NORMAL, TEXCOORD_0 and triangles after checking their
/// accessors; `None` for points and lines. `sparse` accepts sparse accessors.
pub(super) fn read_primitive(
    ctx: Context<'_>,
    primitive: &gltf::Primitive<'_>,
    what: &str,
    buffers: &[Vec<u8>],
    sparse: bool,
) -> Result<Option<Primitive>, IoError> {
    let (parse, unsupported) = (|m| ctx.parse(m), |m| ctx.unsupported(m));
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(None);
    }
    let position = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or_else(|| parse(format!("{what} has no POSITION attribute")))?;
    let normal = primitive.get(&gltf::Semantic::Normals);
    let uv = primitive.get(&gltf::Semantic::TexCoords(0));
    let indices = primitive.indices();
    let any = [
        DataType::F32,
        DataType::I8,
        DataType::U8,
        DataType::I16,
        DataType::U16,
    ];
    let checks = [
        (Some(&position), "POSITION", Dimensions::Vec3, &any[..]),
        (normal.as_ref(), "NORMAL", Dimensions::Vec3, &any[..]),
        (uv.as_ref(), "TEXCOORD_0", Dimensions::Vec2, &any[..]),
        (
            indices.as_ref(),
            "indices",
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        ),
    ];
    for (accessor, name, dimensions, types) in checks {
        if let Some(accessor) = accessor {
            check_accessor(accessor, dimensions, types, buffers, sparse)
                .map_err(|m| unsupported(format!("{what} {name}: {m}")))?;
        }
    }
    let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let count_mismatch = |name: &str, got: usize, n: usize| {
        parse(format!("{what} has {got} {name} values for {n} positions"))
    };
    // Any component type: integers (KHR_mesh_quantization) read as the floats they stand for.
    let floats = |accessor: &Accessor, name: &str| {
        super::scene::read_floats(accessor, buffers)
            .map_err(|m| parse(format!("{what} {name}: {m}")))
    };
    let positions: Vec<[f32; 3]> = floats(&position, "POSITION")?
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let n = positions.len();
    if n != position.count() {
        return Err(count_mismatch("POSITION", n, position.count()));
    }
    let normals: Option<Vec<[f32; 3]>> = match &normal {
        Some(a) => Some(
            floats(a, "NORMAL")?
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect(),
        ),
        None => None,
    };
    let uvs: Option<Vec<[f32; 2]>> = match &uv {
        Some(a) => Some(
            floats(a, "TEXCOORD_0")?
                .chunks_exact(2)
                .map(|c| flip_v([c[0], c[1]]))
                .collect(),
        ),
        None => None,
    };
    for (name, got) in [
        ("NORMAL", normals.as_ref().map(Vec::len)),
        ("TEXCOORD_0", uvs.as_ref().map(Vec::len)),
    ] {
        if let Some(got) = got.filter(|&g| g != n) {
            return Err(count_mismatch(name, got, n));
        }
    }
    let corners: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = corners.iter().find(|&&i| i as usize >= n) {
        return Err(parse(format!(
            "{what} uses vertex {bad} but has only {n} vertices"
        )));
    }
    let mut triangles = assemble(mode, &corners).map_err(|m| parse(format!("{what}: {m}")))?;
    // Zero-area triangles (valid glTF, common in exported assets) draw nothing: the merged
    // mesh leaves them out. The scene path keeps them, refined flat.
    triangles.retain(|t| {
        t[0] != t[1]
            && t[1] != t[2]
            && t[0] != t[2]
            && !tessella_core::mesh::has_zero_area(&positions, *t)
    });
    Ok(Some(Primitive {
        positions,
        normals,
        uvs,
        triangles,
    }))
}

/// Appends a primitive's attribute, or drops the attribute for the whole mesh once one lacks it.
pub(super) fn merge_attribute<T>(all: &mut Option<Vec<T>>, primitive: Option<Vec<T>>) {
    match (all.as_mut(), primitive) {
        (Some(all), Some(values)) => all.extend(values),
        _ => *all = None,
    }
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

/// Meshes to read with their world transforms.
fn instances(document: &Document) -> Result<Vec<(gltf::Mesh<'_>, Mat4)>, String> {
    let Some(nodes) = scene_nodes(document)? else {
        return Ok(document.meshes().map(|m| (m, Mat4::IDENTITY)).collect());
    };
    Ok(nodes
        .into_iter()
        .filter_map(|(node, world)| Some((node.mesh()?, world)))
        .collect())
}

/// The nodes of the default scene (or the first scene) with their world transforms, parents
/// before children and roots in the file's order; `None` for a file without scenes.
pub(super) fn scene_nodes(
    document: &Document,
) -> Result<Option<Vec<(gltf::Node<'_>, Mat4)>>, String> {
    let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    else {
        return Ok(None);
    };
    let limit = document.nodes().len();
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > limit {
            return Err("the node hierarchy has a cycle".into());
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        stack.extend(node.children().map(|c| (c.clone(), world, depth + 1)));
        out.push((node, world));
    }
    // The stack visits nodes last-first; keep the file's order for readers' sake.
    out.reverse();
    Ok(Some(out))
}

/// Applies a world transform; normals use the inverse transpose, and mirroring flips winding.
fn apply(
    transform: Mat4,
    mut positions: Vec<[f32; 3]>,
    mut normals: Option<Vec<[f32; 3]>>,
    triangles: &mut [[u32; 3]],
) -> (Vec<[f32; 3]>, Option<Vec<[f32; 3]>>) {
    // Identity leaves the data bit-exact (no -0.0 + 0.0 rounding).
    if transform == Mat4::IDENTITY {
        return (positions, normals);
    }
    for p in &mut positions {
        *p = transform.transform_point3(Vec3::from(*p)).into();
    }
    let linear = Mat3::from_mat4(transform);
    let normal_matrix = if linear.determinant() != 0.0 {
        linear.inverse().transpose()
    } else {
        linear
    };
    if let Some(normals) = &mut normals {
        for n in normals {
            *n = (normal_matrix * Vec3::from(*n)).into();
        }
    }
    if linear.determinant() < 0.0 {
        for t in triangles {
            t.swap(1, 2);
        }
    }
    (positions, normals)
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
