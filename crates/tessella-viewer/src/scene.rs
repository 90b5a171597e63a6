//! The viewer's coarse side, without a GPU: reading a file (with its clips), the tags and
//! their edits, a moved vertex, and which pose each frame shows ([`Motion`]), held together
//! with the panels by `Scene` (crate-private). The WebGPU [`crate::Viewer`] and the GPU-less
//! [`crate::CoarseViewer`] (the WebGL2 fallback's source of control nets) each hold a
//! `Scene` of their own panel type, so they load, pose and tag alike.

use crate::deform;
use crate::error::ViewerError;
use crate::params::Params;
use crate::playback::{Playback, ANIMATED_SAMPLE};
use serde_json::{Map, Value};
use tessella_core::displace::Displacement;
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme, Tags};
use tessella_io::tags::{JsonSource, TagFile, TagFileEdge, TagFileVertex, TagSources};
use tessella_io::RawMesh;

/// The samples `load_sample` takes: the core's static ones and the animated creature.
pub fn sample_names() -> Vec<String> {
    samples::NAMES
        .iter()
        .map(|s| s.to_string())
        .chain([ANIMATED_SAMPLE.to_string()])
        .collect()
}

/// A glTF file's animation clips, when it has any (other formats hold none).
fn animation_of(name: &str, bytes: &[u8]) -> Result<Option<Playback>, ViewerError> {
    let lower = name.to_ascii_lowercase();
    if !(lower.ends_with(".glb") || lower.ends_with(".gltf")) {
        return Ok(None);
    }
    let model = tessella_io::read_animated_bytes(name, bytes, &[])?;
    Playback::new(name, model)
}

/// A mesh file's coarse mesh (an animated file's rest pose, in the scene's space), its raw
/// form (PLY tag properties) and its clips.
pub fn read_file(
    name: &str,
    bytes: &[u8],
) -> Result<(Mesh, RawMesh, Option<Playback>), ViewerError> {
    let mut raw = tessella_io::read_raw_bytes(name, bytes, &[])?;
    let playback = animation_of(name, bytes)?;
    let mesh = match &playback {
        Some(playback) if playback.vertex_count() == raw.positions.len() => {
            let rest = playback.rest()?;
            raw.positions = rest.positions().to_vec();
            raw.normals = Some(rest.normals().to_vec());
            rest
        }
        _ => Mesh::new(
            raw.positions.clone(),
            raw.normals.clone(),
            raw.uvs.clone(),
            raw.triangles.clone(),
        )
        .map_err(|e| ViewerError::Refused(format!("cannot use {name}: {e}")))?,
    };
    let playback = playback.filter(|p| p.vertex_count() == mesh.vertex_count());
    Ok((mesh, raw, playback))
}

/// A bundled sample ([`sample_names`]) and its clips.
pub fn read_sample(name: &str) -> Result<(Mesh, Option<Playback>), ViewerError> {
    if name == ANIMATED_SAMPLE {
        let playback = Playback::sample()?;
        return Ok((playback.rest()?, Some(playback)));
    }
    let mesh = samples::by_name(name).ok_or_else(|| {
        ViewerError::Refused(format!(
            "no sample {name:?}; use one of {:?}",
            sample_names()
        ))
    })?;
    Ok((mesh, None))
}

/// The tags `scheme` gets on `mesh` from the file's PLY properties and `tags`, layered as the
/// CLI layers them (split normals first, for the scalar-tagged scheme).
pub fn gather_tags(
    mesh: &Mesh,
    raw: Option<&RawMesh>,
    tags: &TagFile,
    scheme: tessella_core::Scheme,
) -> Result<Option<tessella_core::Tags>, ViewerError> {
    let text = tags.to_json();
    let empty = tags.edges.is_empty() && tags.vertices.is_empty();
    let sources = TagSources {
        crease_angle: None,
        file: raw,
        json: (!empty).then_some(JsonSource::Text {
            text: &text,
            origin: "in the viewer's tags",
        }),
    };
    tessella_io::tags::gather(mesh, scheme, &sources).map_err(|e| ViewerError::Tags(e.to_string()))
}

/// The `tags` parameter's JSON text as tags (`""`: none).
pub fn tag_file(text: &str) -> Result<TagFile, ViewerError> {
    if text.trim().is_empty() {
        return Ok(TagFile::default());
    }
    TagFile::parse(text).map_err(|e| ViewerError::Param {
        name: "tags",
        message: e.to_string(),
    })
}

