//! The backends under test, each behind [`Backend`]: what the suite needs from an evaluator
//! (its samples: face, barycentric point, position, normal) and what it documents about it
//! (its tolerances, which patterns it runs, whether it displaces).

use std::sync::OnceLock;
use tessella_core::displace::{DisplaceFrame, Displacement};
use tessella_core::refine::{CpuEvaluator, Evaluator, Frame, Plan, VertexFormat, VertexOutput};
use tessella_core::{RefineOptions, RefinedMesh};
use tessella_gl::{GlContext, GlEvaluator, GlRefined};
use tessella_gpu::{
    AdapterChoice, GpuContext, GpuError, GpuEvaluator, GpuOutput, GpuRefineOptions,
};

/// One output vertex: the coarse face and barycentric point it stands for, and what the
/// backend computed there.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    pub face: u32,
    pub l: [f32; 3],
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// How close a backend must come to the f64 reference.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// Position distance, in bounding-box diagonals of the coarse mesh.
    pub position: f64,
    /// Length of the difference of the unit normals.
    pub normal: f64,
}

/// What every backend holds: positions within `1e-6` of the bounding-box diagonal, unit
/// normals within `1e-5`. All three evaluate in f32 (the GPU compute and GL shaders with the
/// driver's fused multiply-adds and `inversesqrt`): on the corpus the worst errors are about
/// `1.3e-7` diagonals and `2.5e-6` for normals (lavapipe and llvmpipe alike; the test prints
/// them). Positions are sums of products of the nets (no division), so `1e-6` leaves a margin
/// of about 8 ulp-scale roundings; normals are normalised (`inversesqrt`, a few ulp on
/// hardware), so `1e-5`. The backends' own tests against the CPU hold the looser `1e-5` and
/// `1e-4`; a backend that needs more than `EXACT` must say why here.
pub const EXACT: Tolerance = Tolerance {
    position: 1e-6,
    normal: 1e-5,
};

/// A refining backend as the suite sees it.
pub trait Backend {
    fn name(&self) -> &'static str;
    fn tolerance(&self) -> Tolerance;
    /// Whether the backend runs plans of `options`; where it does not, the suite checks that
    /// it refuses them with an error (a documented limit, not a silent skip).
    fn runs(&self, options: &RefineOptions) -> bool;
    /// Whether the backend displaces plans of `options`; where it does not, the suite checks
    /// that it refuses.
    fn displaces(&self, options: &RefineOptions) -> bool;
    /// One frame of `plan`, displaced by `displacement` (none: plain), as samples.
    fn refine(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        displacement: &Displacement,
    ) -> Result<Vec<Sample>, String>;
}

/// Samples of an output in the plan's layout: vertex `i` at `plan.origin()`'s face and point.
fn layout_samples(plan: &Plan, positions: &[[f32; 3]], normals: &[[f32; 3]]) -> Vec<Sample> {
    let (faces, bary) = plan.origin();
    (0..plan.vertex_count())
        .map(|i| Sample {
            face: faces[i],
            l: bary[i],
            position: positions[i],
            normal: normals[i],
        })
        .collect()
}

/// The CPU: `CpuEvaluator` into caller slices; displacement after evaluation
/// (`Displacement::apply`, the CPU's and the reference of the GPU's).
pub struct Cpu;

impl Backend for Cpu {
    fn name(&self) -> &'static str {
        "cpu"
    }
    fn tolerance(&self) -> Tolerance {
        EXACT
    }
    fn runs(&self, _: &RefineOptions) -> bool {
        true
    }
    fn displaces(&self, _: &RefineOptions) -> bool {
        true
    }
    fn refine(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        displacement: &Displacement,
    ) -> Result<Vec<Sample>, String> {
        let n = plan.vertex_count();
        let mut out = RefinedMesh {
            positions: vec![[0.0; 3]; n],
            normals: vec![[0.0; 3]; n],
            ..RefinedMesh::default()
        };
        CpuEvaluator
            .evaluate(
                plan,
                frame,
                VertexOutput::Separate {
                    positions: &mut out.positions,
                    normals: Some(&mut out.normals),
                    uvs: None,
                },
            )
            .map_err(|e| e.to_string())?;
        if displacement.is_some() {
            let d = DisplaceFrame::new(frame.mesh(), plan.topology(), plan.layout());
            displacement
                .apply(&mut out, &d)
                .map_err(|e| e.to_string())?;
        }
        Ok(layout_samples(plan, &out.positions, &out.normals))
    }
}

