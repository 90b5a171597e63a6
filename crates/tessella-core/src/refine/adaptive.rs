//! Adaptive refinement: a pattern per coarse face from per-edge levels (docs/formulas.md,
//! "Adaptive layout").
//!
//! Every unique coarse edge gets a level from its own data only ([`Levels`], [`Lod`]), so the
//! two faces sharing it agree on its points. A face's pattern is made from its three edge
//! levels and an inner level (the largest of the three, raised by a per-face minimum when one
//! is given):
//!
//! - [`Spacing::Grid`]: the uniform grid of the inner level `N`, each edge's boundary points
//!   moved to the nearest point of that edge's own `n_e`-segment layout (step `s` of `N` goes to
//!   `round(s n_e / N)`, monotone), and the triangles that became degenerate dropped; fractional
//!   levels round up and geomorph ([`super::morph`]): points move continuously from the
//!   coarser level's flat surface as the level grows;
//! - [`Spacing::Equal`], [`Spacing::FractionalOdd`], [`Spacing::FractionalEven`]: the hardware
//!   tessellator's pattern ([`crate::tessellator`]) with the edge levels as outer levels.
//!
//! Edge points are evaluated canonically ([`super::canonical`]), so a vertex on a shared edge
//! has the same bits from both faces, welded or soup.

#![allow(clippy::needless_range_loop)] // corners, edges and axes index several tables