/// The `tags` parameter's text for `tags` (`""` for none).
pub fn tags_text(tags: &TagFile) -> String {
    if *tags == TagFile::default() {
        String::new()
    } else {
        tags.to_json()
    }
}

/// `tags` with the edge `a`–`b` at `sharpness` (0 removes the tag), checked against `rest`
/// (whatever the schemes drawn, so a saved file is one the CLI reads).
pub fn with_edge_sharpness(
    tags: &TagFile,
    rest: &Mesh,
    a: u32,
    b: u32,
    sharpness: f32,
) -> Result<TagFile, ViewerError> {
    if !(0.0..=1.0).contains(&sharpness) {
        return Err(ViewerError::Tags(format!(
            "edge sharpness must be within 0..=1, got {sharpness}"
        )));
    }
    let mut tags = tags.clone();
    let same = |e: &TagFileEdge| e.vertices == [a, b] || e.vertices == [b, a];
    match tags.edges.iter_mut().find(|e| same(e)) {
        Some(e) => e.sharpness = sharpness,
        None => tags.edges.push(TagFileEdge {
            vertices: [a, b],
            sharpness,
            kappa: 0.0,
        }),
    }
    tags.edges.retain(|e| e.sharpness != 0.0 || e.kappa != 0.0);
    check_tags(&tags, rest)?;
    Ok(tags)
}

/// `tags` with vertex `v`'s tension and bias (keeping its sharpness and crease), checked.
pub fn with_vertex_tension(
    tags: &TagFile,
    rest: &Mesh,
    v: u32,
    tension: f32,
    bias: f32,
) -> Result<TagFile, ViewerError> {
    let mut tags = tags.clone();
    match tags.vertices.iter_mut().find(|t| t.index == v) {
        Some(t) => {
            t.tag.tension = tension;
            t.tag.bias = bias;
        }
        None => tags.vertices.push(TagFileVertex {
            index: v,
            tag: tessella_core::tags::VertexTag {
                tension,
                bias,
                ..Default::default()
            },
        }),
    }
    tags.vertices
        .retain(|t| t.tag != tessella_core::tags::VertexTag::default());
    check_tags(&tags, rest)?;
    Ok(tags)
}

fn check_tags(tags: &TagFile, rest: &Mesh) -> Result<(), ViewerError> {
    tags.tags(rest)
        .map(|_| ())
        .map_err(|e| ViewerError::Tags(e.to_string()))
}

/// `rest` with vertex `index` (and every vertex at its position, so hard edges stay closed)
/// at `position`; refused for an unknown vertex, a non-finite position or a degenerate
/// triangle. Computed normals follow the move; a file's own normals stay as it gave them.
pub fn moved(rest: &Mesh, index: u32, position: [f32; 3]) -> Result<Mesh, ViewerError> {
    let mut positions = rest.positions().to_vec();
    let old = *positions.get(index as usize).ok_or_else(|| {
        ViewerError::Refused(format!(
            "no vertex {index}: the mesh has {}",
            positions.len()
        ))
    })?;
    for p in positions.iter_mut().filter(|p| **p == old) {
        *p = position;
    }
    let mut out = rest.clone();
    let normals = (!out.normals_computed()).then(|| out.normals().to_vec());
    out.update(&positions, normals.as_deref())?;
    Ok(out)
}

/// Something a frame's coarse pose is handed to: a WebGPU panel, a fallback's surface.
pub trait Deform {
    /// Moves the coarse mesh to `positions` (and `normals`, or computed ones); returns the
    /// bytes this costs the GPU.
    fn deform(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<u64, ViewerError>;
}

/// Moves every one of `targets` to `positions`/`normals`; on an error the ones already moved
/// go back to `rest`.
pub fn deform_all<T: Deform>(
    targets: &mut [T],
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
    rest: &Mesh,
) -> Result<u64, ViewerError> {
    let mut bytes = 0;
    for i in 0..targets.len() {
        match targets[i].deform(positions, normals) {
            Ok(b) => bytes += b,
            Err(e) => {
                for t in &mut targets[..i] {
                    t.deform(rest.positions(), Some(rest.normals()))?;
                }
                return Err(e);
            }
        }
    }
    Ok(bytes)
}

/// The loaded file's clips and which pose the surfaces hold: the clip playing (its time in
/// `params.time`), the `animate` deformation, or the rest pose.
#[derive(Debug, Default)]
pub struct Motion {
    /// The loaded file's animation clips, when it has any.
    pub playback: Option<Playback>,
    /// The clip `params.clip` names, resolved.
    pub clip: Option<usize>,
    /// The clip and time (bits) the surfaces show; a paused clip is not posed again.
    posed: Option<(usize, u32)>,
    /// The surfaces are not the rest pose (an animation ran).
    deformed: bool,
}

/// What [`Motion::step`] did.
#[derive(Debug, Default)]
pub struct Stepped {
    /// Bytes the surfaces' updates cost.
    pub uploaded: u64,
    /// When a new clip pose was tried: `Some(None)` when the surfaces took it, `Some(why)`
    /// when they refused it (the previous pose stays drawn).
    pub pose_error: Option<Option<String>>,
}

impl Motion {
    pub fn new(playback: Option<Playback>, clip: Option<usize>) -> Motion {
        Motion {
            playback,
            clip,
            posed: None,
            deformed: false,
        }
    }

