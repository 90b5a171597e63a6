//! The CPU evaluator: every output vertex is `sum_k w_k C_k` over its patch's control points,
//! with the weights read from the pattern's [`Stencil`] row. Work is split into disjoint output
//! blocks (corners, edges, interiors, triangles) so threads never share a slot.

use super::layout::OutputLayout;
use super::RefinedMesh;
use crate::basis::NORMAL_NET_LEN;
use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::scheme::{NormalMode, PatchNets};
use crate::stencil::{Block, Stencil};
use glam::Vec3;
use rayon::prelude::*;

/// Faces per parallel task: large enough to amortise scheduling, small enough to balance.
const FACES_PER_TASK: usize = 32;
/// Corner vertices per parallel task (each is one point evaluation).
const CORNERS_PER_TASK: usize = 1024;
/// Coarse edges per parallel task.
const EDGES_PER_TASK: usize = 64;

/// Evaluates one point of one patch from its stencil row: `(position, unit normal)`.
///
/// Normals: `Real` takes `Du × Dv` and falls back to the normal net where the derivatives are
/// (nearly) parallel; the others take the normal net. A normal that still vanishes becomes the
/// normal of the patch's corner triangle. [`eval_block`] computes the same, bit for bit, for
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
    let (du, dv) = if mode == NormalMode::Real {
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

/// The unit normal from the accumulated derivatives (`Real`) or the normal net, with the
/// fallbacks described at [`eval_point`].
#[inline(always)]
fn finish_normal<const K: usize>(
    mode: NormalMode,
    du: Vec3,
    dv: Vec3,
    row: &[f32],
    points: &[[f32; 3]; K],
    normals: &[[f32; 3]],
) -> Vec3 {
    let mut n = Vec3::ZERO;
    if mode == NormalMode::Real {
        let c = du.cross(dv);
        if c.length_squared() > 1e-12 * du.length_squared() * dv.length_squared() {
            n = c;
        }
    }
    if n == Vec3::ZERO {
        let normals: &[[f32; 3]; NORMAL_NET_LEN] =
            normals.try_into().expect("normal net has 6 entries");
        let nw: &[f32; NORMAL_NET_LEN] = row[3 * K..3 * K + NORMAL_NET_LEN].try_into().unwrap();
        n = combine(nw, normals);
    }
    let unit = n.normalize_or_zero();
    if unit == Vec3::ZERO {
        let [a, b, c] = [points[0], points[1], points[2]].map(Vec3::from);
        return (b - a).cross(c - a).normalize_or(Vec3::Z);
    }
    unit
}

#[inline(always)]
fn combine<const K: usize>(w: &[f32; K], c: &[[f32; 3]; K]) -> Vec3 {
    let (mut x, mut y, mut z) = (0.0f32, 0.0f32, 0.0f32);
    for k in 0..K {
        x += w[k] * c[k][0];
        y += w[k] * c[k][1];
        z += w[k] * c[k][2];
    }
    Vec3::new(x, y, z)
}

/// Points per tile of [`eval_block`]: the accumulators stay in L1.
const TILE: usize = 64;

/// Accumulates `Σ_k w[k*len + i] c[k]` for the tile's points `start..start+n` into `acc`.
#[inline(always)]
fn accumulate(
    weights: &[f32],
    len: usize,
    start: usize,
    n: usize,
    controls: &[[f32; 3]],
    acc: &mut [[f32; TILE]; 3],
) {
    for a in acc.iter_mut() {
        a[..n].fill(0.0);
    }
    for (k, c) in controls.iter().enumerate() {
        let w = &weights[k * len + start..k * len + start + n];
        let [cx, cy, cz] = *c;
        let [ax, ay, az] = acc;
        for i in 0..n {
            ax[i] += w[i] * cx;
            ay[i] += w[i] * cy;
            az[i] += w[i] * cz;
        }
    }
}

/// Evaluates a run of pattern points of one patch ([`Block`]) into `positions`/`normals`
/// (reversed when `reverse`, for edges stored against the owner's direction). Equal, bit for
/// bit, to [`eval_point`] on each point.
#[allow(clippy::too_many_arguments)]
pub fn eval_block<const K: usize>(
    block: &Block,
    stencil: &Stencil,
    points: &[[f32; 3]],
    normals: &[[f32; 3]],
    mode: NormalMode,
    positions_out: &mut [[f32; 3]],
    normals_out: &mut [[f32; 3]],
    reverse: bool,
) {
    let points: &[[f32; 3]; K] = points.try_into().expect("patch has K control points");
    let len = block.len();
    let slot = |i: usize| if reverse { len - 1 - i } else { i };
    let mut pos = [[0.0f32; TILE]; 3];
    let mut d1 = [[0.0f32; TILE]; 3];
    let mut d2 = [[0.0f32; TILE]; 3];
    for start in (0..len).step_by(TILE) {
        let n = TILE.min(len - start);
        accumulate(&block.value, len, start, n, points, &mut pos);
        if mode == NormalMode::Real {
            accumulate(&block.du, len, start, n, points, &mut d1);
            accumulate(&block.dv, len, start, n, points, &mut d2);
        } else {
            accumulate(&block.normal, len, start, n, normals, &mut d1);
        }
        for i in 0..n {
            let at = |a: &[[f32; TILE]; 3]| Vec3::new(a[0][i], a[1][i], a[2][i]);
            let p = block.points[start + i] as usize;
            let normal = if mode == NormalMode::Real {
                finish_normal::<K>(mode, at(&d1), at(&d2), stencil.row(p), points, normals)
            } else {
                // The net normal is already summed: normalise it as finish_normal would.
                let unit = at(&d1).normalize_or_zero();
                if unit == Vec3::ZERO {
                    finish_normal::<K>(
                        mode,
                        Vec3::ZERO,
                        Vec3::ZERO,
                        stencil.row(p),
                        points,
                        normals,
                    )
                } else {
                    unit
                }
            };
            let s = slot(start + i);
            positions_out[s] = at(&pos).into();
            normals_out[s] = normal.into();
        }
    }
}

/// Barycentric interpolation of the face's UVs at the row's `l`.
#[inline(always)]
fn interpolate_uv(row: &[f32], uv: &[[f32; 2]; 3]) -> [f32; 2] {
    let l = &row[row.len() - 3..];
    [
        l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0],
        l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1],
    ]
}

