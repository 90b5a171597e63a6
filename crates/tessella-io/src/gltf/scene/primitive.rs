//! One triangle primitive refined, with every attribute and morph target carried.

use super::accessor::{read_f32, read_u32, width};
use super::carry::Origins;
use super::out::{Out, U16, U8};
use super::{skin, tangents, PrimitiveReport};
use crate::gltf::flip_v;
use gltf::accessor::DataType;
use serde_json::{Map, Value};
use tessella_core::mesh::is_degenerate;
use tessella_core::{Mesh, Pattern, RefineError, RefineOptions, RefinedMesh, Refiner};

/// What refining a primitive can fail on: the file's data, or the refinement itself.
pub(super) enum Failure {
    Data(String),
    Refine(RefineError),
}

impl From<String> for Failure {
    fn from(m: String) -> Failure {
        Failure::Data(m)
    }
}

/// Reads a primitive's accessor by its attribute name.
struct Source<'a> {
    document: &'a gltf::Document,
    buffers: &'a [Vec<u8>],
}

impl Source<'_> {
    fn accessor(&self, index: &Value) -> Result<gltf::Accessor<'_>, String> {
        let i = super::json::whole(index)
            .ok_or_else(|| format!("accessor index {index} is not a whole number"))?;
        self.document
            .accessors()
            .nth(i as usize)
            .ok_or_else(|| format!("accessor {i} does not exist"))
    }

    /// A float attribute with `count` elements (of any width).
    fn floats(&self, index: &Value, count: usize, name: &str) -> Result<(Vec<f32>, usize), String> {
        let accessor = self.accessor(index)?;
        let w = width(accessor.dimensions())
            .ok_or_else(|| format!("{name} is a {:?}", accessor.dimensions()))?;
        if accessor.count() != count {
            return Err(format!(
                "{name} has {} values for {count} positions",
                accessor.count()
            ));
        }
        let values = read_f32(&accessor, self.buffers).map_err(|m| format!("{name}: {m}"))?;
        if let Some(bad) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "{name} has the non-finite value {} at vertex {}",
                values[bad],
                bad / w
            ));
        }
        Ok((values, w))
    }
}

