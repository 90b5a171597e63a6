//! Displacement of refined surfaces (GMR section 4): sine, Perlin noise and height maps, on the
//! CPU. The GPU crate's `shaders/displace.wgsl` is this module's twin (same formulas, same
//! direction rule); tests compare the two.
//!
//! A refined vertex `P` with unit normal `N` and texture coordinate `uv` moves to
//! `P + d(P, uv) D`, where `d` is [`Displacement::offset`] and `D` its *direction*:
//!
//! - normally `D = N`, the refined normal;
//! - on a **hard edge or split corner**, where the coarse mesh gives one position several
//!   vertices (split normals, UV seams), each copy of a refined vertex would otherwise move
//!   along its own side's normal and the displaced surface would tear open. There `D` is shared:
//!   `D = normalize(l1 M1 + l2 M2 + l3 M3)`, with `l` the vertex's barycentric coordinates on its
//!   coarse face and `M_i` the *position means* of the face's corners (see [`FaceFrame`]). Along
//!   a coarse edge both sides have the same `l` (`k/N` and `1 - k/N`, exact) and the same `M`s,
//!   so both copies get the same direction bit for bit and the edge stays closed.
//!
//! Which refined vertices use the shared direction is decided per coarse face from that face's
//! own [`FaceFrame`] (so the GPU can decide it per instance): a corner at a split position, and
//! a point inside a split edge. Interior points, and everything on a mesh without split
//! vertices, move along their own normal, exactly as before.
//!
//! Normals are left as evaluated (the undisplaced surface's); the renderer shades displaced
//! surfaces with facet normals instead.
//!
//! ```
//! use tessella_core::displace::{DisplaceFrame, Displacement};
//! use tessella_core::{samples, RefineOptions, Refiner, Scheme};
//!
//! let mesh = samples::hard_cube();
//! let refiner = Refiner::new(&mesh, &RefineOptions::new(Scheme::PnAen, 4))?;
//! let mut out = refiner.refine();
//! let frame = DisplaceFrame::new(refiner.mesh(), refiner.topology(), refiner.layout());
//! let d = Displacement::Sine { amplitude: 0.1, frequency: 10.0 };
//! d.apply(&mut out, &frame)?;
//! assert!((d.offset([0.3, 0.4, 0.0], [0.0, 0.0]) - 0.1 * 5.0f32.sin()).abs() < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::mesh::{Mesh, Topology};
use crate::pattern::Pattern;
use crate::refine::{OutputLayout, RefinedMesh};
use crate::scalar::{Noise, Real, Word};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use thiserror::Error;

/// Why a displacement cannot be applied.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DisplaceError {
    #[error("a height map needs texture coordinates; the mesh has none")]
    NeedsUvs,
    #[error(
        "the height map is {width}x{height} but holds {len} heights; it needs width × height \
         (at least one)"
    )]
    MapSize { width: u32, height: u32, len: usize },
    #[error(
        "displacement amplitude and frequency must be finite, got {amplitude} and {frequency}"
    )]
    NotFinite { amplitude: f32, frequency: f32 },
    #[error(
        "the displacement frame was built for {expected} refined vertices but the mesh has \
         {got}; build the frame from the same mesh and output layout"
    )]
    FrameMismatch { expected: u64, got: usize },
    /// Displacement follows the uniform output layout; adaptive plans have another.
    #[error(
        "displacement works with uniform grid levels; adaptive plans (fractional levels, \
         tessellator spacings, LOD) are not displaced"
    )]
    Adaptive,
    /// A displacement spec ([`Displacement::parse`]) that says no displacement.
    #[error("displacement {spec:?}: {reason}")]
    Spec { spec: String, reason: String },
}

/// A scalar height field; samples are bilinear and repeat, `v = 0` is the bottom row.
///
/// Reading one from an image file is the file crate's job (`tessella_io::read_height_map`).
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    pub width: u32,
    pub height: u32,
    /// Row-major from the image's top row, usually in `0..=1`.
    pub heights: Vec<f32>,
}

impl HeightMap {
    /// A height map of `width × height` values, row-major from the top row.
    pub fn new(width: u32, height: u32, heights: Vec<f32>) -> Result<HeightMap, DisplaceError> {
        let map = HeightMap {
            width,
            height,
            heights,
        };
        map.check()?;
        Ok(map)
    }

    fn check(&self) -> Result<(), DisplaceError> {
        if self.heights.is_empty()
            || self.heights.len() != (self.width as usize) * (self.height as usize)
        {
            return Err(DisplaceError::MapSize {
                width: self.width,
                height: self.height,
                len: self.heights.len(),
            });
        }
        Ok(())
    }

    fn texel(&self, x: i32, y: i32) -> f32 {
        let (w, h) = (self.width as i32, self.height as i32);
        let xx = ((x % w) + w) % w;
        let yy = ((y % h) + h) % h;
        self.heights[(yy * w + xx) as usize]
    }

