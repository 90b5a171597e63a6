//! What defines a curved surface apart from any refinement level: the coarse mesh's topology
//! and the scheme (with its normal mode and tags). A [`Surface`] builds and rebuilds the
//! control nets of a deforming mesh ([`Frame`]); a [`Plan`](super::table::Plan) holds one and adds
//! the level's pattern, layout and stencil, and renderers that choose levels per frame (the GPU
//! adaptive renderer) need nothing more than the surface.
//!
//! ```
//! use tessella_core::refine::{Surface, SurfaceOptions};
//! use tessella_core::{samples, Scheme};
//!
//! let mesh = samples::icosphere(1);
//! let surface = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn))?;
//! let mut frame = surface.frame(&mesh)?;
//! let before = frame.nets().points.clone();
//! let moved: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| 2.0 * c)).collect();
//! surface.update(&mut frame, &moved, None)?; // O(coarse triangles): new nets
//! // PN's control points scale with the mesh (its normals do not change).
//! for (b, a) in before.iter().zip(&frame.nets().points) {
//!     assert!((0..3).all(|k| (a[k] - 2.0 * b[k]).abs() < 1e-5));
//! }
//! // A frame of another surface is refused.
//! let other = Surface::new(&mesh, &SurfaceOptions::new(Scheme::Pn))?;
//! assert!(other.update(&mut frame, &moved, None).is_err());
//! # Ok::<(), tessella_core::RefineError>(())
//! ```

use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::scheme::{fill_nets, validate_nets, NormalMode, PatchNets, Scheme};
use crate::tags::Tags;
use std::borrow::Cow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Tells surfaces apart, so a frame is never evaluated by a surface (or plan) that did not make
/// it.
static NEXT_SURFACE_ID: AtomicU64 = AtomicU64::new(1);

/// The scheme options that define a surface: no level, no layout.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceOptions {
    pub scheme: Scheme,
    /// `None`: the scheme's default ([`Scheme::default_normals`]).
    pub normals: Option<NormalMode>,
    /// Shape tags (creases, scalar tags) for the schemes that read them; `None`: no tags.
    pub tags: Option<Arc<Tags>>,
}

impl SurfaceOptions {
    /// Checks the scheme (and its tags) against `mesh` and its topology.
    pub(crate) fn validate(&self, mesh: &Mesh, topology: &Topology) -> Result<(), RefineError> {
        validate_nets(mesh, Some(topology), &self.scheme, self.tags.as_deref())
    }

    /// The scheme's default normals, no tags.
    pub fn new(scheme: Scheme) -> SurfaceOptions {
        SurfaceOptions {
            scheme,
            normals: None,
            tags: None,
        }
    }
    /// Sets the normal mode.
    pub fn with_normals(mut self, normals: NormalMode) -> Self {
        self.normals = Some(normals);
        self
    }
    /// Sets the shape tags.
    pub fn with_tags(mut self, tags: Tags) -> Self {
        self.tags = Some(Arc::new(tags));
        self
    }
    /// The normal mode in effect.
    pub fn normal_mode(&self) -> NormalMode {
        self.normals
            .unwrap_or_else(|| self.scheme.default_normals())
    }
}

/// The mesh's topology and the scheme: builds a [`Frame`]'s control nets and rebuilds them
/// when the mesh moves. Clones share the identity: a frame of one is a frame of the other.
///
/// A surface is made from one mesh and serves every mesh with the same triangles and vertex
/// count; which vertices share a position (for the schemes that look across edges) is fixed by
/// the mesh it was made from.
#[derive(Debug, Clone)]
pub struct Surface {
    id: u64,
    options: SurfaceOptions,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) vertex_count: usize,
    pub(crate) has_uvs: bool,
    pub(crate) topology: Topology,
}

/// One frame of a deforming mesh: its coarse mesh and the control nets built from it. Made by
/// [`Surface::frame`] (or [`Plan::frame`](super::table::Plan::frame),
/// [`Plan::with_frame`](super::table::Plan::with_frame)), moved by [`Surface::update`], read by
/// every evaluator.
///
/// A frame does not copy its mesh: made from a `&Mesh` it borrows it (`Frame<'m>`), made from
/// a `Mesh` it owns it (`Frame<'static>`, for a frame kept beyond the mesh's scope). A frame
/// that borrows its mesh takes a copy of it at its first [`Surface::update`] (the borrowed mesh
/// never changes); an owned one moves in place.
#[derive(Debug, Clone)]
pub struct Frame<'m> {
    surface_id: u64,
    pub(crate) mesh: Cow<'m, Mesh>,
    pub(crate) nets: PatchNets,
}

impl Frame<'_> {
    /// The coarse mesh of this frame.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }
    /// The control nets of this frame (what a GPU backend uploads each frame).
    pub fn nets(&self) -> &PatchNets {
        &self.nets
    }
    /// True when the frame owns its mesh (made from a `Mesh`, or moved once); false while it
    /// borrows the mesh it was made from.
    pub fn owns_mesh(&self) -> bool {
        matches!(self.mesh, Cow::Owned(_))
    }
    /// The frame with a mesh of its own: a borrowed mesh is copied (the one copy), an owned one
    /// moved.
    pub fn into_owned(self) -> Frame<'static> {
        Frame {
            surface_id: self.surface_id,
            mesh: Cow::Owned(self.mesh.into_owned()),
            nets: self.nets,
        }
    }
}

/// The mesh a frame is made from: `&Mesh` (borrowed) or `Mesh` (owned), so
/// [`Surface::frame`] and [`Plan::frame`](super::table::Plan::frame) take either.
impl<'m> From<&'m Mesh> for Cow<'m, Mesh> {
    fn from(mesh: &'m Mesh) -> Self {
        Cow::Borrowed(mesh)
    }
}

