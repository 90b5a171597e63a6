//! [`CoarseViewer`]: the viewer's coarse side without a GPU, for the web page's WebGL2
//! fallback. It loads files (with their clips), takes the same parameters, tags, dragged
//! vertices and `animate`/clip poses as the WebGPU [`crate::Viewer`] (through [`crate::scene`],
//! the same code) and keeps one surface per panel; every frame it hands out the control nets
//! of the pose, packed as RGBA float texels in the layout `tessella`'s `InstancedSurface`
//! reads (its GLSL draws them): O(coarse triangles) per frame, nothing refined here.

use crate::error::ViewerError;
use crate::panel::refine_options;
use crate::params::Params;
use crate::pick::{self, Picked};
use crate::scene::{self, BuildPanels, Deform, PanelSpec, Scene};
use glam::Mat4;
use serde_json::{Map, Value};
use tessella_core::basis::NORMAL_NET_LEN;
use tessella_core::displace::Displacement;
use tessella_core::refine::{Frame, Surface};
use tessella_core::{Mesh, RefineOptions, Scheme};

/// One panel's surface: its scheme's control nets of the pose shown.
struct Nets {
    scheme: Scheme,
    options: RefineOptions,
    surface: Surface,
    frame: Frame<'static>,
    /// The nets moved since [`CoarseViewer::pack`] last packed them.
    changed: bool,
}

impl Deform for Nets {
    fn deform(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<u64, ViewerError> {
        self.surface.update(&mut self.frame, positions, normals)?;
        self.changed = true;
        // What crosses to the GPU is the caller's to count (it uploads the packed nets).
        Ok(0)
    }
}

/// Builds the fallback's panels: one scheme's nets each.
struct BuildNets;

impl BuildPanels<Nets> for BuildNets {
    fn panel(
        &self,
        PanelSpec {
            mesh,
            params,
            scheme,
            tags,
        }: PanelSpec<'_>,
    ) -> Result<Nets, ViewerError> {
        let options = refine_options(params, scheme, tags)?;
        let surface = Surface::new(mesh, &options.surface_options())?;
        let frame = surface.frame(mesh.clone())?;
        Ok(Nets {
            scheme,
            options,
            surface,
            frame,
            changed: true,
        })
    }
}

/// The viewer without a GPU (see the module docs). Every call succeeds or changes nothing.
pub struct CoarseViewer {
    scene: Scene<Nets>,
}

impl CoarseViewer {
    /// The viewer's first sample with the default parameters.
    pub fn new() -> Result<CoarseViewer, ViewerError> {
        Ok(CoarseViewer {
            scene: Scene::new(&BuildNets)?,
        })
    }

    /// As [`crate::Viewer::load`].
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<(), ViewerError> {
        self.scene.load(name, bytes, &BuildNets)
    }

    /// As [`crate::Viewer::load_sample`].
    pub fn load_sample(&mut self, name: &str) -> Result<(), ViewerError> {
        self.scene.load_sample(name, &BuildNets)
    }

    /// As [`crate::Viewer::set`]: the same checks and messages.
    pub fn set(&mut self, changes: &Map<String, Value>) -> Result<(), ViewerError> {
        self.scene.set(changes, &BuildNets)
    }

    /// The parameters in effect.
    pub fn params(&self) -> &Params {
        &self.scene.params
    }

    /// Moves the surfaces to the pose at page time `time_ms` (the clip's, the `animate`
    /// deformation's, or the rest pose after one), as the WebGPU viewer's frame does.
    pub fn frame(&mut self, time_ms: f64) -> Result<(), ViewerError> {
        self.scene.step(time_ms).map(|_| ())
    }

    /// Panels (one surface each).
    pub fn panel_count(&self) -> usize {
        self.scene.panels.len()
    }

    /// Panel `i`'s scheme, as its name.
    pub fn scheme(&self, i: usize) -> Option<&Scheme> {
        self.scene.panels.get(i).map(|p| &p.scheme)
    }

    /// Whether panel `i`'s nets moved since they were last packed.
    pub fn changed(&self, i: usize) -> bool {
        self.scene.panels.get(i).is_some_and(|p| p.changed)
    }

