//! `backend="gl"`: the OpenGL 4 tessellation stages through tessella-gl (the CLI's
//! `refine --backend gl`), with a tessellator spacing; the output is an unwelded soup
//! (vertex `3t + i` is corner `i` of triangle `t`), as the CLI writes it. A GL context belongs
//! to one thread, so each call makes its own (tens of milliseconds on llvmpipe).

use crate::errors::bad_option;
use pyo3::PyResult;
use tessella_core::{Mesh, RefineOptions, RefinedMesh};

/// What `backend="gl"` with the grid spacing (`tessella.refine`'s whole-level path) raises.
pub const GL_NEEDS_SPACING: &str = "backend=\"gl\" runs the hardware tessellator, whose \
     patterns are not the grid pattern: give spacing=\"equal\", \"fractional-odd\" or \
     \"fractional-even\" (and level= or lod=)";

/// Refines `mesh` on the GL tessellator.
#[cfg(feature = "gl")]
pub fn refine(mesh: &Mesh, options: &RefineOptions) -> PyResult<RefinedMesh> {
    use tessella_gl::{GlContext, GlError, GlTessellator};
    let err = |e: GlError| match e {
        GlError::Unsupported(_) => bad_option(e.to_string()),
        GlError::Refine(e) => crate::errors::refine_error(e),
        _ => crate::errors::gpu_failure(e.to_string()),
    };
    // Refuse the grid before looking for a driver: the message is about the options.
    tessella_gl::hardware_spacing(options).map_err(|_| bad_option(GL_NEEDS_SPACING))?;
    let ctx = GlContext::new().map_err(err)?;
    let mut gl = GlTessellator::new(&ctx).map_err(err)?;
    Ok(gl.refine(mesh, options, None).map_err(err)?.to_mesh())
}

/// Whether `backend="gl"` can run here: an OpenGL 4.3 context opens (made and dropped).
#[cfg(feature = "gl")]
pub fn available() -> bool {
    tessella_gl::GlContext::new().is_ok()
}

/// Without the `gl` feature: never.
#[cfg(not(feature = "gl"))]
pub fn available() -> bool {
    false
}

/// What `backend="gl"` raises in a build without the `gl` feature.
#[cfg(not(feature = "gl"))]
pub const NO_GL_FEATURE: &str = "this tessella package was built without OpenGL support (the \
     \"gl\" cargo feature is off); use backend=\"cpu\", or rebuild with the default features";

/// Without the `gl` feature: a `ValueError`.
#[cfg(not(feature = "gl"))]
pub fn refine(_mesh: &Mesh, _options: &RefineOptions) -> PyResult<RefinedMesh> {
    Err(bad_option(NO_GL_FEATURE))
}
