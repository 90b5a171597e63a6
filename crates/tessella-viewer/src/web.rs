//! The wasm-bindgen face of the viewer: `WebViewer`, exactly as `CONTRACT.md` says. Thin: it
//! turns JS values into the [`crate::Viewer`]'s Rust calls and errors into thrown `Error`s.

use crate::error::ViewerError;
use crate::present::Presenter;
use crate::viewer::Viewer;
use tessella_gpu::{AdapterChoice, GpuContext};
use wasm_bindgen::prelude::*;
use web_sys::HtmlCanvasElement;

/// The start of the message a panic is thrown with.
pub const PANIC_PREFIX: &str = "tessella-viewer panicked (a bug, please report it): ";

/// Runs when the module is instantiated: a panic throws a JS `Error` instead of trapping with
/// `RuntimeError: unreachable`.
#[wasm_bindgen(start)]
pub fn start() {
    std::panic::set_hook(Box::new(|info| {
        wasm_bindgen::throw_str(&format!("{PANIC_PREFIX}{info}"))
    }));
}

fn js(e: ViewerError) -> JsError {
    JsError::new(&e.to_string())
}

/// A JS value as JSON (`JSON.stringify`: NaN and infinities become `null`, which the
/// parameters then refuse by name).
fn to_json(value: &JsValue) -> Result<serde_json::Value, JsError> {
    let text = js_sys::JSON::stringify(value)
        .map_err(|_| JsError::new("the value cannot be written as JSON"))?;
    let text = String::from(text);
    serde_json::from_str(&text).map_err(|e| JsError::new(&format!("bad JSON value: {e}")))
}

/// A JSON value as a plain JS object.
fn from_json(value: &serde_json::Value) -> Result<JsValue, JsError> {
    js_sys::JSON::parse(&value.to_string()).map_err(|_| JsError::new("cannot read back JSON"))
}

/// Whether the page has `navigator.gpu` (wgpu's WebGPU backend needs it).
fn has_webgpu() -> bool {
    let global = js_sys::global();
    js_sys::Reflect::get(&global, &"navigator".into())
        .ok()
        .filter(|n| !n.is_undefined())
        .and_then(|n| js_sys::Reflect::get(&n, &"gpu".into()).ok())
        .is_some_and(|gpu| !gpu.is_undefined() && !gpu.is_null())
}

#[wasm_bindgen]
pub struct WebViewer {
    viewer: Viewer,
    presenter: Presenter,
    canvas: HtmlCanvasElement,
}

