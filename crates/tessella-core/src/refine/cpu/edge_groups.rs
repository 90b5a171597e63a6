//! The points inside coarse edges, several edges at a time. An edge holds `level - 1` points,
//! one or a few vectors: evaluated one edge at a time (as [`super::kernels::eval_block`]
//! does for a face's interior), each of its sums is one chain of dependent additions and the
//! adders wait on their latency, and every edge pays the block's set-up. Here `G` edges (of
//! different faces, each with its own control points) are summed side by side: `3 G`
//! independent chains, the control points broadcast straight from the patch's net.
//!
//! Each point's sums are the same operations in the same order as [`super::kernels::eval_point`]
//! (start from zero, add `w_k C_k` for `k` in order; normalise as glam does), so the bits are
//! the same as every other path's: an edge point gets the same bits from both of its faces'
//! evaluations (welded output evaluates it once, on the owning face).

use super::kernels::{
    compiled_for, cross_vectors, cubic_derivative_nets, dispatched_kernel, fallback_normals,
    lane_weights, normalize_vectors, BlockRun, Scratch, CUBIC_LEN, LANES, TILE,
};
use super::output::Sink;
use crate::basis::NORMAL_NET_LEN;
use crate::scheme::NormalMode;
use crate::stencil::Stencil;

dispatched_kernel! {
    /// Evaluates every run of `runs` into `sink` (see [`eval_edges_body`]), with the code
    /// compiled for the widest vectors the CPU has, as [`super::kernels::eval_block`] chooses:
    /// four edges side by side with AVX-512, one at a time with AVX2 (an edge's 16 points
    /// already fill six of its 16 registers).
    pub(crate) fn eval_edges = eval_edges_body, eval_edges_avx512, eval_edges_avx2 (
        runs: &[BlockRun],
        stencil: &Stencil,
        mode: NormalMode,
        sink: &mut Sink,
        scratch: &mut Scratch,
    )
}

/// Evaluates every run of `runs` into `sink`, `G` at a time where the runs are short enough
/// for `G` of them to share one tile (all edge blocks of a stencil have one length). Equal,
/// bit for bit, to [`super::kernels::eval_point`] on each point.
#[inline(always)]
pub(crate) fn eval_edges_body<const K: usize, const G: usize>(
    runs: &[BlockRun],
    stencil: &Stencil,
    mode: NormalMode,
    sink: &mut Sink,
    scratch: &mut Scratch,
) {
    let Some(first) = runs.first() else { return };
    let vectors = first.block.len().div_ceil(LANES);
    let mut groups = runs.chunks_exact(G);
    if G > 1 && G * vectors * LANES <= TILE {
        for group in groups.by_ref() {
            let group: &[BlockRun; G] = group.try_into().expect("chunks of G");
            eval_group::<K, G>(group, stencil, mode, sink, scratch);
        }
    }
    let rest = if G > 1 && G * vectors * LANES <= TILE {
        groups.remainder()
    } else {
        runs
    };
    for run in rest {
        if vectors * LANES <= TILE {
            eval_group::<K, 1>(
                std::slice::from_ref(run).try_into().expect("one run"),
                stencil,
                mode,
                sink,
                scratch,
            );
        } else {
            super::kernels::eval_block_body::<K, 1>(run, stencil, mode, sink, scratch);
        }
    }
}

/// `Σ_k w_g[k] c_g[k]` for each run `g` of the group, vector by vector, into the tile at
/// `g * vectors * LANES`: `weights(g)` weight-major with `stride` floats a control point,
/// `controls(g)` its control points. (Closures, not arrays built with `map`: an array's `map`
/// stayed a call in the vectorised code.)
#[inline(always)]
fn accumulate_runs<'a, const C: usize, const G: usize>(
    weights: impl Fn(usize) -> &'a [f32],
    stride: usize,
    vectors: usize,
    controls: impl Fn(usize) -> &'a [[f32; 3]; C],
    acc: &mut [[f32; TILE]; 3],
) {
    assert!(
        vectors * LANES <= stride && (0..G).all(|g| C * stride <= weights(g).len()),
        "stencil rows are padded to whole vectors"
    );
    for v in 0..vectors {
        let mut x = [[0.0f32; LANES]; G];
        let mut y = [[0.0f32; LANES]; G];
        let mut z = [[0.0f32; LANES]; G];
        for k in 0..C {
            for g in 0..G {
                let w = lane_weights(weights(g), k * stride + v * LANES);
                let [cx, cy, cz] = controls(g)[k];
                for l in 0..LANES {
                    x[g][l] += w[l] * cx;
                    y[g][l] += w[l] * cy;
                    z[g][l] += w[l] * cz;
                }
            }
        }
        for g in 0..G {
            let i = (g * vectors + v) * LANES;
            acc[0][i..i + LANES].copy_from_slice(&x[g]);
            acc[1][i..i + LANES].copy_from_slice(&y[g]);
            acc[2][i..i + LANES].copy_from_slice(&z[g]);
        }
    }
}

