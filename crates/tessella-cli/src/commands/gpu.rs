//! What several commands share about the GPU: choosing an adapter.

use crate::args::BackendArg;
use anyhow::Context;
use tessella_core::names::Device;
use tessella_core::Named;
use tessella_gpu::{AdapterChoice, GpuContext};

/// The GPU context `backend` asks for an output of `vertices` refined vertices (the plan's
/// count), or `None` to use the CPU: the core's one choice (`Backend::device`).
///
/// `auto` takes a hardware adapter when there is one (a software adapter is slower than the CPU
/// path) and the CPU otherwise; `gpu` takes any adapter, software included, and fails with the
/// reason when there is none.
pub fn context_for(backend: BackendArg, vertices: u64) -> anyhow::Result<Option<GpuContext>> {
    match backend.device(vertices) {
        // The GL backend has its own context (commands/refine_gl.rs).
        Device::Cpu | Device::Gl => Ok(None),
        // No hardware GPU is the ordinary case on servers: the CPU is the documented fallback,
        // so it goes quietly.
        Device::HardwareGpu => Ok(GpuContext::new(AdapterChoice::Hardware).ok()),
        Device::AnyGpu => Ok(Some(
            GpuContext::new(AdapterChoice::Auto).context("--backend gpu needs a GPU adapter")?,
        )),
        // A device added to the core after this command was written.
        other => anyhow::bail!(
            "--backend {} ({other:?}) is not supported by this command",
            backend.name()
        ),
    }
}

/// Any adapter, for pictures: a hardware GPU, else the software one.
pub fn render_context() -> anyhow::Result<GpuContext> {
    GpuContext::new(AdapterChoice::Auto).context(
        "rendering needs a GPU adapter; without a GPU install Mesa's software Vulkan driver \
         (Debian: apt-get install mesa-vulkan-drivers libvulkan1)",
    )
}
