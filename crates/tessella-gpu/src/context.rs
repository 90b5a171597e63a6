//! Device setup, kept apart from the GPU work so callers and tests open one device and reuse it.

use crate::error::GpuError;
use std::sync::{Arc, Mutex, OnceLock};

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
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// First uncaptured error or loss reported by the device, turned into a `GpuError` by
    /// [`GpuContext::check`] (wgpu's default handler would panic).
    fault: Arc<Mutex<Option<GpuError>>>,
    refine_pipelines: OnceLock<crate::compute::Pipelines>,
    render_pipelines: OnceLock<crate::render::Pipelines>,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter_label())
            .finish()
    }
}

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
        let supported = adapter.limits();
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: supported.max_storage_buffer_binding_size,
            max_buffer_size: supported.max_buffer_size,
            max_storage_buffers_per_shader_stage: supported
                .max_storage_buffers_per_shader_stage
                .min(16),
            ..wgpu::Limits::default()
        };
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
        Ok(GpuContext {
            device,
            queue,
            info,
            limits,
            fault,
            refine_pipelines: OnceLock::new(),
            render_pipelines: OnceLock::new(),
        })
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

    /// The compute kernels, compiled on first use.
    pub(crate) fn refine_pipelines(&self) -> &crate::compute::Pipelines {
        self.refine_pipelines
            .get_or_init(|| crate::compute::Pipelines::new(self))
    }

    /// The render pipelines, compiled on first use.
    pub(crate) fn render_pipelines(&self) -> &crate::render::Pipelines {
        self.render_pipelines
            .get_or_init(|| crate::render::Pipelines::new(self))
    }

    /// Returns the first error the device reported since the last call, if any.
    pub fn check(&self) -> Result<(), GpuError> {
        let mut slot = self.fault.lock().unwrap_or_else(|p| p.into_inner());
        match slot.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Submits `encoder` and blocks until the GPU has finished it.
    pub(crate) fn submit_and_wait(&self, encoder: wgpu::CommandEncoder) -> Result<(), GpuError> {
        let index = self.queue.submit([encoder.finish()]);
        // A rejected submission shows up as a recorded error; report that, not the wait.
        self.check()?;
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

    /// Maps a MAP_READ buffer and copies it out.
    pub(crate) fn map_and_copy(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
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

    /// A buffer initialised from `contents`: the one place buffers with data are made.
    pub(crate) fn buffer_init(
        &self,
        label: &str,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
    }

    /// A storage buffer initialised from `data` (at least 4 bytes: empty bindings are invalid).
    pub(crate) fn storage_buffer(
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