#[wasm_bindgen]
impl WebViewer {
    /// Opens WebGPU on `canvas` and shows the first sample; rejects when WebGPU, an adapter or
    /// a device is missing.
    pub async fn create(canvas: HtmlCanvasElement) -> Result<WebViewer, JsError> {
        if !has_webgpu() {
            return Err(JsError::new(
                "WebGPU is not available in this browser (no navigator.gpu)",
            ));
        }
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::BROWSER_WEBGPU,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas.clone()))
            .map_err(|e| JsError::new(&format!("cannot draw on this canvas with WebGPU: {e}")))?;
        let ctx = GpuContext::for_surface_async(&instance, Some(&surface), AdapterChoice::Auto)
            .await
            .map_err(|e| js(e.into()))?;
        let presenter = Presenter::new(&ctx, surface, width, height).map_err(js)?;
        let mut viewer = Viewer::new(ctx, presenter.view_format()).map_err(js)?;
        viewer.resize(width, height).map_err(js)?;
        Ok(WebViewer {
            viewer,
            presenter,
            canvas,
        })
    }

    /// The adapter's name and backend.
    pub fn adapter(&self) -> String {
        self.viewer.context().adapter_label()
    }

    /// Loads a mesh file's bytes; the extension of `name` picks the format.
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<(), JsError> {
        self.viewer.load(name, bytes).map_err(js)
    }

    #[wasm_bindgen(js_name = loadSample)]
    pub fn load_sample(&mut self, name: &str) -> Result<(), JsError> {
        self.viewer.load_sample(name).map_err(js)
    }

    pub fn samples(&self) -> Vec<String> {
        crate::scene::sample_names()
    }

    pub fn set(&mut self, params: JsValue) -> Result<(), JsError> {
        let value = to_json(&params)?;
        let changes = value
            .as_object()
            .ok_or_else(|| JsError::new("params: set() takes a plain object"))?;
        self.viewer.set(changes).map_err(js)
    }

    pub fn get(&self) -> Result<JsValue, JsError> {
        from_json(&self.viewer.params_json())
    }

    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), JsError> {
        self.viewer.resize(width, height).map_err(js)?;
        self.canvas.set_width(width);
        self.canvas.set_height(height);
        let ctx = self.viewer.context().clone();
        self.presenter.resize(&ctx, width, height).map_err(js)
    }

    pub fn frame(&mut self, time_ms: f64) -> Result<(), JsError> {
        let ctx = self.viewer.context().clone();
        self.presenter
            .frame(&ctx, &mut self.viewer, time_ms)
            .map(|_| ())
            .map_err(js)
    }

    pub fn stats(&self) -> Result<JsValue, JsError> {
        let value = serde_json::to_value(self.viewer.stats())
            .map_err(|e| JsError::new(&format!("stats: {e}")))?;
        from_json(&value)
    }

    pub fn pick(&self, x: f32, y: f32) -> Result<JsValue, JsError> {
        match self.viewer.pick(x, y) {
            None => Ok(JsValue::NULL),
            Some(p) => from_json(&serde_json::json!({ "vertex": p.vertex, "edge": p.edge })),
        }
    }

    #[wasm_bindgen(js_name = moveVertex)]
    pub fn move_vertex(&mut self, index: u32, x: f32, y: f32, z: f32) -> Result<(), JsError> {
        self.viewer.move_vertex(index, [x, y, z]).map_err(js)
    }

    #[wasm_bindgen(js_name = setEdgeSharpness)]
    pub fn set_edge_sharpness(&mut self, a: u32, b: u32, s: f32) -> Result<(), JsError> {
        self.viewer.set_edge_sharpness(a, b, s).map_err(js)
    }

    #[wasm_bindgen(js_name = setVertexTension)]
    pub fn set_vertex_tension(&mut self, v: u32, tension: f32, bias: f32) -> Result<(), JsError> {
        self.viewer.set_vertex_tension(v, tension, bias).map_err(js)
    }

    #[wasm_bindgen(js_name = tagsJson)]
    pub fn tags_json(&self) -> String {
        self.viewer.tags_json()
    }

    #[wasm_bindgen(js_name = exportGlb)]
    pub fn export_glb(&self) -> Result<Vec<u8>, JsError> {
        self.viewer.export_glb().map_err(js)
    }

    /// The benchmark (`tessella_bench::web`, CONTRACT.md) on this viewer's device: resolves to
    /// its report, rejects on a bad configuration or a device error. `config` may be
    /// `undefined` (the papers' sizes). The page keeps running meanwhile: every frame is
    /// awaited, never waited for.
    pub fn bench(&self, config: JsValue) -> js_sys::Promise {
        use tessella_bench::web::{run, BenchConfig, BenchError};
        let thrown = |e: BenchError| JsValue::from(JsError::new(&e.to_string()));
        // Its own error lists: a late error of the viewer's frames is not the benchmark's.
        let ctx = self.viewer.context().with_own_errors();
        let parsed = if config.is_undefined() {
            Ok(serde_json::Value::Null)
        } else {
            to_json(&config).map_err(JsValue::from)
        };
        wasm_bindgen_futures::future_to_promise(async move {
            let config = BenchConfig::from_json(&parsed?).map_err(thrown)?;
            let report = run(&ctx, &config).await.map_err(thrown)?;
            from_json(&report).map_err(JsValue::from)
        })
    }
}

/// The viewer's coarse side without a GPU ([`crate::CoarseViewer`]), for the WebGL2 fallback:
/// files, clips, parameters, tags and poses as `WebViewer` takes them, and every frame the
/// control nets of the pose packed for `tessella`'s `InstancedSurface` GLSL.
#[wasm_bindgen]
pub struct WebCoarseViewer {
    inner: crate::CoarseViewer,
}

fn flat(points: &[[f32; 3]]) -> Vec<f32> {
    points.iter().flatten().copied().collect()
}

#[wasm_bindgen]
impl WebCoarseViewer {
    /// Shows the first sample with the default parameters until `load`.
    #[wasm_bindgen(constructor)]
    pub fn new() -> Result<WebCoarseViewer, JsError> {
        Ok(WebCoarseViewer {
            inner: crate::CoarseViewer::new().map_err(js)?,
        })
    }

    /// As `WebViewer.load`.
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<(), JsError> {
        self.inner.load(name, bytes).map_err(js)
    }

    /// As `WebViewer.set`: the same checks and messages.
    pub fn set(&mut self, params: JsValue) -> Result<(), JsError> {
        let value = to_json(&params)?;
        let changes = value
            .as_object()
            .ok_or_else(|| JsError::new("params: set() takes a plain object"))?;
        self.inner.set(changes).map_err(js)
    }

    pub fn get(&self) -> Result<JsValue, JsError> {
        from_json(&self.inner.params().to_json())
    }

