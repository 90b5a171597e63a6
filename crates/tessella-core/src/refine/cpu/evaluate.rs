//! Whole-frame evaluation on the CPU: a plan's vertices for one frame (and, for
//! [`Plan::refine_into`], its triangles too), split across all cores by the uniform or the
//! adaptive job.

use super::adaptive::AdaptiveJob;
use super::output::{Sink, VertexOutput};
use super::refiner::RefinedMesh;
use super::uniform::Job;
use crate::error::RefineError;
use crate::refine::plan::surface::Frame;
use crate::refine::plan::table::Plan;

impl Plan {
    /// Writes every refined vertex of `frame` into `out` on the CPU (all cores): positions,
    /// and normals and UVs where `out` takes them. Indices are not written: they are the same
    /// for every frame ([`Plan::indices`]). On error nothing is written.
    pub fn evaluate(&self, frame: &Frame, out: VertexOutput<'_>) -> Result<(), RefineError> {
        self.evaluate_with_progress(frame, out, &|_| {})
    }

    /// [`Plan::evaluate`], calling `progress` from worker threads with numbers of coarse faces
    /// done (they add up to the face count).
    pub fn evaluate_with_progress(
        &self,
        frame: &Frame,
        out: VertexOutput<'_>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<(), RefineError> {
        self.check_frame(frame)?;
        let sink = out.sink(self.vertex_count(), self.surface.has_uvs)?;
        self.vertices(frame, sink, progress);
        Ok(())
    }

    fn vertices(&self, frame: &Frame, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        match self.adaptive_job(frame) {
            Some(job) => job.vertices(sink, progress),
            None => self.job(frame).vertices(sink, progress),
        }
    }

    pub(super) fn adaptive_job<'a>(&'a self, frame: &'a Frame) -> Option<AdaptiveJob<'a>> {
        Some(AdaptiveJob {
            mesh: &frame.mesh,
            topology: &self.surface.topology,
            tiling: self.tiling.as_ref()?,
            nets: &frame.nets,
            weld: self.layout.weld,
        })
    }

    pub(crate) fn job<'a>(&'a self, frame: &'a Frame) -> Job<'a> {
        Job {
            mesh: &frame.mesh,
            topology: &self.surface.topology,
            layout: &self.layout,
            stencil: &self.stencil,
            nets: &frame.nets,
        }
    }

    /// Refines `frame` into `out` (vertices, normals, UVs when the mesh has them, and indices),
    /// reusing its allocations when they fit. `progress` counts two units per coarse face (its
    /// vertices, its triangles): see [`Plan::progress_total`].
    pub fn refine_into(
        &self,
        frame: &Frame,
        out: &mut RefinedMesh,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<(), RefineError> {
        self.check_frame(frame)?;
        let nv = self.vertex_count();
        resize(&mut out.positions, nv);
        resize(&mut out.normals, nv);
        match self.surface.has_uvs {
            true => resize(out.uvs.get_or_insert_with(Vec::new), nv),
            false => out.uvs = None,
        }
        resize(&mut out.triangles, self.triangle_count());
        let sink = VertexOutput::Separate {
            positions: &mut out.positions,
            normals: Some(&mut out.normals),
            uvs: out.uvs.as_deref_mut(),
        }
        .sink(nv, self.surface.has_uvs)?;
        self.vertices(frame, sink, progress);
        match self.indices.get() {
            Some(cached) => {
                out.triangles.copy_from_slice(cached);
                progress(self.face_count() as u64);
            }
            None => self.write_triangles(&mut out.triangles, progress),
        }
        Ok(())
    }
}

/// Resizes `v` to `n` slots, keeping the allocation when it already fits. Slots are
/// overwritten by the caller, so their contents do not matter.
fn resize<T: Copy + Default>(v: &mut Vec<T>, n: usize) {
    if v.len() != n {
        if v.capacity() >= n {
            v.resize(n, T::default());
            v.truncate(n);
        } else {
            *v = vec![T::default(); n];
        }
    }
}
