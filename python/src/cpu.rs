//! What the backends of both builds share (`gpu.rs`, and `cpu_only.rs` without the `gpu`
//! feature): the outcome of a refinement, and the CPU path.

use tessella_core::{DisplaceError, DisplaceFrame, Displacement, RefinedMesh, Refiner};

/// A refined mesh, and a note to raise as a warning when `"auto"` fell back from a failing GPU
/// (never in a build without the `gpu` feature).
pub struct Outcome {
    pub mesh: RefinedMesh,
    pub fallback: Option<String>,
}

/// Refines on the CPU, then applies `displacement` (the reference the GPU path is tested
/// against). The caller turns the displacement's error into the exception of its build.
pub fn refine(
    refiner: &Refiner,
    displacement: &Displacement,
) -> Result<RefinedMesh, DisplaceError> {
    let mut mesh = crate::pool::refine(refiner);
    if displacement.is_some() {
        let frame = DisplaceFrame::new(refiner.mesh(), refiner.topology(), refiner.layout());
        displacement.apply(&mut mesh, &frame)?;
    }
    Ok(mesh)
}
