//! A whole glTF scene, read once, refined primitive by primitive and written back with
//! everything else it held.
//!
//! [`Scene::read`] parses a `.gltf` or `.glb` file once: its JSON is kept whole (every node,
//! material, texture, image, sampler, camera, light, skin, animation, extension and extra),
//! its buffers are loaded and `EXT_meshopt_compression` views decoded, and the `gltf` crate
//! validates every index. [`Scene::refine`] refines every triangle primitive of every mesh on
//! its own (a mesh used by several nodes once), keeping its material, carrying its attributes
//! and morph targets; points and lines are copied. [`RefinedScene::write`] writes the same
//! document with the refined primitives.
//!
//! ```
//! use tessella_core::{RefineOptions, Scheme};
//! use tessella_io::gltf::scene::{Scene, SceneLevels, SceneOptions};
//! let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("tetrahedron.glb");
//! tessella_io::write_mesh(&path, (&tessella_core::samples::tetrahedron()).into(), &Default::default())?;
//! let scene = Scene::read(&path)?;
//! let options = SceneOptions::new(RefineOptions::new(Scheme::Pn, 1), SceneLevels::Uniform(4));
//! let refined = scene.refine(&options)?;
//! assert_eq!(refined.primitives[0].triangles, 4 * 16);
//! refined.write(&dir.path().join("out.glb"), tessella_io::Durability::Synced)?;
//! # Ok::<(), tessella_io::IoError>(())
//! ```
//!
//! Conventions (docs/gltf.md has the whole story): attributes other than POSITION, NORMAL,
//! TANGENT and skin influences are interpolated linearly over each coarse triangle; tangents
//! are recomputed (MikkTSpace); skin influences are blended, the strongest kept; a morph
//! target's refined delta is the refinement of its shape minus the refinement of the base.
//! Degenerate (zero-area) triangles are refined flat and left out of the surface.

mod accessor;
mod carry;
mod data_checks;
pub mod extensions;
mod json;
mod levels;
mod load;
mod meshopt_views;
mod mikktspace;
mod out;
mod primitive;
mod skin;
mod tangents;
mod write;

pub use levels::{PrimitiveSummary, SceneLevels, MAX_SCENE_LEVEL};

/// A primitive by its place in the document: (mesh index, primitive index).
pub type PrimitiveId = (usize, usize);

use super::Buffers;
use crate::IoError;
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use tessella_core::RefineOptions;

/// A glTF document as read: its JSON whole, its buffers, its validated structure.
pub struct Scene {
    json: Value,
    document: gltf::Document,
    buffers: Vec<Vec<u8>>,
    path: PathBuf,
    format: &'static str,
}

/// How to refine a scene: the scheme and its options (their level is replaced per primitive),
/// the levels, where refined tangents come from and how many skin influence sets to write.
#[derive(Debug, Clone)]
pub struct SceneOptions {
    pub refine: RefineOptions,
    pub levels: SceneLevels,
    pub tangents: Tangents,
    pub joint_sets: JointSets,
}

impl SceneOptions {
    /// `refine` and `levels`, tangents recomputed ([`Tangents::Recomputed`]).
    pub fn new(refine: RefineOptions, levels: SceneLevels) -> SceneOptions {
        SceneOptions {
            refine,
            levels,
            tangents: Tangents::Recomputed,
            joint_sets: JointSets::AsInput,
        }
    }

    /// Sets how many `JOINTS_n`/`WEIGHTS_n` sets skinned primitives get.
    pub fn with_joint_sets(mut self, joint_sets: JointSets) -> SceneOptions {
        self.joint_sets = joint_sets;
        self
    }

    /// Sets where refined tangents come from.
    pub fn with_tangents(mut self, tangents: Tangents) -> SceneOptions {
        self.tangents = tangents;
        self
    }
}

