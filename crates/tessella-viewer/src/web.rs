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
        crate::viewer::sample_names()
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
