//! The levels asked for: how a level divides an edge ([`Spacing`]), and per-edge, fractional
//! or LOD levels ([`Levels`], [`Lod`]); what a plan is built from, before any tiling.

use crate::names::{parse_name, Named, UnknownName};
use crate::tessellator;
use std::sync::Arc;

/// How a level divides a coarse edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum Spacing {
    /// The uniform grid pattern ([`Pattern::uniform`](crate::Pattern::uniform)); fractional levels round up and
    /// geomorph: level `f` draws the grid of `⌈f⌉` segments with its new points blended towards
    /// the coarser level's flat surface by `f − (⌈f⌉ − 1)`, so points move continuously with
    /// the level ([`super::morph`]). With one integer level everywhere this is the classic
    /// refinement, bit for bit.
    #[default]
    Grid,
    /// The tessellator's integer spacing: levels rounded up, clamped to `[1, 64]`.
    Equal,
    /// Fractional-odd spacing, levels clamped to `[1, 63]`: points move continuously.
    FractionalOdd,
    /// Fractional-even spacing, levels clamped to `[2, 64]`.
    FractionalEven,
}

impl Spacing {
    /// The tessellator's spacing, `None` for the grid.
    pub fn tessellator(self) -> Option<tessellator::Partitioning> {
        match self {
            Spacing::Grid => None,
            Spacing::Equal => Some(tessellator::Partitioning::Equal),
            Spacing::FractionalOdd => Some(tessellator::Partitioning::FractionalOdd),
            Spacing::FractionalEven => Some(tessellator::Partitioning::FractionalEven),
        }
    }
    /// `(minimum, maximum)` level: the tessellator's clamping range; the grid has `[1, ∞)`.
    pub fn range(self) -> (f32, f32) {
        match self.tessellator() {
            Some(s) => s.range(),
            None => (1.0, f32::INFINITY),
        }
    }
}

/// `grid`, `equal`, `fractional-odd`, `fractional-even`, parsed and printed as the other
/// names are ([`crate::names`]).
impl Named for Spacing {
    const WHAT: &'static str = "spacing";
    const ALL: &'static [Spacing] = &[
        Spacing::Grid,
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ];
    const NAMES: &'static [&'static str] = &["grid", "equal", "fractional-odd", "fractional-even"];
    fn name(&self) -> &'static str {
        match self {
            Spacing::Grid => "grid",
            Spacing::Equal => "equal",
            Spacing::FractionalOdd => "fractional-odd",
            Spacing::FractionalEven => "fractional-even",
        }
    }
    fn description(&self) -> &'static str {
        match self {
            Spacing::Grid => {
                "The uniform pattern: LEVEL equal segments per edge (fractional levels geomorph)"
            }
            Spacing::Equal => "Hardware tessellator, equal spacing (levels rounded up, 1 to 64)",
            Spacing::FractionalOdd => {
                "Hardware tessellator, fractional-odd spacing (levels 1 to 63)"
            }
            Spacing::FractionalEven => {
                "Hardware tessellator, fractional-even spacing (levels 2 to 64)"
            }
        }
    }
}

impl std::str::FromStr for Spacing {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Spacing, UnknownName> {
        parse_name(s)
    }
}

impl std::fmt::Display for Spacing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A camera for the view-dependent LOD functions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_deg: f32,
}

/// A level-of-detail function: each edge's level from that edge's data alone.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Lod {
    /// The smallest levels such that the flat refined triangles stay within `max_deviation`
    /// of the curved surface (chordal deviation, "linear deflection"): per edge from its
    /// boundary cubic's second differences, `n_e = ⌈√(3 M_e / (4 D))⌉`; per face an interior
    /// minimum from its net's second differences folded into the inner level.
    Tolerance { max_deviation: f32 },
    /// `pixels` per refined edge on a `width × height` image seen by `camera`: an edge of
    /// length `L` (its control polygon) at distance `d` from the eye covers about
    /// `L · (height / 2) / (d tan(fov / 2))` pixels.
    Screen {
        pixels: f32,
        camera: Camera,
        size: [u32; 2],
    },
    /// `max` segments up to distance `near` from the eye, falling linearly to 1 at `far`.
    Distance {
        near: f32,
        far: f32,
        max: f32,
        eye: [f32; 3],
    },
}

/// Levels of a refinement.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Levels {
    /// One level for every edge (fractional for the tessellator spacings).
    Uniform(f32),
    /// One level per unique edge, in [`Topology::edges`](crate::mesh::Topology::edges) order, and optionally a minimum inner
    /// level per face.
    PerEdge {
        edges: Arc<[f32]>,
        faces: Option<Arc<[f32]>>,
    },
    /// Levels computed from the plan's mesh by a LOD function when the plan is made, once: the
    /// plan's frames, moved or of other meshes, keep them (see [`Plan`](super::table::Plan)).
    Lod(Lod),
}

/// Biggest grid level the tolerance LOD asks for (it then meets `--max-memory`).
pub const MAX_LOD_GRID_LEVEL: f32 = 1024.0;

#[cfg(test)]
mod tests {
    #[test]
    fn spacing_names_round_trip() {
        crate::names::tests::round_trip::<super::Spacing>();
    }
}