    /// Bilinear sample at `uv`, repeating ([`height_map_of`]).
    pub fn sample(&self, uv: [f32; 2]) -> f32 {
        let texel = |x: u32, y: u32| self.texel(x as i32, y as i32);
        height_map_of(texel, [self.width as f32, self.height as f32], uv)
    }
}

/// How far refined vertices move (see the module docs for the direction).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Displacement {
    #[default]
    None,
    /// `a · sin(f · ‖P‖)` (GMR section 4, Figure 4).
    Sine { amplitude: f32, frequency: f32 },
    /// `a · noise(f · P)`, Perlin's improved noise (2002) with a permutation shuffled by `seed`.
    Perlin {
        amplitude: f32,
        frequency: f32,
        seed: u32,
    },
    /// `a · h(uv)`: needs a mesh with texture coordinates.
    HeightMap { amplitude: f32, map: HeightMap },
}

impl Displacement {
    /// Parses a displacement as the CLI's `--displace` and the viewer's `displace` take it:
    /// `sine:AMP,FREQ`, `perlin:AMP,FREQ[,SEED]`, `heightmap:IMAGE,AMP` (the image read by
    /// `height_map`, which the file crate provides: the core reads no files), or `none`.
    ///
    /// ```
    /// use tessella_core::displace::Displacement;
    /// let none = |_: &str| Err("no images here".to_string());
    /// assert_eq!(Displacement::parse("sine:0.1,20", none)?,
    ///            Displacement::Sine { amplitude: 0.1, frequency: 20.0 });
    /// assert_eq!(Displacement::parse("perlin:0.1,4,7", none)?,
    ///            Displacement::Perlin { amplitude: 0.1, frequency: 4.0, seed: 7 });
    /// assert!(Displacement::parse("sine:0.1", none).is_err());
    /// assert!(Displacement::parse("wobble:1", none).is_err());
    /// assert!(Displacement::parse("heightmap:h.png,1", none).is_err());
    /// # Ok::<(), tessella_core::DisplaceError>(())
    /// ```
    pub fn parse(
        spec: &str,
        height_map: impl FnOnce(&str) -> Result<HeightMap, String>,
    ) -> Result<Displacement, DisplaceError> {
        let fail = |reason: String| DisplaceError::Spec {
            spec: spec.to_string(),
            reason,
        };
        if spec.trim() == "none" {
            return Ok(Displacement::None);
        }
        let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let parts: Vec<&str> = rest
            .split(',')
            .map(str::trim)
            .filter(|p| !p.is_empty())
            .collect();
        let number = |i: usize, what: &str| -> Result<f32, DisplaceError> {
            let text = parts
                .get(i)
                .ok_or_else(|| fail(format!("missing {what}")))?;
            text.parse()
                .map_err(|_| fail(format!("{what} '{text}' is not a number")))
        };
        let displacement = match kind {
            "sine" => Displacement::Sine {
                amplitude: number(0, "amplitude")?,
                frequency: number(1, "frequency")?,
            },
            "perlin" => Displacement::Perlin {
                amplitude: number(0, "amplitude")?,
                frequency: number(1, "frequency")?,
                seed: match parts.get(2) {
                    Some(s) => s
                        .parse()
                        .map_err(|_| fail(format!("seed '{s}' is not a whole number")))?,
                    None => 0,
                },
            },
            "heightmap" => {
                let path = parts
                    .first()
                    .ok_or_else(|| fail("missing the image path".into()))?;
                let amplitude = number(1, "amplitude")?;
                Displacement::HeightMap {
                    amplitude,
                    map: height_map(path).map_err(fail)?,
                }
            }
            _ => {
                return Err(fail(format!(
                    "unknown kind '{kind}'; use sine:AMP,FREQ, perlin:AMP,FREQ[,SEED] or \
                     heightmap:IMAGE,AMP"
                )))
            }
        };
        Ok(displacement)
    }

    /// `true` unless [`Displacement::None`].
    pub fn is_some(&self) -> bool {
        !matches!(self, Displacement::None)
    }

    /// The largest distance a vertex can move: `|a|` (height maps are taken to be in `0..=1`).
    pub fn reach(&self) -> f32 {
        match self {
            Displacement::None => 0.0,
            Displacement::Sine { amplitude, .. }
            | Displacement::Perlin { amplitude, .. }
            | Displacement::HeightMap { amplitude, .. } => amplitude.abs(),
        }
    }

    /// Checks the parameters; `has_uvs` says whether the mesh has texture coordinates.
    pub fn validate(&self, has_uvs: bool) -> Result<(), DisplaceError> {
        let (amplitude, frequency) = match self {
            Displacement::None => return Ok(()),
            Displacement::Sine {
                amplitude,
                frequency,
            }
            | Displacement::Perlin {
                amplitude,
                frequency,
                ..
            } => (*amplitude, *frequency),
            Displacement::HeightMap { amplitude, map } => {
                if !has_uvs {
                    return Err(DisplaceError::NeedsUvs);
                }
                map.check()?;
                (*amplitude, 1.0)
            }
        };
        if !amplitude.is_finite() || !frequency.is_finite() {
            return Err(DisplaceError::NotFinite {
                amplitude,
                frequency,
            });
        }
        Ok(())
    }

