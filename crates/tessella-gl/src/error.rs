//! Errors of the GL backend: a missing driver names what is missing and which packages provide
//! it; shader and GL failures carry the driver's own log.

use thiserror::Error;

/// Debian/Ubuntu packages that provide a headless OpenGL 4 driver (Mesa's llvmpipe in software).
pub const DRIVER_PACKAGES: &str = "libegl1 libegl-mesa0 libgl1-mesa-dri";

/// Why the GL backend could not do its work.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum GlError {
    /// No usable EGL / OpenGL 4 driver: `what` says which piece is missing.
    #[error(
        "no OpenGL 4 driver for the GL backend: {what}. Install an EGL driver with OpenGL 4.3+ \
         (Debian/Ubuntu: apt-get install {DRIVER_PACKAGES}; Mesa's llvmpipe runs without a GPU), \
         or use --backend cpu"
    )]
    NoDriver { what: String },
    /// A shader did not compile.
    #[error("the GL driver rejected the {stage} shader:\n{log}")]
    Compile { stage: &'static str, log: String },
    /// The program did not link.
    #[error("the GL driver could not link the tessellation program:\n{log}")]
    Link { log: String },
    /// A GL call reported an error.
    #[error("GL error 0x{code:04x} ({name}) after {call}")]
    Gl {
        call: &'static str,
        code: u32,
        name: &'static str,
    },
    /// The hardware wrote something other than what the plan expects.
    #[error("the GL tessellator wrote {got} triangles where {expected} were expected")]
    Count { got: u64, expected: u64 },
    /// Options the GL backend cannot run.
    #[error("{0}")]
    Unsupported(String),
    /// The options or the mesh were refused by tessella-core.
    #[error(transparent)]
    Refine(#[from] tessella_core::RefineError),
}
