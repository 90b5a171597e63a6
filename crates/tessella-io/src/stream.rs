//! Writing a mesh that never sits in memory whole: a [`MeshSource`] hands out its vertices and
//! triangles in runs, and each format's writer streams its sections from them. Headers (PLY
//! counts, the GLB JSON and chunk lengths) are computed before any data, from the counts (and,
//! for glTF, a first pass for the position bounds). Sections that a format stores one after
//! the other (OBJ's `v`, `vt`, `vn`; GLB's positions, normals, uvs) take one pass each over the
//! source. The bytes are those of [`crate::write_mesh`] for the same mesh: the writers share
//! their record encoders.

use crate::{Format, IoError, MeshView, WriteOptions};
use std::io::Write;
use std::path::Path;

/// Which attributes a pass over the vertices needs (positions are always filled).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Wanted {
    pub normals: bool,
    pub uvs: bool,
    /// The per-vertex scalars ([`MeshSource::scalar_names`]) and, where the source has them,
    /// the origins ([`MeshSource::has_origin`]).
    pub extras: bool,
}

/// One run of consecutive vertices (defined with the PLY extras it carries, which the PLY
/// writer writes from one run too).
pub use crate::ply::VertexRun;

/// A triangle given by its three corner positions (what STL stores).
pub type Corners = [[f32; 3]; 3];

/// A mesh produced in runs: consecutive vertices, consecutive triangles, or the corner
/// positions of consecutive triangles (for STL). Every call covers the whole mesh, in order.
pub trait MeshSource: Sync {
    fn vertex_count(&self) -> u64;
    fn triangle_count(&self) -> u64;
    fn has_normals(&self) -> bool;
    fn has_uvs(&self) -> bool;
    /// The names of the per-vertex scalars the vertex runs carry when asked (PLY vertex
    /// properties, glTF `_NAME` attributes); none unless the source says otherwise.
    fn scalar_names(&self) -> Vec<&str> {
        Vec::new()
    }
    /// Whether the vertex runs carry each vertex's origin (coarse face and barycentrics, PLY
    /// only) when asked.
    fn has_origin(&self) -> bool {
        false
    }
    /// Calls `each` with runs of vertices (positions, the attributes in `want`) that together
    /// are all vertices in order.
    fn vertices(
        &self,
        want: Wanted,
        each: &mut dyn FnMut(VertexRun<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<()>;
    /// Calls `each` with runs of triangles that together are all triangles in order.
    fn triangles(
        &self,
        each: &mut dyn FnMut(&[[u32; 3]]) -> std::io::Result<()>,
    ) -> std::io::Result<()>;
    /// Calls `each` with the corner positions of runs of triangles, all triangles in order.
    fn triangle_corners(
        &self,
        each: &mut dyn FnMut(&[Corners]) -> std::io::Result<()>,
    ) -> std::io::Result<()>;
}

/// The format `path` and `options` name (binary or ascii PLY).
fn format_of(path: &Path, options: &WriteOptions) -> Result<Format, IoError> {
    Ok(match Format::from_path(path)? {
        Format::Ply if options.ply_ascii => Format::PlyAscii,
        format => format,
    })
}

/// The bytes a file of `source` will take: exact for binary PLY, GLB and STL; for text
/// (ascii PLY, OBJ, glTF's base64) an estimate from typical number lengths.
pub fn expected_bytes(
    path: &Path,
    source: &dyn MeshSource,
    options: &WriteOptions,
) -> Result<u64, IoError> {
    let (v, t) = (source.vertex_count(), source.triangle_count());
    let floats = 3
        + 3 * u64::from(source.has_normals())
        + 2 * u64::from(source.has_uvs())
        + source.scalar_names().len() as u64
        + 4 * u64::from(source.has_origin());
    Ok(match format_of(path, options)? {
        Format::Ply => 300 + v * 4 * floats + t * 13,
        // About 10 characters per number and separator (shortest round-trip text).
        Format::PlyAscii => 300 + v * 10 * floats + t * 30,
        Format::Obj => 30 + v * (10 * floats + 6) + t * 40,
        Format::Glb => 1000 + v * 4 * floats + t * 12,
        Format::Gltf => 1000 + (v * 4 * floats + t * 12) * 4 / 3,
        Format::Stl => 84 + t * 50,
    })
}

/// Refuses to start when the disk holding `path`'s folder has less than `need` bytes free,
/// with a message that gives both.
pub fn check_free_space(path: &Path, need: u64) -> Result<(), IoError> {
    let Some(free) = free_bytes(path) else {
        return Ok(()); // the system does not say; writing will
    };
    if need > free {
        return Err(IoError::Write {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::StorageFull,
                format!(
                    "needs {}, the disk has {} free",
                    decimal_bytes(need),
                    decimal_bytes(free)
                ),
            ),
        });
    }
    Ok(())
}

/// Bytes available to this user on the file system of `path`'s folder; `None` when the system
/// cannot say (the free-space check is then skipped and a full disk surfaces as a write error).
#[cfg(unix)]
fn free_bytes(path: &Path) -> Option<u64> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let stat = rustix::fs::statvfs(dir).ok()?;
    Some(stat.f_bavail.saturating_mul(stat.f_frsize))
}