    /// The offset along the direction at surface point `p` with texture coordinate `uv`.
    pub fn offset(&self, p: [f32; 3], uv: [f32; 2]) -> f32 {
        match self {
            Displacement::Perlin { seed, .. } => self.offset_with(&permutation(*seed), p, uv),
            _ => self.offset_with(&[0; 512], p, uv),
        }
    }

    /// [`Displacement::offset`] with Perlin's permutation already built.
    fn offset_with(&self, perm: &[u32; 512], p: [f32; 3], uv: [f32; 2]) -> f32 {
        match self {
            Displacement::None => 0.0,
            Displacement::Sine {
                amplitude,
                frequency,
            } => sine_of(*amplitude, *frequency, p),
            Displacement::Perlin {
                amplitude,
                frequency,
                ..
            } => amplitude * perlin(perm, p.map(|x| frequency * x)),
            Displacement::HeightMap { amplitude, map } => amplitude * map.sample(uv),
        }
    }

    /// Displaces every vertex of `out`, refined with the mesh and layout `frame` was built for
    /// (the reference for the GPU paths). Vertices on hard edges and split corners move along
    /// the shared direction, every other one along its normal; normals are kept.
    pub fn apply(&self, out: &mut RefinedMesh, frame: &DisplaceFrame) -> Result<(), DisplaceError> {
        self.validate(out.uvs.is_some())?;
        if frame.vertex_count != out.positions.len() as u64 {
            return Err(DisplaceError::FrameMismatch {
                expected: frame.vertex_count,
                got: out.positions.len(),
            });
        }
        if !self.is_some() {
            return Ok(());
        }
        let shared = frame.shared();
        self.apply_range(
            0,
            &mut out.positions,
            &out.normals,
            out.uvs.as_deref(),
            frame,
            &shared,
        )
    }

    /// Displaces the output vertices `first..first + positions.len()` (a piece of the output,
    /// in layout order, with its own `normals` and `uvs`) exactly as [`Displacement::apply`]
    /// displaces them in the whole output: what a refinement written piece by piece uses.
    /// `shared` is the frame's [`DisplaceFrame::shared`], built once for all pieces.
    pub fn apply_range(
        &self,
        first: usize,
        positions: &mut [[f32; 3]],
        normals: &[[f32; 3]],
        uvs: Option<&[[f32; 2]]>,
        frame: &DisplaceFrame,
        shared: &SharedSlots,
    ) -> Result<(), DisplaceError> {
        self.validate(uvs.is_some())?;
        let n = positions.len();
        let end = first.saturating_add(n);
        if normals.len() != n
            || uvs.is_some_and(|u| u.len() != n)
            || end as u64 > frame.vertex_count
        {
            return Err(DisplaceError::FrameMismatch {
                expected: frame.vertex_count,
                got: end,
            });
        }
        if !self.is_some() {
            return Ok(());
        }
        let perm = match self {
            Displacement::Perlin { seed, .. } => permutation(*seed),
            _ => [0; 512],
        };
        let uv_of = |i: usize| uvs.map_or([0.0; 2], |u| u[i]);
        let moved = |p: [f32; 3], i: usize, dir: [f32; 3]| {
            let d = self.offset_with(&perm, p, uv_of(i));
            [p[0] + d * dir[0], p[1] + d * dir[1], p[2] + d * dir[2]]
        };
        // Shared directions first, from the undisplaced positions.
        let lo = shared.0.partition_point(|s| s.0 < first);
        let hi = shared.0.partition_point(|s| s.0 < end);
        let moved_shared: Vec<(usize, [f32; 3])> = shared.0[lo..hi]
            .par_iter()
            .map(|&(slot, face, l)| {
                let i = slot - first;
                let dir = frame.faces[face].direction(l, normals[i]);
                (i, moved(positions[i], i, dir))
            })
            .collect();
        positions
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, p)| *p = moved(*p, i, normals[i]));
        for (i, p) in moved_shared {
            positions[i] = p;
        }
        Ok(())
    }
}

/// The output vertices that move along a direction shared by the faces around them (split
/// corners and edges), sorted by output slot: `(slot, face, l)`. See [`DisplaceFrame::shared`].
#[derive(Debug, Clone, PartialEq)]
pub struct SharedSlots(Vec<(usize, usize, [f32; 3])>);

