//! Device setup, kept apart from the GPU work so callers and tests open one device and reuse it.

use crate::error::GpuError;
use crate::pipeline_cache::PipelineCache;
use std::future::Future;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Waker};

/// Storage buffers the compute path binds in one shader stage: within WebGPU's default of 8.
pub const COMPUTE_STORAGE_BUFFERS: u32 = 8;

/// An error scope popped but not answered yet (on the web the answer is a promise).
#[cfg(not(target_arch = "wasm32"))]
type ScopeAnswer = Pin<Box<dyn Future<Output = Option<wgpu::Error>> + Send>>;
#[cfg(target_arch = "wasm32")]
type ScopeAnswer = Pin<Box<dyn Future<Output = Option<wgpu::Error>>>>;

/// How long a native read-back waits for its map after the device went idle.
#[cfg(not(target_arch = "wasm32"))]
const MAP_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(30);

/// Polls `future` once: native wgpu answers error scopes and finished maps at once, the web
/// later.
fn poll_now<F: Future + ?Sized>(future: Pin<&mut F>) -> Option<F::Output> {
    match future.poll(&mut Context::from_waker(Waker::noop())) {
        Poll::Ready(value) => Some(value),
        Poll::Pending => None,
    }
}

/// Which adapter [`GpuContext::new`] asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum AdapterChoice {
    /// A hardware adapter when there is one, otherwise a software one (lavapipe, WARP, ...).
    #[default]
    Auto,
    /// Hardware only: [`GpuError::NoAdapter`] when there is none.
    Hardware,
    /// A software (CPU) adapter only: deterministic, for tests.
    Software,
}

/// An open device and queue, plus what the work needs to know about the adapter.
///
/// Cheap to clone (wgpu's device and queue are handles); clones share the error slot and the
/// compiled pipelines: a second renderer or evaluator of the same kind reuses the first one's
/// ([`GpuContext::cached_pipelines`]).
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// The adapter's downlevel capabilities where known: [`GpuContext::new`] reads them from
    /// its adapter; after [`GpuContext::from_device`] they are unknown (the device is taken to
    /// be WebGPU-compliant) until [`GpuContext::with_downlevel`] gives them.
    downlevel: Option<wgpu::DownlevelCapabilities>,
    /// The adapter the device came from, when tessella opened it (for a surface's formats).
    adapter: Option<wgpu::Adapter>,
    /// First error tessella met outside an error scope (a buffer it could not fill) or, on a
    /// device tessella opened itself, an uncaptured error or loss; taken by
    /// [`GpuContext::check`].
    fault: Arc<Mutex<Option<GpuError>>>,
    /// Error scopes of tessella's calls whose answer had not come when the call returned (on
    /// the web): [`GpuContext::check`] / [`GpuContext::check_async`] take them.
    pending: Arc<Mutex<Vec<(ErrorKind, ScopeAnswer)>>>,
    /// The pipelines compiled on this device, by kind and variant.
    pipelines: Arc<PipelineCache>,
}

/// Which scope an answer belongs to.
#[derive(Debug, Clone, Copy)]
enum ErrorKind {
    Validation,
    OutOfMemory,
}

impl ErrorKind {
    fn error(self, e: wgpu::Error) -> GpuError {
        match self {
            ErrorKind::Validation => GpuError::Validation(e.to_string()),
            ErrorKind::OutOfMemory => GpuError::OutOfMemory(e.to_string()),
        }
    }
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter_label())
            .finish()
    }
}

/// Keeps the adapter probe from printing on machines without a display.
///
/// wgpu enables every Vulkan surface extension the loader offers, Wayland's included; Mesa's
/// implicit device-selection layer (`VK_LAYER_MESA_device_select`) then connects to the Wayland
/// display to order the adapters, and libwayland prints `error: XDG_RUNTIME_DIR is invalid or
/// not set in the environment.` twice per probe when there is no session. That layer only
/// reorders adapters, which [`GpuContext::new`] ranks itself, so when `XDG_RUNTIME_DIR` is unset
/// (no Wayland session can exist) the layer is switched off with its documented
/// `NODEVICE_SELECT=1`, once, before the first instance is created. Set `NODEVICE_SELECT`
/// yourself (to anything) to keep this from happening.
#[cfg(not(target_arch = "wasm32"))]
fn quiet_probe() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("XDG_RUNTIME_DIR").is_none()
            && std::env::var_os("NODEVICE_SELECT").is_none()
        {
            std::env::set_var("NODEVICE_SELECT", "1");
        }
    });
}

