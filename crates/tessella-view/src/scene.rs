//! What a view is, apart from drawing it: [`RenderOptions`], the camera uniforms
//! ([`scene_uniforms`]), the LOD camera and the panels' layout. No blocking call here, so
//! this part builds for the web too (the viewer's camera is this one).

use crate::appearance::RenderUniforms;
use crate::colormap::FieldColors;
use tessella_core::framing::Framing;
use tessella_core::Mesh;
use tessella_gpu::{Displacement, GpuError};

/// Largest picture side.
const MAX_SIDE: u32 = 8192;

/// How to draw a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Orbit about the vertical axis, degrees (0 looks along -Z).
    pub yaw: f32,
    /// Elevation of the eye, degrees.
    pub pitch: f32,
    /// 1 frames the mesh's bounding sphere; larger values move closer.
    pub zoom: f32,
    /// The orbit centre moved along the view's right and up axes, in units of the framed
    /// radius (`[0, 0]`: the bounding sphere's centre).
    pub pan: [f32; 2],
    /// Overlay the refinement pattern's edges.
    pub wireframe: bool,
    /// Clear colour, sRGB with alpha.
    pub background: [u8; 4],
    /// Surface colour, sRGB.
    pub color: [u8; 3],
    /// Displacement applied in the vertex shader.
    pub displacement: Displacement,
    /// Paint back faces in this sRGB colour instead of shading them: on a closed surface they
    /// show only through cracks (a crack finder).
    pub back_color: Option<[u8; 3]>,
    /// Colour the surface by this per-vertex field (instead of `color`), with a colour bar on
    /// the right (its width taken from `size`).
    pub field: Option<FieldColors>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            size: (512, 512),
            yaw: 30.0,
            pitch: 20.0,
            zoom: 1.0,
            pan: [0.0, 0.0],
            wireframe: false,
            background: [255, 255, 255, 255],
            color: [120, 160, 215],
            displacement: Displacement::None,
            back_color: None,
            field: None,
        }
    }
}

impl RenderOptions {
    /// Checks size, zoom and angles.
    pub fn validate(&self) -> Result<(), GpuError> {
        let (w, h) = self.size;
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
            return Err(GpuError::BadOption(format!(
                "picture size {w}x{h} must be within 1x1 ..= {MAX_SIDE}x{MAX_SIDE}"
            )));
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            return Err(GpuError::BadOption(format!(
                "zoom must be positive, got {}",
                self.zoom
            )));
        }
        if !self.yaw.is_finite() || !self.pitch.is_finite() {
            return Err(GpuError::BadOption("yaw and pitch must be finite".into()));
        }
        if !self.pan.iter().all(|p| p.is_finite()) {
            return Err(GpuError::BadOption(format!(
                "pan must be finite, got {:?}",
                self.pan
            )));
        }
        Ok(())
    }
}

/// Widths of `n` panels filling `total` pixels with [`crate::font::GAP`]-pixel separators;
/// `None` when a panel would be narrower than one pixel.
pub fn panel_widths(total: u32, n: usize) -> Option<Vec<u32>> {
    let n = u32::try_from(n).ok().filter(|&n| n > 0)?;
    let room = total.checked_sub((n - 1).checked_mul(crate::font::GAP)?)?;
    let (base, extra) = (room / n, room % n);
    (base > 0).then(|| (0..n).map(|i| base + u32::from(i < extra)).collect())
}

/// The camera [`render`](crate::render()) views `mesh` with, for the view-dependent LOD functions
/// (`Lod::Screen`, `Lod::Distance`): levels then follow what this very picture shows.
pub fn lod_camera(mesh: &Mesh, options: &RenderOptions) -> tessella_core::refine::Camera {
    let (w, h) = options.size;
    let cam = Framing::points(
        mesh.positions(),
        0.0,
        (options.yaw, options.pitch, options.zoom, options.pan),
        w.max(1) as f32 / h.max(1) as f32,
    );
    tessella_core::refine::Camera {
        eye: cam.eye,
        target: cam.target,
        fov_y_deg: crate::camera::FOV_Y_DEGREES,
    }
}

/// Uniforms for a view of `mesh` framed by its bounding sphere grown by `reach` (how far
/// displacement can move a point).
pub fn scene_uniforms(mesh: &Mesh, options: &RenderOptions, reach: f32) -> RenderUniforms {
    let (w, h) = options.size;
    let cam = Framing::points(
        mesh.positions(),
        reach,
        (options.yaw, options.pitch, options.zoom, options.pan),
        w as f32 / h as f32,
    );
    let c = options.color.map(srgb_to_linear);
    RenderUniforms {
        view_proj: cam.view_proj,
        eye: [cam.eye[0], cam.eye[1], cam.eye[2], 1.0],
        light_dir: [cam.light_dir[0], cam.light_dir[1], cam.light_dir[2], 0.0],
        base_color: [c[0], c[1], c[2], 1.0],
        wire_color: [0.004, 0.006, 0.015, 1.0],
        flags: [
            options.wireframe as u32,
            0,
            options.displacement.is_some() as u32,
            options.back_color.map_or(0, |[r, g, b]| {
                1 << 24 | r as u32 | (g as u32) << 8 | (b as u32) << 16
            }),
        ],
    }
}

/// The clear colour of a render pass for an sRGB `background` with alpha (the attachments are
/// sRGB formats, so the colour is given linear).
pub fn clear_color(background: [u8; 4]) -> wgpu::Color {
    let [r, g, b] = [background[0], background[1], background[2]].map(|c| srgb_to_linear(c) as f64);
    wgpu::Color {
        r,
        g,
        b,
        a: background[3] as f64 / 255.0,
    }
}

/// An sRGB byte as a linear intensity.
pub(crate) fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