impl From<Mesh> for Cow<'static, Mesh> {
    fn from(mesh: Mesh) -> Self {
        Cow::Owned(mesh)
    }
}

impl Surface {
    /// Validates the scheme (and its tags) against `mesh` and builds its topology.
    pub fn new(mesh: &Mesh, options: &SurfaceOptions) -> Result<Surface, RefineError> {
        let topology = mesh.topology();
        options.validate(mesh, &topology)?;
        Ok(Surface::from_parts(mesh, topology, options.clone()))
    }

    /// A surface from a topology already built and options already validated (a plan's).
    pub(crate) fn from_parts(mesh: &Mesh, topology: Topology, options: SurfaceOptions) -> Surface {
        Surface {
            id: NEXT_SURFACE_ID.fetch_add(1, Ordering::Relaxed),
            options,
            triangles: mesh.triangles().to_vec(),
            vertex_count: mesh.vertex_count(),
            has_uvs: mesh.uvs().is_some(),
            topology,
        }
    }

    /// The first frame of `mesh` (which must have the surface's topology) and its nets: it
    /// borrows a `&Mesh` and owns a `Mesh`, copying neither ([`Frame`]).
    pub fn frame<'m>(&self, mesh: impl Into<Cow<'m, Mesh>>) -> Result<Frame<'m>, RefineError> {
        self.frame_with(mesh.into(), None)
    }

    /// A frame of `mesh` carrying `nets` when they are given (the nets a plan built from this
    /// very mesh for its levels), else nets built now: either way, built once.
    pub(crate) fn frame_with<'m>(
        &self,
        mesh: Cow<'m, Mesh>,
        nets: Option<PatchNets>,
    ) -> Result<Frame<'m>, RefineError> {
        self.check_topology(&mesh)?;
        let nets = nets.unwrap_or_else(|| {
            let mut nets = PatchNets::empty(self.options.scheme.basis(), self.normal_mode());
            self.fill(&mesh, &mut nets);
            nets
        });
        Ok(Frame {
            surface_id: self.id,
            mesh,
            nets,
        })
    }

    /// Moves `frame` to new `positions` (and `normals`; `None` recomputes them, see
    /// [`Mesh::update`]) and rebuilds its nets: O(coarse triangles), no allocation but the
    /// recomputed normals, and, for a frame that still borrows its mesh, the copy of that mesh
    /// it then takes (once: the borrowed mesh is not changed). On error (wrong vertex count,
    /// non-finite positions, zero or non-finite normals, a degenerate triangle, a frame of
    /// another surface) `frame` is unchanged.
    pub fn update(
        &self,
        frame: &mut Frame,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<(), RefineError> {
        self.check_frame(frame)?;
        match &mut frame.mesh {
            Cow::Owned(mesh) => mesh.update(positions, normals)?,
            Cow::Borrowed(borrowed) => {
                let mut mesh = (*borrowed).clone();
                mesh.update(positions, normals)?;
                frame.mesh = Cow::Owned(mesh);
            }
        }
        self.fill(&frame.mesh, &mut frame.nets);
        Ok(())
    }

    /// Like [`Surface::update`] from a whole mesh of the surface's topology (its UVs are
    /// ignored: they belong to the first mesh).
    pub fn update_from_mesh(&self, frame: &mut Frame, mesh: &Mesh) -> Result<(), RefineError> {
        self.check_topology(mesh)?;
        self.update(frame, mesh.positions(), Some(mesh.normals()))
    }

    /// Refuses a frame another surface made.
    pub fn check_frame(&self, frame: &Frame) -> Result<(), RefineError> {
        if frame.surface_id != self.id {
            return Err(RefineError::ForeignFrame);
        }
        Ok(())
    }

    /// Refuses a mesh whose topology is not the surface's.
    pub(crate) fn check_topology(&self, mesh: &Mesh) -> Result<(), RefineError> {
        let reason = if mesh.vertex_count() != self.vertex_count {
            format!(
                "{} vertices, the plan has {}",
                mesh.vertex_count(),
                self.vertex_count
            )
        } else if mesh.face_count() != self.triangles.len() {
            format!(
                "{} triangles, the plan has {}",
                mesh.face_count(),
                self.triangles.len()
            )
        } else if let Some(f) =
            (0..self.triangles.len()).find(|&f| mesh.triangles()[f] != self.triangles[f])
        {
            format!(
                "triangle {f} is {:?}, the plan's is {:?}",
                mesh.triangles()[f],
                self.triangles[f]
            )
        } else if mesh.uvs().is_some() != self.has_uvs {
            "texture coordinates differ in presence".to_string()
        } else {
            return Ok(());
        };
        Err(RefineError::TopologyMismatch { reason })
    }

    fn fill(&self, mesh: &Mesh, nets: &mut PatchNets) {
        fill_nets(
            mesh,
            Some(&self.topology),
            &self.options.scheme,
            self.normal_mode(),
            self.options.tags.as_deref(),
            nets,
        );
    }

    /// The scheme options.
    pub fn options(&self) -> &SurfaceOptions {
        &self.options
    }
    /// The normal mode in effect.
    pub fn normal_mode(&self) -> NormalMode {
        self.options.normal_mode()
    }
    /// Edges, owners and neighbours of the coarse mesh.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }
    /// The coarse triangles this surface serves.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// Number of coarse triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }
    /// Number of coarse vertices a frame has.
    pub fn coarse_vertex_count(&self) -> usize {
        self.vertex_count
    }
    /// True when frames carry texture coordinates.
    pub fn has_uvs(&self) -> bool {
        self.has_uvs
    }
}
