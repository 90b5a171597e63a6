//! Refinement on the CPU: control nets × stencil, into an indexed mesh.
//!
//! ```
//! use tessella_core::{refine, samples, RefineOptions, Scheme};
//! let mesh = samples::icosphere(1);
//! let out = refine(&mesh, &RefineOptions::new(Scheme::Pn, 4))?;
//! assert_eq!(out.triangles.len(), mesh.face_count() * 16);
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

mod evaluate;
mod layout;

pub use evaluate::{eval_block, eval_point};
pub use layout::{OutputLayout, BYTES_PER_INDEXED_TRIANGLE};

use crate::error::{human_bytes, RefineError};
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::scheme::{build_nets_tagged, NormalMode, PatchNets, Scheme};
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

/// Everything prepared for refining one mesh at one level: topology, pattern weights and control
/// nets. Reuse it to refine again (into the same buffers) without redoing that work.
pub struct Refiner<'m> {
    mesh: &'m Mesh,
    options: RefineOptions,
    layout: OutputLayout,
    topology: Option<Topology>,
    pattern: Pattern,
    stencil: Stencil,
    nets: PatchNets,
}

impl<'m> Refiner<'m> {
    /// Validates the options, checks the output's size and prepares the work.
    pub fn new(mesh: &'m Mesh, options: &RefineOptions) -> Result<Refiner<'m>, RefineError> {
        options.scheme.validate()?;
        let topology = options.weld.then(|| mesh.topology());
        let layout = OutputLayout::new(mesh, topology.as_ref(), options.level, options.weld)?;
        let bytes = layout.output_bytes(mesh.uvs().is_some());
        if bytes > options.max_output_bytes {
            return Err(RefineError::TooLarge {
                level: options.level,
                faces: mesh.face_count(),
                vertices: layout.vertex_count,
                triangles: layout.triangle_count,
                bytes,
                bytes_human: human_bytes(bytes),
                limit: options.max_output_bytes,
                limit_human: human_bytes(options.max_output_bytes),
            });
        }
        if layout.vertex_count > u32::MAX as u64 {
            return Err(RefineError::IndexOverflow {
                level: options.level,
                vertices: layout.vertex_count,
            });
        }
        let pattern = Pattern::uniform(options.level);
        let stencil = Stencil::new(&pattern, options.scheme.basis());
        let nets = build_nets_tagged(
            mesh,
            topology.as_ref(),
            &options.scheme,
            options.normal_mode(),
            options.tags.as_deref(),
        )?;
        Ok(Refiner {
            mesh,
            options: options.clone(),
            layout,
            topology,
            pattern,
            stencil,
            nets,
        })
    }

    /// Total that [`Refiner::refine_into`]'s progress calls add up to.
    pub fn progress_total(&self) -> u64 {
        2 * self.mesh.face_count() as u64
    }
    /// The pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }
    /// The output's vertex and triangle counts.
    pub fn layout(&self) -> &OutputLayout {
        &self.layout
    }
    /// The control nets (what a GPU backend uploads).
    pub fn nets(&self) -> &PatchNets {
        &self.nets
    }
    /// The pattern's weights.
    pub fn stencil(&self) -> &Stencil {
        &self.stencil
    }
    /// The options.
    pub fn options(&self) -> &RefineOptions {
        &self.options
    }
    /// The mesh being refined.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }
    /// The topology (edges and their owners); `Some` for welded output.
    pub fn topology(&self) -> Option<&Topology> {
        self.topology.as_ref()
    }

    /// Refines into `out`, reusing its allocations when they are large enough.
    /// `progress` is called from worker threads with amounts of work just finished; they add up
    /// to [`Refiner::progress_total`].
    pub fn refine_into(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        let job = evaluate::Job {
            mesh: self.mesh,
            topology: self.topology.as_ref(),
            layout: &self.layout,
            pattern: &self.pattern,
            stencil: &self.stencil,
            nets: &self.nets,
        };
        job.run(out, progress);
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