/// The level-`level` refinement of `primitive` (mesh `m`, primitive `p` of the document),
/// written into `out`; returns the new primitive's JSON.
#[allow(clippy::too_many_arguments)]
pub(super) fn refine(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    primitive_json: &Value,
    mode: gltf::mesh::Mode,
    options: &RefineOptions,
    level: u32,
    normal_uv_set: u32,
    tangent_mode: super::Tangents,
    joint_sets: super::JointSets,
    out: &mut Out,
) -> Result<(Value, PrimitiveReport), Failure> {
    let source = Source { document, buffers };
    let attributes = primitive_json
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| "no attributes".to_string())?;
    let position = attributes
        .get("POSITION")
        .ok_or_else(|| "no POSITION attribute".to_string())?;
    let n = source.accessor(position)?.count();
    let (flat_positions, w) = source.floats(position, n, "POSITION")?;
    if w != 3 {
        return Err(Failure::Data("POSITION is not a VEC3".into()));
    }
    let positions: Vec<[f32; 3]> = flat_positions
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let corners: Vec<u32> = match primitive_json.get("indices") {
        Some(index) => {
            let accessor = source.accessor(index)?;
            read_u32(&accessor, buffers).map_err(|m| format!("indices: {m}"))?
        }
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = corners.iter().find(|&&i| i as usize >= n) {
        return Err(Failure::Data(format!(
            "uses vertex {bad} but has only {n} vertices"
        )));
    }
    let triangles = super::super::data::assemble(mode, &corners)?;
    // Zero-area triangles (a repeated corner, collinear corners) are valid glTF: they are
    // refined flat (each stays on its segment), and left out of the surface and its normals.
    let (flat, good): (Vec<[u32; 3]>, Vec<[u32; 3]>) = triangles
        .iter()
        .partition(|t| is_degenerate(&positions, **t));
    let given_normals = match attributes.get("NORMAL") {
        Some(index) => Some(vec3s(&source.floats(index, n, "NORMAL")?.0)),
        None => None,
    };
    let coarse = coarse_mesh(&positions, given_normals.as_deref(), &good)?;
    let options = options.clone().with_uniform_level(level as f64);
    let pattern = Pattern::uniform(level);
    let refiner = match &coarse {
        Some(mesh) => Some(Refiner::new(mesh, &options).map_err(Failure::Refine)?),
        None => None,
    };
    let (refined, origins) = match (&refiner, &coarse) {
        (Some(refiner), Some(mesh)) => {
            let refined = refiner.refine();
            let (faces, bary) = refiner.plan().origin();
            let origins = Origins::new(&faces, &bary, mesh.triangles(), &flat, &pattern.points);
            (refined, origins)
        }
        _ => {
            let none = Origins::new(&[], &[], &[], &flat, &pattern.points);
            (RefinedMesh::default(), none)
        }
    };
    let coarse_normals: Vec<[f32; 3]> = match (&coarse, &given_normals) {
        (Some(mesh), _) => mesh.normals().to_vec(),
        (None, Some(given)) => given.clone(),
        (None, None) => vec![[0.0, 0.0, 1.0]; n],
    };
    // The output: the refined surface, then each degenerate triangle's flat pattern.
    let base = refined.positions.len();
    let RefinedMesh {
        positions: mut out_positions,
        normals: mut out_normals,
        triangles: mut out_triangles,
        ..
    } = refined;
    let flat_part = Origins {
        corners: origins.corners[base..].to_vec(),
        weights: origins.weights[base..].to_vec(),
    };
    out_positions.extend(vec3s(&flat_part.interpolate(&flat_positions, 3)));
    let flat_normals = flat_part.interpolate(coarse_normals.as_flattened(), 3);
    out_normals.extend(
        flat_normals
            .chunks_exact(3)
            .map(|c| unit([c[0], c[1], c[2]])),
    );
    for (k, _) in flat.iter().enumerate() {
        let first = (base + k * pattern.points.len()) as u32;
        out_triangles.extend(pattern.triangles.iter().map(|t| t.map(|i| i + first)));
    }
    let count = out_positions.len();

    let mut new_attributes = Map::new();
    new_attributes.insert(
        "POSITION".into(),
        out.floats(out_positions.as_flattened(), 3, true).into(),
    );
    new_attributes.insert(
        "NORMAL".into(),
        out.floats(out_normals.as_flattened(), 3, false).into(),
    );
    let mut skin_sets: Vec<(usize, Vec<u32>, Vec<f32>)> = Vec::new();
    for (name, index) in attributes {
        if name == "POSITION" || name == "NORMAL" || name == "TANGENT" {
            continue;
        }
        if let Some(set) = name
            .strip_prefix("JOINTS_")
            .and_then(|s| s.parse::<usize>().ok())
        {
            let accessor = source.accessor(index)?;
            if accessor.count() != n {
                return Err(Failure::Data(format!(
                    "{name} has {} values for {n} positions",
                    accessor.count()
                )));
            }
            let joints = read_u32(&accessor, buffers).map_err(|m| format!("{name}: {m}"))?;
            let weights_index = attributes
                .get(&format!("WEIGHTS_{set}"))
                .ok_or_else(|| format!("{name} has no WEIGHTS_{set}"))?;
            let (weights, ww) = source.floats(weights_index, n, &format!("WEIGHTS_{set}"))?;
            if joints.len() != n * 4 || ww != 4 {
                return Err(Failure::Data(format!(
                    "{name} and WEIGHTS_{set} are not VEC4"
                )));
            }
            skin_sets.push((set, joints, weights));
            continue;
        }
        if name.starts_with("WEIGHTS_") {
            continue;
        }
        let index = carry_attribute(&source, out, &origins, index, n, name)?;
        new_attributes.insert(name.clone(), index.into());
    }
    if !skin_sets.is_empty() {
        skin_sets.sort_by_key(|s| s.0);
        let (joints, weights): (Vec<Vec<u32>>, Vec<Vec<f32>>) =
            skin_sets.into_iter().map(|(_, j, w)| (j, w)).unzip();
        let (joints, weights) = skin::blend(&origins, &joints, &weights, joint_sets);
        let wide = joints.iter().flatten().any(|&j| j > 255);
        for (s, (j, w)) in joints.iter().zip(&weights).enumerate() {
            let component = if wide { U16 } else { U8 };
            new_attributes.insert(format!("JOINTS_{s}"), out.ints(j, 4, component).into());
            new_attributes.insert(format!("WEIGHTS_{s}"), out.floats(w, 4, false).into());
        }
    }
    if let Some(index) = attributes.get("TANGENT") {
        let (tangents_in, tw) = source.floats(index, n, "TANGENT")?;
        if tw != 4 {
            return Err(Failure::Data("TANGENT is not a VEC4".into()));
        }
        let uv_name = format!("TEXCOORD_{normal_uv_set}");
        let uvs = match attributes.get(&uv_name) {
            Some(uv) if tangent_mode == super::Tangents::Recomputed => {
                Some(source.floats(uv, n, &uv_name)?.0)
            }
            _ => None,
        };
        let tangents = uvs
            .map(|uvs| {
                // glTF's v points down the image; MikkTSpace wants the OBJ/PLY convention.
                let flipped: Vec<f32> = origins
                    .interpolate(&uvs, 2)
                    .chunks_exact(2)
                    .flat_map(|c| flip_v([c[0], c[1]]))
                    .collect();
                tangents::mikktspace(&out_positions, &out_normals, &flipped, &out_triangles)
            })
            .unwrap_or_else(|| tangents::interpolated(&origins, &tangents_in, &out_normals));
        new_attributes.insert(
            "TANGENT".into(),
            out.floats(tangents.as_flattened(), 4, false).into(),
        );
    }

    let targets = primitive_json.get("targets").and_then(Value::as_array);
    let mut new_targets = Vec::new();
    let mut notes = Vec::new();
    for (t, target) in targets.into_iter().flatten().enumerate() {
        let target = target
            .as_object()
            .ok_or_else(|| format!("morph target {t} is not an object"))?;
        let mut new_target = Map::new();
        let delta = |name: &str| -> Result<Option<Vec<f32>>, String> {
            match target.get(name) {
                Some(index) => Ok(Some(
                    source.floats(index, n, &format!("target {t} {name}"))?.0,
                )),
                None => Ok(None),
            }
        };
        let dp = delta("POSITION")?;
        let dn = delta("NORMAL")?;
        // Refined normals change with the shape when the file gave none (they are computed).
        let normals_move = dn.is_some() || (given_normals.is_none() && dp.is_some());
        if dp.is_some() || dn.is_some() {
            let shape = TargetShape {
                positions: &positions,
                given_normals: given_normals.as_deref(),
                dp: dp.as_deref(),
                dn: dn.as_deref(),
            };
            let (dpos, dnorm) = match (&refiner, shape.mesh(&good)) {
                (Some(refiner), Ok(Some(moved))) => {
                    let base_refined = (&out_positions[..base], &out_normals[..base]);
                    refine_target(refiner, &moved, base_refined, &flat_part, &shape)
                        .map_err(Failure::Refine)?
                }
                (_, result) => {
                    if let Err(why) = result {
                        notes.push(format!("morph target {t} is carried linearly ({why})"));
                    }
                    shape.linear(&origins)
                }
            };
            if dp.is_some() {
                new_target.insert("POSITION".into(), out.floats(&dpos, 3, true).into());
            }
            if normals_move {
                new_target.insert("NORMAL".into(), out.floats(&dnorm, 3, false).into());
            }
        }
        for (name, index) in target {
            if name == "POSITION" || name == "NORMAL" {
                continue;
            }
            let (values, w) = source.floats(index, n, &format!("target {t} {name}"))?;
            let carried = origins.interpolate(&values, w);
            new_target.insert(name.clone(), out.floats(&carried, w, false).into());
        }
        new_targets.push(Value::Object(new_target));
    }

    let mut new_primitive = primitive_json.clone();
    let object = new_primitive
        .as_object_mut()
        .expect("primitive is an object");
    object.insert("attributes".into(), Value::Object(new_attributes));
    object.insert("indices".into(), out.indices(&out_triangles, count).into());
    object.remove("mode");
    if !new_targets.is_empty() {
        object.insert("targets".into(), Value::Array(new_targets));
    }
    if let Some(exts) = object.get_mut("extensions").and_then(Value::as_object_mut) {
        exts.remove("KHR_draco_mesh_compression");
        if exts.is_empty() {
            object.remove("extensions");
        }
    }
    let report = PrimitiveReport {
        level,
        coarse_triangles: triangles.len(),
        degenerate: flat.len(),
        vertices: count,
        triangles: out_triangles.len(),
        notes,
    };
    Ok((new_primitive, report))
}

