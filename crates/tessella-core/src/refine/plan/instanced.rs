//! Adaptive levels drawn with index buffers built once: the per-frame data of an instanced
//! renderer whose levels change every frame (tessella-gpu's `AdaptiveRenderer`).
//!
//! An adaptive plan ([`Tiling`](crate::refine::Tiling)) builds a pattern and a stencil per distinct set of
//! levels; when the levels change every frame, so do those. Here instead:
//!
//! - **Parts, built once per spacing ([`PartTable`]).** Tessellator spacings: the strips and
//!   interiors of [`crate::tessellator::parts`] for every layout shape (their topology depends on
//!   integer point counts and parities only), and the one-triangle pattern. Grid: the uniform grid
//!   of each level `N` up to [`MAX_GRID_LEVEL`]. Triangles hold point codes, not stencil rows.
//! - **Per frame, O(coarse) ([`frame_instances`]).** Per face a record of [`RECORD_WORDS`]
//!   words: its four rulers (tessellator: the fixed-point constants that place its points), or
//!   its edge segment counts, grid level and geomorph factors (grid); and which of its edges
//!   run canonically. Per part drawn, the instances (face and side) that draw it.
//!
//! The vertex shader turns a code into a barycentric point with the face's record, evaluates the
//! basis there and sums the control net (the weights are no longer a table: they follow the
//! face's fractional levels). The positions are those of [`Tiling`](crate::refine::Tiling)'s patterns: the
//! tessellator's 16.16 placement exactly; the grid's edge points snapped to each edge's own
//! layout, where grid triangles that become degenerate stay in the index buffer with zero area
//! (the rasteriser draws nothing for them) instead of being dropped. Edge points are
//! evaluated from the edge's own data in canonical direction, so both faces agree bit for bit.

use super::canonical;
use super::levels::Spacing;
use super::morph;
use super::tiling::{check_per_edge, clamp_edge_levels, face_levels, gl_levels, grid_segments};
use crate::error::RefineError;
use crate::mesh::Topology;
use crate::tessellator::parts::{self, FaceRulers, Shape};
use crate::tessellator::process_levels;
use std::ops::Range;

/// `u32` words of one face's record.
pub const RECORD_WORDS: usize = 24;
/// Word of a record holding the canonical bits: bit `k` set when edge `k` runs canonically
/// ([`canonical::forward`]).
pub const FORWARD_WORD: usize = 20;
/// Grid records: the first of the three edges' segment counts.
pub(crate) const GRID_SEGMENTS_WORD: usize = 0;
/// Grid records: the face's grid level (the largest of its levels).
pub(crate) const GRID_LEVEL_WORD: usize = 3;
/// Grid records: the first of the three edges' geomorph factors (`f32` bits).
pub(crate) const GRID_MORPH_WORD: usize = 4;
/// Grid records: the inner level's geomorph factor (`f32` bits).
pub(crate) const GRID_INNER_MORPH_WORD: usize = 7;
/// Largest grid level the parts cover: grid levels above it are drawn at it (no geomorph there).
pub const MAX_GRID_LEVEL: u32 = 64;

/// Part ids of the tessellator spacings: strips, interiors, the single triangle.
const STRIPS: u32 = Shape::COUNT * Shape::COUNT;
const SINGLE: u32 = STRIPS + Shape::COUNT;

/// Part id of the strip between an outer edge of shape `outer` and the inner shape `inner`.
pub fn strip_part(inner: Shape, outer: Shape) -> u32 {
    inner.id() * Shape::COUNT + outer.id()
}

/// Part id of the interior of inner shape `inner`.
pub fn interior_part(inner: Shape) -> u32 {
    STRIPS + inner.id()
}

/// Part id of the grid of level `n` (1..=[`MAX_GRID_LEVEL`]).
pub fn grid_part(n: u32) -> u32 {
    n - 1
}

/// Code of grid point `(i, j)` (see [`crate::Pattern`]).
pub const fn grid_code(i: u32, j: u32) -> u32 {
    i | j << 8
}

/// The parts of a spacing: their triangles (point codes) one after the other.
#[derive(Debug, Clone)]
pub struct PartTable {
    pub spacing: Spacing,
    pub triangles: Vec<[u32; 3]>,
    /// Triangle range of each part id (empty for shapes the spacing never makes).
    pub ranges: Vec<Range<u32>>,
}