/// Evaluates the `G` runs of one group: positions, then normals (the sink's kind), then each
/// run's points into its slots, then the scalar fallbacks of any normal that failed.
#[inline(always)]
fn eval_group<const K: usize, const G: usize>(
    runs: &[BlockRun; G],
    stencil: &Stencil,
    mode: NormalMode,
    sink: &mut Sink,
    scratch: &mut Scratch,
) {
    let len = runs[0].block.len();
    let stride = runs[0].block.stride;
    assert!(
        runs.iter()
            .all(|r| r.block.len() == len && r.block.stride == stride),
        "edge blocks of one stencil have one length"
    );
    let vectors = len.div_ceil(LANES);
    let span = vectors * LANES;
    let points = |g: usize| -> &[[f32; 3]; K] {
        runs[g]
            .points
            .try_into()
            .expect("patch has K control points")
    };
    let Scratch {
        pos,
        d1,
        d2,
        unit,
        stage,
        ..
    } = scratch;
    accumulate_runs::<K, G>(|g| &runs[g].block.value, stride, vectors, points, pos);
    let want_normals = sink.wants_normals();
    let mut all_ok = true;
    if want_normals {
        if mode == NormalMode::Real {
            if K == CUBIC_LEN {
                let mut nets = [([[0.0f32; 3]; NORMAL_NET_LEN], [[0.0f32; 3]; NORMAL_NET_LEN]); G];
                for (g, net) in nets.iter_mut().enumerate() {
                    *net = cubic_derivative_nets(points(g)[..].try_into().expect("cubic patch"));
                }
                let normal = |g: usize| &runs[g].block.normal[..];
                accumulate_runs::<NORMAL_NET_LEN, G>(normal, stride, vectors, |g| &nets[g].0, d1);
                accumulate_runs::<NORMAL_NET_LEN, G>(normal, stride, vectors, |g| &nets[g].1, d2);
            } else {
                accumulate_runs::<K, G>(|g| &runs[g].block.du, stride, vectors, points, d1);
                accumulate_runs::<K, G>(|g| &runs[g].block.dv, stride, vectors, points, d2);
            }
            for g in 0..G {
                all_ok &= cross_vectors(d1, d2, g * span, vectors, len, unit);
            }
        } else {
            let net = |g: usize| -> &[[f32; 3]; NORMAL_NET_LEN] {
                runs[g]
                    .normals
                    .try_into()
                    .expect("normal net has 6 entries")
            };
            accumulate_runs::<NORMAL_NET_LEN, G>(
                |g| &runs[g].block.normal,
                stride,
                vectors,
                net,
                unit,
            );
            for g in 0..G {
                all_ok &= normalize_vectors(unit, g * span, vectors, len);
            }
        }
    }
    for (g, run) in runs.iter().enumerate() {
        let first = if run.reverse {
            run.base + len - 1
        } else {
            run.base
        };
        sink.put_tile(
            first,
            run.reverse,
            len,
            g * span,
            pos,
            want_normals.then_some(&*unit),
            stage,
        );
    }
    if !all_ok {
        for (g, run) in runs.iter().enumerate() {
            fallback_normals::<K>(
                (d1, d2, unit),
                g * span,
                len,
                &run.block.points,
                stencil,
                mode,
                (points(g), run.normals),
                sink,
                |i| run.base + if run.reverse { len - 1 - i } else { i },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::Basis;
    use crate::pattern::Pattern;
    use crate::refine::cpu::kernels::eval_point;
    use crate::refine::cpu::kernels::tests::{into_arrays, test_patch};

    /// Six edges (a full group of four and two left over), each of its own patch, forward and
    /// reversed, some with vanishing or overflowing normal nets or collinear control points
    /// (the fallbacks):
    /// every point has the bits of [`eval_point`], for each way of running them.
    fn check<const K: usize>(basis: Basis, level: u32) {
        let stencil = Stencil::new(&Pattern::uniform(level), basis);
        let len = stencil.blocks.edges[0].len();
        let mut seed = 11;
        type Patch = (Vec<[f32; 3]>, Vec<[f32; 3]>);
        let nets: Vec<Patch> = [0, 5, 2, 0, 4, 3]
            .into_iter()
            .map(|case| test_patch::<K>(&mut seed, case))
            .collect();
        let runs: Vec<BlockRun> = nets
            .iter()
            .enumerate()
            .map(|(i, (points, normals))| BlockRun {
                block: &stencil.blocks.edges[i % 3],
                points,
                normals,
                base: i * len,
                reverse: i % 2 == 1,
            })
            .collect();
        type Run = fn(&[BlockRun], &Stencil, NormalMode, &mut Sink, &mut Scratch);
        let mut ways: Vec<(&str, Run)> = vec![
            ("dispatched", eval_edges::<K>),
            ("four at a time", eval_edges_body::<K, 4>),
            ("one at a time", eval_edges_body::<K, 1>),
        ];
        // The AVX2 copy where the CPU has it (a machine with AVX-512 dispatches past it).
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            ways.push(("avx2", |r, st, m, sink, sc| unsafe {
                eval_edges_avx2::<K>(r, st, m, sink, sc)
            }));
        }
        for (way, run) in ways {
            for mode in [NormalMode::Quadratic, NormalMode::Real] {
                for stream in [false, true] {
                    let (pos, nrm) = into_arrays(runs.len() * len, stream, |sink| {
                        run(&runs, &stencil, mode, sink, &mut Scratch::new())
                    });
                    for (i, r) in runs.iter().enumerate() {
                        for (s, &p) in r.block.points.iter().enumerate() {
                            let (want_p, want_n) =
                                eval_point::<K>(stencil.row(p as usize), r.points, r.normals, mode);
                            let slot = r.base + if r.reverse { len - 1 - s } else { s };
                            let bits = |v: [f32; 3]| v.map(f32::to_bits);
                            let what = format!(
                                "{way} level {level} {mode:?} stream {stream} edge {i} point {s}"
                            );
                            assert_eq!(bits(pos[slot]), bits(want_p), "{what}");
                            assert_eq!(bits(nrm[slot]), bits(want_n), "{what}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn edge_groups_equal_point_evaluation_bit_for_bit() {
        // Level 24: two vectors an edge, four edges a tile. Level 80: five vectors, too many
        // for four edges a tile (one at a time). Level 300: longer than a tile (by blocks).
        for level in [3, 24, 80, 300] {
            check::<10>(Basis::Cubic, level);
            check::<21>(Basis::Png1, level);
        }
    }
}
