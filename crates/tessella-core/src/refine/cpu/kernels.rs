//! The CPU kernels: every output vertex is `sum_k w_k C_k` over its patch's control points,
//! with the weights read from the pattern's [`Stencil`] row; one point at a time
//! ([`eval_point`]) or a block of points in vectors ([`eval_block`]), bit for bit the same.

use super::output::Sink;
use crate::basis::surface_normal::{normal_of, real_normal_of};
use crate::basis::NORMAL_NET_LEN;
use crate::scheme::NormalMode;
use crate::stencil::{Block, Stencil, BLOCK_LANES};
use glam::Vec3;

/// Evaluates one point of one patch from its stencil row: `(position, unit normal)`.
///
/// Normals: `Real` takes `Du × Dv` and falls back to the normal net where the derivatives are
/// (nearly) parallel; the others take the normal net. A normal that still vanishes becomes the
/// normal of the patch's corner triangle. `eval_block` computes the same, bit for bit, for
/// many points at once.
#[inline(always)]
pub fn eval_point<const K: usize>(
    row: &[f32],
    points: &[[f32; 3]],
    normals: &[[f32; 3]],
    mode: NormalMode,
) -> ([f32; 3], [f32; 3]) {
    let points: &[[f32; 3]; K] = points.try_into().expect("patch has K control points");
    let w: &[f32; K] = row[..K].try_into().unwrap();
    let position = combine(w, points);
    let (du, dv) = if mode == NormalMode::Real && K == CUBIC_LEN {
        let (du_net, dv_net) = cubic_derivative_nets(points[..].try_into().unwrap());
        let q: &[f32; NORMAL_NET_LEN] = row[3 * K..3 * K + NORMAL_NET_LEN].try_into().unwrap();
        (combine(q, &du_net), combine(q, &dv_net))
    } else if mode == NormalMode::Real {
        (
            combine::<K>(row[K..2 * K].try_into().unwrap(), points),
            combine::<K>(row[2 * K..3 * K].try_into().unwrap(), points),
        )
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    };
    let normal = finish_normal::<K>(mode, du, dv, row, points, normals);
    (position.into(), normal.into())
}

/// Control points of the cubic basis ([`crate::basis::CUBIC_ORDER`]).
pub(super) const CUBIC_LEN: usize = 10;

/// `Du` and `Dv` of a cubic patch as quadratic nets, weighted like the normal net
/// (`l1², l2², l3², l1 l2, l2 l3, l3 l1`): the derivative of a cubic Bézier triangle along
/// `u` is `3 Σ B²_a (b_{a+e2} - b_{a+e1})` (along `v`, `e3` for `e2`), and `B²` of a mid
/// slot is twice its normal weight. Six weights per derivative instead of ten, and real
/// normals cost about what quadratic ones do.
#[inline(always)]
pub(super) fn cubic_derivative_nets(p: &[[f32; 3]; CUBIC_LEN]) -> ([[f32; 3]; 6], [[f32; 3]; 6]) {
    // Storage order: b300 b030 b003 b210 b120 b021 b012 b102 b201 b111.
    // Written out, not `[0, 1, 2].map(..)`: an array's `map` stayed a call in the
    // target-feature copies of the evaluator.
    let d = |s: f32, [a, b]: [usize; 2]| {
        [
            s * (p[a][0] - p[b][0]),
            s * (p[a][1] - p[b][1]),
            s * (p[a][2] - p[b][2]),
        ]
    };
    // Slot `i` of a net is `s (P_a - P_b)` for `(a, b) = ab[i]`: `s` is 3 at the corner slots
    // and 6 at the mid slots, along `u` and along `v` alike.
    let net = |ab: [[usize; 2]; 6]| {
        [
            d(3.0, ab[0]),
            d(3.0, ab[1]),
            d(3.0, ab[2]),
            d(6.0, ab[3]),
            d(6.0, ab[4]),
            d(6.0, ab[5]),
        ]
    };
    (
        net([[3, 0], [1, 4], [6, 7], [4, 3], [5, 9], [9, 8]]),
        net([[8, 0], [5, 4], [2, 7], [9, 3], [6, 9], [7, 8]]),
    )
}