impl PartTable {
    /// Every part `spacing` can draw.
    pub fn new(spacing: Spacing) -> PartTable {
        let mut triangles = Vec::new();
        let mut ranges = Vec::new();
        let mut push = |tris: Vec<[u32; 3]>, ranges: &mut Vec<Range<u32>>| {
            let start = triangles.len() as u32;
            triangles.extend(tris);
            ranges.push(start..triangles.len() as u32);
        };
        match spacing {
            Spacing::Grid => {
                for n in 1..=MAX_GRID_LEVEL {
                    push(grid_triangles(n), &mut ranges);
                }
            }
            _ => {
                // Which parities the spacing makes; equal spacing makes both.
                let made = |s: Shape| match spacing {
                    Spacing::FractionalOdd => s.odd,
                    Spacing::FractionalEven => !s.odd,
                    _ => true,
                };
                for inner in (0..Shape::COUNT).map(Shape::from_id) {
                    for outer in (0..Shape::COUNT).map(Shape::from_id) {
                        let tris = if made(inner) && made(outer) {
                            parts::strip(inner, outer)
                        } else {
                            Vec::new()
                        };
                        push(tris, &mut ranges);
                    }
                }
                for inner in (0..Shape::COUNT).map(Shape::from_id) {
                    let tris = if made(inner) {
                        parts::interior(inner)
                    } else {
                        Vec::new()
                    };
                    push(tris, &mut ranges);
                }
                push(vec![parts::single()], &mut ranges);
            }
        }
        PartTable {
            spacing,
            triangles,
            ranges,
        }
    }

    /// Part `part` as a small indexed mesh: its distinct point codes, in the order its
    /// triangles first use them, and its triangles as indices into those (three a triangle).
    /// What every host draws a part with (a vertex a code, shared by the part's triangles);
    /// empty for a part id the table does not have.
    pub fn part_vertices(&self, part: u32) -> (Vec<u32>, Vec<u32>) {
        let Some(range) = self.ranges.get(part as usize) else {
            return (Vec::new(), Vec::new());
        };
        let triangles = &self.triangles[range.start as usize..range.end as usize];
        let mut codes: Vec<u32> = Vec::new();
        let mut local: rustc_hash::FxHashMap<u32, u32> = Default::default();
        let mut indices = Vec::with_capacity(3 * triangles.len());
        for &code in triangles.iter().flatten() {
            let next = codes.len() as u32;
            let i = *local.entry(code).or_insert_with(|| {
                codes.push(code);
                next
            });
            indices.push(i);
        }
        (codes, indices)
    }
}

/// The uniform grid of level `n`'s triangles as grid codes, in [`crate::Pattern::uniform`]'s
/// order.
fn grid_triangles(n: u32) -> Vec<[u32; 3]> {
    let mut tris = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..(n - j) {
            tris.push([grid_code(i, j), grid_code(i + 1, j), grid_code(i, j + 1)]);
            if i + 1 < n - j {
                tris.push([
                    grid_code(i + 1, j),
                    grid_code(i + 1, j + 1),
                    grid_code(i, j + 1),
                ]);
            }
        }
    }
    tris
}

/// The barycentric point grid code `(i, j)` names on a face whose edges have `n` segments and
/// whose grid has `big` (at least each `n`): an edge point moves to the nearest step of its
/// edge's own layout, ties up, as [`super::tiling::grid_pattern`] does: the point of the plan the
/// adaptive renderer's shader traces (`tessella_core::shader::grid_plan_wgsl`), run on the CPU
/// (the tests compare the parts with the CPU's patterns through it).
pub fn grid_point(n: [u32; 3], big: u32, i: u32, j: u32) -> [f64; 3] {
    super::grid_point::grid_point_of::<f64>(big, i, j, n, [1.0; 3], 1.0, 0).l
}

/// One instanced draw: a part and the instances (positions in
/// [`FrameInstances::instances`]) that draw it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartDraw {
    pub part: u32,
    pub instances: Range<u32>,
}

/// One frame's per-face data for drawing with a [`PartTable`].
#[derive(Debug, Clone, Default)]
pub struct FrameInstances {
    /// [`RECORD_WORDS`] per face.
    pub records: Vec<u32>,
    /// `face | side << 30`, grouped by part.
    pub instances: Vec<u32>,
    pub draws: Vec<PartDraw>,
    /// Triangles the draws make (grid: with the zero-area ones).
    pub triangles: u64,
}

