//! One-shot refinement of one mesh on the CPU: a plan and its first frame in one value
//! ([`Refiner`]), and the indexed mesh it writes ([`RefinedMesh`]).

use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::refine::plan::layout::OutputLayout;
use crate::refine::plan::options::RefineOptions;
use crate::refine::plan::surface::Frame;
use crate::refine::plan::table::Plan;
use crate::scheme::PatchNets;
use crate::stencil::Stencil;

/// A refined mesh: indexed, counter-clockwise triangles, unit normals.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RefinedMesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub triangles: Vec<[u32; 3]>,
}

impl RefinedMesh {
    /// Bytes held by the arrays.
    pub fn byte_size(&self) -> u64 {
        (self.positions.len() * 12
            + self.normals.len() * 12
            + self.uvs.as_ref().map_or(0, |u| u.len() * 8)
            + self.triangles.len() * 12) as u64
    }
}

/// A plan and its first frame, for one-shot refinement of one mesh: [`Plan`] + [`Frame`] in
/// one value ([`Plan::with_frame`]: the frame borrows the mesh, and its nets are built once).
/// Reuse it to refine again into the same buffers; for a deforming mesh use the plan and frames
/// directly.
pub struct Refiner<'m> {
    mesh: &'m Mesh,
    plan: Plan,
    frame: Frame<'m>,
}

impl<'m> Refiner<'m> {
    /// Validates the options, checks the output's size and prepares the work.
    pub fn new(mesh: &'m Mesh, options: &RefineOptions) -> Result<Refiner<'m>, RefineError> {
        let (plan, frame) = Plan::with_frame(mesh, options)?;
        Ok(Refiner { mesh, plan, frame })
    }

    /// Total that [`Refiner::refine_into`]'s progress calls add up to.
    pub fn progress_total(&self) -> u64 {
        self.plan.progress_total()
    }
    /// The plan (everything that does not depend on positions).
    pub fn plan(&self) -> &Plan {
        &self.plan
    }
    /// The frame (the mesh's control nets).
    pub fn frame(&self) -> &Frame<'m> {
        &self.frame
    }
    /// The pattern.
    pub fn pattern(&self) -> &Pattern {
        self.plan.pattern()
    }
    /// The output's vertex and triangle counts.
    pub fn layout(&self) -> &OutputLayout {
        self.plan.layout()
    }
    /// The control nets (what a GPU backend uploads).
    pub fn nets(&self) -> &PatchNets {
        self.frame.nets()
    }
    /// The pattern's weights.
    pub fn stencil(&self) -> &Stencil {
        self.plan.stencil()
    }
    /// The options.
    pub fn options(&self) -> &RefineOptions {
        self.plan.options()
    }
    /// The mesh being refined.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }
    /// The topology (edges, owners, neighbours).
    pub fn topology(&self) -> &Topology {
        self.plan.topology()
    }

    /// Refines into `out`, reusing its allocations when they are large enough.
    /// `progress` is called from worker threads with amounts of work just finished; they add up
    /// to [`Refiner::progress_total`].
    pub fn refine_into(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        self.plan
            .refine_into(&self.frame, out, progress)
            .expect("a refiner's own frame fits its plan");
    }

    /// Refines into a new mesh.
    pub fn refine(&self) -> RefinedMesh {
        let mut out = RefinedMesh::default();
        self.refine_into(&mut out, &|_| {});
        out
    }
}

/// Refines `mesh` with `options`: the one-call form of [`Refiner`].
pub fn refine(mesh: &Mesh, options: &RefineOptions) -> Result<RefinedMesh, RefineError> {
    Ok(Refiner::new(mesh, options)?.refine())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::plan::levels::{Camera, Levels, Lod, Spacing};
    use crate::samples;
    use crate::scheme::{Scheme, NET_BUILDS};

    /// Net builds on this thread while `f` runs.
    fn builds<T>(f: impl FnOnce() -> T) -> (usize, T) {
        let before = NET_BUILDS.with(|n| n.get());
        let out = f();
        (NET_BUILDS.with(|n| n.get()) - before, out)
    }

    #[test]
    fn each_frame_builds_its_nets_once_and_plans_only_where_levels_read_them() {
        let mesh = samples::creature();
        let camera = Camera {
            eye: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            fov_y_deg: 45.0,
        };
        let lods = [
            Lod::Tolerance {
                max_deviation: 0.01,
            },
            Lod::Screen {
                pixels: 20.0,
                camera,
                size: [640, 480],
            },
            Lod::Distance {
                near: 1.0,
                far: 10.0,
                max: 8.0,
                eye: camera.eye,
            },
        ];
        let mut cases: Vec<(RefineOptions, bool)> = vec![
            (RefineOptions::new(Scheme::Pn, 4), false),
            (
                RefineOptions::new(Scheme::Png1, 3).with_uniform_level(3.5),
                false,
            ),
            (
                RefineOptions::new(Scheme::Pn, 1)
                    .with_spacing(Spacing::FractionalOdd)
                    .with_uniform_level(5.5),
                false,
            ),
        ];
        for lod in lods {
            for spacing in [Spacing::Grid, Spacing::FractionalEven] {
                let mut options = RefineOptions::new(Scheme::Png1, 1).with_spacing(spacing);
                options.levels = Levels::Lod(lod.clone());
                cases.push((options, true));
            }
        }
        for (options, lod) in cases {
            let what = format!("{:?} {:?}", options.levels, options.spacing);
            let (n, plan) = builds(|| Plan::new(&mesh, &options).unwrap());
            assert_eq!(n, usize::from(lod), "Plan::new, {what}");
            let (n, frame) = builds(|| plan.frame(&mesh).unwrap());
            assert_eq!(n, 1, "plan.frame, {what}");
            let (n, (_, first)) = builds(|| Plan::with_frame(&mesh, &options).unwrap());
            assert_eq!(n, 1, "Plan::with_frame, {what}");
            assert_eq!(first.nets(), frame.nets(), "{what}");
            let (n, refiner) = builds(|| Refiner::new(&mesh, &options).unwrap());
            assert_eq!(n, 1, "Refiner::new, {what}");
            assert!(std::ptr::eq(refiner.frame().mesh(), &mesh), "{what}");
        }
    }
}
