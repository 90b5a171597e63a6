//! What `stats()` reports: the numbers of the last frame (the contract's table).

use crate::panel::Panel;
use serde::Serialize;
use tessella_gpu::GpuContext;

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Stats {
    pub adapter: String,
    /// CPU time of the last frame (deformation, levels, recording, submission), ms.
    pub frame_ms: f64,
    pub coarse_triangles: u64,
    /// Triangles drawn by the last frame, all panels.
    pub refined_triangles: u64,
    /// Bytes written to GPU buffers by the last frame: control nets, level records and
    /// instances (the uniforms' 144 bytes per panel are not counted).
    pub uploaded_bytes: u64,
    /// GPU bytes the renderers keep, all panels.
    pub pattern_bytes: u64,
    /// What static, welded and indexed refined meshes of the same panels would need.
    pub static_bytes: u64,
    /// The uniform level, or the largest edge level of the last frame with a LOD (first panel).
    pub level: f32,
    /// `"webgpu"` in the browser, else wgpu's backend (`"vulkan"`, `"metal"`, ...).
    pub backend: String,
    /// The loaded file's animation clips (empty: none).
    pub clips: Vec<String>,
    /// The duration of the clip playing, seconds (0 without one).
    pub duration: f32,
    /// Why the last frame kept the previous pose (a pose the surfaces refuse), if it did.
    pub pose_error: Option<String>,
}

/// The backend's name as `stats()` gives it.
pub fn backend_name(backend: wgpu::Backend) -> String {
    match backend {
        wgpu::Backend::BrowserWebGpu => "webgpu".into(),
        other => format!("{other:?}").to_ascii_lowercase(),
    }
}

impl Stats {
    /// Before any frame.
    pub fn new(ctx: &GpuContext, coarse_triangles: usize) -> Stats {
        Stats {
            adapter: ctx.adapter_label(),
            frame_ms: 0.0,
            coarse_triangles: coarse_triangles as u64,
            refined_triangles: 0,
            uploaded_bytes: 0,
            pattern_bytes: 0,
            static_bytes: 0,
            level: 0.0,
            backend: backend_name(ctx.info.backend),
            clips: Vec::new(),
            duration: 0.0,
            pose_error: None,
        }
    }

    /// After a frame that drew `panels`, uploading `uploaded` bytes in `frame_ms`.
    pub fn frame(&mut self, panels: &[Panel], uploaded: u64, frame_ms: f64) {
        self.frame_ms = frame_ms;
        self.uploaded_bytes = uploaded;
        self.refined_triangles = panels.iter().map(Panel::triangles).sum();
        self.pattern_bytes = panels.iter().map(Panel::gpu_bytes).sum();
        self.static_bytes = panels.iter().map(Panel::static_bytes).sum();
        self.level = panels.first().map_or(0.0, Panel::level);
    }
}
