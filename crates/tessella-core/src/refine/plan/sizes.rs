//! [`PlanSizes`]: what a plan's output and coarse data are sized by, the first part of the
//! key the GPU and GL evaluators check a plan against.

use super::table::Plan;

/// What a plan's output and coarse data are sized by: refined vertices and triangles, coarse
/// faces, level and welding. The GPU and GL evaluators are made for one plan and refuse a plan
/// of other sizes (or other shader choices) with these as the first part of their key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlanSizes {
    pub vertices: usize,
    pub triangles: usize,
    pub faces: usize,
    pub level: u32,
    pub weld: bool,
}

impl Plan {
    /// The plan's [`PlanSizes`].
    pub fn sizes(&self) -> PlanSizes {
        let layout = self.layout();
        PlanSizes {
            vertices: self.vertex_count(),
            triangles: self.triangle_count(),
            faces: self.face_count(),
            level: layout.level,
            weld: layout.weld,
        }
    }
}