    /// The surfaces were rebuilt on the rest pose (new parameters, tags, a moved vertex).
    pub fn at_rest(&mut self) {
        self.deformed = false;
        self.posed = None;
    }

    /// The surfaces were moved to a new rest pose (a dragged vertex); a paused clip's pose is
    /// not taken again.
    pub fn rest_moved(&mut self) {
        self.deformed = false;
    }

    /// The clips' names (`[]`: none).
    pub fn clip_names(&self) -> Vec<String> {
        self.playback
            .as_ref()
            .map_or_else(Vec::new, Playback::clip_names)
    }

    /// The playing clip's duration, seconds (0 without one).
    pub fn duration(&self) -> f32 {
        match (&self.playback, self.clip) {
            (Some(playback), Some(clip)) => playback.duration(clip),
            _ => 0.0,
        }
    }

    /// The clip `params.clip` names, checked against the file's clips.
    pub fn resolve(&self, params: &Params) -> Result<Option<usize>, ViewerError> {
        match (&params.clip, &self.playback) {
            (None, _) => Ok(None),
            (Some(name), Some(playback)) => Ok(Some(playback.resolve(name)?)),
            (Some(_), None) => Err(ViewerError::Param {
                name: "clip",
                message: "this mesh has no animation clips".into(),
            }),
        }
    }

    /// After `set` took `changes` and `clip`: a new clip, time or play state restarts the
    /// clip's clock from `time`.
    pub fn after_set(
        &mut self,
        changes: &serde_json::Map<String, serde_json::Value>,
        clip: Option<usize>,
    ) {
        if ["clip", "time", "playing"]
            .iter()
            .any(|k| changes.contains_key(*k))
        {
            if let Some(playback) = &mut self.playback {
                playback.restart();
            }
        }
        self.clip = clip;
    }

    /// Moves `targets` to this frame's pose at page time `time_ms`: the clip's (written to
    /// `params.time`; posed again only when its time changed), else the `animate`
    /// deformation of `rest`, else `rest` once after a deformation.
    pub fn step<T: Deform>(
        &mut self,
        rest: &Mesh,
        params: &mut Params,
        time_ms: f64,
        targets: &mut [T],
    ) -> Result<Stepped, ViewerError> {
        let mut out = Stepped::default();
        if let (Some(playback), Some(clip)) = (&mut self.playback, self.clip) {
            let time = playback.time_at(clip, params.time, params.playing, time_ms);
            params.time = time;
            if self.posed != Some((clip, time.to_bits())) {
                // A pose the surfaces refuse (a triangle collapsed to no area) keeps the last
                // good frame on screen; the stats say why.
                let mut error = None;
                let (positions, normals) = playback.pose(clip, time)?;
                for target in targets.iter_mut() {
                    match target.deform(positions, normals) {
                        Ok(bytes) => out.uploaded += bytes,
                        Err(ViewerError::Refine(e)) => {
                            error = Some(format!("clip at {time} s: {e}"));
                            break;
                        }
                        Err(e) => return Err(e),
                    }
                }
                out.pose_error = Some(error);
                self.posed = Some((clip, time.to_bits()));
                self.deformed = true;
            }
            return Ok(out);
        }
        self.posed = None;
        match deform::at(rest, params.animate, time_ms) {
            Some((positions, normals)) => {
                for target in targets.iter_mut() {
                    out.uploaded += target.deform(&positions, Some(&normals))?;
                }
                self.deformed = true;
            }
            None if self.deformed => {
                for target in targets.iter_mut() {
                    out.uploaded += target.deform(rest.positions(), Some(rest.normals()))?;
                }
                self.deformed = false;
            }
            None => {}
        }
        Ok(out)
    }
}

/// The largest CPU export: 32-bit wasm memory holds 4 GiB in all.
const MAX_EXPORT_BYTES: u64 = 1 << 30;

/// `mesh` refined on the CPU by tessella-core with `options` (and `displacement`), written
/// as GLB by tessella-io.
pub fn export_glb(
    mesh: &Mesh,
    options: &RefineOptions,
    displacement: &Displacement,
) -> Result<Vec<u8>, ViewerError> {
    let options = options.clone().with_max_output_bytes(MAX_EXPORT_BYTES);
    let refiner = Refiner::new(mesh, &options)?;
    let mut refined = refiner.refine();
    if displacement.is_some() {
        let frame =
            tessella_core::DisplaceFrame::new(refiner.mesh(), refiner.topology(), refiner.layout());
        displacement.apply(&mut refined, &frame)?;
    }
    Ok(tessella_io::write_mesh_bytes(
        tessella_io::Format::Glb,
        (&refined).into(),
    )?)
}

/// What one panel draws: `scheme` on `mesh` with `params`, and the tags [`gather_tags`] gave
/// that scheme.
#[derive(Clone, Copy)]
pub(crate) struct PanelSpec<'a> {
    pub mesh: &'a Mesh,
    pub params: &'a Params,
    pub scheme: Scheme,
    pub tags: Option<&'a Tags>,
}

