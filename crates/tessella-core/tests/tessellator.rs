//! Hardware tessellator patterns (`tessellator::tessellate`) against facts that do not come from
//! the code: counts from the hardware documentation, exact tiling of the domain, watertight
//! edges, continuity of fractional spacing, culling and clamping, and small cases worked by hand
//! from the D3D11 reference algorithm.

use std::collections::HashMap;
use tessella_core::pattern::PointClass;
use tessella_core::tessellator::{process_levels, tessellate, Partitioning, TessLevels};
use tessella_core::Pattern;

const ULP: f64 = 1.0 / 65536.0;
const SPACINGS: [Partitioning; 3] = [
    Partitioning::Equal,
    Partitioning::FractionalOdd,
    Partitioning::FractionalEven,
];

fn levels(inner: f32, outer: [f32; 3]) -> TessLevels {
    TessLevels { inner, outer }
}

/// Twice the signed area in the `(l2, l3)` plane (the whole domain has +1).
fn area2(p: &Pattern, t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|i| p.points[i as usize]);
    (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1])
}

/// The pattern tiles the domain: every point inside it with barycentrics summing to 1, no
/// triangle turned over (and none flat when `strict`), areas summing to the domain's, and every
/// edge either shared by two triangles in opposite directions or lying on the domain boundary.
/// Positive areas adding up to the whole with such a manifold edge structure leave no overlap.
fn assert_tiles(p: &Pattern, strict: bool, what: &str) {
    for (i, l) in p.points.iter().enumerate() {
        assert!(
            l.iter().all(|&x| (0.0..=1.0).contains(&x)),
            "{what}: point {i} {l:?}"
        );
        assert!(
            (l.iter().sum::<f64>() - 1.0).abs() <= ULP,
            "{what}: point {i}"
        );
    }
    let mut total = 0.0;
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, &t) in p.triangles.iter().enumerate() {
        let a = area2(p, t);
        if strict {
            assert!(a > 0.0, "{what}: triangle {k} {t:?} has area {a}");
        } else {
            assert!(a >= 0.0, "{what}: triangle {k} {t:?} is turned over ({a})");
        }
        total += a;
        for e in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *directed.entry(e).or_default() += 1;
        }
    }
    // Coordinates are multiples of 2⁻¹⁶, so these sums are exact.
    assert_eq!(total, 1.0, "{what}: areas");
    for (&(a, b), &n) in &directed {
        assert_eq!(
            n, 1,
            "{what}: edge {a}->{b} used {n} times in one direction"
        );
        if !directed.contains_key(&(b, a)) {
            let (pa, pb) = (p.points[a as usize], p.points[b as usize]);
            assert!(
                (0..3).any(|i| pa[i] == 0.0 && pb[i] == 0.0),
                "{what}: unpaired edge {a}->{b} inside the domain"
            );
        }
    }
}

/// Positions along our edge `edge` (from its first corner), in step order: corner, edge points,
/// end corner. Edge 0 runs P1 → P2, 1 P2 → P3, 2 P3 → P1.
fn edge_params(p: &Pattern, edge: u8) -> Vec<f64> {
    let (start, end) = (edge as usize, (edge as usize + 1) % 3);
    let mut steps: Vec<(u32, f64)> = Vec::new();
    for (l, c) in p.points.iter().zip(&p.classes) {
        match *c {
            PointClass::Corner { corner } if corner as usize == start => steps.push((0, 0.0)),
            PointClass::Corner { corner } if corner as usize == end => steps.push((u32::MAX, 1.0)),
            PointClass::Edge { edge: e, step } if e == edge => steps.push((step, l[end])),
            _ => {}
        }
    }
    steps.sort_by_key(|s| s.0);
    steps.into_iter().map(|s| s.1).collect()
}

/// Our edge index of `outer[k]` (the edge `l_{k+1} = 0`).
fn edge_of(k: usize) -> u8 {
    [1, 2, 0][k]
}