/// The parts one face draws, with their instance sides: none (culled), one or four. Fixed
/// size, so a frame allocates nothing per face.
#[derive(Debug, Clone, Copy, Default)]
struct FaceParts {
    parts: [(u32, u32); 4],
    len: usize,
}

impl FaceParts {
    fn push(&mut self, part: u32, side: u32) {
        self.parts[self.len] = (part, side);
        self.len += 1;
    }
    fn as_slice(&self) -> &[(u32, u32)] {
        &self.parts[..self.len]
    }
}

/// The record and the parts (with their instance sides) of one face with edge levels `outer`
/// (our edge order, already clamped) and inner level `inner`; no parts when it is culled.
fn face_record(
    spacing: Spacing,
    outer: [f32; 3],
    inner: f32,
    forward: u32,
) -> ([u32; RECORD_WORDS], FaceParts) {
    let mut record = [0u32; RECORD_WORDS];
    record[FORWARD_WORD] = forward;
    let mut parts = FaceParts::default();
    match spacing.tessellator() {
        None => {
            let cap = MAX_GRID_LEVEL as f32;
            let outer = outer.map(|x| x.min(cap));
            let inner = inner.min(cap);
            let n = outer.map(grid_segments);
            let big = grid_segments(inner).max(n[0]).max(n[1]).max(n[2]);
            record[GRID_SEGMENTS_WORD..GRID_SEGMENTS_WORD + 3].copy_from_slice(&n);
            record[GRID_LEVEL_WORD] = big;
            for k in 0..3 {
                record[GRID_MORPH_WORD + k] = (morph::factor(outer[k], n[k]) as f32).to_bits();
            }
            record[GRID_INNER_MORPH_WORD] = (morph::factor(inner, big) as f32).to_bits();
            parts.push(grid_part(big), 0);
        }
        Some(s) => {
            if let Some(p) = process_levels(s, gl_levels(outer, inner)) {
                let rulers = FaceRulers::new(&p);
                let words = rulers.words();
                record[..words.len()].copy_from_slice(&words);
                if rulers.single_triangle {
                    parts.push(SINGLE, 0);
                } else {
                    let (outer, inner) = rulers.shapes();
                    for (k, &o) in outer.iter().enumerate() {
                        parts.push(strip_part(inner, o), k as u32);
                    }
                    parts.push(interior_part(inner), 0);
                }
            }
        }
    }
    (record, parts)
}

/// One frame's records and instances: `edge_levels` one per unique edge of `topology`
/// ([`Topology::edges`] order), `face_levels` optional per-face minimum inner levels, as
/// [`super::levels::Levels::PerEdge`] takes them; `triangles` and `position_ids` the plan's, for the
/// canonical edge directions. O(faces + parts).
pub fn frame_instances(
    table: &PartTable,
    topology: &Topology,
    triangles: &[[u32; 3]],
    position_ids: &[u32],
    edge_levels: &[f32],
    face_minimums: Option<&[f32]>,
) -> Result<FrameInstances, RefineError> {
    let nf = triangles.len();
    // Instances are `face | side << 30`.
    if nf >= 1 << 30 {
        return Err(RefineError::BadLevels(format!(
            "{nf} triangles; instanced drawing takes fewer than 2^30"
        )));
    }
    check_per_edge(topology.edges.len(), nf, edge_levels, face_minimums)?;
    let edge_levels = clamp_edge_levels(table.spacing, edge_levels.to_vec());
    let mut records = Vec::with_capacity(nf * RECORD_WORDS);
    let mut face_parts = Vec::with_capacity(nf);
    let mut counts = vec![0u32; table.ranges.len()];
    for (f, &t) in triangles.iter().enumerate() {
        let (outer, inner) = face_levels(topology, f, &edge_levels, face_minimums);
        let forward = (0..3).fold(0u32, |bits, k| {
            bits | u32::from(canonical::forward(t, k, position_ids)) << k
        });
        let (record, parts) = face_record(table.spacing, outer, inner, forward);
        records.extend_from_slice(&record);
        for &(part, _) in parts.as_slice() {
            counts[part as usize] += 1;
        }
        face_parts.push(parts);
    }
    // Instances grouped by part (a counting sort), in face order within a part.
    let mut starts = Vec::with_capacity(counts.len());
    let mut at = 0u32;
    let mut draws = Vec::new();
    let mut drawn = 0u64;
    for (part, &c) in counts.iter().enumerate() {
        starts.push(at);
        let range = &table.ranges[part];
        if c > 0 && !range.is_empty() {
            draws.push(PartDraw {
                part: part as u32,
                instances: at..at + c,
            });
            drawn += c as u64 * range.len() as u64;
        }
        at += c;
    }
    let mut instances = vec![0u32; at as usize];
    for (f, parts) in face_parts.iter().enumerate() {
        for &(part, side) in parts.as_slice() {
            let slot = &mut starts[part as usize];
            instances[*slot as usize] = f as u32 | side << 30;
            *slot += 1;
        }
    }
    Ok(FrameInstances {
        records,
        instances,
        draws,
        triangles: drawn,
    })
}