/// No free-space query off Unix: the check is skipped (see the Unix version).
#[cfg(not(unix))]
fn free_bytes(_path: &Path) -> Option<u64> {
    None
}

/// `41.2 GB`, `512.0 MB`: decimal units, as disks are sold and `df -H` prints.
pub fn decimal_bytes(bytes: u64) -> String {
    let units = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1000.0 && unit + 1 < units.len() {
        value /= 1000.0;
        unit += 1;
    }
    match unit {
        0 => format!("{bytes} B"),
        _ => format!("{value:.1} {}", units[unit]),
    }
}

/// Writes `source` to `path` (format by extension, as [`crate::write_mesh`]) run by run,
/// atomically: after checking the free disk space against [`expected_bytes`], into a
/// temporary file renamed over `path` once complete. `progress` receives bytes written.
pub fn write_streamed(
    path: &Path,
    source: &dyn MeshSource,
    options: &WriteOptions,
    progress: &dyn Fn(u64),
) -> Result<(), IoError> {
    let format = format_of(path, options)?;
    if source.triangle_count() == 0 {
        return Err(IoError::BadMesh {
            path: path.to_path_buf(),
            message: "the mesh has no triangles".into(),
        });
    }
    crate::check_vertex_extras(path, format, &source.scalar_names(), source.has_origin())?;
    check_free_space(path, expected_bytes(path, source, options)?)?;
    crate::write_atomic_with(path, options.durability, |out| {
        let mut out = Counted { out, progress };
        match format {
            Format::Ply => ply(&mut out, source, false),
            Format::PlyAscii => ply(&mut out, source, true),
            Format::Obj => obj(&mut out, source),
            Format::Glb => glb(&mut out, source),
            Format::Gltf => gltf(&mut out, source),
            Format::Stl => stl(&mut out, source),
        }
    })
}

/// A writer that reports the bytes passing through it.
struct Counted<'a> {
    out: &'a mut dyn Write,
    progress: &'a dyn Fn(u64),
}

impl Write for Counted<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        (self.progress)(n as u64);
        Ok(n)
    }
    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        self.out.write_all(buf)?;
        (self.progress)(buf.len() as u64);
        Ok(())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

fn all(source: &dyn MeshSource) -> Wanted {
    Wanted {
        normals: source.has_normals(),
        uvs: source.has_uvs(),
        extras: true,
    }
}

fn ply(out: &mut dyn Write, source: &dyn MeshSource, ascii: bool) -> std::io::Result<()> {
    let counts = (source.vertex_count(), source.triangle_count());
    let has = (source.has_normals(), source.has_uvs());
    let names = source.scalar_names();
    crate::ply::write_header(out, counts, has, &names, source.has_origin(), ascii)?;
    source.vertices(all(source), &mut |run| {
        crate::ply::write_vertices(out, &run, ascii)
    })?;
    source.triangles(&mut |run| crate::ply::write_faces(out, run, ascii))
}

fn obj(out: &mut dyn Write, source: &dyn MeshSource) -> std::io::Result<()> {
    use crate::obj::{write_floats, HEADER};
    out.write_all(HEADER)?;
    source.vertices(only(false, false), &mut |run| {
        write_floats(out, b"v", run.mesh.positions)
    })?;
    if source.has_uvs() {
        source.vertices(only(false, true), &mut |run| {
            write_floats(out, b"vt", run.mesh.uvs.unwrap_or_default())
        })?;
    }
    if source.has_normals() {
        source.vertices(only(true, false), &mut |run| {
            write_floats(out, b"vn", run.mesh.normals.unwrap_or_default())
        })?;
    }
    let (uvs, normals) = (source.has_uvs(), source.has_normals());
    source.triangles(&mut |run| crate::obj::write_faces(out, run, uvs, normals))
}

