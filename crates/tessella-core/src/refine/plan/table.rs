//! What is built once per topology ([`Plan`]) kept apart from what changes every frame
//! ([`Frame`]): the papers' real-time loop, where the coarse mesh deforms and only coarse data
//! is recomputed.
//!
//! ```
//! use tessella_core::refine::{Plan, VertexOutput};
//! use tessella_core::{samples, RefineOptions, Scheme};
//!
//! let mesh = samples::icosphere(1);
//! let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 8))?;
//! let mut frame = plan.frame(&mesh)?;
//! let n = plan.vertex_count();
//! let (mut positions, mut normals) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
//! let indices = plan.indices(); // computed once, valid for every frame
//! for t in 0..3 {
//!     let s = 1.0 + 0.1 * t as f32;
//!     let moved: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| s * c)).collect();
//!     plan.update(&mut frame, &moved, None)?; // O(coarse triangles)
//!     plan.evaluate(&frame, VertexOutput::Separate {
//!         positions: &mut positions,
//!         normals: Some(&mut normals),
//!         uvs: None,
//!     })?; // writes vertices only, into the caller's memory
//! }
//! assert_eq!(indices.len(), mesh.face_count() * 64);
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

use super::indices::{AdaptiveIndex, IndexInt, IndexJob};
use super::layout::OutputLayout;
use super::levels::{Levels, Lod};
use super::lod;
use super::options::RefineOptions;
use super::surface::{Frame, Surface};
use super::tiling::{build_tiling, resolve_levels, Tiling};
use crate::error::{human_bytes, RefineError};
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::scheme::{fill_nets, PatchNets};
use crate::stencil::Stencil;
use std::borrow::Cow;
use std::sync::OnceLock;

/// Everything that does not change while a mesh deforms: the options, the [`Surface`]
/// (topology and scheme, which builds the frames' nets), the output layout, the pattern and its
/// stencil, and the refined triangles' indices (built on first
/// use, then kept).
///
/// A plan is made from one mesh and serves every mesh with the same triangles and vertex count
/// (the same topology); which vertices share a position (for the schemes that look across
/// edges) is fixed by the mesh the plan was made from.
///
/// A plan of LOD levels ([`Levels::Lod`]) computes them once, from the control nets of the mesh
/// it is made from; its frames, of that mesh or any other of its topology, and their updates
/// keep those levels (make a new plan, or draw with a renderer that takes levels every frame,
/// to follow the mesh). [`Plan::with_frame`] hands those nets to the first frame, so they are
/// built once; other levels read no nets, and each frame builds its own.
///
/// Output order, for [`Plan::evaluate`] and [`Plan::indices`]: welded, the mesh's `V` vertices
/// (exact input positions), then `N−1` vertices per unique edge (by vertex index, from the lower
/// index to the higher), then each face's interior points in pattern order; soup, every face's
/// `(N+1)(N+2)/2` pattern points.
#[derive(Debug)]
pub struct Plan {
    pub(in crate::refine) options: RefineOptions,
    pub(in crate::refine) surface: Surface,
    pub(in crate::refine) layout: OutputLayout,
    pub(in crate::refine) pattern: Pattern,
    pub(in crate::refine) stencil: Stencil,
    pub(in crate::refine) indices: OnceLock<Vec<[u32; 3]>>,
    pub(in crate::refine) tiling: Option<Tiling>,
}

impl Plan {
    /// Validates the options and the output's size against `mesh` and builds the tables.
    pub fn new(mesh: &Mesh, options: &RefineOptions) -> Result<Plan, RefineError> {
        Ok(Self::build(mesh, options)?.0)
    }