    /// Poses the surfaces for page time `timeMs` (clip, `animate`, or the rest pose).
    pub fn frame(&mut self, time_ms: f64) -> Result<(), JsError> {
        self.inner.frame(time_ms).map_err(js)
    }

    #[wasm_bindgen(js_name = panelCount)]
    pub fn panel_count(&self) -> usize {
        self.inner.panel_count()
    }

    /// Whether panel `i`'s nets moved since `nets(i, ...)` last packed them.
    pub fn changed(&self, i: usize) -> bool {
        self.inner.changed(i)
    }

    /// Panel `i`'s control nets, packed `facesPerRow` nets of `texelsPerFace` RGBA texels to
    /// a row (`InstancedSurface`'s layout), `facesPerRow * texelsPerFace * rows * 4` floats.
    pub fn nets(
        &mut self,
        i: usize,
        faces_per_row: usize,
        texels_per_face: usize,
    ) -> Result<Vec<f32>, JsError> {
        let mut out = Vec::new();
        self.inner
            .pack(i, faces_per_row, texels_per_face, &mut out)
            .map_err(js)?;
        Ok(out)
    }

    /// The mesh as loaded (what the camera frames): positions, 3 numbers a vertex.
    #[wasm_bindgen(js_name = modelPositions)]
    pub fn model_positions(&self) -> Vec<f32> {
        flat(self.inner.model().positions())
    }

    /// The first panel's coarse mesh as drawn now (posed): positions.
    #[wasm_bindgen(js_name = shownPositions)]
    pub fn shown_positions(&self) -> Vec<f32> {
        flat(self.inner.shown().positions())
    }

    /// The rest pose (dragged vertices moved): positions and normals.
    #[wasm_bindgen(js_name = restPositions)]
    pub fn rest_positions(&self) -> Vec<f32> {
        flat(self.inner.rest().positions())
    }

    #[wasm_bindgen(js_name = restNormals)]
    pub fn rest_normals(&self) -> Vec<f32> {
        flat(self.inner.rest().normals())
    }

    /// The coarse triangles, 3 vertex indices each.
    pub fn indices(&self) -> Vec<u32> {
        self.inner
            .rest()
            .triangles()
            .iter()
            .flatten()
            .copied()
            .collect()
    }

    /// `{ vertex, edge }` under `(ndcX, ndcY)` (y up) of a view drawn with `viewProj` (16
    /// numbers, column-major, wgpu's depth), ray-cast as `WebViewer.pick` does, or null.
    pub fn pick(&self, view_proj: &[f32], ndc_x: f32, ndc_y: f32) -> Result<JsValue, JsError> {
        let m: &[f32; 16] = view_proj
            .try_into()
            .map_err(|_| JsError::new("pick: viewProj must have 16 numbers"))?;
        match self.inner.pick(m, [ndc_x, ndc_y]) {
            None => Ok(JsValue::NULL),
            Some(p) => from_json(&serde_json::json!({ "vertex": p.vertex, "edge": p.edge })),
        }
    }

    #[wasm_bindgen(js_name = moveVertex)]
    pub fn move_vertex(&mut self, index: u32, x: f32, y: f32, z: f32) -> Result<(), JsError> {
        self.inner.move_vertex(index, [x, y, z]).map_err(js)
    }

    #[wasm_bindgen(js_name = setEdgeSharpness)]
    pub fn set_edge_sharpness(&mut self, a: u32, b: u32, s: f32) -> Result<(), JsError> {
        self.inner.set_edge_sharpness(a, b, s).map_err(js)
    }

    #[wasm_bindgen(js_name = setVertexTension)]
    pub fn set_vertex_tension(&mut self, v: u32, tension: f32, bias: f32) -> Result<(), JsError> {
        self.inner.set_vertex_tension(v, tension, bias).map_err(js)
    }

    #[wasm_bindgen(js_name = tagsJson)]
    pub fn tags_json(&self) -> String {
        self.inner.tags_json()
    }

    /// The first panel's refined mesh as drawn (pose, tags), as GLB.
    #[wasm_bindgen(js_name = exportGlb)]
    pub fn export_glb(&self) -> Result<Vec<u8>, JsError> {
        self.inner.export_glb().map_err(js)
    }

    /// The loaded file's clips (`[]`: none).
    pub fn clips(&self) -> Vec<String> {
        self.inner.clips()
    }

    /// The playing clip's duration, seconds (0 without one).
    pub fn duration(&self) -> f32 {
        self.inner.duration()
    }

    /// Why the last clip pose was refused, or `undefined`.
    #[wasm_bindgen(js_name = poseError)]
    pub fn pose_error(&self) -> Option<String> {
        self.inner.pose_error().map(str::to_string)
    }
}
