//! What several commands share about the GPU: choosing an adapter.

use crate::args::BackendArg;
use anyhow::Context;
use tessella_core::Named;
use tessella_gpu::{AdapterChoice, GpuContext};

/// The GPU context `backend` asks for, or `None` to use the CPU.
///
/// `auto` takes a hardware adapter when there is one (a software adapter is slower than the CPU
/// path) and the CPU otherwise; `gpu` takes any adapter, software included, and fails with the
/// reason when there is none.
pub fn context_for(backend: BackendArg) -> anyhow::Result<Option<GpuContext>> {
    match backend {
        // The GL backend has its own context (commands/refine_gl.rs).
        BackendArg::Cpu | BackendArg::Gl => Ok(None),
        // No hardware GPU is the ordinary case on servers: the CPU is the documented fallback,
        // so it goes quietly.
        BackendArg::Auto => Ok(GpuContext::new(AdapterChoice::Hardware).ok()),
        BackendArg::Gpu => Ok(Some(
            GpuContext::new(AdapterChoice::Auto).context("--backend gpu needs a GPU adapter")?,
        )),
        // A backend added to the core after this command was written.
        other => anyhow::bail!(
            "--backend {} is not supported by this command",
            other.name()
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