/// Makes one viewer's panels (of type `P`), one per scheme drawn.
pub(crate) trait BuildPanels<P> {
    /// The panel `spec` describes.
    fn panel(&self, spec: PanelSpec<'_>) -> Result<P, ViewerError>;

    /// Every panel of `params` on `mesh` (`raw`: the file's PLY tag properties).
    fn panels(
        &self,
        mesh: &Mesh,
        raw: Option<&RawMesh>,
        params: &Params,
        tags: &TagFile,
    ) -> Result<Vec<P>, ViewerError> {
        params
            .schemes()
            .into_iter()
            .map(|scheme| {
                let tags = gather_tags(mesh, raw, tags, scheme)?;
                self.panel(PanelSpec {
                    mesh,
                    params,
                    scheme,
                    tags: tags.as_ref(),
                })
            })
            .collect()
    }
}

/// A viewer's coarse state and its panels of type `P` (a WebGPU panel, a fallback's
/// surface): what [`crate::Viewer`] and [`crate::CoarseViewer`] share. The calls that make
/// panels take the viewer's [`BuildPanels`]; each either succeeds or changes nothing.
pub(crate) struct Scene<P> {
    /// The mesh as loaded: what the camera frames (so deforming it does not move the camera).
    pub model: Mesh,
    /// The loaded file's raw form (PLY tag properties); `None` for a sample.
    pub raw: Option<RawMesh>,
    /// The model with dragged vertices moved: the rest pose that animations deform.
    pub rest: Mesh,
    pub params: Params,
    /// The tags in effect: `params.tags` and the edits since.
    pub tags: TagFile,
    pub panels: Vec<P>,
    /// The file's clips and the pose the panels hold.
    pub motion: Motion,
    /// Why the last clip pose was refused (the previous one stays), if it was.
    pub pose_error: Option<String>,
}

impl<P: Deform> Scene<P> {
    /// [`crate::FIRST_SAMPLE`] with the default parameters.
    pub fn new(build: &impl BuildPanels<P>) -> Result<Scene<P>, ViewerError> {
        let mesh = samples::by_name(crate::FIRST_SAMPLE)
            .ok_or_else(|| ViewerError::Refused(format!("no sample {:?}", crate::FIRST_SAMPLE)))?;
        let params = Params::default();
        let tags = TagFile::default();
        let panels = build.panels(&mesh, None, &params, &tags)?;
        Ok(Scene {
            rest: mesh.clone(),
            model: mesh,
            raw: None,
            params,
            tags,
            panels,
            motion: Motion::default(),
            pose_error: None,
        })
    }

    /// Replaces the mesh with one read from a file's bytes (`name`'s extension picks the
    /// format). Tags are cleared (they named the old mesh's vertices).
    pub fn load(
        &mut self,
        name: &str,
        bytes: &[u8],
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        let (mesh, raw, playback) = read_file(name, bytes)?;
        self.replace_mesh(mesh, Some(raw), playback, build)
    }

