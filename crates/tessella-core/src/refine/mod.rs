//! Refinement on the CPU: control nets × stencil, into an indexed mesh.
//!
//! ```
//! use tessella_core::{refine, samples, RefineOptions, Scheme};
//! let mesh = samples::icosphere(1);
//! let out = refine(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
//! assert_eq!(out.triangles.len(), mesh.face_count() * 16);
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

pub mod adaptive;
pub mod canonical;
mod edge_groups;
mod evaluate;
mod evaluator;
mod indices;
pub mod instanced;
mod layout;
pub mod lod;
pub mod morph;
mod nontemporal;
mod output;
mod plan;
pub mod stream;
mod surface;

pub use adaptive::{Camera, Levels, Lod, Morph, Spacing, Tile, Tiling};
pub use evaluate::eval_point;
pub use evaluator::{CpuEvaluator, Evaluator};
pub use indices::IndexInt;
pub use layout::{OutputLayout, BYTES_PER_INDEXED_TRIANGLE};
pub use output::{VertexFormat, VertexOutput};
pub use plan::{Plan, NO_FACE};
pub use stream::Piece;
pub use surface::{Frame, Surface, SurfaceOptions};

use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::scheme::{NormalMode, PatchNets, Scheme};
use crate::stencil::Stencil;

/// Default cap on the output's size: 8 GiB.
pub const DEFAULT_MAX_OUTPUT_BYTES: u64 = 8 << 30;

/// What to refine into.
#[derive(Debug, Clone, PartialEq)]
pub struct RefineOptions {
    pub scheme: Scheme,
    /// Segments per coarse edge, 1 or more.
    pub level: u32,
    /// `None`: the scheme's default ([`Scheme::default_normals`]).
    pub normals: Option<NormalMode>,
    /// `true` (default): vertices on shared coarse corners and edges are shared. `false`: every
    /// coarse triangle gets its own copy of all its pattern points (a "soup" of patches).
    pub weld: bool,
    /// Refuse work whose output would need more bytes than this.
    pub max_output_bytes: u64,
    /// Shape tags (creases, scalar tags) for the schemes that read them; `None`: no tags.
    pub tags: Option<std::sync::Arc<crate::tags::Tags>>,
    /// How levels divide edges: the grid (default) or a hardware tessellator spacing.
    pub spacing: Spacing,
    /// `None` (default): `level` on every edge. `Some`: fractional, per-edge or LOD levels
    /// (an adaptive plan, see [`Tiling`]; `level` is then ignored). `Uniform` of an integer
    /// with [`Spacing::Grid`] is the same as setting `level`.
    pub levels: Option<Levels>,
}

impl RefineOptions {
    /// Welded output, the scheme's default normals, the default size cap.
    pub fn new(scheme: Scheme, level: u32) -> RefineOptions {
        RefineOptions {
            scheme,
            level,
            normals: None,
            weld: true,
            max_output_bytes: DEFAULT_MAX_OUTPUT_BYTES,
            tags: None,
            spacing: Spacing::Grid,
            levels: None,
        }
    }
    /// Sets the spacing ([`Spacing::Grid`] by default).
    pub fn with_spacing(mut self, spacing: Spacing) -> Self {
        self.spacing = spacing;
        self
    }
    /// Sets fractional, per-edge or LOD levels (overriding `level`).
    pub fn with_levels(mut self, levels: Levels) -> Self {
        self.levels = Some(levels);
        self
    }
    /// Sets one level for every edge as the CLI's `--level`, Python's `level=` and the viewer
    /// take it (the caller has checked it is finite and positive): a whole level with
    /// [`Spacing::Grid`] is the classic integer refinement, bit for bit; anything else (a
    /// fractional level, a tessellator spacing) becomes [`Levels::Uniform`], which geomorphs on
    /// the grid and is clamped to a tessellator spacing's range. Call after
    /// [`RefineOptions::with_spacing`].
    ///
    /// ```
    /// use tessella_core::refine::{Levels, Spacing};
    /// use tessella_core::{RefineOptions, Scheme};
    /// let whole = RefineOptions::new(Scheme::Pn, 1).with_uniform_level(6.0);
    /// assert_eq!((whole.level, whole.levels), (6, None));
    /// let morph = RefineOptions::new(Scheme::Pn, 1).with_uniform_level(5.5);
    /// assert_eq!(morph.levels, Some(Levels::Uniform(5.5)));
    /// let odd = RefineOptions::new(Scheme::Pn, 1)
    ///     .with_spacing(Spacing::FractionalOdd)
    ///     .with_uniform_level(3.0);
    /// assert_eq!(odd.levels, Some(Levels::Uniform(3.0)));
    /// ```
    pub fn with_uniform_level(mut self, level: f64) -> Self {
        let whole =
            level.is_finite() && level >= 0.0 && level.fract() == 0.0 && level <= u32::MAX as f64;
        self.level = if whole { level as u32 } else { 1 };
        self.levels = match (self.spacing, whole) {
            (Spacing::Grid, true) => None,
            _ => Some(Levels::Uniform(level as f32)),
        };
        self
    }
    /// Sets the size cap in bytes.
    pub fn with_max_output_bytes(mut self, bytes: u64) -> Self {
        self.max_output_bytes = bytes;
        self
    }
    /// The uniform integer grid level these options amount to, if they do (the classic,
    /// fastest path): grid spacing and no levels, or `Levels::Uniform` of an integer.
    pub fn uniform_grid_level(&self) -> Option<u32> {
        if self.spacing != Spacing::Grid {
            return None;
        }
        match &self.levels {
            None => Some(self.level),
            Some(Levels::Uniform(x)) if x.fract() == 0.0 && *x >= 1.0 && *x <= u32::MAX as f32 => {
                Some(*x as u32)
            }
            _ => None,
        }
    }
    /// Sets the shape tags.
    pub fn with_tags(mut self, tags: crate::tags::Tags) -> Self {
        self.tags = Some(std::sync::Arc::new(tags));
        self
    }
    /// Sets the normal mode.
    pub fn with_normals(mut self, normals: NormalMode) -> Self {
        self.normals = Some(normals);
        self
    }
    /// Sets welded (`true`) or soup (`false`) output.
    pub fn with_weld(mut self, weld: bool) -> Self {
        self.weld = weld;
        self
    }
    /// The normal mode in effect.
    pub fn normal_mode(&self) -> NormalMode {
        self.normals
            .unwrap_or_else(|| self.scheme.default_normals())
    }
    /// The part of these options that defines the surface (scheme, normals, tags; no level).
    pub fn surface_options(&self) -> SurfaceOptions {
        SurfaceOptions {
            scheme: self.scheme,
            normals: self.normals,
            tags: self.tags.clone(),
        }
    }
}

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
/// one value. Reuse it to refine again into the same buffers; for a deforming mesh use the
/// plan and frames directly.
pub struct Refiner<'m> {
    mesh: &'m Mesh,
    plan: Plan,
    frame: Frame,
}

impl<'m> Refiner<'m> {
    /// Validates the options, checks the output's size and prepares the work.
    pub fn new(mesh: &'m Mesh, options: &RefineOptions) -> Result<Refiner<'m>, RefineError> {
        let plan = Plan::new(mesh, options)?;
        let frame = plan.frame(mesh)?;
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
    pub fn frame(&self) -> &Frame {
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
