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
    /// (an adaptive plan, see [`Tiling`](crate::refine::Tiling); `level` is then ignored). `Uniform` of an integer
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