#[test]
fn equal_spacing_counts_and_tiles() {
    for n in 1..=64u32 {
        let p = tessellate(Partitioning::Equal, TessLevels::uniform(n as f32));
        let t = p.triangles.len() as u32;
        let expected = if n == 1 { 1 } else { (3 * n * n - n % 2) / 2 };
        assert_eq!(t, expected, "level {n}");
        // Euler on a disk with 3n boundary edges: V = 1 + (T + 3n) / 2.
        assert_eq!(p.points.len() as u32, 1 + (t + 3 * n) / 2, "level {n}");
        assert_tiles(&p, true, &format!("equal {n}"));
        assert_eq!(p.level, n);
    }
}

#[test]
fn every_spacing_tiles_for_mixed_levels() {
    let values = [
        0.5, 1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 3.7, 4.0, 5.5, 8.01, 13.3, 31.9, 63.5, 64.0,
    ];
    let mut cases = 0;
    for spacing in SPACINGS {
        for (a, &i) in values.iter().enumerate() {
            for o in [
                [i, i, i],
                [
                    values[(a + 3) % 15],
                    values[(a + 7) % 15],
                    values[(a + 11) % 15],
                ],
                [1.0, values[(a + 5) % 15], 64.0],
            ] {
                let p = tessellate(spacing, levels(i, o));
                // Fractional levels just above a parity step give flat triangles (new points on
                // top of old ones, by design); equal spacing never does.
                let strict = spacing == Partitioning::Equal;
                assert_tiles(&p, strict, &format!("{spacing:?} {i} {o:?}"));
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 3 * 15 * 3);
}

#[test]
fn equal_spacing_puts_edge_points_at_k_over_n() {
    for n in 1..=64u32 {
        let p = tessellate(Partitioning::Equal, levels(5.0, [n as f32, 3.0, 2.0]));
        let t = edge_params(&p, edge_of(0));
        assert_eq!(t.len() as u32, n + 1);
        for (k, &x) in t.iter().enumerate() {
            let k = k as u32;
            // The hardware multiplies by a 16-bit reciprocal (off by at most half an ulp) and
            // mirrors the second half: the error grows with the distance to the nearer end.
            let bound = k.min(n - k) as f64 * ULP / 2.0;
            assert!(
                (x - k as f64 / n as f64).abs() <= bound,
                "n {n}, k {k}: {x}"
            );
            if n.is_power_of_two() {
                assert_eq!(x, k as f64 / n as f64, "n {n}, k {k}");
            }
        }
    }
}

#[test]
fn outer_edges_depend_only_on_their_own_level_and_are_symmetric() {
    let values = [
        1.0f32, 1.3, 2.0, 2.5, 3.0, 3.7, 6.2, 7.01, 16.5, 33.3, 63.0, 64.0,
    ];
    let others = [
        (1.0, [1.0, 1.0]),
        (7.5, [2.0, 40.0]),
        (64.0, [5.5, 1.5]),
        (f32::NAN, [3.0, 3.0]),
    ];
    for spacing in SPACINGS {
        for &f in &values {
            let mut reference: Option<Vec<f64>> = None;
            for k in 0..3 {
                for &(inner, [a, b]) in &others {
                    let mut outer = [a, b, a];
                    outer[k] = f;
                    outer[(k + 1) % 3] = b;
                    let p = tessellate(spacing, levels(inner, outer));
                    let t = edge_params(&p, edge_of(k));
                    // Bit-identical whatever the other levels are, on whichever edge.
                    match &reference {
                        None => reference = Some(t.clone()),
                        Some(r) => assert_eq!(&t, r, "{spacing:?} {f} on outer[{k}], {outer:?}"),
                    }
                    // Read from the other end (as the neighbouring patch does), position
                    // n - i is exactly 1 - position i.
                    let n = t.len() - 1;
                    for i in 0..=n {
                        assert_eq!(t[n - i], 1.0 - t[i], "{spacing:?} {f}: point {i}");
                    }
                    assert!(t.windows(2).all(|w| w[0] <= w[1]), "{spacing:?} {f}: order");
                }
            }
        }
    }
}

/// Hausdorff distance between two point sets (brute force).
fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let d = |p: &[f64; 3], q: &[f64; 3]| (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f64::max);
    let one_way = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .map(|p| b.iter().map(|q| d(p, q)).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

#[test]
fn fractional_points_move_continuously() {
    let delta = 1e-3f32;
    // A point moves at most as fast as the half-level's fraction (1/2 per unit level) times a
    // segment (≤ 1), plus fixed-point rounding.
    let tol = delta as f64 + 4.0 * ULP;
    for spacing in [Partitioning::FractionalOdd, Partitioning::FractionalEven] {
        let (lo, hi) = spacing.range();
        // A grid of levels, plus each parity step (odd integers for fractional-odd, even ones for
        // fractional-even), where the pair (f, f + delta) gains points.
        // The grid starts at the minimum, itself a step: fractional-odd goes from the single
        // triangle of level 1 to a ring, fractional-even from 2 to 4 segments.
        let first_step = if spacing == Partitioning::FractionalOdd {
            3
        } else {
            4
        };
        let mut fs: Vec<f32> = (0..)
            .map(|i| lo + 0.0635 * i as f32)
            .take_while(|&f| f + delta <= hi)
            .collect();
        fs.extend((first_step..hi as i32).step_by(2).map(|s| s as f32));
        let (mut steps, mut topology_changes) = (0, 0);
        for f in fs {
            let (a, b) = (
                tessellate(spacing, TessLevels::uniform(f)),
                tessellate(spacing, TessLevels::uniform(f + delta)),
            );
            if a.points.len() == b.points.len() {
                // Same topology: every point moves a little.
                for (i, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
                    let jump = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max);
                    assert!(jump <= tol, "{spacing:?} {f}: point {i} jumps {jump}");
                }
            } else {
                // A parity step: new points appear on top of existing ones.
                assert!(b.points.len() > a.points.len(), "{spacing:?} {f}");
                let h = hausdorff(&a.points, &b.points);
                assert!(h <= tol, "{spacing:?} {f}: new points start {h} away");
                topology_changes += 1;
            }
            steps += 1;
        }
        // Every parity step changed the topology (and nothing else did more than that).
        let expected = 1 + (first_step..hi as i32).step_by(2).count();
        assert_eq!(topology_changes, expected, "{spacing:?}");
        assert!(steps > 30);
    }
}

#[test]
fn new_edge_points_start_as_zero_length_segments() {
    // At the parity steps (odd integers for fractional-odd, even integers for fractional-even)
    // an edge gains two segments, which start with zero length.
    for (spacing, steps) in [
        (
            Partitioning::FractionalOdd,
            [3.0f32, 5.0, 7.0, 9.0, 17.0, 33.0, 61.0],
        ),
        (
            Partitioning::FractionalEven,
            [2.0f32, 4.0, 6.0, 8.0, 16.0, 32.0, 62.0],
        ),
    ] {
        for s in steps {
            let at = edge_params(&tessellate(spacing, TessLevels::uniform(s)), 0);
            let after = edge_params(
                &tessellate(spacing, TessLevels::uniform(s + 1.0 / 1024.0)),
                0,
            );
            assert_eq!(after.len(), at.len() + 2, "{spacing:?} {s}");
            let short: Vec<f64> = after
                .windows(2)
                .map(|w| w[1] - w[0])
                .filter(|&d| d < 1.0 / 512.0)
                .collect();
            assert_eq!(short.len(), 2, "{spacing:?} {s}: {after:?}");
            // Every other segment still has (nearly) its length at the step.
            assert!(
                after
                    .windows(2)
                    .filter(|w| w[1] - w[0] >= 1.0 / 512.0)
                    .count()
                    == at.len() - 1
            );
        }
    }
}

#[test]
fn culled_patches_are_empty() {
    for spacing in SPACINGS {
        for bad in [0.0, -0.0, -1.0, f32::NAN, f32::NEG_INFINITY, -1e30] {
            for k in 0..3 {
                let mut outer = [4.0; 3];
                outer[k] = bad;
                let l = levels(4.0, outer);
                assert!(process_levels(spacing, l).is_none());
                let p = tessellate(spacing, l);
                assert!(p.points.is_empty() && p.triangles.is_empty() && p.classes.is_empty());
                assert_eq!(p.level, 0);
            }
        }
        // A bad inner level does not cull: it is clamped to the minimum.
        for inner in [f32::NAN, -5.0, 0.0] {
            let p = tessellate(spacing, levels(inner, [4.0; 3]));
            let lo = tessellate(spacing, levels(spacing.range().0, [4.0; 3]));
            assert_eq!(p, lo, "{spacing:?} inner {inner}");
        }
    }
}

#[test]
fn levels_are_clamped_to_the_hardware_range() {
    for spacing in SPACINGS {
        let (lo, hi) = spacing.range();
        let top = tessellate(spacing, TessLevels::uniform(hi));
        for big in [hi + 0.5, 100.0, 1e30, f32::INFINITY] {
            assert_eq!(
                tessellate(spacing, TessLevels::uniform(big)),
                top,
                "{spacing:?} {big}"
            );
            assert_eq!(
                tessellate(spacing, levels(3.0, [big, 2.0, 5.0])),
                tessellate(spacing, levels(3.0, [hi, 2.0, 5.0])),
                "{spacing:?} {big}"
            );
        }
        // Tiny positive levels are raised to the minimum (they do not cull).
        assert_eq!(
            tessellate(spacing, TessLevels::uniform(1e-30)),
            tessellate(spacing, TessLevels::uniform(lo))
        );
    }
    // The hardware maxima: 64 segments (equal, fractional-even), 63 (fractional-odd).
    let segs = |s| {
        process_levels(s, TessLevels::uniform(1000.0))
            .unwrap()
            .outer_segments
    };
    assert_eq!(segs(Partitioning::Equal), [64; 3]);
    assert_eq!(segs(Partitioning::FractionalEven), [64; 3]);
    assert_eq!(segs(Partitioning::FractionalOdd), [63; 3]);
    // Equal spacing rounds up; fractional-odd keeps the inner level above 1 when an edge is.
    let p = process_levels(Partitioning::Equal, levels(2.2, [1.01, 3.0, 4.5])).unwrap();
    assert_eq!(p.levels.outer, [2.0, 3.0, 5.0]);
    assert_eq!(p.levels.inner, 3.0);
    let p = process_levels(Partitioning::FractionalOdd, levels(1.0, [1.0, 2.0, 1.0])).unwrap();
    assert!(p.levels.inner > 1.0 && !p.single_triangle);
}

#[test]
fn level_one_is_a_single_triangle() {
    let corners = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
    for spacing in [Partitioning::Equal, Partitioning::FractionalOdd] {
        for l in [1.0, 0.3, 1e-20] {
            let p = tessellate(spacing, TessLevels::uniform(l));
            assert_eq!(p.points, corners, "{spacing:?} {l}");
            assert_eq!(p.triangles, [[0, 1, 2]]);
            assert!(area2(&p, p.triangles[0]) > 0.0);
        }
    }
    // Fractional-even has no level 1: its minimum, 2, is the six-triangle fan below.
    assert_eq!(
        tessellate(Partitioning::FractionalEven, TessLevels::uniform(1.0)),
        tessellate(Partitioning::Equal, TessLevels::uniform(2.0))
    );
}

#[test]
fn level_two_by_hand() {
    // Equal spacing, all levels 2. Each outer edge has 3 points, listed from its first corner
    // without its last: P2, mid(P2P3), P3, mid(P3P1), P1, mid(P1P2). The inner level 2 has 3
    // points, so no ring, only the centre, at (0x5555, 0x5555) in 16.16 with w = 1 - u - v.
    // Connectivity: each side's transition strip is two triangles fanning to the centre.
    let p = tessellate(Partitioning::Equal, TessLevels::uniform(2.0));
    let c = 21845.0 / 65536.0;
    assert_eq!(
        p.points,
        [
            [0.0, 1.0, 0.0],
            [0.0, 0.5, 0.5],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, 0.5],
            [1.0, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [c, c, 1.0 - 2.0 * c],
        ]
    );
    assert_eq!(
        p.triangles,
        [
            [0, 1, 6],
            [1, 2, 6],
            [2, 3, 6],
            [3, 4, 6],
            [4, 5, 6],
            [5, 0, 6]
        ]
    );
    assert_eq!(
        p.classes[..6],
        [
            PointClass::Corner { corner: 1 },
            PointClass::Edge { edge: 1, step: 1 },
            PointClass::Corner { corner: 2 },
            PointClass::Edge { edge: 2, step: 1 },
            PointClass::Corner { corner: 0 },
            PointClass::Edge { edge: 0, step: 1 },
        ]
    );
    // Fractional-even 2 is the same layout.
    assert_eq!(
        tessellate(Partitioning::FractionalEven, TessLevels::uniform(2.0)),
        p
    );
}

#[test]
fn fractional_odd_one_and_a_half_by_hand() {
    // Fractional-odd, all levels 1.5 (0x18000). Half-level (0x18000 + 1) / 2 + 1/2 = 1.25:
    // floor 1 (1 segment), ceil 2 (3 segments), fraction 1/4. Point 1 of an edge lerps from
    // 0 (floor layout) to 0x5555 (1/3) by 1/4: (0x5555 · 0x4000 + 0x8000) >> 16 = 0x1555 = 5461;
    // point 2 is its mirror 65536 - 5461 = 60075. So each edge is 0, t, 1 - t, 1 (t ≈ 1/12).
    let t = 5461.0 / 65536.0;
    let p = tessellate(Partitioning::FractionalOdd, TessLevels::uniform(1.5));
    assert_eq!(edge_params(&p, 0), [0.0, t, 1.0 - t, 1.0]);
    // Inner ring 1 (one point per side): perpendicular distance 5461 · 0xaaaa rounded >> 16 =
    // 3641, the side parameter slides back by (3641 + 1) / 2 = 1821:
    //   side u = 0: (u, v) = (3641, 60075 - 1821)          -> w = 3641
    //   side v = 0: (u, v) = (5461 - 1821, 3641)           -> w = 58255
    //   side w = 0: u = 60075 - 1821, v = 65536 - u - 3641 -> (58254, 3641, 3641)
    let q = |a: f64, b: f64, c: f64| [a / 65536.0, b / 65536.0, c / 65536.0];
    assert_eq!(p.points.len(), 9 + 3);
    assert_eq!(
        p.points[9..],
        [
            q(3641.0, 58254.0, 3641.0),
            q(3640.0, 3641.0, 58255.0),
            q(58254.0, 3641.0, 3641.0)
        ]
    );
    // Per side: one triangle at the start, the quad of the two middle segments, one at the end;
    // then the inner ring's triangle: 3 · 4 + 1 = 13.
    assert_eq!(p.triangles.len(), 13);
    assert_eq!(
        p.triangles[..4],
        [[0, 1, 9], [9, 1, 10], [10, 1, 2], [2, 3, 10]]
    );
    assert_eq!(p.triangles[12], [9, 10, 11]);
    assert_tiles(&p, true, "odd 1.5");
}
