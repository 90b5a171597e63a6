//! Reads every triangle primitive the default scene shows, in world space.
//!
//! Meshes are taken from the default scene (or the first scene) with each node's world transform
//! applied to positions and normals; a mesh used by two nodes appears twice, and a mirroring
//! transform flips the triangles' winding back to counter-clockwise. A file without scenes has
//! its meshes read as stored. Primitives are merged with offset indices and are not welded to
//! each other. Zero-area triangles (a repeated corner, corners on a line) are left out: they
//! draw nothing, and the core's mesh refuses them ([`super::scene`] keeps them, refined flat).
//! Modes TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN are read (strip triangles with a repeated
//! index, used to stitch strips, are dropped); points and lines are skipped.
//!
//! Attributes: POSITION, NORMAL, TEXCOORD_0 (floats, or integers under
//! `KHR_mesh_quantization`, read as the floats they stand for), indices (u8/u16/u32) or none. If
//! any primitive lacks NORMAL (or TEXCOORD_0), the merged mesh has no normals (uvs), since they
//! cannot be mixed; the core then computes normals. Sparse accessors and accessors without a
//! buffer view are refused.
//! Float `SCALAR` attributes `_NAME` go to [`RawMesh::vertex_scalars`] as `NAME` when every
//! primitive has them; other application-specific attributes are ignored.
//!
//! The parsing ([`open`]), accessor checks ([`super::data::check_accessor`]), primitive reading
//! ([`read_primitive`]) and scene walk ([`scene_nodes`]) are shared with
//! [`super::read_animated`], which accepts sparse accessors.

use super::data::{assemble, check_accessor, Buffers};
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
    super::scene::read_for_readers(path, bytes, format, buffers)
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
    triangles.retain(|t| !tessella_core::mesh::is_degenerate(&positions, *t));
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
