//! Wavefront OBJ: read with `tobj`, written by hand.
//!
//! Reading builds one vertex per distinct (position, uv, normal) index triple (`tobj`'s
//! `single_index`), so a position with three normals (a hard corner) becomes three vertices and
//! shared triples stay shared. Polygons are fan-triangulated; points and lines are ignored;
//! `mtllib`/`usemtl` are ignored. `tobj` starts a new vertex set at every `o`, `g` or material
//! change; vertices of a later group with exactly the same position, uv and normal as an
//! earlier group's are welded back, so groups do not cut the surface apart.

use crate::{IoError, MeshView, RawMesh};
use std::collections::HashMap;
use std::io::{BufRead, Read, Write};
use std::path::Path;

const FORMAT: &str = "OBJ";

/// Counts the lines `tobj` has consumed, so errors can say where they happened.
struct LineCounter<R> {
    inner: R,
    lines: usize,
}

impl<R: BufRead> Read for LineCounter<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.lines += buf[..n].iter().filter(|&&b| b == b'\n').count();
        Ok(n)
    }
}

impl<R: BufRead> BufRead for LineCounter<R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.inner.fill_buf()
    }
    fn consume(&mut self, amount: usize) {
        if let Ok(buf) = self.inner.fill_buf() {
            let amount = amount.min(buf.len());
            self.lines += buf[..amount].iter().filter(|&&b| b == b'\n').count();
        }
        self.inner.consume(amount);
    }
}

/// Reads an OBJ file's triangles, normals and uvs.
pub fn read(path: &Path, reader: impl BufRead) -> Result<RawMesh, IoError> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut counted = LineCounter {
        inner: reader,
        lines: 0,
    };
    // Materials are not needed: a loader that loads nothing.
    let no_materials = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let (models, _materials) =
        tobj::load_obj_buf(&mut counted, &options, no_materials).map_err(|e| IoError::Parse {
            path: path.to_path_buf(),
            format: FORMAT,
            message: format!("{e} (detected at line {})", counted.lines.max(1)),
        })?;
    merge(path, models)
}

/// Joins tobj's per-group meshes into one, welding identical vertices across groups.
fn merge(path: &Path, models: Vec<tobj::Model>) -> Result<RawMesh, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message,
    };
    // One corner with a normal (uv) means every corner must have one: they cannot be mixed.
    let has_normals = models.iter().any(|m| !m.mesh.normals.is_empty());
    let has_uvs = models.iter().any(|m| !m.mesh.texcoords.is_empty());
    let mut raw = RawMesh::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    // (position, uv, normal) bits -> vertex, for vertices of earlier groups only.
    let mut earlier: HashMap<[u32; 8], u32> = HashMap::new();
    for model in &models {
        let mesh = &model.mesh;
        let count = mesh.positions.len() / 3;
        if has_normals && mesh.normals.len() != count * 3 {
            return Err(parse(format!(
                "object {:?}: some face corners have a normal (`f v//vn`) and others do not; \
                 give every corner a normal or none",
                model.name
            )));
        }
        if has_uvs && mesh.texcoords.len() != count * 2 {
            return Err(parse(format!(
                "object {:?}: some face corners have a texture coordinate (`f v/vt`) and others \
                 do not; give every corner one or none",
                model.name
            )));
        }
        let mut local = Vec::with_capacity(count);
        let mut added = Vec::new();
        for v in 0..count {
            let p = [0, 1, 2].map(|k| mesh.positions[3 * v + k]);
            let n = has_normals.then(|| [0, 1, 2].map(|k| mesh.normals[3 * v + k]));
            let t = has_uvs.then(|| [0, 1].map(|k| mesh.texcoords[2 * v + k]));
            let key = vertex_key(p, n, t);
            let index = match earlier.get(&key) {
                Some(&index) => index,
                None => {
                    let index = u32::try_from(raw.positions.len()).map_err(|_| {
                        parse("more than 4294967295 vertices do not fit 32-bit indices".into())
                    })?;
                    raw.positions.push(p);
                    normals.extend(n);
                    uvs.extend(t);
                    added.push((key, index));
                    index
                }
            };
            local.push(index);
        }
        earlier.extend(added);
        for (face, corners) in mesh.indices.chunks_exact(3).enumerate() {
            let mut t = [0u32; 3];
            for (slot, &i) in t.iter_mut().zip(corners) {
                *slot = *local
                    .get(i as usize)
                    .ok_or_else(|| IoError::IndexOutOfRange {
                        path: path.to_path_buf(),
                        what: "face",
                        item: face,
                        index: i.into(),
                        count,
                    })?;
            }
            raw.triangles.push(t);
        }
    }
    raw.normals = has_normals.then_some(normals);
    raw.uvs = has_uvs.then_some(uvs);
    raw.check(path, FORMAT)?;
    Ok(raw)
}

fn vertex_key(p: [f32; 3], n: Option<[f32; 3]>, t: Option<[f32; 2]>) -> [u32; 8] {
    let n = n.unwrap_or_default();
    let t = t.unwrap_or_default();
    [p[0], p[1], p[2], n[0], n[1], n[2], t[0], t[1]].map(f32::to_bits)
}

/// Writes one `v` (and `vt`, `vn`) per vertex and `f` lines with the same index for each
/// attribute. Numbers use Rust's shortest round-trip formatting, so reading back is exact.
pub fn write(out: &mut dyn Write, mesh: &MeshView) -> std::io::Result<()> {
    out.write_all(HEADER)?;
    write_floats(out, b"v", mesh.positions)?;
    if let Some(uvs) = mesh.uvs {
        write_floats(out, b"vt", uvs)?;
    }
    if let Some(normals) = mesh.normals {
        write_floats(out, b"vn", normals)?;
    }
    write_faces(
        out,
        mesh.triangles,
        mesh.uvs.is_some(),
        mesh.normals.is_some(),
    )
}

/// The file's first line.
pub(crate) const HEADER: &[u8] = b"# written by tessella\n";

/// One `tag x y z` line per value: a run of the `v`, `vt` or `vn` section.
pub(crate) fn write_floats<const N: usize>(
    out: &mut dyn Write,
    tag: &'static [u8],
    values: &[[f32; N]],
) -> std::io::Result<()> {
    use crate::encode::{push_f32, write_records};
    write_records(out, values.len(), 12 * N, |i, out| {
        out.extend_from_slice(tag);
        for x in values[i] {
            out.push(b' ');
            push_f32(out, x);
        }
        out.push(b'\n');
    })
}

/// One `f` line per triangle (0-based indices in, 1-based out), naming the uv and normal of
/// each corner by the same index when the file has them.
pub(crate) fn write_faces(
    out: &mut dyn Write,
    triangles: &[[u32; 3]],
    uvs: bool,
    normals: bool,
) -> std::io::Result<()> {
    use crate::encode::{push_int, write_records};
    write_records(out, triangles.len(), 40, |f, out| {
        out.push(b'f');
        for &i in &triangles[f] {
            let i = u64::from(i) + 1;
            out.push(b' ');
            push_int(out, i);
            match (uvs, normals) {
                (true, true) => {
                    out.push(b'/');
                    push_int(out, i);
                    out.push(b'/');
                    push_int(out, i);
                }
                (true, false) => {
                    out.push(b'/');
                    push_int(out, i);
                }
                (false, true) => {
                    out.extend_from_slice(b"//");
                    push_int(out, i);
                }
                (false, false) => {}
            }
        }
        out.push(b'\n');
    })
}