/// The unit normal from the accumulated derivatives (`Real`) or the normal net, with the
/// fallbacks described at [`eval_point`].
#[inline(always)]
pub(super) fn finish_normal<const K: usize>(
    mode: NormalMode,
    du: Vec3,
    dv: Vec3,
    row: &[f32],
    points: &[[f32; 3]; K],
    normals: &[[f32; 3]],
) -> Vec3 {
    let real = (mode == NormalMode::Real).then(|| (du.into(), dv.into()));
    let net = || {
        let normals: &[[f32; 3]; NORMAL_NET_LEN] =
            normals.try_into().expect("normal net has 6 entries");
        let nw: &[f32; NORMAL_NET_LEN] = row[3 * K..3 * K + NORMAL_NET_LEN].try_into().unwrap();
        combine(nw, normals).into()
    };
    normal_of(real, net, || [points[0], points[1], points[2]]).into()
}

#[inline(always)]
pub(super) fn combine<const K: usize>(w: &[f32; K], c: &[[f32; 3]; K]) -> Vec3 {
    let (mut x, mut y, mut z) = (0.0f32, 0.0f32, 0.0f32);
    for k in 0..K {
        x += w[k] * c[k][0];
        y += w[k] * c[k][1];
        z += w[k] * c[k][2];
    }
    Vec3::new(x, y, z)
}

/// Points per tile of [`eval_block`]: the four accumulator arrays (12 KiB) stay in L1, and
/// the per-tile set-up is spread over enough points (64 spent 9 instructions a point on it).
pub(super) const TILE: usize = 256;

/// Points summed together by [`accumulate`]: their running sums stay in registers (six
/// 8-wide vectors for x, y, z) over all control points, enough independent additions to hide
/// the adder's latency.
pub(super) const LANES: usize = BLOCK_LANES;
const _: () = assert!(TILE.is_multiple_of(LANES), "tiles hold whole vectors");

/// The weights `k` of the tile's vector `v` in a weight-major block: the points
/// `start + v * LANES..` of row `k`. `check_tile` has made sure the tile's vectors lie within
/// the rows (the last one padded with zeros).
#[inline(always)]
pub(super) fn lane_weights(weights: &[f32], at: usize) -> &[f32; LANES] {
    debug_assert!(at + LANES <= weights.len());
    // SAFETY: `check_tile` bounds every `at` passed here (k * stride + start + v * LANES, with
    // start + vectors * LANES <= stride and rows * stride <= weights.len()). A checked slice
    // costs a compare and a branch per weight and vector, a third of the sum's instructions.
    unsafe { &*weights.as_ptr().add(at).cast::<[f32; LANES]>() }
}

/// Number of whole vectors covering the tile's points `start..start + n` of `rows` weight
/// rows, after checking that they lie within the block (panics otherwise: a stencil bug).
#[inline(always)]
fn check_tile(weights: &[f32], rows: usize, stride: usize, start: usize, n: usize) -> usize {
    let vectors = n.div_ceil(LANES);
    assert!(
        start + vectors * LANES <= stride && rows * stride <= weights.len(),
        "stencil rows are padded to whole vectors"
    );
    vectors
}

/// Accumulates `Σ_k w[k*stride + i] c[k]` for the tile's points `start..start+n` into `acc`,
/// summing over `k` in order from zero for every point (the order [`combine`] uses, so the
/// same bits). Works in whole vectors: a short last vector sums the weights' zero padding into
/// slots past `n`, which nobody reads. `G` vectors are summed side by side (see
/// [`accumulate_group`]), each control point broadcast once per group. One vector at a time
/// (`G = 1`, the AVX2 and SSE2 copies), the control points are first spread over whole
/// vectors in `spread`, so the multiply takes its operand from memory: on AVX2, which has no
/// broadcast operand, that is one instruction where a broadcast and a multiply are two
/// (callgrind: 2-3 instructions a vertex).
#[inline(always)]
fn accumulate<const C: usize, const G: usize>(
    weights: &[f32],
    stride: usize,
    start: usize,
    n: usize,
    controls: &[[f32; 3]; C],
    spread: &mut [[[f32; LANES]; 3]; MAX_CONTROLS],
    acc: &mut [[f32; TILE]; 3],
) {
    let vectors = check_tile(weights, C, stride, start, n);
    if G == 1 {
        for (s, c) in spread.iter_mut().zip(controls) {
            *s = [[c[0]; LANES], [c[1]; LANES], [c[2]; LANES]];
        }
        let spread = &*spread;
        for v in 0..vectors {
            accumulate_group::<C, 1>(weights, stride, start, v, |k| spread[k], acc);
        }
        return;
    }
    let lanes = |k: usize| {
        let [x, y, z] = controls[k];
        [[x; LANES], [y; LANES], [z; LANES]]
    };
    let mut v = 0;
    while v + G <= vectors {
        accumulate_group::<C, G>(weights, stride, start, v, lanes, acc);
        v += G;
    }
    if G > 2 && v + 2 <= vectors {
        accumulate_group::<C, 2>(weights, stride, start, v, lanes, acc);
        v += 2;
    }
    while v < vectors {
        accumulate_group::<C, 1>(weights, stride, start, v, lanes, acc);
        v += 1;
    }
}

