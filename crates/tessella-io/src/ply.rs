//! PLY: read with `ply-rs-bw` (ascii, binary little- and big-endian), written by hand.
//!
//! Read: element `vertex` with `x y z` (float or double; required), `nx ny nz`, texture
//! coordinates as `u v`, `s t`, `texture_u texture_v` or `texture_s texture_t`; every other
//! scalar vertex property goes to [`RawMesh::vertex_scalars`] as f32 (list properties on vertices
//! are ignored). Element `face` with a list `vertex_indices` or `vertex_index` of any integer
//! type; polygons with more than three corners are fan-triangulated (corner 0 with each
//! following pair), faces with fewer than three corners are refused. Element `edge` with
//! `vertex1 vertex2` and scalar properties goes to [`RawMesh::edges`]. Other elements are read
//! and ignored.
//!
//! Write: `binary_little_endian` (default) or `ascii`; float `x y z`, `nx ny nz`, `u v`, then
//! any extra scalar vertex properties ([`write_file_with`]: solution fields carried through
//! refinement) as `float NAME`; faces as `list uchar uint vertex_indices`.

use crate::{IoError, MeshView, RawEdge, RawMesh};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{ElementDef, Property, PropertyAccess, PropertyAccessResult, PropertyType};
use smallvec::SmallVec;
use std::collections::BTreeMap;
use std::io::{BufRead, Write};
use std::path::Path;

const FORMAT: &str = "PLY";

/// One element of the payload: scalar values and lists in header order. Cheaper than
/// `ply_rs_bw::ply::DefaultElement`, which keeps a map with owned names per element; held
/// inline for the usual sizes (a vertex's few properties, a triangle's one list of three), since
/// allocating per row was most of a small file's reading.
#[derive(Debug, Default)]
struct Row {
    scalars: SmallVec<[f64; 12]>,
    lists: SmallVec<[List; 1]>,
}

/// One list property's values.
type List = SmallVec<[f64; 4]>;

fn list<T: Copy + Into<f64>>(values: Vec<T>) -> List {
    values.into_iter().map(Into::into).collect()
}

impl PropertyAccess for Row {
    fn new() -> Self {
        Row::default()
    }
    fn set_property(&mut self, _name: &str, property: Property) -> PropertyAccessResult {
        match property {
            Property::Char(v) => self.scalars.push(v.into()),
            Property::UChar(v) => self.scalars.push(v.into()),
            Property::Short(v) => self.scalars.push(v.into()),
            Property::UShort(v) => self.scalars.push(v.into()),
            Property::Int(v) => self.scalars.push(v.into()),
            Property::UInt(v) => self.scalars.push(v.into()),
            Property::Float(v) => self.scalars.push(v.into()),
            Property::Double(v) => self.scalars.push(v),
            Property::ListChar(v) => self.lists.push(list(v)),
            Property::ListUChar(v) => self.lists.push(list(v)),
            Property::ListShort(v) => self.lists.push(list(v)),
            Property::ListUShort(v) => self.lists.push(list(v)),
            Property::ListInt(v) => self.lists.push(list(v)),
            Property::ListUInt(v) => self.lists.push(list(v)),
            Property::ListFloat(v) => self.lists.push(list(v)),
            Property::ListDouble(v) => self.lists.push(v.into()),
        }
        PropertyAccessResult::Set
    }
}

/// Where each named property of an element lands in a [`Row`].
#[derive(Debug)]
enum Slot {
    Scalar(usize),
    List(usize),
}

fn slots(element: &ElementDef) -> Vec<(&str, Slot)> {
    let (mut scalars, mut lists) = (0, 0);
    element
        .properties
        .values()
        .map(|p| {
            let slot = match p.data_type {
                PropertyType::Scalar(_) => {
                    scalars += 1;
                    Slot::Scalar(scalars - 1)
                }
                PropertyType::List(..) => {
                    lists += 1;
                    Slot::List(lists - 1)
                }
            };
            (p.name.as_str(), slot)
        })
        .collect()
}

fn scalar_slot(slots: &[(&str, Slot)], name: &str) -> Option<usize> {
    slots.iter().find_map(|(n, s)| match s {
        Slot::Scalar(i) if *n == name => Some(*i),
        _ => None,
    })
}