/// What displacement needs to know about one coarse face: the position means of its corners
/// and which of its corners and edges are split. The GPU uploads one per face (10 floats:
/// `mask, M1, M2, M3`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceFrame {
    /// `M_c`: the unit mean normal of the position of corner `c` (see [`position_means`]).
    pub means: [[f32; 3]; 3],
    /// Bit `k` (0..3): local edge `k` (corner `k` to `k + 1`) is split. Bit `3 + c`: corner `c`
    /// lies at a split position.
    pub mask: u8,
}

impl FaceFrame {
    /// Marks local edge `k` as split.
    pub const EDGE: [u8; 3] = [1, 2, 4];
    /// Marks corner `c` as split.
    pub const CORNER: [u8; 3] = [8, 16, 32];

    /// The displacement direction of the refined point with barycentric coordinates `l` and
    /// refined normal `normal` on this face. `l` must be the pattern's (exact `k/N`, as the
    /// stencil stores it): a point is corner `c` when `l_c == 1`, on edge `k` when the
    /// coordinate of the corner opposite edge `k` (`l_{k+2 mod 3}`) is `0`, else interior.
    /// Split corners and points inside split edges get `normalize(Σ l_i M_i)`; everything else
    /// (and a vanishing sum) gets `normal`.
    pub fn direction(&self, l: [f32; 3], normal: [f32; 3]) -> [f32; 3] {
        // No split corner or edge: the normal, as `direction_of` gives it, without its work.
        if self.mask == 0 {
            return normal;
        }
        direction_of(u32::from(self.mask), self.means, l, normal)
    }
}

/// [`FaceFrame::direction`] for any [`Noise`] number, the face's `mask` and `means` given: the
/// one source of the CPU's direction and the shaders' `tessella_direction`.
pub fn direction_of<R: Noise>(mask: R::W, means: [[R; 3]; 3], l: [R; 3], normal: [R; 3]) -> [R; 3] {
    let w = |x: u8| <R::W as Word>::lit(u32::from(x));
    let (one, zero) = (R::lit(1.0), R::lit(0.0));
    let (corner, edge) = (FaceFrame::CORNER, FaceFrame::EDGE);
    // The first that holds: corner 0, 1, 2 (l_c = 1), then edge k (l_{k+2 mod 3} = 0), else
    // none (interior).
    let tests = [
        (l[0], one, corner[0]),
        (l[1], one, corner[1]),
        (l[2], one, corner[2]),
        (l[2], zero, edge[0]),
        (l[0], zero, edge[1]),
        (l[1], zero, edge[2]),
    ];
    let bit = tests.iter().rev().fold(w(0), |rest, &(x, value, bit)| {
        R::word_if_eq(x, value, w(bit), rest)
    });
    let split = mask.and(bit);
    let [m0, m1, m2] = means;
    let s: [R; 3] = std::array::from_fn(|i| l[0] * m0[i] + l[1] * m1[i] + l[2] * m2[i]);
    let len2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
    let len = len2.sqrt();
    // Both sides are computed (a vanishing sum divides by zero there) and one kept.
    std::array::from_fn(|i| {
        let shared = R::pick_gt(len2, R::lit(1e-12), s[i] / len, normal[i]);
        R::pick_eq(split, w(0), normal[i], shared)
    })
}

/// For each vertex, the shared displacement direction `M` of its position: the normalised,
/// angle-weighted mean of the normals of all face corners at that position,
/// `normalize(Σ θ_c n_c)` (`θ_c` the corner's angle in its triangle, `n_c` its vertex's
/// normal), in f64. Angle weights make `M` independent of how the faces around the position are
/// triangulated (a hard cube's corner gets `(±1, ±1, ±1)/√3` however its quads are split). When
/// the normals cancel, the angle-weighted mean of the faces' geometric normals is used, and
/// failing that the vertex's own normal. Vertices no face uses get their own normal.
///
/// `position_ids` gives each vertex's position as the lowest vertex index there
/// ([`Topology::position_ids`]).
pub fn position_means(mesh: &Mesh, position_ids: &[u32]) -> Vec<[f32; 3]> {
    let nv = mesh.vertex_count();
    let pid = position_ids;
    // Per position id: (Σ θ n, Σ θ face normal).
    let mut sums = vec![(DVec3::ZERO, DVec3::ZERO); nv];
    for t in mesh.triangles() {
        let p = t.map(|v| DVec3::from(mesh.positions()[v as usize].map(f64::from)));
        let face_normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for c in 0..3 {
            let (a, b) = (p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]);
            let angle = a.cross(b).length().atan2(a.dot(b));
            let n = DVec3::from(mesh.normals()[t[c] as usize].map(f64::from));
            let s = &mut sums[pid[t[c] as usize] as usize];
            s.0 += angle * n;
            s.1 += angle * face_normal;
        }
    }
    (0..nv)
        .map(|v| {
            let (normals, faces) = sums[pid[v] as usize];
            let m = normals
                .try_normalize()
                .filter(|_| normals.length() > 1e-9)
                .or_else(|| faces.try_normalize().filter(|_| faces.length() > 1e-9))
                .unwrap_or_else(|| DVec3::from(mesh.normals()[v].map(f64::from)));
            m.to_array().map(|x| x as f32)
        })
        .collect()
}

