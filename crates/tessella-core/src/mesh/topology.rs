//! Edge adjacency of a [`Mesh`], at two levels:
//!
//! - **by vertex index**: the edges refined output shares. Two faces that use the same two vertex
//!   indices share their refined edge; each such edge is evaluated once, on its *owner* (the
//!   first face in file order that uses it).
//! - **by position**: the surface's real connectivity, also across hard edges and UV seams where
//!   a file splits a vertex. Neighbours across edges (for schemes that need them), boundary and
//!   non-manifold edges, split normals.

use super::Mesh;
use rayon::prelude::*;
// FxHash: the keys are vertex indices and position bits of the caller's own mesh, so a fast
// non-cryptographic hash is safe here (SipHash cost a tenth of a one-shot refinement).
use rustc_hash::FxHashMap as HashMap;

/// Marks "no neighbour" in [`Topology::neighbors`].
pub const NO_NEIGHBOR: u32 = u32::MAX;

/// Adjacency of a mesh; see the module docs.
#[derive(Debug, Clone)]
pub struct Topology {
    /// Unique edges by vertex index, `[a, b]` with `a < b`.
    pub edges: Vec<[u32; 2]>,
    /// For each face, the edge id of its local edge `k` (from corner `k` to corner `k + 1`).
    pub face_edges: Vec<[u32; 3]>,
    /// For each edge, the face that owns it and the owner's local edge index.
    pub edge_owner: Vec<(u32, u8)>,
    /// For each vertex, the face that owns it and the owner's local corner; `None` when no face
    /// uses the vertex.
    pub vertex_owner: Vec<Option<(u32, u8)>>,
    /// For each vertex, the lowest vertex index at the same position.
    pub position_ids: Vec<u32>,
    /// For each face and local edge, the face across that edge by position, or [`NO_NEIGHBOR`]
    /// on boundary and non-manifold edges.
    pub neighbors: Vec<[u32; 3]>,
    /// Counts for reports.
    pub report: TopologyReport,
}

/// What [`Topology`] found, for `tessella info` and quality reports.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct TopologyReport {
    pub vertices: usize,
    pub faces: usize,
    /// Distinct positions used by faces.
    pub positions: usize,
    /// Edges between positions.
    pub edges: usize,
    /// Edges with one face.
    pub boundary_edges: usize,
    /// Edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Edges whose two faces run the same direction along them (inconsistent winding).
    pub inconsistent_edges: usize,
    /// Edges whose two faces meet at one position but different vertices (hard edges, UV seams).
    pub seam_edges: usize,
    /// Positions carried by several vertices with different normals.
    pub split_normal_positions: usize,
    /// Vertices no face uses.
    pub unreferenced_vertices: usize,
    /// V - E + F over positions, edges and faces (2 for a closed sphere-like surface).
    pub euler_characteristic: i64,
}

impl TopologyReport {
    /// True when every edge has exactly two consistently oriented faces.
    pub fn is_closed_manifold(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0 && self.inconsistent_edges == 0
    }
}

/// For each vertex, the lowest vertex index with bit-identical position (`-0.0` equals `0.0`).
pub fn position_ids(positions: &[[f32; 3]]) -> Vec<u32> {
    let mut first: HashMap<[u32; 3], u32> =
        HashMap::with_capacity_and_hasher(positions.len(), Default::default());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *first
                .entry(p.map(|c| (c + 0.0).to_bits()))
                .or_insert(i as u32)
        })
        .collect()
}

/// One face's local edge: `(lo, hi, face, local edge, forward)`.
type HalfEdge = (u32, u32, u32, u8, bool);

/// Groups the faces' local edges by a key `(lo, hi)`: returns, sorted by key, the runs of
/// `(lo, hi, face, local edge, forward)` that share a key.
fn edge_runs(triangles: &[[u32; 3]], key: impl Fn(u32) -> u32 + Sync + Send) -> Vec<HalfEdge> {
    let half = half_edges(triangles, key);
    // Stable order inside a run (by face, then local edge) makes the owner the first face.
    // One thread (wasm) or a small mesh (a parallel sort's set-up costs more than the linear
    // sort there: a tenth of a batch of small files went to it): the counting sort.
    if cfg!(target_arch = "wasm32") || half.len() <= SORT_IN_PARALLEL_FROM {
        return sorted_by_buckets(half);
    }
    sorted_in_parallel(half)
}

/// Half-edges from which they are made and sorted in parallel (native builds).
const SORT_IN_PARALLEL_FROM: usize = 1 << 16;

/// The faces' local edges in face order, keyed (in parallel for large meshes only: for a
/// few hundred faces, collecting across threads costs more than the loop).
fn half_edges(triangles: &[[u32; 3]], key: impl Fn(u32) -> u32 + Sync + Send) -> Vec<HalfEdge> {
    let key = &key;
    let of_face = |(f, t): (usize, &[u32; 3])| {
        let t = *t;
        (0..3).map(move |k| {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            (a.min(b), a.max(b), f as u32, k as u8, a < b)
        })
    };
    if triangles.len() * 3 <= SORT_IN_PARALLEL_FROM {
        let mut half = Vec::with_capacity(triangles.len() * 3);
        for face in triangles.iter().enumerate() {
            half.extend(of_face(face));
        }
        return half;
    }
    triangles
        .par_iter()
        .enumerate()
        .flat_map_iter(of_face)
        .collect()
}