/// Reads a PLY file (any encoding).
pub fn read(path: &Path, mut reader: impl BufRead) -> Result<RawMesh, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message,
    };
    let parser = Parser::<Row>::new();
    let mut reader = ply_rs_bw::parser::Reader::new(&mut reader);
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| parse(e.to_string()))?;
    // An element without properties takes no bytes per row, so a huge declared count would be
    // read (as empty rows) for ever instead of running into the end of the file (found by
    // `fuzz/fuzz_targets/ply_binary.rs`).
    if let Some((name, element)) = header
        .elements
        .iter()
        .find(|(_, e)| e.properties.is_empty() && e.count > 0)
    {
        return Err(parse(format!(
            "element {name:?} declares {} rows but no properties",
            element.count
        )));
    }
    let payload = parser
        .read_payload(&mut reader, &header)
        .map_err(|e| parse(e.to_string()))?;
    let mut ply = ply_rs_bw::ply::Ply::<Row>::new();
    ply.header = header;
    ply.payload = payload;
    let rows = |name: &str| ply.payload.get(name).map(Vec::as_slice).unwrap_or(&[]);
    for (name, element) in &ply.header.elements {
        let (scalars, lists) =
            element
                .properties
                .values()
                .fold((0, 0), |(s, l), p| match p.data_type {
                    PropertyType::Scalar(_) => (s + 1, l),
                    PropertyType::List(..) => (s, l + 1),
                });
        if let Some(row) = rows(name)
            .iter()
            .find(|r| r.scalars.len() != scalars || r.lists.len() != lists)
        {
            return Err(parse(format!(
                "element {name:?} has {} scalars and {} lists where the header declares {scalars} and {lists}",
                row.scalars.len(),
                row.lists.len()
            )));
        }
    }
    let vertex = ply.header.elements.get("vertex").ok_or_else(|| {
        parse("there is no `element vertex`; a mesh PLY needs one with x, y, z".into())
    })?;
    let mut raw = read_vertices(path, vertex, rows("vertex"))?;
    if let Some(face) = ply.header.elements.get("face") {
        raw.triangles = read_faces(path, face, rows("face"))?;
    }
    if let Some(edge) = ply.header.elements.get("edge") {
        raw.edges = read_edges(path, edge, rows("edge"))?;
    }
    raw.check(path, FORMAT)?;
    Ok(raw)
}

/// Texture coordinate property pairs, in order of preference.
const UV_NAMES: [[&str; 2]; 4] = [
    ["u", "v"],
    ["s", "t"],
    ["texture_u", "texture_v"],
    ["texture_s", "texture_t"],
];

fn read_vertices(path: &Path, element: &ElementDef, rows: &[Row]) -> Result<RawMesh, IoError> {
    let slots = slots(element);
    let find = |names: &[&str]| -> Option<Vec<usize>> {
        names.iter().map(|n| scalar_slot(&slots, n)).collect()
    };
    let position = find(&["x", "y", "z"]).ok_or_else(|| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message: "`element vertex` lacks one of the scalar properties x, y, z".into(),
    })?;
    let normal = find(&["nx", "ny", "nz"]);
    let (uv_names, uv) = UV_NAMES
        .iter()
        .find_map(|names| find(names).map(|slots| (&names[..], slots)))
        .unzip();
    let used: Vec<&str> = ["x", "y", "z"]
        .into_iter()
        .chain(
            normal
                .as_ref()
                .map_or(&[][..], |_| &["nx", "ny", "nz"][..])
                .iter()
                .copied(),
        )
        .chain(uv_names.unwrap_or(&[]).iter().copied())
        .collect();
    let gather = |slots: &[usize]| -> Vec<Vec<f32>> {
        rows.iter()
            .map(|r| slots.iter().map(|&i| r.scalars[i] as f32).collect())
            .collect()
    };
    let mut raw = RawMesh {
        positions: gather(&position)
            .into_iter()
            .map(|v| [v[0], v[1], v[2]])
            .collect(),
        normals: normal.map(|s| gather(&s).into_iter().map(|v| [v[0], v[1], v[2]]).collect()),
        uvs: uv.map(|s| gather(&s).into_iter().map(|v| [v[0], v[1]]).collect()),
        ..RawMesh::default()
    };
    for (name, slot) in &slots {
        if let (Slot::Scalar(i), false) = (slot, used.contains(name)) {
            let values = rows.iter().map(|r| r.scalars[*i] as f32).collect();
            raw.vertex_scalars.insert(name.to_string(), values);
        }
    }
    Ok(raw)
}