/// One [`FaceFrame`] per coarse face of `mesh`.
///
/// A position is **split** when faces use more than one vertex at it (split normals, UV
/// seams). A face's edge is **split** when the faces along that edge (by position) do not all
/// use the same two vertices for it; a boundary edge is never split. Both are properties of the
/// coarse mesh alone, so welded and soup output, CPU and GPU agree on them.
///
/// `position_ids` as for [`position_means`]. A deforming mesh keeps its masks (they depend on
/// the triangles and the position ids only); its means follow the frame's positions and
/// normals, so call this again per frame.
pub fn face_frames(mesh: &Mesh, position_ids: &[u32]) -> Vec<FaceFrame> {
    let means = position_means(mesh, position_ids);
    let pid = position_ids;
    let triangles = mesh.triangles();
    // Per position: the first vertex used there, and whether another one is.
    let mut first_vertex: HashMap<u32, (u32, bool)> = HashMap::new();
    // Per position edge (lower id first): the first vertex edge used there, and whether
    // another one is.
    let mut first_edge: HashMap<(u32, u32), ([u32; 2], bool)> = HashMap::new();
    for t in triangles {
        for c in 0..3 {
            let v = t[c];
            let e = first_vertex.entry(pid[v as usize]).or_insert((v, false));
            e.1 |= e.0 != v;
            let (a, b) = (t[c], t[(c + 1) % 3]);
            let (pa, pb) = (pid[a as usize], pid[b as usize]);
            let key = (pa.min(pb), pa.max(pb));
            let pair = [a.min(b), a.max(b)];
            let e = first_edge.entry(key).or_insert((pair, false));
            e.1 |= e.0 != pair;
        }
    }
    triangles
        .iter()
        .map(|t| {
            let mut mask = 0;
            for c in 0..3 {
                if first_vertex[&pid[t[c] as usize]].1 {
                    mask |= FaceFrame::CORNER[c];
                }
                let (pa, pb) = (pid[t[c] as usize], pid[t[(c + 1) % 3] as usize]);
                if first_edge[&(pa.min(pb), pa.max(pb))].1 {
                    mask |= FaceFrame::EDGE[c];
                }
            }
            FaceFrame {
                means: t.map(|v| means[v as usize]),
                mask,
            }
        })
        .collect()
}

/// Everything [`Displacement::apply`] needs besides the refined mesh: the [`FaceFrame`]s and
/// where the output layout put the refined vertices of split corners and edges. Built once per
/// mesh and layout (and again when the coarse positions or normals change, e.g. per animation
/// frame), in `O(coarse)` time and memory; it does not depend on the displacement itself.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplaceFrame {
    /// One per coarse face (what the GPU uploads).
    pub faces: Vec<FaceFrame>,
    position_ids: Vec<u32>,
    level: u32,
    weld: bool,
    vertex_count: u64,
    edge_base: u64,
    /// Welded: corner slots at split positions, `(vertex, owner face, owner's corner)`.
    corners: Vec<(u32, u32, u8)>,
    /// Welded: split edges, `(edge id, owner face, owner's local edge, stored from the owner's
    /// corner k)`.
    edges: Vec<(u32, u32, u8, bool)>,
}

impl DisplaceFrame {
    /// The frame for output of `layout` (welded or soup) refined from `mesh`; `topology` is the
    /// mesh's (the one the layout was built with).
    pub fn new(mesh: &Mesh, topology: &Topology, layout: &OutputLayout) -> DisplaceFrame {
        let faces = face_frames(mesh, &topology.position_ids);
        let (mut corners, mut edges) = (Vec::new(), Vec::new());
        if layout.weld {
            for (v, owner) in topology.vertex_owner.iter().enumerate() {
                if let Some((f, c)) = *owner {
                    if faces[f as usize].mask & FaceFrame::CORNER[c as usize] != 0 {
                        corners.push((v as u32, f, c));
                    }
                }
            }
            for (e, &(f, k)) in topology.edge_owner.iter().enumerate() {
                if faces[f as usize].mask & FaceFrame::EDGE[k as usize] != 0 {
                    let forward = mesh.triangles()[f as usize][k as usize] == topology.edges[e][0];
                    edges.push((e as u32, f, k, forward));
                }
            }
        }
        DisplaceFrame {
            faces,
            position_ids: topology.position_ids.clone(),
            level: layout.level,
            weld: layout.weld,
            vertex_count: layout.vertex_count,
            edge_base: layout.edge_base,
            corners,
            edges,
        }
    }