use super::canonical::{self, EdgeWeights};
use super::output::Sink;
use super::stream::Piece;
use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::pattern::{Pattern, PointClass};
use crate::scheme::{NormalMode, PatchNets};
use crate::stencil::Stencil;
use crate::tessellator::{self, TessLevels};
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// How a level divides a coarse edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Spacing {
    /// The uniform grid pattern ([`Pattern::uniform`]); fractional levels round up and
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
    /// Every spacing, in the CLI's order.
    pub const ALL: [Spacing; 4] = [
        Spacing::Grid,
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ];
    /// The tessellator's spacing, `None` for the grid.
    pub fn tessellator(self) -> Option<tessellator::Spacing> {
        match self {
            Spacing::Grid => None,
            Spacing::Equal => Some(tessellator::Spacing::Equal),
            Spacing::FractionalOdd => Some(tessellator::Spacing::FractionalOdd),
            Spacing::FractionalEven => Some(tessellator::Spacing::FractionalEven),
        }
    }
    /// The name on the command line: `grid`, `equal`, `fractional-odd`, `fractional-even`.
    pub fn name(self) -> &'static str {
        match self {
            Spacing::Grid => "grid",
            Spacing::Equal => "equal",
            Spacing::FractionalOdd => "fractional-odd",
            Spacing::FractionalEven => "fractional-even",
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

impl std::str::FromStr for Spacing {
    type Err = String;
    fn from_str(s: &str) -> Result<Spacing, String> {
        Spacing::ALL
            .into_iter()
            .find(|x| x.name() == s)
            .ok_or_else(|| {
                format!("unknown spacing {s:?}; expected grid, equal, fractional-odd or fractional-even")
            })
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
pub enum Levels {
    /// One level for every edge (fractional for the tessellator spacings).
    Uniform(f32),
    /// One level per unique edge, in [`Topology::edges`] order, and optionally a minimum inner
    /// level per face.
    PerEdge {
        edges: Arc<[f32]>,
        faces: Option<Arc<[f32]>>,
    },
    /// Levels computed from the plan's mesh by a LOD function when the plan is made.
    Lod(Lod),
}

/// Biggest grid level the tolerance LOD asks for (it then meets `--max-memory`).
pub const MAX_LOD_GRID_LEVEL: f32 = 1024.0;

/// Morph factors of a geomorphing grid tile, each in `(0, 1]` (1: no morph): per edge and for
/// the interior ([`super::morph`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Morph {
    pub outer: [f64; 3],
    pub inner: f64,
}

/// One distinct pattern of an adaptive plan, with its weights and its points by role.
#[derive(Debug, Clone)]
pub struct Tile {
    /// Per-edge levels as used (tessellator spacings: after clamping; grid: as given, the
    /// pattern rounding them up) and the inner level.
    pub outer: [f32; 3],
    pub inner: f32,
    pub pattern: Pattern,
    /// The pattern's weights (geomorphing grid tiles: the morphed weights).
    pub stencil: Stencil,
    /// Grid tiles with a fractional level: the morph factors (`None`: integer levels, plain
    /// weights).
    pub morph: Option<Morph>,
    /// Pattern point of corner `c`.
    pub corners: [u32; 3],
    /// Pattern points inside edge `k`, by step from corner `k` (`edges[k][s - 1]` is step `s`).
    pub edges: [Vec<u32>; 3],
    /// Interior pattern points, in interior order.
    pub interior: Vec<u32>,
}

impl Tile {
    /// Canonical weights ([`canonical`]) of step `step` (from corner `k`) of edge `k`, whose
    /// canonical start is corner `k` when `forward`: the plain weights at the point's exact
    /// barycentrics, or the morphed ones ([`super::morph::edge_weights`]). Every backend that
    /// evaluates edges canonically takes its weights from here, so shared points keep their bits.
    pub fn edge_weights(&self, k: usize, step: u32, forward: bool) -> EdgeWeights {
        let n = self.edges[k].len() as u32 + 1;
        match self.morph {
            Some(m) if m.outer[k] < 1.0 => {
                let s = if forward { step } else { n - step };
                super::morph::edge_weights(n, s, m.outer[k])
            }
            _ => {
                let l = self.pattern.points[self.edges[k][step as usize - 1] as usize];
                let (c0, c1) = (k, (k + 1) % 3);
                let (a, b) = if forward {
                    (l[c0], l[c1])
                } else {
                    (l[c1], l[c0])
                };
                EdgeWeights::new(a, b)
            }
        }
    }
}

/// The per-face patterns of an adaptive plan and where their points go. Offsets are vertex
/// slots of the plan's output.
#[derive(Debug, Clone)]
pub struct Tiling {
    pub spacing: Spacing,
    /// Level of each unique edge after clamping ([`Topology::edges`] order; grid: as given,
    /// fractional levels geomorph on `⌈level⌉` segments).
    pub edge_levels: Vec<f32>,
    /// Segments of each unique edge.
    pub edge_segments: Vec<u32>,
    /// Welded: first slot of edge `e`'s `segments − 1` vertices, from the lower vertex index.
    pub edge_offset: Vec<u64>,
    /// Tile index of each face.
    pub face_tile: Vec<u32>,
    /// Welded: first slot of each face's interior points; soup: of each face's points.
    pub face_offset: Vec<u64>,
    /// First refined triangle of each face (one more entry: the total).
    pub triangle_offset: Vec<u64>,
    pub tiles: Vec<Tile>,
}

impl Tiling {
    /// The tile of face `f`.
    pub fn tile(&self, f: usize) -> &Tile {
        &self.tiles[self.face_tile[f] as usize]
    }
    /// Largest segment count of any edge or inner level.
    pub fn max_level(&self) -> u32 {
        self.tiles
            .iter()
            .map(|t| t.pattern.level)
            .max()
            .unwrap_or(1)
    }
}

fn bad(msg: String) -> RefineError {
    RefineError::BadLevels(msg)
}

/// Checks one level: a finite number above 0.
pub fn check_level(what: &str, x: f32) -> Result<(), RefineError> {
    if !x.is_finite() || x <= 0.0 {
        return Err(bad(format!(
            "{what} is {x}; levels must be finite numbers above 0"
        )));
    }
    Ok(())
}

/// Checks per-edge levels (one per unique edge of `ne`) and optional per-face minimum inner
/// levels (one per face of `nf`): the right counts, each finite and above 0.
pub fn check_per_edge(
    ne: usize,
    nf: usize,
    edges: &[f32],
    faces: Option<&[f32]>,
) -> Result<(), RefineError> {
    if edges.len() != ne {
        return Err(bad(format!(
            "{} edge levels for a mesh of {ne} unique edges",
            edges.len()
        )));
    }
    for (e, &x) in edges.iter().enumerate() {
        check_level(&format!("the level of edge {e}"), x)?;
    }
    if let Some(f) = faces {
        if f.len() != nf {
            return Err(bad(format!(
                "{} face levels for a mesh of {nf} triangles",
                f.len()
            )));
        }
        for (i, &x) in f.iter().enumerate() {
            check_level(&format!("the inner level of face {i}"), x)?;
        }
    }
    Ok(())
}

/// The per-edge and per-face levels `levels` gives on `mesh` (`nets`: the mesh's control
/// nets, for the tolerance LOD).
pub fn resolve_levels(
    mesh: &Mesh,
    topology: &Topology,
    nets: &PatchNets,
    levels: &Levels,
) -> Result<(Vec<f32>, Option<Vec<f32>>), RefineError> {
    let ne = topology.edges.len();
    match levels {
        Levels::Uniform(x) => {
            check_level("the level", *x)?;
            Ok((vec![*x; ne], None))
        }
        Levels::PerEdge { edges, faces } => {
            check_per_edge(ne, mesh.face_count(), edges, faces.as_deref())?;
            Ok((edges.to_vec(), faces.as_ref().map(|f| f.to_vec())))
        }
        Levels::Lod(lod) => super::lod::levels(mesh, topology, nets, lod),
    }
}

/// Segments of a grid level: rounded up, at least 1.
pub fn grid_segments(x: f32) -> u32 {
    (x.ceil() as f64).clamp(1.0, u32::MAX as f64 / 4.0) as u32
}

/// Upper bounds of `(points, triangles)` of one face's pattern, before building it.
fn bound(spacing: Spacing, outer: [f32; 3], inner: f32) -> (u64, u64) {
    match spacing.tessellator() {
        None => {
            let n = grid_segments(inner.max(outer[0]).max(outer[1]).max(outer[2]));
            (Pattern::point_count(n), n as u64 * n as u64)
        }
        Some(s) => {
            let (_, hi) = s.range();
            let m = inner
                .max(outer[0])
                .max(outer[1])
                .max(outer[2])
                .min(hi)
                .ceil() as u64
                + 1;
            ((m + 1) * (m + 2), 2 * m * m)
        }
    }
}

/// Builds the pattern of one face.
fn build_tile(spacing: Spacing, outer: [f32; 3], inner: f32, basis: crate::Basis) -> Tile {
    let mut morph = None;
    let pattern = match spacing.tessellator() {
        None => grid_pattern(outer.map(grid_segments), grid_segments(inner)),
        Some(s) => tessellator::tessellate(s, gl_levels(outer, inner)),
    };
    let mut corners = [0u32; 3];
    let mut edges: [Vec<(u32, u32)>; 3] = Default::default();
    let mut interior = Vec::new();
    for (p, class) in pattern.classes.iter().enumerate() {
        match *class {
            PointClass::Corner { corner } => corners[corner as usize] = p as u32,
            PointClass::Edge { edge, step } => edges[edge as usize].push((step, p as u32)),
            PointClass::Interior { .. } => interior.push(p as u32),
        }
    }
    let edges: [Vec<u32>; 3] = edges.map(|mut e| {
        e.sort_unstable();
        e.into_iter().map(|(_, p)| p).collect()
    });
    if spacing == Spacing::Grid {
        let segments = edges.each_ref().map(|e| e.len() as u32 + 1);
        let m = Morph {
            outer: [0, 1, 2].map(|k| super::morph::factor(outer[k], segments[k])),
            inner: super::morph::factor(inner, pattern.level),
        };
        if m.inner < 1.0 || m.outer.iter().any(|&a| a < 1.0) {
            morph = Some(m);
        }
    }
    let stencil = match morph {
        Some(m) => super::morph::grid_stencil(
            &pattern,
            basis,
            edges.each_ref().map(|e| e.len() as u32 + 1),
            m.outer,
            m.inner,
        ),
        None => Stencil::new(&pattern, basis),
    };
    Tile {
        outer,
        inner,
        pattern,
        stencil,
        morph,
        corners,
        edges,
        interior,
    }
}

/// Where step `step` of a level-`big` grid edge goes on the edge's own `n`-segment layout: the
/// nearest step, ties up (monotone in `step`, so the boundary keeps its order).
pub fn snap_step(step: u32, n: u32, big: u32) -> u32 {
    ((2 * step as u64 * n as u64 + big as u64) / (2 * big as u64)) as u32
}

/// The hardware tessellator's levels of a face with edge levels `outer` (our edge order) and
/// inner level `inner`: GL's `outer[k]` is the edge opposite corner `k`, our edges 1, 2, 0.
pub fn gl_levels(outer: [f32; 3], inner: f32) -> TessLevels {
    TessLevels {
        inner,
        outer: [outer[1], outer[2], outer[0]],
    }
}

/// The grid pattern of level `n_inner` (at least the largest edge level) with edge `k`'s
/// boundary points snapped to its own `n[k]`-segment layout; degenerate triangles dropped.
pub fn grid_pattern(n: [u32; 3], n_inner: u32) -> Pattern {
    let big = n_inner.max(n[0]).max(n[1]).max(n[2]).max(1);
    let uniform = Pattern::uniform(big);
    if n == [big; 3] {
        return uniform;
    }
    let mut points = Vec::new();
    let mut classes = Vec::new();
    let mut map = vec![0u32; uniform.points.len()];
    let mut corner_at = [0u32; 3];
    let mut interior = 0;
    // Corners and interior points keep their place.
    for (p, class) in uniform.classes.iter().enumerate() {
        match *class {
            PointClass::Corner { corner } => {
                corner_at[corner as usize] = points.len() as u32;
                map[p] = points.len() as u32;
                points.push(uniform.points[p]);
                classes.push(*class);
            }
            PointClass::Interior { .. } => {
                map[p] = points.len() as u32;
                points.push(uniform.points[p]);
                classes.push(PointClass::Interior { index: interior });
                interior += 1;
            }
            PointClass::Edge { .. } => {}
        }
    }
    // Each edge's own layout.
    let mut edge_first = [0u32; 3];
    for k in 0..3 {
        edge_first[k] = points.len() as u32;
        let (c0, c1) = (k, (k + 1) % 3);
        let ne = n[k];
        for s in 1..ne {
            let mut l = [0.0f64; 3];
            l[c0] = (ne - s) as f64 / ne as f64;
            l[c1] = s as f64 / ne as f64;
            points.push(l);
            classes.push(PointClass::Edge {
                edge: k as u8,
                step: s,
            });
        }
    }
    for (p, class) in uniform.classes.iter().enumerate() {
        if let PointClass::Edge { edge, step } = *class {
            let k = edge as usize;
            let ne = n[k] as u64;
            let s = snap_step(step, n[k], big);
            map[p] = if s == 0 {
                corner_at[k]
            } else if s as u64 == ne {
                corner_at[(k + 1) % 3]
            } else {
                edge_first[k] + s - 1
            };
        }
    }
    let triangles = uniform
        .triangles
        .iter()
        .map(|t| t.map(|p| map[p as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    Pattern {
        level: big,
        points,
        triangles,
        classes,
    }
}

/// Edge levels as a spacing uses them: clamped as the hardware does (tessellator spacings;
/// equal spacing also rounds up). The grid keeps fractional levels: its pattern rounds them up
/// and its stencil morphs.
pub fn clamp_edge_levels(spacing: Spacing, mut levels: Vec<f32>) -> Vec<f32> {
    if let Some(s) = spacing.tessellator() {
        let (lo, hi) = s.range();
        for x in &mut levels {
            *x = x.clamp(lo, hi);
            if spacing == Spacing::Equal {
                *x = x.ceil();
            }
        }
    }
    levels
}

/// Face `f`'s edge levels in its own edge order and its inner level.
pub fn face_levels(
    topology: &Topology,
    f: usize,
    edge_levels: &[f32],
    faces: Option<&[f32]>,
) -> ([f32; 3], f32) {
    let outer = topology.face_edges[f].map(|e| edge_levels[e as usize]);
    let mut inner = outer[0].max(outer[1]).max(outer[2]);
    if let Some(fl) = faces {
        inner = inner.max(fl[f]);
    }
    (outer, inner)
}

/// Everything an adaptive plan needs, after the size check.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_tiling(
    mesh: &Mesh,
    topology: &Topology,
    spacing: Spacing,
    edge_levels: Vec<f32>,
    faces: Option<Vec<f32>>,
    basis: crate::Basis,
    weld: bool,
    uvs: bool,
    max_bytes: u64,
) -> Result<Tiling, RefineError> {
    let edge_levels = clamp_edge_levels(spacing, edge_levels);
    let nf = mesh.face_count();
    // Size check from upper bounds, before building any pattern.
    let mut bound_points = 0u64;
    let mut bound_tris = 0u64;
    for f in 0..nf {
        let (outer, inner) = face_levels(topology, f, &edge_levels, faces.as_deref());
        let (p, t) = bound(spacing, outer, inner);
        bound_points = bound_points.saturating_add(p);
        bound_tris = bound_tris.saturating_add(t);
    }
    let per_vertex = 24 + if uvs { 8 } else { 0 };
    let bytes = bound_points
        .saturating_mul(per_vertex)
        .saturating_add(bound_tris.saturating_mul(12));
    if bytes > max_bytes {
        return Err(RefineError::TooLarge {
            level: edge_levels.iter().fold(1.0f32, |a, &b| a.max(b)).ceil() as u32,
            faces: nf,
            vertices: bound_points,
            triangles: bound_tris,
            bytes,
            bytes_human: crate::error::human_bytes(bytes),
            limit: max_bytes,
            limit_human: crate::error::human_bytes(max_bytes),
        });
    }
    // Distinct patterns, keyed by their levels' bits.
    let mut keys: HashMap<([u32; 3], u32), u32> = HashMap::new();
    let mut tiles = Vec::new();
    let mut face_tile = Vec::with_capacity(nf);
    for f in 0..nf {
        let (outer, inner) = face_levels(topology, f, &edge_levels, faces.as_deref());
        let key = (outer.map(f32::to_bits), inner.to_bits());
        let id = *keys.entry(key).or_insert_with(|| {
            tiles.push(build_tile(spacing, outer, inner, basis));
            tiles.len() as u32 - 1
        });
        face_tile.push(id);
    }
    // Every edge's segment count, from any face using it (both agree by construction).
    let mut edge_segments = vec![0u32; topology.edges.len()];
    for f in 0..nf {
        let tile = &tiles[face_tile[f] as usize];
        for k in 0..3 {
            let e = topology.face_edges[f][k] as usize;
            let seg = tile.edges[k].len() as u32 + 1;
            debug_assert!(edge_segments[e] == 0 || edge_segments[e] == seg);
            edge_segments[e] = seg;
        }
    }
    let mut edge_offset = Vec::with_capacity(edge_segments.len());
    let mut face_offset = Vec::with_capacity(nf);
    let mut at = if weld { mesh.vertex_count() as u64 } else { 0 };
    if weld {
        for &s in &edge_segments {
            edge_offset.push(at);
            at += s.max(1) as u64 - 1;
        }
    }
    for &t in &face_tile {
        face_offset.push(at);
        let tile = &tiles[t as usize];
        at += if weld {
            tile.interior.len()
        } else {
            tile.pattern.points.len()
        } as u64;
    }
    face_offset.push(at);
    let mut triangle_offset = Vec::with_capacity(nf + 1);
    let mut tris = 0u64;
    for &t in &face_tile {
        triangle_offset.push(tris);
        tris += tiles[t as usize].pattern.triangles.len() as u64;
    }
    triangle_offset.push(tris);
    Ok(Tiling {
        spacing,
        edge_levels,
        edge_segments,
        edge_offset,
        face_tile,
        face_offset,
        triangle_offset,
        tiles,
    })
}

impl Tiling {
    /// Output vertex count (the last face offset).
    pub fn vertex_count(&self) -> u64 {
        *self.face_offset.last().unwrap_or(&0)
    }
    /// Output triangle count.
    pub fn triangle_count(&self) -> u64 {
        *self.triangle_offset.last().unwrap_or(&0)
    }
}

/// One frame's vertices on an adaptive tiling.
pub(crate) struct AdaptiveJob<'a> {
    pub mesh: &'a Mesh,
    pub topology: &'a Topology,
    pub tiling: &'a Tiling,
    pub nets: &'a PatchNets,
    pub weld: bool,
}

/// Splits `sink` into consecutive runs of the given lengths.
fn runs<'a>(mut sink: Sink<'a>, lens: impl Iterator<Item = usize>) -> Vec<Sink<'a>> {
    let mut out = Vec::new();
    for len in lens {
        let (head, tail) = sink.split_at(len);
        out.push(head);
        sink = tail;
    }
    out
}

impl AdaptiveJob<'_> {
    pub fn vertices(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        match self.nets.basis.len() {
            10 => self.vertices_k::<10>(sink, progress),
            21 => self.vertices_k::<21>(sink, progress),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
    }

    fn point<const K: usize>(&self, tile: &Tile, f: usize, p: u32) -> ([f32; 3], [f32; 3]) {
        super::eval_point::<K>(
            tile.stencil.row(p as usize),
            self.nets.patch_points(f),
            self.nets.patch_normals(f),
            self.nets.normal_mode,
        )
    }

    fn uv(&self, tile: &Tile, f: usize, p: u32) -> Option<[f32; 2]> {
        let uv = self.mesh.uvs()?;
        let t = self.mesh.triangles()[f];
        let l = tile.pattern.points[p as usize].map(|x| x as f32);
        let c = t.map(|v| uv[v as usize]);
        Some([
            l[0] * c[0][0] + l[1] * c[1][0] + l[2] * c[2][0],
            l[0] * c[0][1] + l[1] * c[1][1] + l[2] * c[2][1],
        ])
    }

    /// Writes pattern point `p` (step `step` from corner `k` of edge `k`) of face `f`
    /// canonically into `slot`.
    #[allow(clippy::too_many_arguments)]
    fn edge_point<const K: usize>(
        &self,
        tile: &Tile,
        f: usize,
        k: usize,
        fwd: bool,
        (step, p): (usize, u32),
        sink: &mut Sink,
        slot: usize,
    ) {
        let w = tile.edge_weights(k, step as u32, fwd);
        let points = self.nets.patch_points(f);
        let c = canonical::canonical_points(self.nets.basis, points, k, fwd);
        sink.set_position(slot, canonical::position(&w, &c));
        if sink.wants_normals() {
            let net = (self.nets.normal_mode != NormalMode::Real)
                .then(|| {
                    let cn = canonical::canonical_normals(self.nets.patch_normals(f), k, fwd);
                    canonical::net_normal(&w, &cn)
                })
                .flatten();
            sink.set_normal(slot, net.unwrap_or_else(|| self.point::<K>(tile, f, p).1));
        }
        if sink.wants_uvs() {
            if let Some(uv) = self.uv(tile, f, p) {
                sink.set_uv(slot, uv);
            }
        }
    }

    fn full_point<const K: usize>(
        &self,
        tile: &Tile,
        f: usize,
        p: u32,
        sink: &mut Sink,
        slot: usize,
    ) {
        let (pos, n) = self.point::<K>(tile, f, p);
        sink.set_position(slot, pos);
        if sink.wants_normals() {
            sink.set_normal(slot, n);
        }
        if sink.wants_uvs() {
            if let Some(uv) = self.uv(tile, f, p) {
                sink.set_uv(slot, uv);
            }
        }
    }

    fn vertices_k<const K: usize>(&self, sink: Sink, progress: &(dyn Fn(u64) + Sync)) {
        let (nv, ne, nf) = (
            self.mesh.vertex_count(),
            self.topology.edges.len(),
            self.mesh.face_count(),
        );
        if !self.weld {
            return self.faces_k::<K>(0..nf, sink, progress);
        }
        let (corners, rest) = sink.split_at(nv);
        let edge_total = (self.tiling.face_offset[0] - nv as u64) as usize;
        let (edges, interiors) = rest.split_at(edge_total);
        self.corners_k::<K>(0..nv, corners);
        self.edges_k::<K>(0..ne, edges);
        self.interiors_k::<K>(0..nf, interiors, progress);
    }

    /// The vertices of one piece of the layout (`sink` holds just that piece's slots).
    pub fn piece(&self, piece: &Piece, sink: Sink) {
        match self.nets.basis.len() {
            10 => self.piece_k::<10>(piece, sink),
            21 => self.piece_k::<21>(piece, sink),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
    }

    fn piece_k<const K: usize>(&self, piece: &Piece, sink: Sink) {
        match piece.clone() {
            Piece::Corners(r) => self.corners_k::<K>(r, sink),
            Piece::Edges(r) => self.edges_k::<K>(r, sink),
            Piece::Interiors(r) => self.interiors_k::<K>(r, sink, &|_| {}),
            Piece::Faces(r) => self.faces_k::<K>(r, sink, &|_| {}),
        }
    }

    /// Soup: the whole patterns of faces `r`, one after the other.
    fn faces_k<const K: usize>(
        &self,
        r: Range<usize>,
        sink: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let (tiling, mesh, pid) = (self.tiling, self.mesh, &self.topology.position_ids);
        let lens = r.clone().map(|f| tiling.tile(f).pattern.points.len());
        runs(sink, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let f = r.start + i;
                let tile = tiling.tile(f);
                let t = mesh.triangles()[f];
                for p in 0..tile.pattern.points.len() as u32 {
                    self.full_point::<K>(tile, f, p, &mut sink, p as usize);
                }
                for c in 0..3 {
                    sink.set_position(tile.corners[c] as usize, mesh.positions()[t[c] as usize]);
                }
                for k in 0..3 {
                    let fwd = canonical::forward(t, k, pid);
                    for (s, &p) in tile.edges[k].iter().enumerate() {
                        let at = (s + 1, p);
                        self.edge_point::<K>(tile, f, k, fwd, at, &mut sink, p as usize);
                    }
                }
                progress(1);
            });
    }

    /// Welded: coarse vertices `r`, evaluated on their owner faces.
    fn corners_k<const K: usize>(&self, r: Range<usize>, mut corners: Sink) {
        let (tiling, mesh, topo) = (self.tiling, self.mesh, self.topology);
        for (i, v) in r.enumerate() {
            match topo.vertex_owner[v] {
                Some((f, c)) => {
                    let tile = tiling.tile(f as usize);
                    let p = tile.corners[c as usize];
                    self.full_point::<K>(tile, f as usize, p, &mut corners, i);
                }
                None => {
                    if corners.wants_normals() {
                        corners.set_normal(i, mesh.normals()[v]);
                    }
                    if let (true, Some(uv)) = (corners.wants_uvs(), mesh.uvs()) {
                        corners.set_uv(i, uv[v]);
                    }
                }
            }
            corners.set_position(i, mesh.positions()[v]);
        }
    }

    /// Welded: the inner points of unique edges `r`, from their lower vertex index.
    fn edges_k<const K: usize>(&self, r: Range<usize>, edges: Sink) {
        let (tiling, mesh, topo) = (self.tiling, self.mesh, self.topology);
        let lens = r
            .clone()
            .map(|e| tiling.edge_segments[e].max(1) as usize - 1);
        runs(edges, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let e = r.start + i;
                let (f, k) = topo.edge_owner[e];
                let (f, k) = (f as usize, k as usize);
                let tile = tiling.tile(f);
                let t = mesh.triangles()[f];
                let fwd = canonical::forward(t, k, &topo.position_ids);
                let by_index = t[k] == topo.edges[e][0];
                let m = tile.edges[k].len();
                for (s, &p) in tile.edges[k].iter().enumerate() {
                    let slot = if by_index { s } else { m - 1 - s };
                    self.edge_point::<K>(tile, f, k, fwd, (s + 1, p), &mut sink, slot);
                }
            });
    }

    /// Welded: the interior points of faces `r`.
    fn interiors_k<const K: usize>(
        &self,
        r: Range<usize>,
        interiors: Sink,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let tiling = self.tiling;
        let lens = r.clone().map(|f| tiling.tile(f).interior.len());
        runs(interiors, lens)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut sink)| {
                let f = r.start + i;
                let tile = tiling.tile(f);
                for (i, &p) in tile.interior.iter().enumerate() {
                    self.full_point::<K>(tile, f, p, &mut sink, i);
                }
                progress(1);
            });
    }
}