/// The most control points of a patch (PNG1's quartic net).
const MAX_CONTROLS: usize = 21;

/// [`accumulate`] for the tile's vectors `v..v + G`, control point `k` as `lanes(k)` (its
/// coordinates, each repeated over a vector). Each point's sum is one chain of dependent
/// additions (the order is fixed, for the bits), so one vector's three chains leave the adders
/// waiting on their latency; `G` vectors give `3 G` independent chains, and each control
/// point, loaded once, serves all of them.
#[inline(always)]
fn accumulate_group<const C: usize, const G: usize>(
    weights: &[f32],
    stride: usize,
    start: usize,
    v: usize,
    lanes: impl Fn(usize) -> [[f32; LANES]; 3],
    acc: &mut [[f32; TILE]; 3],
) {
    let mut x = [[0.0f32; LANES]; G];
    let mut y = [[0.0f32; LANES]; G];
    let mut z = [[0.0f32; LANES]; G];
    // Two control points a pass, in order: LLVM kept the ten-point loop rolled, and its
    // counting was a fifth of the sum's instructions.
    let mut k = 0;
    while k + 2 <= C {
        add_control::<G>(
            weights,
            k * stride + start + v * LANES,
            lanes(k),
            [&mut x, &mut y, &mut z],
        );
        add_control::<G>(
            weights,
            (k + 1) * stride + start + v * LANES,
            lanes(k + 1),
            [&mut x, &mut y, &mut z],
        );
        k += 2;
    }
    if k < C {
        add_control::<G>(
            weights,
            k * stride + start + v * LANES,
            lanes(k),
            [&mut x, &mut y, &mut z],
        );
    }
    for g in 0..G {
        let i = (v + g) * LANES;
        acc[0][i..i + LANES].copy_from_slice(&x[g]);
        acc[1][i..i + LANES].copy_from_slice(&y[g]);
        acc[2][i..i + LANES].copy_from_slice(&z[g]);
    }
}

/// Adds one control point's terms `w[l] c` to the `G` vectors' sums, the weights of vector `g`
/// at `at + g * LANES`. A function, not a closure: a closure is compiled without the caller's
/// target features and stayed a call, five times slower.
#[inline(always)]
fn add_control<const G: usize>(
    weights: &[f32],
    at: usize,
    [cx, cy, cz]: [[f32; LANES]; 3],
    [x, y, z]: [&mut [[f32; LANES]; G]; 3],
) {
    for g in 0..G {
        let w = lane_weights(weights, at + g * LANES);
        for l in 0..LANES {
            x[g][l] += w[l] * cx[l];
            y[g][l] += w[l] * cy[l];
            z[g][l] += w[l] * cz[l];
        }
    }
}

/// Normalises the tile's vectors at `from..from + vectors * LANES` in place, exactly as
/// `Vec3::normalize_or_zero` does per vector (the same operations in the same order, so the
/// same bits), one component array at a time and in whole vectors so the loop vectorises with
/// no scalar remainder. Returns whether every point could be normalised; one that could not
/// (zero, tiny or not finite) is left zero or NaN, and [`fallback_normals`] finds it by that.
/// Only the first `len` are points: the padding lanes after them do not count.
#[inline(always)]
pub(super) fn normalize_vectors(
    v: &mut [[f32; TILE]; 3],
    from: usize,
    vectors: usize,
    len: usize,
) -> bool {
    assert!(from + vectors * LANES <= TILE, "whole vectors of the tile");
    let mut failed = [0u32; LANES];
    for vector in 0..vectors {
        let at = from + vector * LANES;
        // Three loads, not `each_ref().map(..)`: that stayed a call, a fifth of the time.
        let (x, y, z) = (lanes(&v[0], at), lanes(&v[1], at), lanes(&v[2], at));
        let mut good = [0u32; LANES];
        let mut out = [[0.0f32; LANES]; 3];
        for l in 0..LANES {
            let rcp = 1.0 / ((x[l] * x[l]) + (y[l] * y[l]) + (z[l] * z[l])).sqrt();
            let fine = stands(rcp);
            good[l] = if fine { u32::MAX } else { 0 };
            let rcp = if fine { rcp } else { 0.0 };
            out[0][l] = x[l] * rcp;
            out[1][l] = y[l] * rcp;
            out[2][l] = z[l] * rcp;
        }
        store_vector(v, at, &out, &good, points_of(vector, len), &mut failed);
    }
    failed.iter().all(|&f| f == 0)
}