/// The glTF shape of `source`: its counts, attributes, and the bounds of its positions and
/// scalars (one pass).
fn gltf_shape(source: &dyn MeshSource) -> std::io::Result<crate::gltf::Shape> {
    use glam::Vec3;
    // The bounds, folded point by point in file order as `tessella_core::mesh::bounds` and
    // the in-memory writer do.
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    let names = source.scalar_names();
    let mut ranges = vec![(f32::INFINITY, f32::NEG_INFINITY); names.len()];
    let want = Wanted {
        extras: !names.is_empty(),
        ..only(false, false)
    };
    source.vertices(want, &mut |run| {
        for p in run.mesh.positions {
            lo = lo.min(Vec3::from(*p));
            hi = hi.max(Vec3::from(*p));
        }
        for ((_, values), range) in run.scalars.iter().zip(&mut ranges) {
            *range = crate::gltf::fold_range(*range, values);
        }
        Ok(())
    })?;
    Ok(crate::gltf::Shape {
        vertices: source.vertex_count(),
        triangles: source.triangle_count(),
        normals: source.has_normals(),
        uvs: source.has_uvs(),
        bounds: (lo.into(), hi.into()),
        scalars: names.iter().map(|n| n.to_string()).zip(ranges).collect(),
    })
}

fn only(normals: bool, uvs: bool) -> Wanted {
    Wanted {
        normals,
        uvs,
        extras: false,
    }
}

/// The glTF buffer of `source` (positions, normals, uvs, triangles), a pass per attribute.
fn gltf_buffer(
    out: &mut dyn Write,
    source: &dyn MeshSource,
    shape: &crate::gltf::Shape,
) -> std::io::Result<()> {
    use crate::encode::{write_le, write_records};
    source.vertices(only(false, false), &mut |run| {
        write_le(out, run.mesh.positions)
    })?;
    if shape.normals {
        source.vertices(only(true, false), &mut |run| {
            write_le(out, run.mesh.normals.unwrap_or_default())
        })?;
    }
    if shape.uvs {
        source.vertices(only(false, true), &mut |run| {
            let uvs = run.mesh.uvs.unwrap_or_default();
            write_records(out, uvs.len(), 8, |i, out| {
                crate::gltf::flip_v(uvs[i])
                    .iter()
                    .for_each(|x| out.extend_from_slice(&x.to_le_bytes()))
            })
        })?;
    }
    // One pass a scalar: the buffer holds each attribute whole, one after the other.
    let extras = Wanted {
        extras: true,
        ..only(false, false)
    };
    for k in 0..shape.scalars.len() {
        source.vertices(extras, &mut |run| write_le(out, run.scalars[k].1))?;
    }
    source.triangles(&mut |run| write_le(out, run))
}

fn glb(out: &mut dyn Write, source: &dyn MeshSource) -> std::io::Result<()> {
    let shape = gltf_shape(source)?;
    let (doc, bin_len) = crate::gltf::glb_document(&shape);
    crate::gltf::write_glb_header(out, &doc, bin_len)?;
    gltf_buffer(out, source, &shape)?;
    crate::gltf::write_glb_padding(out, bin_len)
}

/// `.gltf`: the JSON text with the buffer base64-encoded into it as the pieces come.
fn gltf(out: &mut dyn Write, source: &dyn MeshSource) -> std::io::Result<()> {
    let shape = gltf_shape(source)?;
    let doc = crate::gltf::gltf_document(&shape);
    crate::gltf::write_gltf_text(out, &doc, |encoder| gltf_buffer(encoder, source, &shape))
}

fn stl(out: &mut dyn Write, source: &dyn MeshSource) -> std::io::Result<()> {
    let count = crate::stl::check_count(source.triangle_count())?;
    crate::stl::write_header(out, count)?;
    source.triangle_corners(&mut |run| crate::stl::write_facets(out, run))
}

/// A [`MeshView`] as a source of one run each (what the tests compare streamed files with,
/// and what small in-memory meshes are written through).
impl MeshSource for MeshView<'_> {
    fn vertex_count(&self) -> u64 {
        self.positions.len() as u64
    }
    fn triangle_count(&self) -> u64 {
        self.triangles.len() as u64
    }
    fn has_normals(&self) -> bool {
        self.normals.is_some()
    }
    fn has_uvs(&self) -> bool {
        self.uvs.is_some()
    }
    fn vertices(
        &self,
        _want: Wanted,
        each: &mut dyn FnMut(VertexRun<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        each(VertexRun {
            mesh: MeshView {
                triangles: &[],
                ..*self
            },
            scalars: &[],
            origin: None,
        })
    }
    fn triangles(
        &self,
        each: &mut dyn FnMut(&[[u32; 3]]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        each(self.triangles)
    }
    fn triangle_corners(
        &self,
        each: &mut dyn FnMut(&[Corners]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let corners: Vec<Corners> = self
            .triangles
            .iter()
            .map(|t| t.map(|i| self.positions[i as usize]))
            .collect();
        each(&corners)
    }
}