    /// Panel `i`'s control nets packed into `out` as `InstancedSurface` lays them out: face
    /// `f`'s net is `texels` RGBA texels, its control points then its normal-net entries,
    /// 3 floats each, at texel `((f % faces_per_row) * texels, f / faces_per_row)`, rows of
    /// `faces_per_row * texels` texels; the rest of `out` is zero. Marks the nets packed.
    pub fn pack(
        &mut self,
        i: usize,
        faces_per_row: usize,
        texels: usize,
        out: &mut Vec<f32>,
    ) -> Result<(), ViewerError> {
        let panel = self
            .scene
            .panels
            .get_mut(i)
            .ok_or_else(|| ViewerError::Refused(format!("no panel {i}")))?;
        let nets = panel.frame.nets();
        let k = nets.basis.len();
        if faces_per_row == 0 || texels * 4 < 3 * (k + NORMAL_NET_LEN) {
            return Err(ViewerError::Refused(format!(
                "nets of {k} control points do not fit {texels} texels a face ({faces_per_row} a row)"
            )));
        }
        let faces = nets.len();
        let width = faces_per_row * texels;
        let height = faces.div_ceil(faces_per_row);
        out.clear();
        out.resize(width * height * 4, 0.0);
        nets.pack_texels(faces_per_row, texels, out);
        panel.changed = false;
        Ok(())
    }

    /// The mesh as loaded (what the camera frames).
    pub fn model(&self) -> &Mesh {
        &self.scene.model
    }

    /// The rest pose (dragged vertices moved).
    pub fn rest(&self) -> &Mesh {
        &self.scene.rest
    }

    /// The first panel's coarse mesh as drawn now (posed, deformed).
    pub fn shown(&self) -> &Mesh {
        let scene = &self.scene;
        scene.panels.first().map_or(&scene.rest, |p| p.frame.mesh())
    }

    /// The coarse vertex and edge under `ndc` (x, y in -1..1, y up) of a view drawn with
    /// `view_proj` (column-major, wgpu's 0..1 depth), ray-cast against the mesh as drawn, as
    /// [`crate::Viewer::pick`] does; `None` when the ray misses.
    pub fn pick(&self, view_proj: &[f32; 16], ndc: [f32; 2]) -> Option<Picked> {
        let (origin, dir) = pick::ray(&Mat4::from_cols_array(view_proj), ndc)?;
        let mesh = self.shown();
        pick::pick(mesh.positions(), mesh.triangles(), origin, dir)
    }

    /// As [`crate::Viewer::move_vertex`].
    pub fn move_vertex(&mut self, index: u32, position: [f32; 3]) -> Result<(), ViewerError> {
        self.scene.move_vertex(index, position).map(|_| ())
    }

    /// As [`crate::Viewer::set_edge_sharpness`].
    pub fn set_edge_sharpness(&mut self, a: u32, b: u32, s: f32) -> Result<(), ViewerError> {
        self.scene.set_edge_sharpness(a, b, s, &BuildNets)
    }

    /// As [`crate::Viewer::set_vertex_tension`].
    pub fn set_vertex_tension(
        &mut self,
        v: u32,
        tension: f32,
        bias: f32,
    ) -> Result<(), ViewerError> {
        self.scene.set_vertex_tension(v, tension, bias, &BuildNets)
    }

    /// The tags in effect as the JSON `tessella refine --tags FILE` reads.
    pub fn tags_json(&self) -> String {
        self.scene.tags.to_json()
    }

    /// The loaded file's clips (`[]`: none).
    pub fn clips(&self) -> Vec<String> {
        self.scene.motion.clip_names()
    }

    /// The playing clip's duration, seconds (0 without one).
    pub fn duration(&self) -> f32 {
        self.scene.motion.duration()
    }

    /// Why the last clip pose was refused (the previous one stays), if it was.
    pub fn pose_error(&self) -> Option<&str> {
        self.scene.pose_error.as_deref()
    }

