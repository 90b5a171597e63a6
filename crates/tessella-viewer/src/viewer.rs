//! [`Viewer`]: the loaded coarse mesh, the parameters, one [`Panel`] per scheme, and a frame
//! drawn into the caller's texture view. Every call either succeeds or leaves the viewer as it
//! was; nothing waits for the GPU.

use crate::deform;
use crate::error::ViewerError;
use crate::panel::Panel;
use crate::params::Params;
use crate::pick::{self, Picked};
use crate::playback::{Playback, ANIMATED_SAMPLE};
use crate::stats::Stats;
use glam::Mat4;
use serde_json::{Map, Value};
use tessella_core::refine::{Levels, Lod};
use tessella_core::{samples, Mesh, Refiner};
use tessella_gpu::{GpuContext, TargetFormats};
use tessella_io::tags::{JsonSource, TagFile, TagFileEdge, TagFileVertex, TagSources};
use tessella_io::RawMesh;
use tessella_view::{lod_camera, panel_widths, scene_uniforms, RenderOptions, RenderUniforms};

/// Multisampling, as `tessella render`'s pictures (the silhouettes are the point).
pub const SAMPLES: u32 = 4;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The largest CPU export: 32-bit wasm memory holds 4 GiB in all.
const MAX_EXPORT_BYTES: u64 = 1 << 30;
/// The sample shown before anything is loaded.
pub const FIRST_SAMPLE: &str = "icosphere";

/// The mesh as loaded: what the camera frames (so deforming it does not move the camera) and,
/// for PLY files, the tag properties it carries.
struct Model {
    mesh: Mesh,
    raw: Option<RawMesh>,
}

/// The multisampled colour and depth attachments of one size.
struct Targets {
    color: wgpu::TextureView,
    depth: wgpu::TextureView,
    size: (u32, u32),
}

/// The interactive viewer's engine (see the crate docs).
pub struct Viewer {
    ctx: GpuContext,
    formats: TargetFormats,
    size: (u32, u32),
    targets: Option<Targets>,
    model: Model,
    /// The model with the vertices moved by [`Viewer::move_vertex`]: the rest pose that
    /// animations deform.
    rest: Mesh,
    params: Params,
    /// The tags in effect: `params.tags` and the edits since.
    tags: TagFile,
    panels: Vec<Panel>,
    /// The panels' meshes are not the rest pose (an animation ran, a vertex moved).
    deformed: bool,
    /// Bytes uploaded outside a frame (a moved vertex), counted with the next frame.
    pending_upload: u64,
    /// The loaded file's animation clips, when it has any.
    playback: Option<Playback>,
    /// The clip `params.clip` names, resolved.
    clip: Option<usize>,
    /// The clip and time (bits) the panels show; a paused clip is not posed again.
    posed: Option<(usize, u32)>,
    stats: Stats,
}

impl std::fmt::Debug for Viewer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Viewer")
            .field("adapter", &self.ctx.adapter_label())
            .field("panels", &self.panels)
            .finish()
    }
}