/// A read-only storage buffer binding (see [`GpuContext::buffer_layout`]).
pub const READ: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };
/// A read-write storage buffer binding.
pub const WRITE: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: false };
/// A uniform buffer binding.
pub const UNIFORM: wgpu::BufferBindingType = wgpu::BufferBindingType::Uniform;

impl GpuContext {
    /// Opens a device on the chosen kind of adapter.
    ///
    /// ```no_run
    /// use tessella_gpu::{AdapterChoice, GpuContext};
    /// match GpuContext::new(AdapterChoice::Auto) {
    ///     Ok(ctx) => println!("using {}", ctx.adapter_label()),
    ///     Err(e) => eprintln!("{e}"),
    /// }
    /// ```
    #[cfg(feature = "blocking")]
    pub fn new(choice: AdapterChoice) -> Result<GpuContext, GpuError> {
        pollster::block_on(Self::new_async(choice))
    }

    /// [`GpuContext::new`] without blocking: the form for the web (where the page's thread may
    /// not wait), and for native callers with an executor of their own.
    pub async fn new_async(choice: AdapterChoice) -> Result<GpuContext, GpuError> {
        #[cfg(not(target_arch = "wasm32"))]
        quiet_probe();
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        Self::for_surface_async(&instance, None, choice).await
    }