    /// Follows a deformed `mesh` (the same triangles and vertex count, new positions and
    /// normals): recomputes the position means, in `O(coarse)`. Which corners and edges are
    /// split stays as built.
    pub fn update(&mut self, mesh: &Mesh) {
        assert_eq!(
            (mesh.vertex_count(), mesh.face_count()),
            (self.position_ids.len(), self.faces.len()),
            "DisplaceFrame::update needs a mesh with the same vertices and triangles"
        );
        let means = position_means(mesh, &self.position_ids);
        for (face, t) in self.faces.iter_mut().zip(mesh.triangles()) {
            face.means = t.map(|v| means[v as usize]);
        }
    }

    /// `true` when some face has a split corner or edge (otherwise every vertex moves along
    /// its own normal).
    pub fn has_splits(&self) -> bool {
        self.faces.iter().any(|f| f.mask != 0)
    }

    /// The output vertices that take a shared direction, sorted by slot, for
    /// [`Displacement::apply_range`].
    pub fn shared(&self) -> SharedSlots {
        let mut slots = self.shared_slots();
        slots.sort_unstable_by_key(|s| s.0);
        SharedSlots(slots)
    }

    /// The output vertices that may take a shared direction: `(slot, face, l)`, with `l` as the
    /// pattern (and the stencil) has it.
    fn shared_slots(&self) -> Vec<(usize, usize, [f32; 3])> {
        let n = self.level;
        let mut slots = Vec::new();
        // Step `t` (1..N) along local edge `k` from corner `k`.
        let edge_l = |k: u8, t: u32| {
            let mut l = [0.0f32; 3];
            l[k as usize] = ((n - t) as f64 / n as f64) as f32;
            l[(k as usize + 1) % 3] = (t as f64 / n as f64) as f32;
            l
        };
        let corner_l = |c: u8| {
            let mut l = [0.0f32; 3];
            l[c as usize] = 1.0;
            l
        };
        if self.weld {
            for &(v, f, c) in &self.corners {
                slots.push((v as usize, f as usize, corner_l(c)));
            }
            let m = (n - 1) as u64;
            for &(e, f, k, forward) in &self.edges {
                for s in 0..n - 1 {
                    let t = if forward { s + 1 } else { n - 1 - s };
                    let slot = self.edge_base + e as u64 * m + s as u64;
                    slots.push((slot as usize, f as usize, edge_l(k, t)));
                }
            }
        } else {
            let per_face = Pattern::point_count(n) as usize;
            // Pattern index of corner c and of edge k's step t (see Pattern's classes).
            let corner_at = |c: u8| match c {
                0 => Pattern::index(n, 0, 0),
                1 => Pattern::index(n, n, 0),
                _ => Pattern::index(n, 0, n),
            };
            let edge_at = |k: u8, t: u32| match k {
                0 => Pattern::index(n, t, 0),
                1 => Pattern::index(n, n - t, t),
                _ => Pattern::index(n, 0, n - t),
            };
            for (f, face) in self.faces.iter().enumerate() {
                for c in 0..3u8 {
                    if face.mask & FaceFrame::CORNER[c as usize] != 0 {
                        slots.push((f * per_face + corner_at(c) as usize, f, corner_l(c)));
                    }
                    if face.mask & FaceFrame::EDGE[c as usize] != 0 {
                        for t in 1..n {
                            slots.push((f * per_face + edge_at(c, t) as usize, f, edge_l(c, t)));
                        }
                    }
                }
            }
        }
        slots
    }
}

/// `a + t (b - a)`.
fn lerp<R: Real>(a: R, b: R, t: R) -> R {
    a + t * (b - a)
}

/// Perlin's permutation of 0..256, shuffled by `seed` (Fisher-Yates on a 32-bit LCG), doubled
/// to 512 entries so lookups need no wrap.
pub fn permutation(seed: u32) -> [u32; 512] {
    let mut p: [u32; 256] = std::array::from_fn(|i| i as u32);
    let mut state = seed.wrapping_mul(2_654_435_761).wrapping_add(1);
    for i in (1..256).rev() {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let j = ((state >> 8) as usize) % (i + 1);
        p.swap(i, j);
    }
    std::array::from_fn(|i| p[i & 255])
}

fn fade<R: Real>(t: R) -> R {
    let c = R::lit;
    t * t * t * (t * (t * c(6.0) - c(15.0)) + c(10.0))
}

/// Perlin's gradient: one of 12 cube-edge directions, chosen by 4 bits of `hash`, dotted with
/// `(x, y, z)`.
fn grad<R: Noise>(hash: R::W, x: R, y: R, z: R) -> R {
    let w = <R::W as Word>::lit;
    let h = hash.and(w(15));
    let u = R::pick_ge(h, w(8), y, x);
    let v = R::pick_ge(
        h,
        w(4),
        R::pick_eq(h, w(12), x, R::pick_eq(h, w(14), x, z)),
        y,
    );
    R::pick_eq(h.and(w(1)), w(0), u, -u) + R::pick_eq(h.and(w(2)), w(0), v, -v)
}

/// Perlin's improved noise (Perlin 2002, "Improving noise"), in about `-1..=1`.
pub fn perlin(perm: &[u32; 512], p: [f32; 3]) -> f32 {
    perlin_of(|i| perm[i as usize], p)
}