/// The tags `scheme` gets on `mesh` from the file's PLY properties and `tags`, layered as the
/// CLI layers them (split normals first, for the scalar-tagged scheme).
fn gather_tags(
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

/// Builds every panel of `params` on `mesh`.
fn build_panels(
    ctx: &GpuContext,
    formats: &TargetFormats,
    mesh: &Mesh,
    raw: Option<&RawMesh>,
    params: &Params,
    tags: &TagFile,
) -> Result<Vec<Panel>, ViewerError> {
    params
        .schemes()
        .into_iter()
        .map(|scheme| {
            let tags = gather_tags(mesh, raw, tags, scheme)?;
            Panel::new(ctx, mesh, params, scheme, tags.as_ref(), formats)
        })
        .collect()
}

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

fn tag_file(text: &str) -> Result<TagFile, ViewerError> {
    if text.trim().is_empty() {
        return Ok(TagFile::default());
    }
    TagFile::parse(text).map_err(|e| ViewerError::Param {
        name: "tags",
        message: e.to_string(),
    })
}

impl Viewer {
    /// A viewer on `ctx` drawing into views of `color_format` (a canvas's or a window's
    /// surface format, or an offscreen texture's), showing [`FIRST_SAMPLE`] with the default
    /// parameters.
    pub fn new(ctx: GpuContext, color_format: wgpu::TextureFormat) -> Result<Viewer, ViewerError> {
        let formats = TargetFormats {
            color: color_format,
            depth: Some(DEPTH_FORMAT),
            samples: SAMPLES,
        };
        let mesh = samples::by_name(FIRST_SAMPLE)
            .ok_or_else(|| ViewerError::Refused(format!("no sample {FIRST_SAMPLE:?}")))?;
        let params = Params::default();
        let tags = TagFile::default();
        let panels = build_panels(&ctx, &formats, &mesh, None, &params, &tags)?;
        let stats = Stats::new(&ctx, mesh.face_count());
        Ok(Viewer {
            ctx,
            formats,
            size: RenderOptions::default().size,
            targets: None,
            rest: mesh.clone(),
            model: Model { mesh, raw: None },
            params,
            tags,
            panels,
            deformed: false,
            pending_upload: 0,
            playback: None,
            clip: None,
            posed: None,
            stats,
        })
    }

    /// The device the viewer draws with.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Replaces the mesh with one read from a file's bytes (`name`'s extension picks the
    /// format). On error the previous mesh stays. Tags are cleared (they named the old mesh's
    /// vertices).
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<(), ViewerError> {
        let mut raw = tessella_io::read_raw_bytes(name, bytes, &[])?;
        let playback = animation_of(name, bytes)?;
        let mesh = match &playback {
            // An animated file's mesh is its rest pose, in the scene's space.
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
        self.replace_mesh(mesh, Some(raw), playback)
    }

    /// Replaces the mesh with a bundled sample ([`samples::NAMES`]).
    pub fn load_sample(&mut self, name: &str) -> Result<(), ViewerError> {
        if name == ANIMATED_SAMPLE {
            let playback = Playback::sample()?;
            return self.replace_mesh(playback.rest()?, None, Some(playback));
        }
        let mesh = samples::by_name(name).ok_or_else(|| {
            ViewerError::Refused(format!(
                "no sample {name:?}; use one of {:?}",
                sample_names()
            ))
        })?;
        self.replace_mesh(mesh, None, None)
    }

    fn replace_mesh(
        &mut self,
        mesh: Mesh,
        raw: Option<RawMesh>,
        playback: Option<Playback>,
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
        let panels = build_panels(
            &self.ctx,
            &self.formats,
            &mesh,
            raw.as_ref(),
            &params,
            &tags,
        )?;
        self.stats = Stats::new(&self.ctx, mesh.face_count());
        self.rest = mesh.clone();
        self.model = Model { mesh, raw };
        self.params = params;
        self.tags = tags;
        self.panels = panels;
        self.deformed = false;
        self.playback = playback;
        self.clip = clip;
        self.posed = None;
        self.clip_stats();
        Ok(())
    }

    /// Applies `changes` (any subset of the parameters, see [`crate::params::KEYS`]); all are
    /// validated and the surfaces rebuilt before anything changes.
    pub fn set(&mut self, changes: &Map<String, Value>) -> Result<(), ViewerError> {
        let next = self.params.apply(changes)?;
        let clip = match (&next.clip, &self.playback) {
            (None, _) => None,
            (Some(name), Some(playback)) => Some(playback.resolve(name)?),
            (Some(_), None) => {
                return Err(ViewerError::Param {
                    name: "clip",
                    message: "this mesh has no animation clips".into(),
                })
            }
        };
        let tags = if changes.contains_key("tags") {
            tag_file(&next.tags)?
        } else {
            self.tags.clone()
        };
        if self.params.needs_rebuild(&next) || tags != self.tags {
            self.rebuild(next, tags)?;
        } else {
            self.params = next;
        }
        // A new clip, time or play state restarts the clip's clock from `time`.
        if ["clip", "time", "playing"]
            .iter()
            .any(|k| changes.contains_key(*k))
        {
            if let Some(playback) = &mut self.playback {
                playback.restart();
            }
        }
        self.clip = clip;
        self.clip_stats();
        Ok(())
    }

    /// Builds the panels for `params` and `tags` on the current rest pose, then takes them.
    fn rebuild(&mut self, params: Params, tags: TagFile) -> Result<(), ViewerError> {
        let panels = build_panels(
            &self.ctx,
            &self.formats,
            &self.rest,
            self.model.raw.as_ref(),
            &params,
            &tags,
        )?;
        self.params = Params {
            tags: if tags == TagFile::default() {
                String::new()
            } else {
                tags.to_json()
            },
            ..params
        };
        self.tags = tags;
        self.panels = panels;
        self.deformed = false;
        self.posed = None;
        Ok(())
    }

    /// The clips and the playing clip's duration in the stats (they change with the file and
    /// the `clip` parameter, not per frame).
    fn clip_stats(&mut self) {
        self.stats.clips = self
            .playback
            .as_ref()
            .map_or_else(Vec::new, Playback::clip_names);
        self.stats.duration = match (&self.playback, self.clip) {
            (Some(playback), Some(clip)) => playback.duration(clip),
            _ => 0.0,
        };
    }

    /// The parameters in effect.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The drawing size, in pixels: the size of the views [`Viewer::draw`] draws into.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), ViewerError> {
        let max = self.ctx.limits.max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(ViewerError::Refused(format!(
                "size {width}x{height}: each side must be within 1..={max} on this device"
            )));
        }
        self.size = (width, height);
        Ok(())
    }

    /// The drawing size.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Each panel's left edge and width.
    fn layout(&self) -> Result<Vec<(u32, u32)>, ViewerError> {
        let widths = panel_widths(self.size.0, self.panels.len()).ok_or_else(|| {
            ViewerError::Refused(format!(
                "a view {} pixels wide has no room for {} panels",
                self.size.0,
                self.panels.len()
            ))
        })?;
        let mut x = 0;
        Ok(widths
            .into_iter()
            .map(|w| {
                let left = x;
                x += w + tessella_view::font::GAP;
                (left, w)
            })
            .collect())
    }

    /// The view options (`tessella render`'s) of a panel `width` pixels wide.
    fn view(&self, width: u32) -> RenderOptions {
        RenderOptions {
            size: (width, self.size.1),
            yaw: self.params.yaw,
            pitch: self.params.pitch,
            zoom: self.params.zoom,
            pan: self.params.pan,
            wireframe: self.params.wireframe,
            displacement: self.params.displacement.clone(),
            ..RenderOptions::default()
        }
    }

    /// The uniforms of panel `i`, `width` pixels wide: the camera frames the mesh as loaded.
    fn uniforms(&self, i: usize, width: u32) -> RenderUniforms {
        scene_uniforms(&self.model.mesh, &self.view(width), self.panels[i].reach())
    }

    /// Makes the attachments for the current size unless they are there.
    fn ensure_targets(&mut self) -> Result<(), ViewerError> {
        if self.targets.as_ref().is_none_or(|t| t.size != self.size) {
            let (ctx, formats, size) = (&self.ctx, self.formats, self.size);
            let made = ctx.scoped(|| {
                let texture = |label, format| {
                    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
                    tessella_view::texture(ctx, label, size, format, SAMPLES, usage)
                        .create_view(&Default::default())
                };
                Targets {
                    color: texture("viewer colour", formats.color),
                    depth: texture("viewer depth", DEPTH_FORMAT),
                    size,
                }
            })?;
            self.targets = Some(made);
        }
        Ok(())
    }

    /// Draws one frame into `view` (of the viewer's colour format and size): the animation at
    /// `time_ms`, the levels of the current camera, every panel in its viewport. Records and
    /// submits without waiting; a device error of this frame, or one reported since the last
    /// frame, is returned.
    pub fn draw(&mut self, view: &wgpu::TextureView, time_ms: f64) -> Result<(), ViewerError> {
        let start = crate::clock::now_ms();
        let mut uploaded = std::mem::take(&mut self.pending_upload);
        let clip = match (&mut self.playback, self.clip) {
            (Some(playback), Some(clip)) => Some((playback, clip)),
            _ => None,
        };
        let synthetic = match clip {
            Some(_) => None,
            None => deform::at(&self.rest, self.params.animate, time_ms),
        };
        if let Some((playback, clip)) = clip {
            let time = playback.time_at(clip, self.params.time, self.params.playing, time_ms);
            self.params.time = time;
            if self.posed != Some((clip, time.to_bits())) {
                // A pose the panels refuse (a triangle collapsed to no area) keeps the last
                // good frame on screen; the stats say why.
                self.stats.pose_error = None;
                let (positions, normals) = playback.pose(clip, time)?;
                for panel in &mut self.panels {
                    match panel.deform(positions, normals) {
                        Ok(bytes) => uploaded += bytes,
                        Err(ViewerError::Refine(e)) => {
                            self.stats.pose_error = Some(format!("clip at {time} s: {e}"));
                            break;
                        }
                        Err(e) => return Err(e),
                    }
                }
                self.posed = Some((clip, time.to_bits()));
                self.deformed = true;
            }
        } else {
            self.posed = None;
        }
        match synthetic {
            Some((positions, normals)) => {
                for panel in &mut self.panels {
                    uploaded += panel.deform(&positions, Some(&normals))?;
                }
                self.deformed = true;
            }
            None if self.deformed && self.clip.is_none() => {
                for panel in &mut self.panels {
                    uploaded += panel.deform(self.rest.positions(), Some(self.rest.normals()))?;
                }
                self.deformed = false;
            }
            None => {}
        }
        let layout = self.layout()?;
        for (i, &(_, width)) in layout.iter().enumerate() {
            self.panels[i].set_uniforms(&self.uniforms(i, width));
            if self.panels[i].has_lod() {
                let camera = lod_camera(&self.model.mesh, &self.view(width));
                uploaded += self.panels[i].follow_camera(camera, [width, self.size.1])?;
            }
        }
        let background = RenderOptions::default().background;
        let height = self.size.1 as f32;
        self.ensure_targets()?;
        let Some(targets) = &self.targets else {
            return Err(ViewerError::Refused("no drawing targets".into()));
        };
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        {
            let views = tessella_view::PassViews {
                color: &targets.color,
                resolve: view,
                depth: &targets.depth,
            };
            let mut pass =
                tessella_view::begin_pass(&mut encoder, "viewer frame", views, background);
            for (panel, &(left, width)) in self.panels.iter().zip(&layout) {
                pass.set_viewport(left as f32, 0.0, width as f32, height, 0.0, 1.0);
                panel.draw(&mut pass);
            }
        }
        self.ctx.submit(encoder)?;
        self.ctx.check()?;
        self.stats
            .frame(&self.panels, uploaded, crate::clock::now_ms() - start);
        Ok(())
    }

    /// The numbers of the last frame.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The coarse vertex and edge under pixel `(x, y)` of the view (origin top left), in the
    /// panel there, or `None` when the ray through it misses the coarse mesh.
    pub fn pick(&self, x: f32, y: f32) -> Option<Picked> {
        let layout = self.layout().ok()?;
        let (i, &(left, width)) = layout
            .iter()
            .enumerate()
            .find(|(_, &(left, width))| x >= left as f32 && x < (left + width) as f32)?;
        let ndc = [
            2.0 * (x - left as f32) / width as f32 - 1.0,
            1.0 - 2.0 * y / self.size.1 as f32,
        ];
        let view_proj = Mat4::from_cols_array_2d(&self.uniforms(i, width).view_proj);
        let (origin, dir) = pick::ray(&view_proj, ndc)?;
        let mesh = self.panels[i].mesh();
        pick::pick(mesh.positions(), mesh.triangles(), origin, dir)
    }

    /// Moves coarse vertex `index` (and every vertex at its position, so hard edges stay
    /// closed) to `position` in the rest pose; the surfaces follow from their new control nets
    /// alone. Refused (nothing changes) for an unknown vertex, a non-finite position or one
    /// that makes a triangle degenerate.
    pub fn move_vertex(&mut self, index: u32, position: [f32; 3]) -> Result<(), ViewerError> {
        let mut positions = self.rest.positions().to_vec();
        let old = *positions.get(index as usize).ok_or_else(|| {
            ViewerError::Refused(format!(
                "no vertex {index}: the mesh has {}",
                positions.len()
            ))
        })?;
        for p in positions.iter_mut().filter(|p| **p == old) {
            *p = position;
        }
        let mut rest = self.rest.clone();
        // Computed normals follow the move; the file's own normals stay as the file gave them.
        let normals = (!rest.normals_computed()).then(|| rest.normals().to_vec());
        rest.update(&positions, normals.as_deref())?;
        let mut uploaded = 0;
        for i in 0..self.panels.len() {
            match self.panels[i].deform(rest.positions(), Some(rest.normals())) {
                Ok(bytes) => uploaded += bytes,
                Err(e) => {
                    // Put the panels already moved back where they were.
                    for panel in &mut self.panels[..i] {
                        panel.deform(self.rest.positions(), Some(self.rest.normals()))?;
                    }
                    return Err(e);
                }
            }
        }
        self.rest = rest;
        self.pending_upload += uploaded;
        self.deformed = false;
        Ok(())
    }

    /// Sets the sharpness of the coarse edge between vertices `a` and `b` (0 removes the tag)
    /// and rebuilds the surfaces at once; refused for an edge that is not one, or a value
    /// outside `0..=1`.
    pub fn set_edge_sharpness(
        &mut self,
        a: u32,
        b: u32,
        sharpness: f32,
    ) -> Result<(), ViewerError> {
        if !(0.0..=1.0).contains(&sharpness) {
            return Err(ViewerError::Tags(format!(
                "edge sharpness must be within 0..=1, got {sharpness}"
            )));
        }
        let mut tags = self.tags.clone();
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
        self.check_tags(&tags)?;
        self.rebuild(self.params.clone(), tags)
    }

    /// Sets vertex `v`'s tension and bias (keeping its sharpness and crease) and rebuilds the
    /// surfaces at once.
    pub fn set_vertex_tension(
        &mut self,
        v: u32,
        tension: f32,
        bias: f32,
    ) -> Result<(), ViewerError> {
        let mut tags = self.tags.clone();
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
        self.check_tags(&tags)?;
        self.rebuild(self.params.clone(), tags)
    }

    /// Checks `tags` against the mesh (whatever the schemes drawn, so a saved file is one the
    /// CLI reads).
    fn check_tags(&self, tags: &TagFile) -> Result<(), ViewerError> {
        tags.tags(&self.rest)
            .map(|_| ())
            .map_err(|e| ViewerError::Tags(e.to_string()))
    }

    /// The tags in effect as the JSON `tessella refine --tags FILE` reads.
    pub fn tags_json(&self) -> String {
        self.tags.to_json()
    }

    /// The first panel's refined mesh, as drawn (the current deformation, levels and
    /// displacement), refined on the CPU by tessella-core and written as GLB by tessella-io.
    pub fn export_glb(&self) -> Result<Vec<u8>, ViewerError> {
        let panel = self
            .panels
            .first()
            .ok_or_else(|| ViewerError::Refused("nothing to export".into()))?;
        let mut options = panel
            .options
            .clone()
            .with_max_output_bytes(MAX_EXPORT_BYTES);
        if let Some(spec) = &self.params.lod {
            let (_, width) = self.layout()?[0];
            let camera = lod_camera(&self.model.mesh, &self.view(width));
            let lod = Lod::parse(spec, Some(camera), Some([width, self.size.1]))?;
            options = options.with_levels(Levels::Lod(lod));
        }
        let mesh = panel.mesh();
        let refiner = Refiner::new(mesh, &options)?;
        let mut refined = refiner.refine();
        if self.params.displacement.is_some() {
            let frame = tessella_core::DisplaceFrame::new(
                refiner.mesh(),
                refiner.topology(),
                refiner.layout(),
            );
            self.params.displacement.apply(&mut refined, &frame)?;
        }
        Ok(tessella_io::write_mesh_bytes(
            tessella_io::Format::Glb,
            (&refined).into(),
        )?)
    }

    /// The coarse mesh as loaded.
    pub fn mesh(&self) -> &Mesh {
        &self.model.mesh
    }

    /// The panels drawn.
    pub fn panels(&self) -> &[Panel] {
        &self.panels
    }

    /// Every parameter as JSON (`get()`), the tags as they are now.
    pub fn params_json(&self) -> Value {
        self.params.to_json()
    }
}
