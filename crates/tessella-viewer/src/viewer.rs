//! [`Viewer`]: the loaded coarse mesh, the parameters, one [`Panel`] per scheme, and a frame
//! drawn into the caller's texture view. Every call either succeeds or leaves the viewer as it
//! was; nothing waits for the GPU.

use crate::error::ViewerError;
use crate::panel::Panel;
use crate::params::Params;
use crate::pick::{self, Picked};
use crate::scene::{self, BuildPanels, Deform, PanelSpec, Scene};
use crate::stats::Stats;
use glam::Mat4;
use serde_json::{Map, Value};
use tessella_core::refine::{Levels, Lod};
use tessella_core::Mesh;
use tessella_gpu::{GpuContext, TargetFormats};
use tessella_view::{lod_camera, panel_widths, scene_uniforms, RenderOptions, RenderUniforms};

/// Multisampling, as `tessella render`'s pictures (the silhouettes are the point).
pub const SAMPLES: u32 = 4;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The sample shown before anything is loaded.
pub const FIRST_SAMPLE: &str = "icosphere";

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
    /// The mesh, parameters, tags, clips and panels (the same code as
    /// [`crate::CoarseViewer`]'s).
    scene: Scene<Panel>,
    /// Bytes uploaded outside a frame (a moved vertex), counted with the next frame.
    pending_upload: u64,
    stats: Stats,
}

impl std::fmt::Debug for Viewer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Viewer")
            .field("adapter", &self.ctx.adapter_label())
            .field("panels", &self.scene.panels)
            .finish()
    }
}

/// The viewer's device and formats build its panels.
impl BuildPanels<Panel> for (&GpuContext, &TargetFormats) {
    fn panel(&self, spec: PanelSpec<'_>) -> Result<Panel, ViewerError> {
        Panel::new(
            self.0,
            spec.mesh,
            spec.params,
            spec.scheme,
            spec.tags,
            self.1,
        )
    }
}