    /// Replaces the mesh with a bundled sample ([`sample_names`]).
    pub fn load_sample(
        &mut self,
        name: &str,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        let (mesh, playback) = read_sample(name)?;
        self.replace_mesh(mesh, None, playback, build)
    }

    fn replace_mesh(
        &mut self,
        mesh: Mesh,
        raw: Option<RawMesh>,
        playback: Option<Playback>,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        // The clip stays when the new file has one of that name (a reload), else none.
        let clip = match (&playback, &self.params.clip) {
            (Some(p), Some(name)) => p.resolve(name).ok(),
            _ => None,
        };
        let params = Params {
            tags: String::new(),
            clip: clip.and(self.params.clip.clone()),
            ..self.params.clone()
        };
        let tags = TagFile::default();
        self.panels = build.panels(&mesh, raw.as_ref(), &params, &tags)?;
        self.rest = mesh.clone();
        self.model = mesh;
        self.raw = raw;
        self.params = params;
        self.tags = tags;
        self.motion = Motion::new(playback, clip);
        self.pose_error = None;
        Ok(())
    }

    /// Applies `changes` (any subset of the parameters, see [`crate::params::KEYS`]); all are
    /// validated and the panels rebuilt before anything changes.
    pub fn set(
        &mut self,
        changes: &Map<String, Value>,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        let next = self.params.apply(changes)?;
        let clip = self.motion.resolve(&next)?;
        let tags = if changes.contains_key("tags") {
            tag_file(&next.tags)?
        } else {
            self.tags.clone()
        };
        if self.params.needs_rebuild(&next) || tags != self.tags {
            self.rebuild(next, tags, build)?;
        } else {
            self.params = next;
        }
        self.motion.after_set(changes, clip);
        Ok(())
    }

    /// Builds the panels for `params` and `tags` on the current rest pose, then takes them.
    fn rebuild(
        &mut self,
        params: Params,
        tags: TagFile,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        self.panels = build.panels(&self.rest, self.raw.as_ref(), &params, &tags)?;
        self.params = Params {
            tags: tags_text(&tags),
            ..params
        };
        self.tags = tags;
        self.motion.at_rest();
        Ok(())
    }

    /// Moves the panels to the pose at page time `time_ms` ([`Motion::step`]), keeping why a
    /// clip pose was refused.
    pub fn step(&mut self, time_ms: f64) -> Result<Stepped, ViewerError> {
        let stepped = self
            .motion
            .step(&self.rest, &mut self.params, time_ms, &mut self.panels)?;
        if let Some(error) = &stepped.pose_error {
            self.pose_error.clone_from(error);
        }
        Ok(stepped)
    }

    /// Moves coarse vertex `index` (and every vertex at its position) to `position` in the
    /// rest pose ([`moved`]); the panels follow. Returns the bytes this cost the GPU.
    pub fn move_vertex(&mut self, index: u32, position: [f32; 3]) -> Result<u64, ViewerError> {
        let rest = moved(&self.rest, index, position)?;
        let uploaded = deform_all(
            &mut self.panels,
            rest.positions(),
            Some(rest.normals()),
            &self.rest,
        )?;
        self.rest = rest;
        self.motion.rest_moved();
        Ok(uploaded)
    }

    /// Sets the sharpness of the coarse edge `a`–`b` ([`with_edge_sharpness`]) and rebuilds.
    pub fn set_edge_sharpness(
        &mut self,
        a: u32,
        b: u32,
        sharpness: f32,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        let tags = with_edge_sharpness(&self.tags, &self.rest, a, b, sharpness)?;
        self.rebuild(self.params.clone(), tags, build)
    }

    /// Sets vertex `v`'s tension and bias ([`with_vertex_tension`]) and rebuilds.
    pub fn set_vertex_tension(
        &mut self,
        v: u32,
        tension: f32,
        bias: f32,
        build: &impl BuildPanels<P>,
    ) -> Result<(), ViewerError> {
        let tags = with_vertex_tension(&self.tags, &self.rest, v, tension, bias)?;
        self.rebuild(self.params.clone(), tags, build)
    }

    /// The first panel (the one exported), refused when there is none.
    pub fn first_panel(&self) -> Result<&P, ViewerError> {
        self.panels
            .first()
            .ok_or_else(|| ViewerError::Refused("nothing to export".into()))
    }
}
