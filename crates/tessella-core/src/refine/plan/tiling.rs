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

use super::canonical::EdgeWeights;
use super::levels::{Levels, Spacing};
use crate::error::RefineError;
use crate::mesh::{Mesh, Topology};
use crate::pattern::{Pattern, PointClass};
use crate::scheme::PatchNets;
use crate::stencil::Stencil;
use crate::tessellator::{self, TessLevels};
use std::collections::HashMap;

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
    /// Canonical weights ([`canonical`](crate::refine::canonical)) of step `step` (from corner `k`) of edge `k`, whose
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
    super::grid_point::snap_step_of(step, n, big)
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