/// Converts a list entry to a vertex index, refusing negative and fractional values.
fn to_index(value: f64) -> Option<u32> {
    (value >= 0.0 && value <= f64::from(u32::MAX) && value.fract() == 0.0).then_some(value as u32)
}

fn read_faces(path: &Path, element: &ElementDef, rows: &[Row]) -> Result<Vec<[u32; 3]>, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message,
    };
    let slots = slots(element);
    let list = slots
        .iter()
        .find_map(|(n, s)| match s {
            Slot::List(i) if *n == "vertex_indices" || *n == "vertex_index" => Some(*i),
            _ => None,
        })
        .ok_or_else(|| {
            parse("`element face` has no list property vertex_indices or vertex_index".into())
        })?;
    if let Some(p) = element
        .properties
        .values()
        .find(|p| p.name == "vertex_indices" || p.name == "vertex_index")
    {
        use ply_rs_bw::ply::ScalarType::{Double, Float};
        if let PropertyType::List(_, Float | Double) = p.data_type {
            return Err(parse(format!(
                "face property {} holds floating-point numbers; vertex indices must be integers",
                p.name
            )));
        }
    }
    let mut triangles = Vec::with_capacity(rows.len());
    for (face, row) in rows.iter().enumerate() {
        let corners = &row.lists[list];
        if corners.len() < 3 {
            return Err(parse(format!(
                "face {face} has {} corners; a face needs at least 3",
                corners.len()
            )));
        }
        let index = |k: usize| {
            to_index(corners[k]).ok_or_else(|| {
                parse(format!(
                    "face {face} has an invalid vertex index {}",
                    corners[k]
                ))
            })
        };
        // Fan triangulation: (0, k, k + 1).
        let first = index(0)?;
        for k in 1..corners.len() - 1 {
            triangles.push([first, index(k)?, index(k + 1)?]);
        }
    }
    Ok(triangles)
}

fn read_edges(path: &Path, element: &ElementDef, rows: &[Row]) -> Result<Vec<RawEdge>, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: FORMAT,
        message,
    };
    let slots = slots(element);
    let ends = [
        scalar_slot(&slots, "vertex1"),
        scalar_slot(&slots, "vertex2"),
    ];
    let [Some(a), Some(b)] = ends else {
        return Err(parse(
            "`element edge` lacks one of the scalar properties vertex1, vertex2".into(),
        ));
    };
    rows.iter()
        .enumerate()
        .map(|(edge, row)| {
            let vertex = |i: usize| {
                to_index(row.scalars[i]).ok_or_else(|| {
                    parse(format!(
                        "edge {edge} has an invalid vertex index {}",
                        row.scalars[i]
                    ))
                })
            };
            let scalars: BTreeMap<String, f32> = slots
                .iter()
                .filter_map(|(name, slot)| match slot {
                    Slot::Scalar(i) if *i != a && *i != b => {
                        Some((name.to_string(), row.scalars[*i] as f32))
                    }
                    _ => None,
                })
                .collect();
            Ok(RawEdge {
                vertices: [vertex(a)?, vertex(b)?],
                scalars,
            })
        })
        .collect()
}

/// The vertex properties tessella writes itself: no extra scalar may take their names.
pub(crate) const RESERVED: &[&str] = &[
    "x", "y", "z", "nx", "ny", "nz", "u", "v", "face", "bary1", "bary2", "bary3",
];

/// Where each vertex comes from: its coarse face and barycentric coordinates in that face's
/// corner order (`tessella_core::refine::Plan::origin`), written as the vertex properties
/// `int face` and `float bary1, bary2, bary3`.
#[derive(Debug, Clone, Copy)]
pub struct Origin<'a> {
    pub faces: &'a [u32],
    pub bary: &'a [[f32; 3]],
}