/// The triangles of an adaptive tiling (they depend on the plan only).
pub(crate) struct AdaptiveIndex<'a> {
    pub triangles: &'a [[u32; 3]],
    pub topology: &'a Topology,
    pub tiling: &'a Tiling,
    pub weld: bool,
}

impl AdaptiveIndex<'_> {
    /// Output slot of each pattern point of face `f`.
    pub fn slots(&self, f: usize, out: &mut Vec<u32>) {
        let tile = self.tiling.tile(f);
        out.clear();
        out.resize(tile.pattern.points.len(), 0);
        let base = self.tiling.face_offset[f] as u32;
        if !self.weld {
            for (p, o) in out.iter_mut().enumerate() {
                *o = base + p as u32;
            }
            return;
        }
        let t = self.triangles[f];
        for c in 0..3 {
            out[tile.corners[c] as usize] = t[c];
        }
        for k in 0..3 {
            let e = self.topology.face_edges[f][k] as usize;
            let by_index = t[k] == self.topology.edges[e][0];
            let m = tile.edges[k].len();
            let eb = self.tiling.edge_offset[e] as u32;
            for (s, &p) in tile.edges[k].iter().enumerate() {
                out[p as usize] = eb + if by_index { s } else { m - 1 - s } as u32;
            }
        }
        for (i, &p) in tile.interior.iter().enumerate() {
            out[p as usize] = base + i as u32;
        }
    }

    /// Writes every refined triangle.
    pub fn indices<I: super::IndexInt>(&self, out: &mut [[I; 3]], progress: &(dyn Fn(u64) + Sync)) {
        self.face_indices(0..self.triangles.len(), out, progress);
    }

    /// Writes the refined triangles of faces `faces` (from `triangle_offset[faces.start]` to
    /// `triangle_offset[faces.end]`) into `out`, exactly that long.
    pub fn face_indices<I: super::IndexInt>(
        &self,
        faces: Range<usize>,
        out: &mut [[I; 3]],
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let tiling = self.tiling;
        let mut chunks = Vec::with_capacity(faces.len());
        let mut rest = out;
        for f in faces.clone() {
            let n = tiling.tile(f).pattern.triangles.len();
            let (head, tail) = rest.split_at_mut(n);
            chunks.push(head);
            rest = tail;
        }
        chunks
            .into_par_iter()
            .enumerate()
            .for_each_init(Vec::new, |map, (i, tris)| {
                let f = faces.start + i;
                self.slots(f, map);
                for (dst, src) in tris.iter_mut().zip(&tiling.tile(f).pattern.triangles) {
                    *dst = src.map(|p| I::from_index(map[p as usize]));
                }
                progress(1);
            });
    }

    /// Each output vertex of `piece`'s face and barycentrics (see `Plan::origin`): a shared
    /// (welded) vertex is named by the face that owns (evaluates) it, as in the uniform layout.
    pub fn piece_origin(&self, piece: &Piece, faces: &mut [u32], bary: &mut [[f32; 3]]) {
        let (topo, tiling) = (self.topology, self.tiling);
        let l = |f: usize, p: u32| tiling.tile(f).pattern.points[p as usize].map(|x| x as f32);
        let mut slots = faces.iter_mut().zip(bary.iter_mut());
        let mut put = |face: u32, b: [f32; 3]| {
            let (f, slot) = slots.next().expect("a slot for each vertex of the piece");
            (*f, *slot) = (face, b);
        };
        match piece.clone() {
            Piece::Corners(r) => {
                for v in r {
                    match topo.vertex_owner[v] {
                        Some((f, c)) => put(
                            f,
                            l(f as usize, tiling.tile(f as usize).corners[c as usize]),
                        ),
                        None => put(super::NO_FACE, [1.0, 0.0, 0.0]),
                    }
                }
            }
            Piece::Edges(r) => {
                for e in r {
                    let (f, k) = topo.edge_owner[e];
                    let (fu, k) = (f as usize, k as usize);
                    let points = &tiling.tile(fu).edges[k];
                    let by_index = self.triangles[fu][k] == topo.edges[e][0];
                    let m = points.len();
                    for j in 0..m {
                        let s = if by_index { j } else { m - 1 - j };
                        put(f, l(fu, points[s]));
                    }
                }
            }
            Piece::Interiors(r) => {
                for f in r {
                    for &p in &tiling.tile(f).interior {
                        put(f as u32, l(f, p));
                    }
                }
            }
            Piece::Faces(r) => {
                for f in r {
                    for p in 0..tiling.tile(f).pattern.points.len() as u32 {
                        put(f as u32, l(f, p));
                    }
                }
            }
        }
    }
}
