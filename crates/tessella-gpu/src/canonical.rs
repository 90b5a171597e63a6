//! The table behind canonical edge evaluation on the GPU (`edge_table` in `shaders/eval.wgsl`):
//! a pattern point on a coarse edge is evaluated from that edge's four boundary control points
//! in canonical order (from the lower position id), with weights computed once in f64 on the
//! CPU, the same way tessella-core's `refine::canonical` does it, so the two faces sharing the
//! edge compute the same floats in the same order and their vertices are bit-identical, in the
//! compute path and in the instanced renderer.
//!
//! Layout (`u32`s; weights are `f32` bits):
//!
//! - `[0]`: where the face bits start;
//! - `[1..13)`: per edge `k`, the four control points of its boundary curve
//!   (`canonical::edge_controls`), from corner `k` to corner `k + 1`;
//! - `[13..22)`: per edge `k`, its three normal-net entries (`canonical::edge_normal_controls`);
//! - from [`ROWS_AT`], [`ROW_LEN`] per pattern point: `0` for a point off the coarse edges, else
//!   `1 + k`; then the weights `value[4] | normal[3]` for an edge running canonically (start
//!   corner `k`), then the same for the edge running the other way;
//! - per face: bit `k` set when its edge `k` runs canonically (`canonical::forward`).

use tessella_core::pattern::{Pattern, PointClass};
use tessella_core::refine::canonical::{self, EdgeWeights};
use tessella_core::refine::{morph, Morph};
use tessella_core::Basis;

/// First pattern row of the table.
pub(crate) const ROWS_AT: usize = 22;
/// `u32`s per pattern row.
pub(crate) const ROW_LEN: usize = 15;

/// The table for `patterns` (their points numbered one after the other, as the stencil rows
/// are) on the faces `triangles` (vertex indices) whose vertices have `position_ids`.
/// `morphs[i]`: pattern `i`'s geomorph factors (a fractional grid level's tile; missing or
/// `None`: plain weights), blended as the CPU does (`tessella_core::refine::morph`).
pub(crate) fn edge_table(
    basis: Basis,
    patterns: &[&Pattern],
    morphs: &[Option<Morph>],
    triangles: &[[u32; 3]],
    position_ids: &[u32],
) -> Vec<u32> {
    let rows: usize = patterns.iter().map(|p| p.points.len()).sum();
    let faces_at = ROWS_AT + ROW_LEN * rows;
    let mut table = Vec::with_capacity(faces_at + triangles.len());
    table.push(faces_at as u32);
    for k in 0..3 {
        table.extend(canonical::edge_controls(basis, k).map(|i| i as u32));
    }
    for k in 0..3 {
        table.extend(canonical::edge_normal_controls(k).map(|i| i as u32));
    }
    debug_assert_eq!(table.len(), ROWS_AT);
    let push = |table: &mut Vec<u32>, w: EdgeWeights| {
        table.extend(w.value.iter().chain(&w.normal).map(|x| x.to_bits()));
    };
    for (i, p) in patterns.iter().enumerate() {
        let morph = morphs.get(i).copied().flatten();
        // Segments of each edge (its points + 1).
        let mut segments = [1u32; 3];
        for class in &p.classes {
            if let PointClass::Edge { edge, .. } = *class {
                segments[edge as usize] += 1;
            }
        }
        for (l, class) in p.points.iter().zip(&p.classes) {
            match *class {
                PointClass::Edge { edge, step } => {
                    let k = edge as usize;
                    table.push(1 + k as u32);
                    match morph {
                        Some(m) if m.outer[k] < 1.0 => {
                            let (n, a) = (segments[k], m.outer[k]);
                            push(&mut table, morph::edge_weights(n, step, a));
                            push(&mut table, morph::edge_weights(n, n - step, a));
                        }
                        _ => {
                            let (start, end) = (l[k], l[(k + 1) % 3]);
                            push(&mut table, EdgeWeights::new(start, end));
                            push(&mut table, EdgeWeights::new(end, start));
                        }
                    }
                }
                _ => table.extend([0; ROW_LEN]),
            }
        }
    }
    debug_assert_eq!(table.len(), faces_at);
    table.extend(triangles.iter().map(|&t| {
        (0..3).fold(0u32, |bits, k| {
            bits | (canonical::forward(t, k, position_ids) as u32) << k
        })
    }));
    table
}