#[cfg(test)]
mod tests {
    use super::super::canonical::EdgeWeights;
    use super::super::grid_point::grid_point_of;
    use super::super::tiling::grid_pattern;
    use super::*;
    use crate::basis::Basis;
    use crate::pattern::PointClass;
    use crate::stencil::Stencil;

    #[test]
    fn grid_parts_draw_the_adaptive_grid_patterns() {
        let mut seed = 99u64;
        let mut next = |m: u32| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            1 + ((seed >> 33) % m as u64) as u32
        };
        for case in 0..400 {
            let n = [next(20), next(20), next(20)];
            let big = n[0]
                .max(n[1])
                .max(n[2])
                .max(if case % 2 == 0 { next(24) } else { 1 });
            let expected = grid_pattern(n, big);
            let want: Vec<[[f64; 3]; 3]> = expected
                .triangles
                .iter()
                .map(|t| t.map(|p| expected.points[p as usize]))
                .collect();
            let got: Vec<[[f64; 3]; 3]> = grid_triangles(big)
                .iter()
                .map(|t| t.map(|c| grid_point(n, big, c & 0xff, c >> 8)))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
                .collect();
            assert_eq!(got, want, "edges {n:?}, grid {big}");
        }
    }

    #[test]
    fn instances_group_faces_by_part_and_cover_every_triangle() {
        let mesh = crate::samples::icosphere(1);
        let topology = Topology::new(&mesh);
        let ids = &topology.position_ids;
        let levels: Vec<f32> = (0..topology.edges.len())
            .map(|e| 1.0 + (e * 37 % 71) as f32 / 7.0)
            .collect();
        for &spacing in <Spacing as crate::names::Named>::ALL {
            let table = PartTable::new(spacing);
            let frame =
                frame_instances(&table, &topology, mesh.triangles(), ids, &levels, None).unwrap();
            assert_eq!(frame.records.len(), mesh.face_count() * RECORD_WORDS);
            // Every face drawn by its parts (1 for the grid, 4 or the single triangle).
            let per_face = if spacing == Spacing::Grid { 1 } else { 4 };
            assert_eq!(frame.instances.len(), mesh.face_count() * per_face);
            let mut seen = vec![0; mesh.face_count()];
            for d in &frame.draws {
                for &i in &frame.instances[d.instances.start as usize..d.instances.end as usize] {
                    seen[(i & 0x3fff_ffff) as usize] += 1;
                }
            }
            assert!(seen.iter().all(|&c| c == per_face), "{spacing:?}");
            // The same triangle count as the adaptive plan's patterns (the grid keeps its
            // zero-area triangles: at least as many).
            let options = crate::RefineOptions::new(crate::Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(crate::refine::Levels::PerEdge {
                    edges: levels.clone().into(),
                    faces: None,
                });
            let plan = crate::refine::Plan::new(&mesh, &options).unwrap();
            let cpu = plan.triangle_count() as u64;
            if spacing == Spacing::Grid {
                assert!(frame.triangles >= cpu, "{spacing:?}");
            } else {
                assert_eq!(frame.triangles, cpu, "{spacing:?}");
            }
        }
    }

    #[test]
    fn bad_levels_are_refused() {
        let mesh = crate::samples::tetrahedron();
        let topology = Topology::new(&mesh);
        let table = PartTable::new(Spacing::FractionalOdd);
        let ids = &topology.position_ids;
        let run = |levels: &[f32]| {
            frame_instances(&table, &topology, mesh.triangles(), ids, levels, None)
        };
        assert!(run(&[1.0; 3]).is_err());
        for bad in [f32::NAN, -1.0, 0.0, f32::INFINITY] {
            let mut l = vec![2.0; topology.edges.len()];
            l[2] = bad;
            assert!(run(&l).is_err(), "{bad}");
        }
        // Levels above the maximum are clamped as the hardware does.
        assert!(run(&vec![1e9; topology.edges.len()]).is_ok());
    }

    /// `Σ w row(l)` over a plan's points, in f64.
    fn plan_row(basis: Basis, points: &[([f64; 3], f64)]) -> Vec<f64> {
        let mut row = vec![0.0; Stencil::stride_for(basis.len()) - 3];
        for &(l, w) in points {
            if w == 0.0 {
                continue;
            }
            for (o, x) in row.iter_mut().zip(Stencil::row_f64(basis, l)) {
                *o += w * x;
            }
        }
        row
    }

    /// The plan of every grid point of a face reproduces the CPU's morphed tile: its point is
    /// the snapped pattern's, its weighted points sum to the pattern point's stencil row, and
    /// its canonical edge points to the morphed canonical edge weights.
    #[test]
    fn plans_sum_to_the_cpus_morphed_stencils() {
        let basis = Basis::Cubic;
        let mut checked = 0;
        for (segments, big) in [
            ([3, 5, 2], 5),
            ([1, 4, 4], 4),
            ([6, 6, 6], 6),
            ([2, 7, 5], 8),
            ([1, 1, 1], 1),
        ] {
            for (alpha, alpha_inner) in
                [([1.0; 3], 1.0), ([0.25, 0.5, 1.0], 0.375), ([0.1; 3], 1.0)]
            {
                let pattern = grid_pattern(segments, big);
                let stencil = morph::grid_stencil(&pattern, basis, segments, alpha, alpha_inner);
                for forward in 0..8u32 {
                    for j in 0..=big {
                        for i in 0..=big - j {
                            let plan = grid_point_of::<f64>(
                                big,
                                i,
                                j,
                                segments,
                                alpha,
                                alpha_inner,
                                forward,
                            );
                            let p = pattern
                                .points
                                .iter()
                                .position(|q| q.map(f64::to_bits) == plan.l.map(f64::to_bits))
                                .unwrap_or_else(|| panic!("{:?} in the pattern", plan.l));
                            let want = stencil.row(p);
                            let got = plan_row(basis, &plan.points);
                            for (g, w) in got.iter().zip(want) {
                                let tol = 1e-6 * (1.0 + w.abs() as f64);
                                assert!((g - *w as f64).abs() < tol, "{segments:?} {i} {j}");
                            }
                            match pattern.classes[p] {
                                PointClass::Edge { edge, step } => {
                                    assert_eq!(plan.edge, u32::from(edge));
                                    let k = edge as usize;
                                    let n = segments[k];
                                    let canonical_step = match (forward >> k) & 1 {
                                        1 => step,
                                        _ => n - step,
                                    };
                                    let want = if alpha[k] < 1.0 {
                                        morph::edge_weights(n, canonical_step, alpha[k])
                                    } else {
                                        let nf = n as f64;
                                        let (v, m) = EdgeWeights::new_f64(
                                            (n - canonical_step) as f64 / nf,
                                            canonical_step as f64 / nf,
                                        );
                                        EdgeWeights::from_f64(v, m)
                                    };
                                    let (mut v, mut m) = ([0.0; 4], [0.0; 3]);
                                    for ([a, b], w) in plan.edge_points {
                                        if w == 0.0 {
                                            continue;
                                        }
                                        let (ev, em) = EdgeWeights::new_f64(a, b);
                                        (0..4).for_each(|x| v[x] += w * ev[x]);
                                        (0..3).for_each(|x| m[x] += w * em[x]);
                                    }
                                    for (g, w) in v
                                        .iter()
                                        .chain(&m)
                                        .zip(want.value.iter().chain(&want.normal))
                                    {
                                        assert!(
                                            (g - *w as f64).abs() < 1e-6,
                                            "{segments:?} {i} {j}"
                                        );
                                    }
                                }
                                _ => {
                                    assert_eq!(plan.edge, parts::NO_EDGE);
                                    assert!(plan.edge_points.iter().all(|p| p.1 == 0.0));
                                }
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 1000, "{checked}");
    }
}