/// [`perlin`] for any [`Noise`] number, the permutation read through `perm` (indices below
/// 512): the one source of the CPU's noise and the shaders' `tessella_perlin`.
pub fn perlin_of<R: Noise>(perm: impl Fn(R::W) -> R::W, p: [R; 3]) -> R {
    let w = <R::W as Word>::lit;
    let pm = |i: R::W| perm(i.and(w(511)));
    let f = p.map(R::floor);
    let [xi, yi, zi] = f.map(|x| x.int_word().and(w(255)));
    let (x, y, z) = (p[0] - f[0], p[1] - f[1], p[2] - f[2]);
    let (u, v, t) = (fade(x), fade(y), fade(z));
    let one = R::lit(1.0);
    let a = pm(xi).wadd(yi);
    let aa = pm(a).wadd(zi);
    let ab = pm(a.wadd(w(1))).wadd(zi);
    let b = pm(xi.wadd(w(1))).wadd(yi);
    let ba = pm(b).wadd(zi);
    let bb = pm(b.wadd(w(1))).wadd(zi);
    let x1 = lerp(grad(pm(aa), x, y, z), grad(pm(ba), x - one, y, z), u);
    let x2 = lerp(
        grad(pm(ab), x, y - one, z),
        grad(pm(bb), x - one, y - one, z),
        u,
    );
    let y1 = lerp(x1, x2, v);
    let x3 = lerp(
        grad(pm(aa.wadd(w(1))), x, y, z - one),
        grad(pm(ba.wadd(w(1))), x - one, y, z - one),
        u,
    );
    let x4 = lerp(
        grad(pm(ab.wadd(w(1))), x, y - one, z - one),
        grad(pm(bb.wadd(w(1))), x - one, y - one, z - one),
        u,
    );
    let y2 = lerp(x3, x4, v);
    lerp(y1, y2, t)
}

/// A height map's bilinear sample at `uv`, `size` texels wide and high, the texels read
/// through `texel(x, y)` (signed texel coordinates as word bits; the reader wraps them): the
/// one source of [`HeightMap::sample`] and the shaders' `tessella_height_map`. `v = 0` is the
/// image's bottom row.
pub fn height_map_of<R: Noise>(texel: impl Fn(R::W, R::W) -> R, size: [R; 2], uv: [R; 2]) -> R {
    let c = R::lit;
    let px = uv[0] * size[0] - c(0.5);
    let py = (c(1.0) - uv[1]) * size[1] - c(0.5);
    let (x0, y0) = (px.floor(), py.floor());
    let (tx, ty) = (px - x0, py - y0);
    let (ix, iy) = (x0.int_word(), y0.int_word());
    let one = <R::W as Word>::lit(1);
    let top = lerp(texel(ix, iy), texel(ix.wadd(one), iy), tx);
    let bottom = lerp(
        texel(ix, iy.wadd(one)),
        texel(ix.wadd(one), iy.wadd(one)),
        tx,
    );
    lerp(top, bottom, ty)
}

