//! Refinement patterns (Boubekeur & Schlick 2005): one pre-tessellated triangle, stored once and
//! mapped onto every coarse triangle.
//!
//! The uniform pattern of level `N` has `N` segments per coarse edge, `(N+1)(N+2)/2` points and
//! `N²` small triangles. A point is named by integers `(i, j)` with `i, j ≥ 0`, `i + j ≤ N`; its
//! barycentric coordinates are `(l1, l2, l3) = ((N-i-j)/N, i/N, j/N)`, weights of the coarse
//! corners `(P1, P2, P3)`. Points are stored row by row (`j` outer, `i` inner). Small triangles
//! keep the coarse winding.

use serde::Serialize;

/// Where a pattern point lies on the coarse triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PointClass {
    /// Coarse corner `corner` (0, 1, 2 for P1, P2, P3).
    Corner { corner: u8 },
    /// Inside coarse edge `edge` (from corner `edge` to corner `edge+1 mod 3`), `step` segments
    /// from its start, `1..N`.
    Edge { edge: u8, step: u32 },
    /// Inside the triangle; `index` counts interior points in storage order.
    Interior { index: u32 },
}

/// A uniform refinement pattern: plain tables every backend reuses.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Pattern {
    /// Segments per coarse edge.
    pub level: u32,
    /// Barycentric `(l1, l2, l3)` of each point, exact in f64.
    pub points: Vec<[f64; 3]>,
    /// Small triangles as point indices, counter-clockwise like the coarse triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Where each point lies (corner, edge, interior).
    pub classes: Vec<PointClass>,
}

impl Pattern {
    /// Number of points of the level-`n` pattern.
    pub const fn point_count(n: u32) -> u64 {
        (n as u64 + 1) * (n as u64 + 2) / 2
    }
    /// Number of interior points of the level-`n` pattern.
    pub const fn interior_count(n: u32) -> u64 {
        if n < 3 {
            0
        } else {
            (n as u64 - 1) * (n as u64 - 2) / 2
        }
    }

    /// Storage index of point `(i, j)`.
    #[inline]
    pub fn index(level: u32, i: u32, j: u32) -> u32 {
        // Rows 0..j hold (N+1) + N + ... + (N+2-j) points.
        j * (level + 1) - j * (j.saturating_sub(1)) / 2 + i
    }

    /// The uniform pattern of `level` segments per edge (`level ≥ 1`).
    ///
    /// ```
    /// let p = tessella_core::Pattern::uniform(2);
    /// assert_eq!(p.points.len(), 6);
    /// assert_eq!(p.triangles.len(), 4);
    /// assert_eq!(p.points[1], [0.5, 0.5, 0.0]);
    /// ```
    pub fn uniform(level: u32) -> Pattern {
        assert!(level >= 1, "pattern level must be at least 1");
        let n = level;
        let mut points = Vec::with_capacity(Self::point_count(n) as usize);
        let mut classes = Vec::with_capacity(points.capacity());
        let mut interior = 0;
        for j in 0..=n {
            for i in 0..=(n - j) {
                let k = n - i - j;
                let nf = n as f64;
                points.push([k as f64 / nf, i as f64 / nf, j as f64 / nf]);
                classes.push(classify(n, i, j, &mut interior));
            }
        }
        let mut triangles = Vec::with_capacity((n * n) as usize);
        for j in 0..n {
            for i in 0..(n - j) {
                let a = Self::index(n, i, j);
                let b = Self::index(n, i + 1, j);
                let c = Self::index(n, i, j + 1);
                triangles.push([a, b, c]);
                if i + 1 < n - j {
                    let d = Self::index(n, i + 1, j + 1);
                    triangles.push([b, d, c]);
                }
            }
        }
        Pattern {
            level,
            points,
            triangles,
            classes,
        }
    }
}

fn classify(n: u32, i: u32, j: u32, interior: &mut u32) -> PointClass {
    let k = n - i - j;
    match (i, j, k) {
        (0, 0, _) => PointClass::Corner { corner: 0 },
        (_, 0, 0) => PointClass::Corner { corner: 1 },
        (0, _, 0) => PointClass::Corner { corner: 2 },
        // Edge 0 runs P1 -> P2 (j = 0), edge 1 P2 -> P3 (k = 0), edge 2 P3 -> P1 (i = 0).
        (_, 0, _) => PointClass::Edge { edge: 0, step: i },
        (_, _, 0) => PointClass::Edge { edge: 1, step: j },
        (0, _, _) => PointClass::Edge {
            edge: 2,
            step: n - j,
        },
        _ => {
            *interior += 1;
            PointClass::Interior {
                index: *interior - 1,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_classes() {
        for n in 1..=12 {
            let p = Pattern::uniform(n);
            assert_eq!(p.points.len() as u64, Pattern::point_count(n));
            assert_eq!(p.triangles.len() as u32, n * n);
            let corners = p
                .classes
                .iter()
                .filter(|c| matches!(c, PointClass::Corner { .. }))
                .count();
            let edges = p
                .classes
                .iter()
                .filter(|c| matches!(c, PointClass::Edge { .. }))
                .count();
            let inner = p
                .classes
                .iter()
                .filter(|c| matches!(c, PointClass::Interior { .. }))
                .count();
            assert_eq!(
                (corners, edges as u32, inner as u64),
                (3, 3 * (n - 1), Pattern::interior_count(n))
            );
            for (pt, class) in p.points.iter().zip(&p.classes) {
                assert!((pt.iter().sum::<f64>() - 1.0).abs() < 1e-15);
                match *class {
                    PointClass::Corner { corner } => assert_eq!(pt[corner as usize], 1.0),
                    PointClass::Edge { edge, step } => {
                        let (s, e) = (edge as usize, (edge as usize + 1) % 3);
                        assert_eq!(pt[3 - s - e], 0.0);
                        assert!((pt[e] - step as f64 / n as f64).abs() < 1e-15);
                    }
                    PointClass::Interior { .. } => assert!(pt.iter().all(|&l| l > 0.0)),
                }
            }
        }
    }

    #[test]
    fn triangles_keep_winding_and_tile_the_triangle() {
        for n in 1..=9 {
            let p = Pattern::uniform(n);
            let mut area = 0.0;
            for t in &p.triangles {
                let [a, b, c] = t.map(|i| p.points[i as usize]);
                // Signed area in the (l2, l3) plane; the coarse triangle has +1/2.
                let s = 0.5 * ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]));
                assert!(s > 0.0);
                area += s;
            }
            assert!((area - 0.5).abs() < 1e-12);
        }
    }
}