/// The `TANGENT` of refined vertices, for primitives that have one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Tangents {
    /// MikkTSpace on the refined mesh, from its normals and the normal map's texture
    /// coordinates (the default): what a baker would compute for the refined mesh. The
    /// costliest part of a round trip.
    #[default]
    Recomputed,
    /// The file's tangents interpolated like texture coordinates and made orthogonal to the
    /// refined normal: the frame a rasteriser gives the coarse mesh's pixels, at a fraction of
    /// the cost.
    Carried,
}

impl Tangents {
    /// `recomputed` or `carried`.
    pub fn parse(name: &str) -> Option<Tangents> {
        match name {
            "recomputed" | "mikktspace" => Some(Tangents::Recomputed),
            "carried" => Some(Tangents::Carried),
            _ => None,
        }
    }
}

/// How many `JOINTS_n`/`WEIGHTS_n` sets (four influences each) a refined skinned primitive
/// gets. A refined vertex blends its coarse triangle's corners, so it can be influenced by up to
/// three times as many joints as one corner; what does not fit is dropped and the rest
/// renormalised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum JointSets {
    /// As many sets as the input primitive has (the default): three.js and Bevy skin with the
    /// first set only, and a weight in a set they do not read is a weight lost.
    #[default]
    AsInput,
    /// More sets where a vertex of the primitive has more influences than the input's sets
    /// hold, up to this many sets (never fewer than the input's).
    UpTo(u32),
}

impl JointSets {
    /// `input`, or the largest number of sets (1 to [`MAX_JOINT_SETS`]).
    pub fn parse(text: &str) -> Option<JointSets> {
        match text {
            "input" => Some(JointSets::AsInput),
            n => match n.parse::<u32>() {
                Ok(n) if (1..=MAX_JOINT_SETS).contains(&n) => Some(JointSets::UpTo(n)),
                _ => None,
            },
        }
    }
}

/// The most influence sets [`JointSets::UpTo`] takes: 32 influences, every one a refined
/// vertex can have when the input has up to two sets (three corners of eight).
pub const MAX_JOINT_SETS: u32 = 8;

/// What refining one primitive made.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PrimitiveReport {
    pub level: u32,
    pub coarse_triangles: usize,
    /// Zero-area triangles among them, refined flat.
    pub degenerate: usize,
    pub vertices: usize,
    pub triangles: usize,
    /// Anything carried by a fallback (a morph target whose shape cannot be refined).
    pub notes: Vec<String>,
}

/// Counts of what a scene holds, for `info` and tests.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SceneCounts {
    pub scenes: usize,
    pub nodes: usize,
    pub meshes: usize,
    pub primitives: usize,
    pub triangle_primitives: usize,
    pub materials: usize,
    pub textures: usize,
    pub images: usize,
    pub samplers: usize,
    pub skins: usize,
    pub animations: usize,
    pub cameras: usize,
    pub morph_targets: usize,
    pub extensions_used: Vec<String>,
}

/// A refined scene, ready to write.
pub struct RefinedScene {
    json: Value,
    bin: Vec<u8>,
    /// One entry per refined primitive, mesh by mesh: (mesh, primitive) and its report.
    pub primitives: Vec<PrimitiveReport>,
    /// (mesh, primitive index) of each entry of `primitives`.
    pub which: Vec<PrimitiveId>,
    source_folder: PathBuf,
}