fn vec3s(flat: &[f32]) -> Vec<[f32; 3]> {
    flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

fn unit(v: [f32; 3]) -> [f32; 3] {
    glam::Vec3::from(v)
        .try_normalize()
        .map_or([0.0, 0.0, 1.0], Into::into)
}

/// The coarse surface of the non-degenerate triangles; `None` when every triangle is
/// degenerate. Normals the file gives that are zero or not finite are replaced by computed ones
/// (angle-weighted), vertex by vertex.
fn coarse_mesh(
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
    good: &[[u32; 3]],
) -> Result<Option<Mesh>, String> {
    if good.is_empty() {
        return Ok(None);
    }
    let usable = |n: &[f32; 3]| n.iter().all(|c| c.is_finite()) && n.iter().any(|&c| c != 0.0);
    let normals = match normals {
        Some(given) if !given.iter().all(usable) => {
            let computed = Mesh::new(positions.to_vec(), None, None, good.to_vec())
                .map_err(|e| e.to_string())?;
            Some(
                given
                    .iter()
                    .zip(computed.normals())
                    .map(|(g, c)| if usable(g) { *g } else { *c })
                    .collect(),
            )
        }
        other => other.map(<[_]>::to_vec),
    };
    Mesh::new(positions.to_vec(), normals, None, good.to_vec())
        .map(Some)
        .map_err(|e| e.to_string())
}

/// A morph target's shape: the base plus its deltas.
struct TargetShape<'a> {
    positions: &'a [[f32; 3]],
    given_normals: Option<&'a [[f32; 3]]>,
    dp: Option<&'a [f32]>,
    dn: Option<&'a [f32]>,
}