/// The GPU compute path: `GpuEvaluator` into its own buffer, read back; displacement is an
/// evaluator option (`GpuRefineOptions::displacement`).
pub struct Gpu;

/// The software adapter (lavapipe in CI), one per test binary; a missing one fails the tests
/// with the reason rather than skipping them.
fn gpu_context() -> Result<&'static GpuContext, String> {
    static CTX: OnceLock<Result<GpuContext, GpuError>> = OnceLock::new();
    CTX.get_or_init(|| GpuContext::new(AdapterChoice::Software))
        .as_ref()
        .map_err(|e| format!("no software GPU adapter for the regression suite: {e}"))
}

impl Backend for Gpu {
    fn name(&self) -> &'static str {
        "gpu compute"
    }
    fn tolerance(&self) -> Tolerance {
        EXACT
    }
    fn runs(&self, _: &RefineOptions) -> bool {
        true
    }
    /// Grid plans only: the compute path refuses to displace tessellator and adaptive plans.
    fn displaces(&self, options: &RefineOptions) -> bool {
        options.uniform_grid_level().is_some()
    }
    fn refine(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        displacement: &Displacement,
    ) -> Result<Vec<Sample>, String> {
        let ctx = gpu_context()?;
        let options = GpuRefineOptions {
            displacement: displacement.clone(),
            vertex_format: Some(VertexFormat::POSITION_NORMAL),
            ..GpuRefineOptions::default()
        };
        let run = || -> Result<Vec<f32>, GpuError> {
            let mut gpu = GpuEvaluator::with_options(ctx, plan, &options)?;
            gpu.evaluate(plan, frame, GpuOutput::Own)?;
            gpu.read_back()
        };
        let data = run().map_err(|e| e.to_string())?;
        let stride = VertexFormat::POSITION_NORMAL.stride;
        if data.len() < plan.vertex_count() * stride {
            return Err(format!(
                "the GPU wrote {} floats for {} vertices",
                data.len(),
                plan.vertex_count()
            ));
        }
        let (positions, normals): (Vec<[f32; 3]>, Vec<[f32; 3]>) = data
            .chunks_exact(stride)
            .take(plan.vertex_count())
            .map(|v| ([v[0], v[1], v[2]], [v[3], v[4], v[5]]))
            .unzip();
        Ok(layout_samples(plan, &positions, &normals))
    }
}

/// The GL backend: `GlEvaluator` into a caller `GlRefined`, the hardware tessellator's soup
/// with each vertex's primitive id and tessellation coordinate. It runs the hardware spacings
/// only and does not displace.
pub struct Gl {
    ctx: Result<GlContext, String>,
}

impl Gl {
    pub fn new() -> Gl {
        Gl {
            ctx: GlContext::new()
                .map_err(|e| format!("no GL driver for the regression suite: {e}")),
        }
    }
}

impl Backend for Gl {
    fn name(&self) -> &'static str {
        "gl"
    }
    fn tolerance(&self) -> Tolerance {
        EXACT
    }
    fn runs(&self, options: &RefineOptions) -> bool {
        options.spacing.tessellator().is_some()
    }
    /// No displacement stage in its shaders: refused (`GlEvaluator::with_displacement`).
    fn displaces(&self, _: &RefineOptions) -> bool {
        false
    }
    fn refine(
        &mut self,
        plan: &Plan,
        frame: &Frame,
        displacement: &Displacement,
    ) -> Result<Vec<Sample>, String> {
        let ctx = self.ctx.as_ref().map_err(Clone::clone)?;
        let mut out = GlRefined::default();
        GlEvaluator::with_displacement(ctx, plan, frame, displacement)
            .and_then(|mut gl| gl.evaluate(plan, frame, &mut out))
            .map_err(|e| e.to_string())?;
        if !out.notes.is_empty() {
            return Err(format!("the driver changed the levels: {:?}", out.notes));
        }
        Ok((0..out.positions.len())
            .map(|v| Sample {
                face: out.faces[v],
                l: out.coords[v],
                position: out.positions[v],
                normal: out.normals[v],
            })
            .collect())
    }
}