/// Writes `mesh` with its vertices' [`Origin`] to a `.ply` file, atomically, after the same
/// checks as [`crate::write_mesh`] (and one origin per vertex). A face of `u32::MAX` (a vertex
/// no face uses) is written as -1.
pub fn write_file_with_origin(
    path: &std::path::Path,
    mesh: MeshView,
    origin: Origin,
    ascii: bool,
) -> Result<(), crate::IoError> {
    write_file_with(path, mesh, &[], Some(origin), ascii)
}

/// Extra per-vertex scalars to write: `(name, one value per vertex)`.
pub type VertexScalars<'a> = [(&'a str, &'a [f32])];

/// One run of consecutive vertices: a [`MeshView`] without triangles, and, when the pass
/// asked for [`Wanted::extras`](crate::stream::Wanted::extras), the run's per-vertex scalars
/// (in [`MeshSource::scalar_names`](crate::stream::MeshSource::scalar_names) order) and
/// origins. What a [`crate::stream::MeshSource`] hands its writers, and what the PLY writer
/// writes a whole mesh from.
pub struct VertexRun<'a> {
    pub mesh: MeshView<'a>,
    pub scalars: &'a VertexScalars<'a>,
    pub origin: Option<Origin<'a>>,
}

/// Writes `mesh` to a `.ply` file, atomically, with extra per-vertex scalar properties
/// (`property float NAME`, after the positions, normals and uvs) and optionally each vertex's
/// [`Origin`]. Names must be non-empty PLY words (no whitespace), distinct and not taken by
/// the standard properties; every array needs one value per vertex.
pub fn write_file_with(
    path: &std::path::Path,
    mesh: MeshView,
    scalars: &VertexScalars,
    origin: Option<Origin>,
    ascii: bool,
) -> Result<(), crate::IoError> {
    mesh.check(path)?;
    let n = mesh.positions.len();
    let bad = |message: String| crate::IoError::BadMesh {
        path: path.to_path_buf(),
        message,
    };
    if let Some(origin) = origin {
        if origin.faces.len() != n || origin.bary.len() != n {
            return Err(bad(format!(
                "{} origin faces and {} barycentrics for {n} vertices",
                origin.faces.len(),
                origin.bary.len()
            )));
        }
    }
    let names: Vec<&str> = scalars.iter().map(|(name, _)| *name).collect();
    crate::check_vertex_extras(path, crate::Format::Ply, &names, origin.is_some())?;
    for (name, values) in scalars {
        if values.len() != n {
            return Err(bad(format!(
                "vertex property {name:?} has {} values for {n} vertices",
                values.len()
            )));
        }
    }
    let run = VertexRun {
        mesh,
        scalars,
        origin,
    };
    crate::write_atomic(path, |out| write_whole(out, &run, ascii))
}

/// Writes a PLY file, binary little-endian or ascii.
pub fn write(out: &mut dyn Write, mesh: &MeshView, ascii: bool) -> std::io::Result<()> {
    let run = VertexRun {
        mesh: *mesh,
        scalars: &[],
        origin: None,
    };
    write_whole(out, &run, ascii)
}

/// A whole file from one run of every vertex, with the triangles of its mesh.
fn write_whole(out: &mut dyn Write, run: &VertexRun, ascii: bool) -> std::io::Result<()> {
    let mesh = &run.mesh;
    let counts = (mesh.positions.len() as u64, mesh.triangles.len() as u64);
    let names: Vec<&str> = run.scalars.iter().map(|(name, _)| *name).collect();
    let has = (mesh.normals.is_some(), mesh.uvs.is_some());
    write_header(out, counts, has, &names, run.origin.is_some(), ascii)?;
    write_vertices(out, run, ascii)?;
    write_faces(out, mesh.triangles, ascii)
}