/// Sorts half-edges by the whole tuple, in parallel (native builds, large meshes).
fn sorted_in_parallel(mut half: Vec<HalfEdge>) -> Vec<HalfEdge> {
    // Two packed words, the same order as the tuple's (face and local edge are unique, so
    // `forward` never decides), with fewer field comparisons.
    half.par_sort_unstable_by_key(|&(lo, hi, f, k, _)| {
        (
            ((lo as u64) << 32) | hi as u64,
            ((f as u64) << 2) | k as u64,
        )
    });
    half
}

/// The same order as [`sorted_in_parallel`] by a counting sort on `lo` (wasm, one thread, and
/// small meshes):
/// half-edges come in face order, the scatter keeps it, and each bucket (a vertex's few edges)
/// is then sorted stably by `hi`. A tenth of a one-shot wasm refinement went to the comparison
/// sort.
fn sorted_by_buckets(half: Vec<HalfEdge>) -> Vec<HalfEdge> {
    let buckets = half.iter().map(|e| e.0 as usize + 1).max().unwrap_or(0);
    let mut start = vec![0usize; buckets + 1];
    for e in &half {
        start[e.0 as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut next = start.clone();
    let mut out = vec![(0, 0, 0, 0, false); half.len()];
    for e in half {
        let at = &mut next[e.0 as usize];
        out[*at] = e;
        *at += 1;
    }
    for w in start.windows(2) {
        out[w[0]..w[1]].sort_by_key(|e| e.1);
    }
    out
}

impl Topology {
    /// Computes the adjacency of `mesh`.
    pub fn new(mesh: &Mesh) -> Topology {
        let triangles = mesh.triangles();
        let nv = mesh.vertex_count();

        // Edges by vertex index.
        let half = edge_runs(triangles, |v| v);
        let mut edges = Vec::with_capacity(triangles.len() * 3 / 2 + 1);
        let mut edge_owner = Vec::with_capacity(edges.capacity());
        let mut face_edges = vec![[0u32; 3]; triangles.len()];
        for (i, &(a, b, f, k, _)) in half.iter().enumerate() {
            if i == 0 || (half[i - 1].0, half[i - 1].1) != (a, b) {
                edges.push([a, b]);
                edge_owner.push((f, k));
            }
            face_edges[f as usize][k as usize] = (edges.len() - 1) as u32;
        }
        let mut vertex_owner = vec![None; nv];
        for (f, t) in triangles.iter().enumerate() {
            for (k, &v) in t.iter().enumerate() {
                vertex_owner[v as usize].get_or_insert((f as u32, k as u8));
            }
        }

        // Edges by position: the same runs when no two vertices share a position (each
        // vertex is then its position's first), as in most meshes.
        let position_ids = position_ids(mesh.positions());
        let distinct = position_ids
            .iter()
            .enumerate()
            .all(|(v, &p)| p as usize == v);
        let half = match distinct {
            true => half,
            false => edge_runs(triangles, |v| position_ids[v as usize]),
        };
        let mut neighbors = vec![[NO_NEIGHBOR; 3]; triangles.len()];
        let mut report = TopologyReport {
            vertices: nv,
            faces: triangles.len(),
            ..Default::default()
        };
        let mut start = 0;
        while start < half.len() {
            let mut end = start + 1;
            while end < half.len() && (half[end].0, half[end].1) == (half[start].0, half[start].1) {
                end += 1;
            }
            let run = &half[start..end];
            report.edges += 1;
            match run.len() {
                1 => report.boundary_edges += 1,
                2 => {
                    let (x, y) = (run[0], run[1]);
                    if x.4 == y.4 {
                        report.inconsistent_edges += 1;
                    }
                    neighbors[x.2 as usize][x.3 as usize] = y.2;
                    neighbors[y.2 as usize][y.3 as usize] = x.2;
                    let vx = local_edge(triangles[x.2 as usize], x.3);
                    let vy = local_edge(triangles[y.2 as usize], y.3);
                    let same =
                        (vx[0] == vy[0] && vx[1] == vy[1]) || (vx[0] == vy[1] && vx[1] == vy[0]);
                    if !same {
                        report.seam_edges += 1;
                    }
                }
                _ => report.non_manifold_edges += 1,
            }
            start = end;
        }

        // Positions, split normals, unreferenced vertices.
        let mut used = vec![false; nv];
        for t in triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        report.unreferenced_vertices = used.iter().filter(|u| !**u).count();
        let mut first_normal: HashMap<u32, ([f32; 3], bool)> = HashMap::default();
        for v in (0..nv).filter(|&v| used[v]) {
            let n = mesh.normals()[v];
            let entry = first_normal.entry(position_ids[v]).or_insert((n, false));
            if entry.0 != n {
                entry.1 = true;
            }
        }
        report.positions = first_normal.len();
        report.split_normal_positions = first_normal.values().filter(|(_, split)| *split).count();
        report.euler_characteristic =
            report.positions as i64 - report.edges as i64 + report.faces as i64;

        Topology {
            edges,
            face_edges,
            edge_owner,
            vertex_owner,
            position_ids,
            neighbors,
            report,
        }
    }
}

/// The face across local edge `k` of face `f` (by position), with the vertex indices it uses at
/// the edge's start and end positions and its corner opposite the edge. `None` on boundary and
/// non-manifold edges.
pub(crate) fn across_edge(mesh: &Mesh, topo: &Topology, f: usize, k: usize) -> Option<Across> {
    across_edge_in(mesh.triangles(), topo, f, k)
}

/// [`across_edge`] from the triangles alone (what a `refine::Surface` keeps of its mesh).
pub(crate) fn across_edge_in(
    triangles: &[[u32; 3]],
    topo: &Topology,
    f: usize,
    k: usize,
) -> Option<Across> {
    let g = topo.neighbors[f][k];
    if g == NO_NEIGHBOR {
        return None;
    }
    let t = triangles[f];
    let pid = |v: u32| topo.position_ids[v as usize];
    let (a, b) = (pid(t[k]), pid(t[(k + 1) % 3]));
    let tg = triangles[g as usize];
    let (mut at_a, mut at_b, mut opposite) = (None, None, None);
    for &v in &tg {
        match pid(v) {
            x if x == a => at_a = Some(v),
            x if x == b => at_b = Some(v),
            _ => opposite = Some(v),
        }
    }
    Some(Across {
        face: g as usize,
        at_a: at_a?,
        at_b: at_b?,
        opposite: opposite?,
    })
}

/// See [`across_edge`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Across {
    #[allow(dead_code)]
    pub face: usize,
    pub at_a: u32,
    pub at_b: u32,
    pub opposite: u32,
}

fn local_edge(t: [u32; 3], k: u8) -> [u32; 2] {
    [t[k as usize], t[(k as usize + 1) % 3]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bucket_sort_gives_the_parallel_sorts_order() {
        // Edges of a 12 x 12 grid of quads (two triangles each, shared edges in both
        // directions) and of a fan around one vertex (one large bucket), keyed by vertex and by
        // a key that merges vertices. (Built here: `samples` depends on `mesh`.)
        let n = 13u32;
        let grid: Vec<[u32; 3]> = (0..n - 1)
            .flat_map(|y| (0..n - 1).map(move |x| (x, y)))
            .flat_map(|(x, y)| {
                let v = y * n + x;
                [[v, v + 1, v + n + 1], [v, v + n + 1, v + n]]
            })
            .collect();
        let fan: Vec<[u32; 3]> = (1..40).map(|i| [0, i, i + 1]).collect();
        for triangles in [&grid[..], &fan[..]] {
            for key in [|v: u32| v, |v: u32| v / 3] {
                let half = half_edges(triangles, key);
                let mut want = half.clone();
                want.sort_unstable();
                assert_eq!(sorted_in_parallel(half.clone()), want);
                assert_eq!(sorted_by_buckets(half), want);
            }
        }
    }

    /// A closed tetrahedron, consistently oriented outward.
    fn tetra() -> Mesh {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let t = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        Mesh::new(p, None, None, t).unwrap()
    }

    #[test]
    fn tetrahedron_is_closed_with_euler_two() {
        let topo = tetra().topology();
        assert_eq!(topo.edges.len(), 6);
        assert_eq!(topo.report.edges, 6);
        assert!(topo.report.is_closed_manifold());
        assert_eq!(topo.report.euler_characteristic, 2);
        for (f, n) in topo.neighbors.iter().enumerate() {
            for &g in n {
                assert!(g != NO_NEIGHBOR && g as usize != f);
            }
        }
        // Every edge owner really uses that edge.
        for (e, &(f, k)) in topo.edge_owner.iter().enumerate() {
            assert_eq!(topo.face_edges[f as usize][k as usize], e as u32);
        }
    }

    #[test]
    fn finds_boundary_seam_split_and_non_manifold() {
        // Two triangles sharing an edge by position but not by vertex (a hard edge).
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.5],
        ];
        let n = vec![
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.6, 0.8],
            [0.0, 0.6, 0.8],
            [0.0, 0.0, 1.0],
        ];
        let t = vec![[0, 1, 2], [3, 5, 4]];
        let topo = Mesh::new(p, Some(n), None, t).unwrap().topology();
        assert_eq!(topo.report.edges, 5);
        assert_eq!(topo.report.boundary_edges, 4);
        assert_eq!(topo.report.seam_edges, 1);
        assert_eq!(topo.report.split_normal_positions, 2);
        assert_eq!(
            topo.edges.len(),
            6,
            "by vertex index the hard edge is two edges"
        );
        assert_eq!(topo.neighbors[0][1], 1);

        // Three faces on one edge.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let t = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
        let topo = Mesh::new(p, None, None, t).unwrap().topology();
        assert_eq!(topo.report.non_manifold_edges, 1);
        assert_eq!(topo.neighbors[0][0], NO_NEIGHBOR);
    }
}
