//! `tessella refine --backend gl`: the OpenGL 4 tessellation stages (tessella-gl), read back by
//! transform feedback. Same spacing, level, LOD and normal options as the CPU; unwelded output.

use tessella_core::{Mesh, RefineOptions, RefinedMesh};

/// Refines `mesh` with `options` on the GL tessellator (`refine` has refused what it cannot
/// do: origins, displacement).
#[cfg(feature = "gl")]
pub fn refine(mesh: &Mesh, options: &RefineOptions) -> anyhow::Result<RefinedMesh> {
    use anyhow::Context;
    // Refuse the grid before looking for a driver: the message is about the options.
    tessella_gl::hardware_spacing(options)?;
    let ctx = tessella_gl::GlContext::new()?;
    let mut gl = tessella_gl::GlTessellator::new(&ctx)?;
    let out = gl
        .refine(mesh, options, None)
        .with_context(|| format!("GL refinement on {} failed", ctx.info().renderer))?;
    for note in &out.notes {
        eprintln!("note: {note}");
    }
    Ok(out.to_mesh())
}

/// Without the `gl` feature: a clear error.
#[cfg(not(feature = "gl"))]
pub fn refine(_mesh: &Mesh, _options: &RefineOptions) -> anyhow::Result<RefinedMesh> {
    anyhow::bail!(
        "--backend gl needs the `gl` feature, and this tessella was built without it; rebuild \
         with it (cargo build -p tessella-cli --features gl)"
    )
}