    /// [`GpuContext::new_async`] on the caller's `instance`, choosing among the adapters that
    /// can present to `surface` when one is given (a window's, a canvas's: the surface and the
    /// device must come from the same instance).
    pub async fn for_surface_async(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
        choice: AdapterChoice,
    ) -> Result<GpuContext, GpuError> {
        let adapters = candidate_adapters(instance, surface).await;
        let is_software = |a: &wgpu::Adapter| a.get_info().device_type == wgpu::DeviceType::Cpu;
        let rank = |a: &wgpu::Adapter| match a.get_info().device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu | wgpu::DeviceType::Other => 2,
            wgpu::DeviceType::Cpu => 3,
        };
        let mut candidates: Vec<wgpu::Adapter> = adapters
            .into_iter()
            .filter(|a| match choice {
                AdapterChoice::Auto => true,
                AdapterChoice::Hardware => !is_software(a),
                AdapterChoice::Software => is_software(a),
            })
            .collect();
        candidates.sort_by_key(|a| rank(a));
        let adapter = candidates.into_iter().next().ok_or(GpuError::NoAdapter {
            wanted: match choice {
                AdapterChoice::Auto => "usable",
                AdapterChoice::Hardware => "hardware",
                AdapterChoice::Software => "software",
            },
        })?;
        let info = adapter.get_info();
        // Ask for the adapter's own buffer limits: the defaults (128 MiB bindings) are often
        // lower than what the hardware allows, and larger bindings mean fewer chunks.
        let limits = GpuContext::required_limits(&adapter.limits());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tessella"),
                required_features: wgpu::Features::empty(),
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::RequestDevice {
                adapter: info.name.clone(),
                reason: e.to_string(),
            })?;
        // The device is tessella's own: its uncaptured errors and loss are recorded here (wgpu's
        // default handler would panic), and returned by `check`.
        let mut ctx = GpuContext::from_device(device, queue)
            .with_downlevel(adapter.get_downlevel_capabilities());
        ctx.adapter = Some(adapter);
        let sink = ctx.fault.clone();
        ctx.device
            .on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(GpuError::Validation(e.to_string()));
            }));
        let sink = ctx.fault.clone();
        ctx.device.set_device_lost_callback(move |reason, message| {
            let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
            slot.get_or_insert(GpuError::DeviceLost {
                reason: format!("{reason:?}: {message}"),
            });
        });
        Ok(ctx)
    }

    /// The limits to request when opening a device for tessella: WebGPU's defaults (which
    /// every path works within), raised to the adapter's own buffer sizes (larger bindings
    /// mean fewer chunks). An engine may open its device with WebGPU's defaults instead.
    ///
    /// ```no_run
    /// # async fn open(adapter: wgpu::Adapter) {
    /// let limits = tessella_gpu::GpuContext::required_limits(&adapter.limits());
    /// let (device, queue) = adapter
    ///     .request_device(&wgpu::DeviceDescriptor { required_limits: limits, ..Default::default() })
    ///     .await
    ///     .unwrap();
    /// let ctx = tessella_gpu::GpuContext::from_device(device, queue);
    /// # }
    /// ```
    pub fn required_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
        wgpu::Limits {
            max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
            max_buffer_size: adapter.max_buffer_size,
            ..wgpu::Limits::default()
        }
    }

    /// Wraps a device and queue the caller opened (an engine's own), so tessella's evaluator
    /// and renderers work on the caller's resources. The caller's uncaptured-error handler and
    /// device-lost callback are left alone: tessella's own errors reach its calls through
    /// error scopes and returned `Result`s, and errors in the caller's work stay the caller's.
    ///
    /// The work sizes its chunks from `device.limits()`; tessella needs no optional features,
    /// and works within WebGPU's default limits (see [`GpuContext::check`]).
    // On wasm32 the pending scope answers are JS promises (not `Send`): one thread there.
    #[cfg_attr(target_arch = "wasm32", allow(clippy::arc_with_non_send_sync))]
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> GpuContext {
        GpuContext {
            info: device.adapter_info(),
            limits: device.limits(),
            downlevel: None,
            adapter: None,
            device,
            queue,
            fault: Arc::new(Mutex::new(None)),
            pending: Arc::new(Mutex::new(Vec::new())),
            pipelines: Arc::new(PipelineCache::default()),
        }
    }

    /// Tells tessella the downlevel capabilities of the adapter the caller's device came from
    /// (`adapter.get_downlevel_capabilities()`), so that a device without storage buffers in
    /// the vertex stage (WebGL2, GL ES 3.0: no `wgpu::DownlevelFlags::VERTEX_STORAGE`) has the
    /// renderers refused up front with [`GpuError::NoVertexStorage`] instead of failing when
    /// their pipelines are made. The compute path ([`crate::GpuEvaluator`]) does not need it.
    ///
    /// ```no_run
    /// # async fn open(adapter: wgpu::Adapter) {
    /// let limits = tessella_gpu::GpuContext::required_limits(&adapter.limits());
    /// let (device, queue) = adapter
    ///     .request_device(&wgpu::DeviceDescriptor { required_limits: limits, ..Default::default() })
    ///     .await
    ///     .unwrap();
    /// let ctx = tessella_gpu::GpuContext::from_device(device, queue)
    ///     .with_downlevel(adapter.get_downlevel_capabilities());
    /// # }
    /// ```
    pub fn with_downlevel(mut self, caps: wgpu::DownlevelCapabilities) -> GpuContext {
        self.downlevel = Some(caps);
        self
    }

    /// The adapter of a device tessella opened ([`GpuContext::new`],
    /// [`GpuContext::for_surface_async`]); `None` after [`GpuContext::from_device`]. A surface
    /// asks it for its formats (`wgpu::Surface::get_default_config`).
    pub fn adapter(&self) -> Option<&wgpu::Adapter> {
        self.adapter.as_ref()
    }

    /// The downlevel capabilities tessella checks against, where known
    /// ([`GpuContext::with_downlevel`]).
    pub fn downlevel(&self) -> Option<&wgpu::DownlevelCapabilities> {
        self.downlevel.as_ref()
    }

    /// Refuses a device that allows fewer storage buffers in a shader stage than a path binds:
    /// `what` names the path, `stage` the stage.
    pub(crate) fn check_storage_buffers(
        &self,
        what: &'static str,
        stage: &'static str,
        needed: u32,
    ) -> Result<(), GpuError> {
        // wgpu 30 has one limit for every stage; storage buffers in the vertex stage are a
        // downlevel flag of the adapter.
        let vertex = wgpu::DownlevelFlags::VERTEX_STORAGE;
        if stage == "vertex"
            && self
                .downlevel
                .as_ref()
                .is_some_and(|d| !d.flags.contains(vertex))
        {
            return Err(GpuError::NoVertexStorage { what });
        }
        let allowed = self.limits.max_storage_buffers_per_shader_stage;
        if allowed < needed {
            return Err(GpuError::Limit {
                what,
                stage,
                limit: "max_storage_buffers_per_shader_stage",
                needed: needed as u64,
                allowed: allowed as u64,
            });
        }
        Ok(())
    }

    /// `true` for software adapters (lavapipe, WARP, SwiftShader): correct but slow.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// A context on the same device whose errors are its own: the errors and unanswered
    /// error scopes of tessella's calls through it are not seen by this context's
    /// [`GpuContext::check`], nor this one's by it. For work that runs beside other work on one
    /// device (a benchmark beside a viewer's frames), so each failure is reported to its own
    /// caller. The device's uncaptured errors and loss still go to this context.
    pub fn with_own_errors(&self) -> GpuContext {
        GpuContext {
            fault: Arc::new(Mutex::new(None)),
            pending: Arc::new(Mutex::new(Vec::new())),
            ..self.clone()
        }
    }

    /// How many pipeline bundles this context's device has compiled and keeps (one per kind of
    /// renderer or evaluator and variant: normal mode, displacement, target formats, ...).
    pub fn cached_pipelines(&self) -> usize {
        self.pipelines.len()
    }

    /// The bundle of pipelines stored under `key`, compiled by `make` the first time inside
    /// error scopes of its own ([`GpuContext::scoped`]): a bundle that did not compile (a
    /// caller's shading with broken WGSL) is an error and is not kept. On the web, where the
    /// scopes answer later, a broken bundle is reported by [`GpuContext::check_async`] and kept.
    pub(crate) fn pipelines<T>(&self, key: &str, make: impl FnOnce() -> T) -> Result<T, GpuError>
    where
        T: Clone + wgpu::WasmNotSendSync + 'static,
    {
        self.pipelines.get_or_try_insert(key, || self.scoped(make))
    }

    /// "name (backend)", with "software" added for CPU adapters: the label for benchmark rows.
    /// Browsers may keep the name to themselves (an empty description): "unnamed adapter".
    pub fn adapter_label(&self) -> String {
        let name = self.info.name.trim();
        format!(
            "{} ({:?}{})",
            if name.is_empty() {
                "unnamed adapter"
            } else {
                name
            },
            self.info.backend,
            if self.is_software() { ", software" } else { "" }
        )
    }

    /// Largest byte size of one storage-buffer binding.
    pub fn max_binding(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    /// Returns the first error of tessella's calls since the last check, if any: one recorded
    /// outside a scope, or one an error scope answered after its call returned (the web).
    /// Scopes not answered yet stay for the next check ([`GpuContext::check_async`] awaits
    /// them).
    pub fn check(&self) -> Result<(), GpuError> {
        let mut first = None;
        {
            let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
            pending.retain_mut(|(kind, answer)| match poll_now(answer.as_mut()) {
                Some(found) => {
                    if let Some(e) = found {
                        first.get_or_insert(kind.error(e));
                    }
                    false
                }
                None => true,
            });
        }
        let mut slot = self.fault.lock().unwrap_or_else(|p| p.into_inner());
        match slot.take().or(first) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// [`GpuContext::check`] that first awaits every error scope of tessella's calls not
    /// answered yet: on the web, the way to learn whether a frame's work was accepted.
    pub async fn check_async(&self) -> Result<(), GpuError> {
        let answers: Vec<(ErrorKind, ScopeAnswer)> = {
            let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
            pending.drain(..).collect()
        };
        let mut first = None;
        for (kind, answer) in answers {
            if let Some(e) = answer.await {
                first.get_or_insert(kind.error(e));
            }
        }
        self.check()?;
        first.map_or(Ok(()), Err)
    }

    /// Runs `f` (which creates resources, records or submits work) inside validation and
    /// out-of-memory error scopes of its own, and returns the first error either caught, or
    /// one tessella recorded meanwhile. Never blocks: native wgpu answers the scopes at once;
    /// on the web the answers come later and [`GpuContext::check_async`] returns them. Errors
    /// of work outside `f` (the caller's own) do not enter these scopes.
    pub fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        let answers = [
            (
                ErrorKind::Validation,
                Box::pin(validation.pop()) as ScopeAnswer,
            ),
            (
                ErrorKind::OutOfMemory,
                Box::pin(memory.pop()) as ScopeAnswer,
            ),
        ];
        let mut first = None;
        for (kind, mut answer) in answers {
            match poll_now(answer.as_mut()) {
                Some(found) => {
                    if let Some(e) = found {
                        first.get_or_insert(kind.error(e));
                    }
                }
                None => self
                    .pending
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push((kind, answer)),
            }
        }
        if let Some(e) = first {
            return Err(e);
        }
        self.check()?;
        Ok(value)
    }

    /// Finishes and submits `encoder` inside error scopes, without waiting for the GPU.
    pub fn submit(&self, encoder: wgpu::CommandEncoder) -> Result<wgpu::SubmissionIndex, GpuError> {
        self.scoped(|| self.queue.submit([encoder.finish()]))
    }

    /// Finishes and submits `encoder`, then blocks until the GPU has finished it. Any error
    /// wgpu reports for the commands (or reported earlier and not yet taken by
    /// [`GpuContext::check`]) is returned: a rejected frame is an `Err`, never a blank `Ok`.
    #[cfg(feature = "blocking")]
    pub fn submit_and_wait(&self, encoder: wgpu::CommandEncoder) -> Result<(), GpuError> {
        let index = self.submit(encoder)?;
        self.wait(index)
    }

    /// Blocks until the GPU has finished submission `index`, then returns any error wgpu
    /// reported ([`GpuContext::check`]).
    #[cfg(feature = "blocking")]
    fn wait(&self, index: wgpu::SubmissionIndex) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map_err(|e| GpuError::DeviceLost {
                reason: e.to_string(),
            })?;
        self.check()
    }

    /// Maps a `MAP_READ` buffer (after its copy was submitted) and copies it out; blocks
    /// until the GPU is done.
    #[cfg(feature = "blocking")]
    pub fn map_and_copy(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let mut mapped = std::pin::pin!(self.map_and_copy_async(staging));
        // The first poll requests the map (an async body runs only when polled)...
        if let Some(done) = poll_now(mapped.as_mut()) {
            return done;
        }
        // ...the device's work completes it. Another thread polling the same device may be the
        // one that runs the map's callback, a moment after our own poll returned: poll again
        // until the map is done, within a bound.
        let start = std::time::Instant::now();
        loop {
            self.device
                .poll(wgpu::PollType::Wait {
                    submission_index: None,
                    timeout: None,
                })
                .map_err(|e| GpuError::DeviceLost {
                    reason: e.to_string(),
                })?;
            if let Some(done) = poll_now(mapped.as_mut()) {
                return done;
            }
            if start.elapsed() > MAP_TIMEOUT {
                return Err(GpuError::Readback(format!(
                    "the buffer was not mapped {} s after the device finished its work",
                    MAP_TIMEOUT.as_secs()
                )));
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    /// [`GpuContext::map_and_copy`] without blocking. On the web the browser completes the
    /// map; on native the caller's loop must poll the device (`device.poll(PollType::Poll)`)
    /// for it to complete.
    pub async fn map_and_copy_async(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let done = MapDone::default();
        let sink = done.clone();
        staging.map_async(wgpu::MapMode::Read, .., move |r| sink.finish(r));
        done.await.map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = take_mapped(staging)?;
        self.check()?;
        Ok(bytes)
    }

    /// Resolves once the GPU has finished every submission made so far, then returns any error
    /// those submissions met. On the web the browser answers (the page's thread is never
    /// blocked); natively this drives the device itself and so waits, which lets one async
    /// body (a benchmark, say) run the same in a browser and under a native blocking executor.
    pub async fn work_done_async(&self) -> Result<(), GpuError> {
        let done = MapDone::default();
        let sink = done.clone();
        self.queue
            .on_submitted_work_done(move || sink.finish(Ok(())));
        self.drive(&done)?;
        done.await.map_err(|e| GpuError::Readback(e.to_string()))?;
        self.check_async().await
    }

    /// [`GpuContext::map_and_copy_async`] that natively drives the device until the map is
    /// done (waiting, as [`GpuContext::work_done_async`] does); on the web the same as it.
    pub async fn map_and_copy_driven_async(
        &self,
        staging: &wgpu::Buffer,
    ) -> Result<Vec<u8>, GpuError> {
        let done = MapDone::default();
        let sink = done.clone();
        staging.map_async(wgpu::MapMode::Read, .., move |r| sink.finish(r));
        self.drive(&done)?;
        done.await.map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = take_mapped(staging)?;
        self.check_async().await?;
        Ok(bytes)
    }

    /// Natively, polls the device until `done`'s callback has run (another thread polling
    /// the same device may be the one that runs it, just after our poll returns: poll again,
    /// within a bound). On the web the browser runs callbacks: nothing to do.
    #[cfg(not(target_arch = "wasm32"))]
    fn drive(&self, done: &MapDone) -> Result<(), GpuError> {
        let start = std::time::Instant::now();
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::DeviceLost {
                reason: e.to_string(),
            })?;
        while !done.is_finished() {
            if start.elapsed() > MAP_TIMEOUT {
                return Err(GpuError::Readback(format!(
                    "the device's callback did not run {} s after its work finished",
                    MAP_TIMEOUT.as_secs()
                )));
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
            self.device
                .poll(wgpu::PollType::Poll)
                .map_err(|e| GpuError::DeviceLost {
                    reason: e.to_string(),
                })?;
        }
        Ok(())
    }

    #[cfg(target_arch = "wasm32")]
    fn drive(&self, _done: &MapDone) -> Result<(), GpuError> {
        Ok(())
    }

    /// Records into `encoder` a copy of `len` bytes of `buffer` (which needs `COPY_SRC`) from
    /// byte `offset` into a new staging buffer, returned for [`GpuContext::map_and_copy`] /
    /// [`GpuContext::map_and_copy_async`] once the encoder is submitted. `offset` and `len`
    /// must be multiples of 4.
    pub fn record_readback(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        buffer: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Result<wgpu::Buffer, GpuError> {
        self.scoped(|| {
            let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: len.max(4),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, len);
            staging
        })
    }

    /// Records and submits the copy of `len` bytes of `buffer` from byte `offset` into a new
    /// staging buffer ([`GpuContext::record_readback`]): the staging buffer to map once the
    /// submission is done.
    fn submit_readback(
        &self,
        buffer: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Result<(wgpu::Buffer, wgpu::SubmissionIndex), GpuError> {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let staging = self.record_readback(&mut encoder, buffer, offset, len)?;
        Ok((staging, self.submit(encoder)?))
    }

    /// Copies `len` bytes of `buffer` (which needs `COPY_SRC`) from byte `offset` back to the
    /// CPU; waits for the GPU. `offset` and `len` must be multiples of 4.
    #[cfg(feature = "blocking")]
    pub fn read_buffer(
        &self,
        buffer: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let (staging, index) = self.submit_readback(buffer, offset, len)?;
        self.wait(index)?;
        let mut bytes = self.map_and_copy(&staging)?;
        bytes.truncate(len as usize);
        Ok(bytes)
    }

    /// [`GpuContext::read_buffer`] without blocking (see [`GpuContext::map_and_copy_async`]).
    pub async fn read_buffer_async(
        &self,
        buffer: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let (staging, _submitted) = self.submit_readback(buffer, offset, len)?;
        let mut bytes = self.map_and_copy_async(&staging).await?;
        self.check_async().await?;
        bytes.truncate(len as usize);
        Ok(bytes)
    }

    /// A buffer initialised from `contents`: the one place buffers with data are made.
    pub fn buffer_init(
        &self,
        label: &str,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        // As wgpu's `create_buffer_init`, but a buffer that cannot be mapped (a lost device, a
        // size over the limits) is recorded as this context's fault, returned by the next
        // `check`/`scoped`, instead of a panic inside wgpu's helper.
        let align = wgpu::COPY_BUFFER_ALIGNMENT;
        let size = (contents.len() as u64).div_ceil(align).max(1) * align;
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: true,
        });
        match buffer.get_mapped_range_mut(..) {
            Ok(mut range) => {
                range.slice(..contents.len()).copy_from_slice(contents);
                drop(range);
                buffer.unmap();
            }
            Err(e) => {
                let mut slot = self.fault.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(GpuError::Validation(format!(
                    "buffer '{label}' ({size} bytes) could not be filled (is the device lost?): {e}"
                )));
            }
        }
        buffer
    }

    /// A bind group layout of buffers only, binding `i` being `entries[i]`: the stages that
    /// see it and its kind ([`READ`], [`WRITE`], [`UNIFORM`]).
    pub fn buffer_layout(
        &self,
        label: &str,
        entries: &[(wgpu::ShaderStages, wgpu::BufferBindingType)],
    ) -> wgpu::BindGroupLayout {
        let entries: Vec<_> = entries
            .iter()
            .enumerate()
            .map(|(i, &(visibility, ty))| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility,
                ty: wgpu::BindingType::Buffer {
                    ty,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        self.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
    }

    /// A bind group of whole buffers, binding `i` being `buffers[i]`.
    pub fn buffer_group(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &entries,
        })
    }

    /// A storage buffer initialised from `data` (at least 4 bytes: empty bindings are invalid).
    pub fn storage_buffer(
        &self,
        label: &str,
        data: &[u8],
        extra: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let padded;
        let contents = if data.len() < 4 {
            padded = [0u8; 4];
            &padded[..]
        } else {
            data
        };
        self.buffer_init(label, contents, wgpu::BufferUsages::STORAGE | extra)
    }
}

/// The adapters worth ranking (those that can present to `surface`, when given): every one
/// on native, the browser's one on the web.
#[cfg(not(target_arch = "wasm32"))]
async fn candidate_adapters(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Vec<wgpu::Adapter> {
    let mut adapters = instance.enumerate_adapters(wgpu::Backends::PRIMARY).await;
    if let Some(surface) = surface {
        adapters.retain(|a| a.is_surface_supported(surface));
    }
    adapters
}

#[cfg(target_arch = "wasm32")]
async fn candidate_adapters(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Vec<wgpu::Adapter> {
    instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            compatible_surface: surface,
            ..Default::default()
        })
        .await
        .into_iter()
        .collect()
}

/// The bytes of a mapped `staging` buffer, which is then unmapped.
fn take_mapped(staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let bytes = staging
        .get_mapped_range(..)
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}

/// The answer of one `map_async`, as a future (wgpu gives a callback).
#[derive(Clone, Default)]
struct MapDone(Arc<Mutex<MapState>>);

#[derive(Default)]
struct MapState {
    result: Option<Result<(), wgpu::BufferAsyncError>>,
    waker: Option<Waker>,
}

impl MapDone {
    #[cfg(not(target_arch = "wasm32"))]
    fn is_finished(&self) -> bool {
        self.0
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .result
            .is_some()
    }

    fn finish(&self, result: Result<(), wgpu::BufferAsyncError>) {
        let mut state = self.0.lock().unwrap_or_else(|p| p.into_inner());
        state.result = Some(result);
        if let Some(waker) = state.waker.take() {
            waker.wake();
        }
    }
}

impl Future for MapDone {
    type Output = Result<(), wgpu::BufferAsyncError>;
    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let mut state = self.0.lock().unwrap_or_else(|p| p.into_inner());
        match state.result.take() {
            Some(result) => Poll::Ready(result),
            None => {
                state.waker = Some(cx.waker().clone());
                Poll::Pending
            }
        }
    }
}