impl TargetShape<'_> {
    /// The coarse mesh of the target's shape (normals: the base's plus the delta, or computed
    /// from the moved positions when the file gives none).
    fn mesh(&self, good: &[[u32; 3]]) -> Result<Option<Mesh>, String> {
        let moved: Vec<[f32; 3]> = match self.dp {
            Some(d) => self
                .positions
                .iter()
                .enumerate()
                .map(|(v, p)| [p[0] + d[v * 3], p[1] + d[v * 3 + 1], p[2] + d[v * 3 + 2]])
                .collect(),
            None => self.positions.to_vec(),
        };
        let normals = self.given_normals.map(|given| match self.dn {
            Some(d) => given
                .iter()
                .enumerate()
                .map(|(v, n)| [n[0] + d[v * 3], n[1] + d[v * 3 + 1], n[2] + d[v * 3 + 2]])
                .collect(),
            None => given.to_vec(),
        });
        coarse_mesh(&moved, normals.as_deref(), good)
    }

    /// Deltas carried linearly (the degenerate triangles' rule, and the fallback for a target
    /// whose shape cannot be refined).
    fn linear(&self, origins: &Origins) -> (Vec<f32>, Vec<f32>) {
        let n = self.positions.len() * 3;
        let zeros = vec![0.0; n];
        (
            origins.interpolate(self.dp.unwrap_or(&zeros), 3),
            origins.interpolate(self.dn.unwrap_or(&zeros), 3),
        )
    }
}

/// A target's refined deltas: the refinement of its shape minus the refinement of the base,
/// on the same plan (same topology, same level), then the flat part linearly.
fn refine_target(
    refiner: &Refiner<'_>,
    moved: &Mesh,
    (positions, normals): (&[[f32; 3]], &[[f32; 3]]),
    flat_part: &Origins,
    shape: &TargetShape<'_>,
) -> Result<(Vec<f32>, Vec<f32>), RefineError> {
    let mut dpos = Vec::new();
    let mut dnorm = Vec::new();
    let plan = refiner.plan();
    let frame = plan.frame(moved)?;
    let mut target = RefinedMesh::default();
    plan.refine_into(&frame, &mut target, &|_| {})?;
    for (a, b) in target.positions.iter().zip(positions) {
        dpos.extend([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    }
    for (a, b) in target.normals.iter().zip(normals) {
        dnorm.extend([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    }
    let (fp, fnorm) = shape.linear(flat_part);
    dpos.extend(fp);
    dnorm.extend(fnorm);
    Ok((dpos, dnorm))
}

/// Any other attribute: floats (and normalised integers) interpolated, written as floats;
/// texture coordinates stored as plain integers (`KHR_mesh_quantization`) likewise; other
/// integers (ids) taken from the nearest corner in their own type.
fn carry_attribute(
    source: &Source<'_>,
    out: &mut Out,
    origins: &Origins,
    index: &Value,
    n: usize,
    name: &str,
) -> Result<usize, String> {
    let accessor = source.accessor(index)?;
    let blend = matches!(
        accessor.data_type(),
        DataType::F32 | DataType::I8 | DataType::I16
    ) || accessor.normalized()
        || name.starts_with("TEXCOORD_")
        || name.starts_with("COLOR_");
    if blend {
        let (values, w) = source.floats(index, n, name)?;
        return Ok(out.floats(&origins.interpolate(&values, w), w, false));
    }
    let w = width(accessor.dimensions()).ok_or_else(|| format!("{name} is a matrix"))?;
    if accessor.count() != n {
        return Err(format!(
            "{name} has {} values for {n} positions",
            accessor.count()
        ));
    }
    let values = read_u32(&accessor, source.buffers).map_err(|m| format!("{name}: {m}"))?;
    let nearest = origins.nearest();
    let carried: Vec<u32> = nearest
        .iter()
        .flat_map(|&v| values[v as usize * w..(v as usize + 1) * w].iter().copied())
        .collect();
    let component = match accessor.data_type() {
        DataType::U8 => U8,
        DataType::U16 => U16,
        _ => super::out::U32,
    };
    Ok(out.ints(&carried, w, component))
}