/// The header for `counts` (vertices, triangles), with normals and uvs as `has` says, extra
/// float properties `scalars` and the origin properties.
pub(crate) fn write_header(
    out: &mut dyn Write,
    (vertices, triangles): (u64, u64),
    (normals, uvs): (bool, bool),
    scalars: &[&str],
    origin: bool,
    ascii: bool,
) -> std::io::Result<()> {
    let encoding = if ascii {
        "ascii"
    } else {
        "binary_little_endian"
    };
    writeln!(
        out,
        "ply\nformat {encoding} 1.0\ncomment written by tessella"
    )?;
    writeln!(out, "element vertex {vertices}")?;
    let mut names = vec!["x", "y", "z"];
    if normals {
        names.extend(["nx", "ny", "nz"]);
    }
    if uvs {
        names.extend(["u", "v"]);
    }
    names.extend(scalars);
    for name in &names {
        writeln!(out, "property float {name}")?;
    }
    if origin {
        writeln!(
            out,
            "property int face\nproperty float bary1\nproperty float bary2\nproperty float bary3"
        )?;
    }
    writeln!(out, "element face {triangles}")?;
    writeln!(out, "property list uchar uint vertex_indices\nend_header")
}

/// The vertex records of `run` (its mesh's triangles are not read): a run of the vertex
/// element.
pub(crate) fn write_vertices(
    out: &mut dyn Write,
    run: &VertexRun,
    ascii: bool,
) -> std::io::Result<()> {
    let (mesh, scalars, origin) = (&run.mesh, run.scalars, run.origin);
    // One vertex record: its floats, then the origin (face, barycentrics) if asked for.
    let floats = 3
        + 3 * usize::from(mesh.normals.is_some())
        + 2 * usize::from(mesh.uvs.is_some())
        + scalars.len()
        + 4 * usize::from(origin.is_some());
    let record_bytes = if ascii { 16 * floats } else { 4 * floats };
    if !ascii {
        // Binary: every property is one 4-byte word, stored into the record's slot.
        return crate::encode::write_fixed_records(
            out,
            mesh.positions.len(),
            record_bytes,
            |v, slot| {
                let mut w = crate::encode::Words::new(slot);
                w.floats(mesh.positions[v]);
                if let Some(normals) = mesh.normals {
                    w.floats(normals[v]);
                }
                if let Some(uvs) = mesh.uvs {
                    w.floats(uvs[v]);
                }
                scalars.iter().for_each(|(_, s)| w.put(s[v].to_le_bytes()));
                if let Some(o) = origin {
                    w.put((o.faces[v] as i32).to_le_bytes());
                    w.floats(o.bary[v]);
                }
            },
        );
    }
    crate::encode::write_records(out, mesh.positions.len(), record_bytes, |v, out| {
        let mut first = true;
        let mut separate = |out: &mut Vec<u8>| {
            if ascii && !first {
                out.push(b' ');
            }
            first = false;
        };
        let mut float = |out: &mut Vec<u8>, x: f32| {
            separate(out);
            if ascii {
                crate::encode::push_f32(out, x);
            } else {
                out.extend_from_slice(&x.to_le_bytes());
            }
        };
        mesh.positions[v].into_iter().for_each(|x| float(out, x));
        if let Some(normals) = mesh.normals {
            normals[v].into_iter().for_each(|x| float(out, x));
        }
        if let Some(uvs) = mesh.uvs {
            uvs[v].into_iter().for_each(|x| float(out, x));
        }
        scalars.iter().for_each(|(_, s)| float(out, s[v]));
        if let Some(o) = origin {
            let face = o.faces[v] as i32;
            if ascii {
                out.push(b' ');
                crate::encode::push_int(out, face);
            } else {
                out.extend_from_slice(&face.to_le_bytes());
            }
            o.bary[v].into_iter().for_each(|x| float(out, x));
        }
        if ascii {
            out.push(b'\n');
        }
    })?;
    Ok(())
}

/// Face records for `triangles`: a run of the face element.
pub(crate) fn write_faces(
    out: &mut dyn Write,
    triangles: &[[u32; 3]],
    ascii: bool,
) -> std::io::Result<()> {
    if !ascii {
        // A count byte, then three 4-byte indices.
        return crate::encode::write_fixed_records(out, triangles.len(), 13, |f, slot| {
            let (count, indices) = slot.split_at_mut(1);
            count[0] = 3;
            let mut w = crate::encode::Words::new(indices);
            triangles[f].iter().for_each(|i| w.put(i.to_le_bytes()));
        });
    }
    crate::encode::write_records(out, triangles.len(), 40, |f, out| {
        out.push(b'3');
        for i in triangles[f] {
            out.push(b' ');
            crate::encode::push_int(out, i);
        }
        out.push(b'\n');
    })
}