    /// [`Plan::new`] and its first frame of `mesh` ([`Plan::frame`]: borrowed from a `&Mesh`,
    /// owned from a `Mesh`), each frame's nets built once: a LOD plan's frame carries the nets
    /// its levels were computed from, where `Plan::new` and then `plan.frame(&mesh)` would
    /// build them again.
    ///
    /// ```
    /// use tessella_core::refine::{Levels, Lod, Plan};
    /// use tessella_core::{samples, RefineOptions, Scheme};
    ///
    /// let mesh = samples::icosphere(1);
    /// let mut options = RefineOptions::new(Scheme::Pn, 1);
    /// options.levels = Levels::Lod(Lod::Tolerance { max_deviation: 0.01 });
    /// let (plan, frame) = Plan::with_frame(&mesh, &options)?;
    /// assert!(std::ptr::eq(frame.mesh(), &mesh)); // borrowed, not copied
    /// assert_eq!(frame.nets().points, plan.frame(&mesh)?.nets().points);
    /// # Ok::<(), tessella_core::RefineError>(())
    /// ```
    pub fn with_frame<'m>(
        mesh: impl Into<Cow<'m, Mesh>>,
        options: &RefineOptions,
    ) -> Result<(Plan, Frame<'m>), RefineError> {
        let mesh = mesh.into();
        let (plan, nets) = Self::build(&mesh, options)?;
        let frame = plan.surface.frame_with(mesh, nets)?;
        Ok((plan, frame))
    }

    /// The plan and, for LOD levels, the nets of `mesh` its levels were computed from.
    fn build(
        mesh: &Mesh,
        options: &RefineOptions,
    ) -> Result<(Plan, Option<PatchNets>), RefineError> {
        options.scheme.validate()?;
        match options.uniform_grid_level() {
            Some(level) => Ok((Self::uniform(mesh, options, level)?, None)),
            None => Self::adaptive(mesh, options),
        }
    }

    /// A plan of per-face patterns from per-edge levels (see [`Tiling`]), and the nets LOD
    /// levels were computed from (`None` for other levels: they read none).
    fn adaptive(
        mesh: &Mesh,
        options: &RefineOptions,
    ) -> Result<(Plan, Option<PatchNets>), RefineError> {
        let topology = mesh.topology();
        options.surface_options().validate(mesh, &topology)?;
        let levels = options.levels.clone();
        // Only LOD levels read the surface (the first mesh's control nets), and they are the
        // nets the surface would build for a frame of this mesh (same function, topology,
        // scheme, normal mode and tags): `with_frame` hands them to the first frame. The other
        // levels read none, and every frame builds its own.
        let empty = PatchNets::empty(options.scheme.basis(), options.normal_mode());
        let nets = match levels {
            Levels::Lod(_) => {
                let mut nets = empty.clone();
                fill_nets(
                    mesh,
                    Some(&topology),
                    &options.scheme,
                    options.normal_mode(),
                    options.tags.as_deref(),
                    &mut nets,
                );
                Some(nets)
            }
            _ => None,
        };
        let (mut edges, mut faces) =
            resolve_levels(mesh, &topology, nets.as_ref().unwrap_or(&empty), &levels)?;
        if let (Levels::Lod(Lod::Tolerance { .. }), Some(_)) =
            (&levels, options.spacing.tessellator())
        {
            let parity = |x: &mut f32| *x = lod::with_parity(options.spacing, *x as f64) as f32;
            edges.iter_mut().for_each(parity);
            faces.iter_mut().flatten().for_each(parity);
        }
        let tiling = build_tiling(
            mesh,
            &topology,
            options.spacing,
            edges,
            faces,
            options.scheme.basis(),
            options.weld,
            mesh.uvs().is_some(),
            options.max_output_bytes,
        )?;
        let vertex_count = tiling.vertex_count();
        let triangle_count = tiling.triangle_count();
        let max_level = tiling.max_level();
        if vertex_count > u32::MAX as u64 {
            return Err(RefineError::IndexOverflow {
                level: max_level,
                vertices: vertex_count,
            });
        }
        let layout = OutputLayout {
            level: max_level,
            weld: options.weld,
            vertex_count,
            triangle_count,
            edge_base: if options.weld {
                mesh.vertex_count() as u64
            } else {
                0
            },
            interior_base: if options.weld {
                tiling.face_offset[0]
            } else {
                0
            },
        };
        let (pattern, stencil) = match tiling.tiles.first() {
            Some(t) => (t.pattern.clone(), t.stencil.clone()),
            None => {
                let p = Pattern::uniform(1);
                let s = Stencil::new(&p, options.scheme.basis());
                (p, s)
            }
        };
        let plan = Plan::assemble(
            mesh,
            options,
            topology,
            layout,
            (pattern, stencil),
            Some(tiling),
        );
        Ok((plan, nets))
    }

    /// The classic plan: one uniform grid pattern for every face.
    fn uniform(mesh: &Mesh, options: &RefineOptions, level: u32) -> Result<Plan, RefineError> {
        if level == 0 {
            return Err(RefineError::LevelZero);
        }
        let topology = mesh.topology();
        let layout = OutputLayout::new(mesh, Some(&topology), level, options.weld)?;
        let bytes = layout.output_bytes(mesh.uvs().is_some());
        let limit = options.max_output_bytes;
        if bytes > limit {
            return Err(RefineError::TooLarge {
                level,
                faces: mesh.face_count(),
                vertices: layout.vertex_count,
                triangles: layout.triangle_count,
                bytes,
                bytes_human: human_bytes(bytes),
                limit,
                limit_human: human_bytes(limit),
            });
        }
        if layout.vertex_count > u32::MAX as u64 {
            return Err(RefineError::IndexOverflow {
                level,
                vertices: layout.vertex_count,
            });
        }
        options.surface_options().validate(mesh, &topology)?;
        let pattern = Pattern::uniform(level);
        let stencil = Stencil::new(&pattern, options.scheme.basis());
        Ok(Plan::assemble(
            mesh,
            options,
            topology,
            layout,
            (pattern, stencil),
            None,
        ))
    }

    /// The plan from its parts (the one place a `Plan` is put together).
    fn assemble(
        mesh: &Mesh,
        options: &RefineOptions,
        topology: Topology,
        layout: OutputLayout,
        (pattern, stencil): (Pattern, Stencil),
        tiling: Option<Tiling>,
    ) -> Plan {
        Plan {
            options: options.clone(),
            surface: Surface::from_parts(mesh, topology, options.surface_options()),
            layout,
            pattern,
            stencil,
            indices: OnceLock::new(),
            tiling,
        }
    }

    /// A frame of `mesh` (which must have the plan's topology) and its nets, built now
    /// ([`Surface::frame`]): it borrows a `&Mesh` and owns a `Mesh`, copying neither. For the
    /// mesh the plan is made from, [`Plan::with_frame`] saves a LOD plan's second build of the
    /// nets.
    pub fn frame<'m>(&self, mesh: impl Into<Cow<'m, Mesh>>) -> Result<Frame<'m>, RefineError> {
        self.surface.frame(mesh)
    }

    /// Moves `frame` to new positions and normals and rebuilds its nets ([`Surface::update`]).
    pub fn update(
        &self,
        frame: &mut Frame,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<(), RefineError> {
        self.surface.update(frame, positions, normals)
    }

    /// Like [`Plan::update`] from a whole mesh of the plan's topology
    /// ([`Surface::update_from_mesh`]).
    pub fn update_from_mesh(&self, frame: &mut Frame, mesh: &Mesh) -> Result<(), RefineError> {
        self.surface.update_from_mesh(frame, mesh)
    }

    pub(in crate::refine) fn write_triangles<I: IndexInt>(
        &self,
        out: &mut [[I; 3]],
        progress: &(dyn Fn(u64) + Sync),
    ) {
        match &self.tiling {
            Some(tiling) => self.adaptive_index(tiling).indices(out, progress),
            None => self.index_job().write(out, progress),
        }
    }

    pub(in crate::refine) fn adaptive_index<'a>(&'a self, tiling: &'a Tiling) -> AdaptiveIndex<'a> {
        AdaptiveIndex {
            triangles: &self.surface.triangles,
            topology: &self.surface.topology,
            tiling,
            weld: self.layout.weld,
        }
    }

    /// The adaptive tiling: per-face patterns and where their points go; `None` for a uniform
    /// plan (one [`Plan::pattern`] for every face).
    pub fn tiling(&self) -> Option<&Tiling> {
        self.tiling.as_ref()
    }

    /// The refined triangles (counter-clockwise, as the coarse ones), computed on first use
    /// and kept: they do not depend on positions.
    pub fn indices(&self) -> &[[u32; 3]] {
        self.indices.get_or_init(|| {
            let mut out = vec![[0u32; 3]; self.triangle_count()];
            self.write_triangles(&mut out, &|_| {});
            out
        })
    }

    /// Writes the refined triangles into `out` (at least [`Plan::triangle_count`] long) as
    /// `u32` or, when [`Plan::fits_u16`], `u16` indices.
    pub fn write_indices<I: IndexInt>(&self, out: &mut [[I; 3]]) -> Result<(), RefineError> {
        if self.layout.vertex_count > I::MAX_VERTICES {
            return Err(RefineError::IndicesTooNarrow {
                vertices: self.layout.vertex_count,
                index_bits: (I::MAX_VERTICES - 1).count_ones(),
            });
        }
        let need = self.triangle_count();
        if out.len() < need {
            return Err(RefineError::OutputTooSmall {
                what: "triangles".into(),
                got: out.len(),
                need,
            });
        }
        self.write_triangles(&mut out[..need], &|_| {});
        Ok(())
    }

    /// True when every refined vertex index fits in a `u16`.
    pub fn fits_u16(&self) -> bool {
        self.layout.vertex_count <= <u16 as IndexInt>::MAX_VERTICES
    }

    /// What [`Plan::refine_into`]'s progress calls add up to.
    pub fn progress_total(&self) -> u64 {
        2 * self.face_count() as u64
    }

    /// Number of refined vertices.
    pub fn vertex_count(&self) -> usize {
        self.layout.vertex_count as usize
    }
    /// Number of refined triangles.
    pub fn triangle_count(&self) -> usize {
        self.layout.triangle_count as usize
    }
    /// Number of coarse triangles.
    pub fn face_count(&self) -> usize {
        self.surface.triangles.len()
    }
    /// The coarse triangles this plan serves.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.surface.triangles
    }
    /// Number of coarse vertices a frame has.
    pub fn coarse_vertex_count(&self) -> usize {
        self.surface.vertex_count
    }
    /// The options.
    pub fn options(&self) -> &RefineOptions {
        &self.options
    }
    /// The normal mode in effect.
    pub fn normal_mode(&self) -> crate::scheme::NormalMode {
        self.options.normal_mode()
    }
    /// Sizes and block offsets of the output.
    pub fn layout(&self) -> &OutputLayout {
        &self.layout
    }
    /// The refinement pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }
    /// The pattern's weights for this scheme's basis.
    pub fn stencil(&self) -> &Stencil {
        &self.stencil
    }
    /// Edges, owners and neighbours of the coarse mesh.
    pub fn topology(&self) -> &Topology {
        &self.surface.topology
    }
    /// The surface (topology and scheme) whose nets the plan's frames carry.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }
    /// True when frames carry texture coordinates.
    pub fn has_uvs(&self) -> bool {
        self.surface.has_uvs
    }

    /// Refuses a frame another plan (or surface) made.
    pub fn check_frame(&self, frame: &Frame) -> Result<(), RefineError> {
        self.surface.check_frame(frame)
    }

    fn index_job(&self) -> IndexJob<'_> {
        IndexJob {
            triangles: &self.surface.triangles,
            topology: &self.surface.topology,
            layout: &self.layout,
            pattern: &self.pattern,
            stencil: &self.stencil,
        }
    }
}