/// `is_finite() && rcp > 0`, glam's test of a reciprocal length, as two float compares
/// (`<= MAX` is `< INFINITY`; NaN fails both). Written with `< INFINITY`, LLVM turned the pair
/// into a class test of the bits: fourteen integer instructions a vector instead of two.
#[inline(always)]
fn stands(rcp: f32) -> bool {
    (rcp > 0.0) & (rcp <= f32::MAX)
}

/// The `LANES` floats of a component array at `at`.
#[inline(always)]
fn lanes(c: &[f32; TILE], at: usize) -> [f32; LANES] {
    c[at..at + LANES].try_into().expect("a whole vector")
}

/// `KEEP[LANES - n..][..LANES]`: `n` lanes of ones, then zeros (the padding after a run's
/// last point).
const KEEP: [u32; 2 * LANES] = {
    let mut k = [0; 2 * LANES];
    let mut l = 0;
    while l < LANES {
        k[l] = u32::MAX;
        l += 1;
    }
    k
};

/// Which lanes of vector `vector` hold points of a run of `len`: a mask per lane, all ones
/// but in the last vector.
#[inline(always)]
fn points_of(vector: usize, len: usize) -> &'static [u32; LANES] {
    let n = len.saturating_sub(vector * LANES).min(LANES);
    KEEP[LANES - n..2 * LANES - n]
        .try_into()
        .expect("a whole vector")
}

/// Stores a vector of unit normals at `at` and marks, lane by lane in `failed`, the points
/// (lanes of `keep`) whose normal did not stand (`!good`). Reduced once per tile by the
/// caller: a count per vector compiled to byte shuffles.
#[inline(always)]
fn store_vector(
    dst: &mut [[f32; TILE]; 3],
    at: usize,
    out: &[[f32; LANES]; 3],
    good: &[u32; LANES],
    keep: &[u32; LANES],
    failed: &mut [u32; LANES],
) {
    for (c, o) in dst.iter_mut().zip(out) {
        c[at..at + LANES].copy_from_slice(o);
    }
    for l in 0..LANES {
        failed[l] |= !good[l] & keep[l];
    }
}

/// Whether the normal at tile slot `t` stood: a normalised vector has length about 1, one
/// that failed [`normalize_vectors`] or [`cross_vectors`] was scaled by zero (zero, or NaN
/// where it was not finite).
#[inline(always)]
fn stood(unit: &[[f32; TILE]; 3], t: usize) -> bool {
    let [x, y, z] = [unit[0][t], unit[1][t], unit[2][t]];
    x * x + y * y + z * z > 0.5
}

/// The unit normal `Du × Dv / |Du × Dv|` of one point, as `Vec3::cross` and
/// `normalize_or_zero` compute it, and whether it stands: false where the derivatives are
/// (nearly) parallel (the test [`finish_normal`] makes) or the cross product cannot be
/// normalised, and the point takes the scalar fallback (the normal returned is then zero or
/// NaN, see [`stood`]).
#[inline(always)]
pub(super) fn unit_cross(du: [f32; 3], dv: [f32; 3]) -> ([f32; 3], bool) {
    // The scalar path's test (zero where it fails, which then does not stand), then its
    // `normalize_or_zero` with the fallback left to `fallback_normals`.
    let [x, y, z] = real_normal_of(du, dv);
    let rcp = 1.0 / ((x * x) + (y * y) + (z * z)).sqrt();
    let good = stands(rcp);
    let rcp = if good { rcp } else { 0.0 };
    ([x * rcp, y * rcp, z * rcp], good)
}

/// [`unit_cross`] of the tile's derivatives at `from..from + vectors * LANES`; only the first
/// `len` are points (the padding does not count). Returns whether all stood.
#[inline(always)]
pub(super) fn cross_vectors(
    du: &[[f32; TILE]; 3],
    dv: &[[f32; TILE]; 3],
    from: usize,
    vectors: usize,
    len: usize,
    unit: &mut [[f32; TILE]; 3],
) -> bool {
    let mut failed = [0u32; LANES];
    for vector in 0..vectors {
        let at = from + vector * LANES;
        let a = [lanes(&du[0], at), lanes(&du[1], at), lanes(&du[2], at)];
        let b = [lanes(&dv[0], at), lanes(&dv[1], at), lanes(&dv[2], at)];
        let mut good = [0u32; LANES];
        let mut out = [[0.0f32; LANES]; 3];
        for l in 0..LANES {
            let (u, fine) = unit_cross([a[0][l], a[1][l], a[2][l]], [b[0][l], b[1][l], b[2][l]]);
            good[l] = if fine { u32::MAX } else { 0 };
            out[0][l] = u[0];
            out[1][l] = u[1];
            out[2][l] = u[2];
        }
        store_vector(unit, at, &out, &good, points_of(vector, len), &mut failed);
    }
    failed.iter().all(|&f| f == 0)
}

