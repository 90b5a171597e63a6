//! One evaluator interface for every backend: given a [`Plan`] (built once) and a [`Frame`]
//! (this frame's control nets), write the frame's refined vertices into memory the caller
//! owns. The CPU writes into slices ([`CpuEvaluator`]); the GPU crate's evaluator writes into
//! `wgpu` buffers and keeps its own buffers between frames. OpenSubdiv's `CpuEvaluator` /
//! `GLComputeEvaluator` pair is the model.

use super::output::VertexOutput;
use crate::error::RefineError;
use crate::refine::plan::surface::Frame;
use crate::refine::plan::table::Plan;

/// A backend that evaluates frames of a plan.
pub trait Evaluator {
    /// Where this backend writes one frame's vertices.
    type Output<'a>;
    /// What can go wrong (planning errors included).
    type Error: From<RefineError>;

    /// Writes every refined vertex of `frame` (same layout as [`Plan`] documents) into `out`.
    /// Only the frame's nets depend on the frame: everything else comes from `plan`.
    fn evaluate(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        out: Self::Output<'_>,
    ) -> Result<(), Self::Error>;
}

/// The CPU evaluator: all cores, into caller-owned slices (separate or interleaved).
///
/// ```
/// use tessella_core::refine::{CpuEvaluator, Evaluator, Plan, VertexFormat, VertexOutput};
/// use tessella_core::{samples, RefineOptions, Scheme};
/// let mesh = samples::icosphere(0);
/// let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
/// let frame = plan.frame(&mesh)?;
/// let format = VertexFormat::POSITION_NORMAL;
/// let mut vertex_buffer = vec![0.0f32; plan.vertex_count() * format.stride];
/// CpuEvaluator.evaluate(&plan, &frame, VertexOutput::Interleaved { data: &mut vertex_buffer, format })?;
/// assert_eq!(&vertex_buffer[..3], &mesh.positions()[0]); // corners are exact
/// # Ok::<(), tessella_core::RefineError>(())
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct CpuEvaluator;

impl Evaluator for CpuEvaluator {
    type Output<'a> = VertexOutput<'a>;
    type Error = RefineError;

    fn evaluate(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        out: VertexOutput<'_>,
    ) -> Result<(), RefineError> {
        plan.evaluate(frame, out)
    }
}
