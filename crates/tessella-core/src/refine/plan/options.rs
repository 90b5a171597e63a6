//! What to refine into: the options a plan is built from.

use super::levels::{Levels, Spacing};
use super::surface::SurfaceOptions;
use crate::scheme::{NormalMode, Scheme};

/// Default cap on the output's size: 8 GiB.
pub const DEFAULT_MAX_OUTPUT_BYTES: u64 = 8 << 30;

/// What to refine into.
#[derive(Debug, Clone, PartialEq)]
pub struct RefineOptions {
    pub scheme: Scheme,
    /// Segments per coarse edge, the one field for every kind of level: one level for every
    /// edge ([`Levels::Uniform`]: whole, the classic refinement on the grid, or fractional),
    /// per edge ([`Levels::PerEdge`]) or from a LOD function ([`Levels::Lod`]). Anything but a
    /// whole uniform level on the grid makes an adaptive plan (see
    /// [`Tiling`](crate::refine::Tiling)).
    pub levels: Levels,
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
}

impl RefineOptions {
    /// `level` segments on every edge of the grid, welded output, the scheme's default
    /// normals, the default size cap.
    pub fn new(scheme: Scheme, level: u32) -> RefineOptions {
        RefineOptions {
            scheme,
            levels: Levels::Uniform(level as f32),
            normals: None,
            weld: true,
            max_output_bytes: DEFAULT_MAX_OUTPUT_BYTES,
            tags: None,
            spacing: Spacing::Grid,
        }
    }
    /// Sets the spacing ([`Spacing::Grid`] by default).
    pub fn with_spacing(mut self, spacing: Spacing) -> Self {
        self.spacing = spacing;
        self
    }
    /// Sets the levels: one for every edge, per edge, or from a LOD function.
    pub fn with_levels(mut self, levels: Levels) -> Self {
        self.levels = levels;
        self
    }
    /// Sets one level for every edge: a whole level with [`Spacing::Grid`] is the classic
    /// integer refinement, bit for bit; a fractional one geomorphs on the grid, and a
    /// tessellator spacing clamps it to its range.
    ///
    /// ```
    /// use tessella_core::refine::{Levels, Spacing};
    /// use tessella_core::{RefineOptions, Scheme};
    /// let whole = RefineOptions::new(Scheme::Pn, 1).with_uniform_level(6.0);
    /// assert_eq!(whole.uniform_grid_level(), Some(6));
    /// let morph = RefineOptions::new(Scheme::Pn, 1).with_uniform_level(5.5);
    /// assert_eq!((&morph.levels, morph.uniform_grid_level()), (&Levels::Uniform(5.5), None));
    /// let odd = RefineOptions::new(Scheme::Pn, 1)
    ///     .with_spacing(Spacing::FractionalOdd)
    ///     .with_uniform_level(3.0);
    /// assert_eq!(odd.uniform_grid_level(), None);
    /// ```
    pub fn with_uniform_level(mut self, level: f64) -> Self {
        self.levels = Levels::Uniform(level as f32);
        self
    }
    /// Sets the size cap in bytes.
    pub fn with_max_output_bytes(mut self, bytes: u64) -> Self {
        self.max_output_bytes = bytes;
        self
    }
    /// The uniform integer grid level these options amount to, if they do (the classic,
    /// fastest path): grid spacing and [`Levels::Uniform`] of a whole number (0 included, which
    /// plans refuse with [`RefineError::LevelZero`](crate::RefineError::LevelZero)).
    pub fn uniform_grid_level(&self) -> Option<u32> {
        match (&self.levels, self.spacing) {
            (Levels::Uniform(x), Spacing::Grid)
                if x.fract() == 0.0 && *x >= 0.0 && *x <= u32::MAX as f32 =>
            {
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