/// A tile of vectors, one array per component.
pub(super) type TileVectors = [[f32; TILE]; 3];

/// The scalar path's fallbacks for the normals among the tile's `len` points at `from..` that
/// did not stand (parallel derivatives, a vanishing normal), from the derivatives summed into
/// the tile (the same sums `eval_point` makes); point `i` is stencil row `rows[i]` and goes to
/// sink slot `slot(i)`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn fallback_normals<const K: usize>(
    scratch: (&TileVectors, &TileVectors, &TileVectors),
    from: usize,
    len: usize,
    rows: &[u32],
    stencil: &Stencil,
    mode: NormalMode,
    (points, normals): (&[[f32; 3]; K], &[[f32; 3]]),
    sink: &mut Sink,
    slot: impl Fn(usize) -> usize,
) {
    let (d1, d2, unit) = scratch;
    for i in (0..len).filter(|&i| !stood(unit, from + i)) {
        let t = from + i;
        let du = Vec3::new(d1[0][t], d1[1][t], d1[2][t]);
        let dv = Vec3::new(d2[0][t], d2[1][t], d2[2][t]);
        let row = stencil.row(rows[i] as usize);
        let normal = finish_normal::<K>(mode, du, dv, row, points, normals);
        sink.set_normal(slot(i), normal.into());
    }
}

/// A run of pattern points of one patch to evaluate ([`eval_block`], and `G` of them side by
/// side in `edge_groups`): its block, the patch's control points and normal net, and where
/// its points go.
#[derive(Clone, Copy)]
pub(crate) struct BlockRun<'a> {
    pub block: &'a Block,
    pub points: &'a [[f32; 3]],
    pub normals: &'a [[f32; 3]],
    /// The sink slot of the run's first point (in ascending slot order).
    pub base: usize,
    /// The points go in descending slot order (an edge stored against its owner's direction).
    pub reverse: bool,
}

/// The working arrays of [`eval_block`], one per parallel task and reused for all its blocks:
/// made per call, zeroing them cost more instructions than the evaluation itself.
pub(crate) struct Scratch {
    pub(super) pos: [[f32; TILE]; 3],
    pub(super) d1: [[f32; TILE]; 3],
    pub(super) d2: [[f32; TILE]; 3],
    pub(super) unit: [[f32; TILE]; 3],
    /// A tile as points, on its way to a streaming sink.
    pub(super) stage: [[f32; 3]; TILE],
    /// Control points spread over whole vectors (`[k][c][lane]`), see [`accumulate`].
    spread: [[[f32; LANES]; 3]; MAX_CONTROLS],
}

impl Scratch {
    pub fn new() -> Box<Scratch> {
        Box::new(Scratch {
            pos: [[0.0; TILE]; 3],
            d1: [[0.0; TILE]; 3],
            d2: [[0.0; TILE]; 3],
            unit: [[0.0; TILE]; 3],
            stage: [[0.0; 3]; TILE],
            spread: [[[0.0; LANES]; 3]; MAX_CONTROLS],
        })
    }
}

thread_local! {
    /// Each thread's [`Scratch`], kept between tasks and frames.
    static SCRATCH: std::cell::Cell<Option<Box<Scratch>>> = const { std::cell::Cell::new(None) };
}

impl Scratch {
    /// This thread's scratch (a new one the first time), handed back when the guard drops:
    /// made per task, its 18 KiB were zeroed and moved 300 times a frame at level 16.
    pub fn take() -> ScratchGuard {
        ScratchGuard(Some(SCRATCH.take().unwrap_or_else(Scratch::new)))
    }
}

/// A thread's [`Scratch`] on loan ([`Scratch::take`]).
pub(crate) struct ScratchGuard(Option<Box<Scratch>>);

impl std::ops::Deref for ScratchGuard {
    type Target = Scratch;
    fn deref(&self) -> &Scratch {
        self.0.as_ref().expect("held until dropped")
    }
}