impl Scene {
    /// Reads a `.gltf` or `.glb` file (external buffers from its folder).
    pub fn read(path: &Path) -> Result<Scene, IoError> {
        let format = crate::Format::from_path(path)?;
        let bytes = std::fs::read(path).map_err(|source| IoError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        load::read(path, &bytes, format.name(), Buffers::Folder)
    }

    /// Reads a file held in memory; `name` names it in messages and gives its format, and a
    /// `.gltf`'s external buffers come from `buffers`.
    pub fn from_bytes(name: &str, bytes: &[u8], buffers: Buffers<'_>) -> Result<Scene, IoError> {
        let path = Path::new(name);
        let format = crate::Format::from_path(path)?;
        load::read(path, bytes, format.name(), buffers)
    }

    /// What the scene holds.
    pub fn counts(&self) -> SceneCounts {
        let d = &self.document;
        let primitives = d.meshes().flat_map(|m| m.primitives());
        SceneCounts {
            scenes: d.scenes().len(),
            nodes: d.nodes().len(),
            meshes: d.meshes().len(),
            primitives: d.meshes().map(|m| m.primitives().len()).sum(),
            triangle_primitives: primitives
                .clone()
                .filter(|p| is_triangles(p.mode()))
                .count(),
            materials: d.materials().len(),
            textures: d.textures().len(),
            images: d.images().len(),
            samplers: d.samplers().len(),
            skins: d.skins().len(),
            animations: d.animations().len(),
            cameras: d.cameras().len(),
            morph_targets: primitives.map(|p| p.morph_targets().len()).sum(),
            extensions_used: load::string_list(&self.json, "extensionsUsed"),
        }
    }

    /// The level each triangle primitive gets under `levels`, in (mesh, primitive) order.
    pub fn levels(&self, levels: &SceneLevels) -> Result<Vec<(PrimitiveId, u32)>, IoError> {
        Ok(self
            .primitives(levels)?
            .iter()
            .map(|s| (s.id, s.level))
            .collect())
    }

    /// Every triangle primitive: its triangles, degenerate triangles, mean edge and level.
    pub fn primitives(&self, levels: &SceneLevels) -> Result<Vec<PrimitiveSummary>, IoError> {
        levels::summaries(self, levels).map_err(|m| self.parse(m))
    }

    /// Refines every triangle primitive; see the module's documentation. The whole output's
    /// size is checked against `options.refine.max_output_bytes` before any work.
    pub fn refine(&self, options: &SceneOptions) -> Result<RefinedScene, IoError> {
        let summaries = self.primitives(&options.levels)?;
        let bytes = check_size(&summaries, options.refine.max_output_bytes).map_err(|source| {
            IoError::Refine {
                path: self.path.clone(),
                part: "the scene".into(),
                source: Box::new(source),
            }
        })?;
        let chosen: Vec<(PrimitiveId, u32)> = summaries.iter().map(|s| (s.id, s.level)).collect();
        let refined: BTreeSet<PrimitiveId> = chosen.iter().map(|(k, _)| *k).collect();
        let mut out = out::Out::new(self.json.clone(), &self.buffers, &refined, bytes as usize)
            .map_err(|m| self.parse(m))?;
        let mut reports = Vec::new();
        let mut which = Vec::new();
        for &((m, p), level) in &chosen {
            let mesh = self
                .document
                .meshes()
                .nth(m)
                .expect("chosen from the meshes");
            let primitive = mesh
                .primitives()
                .nth(p)
                .expect("chosen from the primitives");
            let normal_uv_set = primitive
                .material()
                .normal_texture()
                .map_or(0, |t| t.tex_coord());
            let primitive_json = self.json["meshes"][m]["primitives"][p].clone();
            let (new, report) = primitive::refine(
                &self.document,
                &self.buffers,
                &primitive_json,
                primitive.mode(),
                &options.refine,
                level,
                normal_uv_set,
                options.tangents,
                options.joint_sets,
                &mut out,
            )
            .map_err(|failure| {
                let part = format!("mesh {m} primitive {p}");
                match failure {
                    primitive::Failure::Data(message) => self.parse(format!("{part}: {message}")),
                    primitive::Failure::Refine(source) => IoError::Refine {
                        path: self.path.clone(),
                        part,
                        source: Box::new(source),
                    },
                }
            })?;
            out.json["meshes"][m]["primitives"][p] = new;
            reports.push(report);
            which.push((m, p));
        }
        let (json, bin) = out.finish(None);
        Ok(RefinedScene {
            json,
            bin,
            primitives: reports,
            which,
            source_folder: self.path.parent().unwrap_or(Path::new("")).to_path_buf(),
        })
    }

    fn parse(&self, message: String) -> IoError {
        IoError::Parse {
            path: self.path.clone(),
            format: self.format,
            message,
        }
    }
}

/// A GLB container of `json` and its one buffer `bin` (no BIN chunk when `bin` is empty).
pub fn glb(json: &Value, bin: &[u8]) -> std::io::Result<Vec<u8>> {
    write::glb_bytes(json, bin)
}

/// Bytes a refined vertex may take in the output: position, normal, tangent, two texture
/// coordinates, a colour, two skin sets and their weights (an estimate from above for the
/// usual attributes).
const BYTES_PER_VERTEX: u64 = 12 + 12 + 16 + 8 + 8 + 16 + 2 * (8 + 16);
/// Bytes a refined triangle takes (32-bit indices).
const BYTES_PER_TRIANGLE: u64 = 12;

/// Refuses a refinement whose output would exceed `limit` bytes, before anything is allocated
/// (the core's size error, for the scene as a whole).
fn check_size(
    summaries: &[PrimitiveSummary],
    limit: u64,
) -> Result<u64, tessella_core::RefineError> {
    let (mut bytes, mut faces, mut vertices, mut triangles, mut level) =
        (0u64, 0usize, 0u64, 0u64, 0u32);
    for s in summaries {
        let l = s.level as u64;
        let f = s.triangles as u64;
        let v = f.saturating_mul((l + 1).saturating_mul(l + 2) / 2);
        let t = f.saturating_mul(l.saturating_mul(l));
        bytes = bytes
            .saturating_add(t.saturating_mul(BYTES_PER_TRIANGLE))
            .saturating_add(v.saturating_mul(BYTES_PER_VERTEX));
        faces += s.triangles;
        vertices = vertices.saturating_add(v);
        triangles = triangles.saturating_add(t);
        level = level.max(s.level);
    }
    if bytes <= limit {
        return Ok(bytes);
    }
    let human = |b: u64| format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64);
    Err(tessella_core::RefineError::TooLarge {
        level,
        faces,
        vertices,
        triangles,
        bytes,
        bytes_human: human(bytes),
        limit,
        limit_human: human(limit),
    })
}

