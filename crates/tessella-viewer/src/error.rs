//! The viewer's one error type: every message says what was refused and why; the viewer's
//! state is left as it was before the call that failed.

use thiserror::Error;

#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ViewerError {
    /// A parameter's value (the message starts with its name, as the contract says).
    #[error("{name}: {message}")]
    Param { name: &'static str, message: String },
    #[error(transparent)]
    Gpu(#[from] tessella_gpu::GpuError),
    #[error(transparent)]
    Refine(#[from] tessella_core::RefineError),
    #[error(transparent)]
    Mesh(#[from] tessella_core::MeshError),
    #[error(transparent)]
    Displace(#[from] tessella_core::DisplaceError),
    #[error(transparent)]
    Io(#[from] tessella_io::IoError),
    #[error("tags: {0}")]
    Tags(String),
    /// A call that makes no sense in the viewer's state (no such sample, vertex, edge...).
    #[error("{0}")]
    Refused(String),
}

/// A bad refinement option (the core's text form) is a bad parameter of the same name.
impl From<tessella_core::refine::OptionError> for ViewerError {
    fn from(e: tessella_core::refine::OptionError) -> ViewerError {
        let name = tessella_core::refine::OPTION_KEYS
            .iter()
            .find(|(key, _)| *key == e.key)
            .map_or("options", |(key, _)| key);
        ViewerError::Param {
            name,
            message: e.message,
        }
    }
}