impl std::ops::DerefMut for ScratchGuard {
    fn deref_mut(&mut self) -> &mut Scratch {
        self.0.as_mut().expect("held until dropped")
    }
}

impl Drop for ScratchGuard {
    fn drop(&mut self) {
        SCRATCH.set(self.0.take());
    }
}

/// Defines a kernel written once as `$body::<K, G>` (`G` vectors summed side by side): the
/// dispatcher `$name::<K>`, which runs the widest copy the CPU has, and the copies `$avx512`
/// (four vectors side by side, twelve accumulators of its 32 registers) and `$avx2` (one: 16
/// registers), each `$body` compiled with that target feature. The baseline (SSE2, or any other
/// architecture) runs `$body::<K, 1>` as compiled. The bits are the same on every copy: Rust
/// never fuses a multiply and an add on its own, so wider vectors change only how many lanes
/// run at once.
macro_rules! dispatched_kernel {
    (
        $(#[$attr:meta])*
        $vis:vis fn $name:ident = $body:ident, $avx512:ident, $avx2:ident
        ($($arg:ident: $ty:ty),* $(,)?)
    ) => {
        $(#[$attr])*
        #[allow(clippy::too_many_arguments)]
        #[inline]
        $vis fn $name<const K: usize>($($arg: $ty),*) {
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU was just checked to have AVX-512F, the only feature enabled
                // there.
                unsafe { $avx512::<K>($($arg),*) };
                return;
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU was just checked to have AVX2, the only feature the copy
                // enables.
                unsafe { $avx2::<K>($($arg),*) };
                return;
            }
            $body::<K, 1>($($arg),*);
        }
        compiled_for!($avx512, $body, "avx512f", 4, ($($arg: $ty),*));
        compiled_for!($avx2, $body, "avx2", 1, ($($arg: $ty),*));
    };
}
pub(super) use dispatched_kernel;

/// Defines `$name`: `$body::<K, $group>` compiled with the target feature `$feature`.
macro_rules! compiled_for {
    ($name:ident, $body:ident, $feature:literal, $group:literal, ($($arg:ident: $ty:ty),*)) => {
        #[doc = concat!("[`", stringify!($body), "`] compiled for `", $feature, "`.")]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $name<const K: usize>($($arg: $ty),*) {
            $body::<K, $group>($($arg),*);
        }
    };
}
pub(super) use compiled_for;

dispatched_kernel! {
    /// Evaluates a run of pattern points of one patch ([`BlockRun`]) into `sink` slots
    /// `base..base + len` (reversed when `reverse`, for edges stored against the owner's
    /// direction). Normals are computed only when the sink takes them. Equal, bit for bit, to
    /// [`eval_point`] on each point, with the code compiled for the widest vectors the CPU has.
    pub(crate) fn eval_block = eval_block_body, eval_block_avx512, eval_block_avx2 (
        run: &BlockRun,
        stencil: &Stencil,
        mode: NormalMode,
        sink: &mut Sink,
        scratch: &mut Scratch,
    )
}