/// The reading every glTF reader of this crate shares: the validated document and its buffers
/// (meshopt views decoded).
pub(super) fn read_for_readers(
    path: &Path,
    bytes: &[u8],
    format: &'static str,
    buffers: Buffers<'_>,
) -> Result<(gltf::Document, Vec<Vec<u8>>), IoError> {
    let scene = load::read(path, bytes, format, buffers)?;
    Ok((scene.document, scene.buffers))
}

/// An accessor's elements as floats, whatever its component type (normalised integers mapped
/// to their range); sparse accessors included.
pub(super) fn read_floats(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
) -> Result<Vec<f32>, String> {
    accessor::read_f32(accessor, buffers)
}

pub(super) fn is_triangles(mode: gltf::mesh::Mode) -> bool {
    use gltf::mesh::Mode;
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

impl RefinedScene {
    /// The document's JSON (the one buffer has no `uri`: a GLB's).
    pub fn json(&self) -> &Value {
        &self.json
    }

    /// The whole scene as GLB bytes.
    pub fn to_glb(&self) -> Result<Vec<u8>, IoError> {
        write::glb_bytes(&self.json, &self.bin).map_err(|source| IoError::Write {
            path: PathBuf::from("<memory>"),
            source,
        })
    }

    /// Writes `path` (`.glb`: one file; `.gltf`: the JSON and `NAME.bin` beside it), and copies
    /// the images the document names by relative URI next to it when it lies in another
    /// folder. Returns warnings (an image that is missing is not copied; the geometry is
    /// written all the same).
    pub fn write(
        &self,
        path: &Path,
        durability: crate::Durability,
    ) -> Result<Vec<String>, IoError> {
        write::write(self, path, durability)
    }
}
