//! Device setup, kept apart from the GPU work so callers and tests open one device and reuse it.

use crate::error::GpuError;
use std::sync::{Arc, Mutex};

/// Storage buffers the compute path binds in one shader stage; a device must allow at least
/// this many ([`GpuContext::required_limits`]).
pub const COMPUTE_STORAGE_BUFFERS: u32 = 9;

/// Which adapter [`GpuContext::new`] asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
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
/// Cheap to clone (wgpu's device and queue are handles); clones share the error slot. It knows
/// nothing of the work done with it: the evaluator and the renderer own their pipelines.
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// First uncaptured error or loss reported by the device, turned into a `GpuError` by
    /// [`GpuContext::check`] (wgpu's default handler would panic).
    fault: Arc<Mutex<Option<GpuError>>>,
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
pub(crate) const READ: wgpu::BufferBindingType =
    wgpu::BufferBindingType::Storage { read_only: true };
/// A read-write storage buffer binding.
pub(crate) const WRITE: wgpu::BufferBindingType =
    wgpu::BufferBindingType::Storage { read_only: false };
/// A uniform buffer binding.
pub(crate) const UNIFORM: wgpu::BufferBindingType = wgpu::BufferBindingType::Uniform;

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
    pub fn new(choice: AdapterChoice) -> Result<GpuContext, GpuError> {
        pollster::block_on(Self::new_async(choice))
    }

    async fn new_async(choice: AdapterChoice) -> Result<GpuContext, GpuError> {
        quiet_probe();
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapters = instance.enumerate_adapters(wgpu::Backends::PRIMARY).await;
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
        Ok(GpuContext::from_device(device, queue))
    }

    /// The limits to request when opening a device for tessella: WebGPU's defaults, raised to
    /// the adapter's own buffer sizes (larger bindings mean fewer chunks) and to the storage
    /// buffers per shader stage the compute path binds ([`COMPUTE_STORAGE_BUFFERS`], above
    /// WebGPU's default of 8). An engine opening its own device passes these (or larger).
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
            max_storage_buffers_per_shader_stage: adapter
                .max_storage_buffers_per_shader_stage
                .min(16),
            ..wgpu::Limits::default()
        }
    }

    /// Wraps a device and queue the caller opened (an engine's own), so tessella's evaluator
    /// and renderer work on the caller's resources. Installs an uncaptured-error handler and a
    /// device-lost callback that record into this context (see [`GpuContext::check`]):
    /// replace them afterwards if the caller wants its own.
    ///
    /// The work sizes its chunks from `device.limits()`; tessella needs no optional features.
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> GpuContext {
        let fault = Arc::new(Mutex::new(None));
        let sink = fault.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
            slot.get_or_insert(GpuError::Validation(e.to_string()));
        }));
        let sink = fault.clone();
        device.set_device_lost_callback(move |reason, message| {
            let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
            slot.get_or_insert(GpuError::DeviceLost {
                reason: format!("{reason:?}: {message}"),
            });
        });
        GpuContext {
            info: device.adapter_info(),
            limits: device.limits(),
            device,
            queue,
            fault,
        }
    }

    /// `true` for software adapters (lavapipe, WARP, SwiftShader): correct but slow.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// "name (backend)", with "software" added for CPU adapters: the label for benchmark rows.
    pub fn adapter_label(&self) -> String {
        format!(
            "{} ({:?}{})",
            self.info.name,
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

    /// Returns the first error the device reported since the last call, if any.
    pub fn check(&self) -> Result<(), GpuError> {
        let mut slot = self.fault.lock().unwrap_or_else(|p| p.into_inner());
        match slot.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Runs `f` (which creates resources, records or submits work) inside validation and
    /// out-of-memory error scopes, and returns the first error either caught, or one the
    /// device recorded meanwhile. Does not wait for the GPU: on native backends validation is
    /// done when the call returns.
    pub fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        let invalid = pollster::block_on(validation.pop());
        let out_of_memory = pollster::block_on(memory.pop());
        if let Some(e) = invalid {
            return Err(GpuError::Validation(e.to_string()));
        }
        if let Some(e) = out_of_memory {
            return Err(GpuError::OutOfMemory(e.to_string()));
        }
        self.check()?;
        Ok(value)
    }

    /// Finishes and submits `encoder`, then blocks until the GPU has finished it. Any error
    /// wgpu reports for the commands (or reported earlier and not yet taken by
    /// [`GpuContext::check`]) is returned: a rejected frame is an `Err`, never a blank `Ok`.
    pub fn submit_and_wait(&self, encoder: wgpu::CommandEncoder) -> Result<(), GpuError> {
        let index = self.scoped(|| self.queue.submit([encoder.finish()]))?;
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

    /// Maps a `MAP_READ` buffer (after its copy was submitted) and copies it out.
    pub fn map_and_copy(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| GpuError::DeviceLost {
                reason: e.to_string(),
            })?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = staging
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .to_vec();
        staging.unmap();
        self.check()?;
        Ok(bytes)
    }

    /// Copies `len` bytes of `buffer` (which needs `COPY_SRC`) from byte `offset` back to the
    /// CPU; waits for the GPU. `offset` and `len` must be multiples of 4.
    pub fn read_buffer(
        &self,
        buffer: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: len.max(4),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, len);
        self.submit_and_wait(encoder)?;
        let mut bytes = self.map_and_copy(&staging)?;
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
    pub(crate) fn buffer_layout(
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
    pub(crate) fn buffer_group(
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