#[inline(always)]
pub(super) fn eval_block_body<const K: usize, const G: usize>(
    run: &BlockRun,
    stencil: &Stencil,
    mode: NormalMode,
    sink: &mut Sink,
    scratch: &mut Scratch,
) {
    let BlockRun {
        block,
        points,
        normals,
        base,
        reverse,
    } = *run;
    let points: &[[f32; 3]; K] = points.try_into().expect("patch has K control points");
    let len = block.len();
    let want_normals = sink.wants_normals();
    let slot = |i: usize| base + if reverse { len - 1 - i } else { i };
    let Scratch {
        pos,
        d1,
        d2,
        unit,
        stage,
        spread,
    } = scratch;
    // The patch's normal net: what the quadratic normals sum, and what the fallback of a real
    // normal with parallel derivatives uses (as `eval_point` does).
    let patch_normals = normals;
    let normals: &[[f32; 3]; NORMAL_NET_LEN] = if want_normals && mode != NormalMode::Real {
        normals.try_into().expect("normal net has 6 entries")
    } else {
        &[[0.0; 3]; NORMAL_NET_LEN]
    };
    // Real normals of a cubic: `Du` and `Dv` summed from the derivative nets with the normal
    // weights (six terms each instead of ten).
    let derivative_nets = (want_normals && mode == NormalMode::Real && K == CUBIC_LEN)
        .then(|| cubic_derivative_nets(points[..].try_into().expect("cubic patch")));
    for start in (0..len).step_by(TILE) {
        let n = TILE.min(len - start);
        let vectors = n.div_ceil(LANES);
        accumulate::<K, G>(&block.value, block.stride, start, n, points, spread, pos);
        let mut all_ok = true;
        if want_normals {
            all_ok = if mode == NormalMode::Real {
                if let Some((du_net, dv_net)) = &derivative_nets {
                    accumulate::<NORMAL_NET_LEN, G>(
                        &block.normal,
                        block.stride,
                        start,
                        n,
                        du_net,
                        spread,
                        d1,
                    );
                    accumulate::<NORMAL_NET_LEN, G>(
                        &block.normal,
                        block.stride,
                        start,
                        n,
                        dv_net,
                        spread,
                        d2,
                    );
                } else {
                    accumulate::<K, G>(&block.du, block.stride, start, n, points, spread, d1);
                    accumulate::<K, G>(&block.dv, block.stride, start, n, points, spread, d2);
                }
                cross_vectors(d1, d2, 0, vectors, n, unit)
            } else {
                accumulate::<NORMAL_NET_LEN, G>(
                    &block.normal,
                    block.stride,
                    start,
                    n,
                    normals,
                    spread,
                    unit,
                );
                normalize_vectors(unit, 0, vectors, n)
            };
        }
        let first = slot(start);
        sink.put_tile(
            first,
            reverse,
            n,
            0,
            pos,
            want_normals.then_some(&*unit),
            stage,
        );
        if !all_ok {
            fallback_normals::<K>(
                (d1, d2, unit),
                0,
                n,
                &block.points[start..],
                stencil,
                mode,
                (points, patch_normals),
                sink,
                |i| slot(start + i),
            );
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::basis::Basis;
    use crate::pattern::Pattern;
    use crate::refine::cpu::output::VertexOutput;

    /// A small deterministic generator, so the nets below need no crate.
    fn lcg(seed: &mut u64) -> f32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// The positions and normals `run` writes into a sink of `n` separate slots, streamed or
    /// not.
    pub(in crate::refine) fn into_arrays(
        n: usize,
        stream: bool,
        run: impl FnOnce(&mut Sink),
    ) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        let (mut pos, mut nrm) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
        {
            let mut sink = VertexOutput::Separate {
                positions: &mut pos,
                normals: Some(&mut nrm),
                uvs: None,
            }
            .sink(n, false)
            .unwrap()
            .streaming(stream);
            assert_eq!(sink.streams(), stream);
            run(&mut sink);
        }
        (pos, nrm)
    }

    /// A patch's control points and normal net for the bit-for-bit tests. Case 0 or 1: random;
    /// 2: a vanishing normal net and all control points on a line (parallel derivatives);
    /// 3: as 2 with every control point at the origin; 4: random, with a normal net so large
    /// that |n|² overflows (1 / sqrt is 0); 5: control points on a line with a random normal
    /// net (real normals fall back to the net). Cases 2-5 take the scalar fallbacks.
    pub(in crate::refine) fn test_patch<const K: usize>(
        seed: &mut u64,
        case: usize,
    ) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        let mut points: Vec<[f32; 3]> = (0..K).map(|_| [0; 3].map(|_| lcg(seed))).collect();
        let mut normals: Vec<[f32; 3]> = (0..NORMAL_NET_LEN)
            .map(|_| [0; 3].map(|_| lcg(seed)))
            .collect();
        if (2..4).contains(&case) {
            normals.iter_mut().for_each(|n| *n = [0.0; 3]);
            points.iter_mut().for_each(|p| *p = [p[0], 2.0 * p[0], 0.0]);
        }
        if case == 3 {
            points.iter_mut().for_each(|p| *p = [0.0; 3]);
        }
        if case == 4 {
            normals.iter_mut().for_each(|n| *n = n.map(|c| c * 1e30));
        }
        if case == 5 {
            // Collinear control points (parallel derivatives) with a normal net that stands:
            // real normals fall back to the net.
            points.iter_mut().for_each(|p| *p = [p[0], 2.0 * p[0], 0.0]);
        }
        (points, normals)
    }

    /// Runs every block point through `run` and through [`eval_point`]: same bits for
    /// positions and normals, for random nets and for nets whose normals and derivatives
    /// vanish (the fallbacks).
    fn check<const K: usize>(
        basis: Basis,
        eval: impl Fn(&BlockRun, &Stencil, NormalMode, &mut Sink),
    ) {
        // Level 24: 325 points, more than one tile, so tiles after the first are covered.
        let stencil = Stencil::new(&Pattern::uniform(24), basis);
        assert!(stencil.blocks.all.len() > TILE);
        let block = &stencil.blocks.all;
        let mut seed = 7;
        for case in 0..6 {
            let (points, normals) = test_patch::<K>(&mut seed, case);
            for (mode, reverse, stream) in [
                (NormalMode::Quadratic, false, false),
                (NormalMode::Real, false, false),
                (NormalMode::Quadratic, true, false),
                (NormalMode::Real, true, false),
                (NormalMode::Quadratic, false, true),
                (NormalMode::Real, true, true),
            ] {
                let n = block.len();
                let run = BlockRun {
                    block,
                    points: &points,
                    normals: &normals,
                    base: 0,
                    reverse,
                };
                let (pos, nrm) = into_arrays(n, stream, |sink| eval(&run, &stencil, mode, sink));
                for (i, &p) in block.points.iter().enumerate() {
                    let (want_p, want_n) =
                        eval_point::<K>(stencil.row(p as usize), &points, &normals, mode);
                    let bits = |v: [f32; 3]| v.map(f32::to_bits);
                    let at = if reverse { n - 1 - i } else { i };
                    let what =
                        format!("case {case} {mode:?} reverse {reverse} stream {stream} point {i}");
                    assert_eq!(bits(pos[at]), bits(want_p), "{what}");
                    assert_eq!(bits(nrm[at]), bits(want_n), "{what}");
                }
            }
        }
    }

    #[test]
    fn cubic_derivative_nets_give_the_basis_derivatives() {
        let mut seed = 3;
        let points: [[f32; 3]; CUBIC_LEN] = [0; CUBIC_LEN].map(|_| [0; 3].map(|_| lcg(&mut seed)));
        let (du_net, dv_net) = cubic_derivative_nets(&points);
        for l in [
            [1.0, 0.0, 0.0],
            [0.2, 0.3, 0.5],
            [0.0, 0.6, 0.4],
            [1.0 / 3.0; 3],
        ] {
            // The basis's own derivative weights, in f64.
            let w = Basis::Cubic.weights(l);
            let q = crate::basis::normal_weights(l);
            for c in 0..3 {
                let want_u: f64 = (0..CUBIC_LEN).map(|k| w.du[k] * points[k][c] as f64).sum();
                let want_v: f64 = (0..CUBIC_LEN).map(|k| w.dv[k] * points[k][c] as f64).sum();
                let got_u: f64 = (0..6).map(|j| q[j] * du_net[j][c] as f64).sum();
                let got_v: f64 = (0..6).map(|j| q[j] * dv_net[j][c] as f64).sum();
                assert!((got_u - want_u).abs() < 1e-5, "{l:?} du {got_u} {want_u}");
                assert!((got_v - want_v).abs() < 1e-5, "{l:?} dv {got_v} {want_v}");
            }
        }
    }

    #[test]
    fn block_evaluation_equals_point_evaluation_bit_for_bit() {
        check::<10>(Basis::Cubic, |r, s, m, sink| {
            eval_block::<10>(r, s, m, sink, &mut Scratch::new())
        });
        check::<21>(Basis::Png1, |r, s, m, sink| {
            eval_block::<21>(r, s, m, sink, &mut Scratch::new())
        });
        // The baseline code as well, whatever the machine dispatches to.
        check::<10>(Basis::Cubic, |r, s, m, sink| {
            eval_block_body::<10, 1>(r, s, m, sink, &mut Scratch::new())
        });
        check::<21>(Basis::Png1, |r, s, m, sink| {
            eval_block_body::<21, 1>(r, s, m, sink, &mut Scratch::new())
        });
        // And summing several vectors side by side (the AVX-512 choice), on any machine.
        check::<10>(Basis::Cubic, |r, s, m, sink| {
            eval_block_body::<10, 4>(r, s, m, sink, &mut Scratch::new())
        });
        check::<21>(Basis::Png1, |r, s, m, sink| {
            eval_block_body::<21, 4>(r, s, m, sink, &mut Scratch::new())
        });
        // The AVX2 copy where the CPU has it (a machine with AVX-512 dispatches past it).
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY (both): the CPU has AVX2, checked just above.
            check::<10>(Basis::Cubic, |r, s, m, sink| unsafe {
                eval_block_avx2::<10>(r, s, m, sink, &mut Scratch::new())
            });
            check::<21>(Basis::Png1, |r, s, m, sink| unsafe {
                eval_block_avx2::<21>(r, s, m, sink, &mut Scratch::new())
            });
        }
    }
}