/// The sine offset `a sin(f ‖p‖)` (GMR section 4).
pub fn sine_of<R: Noise>(a: R, f: R, p: [R; 3]) -> R {
    let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    a * (f * len).sin()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples;

    #[test]
    fn permutation_is_a_permutation() {
        let p = permutation(7);
        let mut seen = [false; 256];
        for &x in &p[..256] {
            seen[x as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(p[..256], p[256..]);
        assert_ne!(permutation(7), permutation(8));
    }

    #[test]
    fn perlin_vanishes_on_lattice_and_is_bounded_and_continuous() {
        let perm = permutation(1);
        // Perlin noise is zero at integer lattice points (all gradients dotted with 0).
        for p in [[0.0, 0.0, 0.0], [3.0, -2.0, 5.0], [17.0, 4.0, -9.0]] {
            assert_eq!(perlin(&perm, p), 0.0);
        }
        let mut max: f32 = 0.0;
        for i in 0..2000 {
            let t = i as f32 * 0.0137;
            let p = [t * 1.3, 0.7 - t, 2.0 * t.sin()];
            let v = perlin(&perm, p);
            max = max.max(v.abs());
            // Lipschitz-continuous: a tiny step changes the value a little.
            let w = perlin(&perm, [p[0] + 1e-3, p[1], p[2]]);
            assert!((v - w).abs() < 0.01, "jump at {p:?}: {v} vs {w}");
        }
        assert!(max > 0.2 && max <= 1.1, "max |noise| {max}");
    }

    #[test]
    fn height_map_bilinear_matches_hand_values() {
        let map = HeightMap::new(2, 2, vec![0.0, 1.0, 0.5, 0.25]).unwrap();
        // Texel centres: (0.25, 0.75) is the top-left texel, (0.75, 0.25) the bottom-right.
        assert!((map.sample([0.25, 0.75]) - 0.0).abs() < 1e-6);
        assert!((map.sample([0.75, 0.75]) - 1.0).abs() < 1e-6);
        assert!((map.sample([0.25, 0.25]) - 0.5).abs() < 1e-6);
        assert!((map.sample([0.75, 0.25]) - 0.25).abs() < 1e-6);
        // The centre averages all four.
        assert!((map.sample([0.5, 0.5]) - 0.4375).abs() < 1e-6);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let map = HeightMap {
            width: 1,
            height: 1,
            heights: vec![1.0],
        };
        let d = Displacement::HeightMap {
            amplitude: 1.0,
            map: map.clone(),
        };
        assert_eq!(d.validate(false), Err(DisplaceError::NeedsUvs));
        assert_eq!(d.validate(true), Ok(()));
        assert!(matches!(
            HeightMap::new(2, 2, vec![1.0; 3]),
            Err(DisplaceError::MapSize { len: 3, .. })
        ));
        assert!(matches!(
            HeightMap::new(0, 0, vec![]),
            Err(DisplaceError::MapSize { .. })
        ));
        let nan = Displacement::Sine {
            amplitude: f32::NAN,
            frequency: 1.0,
        };
        assert!(matches!(
            nan.validate(false),
            Err(DisplaceError::NotFinite { .. })
        ));
    }

    #[test]
    fn hard_cube_means_are_corner_diagonals_and_every_edge_between_faces_is_split() {
        let mesh = samples::hard_cube();
        let topo = mesh.topology();
        let means = position_means(&mesh, &topo.position_ids);
        for (v, p) in mesh.positions().iter().enumerate() {
            // Every cube corner carries three face normals with equal angle sums (90° each).
            let expected = p.map(|x| x / 3f32.sqrt());
            for i in 0..3 {
                assert!(
                    (means[v][i] - expected[i]).abs() < 1e-6,
                    "vertex {v} at {p:?}: mean {:?}",
                    means[v]
                );
            }
        }
        let frames = face_frames(&mesh, &topo.position_ids);
        for (f, (frame, t)) in frames.iter().zip(mesh.triangles()).enumerate() {
            for k in 0..3 {
                // An edge of the cube joins two faces' own vertices: split. The quad's
                // diagonal joins the two triangles of one face, same vertices: not split.
                let (a, b) = (
                    mesh.positions()[t[k] as usize],
                    mesh.positions()[t[(k + 1) % 3] as usize],
                );
                let differing = (0..3).filter(|&i| a[i] != b[i]).count();
                let is_cube_edge = differing == 1;
                assert_eq!(
                    frame.mask & FaceFrame::EDGE[k] != 0,
                    is_cube_edge,
                    "face {f} edge {k}"
                );
                assert!(
                    frame.mask & FaceFrame::CORNER[k] != 0,
                    "face {f} corner {k}"
                );
            }
        }
    }

    #[test]
    fn a_mesh_with_shared_vertices_has_no_splits() {
        let mesh = samples::icosphere(1);
        let topo = mesh.topology();
        assert!(face_frames(&mesh, &topo.position_ids)
            .iter()
            .all(|f| f.mask == 0));
        // With one normal per position, the mean is that normal.
        for (m, n) in position_means(&mesh, &topo.position_ids)
            .iter()
            .zip(mesh.normals())
        {
            for i in 0..3 {
                assert!((m[i] - n[i]).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn direction_classifies_points_by_their_barycentric_coordinates() {
        let frame = FaceFrame {
            means: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            mask: FaceFrame::EDGE[1] | FaceFrame::CORNER[0],
        };
        let n = [0.0, 0.0, -1.0];
        // Corner 0 is split: its mean.
        assert_eq!(frame.direction([1.0, 0.0, 0.0], n), [1.0, 0.0, 0.0]);
        // Corner 1 lies on the split edge 1 but is not split itself: its normal.
        assert_eq!(frame.direction([0.0, 1.0, 0.0], n), n);
        // Inside edge 1 (corners 1 and 2, l1 = 0): the interpolated means, normalised.
        let d = frame.direction([0.0, 0.25, 0.75], n);
        let len = (0.25f32 * 0.25 + 0.75 * 0.75).sqrt();
        assert!((d[1] - 0.25 / len).abs() < 1e-6 && (d[2] - 0.75 / len).abs() < 1e-6);
        assert_eq!(d[0], 0.0);
        // Inside edge 0 (not split) and inside the face: the normal.
        assert_eq!(frame.direction([0.5, 0.5, 0.0], n), n);
        assert_eq!(frame.direction([0.25, 0.25, 0.5], n), n);
        // Opposite means cancel: the normal rather than NaN.
        let opposite = FaceFrame {
            means: [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
            mask: FaceFrame::EDGE[0],
        };
        assert_eq!(opposite.direction([0.5, 0.5, 0.0], n), n);
    }
}