    /// The first panel's refined mesh as drawn (pose, tags), refined on the CPU, as GLB.
    pub fn export_glb(&self) -> Result<Vec<u8>, ViewerError> {
        let panel = self.scene.first_panel()?;
        // Without the `displacement` parameter, as this export always was.
        scene::export_glb(panel.frame.mesh(), &panel.options, &Displacement::None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;
    use tessella_core::animation::Poser;

    fn set(v: &mut CoarseViewer, changes: Value) -> Result<(), ViewerError> {
        v.set(changes.as_object().unwrap())
    }

    fn glb() -> Vec<u8> {
        std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../samples/animated-creature.glb"
        ))
        .unwrap()
    }

    /// The packed nets of a paused clip are the core's nets of the poser's pose (built here
    /// independently, with a `Plan` of the pose), in InstancedSurface's layout.
    #[test]
    fn a_paused_clip_packs_the_nets_of_the_posers_pose() {
        let mut v = CoarseViewer::new().unwrap();
        v.load("animated-creature.glb", &glb()).unwrap();
        assert_eq!(v.clips(), ["wave", "hop", "breathe"]);
        set(
            &mut v,
            json!({"clip": "wave", "time": 0.5, "playing": false}),
        )
        .unwrap();
        v.frame(1000.0).unwrap();
        assert!(v.changed(0));
        let poser =
            Poser::new(tessella_io::read_animated_bytes("a.glb", &glb(), &[]).unwrap()).unwrap();
        let posed = poser
            .mesh(Some(poser.clip_index("wave").unwrap()), 0.5)
            .unwrap();
        let (_, frame) =
            tessella_core::refine::Plan::with_frame(posed, &RefineOptions::new(Scheme::Pn, 8))
                .unwrap();
        let want = frame.nets();
        let (fpr, texels) = (160, 12);
        let mut out = Vec::new();
        v.pack(0, fpr, texels, &mut out).unwrap();
        assert!(!v.changed(0));
        assert_eq!(out.len(), 2 * fpr * texels * 4);
        let mut worst = 0.0f32;
        for f in 0..want.len() {
            let start = ((f / fpr) * fpr * texels + (f % fpr) * texels) * 4;
            let expect = want
                .patch_points(f)
                .iter()
                .chain(want.patch_normals(f))
                .flatten();
            for (i, e) in expect.enumerate() {
                worst = worst.max((out[start + i] - e).abs());
            }
        }
        assert!(worst < 1e-4, "packed nets {worst} off the poser's");
        // Paused: the next frame poses nothing.
        v.frame(1500.0).unwrap();
        assert!(!v.changed(0));
        // Too few texels for PN's 16 entries is refused.
        assert!(v.pack(0, fpr, 11, &mut out).is_err());
    }

    #[test]
    fn animate_tags_and_bad_values_go_through_the_viewers_checks() {
        let mut v = CoarseViewer::new().unwrap();
        let rest = v.rest().positions().to_vec();
        set(&mut v, json!({"animate": "twist"})).unwrap();
        v.frame(1000.0).unwrap();
        assert!(
            v.shown().positions() != &rest[..],
            "a quarter period twists"
        );
        set(&mut v, json!({"animate": "none"})).unwrap();
        v.frame(1100.0).unwrap();
        assert!(v.shown().positions() == &rest[..], "back at rest");
        // Tags shape the scalar-tagged scheme.
        set(&mut v, json!({"scheme": "st"})).unwrap();
        let mut before = Vec::new();
        v.pack(0, 170, 12, &mut before).unwrap();
        let tri = v.rest().triangles()[0];
        v.set_edge_sharpness(tri[0], tri[1], 1.0).unwrap();
        v.set_vertex_tension(tri[0], 0.8, 0.3).unwrap();
        assert!(v.tags_json().contains("sharpness"));
        assert_eq!(v.params().tags, v.tags_json());
        let mut after = Vec::new();
        v.pack(0, 170, 12, &mut after).unwrap();
        assert!(before != after, "tags change the nets");
        for bad in [
            json!({"clip": "wave"}),
            json!({"level": 0}),
            json!({"tags": "{"}),
        ] {
            let name = bad.as_object().unwrap().keys().next().unwrap().clone();
            let e = set(&mut v, bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("{name}:")), "{e}");
        }
        assert!(v.set_edge_sharpness(0, 0, 2.0).is_err());
    }
}