impl Deform for Panel {
    fn deform(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<u64, ViewerError> {
        Panel::deform(self, positions, normals)
    }
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
        let scene = Scene::new(&(&ctx, &formats))?;
        let stats = Stats::new(&ctx, scene.model.face_count());
        Ok(Viewer {
            ctx,
            formats,
            size: RenderOptions::default().size,
            targets: None,
            scene,
            pending_upload: 0,
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
        self.scene.load(name, bytes, &(&self.ctx, &self.formats))?;
        self.new_mesh();
        Ok(())
    }

    /// Replaces the mesh with a bundled sample ([`scene::sample_names`]).
    pub fn load_sample(&mut self, name: &str) -> Result<(), ViewerError> {
        self.scene.load_sample(name, &(&self.ctx, &self.formats))?;
        self.new_mesh();
        Ok(())
    }

    /// Fresh stats for a mesh just loaded.
    fn new_mesh(&mut self) {
        self.stats = Stats::new(&self.ctx, self.scene.model.face_count());
        self.clip_stats();
    }

    /// Applies `changes` (any subset of the parameters, see [`crate::params::KEYS`]); all are
    /// validated and the surfaces rebuilt before anything changes.
    pub fn set(&mut self, changes: &Map<String, Value>) -> Result<(), ViewerError> {
        self.scene.set(changes, &(&self.ctx, &self.formats))?;
        self.clip_stats();
        Ok(())
    }

    /// The clips and the playing clip's duration in the stats (they change with the file and
    /// the `clip` parameter, not per frame).
    fn clip_stats(&mut self) {
        self.stats.clips = self.scene.motion.clip_names();
        self.stats.duration = self.scene.motion.duration();
    }

    /// The parameters in effect.
    pub fn params(&self) -> &Params {
        &self.scene.params
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
        let widths = panel_widths(self.size.0, self.scene.panels.len()).ok_or_else(|| {
            ViewerError::Refused(format!(
                "a view {} pixels wide has no room for {} panels",
                self.size.0,
                self.scene.panels.len()
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
            yaw: self.scene.params.yaw,
            pitch: self.scene.params.pitch,
            zoom: self.scene.params.zoom,
            pan: self.scene.params.pan,
            wireframe: self.scene.params.wireframe,
            displacement: self.scene.params.displacement.clone(),
            ..RenderOptions::default()
        }
    }

    /// The uniforms of panel `i`, `width` pixels wide: the camera frames the mesh as loaded.
    fn uniforms(&self, i: usize, width: u32) -> RenderUniforms {
        scene_uniforms(
            &self.scene.model,
            &self.view(width),
            self.scene.panels[i].reach(),
        )
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
        let stepped = self.scene.step(time_ms)?;
        uploaded += stepped.uploaded;
        if let Some(error) = stepped.pose_error {
            self.stats.pose_error = error;
        }
        let layout = self.layout()?;
        for (i, &(_, width)) in layout.iter().enumerate() {
            self.scene.panels[i].set_uniforms(&self.uniforms(i, width));
            if self.scene.panels[i].has_lod() {
                let camera = lod_camera(&self.scene.model, &self.view(width));
                uploaded += self.scene.panels[i].follow_camera(camera, [width, self.size.1])?;
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
            for (panel, &(left, width)) in self.scene.panels.iter().zip(&layout) {
                pass.set_viewport(left as f32, 0.0, width as f32, height, 0.0, 1.0);
                panel.draw(&mut pass);
            }
        }
        self.ctx.submit(encoder)?;
        self.ctx.check()?;
        self.stats
            .frame(&self.scene.panels, uploaded, crate::clock::now_ms() - start);
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
        let mesh = self.scene.panels[i].mesh();
        pick::pick(mesh.positions(), mesh.triangles(), origin, dir)
    }

    /// Moves coarse vertex `index` (and every vertex at its position, so hard edges stay
    /// closed) to `position` in the rest pose; the surfaces follow from their new control nets
    /// alone. Refused (nothing changes) for an unknown vertex, a non-finite position or one
    /// that makes a triangle degenerate.
    pub fn move_vertex(&mut self, index: u32, position: [f32; 3]) -> Result<(), ViewerError> {
        self.pending_upload += self.scene.move_vertex(index, position)?;
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
        let build = (&self.ctx, &self.formats);
        self.scene.set_edge_sharpness(a, b, sharpness, &build)
    }

    /// Sets vertex `v`'s tension and bias (keeping its sharpness and crease) and rebuilds the
    /// surfaces at once.
    pub fn set_vertex_tension(
        &mut self,
        v: u32,
        tension: f32,
        bias: f32,
    ) -> Result<(), ViewerError> {
        let build = (&self.ctx, &self.formats);
        self.scene.set_vertex_tension(v, tension, bias, &build)
    }

    /// The tags in effect as the JSON `tessella refine --tags FILE` reads.
    pub fn tags_json(&self) -> String {
        self.scene.tags.to_json()
    }

    /// The first panel's refined mesh, as drawn (the current deformation, levels and
    /// displacement), refined on the CPU by tessella-core and written as GLB by tessella-io.
    pub fn export_glb(&self) -> Result<Vec<u8>, ViewerError> {
        let panel = self.scene.first_panel()?;
        let mut options = panel.options.clone();
        if let Some(spec) = &self.scene.params.lod {
            let (_, width) = self.layout()?[0];
            let camera = lod_camera(&self.scene.model, &self.view(width));
            let lod = Lod::parse(spec, Some(camera), Some([width, self.size.1]))?;
            options = options.with_levels(Levels::Lod(lod));
        }
        scene::export_glb(panel.mesh(), &options, &self.scene.params.displacement)
    }

    /// The coarse mesh as loaded.
    pub fn mesh(&self) -> &Mesh {
        &self.scene.model
    }

    /// The panels drawn.
    pub fn panels(&self) -> &[Panel] {
        &self.scene.panels
    }

    /// Every parameter as JSON (`get()`), the tags as they are now.
    pub fn params_json(&self) -> Value {
        self.scene.params.to_json()
    }
}