/// Resizes `v` to `n` slots, keeping the allocation when it already fits. Slots are overwritten.
fn prepare<T: Copy + Default>(v: &mut Vec<T>, n: usize) {
    if v.len() != n {
        if v.capacity() >= n {
            v.resize(n, T::default());
            v.truncate(n);
        } else {
            *v = vec![T::default(); n];
        }
    }
}

/// One refinement: inputs borrowed from a [`super::Refiner`].
pub(crate) struct Job<'a> {
    pub mesh: &'a Mesh,
    pub topology: Option<&'a Topology>,
    pub layout: &'a OutputLayout,
    pub pattern: &'a Pattern,
    pub stencil: &'a Stencil,
    pub nets: &'a PatchNets,
}

impl Job<'_> {
    pub fn run(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        match self.nets.basis.len() {
            10 => self.run_k::<10>(out, progress),
            21 => self.run_k::<21>(out, progress),
            k => unreachable!("no evaluator for a basis of {k} points"),
        }
    }

    fn face_uvs(&self, f: usize) -> Option<[[f32; 2]; 3]> {
        self.mesh
            .uvs()
            .map(|uv| self.mesh.triangles()[f].map(|v| uv[v as usize]))
    }

    /// Evaluates pattern point `p` of face `f` into the given slots.
    #[inline(always)]
    fn eval_into<const K: usize>(
        &self,
        f: usize,
        p: usize,
        pos: &mut [f32; 3],
        nrm: &mut [f32; 3],
    ) {
        let row = self.stencil.row(p);
        (*pos, *nrm) = eval_point::<K>(
            row,
            self.nets.patch_points(f),
            self.nets.patch_normals(f),
            self.nets.normal_mode,
        );
    }

    /// Evaluates a run of pattern points of face `f`, see [`eval_block`].
    #[inline(always)]
    fn eval_block_into<const K: usize>(
        &self,
        block: &Block,
        f: usize,
        ps: &mut [[f32; 3]],
        ns: &mut [[f32; 3]],
        reverse: bool,
    ) {
        eval_block::<K>(
            block,
            self.stencil,
            self.nets.patch_points(f),
            self.nets.patch_normals(f),
            self.nets.normal_mode,
            ps,
            ns,
            reverse,
        );
    }

    fn run_k<const K: usize>(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        let nv = self.layout.vertex_count as usize;
        prepare(&mut out.positions, nv);
        prepare(&mut out.normals, nv);
        match self.mesh.uvs() {
            Some(_) => prepare(out.uvs.get_or_insert_with(Vec::new), nv),
            None => out.uvs = None,
        }
        prepare(&mut out.triangles, self.layout.triangle_count as usize);
        if self.layout.weld {
            self.welded_vertices::<K>(out, progress);
            self.welded_triangles(out, progress);
        } else {
            self.soup::<K>(out, progress);
        }
    }

    fn welded_vertices<const K: usize>(
        &self,
        out: &mut RefinedMesh,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let topo = self.topology.expect("welded output needs the topology");
        let mesh = self.mesh;
        let n = self.layout.level as usize;
        let m = n - 1;
        let ni = Pattern::interior_count(self.layout.level) as usize;
        let nv = mesh.vertex_count();
        let ne = topo.edges.len();
        let (corner_p, rest_p) = out.positions.split_at_mut(nv);
        let (edge_p, inner_p) = rest_p.split_at_mut(ne * m);
        let (corner_n, rest_n) = out.normals.split_at_mut(nv);
        let (edge_n, inner_n) = rest_n.split_at_mut(ne * m);
        let mut uv_blocks = out.uvs.as_mut().map(|uv| {
            let (c, rest) = uv.split_at_mut(nv);
            let (e, i) = rest.split_at_mut(ne * m);
            (c, e, i)
        });

        // Corners: the input position exactly; the normal of the owning patch.
        corner_p
            .par_iter_mut()
            .zip(corner_n.par_iter_mut())
            .enumerate()
            .with_min_len(CORNERS_PER_TASK)
            .for_each(|(v, (p, nrm))| {
                match topo.vertex_owner[v] {
                    Some((f, c)) => {
                        let mut ignored = [0.0; 3];
                        self.eval_into::<K>(
                            f as usize,
                            self.stencil.corner_point(c as usize) as usize,
                            &mut ignored,
                            nrm,
                        );
                    }
                    None => *nrm = mesh.normals()[v],
                }
                *p = mesh.positions()[v];
            });
        if let Some((corner_uv, _, _)) = uv_blocks.as_mut() {
            corner_uv.copy_from_slice(mesh.uvs().unwrap());
        }

        // Edges: evaluated on the owning face, stored from the lower vertex index to the higher.
        if m > 0 {
            let edge_uv = uv_blocks.as_mut().map(|(_, e, _)| &mut **e);
            let eval_edge = |e: usize,
                             ps: &mut [[f32; 3]],
                             ns: &mut [[f32; 3]],
                             uvs: Option<&mut [[f32; 2]]>| {
                let (f, k) = topo.edge_owner[e];
                let (f, k) = (f as usize, k as usize);
                let forward = mesh.triangles()[f][k] == topo.edges[e][0];
                let along = |s: usize| {
                    self.stencil.edge_points[k][if forward { s } else { m - 1 - s }] as usize
                };
                self.eval_block_into::<K>(&self.stencil.blocks.edges[k], f, ps, ns, !forward);
                if let (Some(uvs), Some(face_uv)) = (uvs, self.face_uvs(f)) {
                    for (s, uv) in uvs.iter_mut().enumerate() {
                        *uv = interpolate_uv(self.stencil.row(along(s)), &face_uv);
                    }
                }
            };
            match edge_uv {
                Some(edge_uv) => edge_p
                    .par_chunks_mut(m)
                    .zip(edge_n.par_chunks_mut(m))
                    .zip(edge_uv.par_chunks_mut(m))
                    .enumerate()
                    .with_min_len(EDGES_PER_TASK)
                    .for_each(|(e, ((ps, ns), uv))| eval_edge(e, ps, ns, Some(uv))),
                None => edge_p
                    .par_chunks_mut(m)
                    .zip(edge_n.par_chunks_mut(m))
                    .enumerate()
                    .with_min_len(EDGES_PER_TASK)
                    .for_each(|(e, (ps, ns))| eval_edge(e, ps, ns, None)),
            }
        }

        // Interiors: per face, in pattern order.
        if ni == 0 {
            progress(mesh.face_count() as u64);
            return;
        }
        let inner_uv = uv_blocks.map(|(_, _, i)| i);
        let eval_faces = |task: usize,
                          ps: &mut [[f32; 3]],
                          ns: &mut [[f32; 3]],
                          uvs: Option<&mut [[f32; 2]]>| {
            let first = task * FACES_PER_TASK;
            let faces = ps.len() / ni;
            for lf in 0..faces {
                let range = lf * ni..(lf + 1) * ni;
                self.eval_block_into::<K>(
                    &self.stencil.blocks.interior,
                    first + lf,
                    &mut ps[range.clone()],
                    &mut ns[range],
                    false,
                );
            }
            if let Some(uvs) = uvs {
                for lf in 0..faces {
                    let face_uv = self.face_uvs(first + lf).unwrap();
                    for (i, &p) in self.stencil.interior_points.iter().enumerate() {
                        uvs[lf * ni + i] = interpolate_uv(self.stencil.row(p as usize), &face_uv);
                    }
                }
            }
            progress(faces as u64);
        };
        let chunk = ni * FACES_PER_TASK;
        match inner_uv {
            Some(inner_uv) => inner_p
                .par_chunks_mut(chunk)
                .zip(inner_n.par_chunks_mut(chunk))
                .zip(inner_uv.par_chunks_mut(chunk))
                .enumerate()
                .for_each(|(t, ((ps, ns), uv))| eval_faces(t, ps, ns, Some(uv))),
            None => inner_p
                .par_chunks_mut(chunk)
                .zip(inner_n.par_chunks_mut(chunk))
                .enumerate()
                .for_each(|(t, (ps, ns))| eval_faces(t, ps, ns, None)),
        }
    }

    fn welded_triangles(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        let topo = self.topology.expect("welded output needs the topology");
        let n = self.layout.level as usize;
        let m = n - 1;
        let ni = Pattern::interior_count(self.layout.level) as usize;
        let per_face = n * n;
        let points = self.pattern.points.len();
        out.triangles
            .par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                // Pattern point -> output vertex, rebuilt for each face.
                let mut map = vec![0u32; points];
                for (lf, face_tris) in tris.chunks_mut(per_face).enumerate() {
                    let f = task * FACES_PER_TASK + lf;
                    let t = self.mesh.triangles()[f];
                    for (c, &v) in t.iter().enumerate() {
                        map[self.stencil.corner_point(c) as usize] = v;
                    }
                    #[allow(clippy::needless_range_loop)] // k indexes four tables
                    for k in 0..3 {
                        let e = topo.face_edges[f][k] as usize;
                        let forward = t[k] == topo.edges[e][0];
                        let base = self.layout.edge_base as usize + e * m;
                        for (s, &p) in self.stencil.edge_points[k].iter().enumerate() {
                            map[p as usize] = (base + if forward { s } else { m - 1 - s }) as u32;
                        }
                    }
                    let base = self.layout.interior_base as usize + f * ni;
                    for (i, &p) in self.stencil.interior_points.iter().enumerate() {
                        map[p as usize] = (base + i) as u32;
                    }
                    for (dst, src) in face_tris.iter_mut().zip(&self.pattern.triangles) {
                        *dst = src.map(|p| map[p as usize]);
                    }
                }
                progress((tris.len() / per_face) as u64);
            });
    }

    fn soup<const K: usize>(&self, out: &mut RefinedMesh, progress: &(dyn Fn(u64) + Sync)) {
        let mesh = self.mesh;
        let np = self.pattern.points.len();
        let chunk = np * FACES_PER_TASK;
        let eval_faces = |task: usize,
                          ps: &mut [[f32; 3]],
                          ns: &mut [[f32; 3]],
                          uvs: Option<&mut [[f32; 2]]>| {
            let first = task * FACES_PER_TASK;
            let faces = ps.len() / np;
            for lf in 0..faces {
                let f = first + lf;
                let (ps, ns) = (
                    &mut ps[lf * np..(lf + 1) * np],
                    &mut ns[lf * np..(lf + 1) * np],
                );
                for p in 0..np {
                    self.eval_into::<K>(f, p, &mut ps[p], &mut ns[p]);
                }
                for (c, &v) in mesh.triangles()[f].iter().enumerate() {
                    ps[self.stencil.corner_point(c) as usize] = mesh.positions()[v as usize];
                }
            }
            if let Some(uvs) = uvs {
                for lf in 0..faces {
                    let face_uv = self.face_uvs(first + lf).unwrap();
                    for p in 0..np {
                        uvs[lf * np + p] = interpolate_uv(self.stencil.row(p), &face_uv);
                    }
                }
            }
            progress(faces as u64);
        };
        match out.uvs.as_mut() {
            Some(uv) => out
                .positions
                .par_chunks_mut(chunk)
                .zip(out.normals.par_chunks_mut(chunk))
                .zip(uv.par_chunks_mut(chunk))
                .enumerate()
                .for_each(|(t, ((ps, ns), uv))| eval_faces(t, ps, ns, Some(uv))),
            None => out
                .positions
                .par_chunks_mut(chunk)
                .zip(out.normals.par_chunks_mut(chunk))
                .enumerate()
                .for_each(|(t, (ps, ns))| eval_faces(t, ps, ns, None)),
        }
        let per_face = self.pattern.triangles.len();
        out.triangles
            .par_chunks_mut(per_face * FACES_PER_TASK)
            .enumerate()
            .for_each(|(task, tris)| {
                for (lf, face_tris) in tris.chunks_mut(per_face).enumerate() {
                    let base = ((task * FACES_PER_TASK + lf) * np) as u32;
                    for (dst, src) in face_tris.iter_mut().zip(&self.pattern.triangles) {
                        *dst = src.map(|p| base + p);
                    }
                }
                progress((tris.len() / per_face) as u64);
            });
    }
}
