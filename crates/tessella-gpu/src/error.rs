//! The GPU crate's one error type.

use thiserror::Error;

/// What went wrong on the GPU side. Every message says what to do about it.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GpuError {
    #[error(
        "no {wanted} GPU adapter found; install a Vulkan/Metal/DX12 driver (for a software \
         adapter on Linux: apt-get install mesa-vulkan-drivers libvulkan1) or use the CPU backend"
    )]
    NoAdapter { wanted: &'static str },
    #[error("the GPU adapter '{adapter}' refused to open a device: {reason}")]
    RequestDevice { adapter: String, reason: String },
    #[error("the GPU device was lost ({reason}); retry, or use the CPU backend")]
    DeviceLost { reason: String },
    #[error(
        "the GPU rejected the work: {0}; if no buffer of yours was involved, this is a bug in \
         tessella-gpu, please report it"
    )]
    Validation(String),
    #[error(
        "the GPU ran out of memory: {0}; use a lower level, fewer triangles or the CPU backend"
    )]
    OutOfMemory(String),
    #[error("the output buffer cannot take this frame: {0}")]
    BadOutput(String),
    #[error("reading GPU results back failed: {0}")]
    Readback(String),
    #[error(
        "{what} needs {bytes} bytes in one GPU buffer binding, over this adapter's limit of \
         {limit}; use fewer coarse triangles or the CPU backend"
    )]
    TooLarge {
        what: &'static str,
        bytes: u64,
        limit: u64,
    },
    #[error(
        "{what} needs {needed} in the {stage} stage for the device limit `{limit}`, and this \
         device allows {allowed}; open the device with higher limits, or use the CPU backend"
    )]
    Limit {
        what: &'static str,
        stage: &'static str,
        limit: &'static str,
        needed: u64,
        allowed: u64,
    },
    #[error(
        "{what} reads storage buffers in the vertex stage, and this device has none there \
         (its adapter lacks wgpu::DownlevelFlags::VERTEX_STORAGE, as WebGL2 and GL ES 3.0 do); \
         the GPU evaluator's compute path still works on it (GpuEvaluator, gpu_refine), or use \
         the CPU backend"
    )]
    NoVertexStorage { what: &'static str },
    #[error("invalid render option: {0}")]
    BadOption(String),
    #[error(
        "GPU skinning needs normals, and an instance of this animated mesh has none; pose it \
         on the CPU (Poser::mesh), where tessella_core::Mesh computes them"
    )]
    SkinNeedsNormals,
    #[error(transparent)]
    Animation(#[from] tessella_core::AnimationError),
    #[error(transparent)]
    Refine(#[from] tessella_core::RefineError),
    #[error(transparent)]
    Displace(#[from] tessella_core::DisplaceError),
    #[error("writing '{path}' failed: {reason}")]
    Write { path: String, reason: String },
}
