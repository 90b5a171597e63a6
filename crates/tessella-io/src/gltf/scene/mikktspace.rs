//! MikkTSpace tangents (Mikkelsen 2008; the tangent space glTF 2.0 names, and the one normal
//! maps are baked in), every vertex on its own and in parallel.
//!
//! The algorithm is the C original's as its maintained Rust port, `bevy_mikktspace`, runs it
//! for triangles with the default angular threshold (180°):
//! - vertices with the same position, normal and texture coordinate are one vertex (welded by
//!   value, `==` on each float);
//! - a triangle whose corners share a position is *degenerate*: its corners copy the tangent of
//!   the first good triangle at the same vertex;
//! - every other triangle has a first-order tangent `s` from its texture-coordinate derivatives
//!   and an orientation (the sign of its uv area); one with no usable derivative "groups with
//!   anything": it takes the orientation of the first group that reaches it and adds nothing;
//! - at each vertex, the triangles around it that are joined by shared edges (opposite winding)
//!   and have the same orientation form a group; the group's tangent is the sum of its
//!   triangles' `s`, each projected onto the vertex's normal plane, normalised and weighted by
//!   the triangle's angle there (measured in that plane), then normalised.
//!
//! The port walks the whole mesh once, in order, and costs about 1.7 µs a triangle (measured on
//! a 1.5M-triangle grid). Here a vertex's group is found from the triangles around it, so
//! vertices are independent: the same arithmetic in the same order, run in parallel. Only the
//! order-dependent part — which group first reaches a triangle that groups with anything — is
//! walked in order, over the vertices such triangles touch. The tests compare the result with
//! `bevy_mikktspace`'s, bit for bit.

use rayon::prelude::*;

const NONE: u32 = u32::MAX;

/// Fans up to this size are walked in fixed arrays (a refined mesh's have 6 or fewer).
const SMALL_FAN: usize = 16;

/// Which triangles around a vertex a walk has reached or still has to visit: one word for up to
/// 64 triangles (every fan of a refined mesh), flags beyond.
trait Marks {
    fn new(n: usize) -> Self;
    fn has(&self, i: usize) -> bool;
    fn mark(&mut self, i: usize);
    /// Removes and returns the lowest marked index.
    fn pop_lowest(&mut self) -> Option<usize>;
}

impl Marks for u64 {
    fn new(_n: usize) -> u64 {
        0
    }
    fn has(&self, i: usize) -> bool {
        self >> i & 1 == 1
    }
    fn mark(&mut self, i: usize) {
        *self |= 1 << i;
    }
    fn pop_lowest(&mut self) -> Option<usize> {
        if *self == 0 {
            return None;
        }
        let i = self.trailing_zeros() as usize;
        *self &= *self - 1;
        Some(i)
    }
}

impl Marks for Vec<bool> {
    fn new(n: usize) -> Vec<bool> {
        vec![false; n]
    }
    fn has(&self, i: usize) -> bool {
        self[i]
    }
    fn mark(&mut self, i: usize) {
        self[i] = true;
    }
    fn pop_lowest(&mut self) -> Option<usize> {
        let i = self.iter().position(|&b| b)?;
        self[i] = false;
        Some(i)
    }
}

/// Per vertex: `[x, y, z, handedness]`, or `None` where no triangle gives it a tangent.
pub(super) fn generate(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    triangles: &[[u32; 3]],
) -> Vec<Option<[f32; 4]>> {
    let n = positions.len();
    let welded = weld(positions, normals, uvs);
    let degenerate: Vec<bool> = triangles
        .par_iter()
        .map(|t| {
            let p = |k: usize| positions[t[k] as usize];
            p(0) == p(1) || p(1) == p(2) || p(2) == p(0)
        })
        .collect();
    // Good triangles, in order, and their corners' welded vertices.
    let good: Vec<u32> = (0..triangles.len() as u32)
        .filter(|&f| !degenerate[f as usize])
        .collect();
    let corners: Vec<[u32; 3]> = good
        .par_iter()
        .map(|&f| {
            let t = triangles[f as usize];
            [
                welded[t[0] as usize],
                welded[t[1] as usize],
                welded[t[2] as usize],
            ]
        })
        .collect();
    let faces: Vec<Face> = good
        .par_iter()
        .map(|&f| {
            let t = triangles[f as usize];
            let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
            Face::new(
                [positions[a], positions[b], positions[c]],
                [uvs[a], uvs[b], uvs[c]],
            )
        })
        .collect();
    let fans = Fans::new(n, &corners);
    // The last degenerate triangle at each vertex (its corners copy a good triangle's).
    let mut last_degenerate = vec![NONE; n];
    for (f, t) in triangles.iter().enumerate() {
        if degenerate[f] {
            for &i in t {
                last_degenerate[i as usize] = f as u32;
            }
        }
    }
    let mesh = Mesh {
        positions,
        normals,
        triangles,
        good: &good,
        corners: &corners,
        faces: &faces,
        fans: &fans,
    };
    let ordered = OrderedGroups::new(&mesh);
    (0..n as u32)
        .into_par_iter()
        .map(|u| mesh.vertex(u, welded[u as usize], last_degenerate[u as usize], &ordered))
        .collect()
}

/// One good triangle's first-order tangent and orientation.
#[derive(Clone, Copy)]
struct Face {
    s: [f32; 3],
    t: [f32; 3],
    orientation: bool,
    /// No usable uv derivative: groups with any neighbour and adds nothing to a sum.
    any: bool,
}

impl Face {
    fn new(p: [[f32; 3]; 3], tx: [[f32; 2]; 3]) -> Face {
        let d_tx = [
            [tx[1][0] - tx[0][0], tx[1][1] - tx[0][1]],
            [tx[2][0] - tx[0][0], tx[2][1] - tx[0][1]],
        ];
        let d_v = [sub(p[1], p[0]), sub(p[2], p[0])];
        let signed_area_double = d_tx[0][0] * d_tx[1][1] - d_tx[0][1] * d_tx[1][0];
        let area_double = signed_area_double.abs();
        let s = sub(scale(d_v[0], d_tx[1][1]), scale(d_v[1], d_tx[0][1]));
        let t = add(scale(d_v[0], -d_tx[1][0]), scale(d_v[1], d_tx[0][0]));
        let orientation = signed_area_double > 0.0;
        let mut face = Face {
            s: [0.0; 3],
            t: [0.0; 3],
            orientation,
            any: true,
        };
        if not_zero(area_double) {
            let sign = if orientation { 1.0 } else { -1.0 };
            face.s = scale(normalized_or_zero(s), sign);
            face.t = scale(normalized_or_zero(t), sign);
            let s_magnitude = length(s) / area_double;
            let t_magnitude = length(t) / area_double;
            face.any = !(not_zero(s_magnitude) && not_zero(t_magnitude));
        }
        face
    }
}

/// The good triangles around each welded vertex, in order (compressed rows).
struct Fans {
    offsets: Vec<u32>,
    faces: Vec<u32>,
}

impl Fans {
    fn new(n: usize, corners: &[[u32; 3]]) -> Fans {
        let mut offsets = vec![0u32; n + 1];
        for c in corners.iter().flatten() {
            offsets[*c as usize + 1] += 1;
        }
        for v in 0..n {
            offsets[v + 1] += offsets[v];
        }
        let mut next = offsets.clone();
        let mut faces = vec![0u32; offsets[n] as usize];
        for (g, c) in corners.iter().enumerate() {
            for &v in c {
                faces[next[v as usize] as usize] = g as u32;
                next[v as usize] += 1;
            }
        }
        Fans { offsets, faces }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.faces[self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize]
    }
}

/// The triangle across edge `e` (corner `e` to corner `e + 1`) of good triangle `g`, as the
/// port pairs them: the triangles on that edge in order, each still unpaired one joined to the
/// first later unpaired one that runs along it the other way. `end` is either end of the edge
/// (whose fan is searched).
fn neighbour(fans: &Fans, corners: &[[u32; 3]], g: u32, e: usize, end: u32) -> u32 {
    let c = corners[g as usize];
    let (x, y) = (c[e], c[(e + 1) % 3]);
    // (triangle, runs x→y) for every triangle on the edge.
    let on_edge = fans.of(end).iter().filter_map(|&h| {
        let d = corners[h as usize];
        let k = d.iter().position(|&w| w == x)?;
        if d[(k + 1) % 3] == y {
            Some((h, true))
        } else if d[(k + 2) % 3] == y {
            Some((h, false))
        } else {
            None
        }
    });
    let list: smallvec::SmallVec<[(u32, bool); 4]> = on_edge.collect();
    if list.len() <= 2 {
        return match list.as_slice() {
            [(a, da), (b, db)] if da != db => {
                if *a == g {
                    *b
                } else {
                    *a
                }
            }
            _ => NONE,
        };
    }
    let mut partner: smallvec::SmallVec<[u32; 4]> = smallvec::smallvec![NONE; list.len()];
    for a in 0..list.len() {
        if partner[a] != NONE {
            continue;
        }
        if let Some(b) = (a + 1..list.len()).find(|&b| partner[b] == NONE && list[b].1 != list[a].1)
        {
            partner[a] = list[b].0;
            partner[b] = list[a].0;
        }
    }
    let at = list.iter().position(|&(h, _)| h == g).unwrap_or(0);
    partner[at]
}

struct Mesh<'a> {
    positions: &'a [[f32; 3]],
    normals: &'a [[f32; 3]],
    triangles: &'a [[u32; 3]],
    good: &'a [u32],
    corners: &'a [[u32; 3]],
    faces: &'a [Face],
    fans: &'a Fans,
}

impl Mesh<'_> {
    /// Vertex `u`'s tangent: that of the last triangle using it that gives one (each triangle
    /// sets its corners in order, so the last one's value stays).
    fn vertex(
        &self,
        u: u32,
        v: u32,
        last_degenerate: u32,
        ordered: &OrderedGroups,
    ) -> Option<[f32; 4]> {
        let fan = self.fans.of(v);
        // A degenerate triangle's corner copies the first good triangle's at the same vertex.
        let copied = || fan.first().and_then(|&g| self.tangent_at(g, v, ordered));
        let mut degenerate_pending = last_degenerate != NONE;
        for &g in fan.iter().rev() {
            if !self.triangles[self.good[g as usize] as usize].contains(&u) {
                continue;
            }
            if degenerate_pending && last_degenerate > self.good[g as usize] {
                degenerate_pending = false;
                if let Some(t) = copied() {
                    return Some(t);
                }
            }
            if let Some(t) = self.tangent_at(g, v, ordered) {
                return Some(t);
            }
        }
        if degenerate_pending {
            return copied();
        }
        None
    }

    /// The tangent good triangle `g` gives its corner at welded vertex `v`: its group's, or
    /// `None` where no group took that corner.
    fn tangent_at(&self, g: u32, v: u32, ordered: &OrderedGroups) -> Option<[f32; 4]> {
        let n = self.normals[self.original(g, v) as usize];
        if ordered.touches(v) {
            let (o, list) = ordered.group_of(g, self.corner(g, v))?;
            let members: Vec<(u32, u32)> = list
                .iter()
                .map(|&h| (h, self.corner(h, v) as u32))
                .collect();
            return Some(self.value(g, n, o, &members));
        }
        let orientation = self.faces[g as usize].orientation;
        let fan = self.fans.of(v);
        if fan.len() <= SMALL_FAN {
            let mut around = [(0u32, 0u32, 0u32, 0u32); SMALL_FAN];
            self.around(v, fan, &mut around);
            let mut members = [(0u32, 0u32); SMALL_FAN];
            let count = self.group::<u64>(g, v, &around[..fan.len()], &mut members);
            Some(self.value(g, n, orientation, &members[..count]))
        } else {
            let mut around = vec![(0u32, 0u32, 0u32, 0u32); fan.len()];
            self.around(v, fan, &mut around);
            let mut members = vec![(0u32, 0u32); fan.len()];
            let count = if fan.len() <= 64 {
                self.group::<u64>(g, v, &around, &mut members)
            } else {
                self.group::<Vec<bool>>(g, v, &around, &mut members)
            };
            Some(self.value(g, n, orientation, &members[..count]))
        }
    }

    /// For each triangle of `fan` (around `v`): it, its corner at `v`, and the vertices after and
    /// before `v` in it.
    fn around(&self, v: u32, fan: &[u32], out: &mut [(u32, u32, u32, u32)]) {
        for (o, &h) in out.iter_mut().zip(fan) {
            let c = self.corners[h as usize];
            let i = self.corner(h, v);
            *o = (h, i as u32, c[(i + 1) % 3], c[(i + 2) % 3]);
        }
    }

    /// Group `g`'s tangent at a vertex with normal `n`: the angle-weighted sum of the members'
    /// projected tangents, in order (`members`: triangle, corner), normalised, and the
    /// group's handedness.
    fn value(&self, g: u32, n: [f32; 3], orientation: bool, members: &[(u32, u32)]) -> [f32; 4] {
        let project = |h: u32| {
            let f = &self.faces[h as usize];
            (
                normalized_or_zero(reject(f.s, n)),
                normalized_or_zero(reject(f.t, n)),
            )
        };
        let a = &self.faces[g as usize];
        let (s_a, t_a) = project(g);
        let mut s = [0.0f32; 3];
        for &(h, corner) in members {
            let b = &self.faces[h as usize];
            if b.any {
                continue;
            }
            let (s_b, t_b) = project(h);
            // The port's sub-group: with a 180° threshold only exactly opposite tangents split.
            if a.any || h == g || (dot(s_a, s_b) > -1.0 && dot(t_a, t_b) > -1.0) {
                s = add(s, scale(s_b, self.angle(h, corner as usize, n)));
            }
        }
        let s = normalized_or_zero(s);
        [s[0], s[1], s[2], if orientation { 1.0 } else { -1.0 }]
    }

    /// The group of good triangle `g` at welded vertex `v` (where no triangle around `v` groups
    /// with anything): the triangles around `v` (`around`) reached from `g` across edges at
    /// `v`, with `g`'s orientation. Written to `members` in order, with their corners; returns
    /// how many.
    fn group<M: Marks>(
        &self,
        g: u32,
        v: u32,
        around: &[(u32, u32, u32, u32)],
        members: &mut [(u32, u32)],
    ) -> usize {
        let orientation = self.faces[g as usize].orientation;
        // Bit y: triangle y of `around` reached; then the ones still to visit.
        let mut reached = M::new(around.len());
        let mut queue = M::new(around.len());
        let start = around.iter().position(|f| f.0 == g).unwrap_or(0);
        reached.mark(start);
        queue.mark(start);
        while let Some(x) = queue.pop_lowest() {
            let (h, i, next, prev) = around[x];
            // Edge v→next pairs with a triangle running next→v; edge prev→v with one v→prev.
            for (w, forward) in [(prev, false), (next, true)] {
                let mut on_edge = 0;
                let mut other = None;
                for (y, f) in around.iter().enumerate() {
                    let runs_back = if forward { f.3 == w } else { f.2 == w };
                    on_edge += usize::from(f.2 == w || f.3 == w);
                    if runs_back {
                        other = Some(y);
                    }
                }
                let y = if on_edge == 2 {
                    other
                } else {
                    let e = if forward {
                        i as usize
                    } else {
                        (i as usize + 2) % 3
                    };
                    let k = neighbour(self.fans, self.corners, h, e, v);
                    around.iter().position(|f| f.0 == k)
                };
                if let Some(y) = y {
                    if !reached.has(y)
                        && self.faces[around[y].0 as usize].orientation == orientation
                    {
                        reached.mark(y);
                        queue.mark(y);
                    }
                }
            }
        }
        let mut count = 0;
        for (y, f) in around.iter().enumerate() {
            if reached.has(y) {
                members[count] = (f.0, f.1);
                count += 1;
            }
        }
        count
    }

    /// Good triangle `h`'s angle at its corner `i`, measured in the plane normal to `n`.
    fn angle(&self, h: u32, i: usize, n: [f32; 3]) -> f32 {
        let t = self.triangles[self.good[h as usize] as usize];
        let here = self.positions[t[i] as usize];
        let after = self.positions[t[(i + 1) % 3] as usize];
        let before = self.positions[t[(i + 2) % 3] as usize];
        let e0 = normalized_or_zero(reject(sub(after, here), n));
        let e1 = normalized_or_zero(reject(sub(before, here), n));
        let cos = dot(e0, e1).clamp(-1.0, 1.0);
        // f64's acos, as the port (to match the C original's bits).
        (cos as f64).acos() as f32
    }

    /// The corner of good triangle `g` at welded vertex `v`.
    fn corner(&self, g: u32, v: u32) -> usize {
        let c = self.corners[g as usize];
        if c[0] == v {
            0
        } else if c[1] == v {
            1
        } else {
            2
        }
    }

    /// The vertex (index) at good triangle `g`'s corner at `v`.
    fn original(&self, g: u32, v: u32) -> u32 {
        self.triangles[self.good[g as usize] as usize][self.corner(g, v)]
    }
}

/// The groups at the vertices that triangles grouping with anything touch, built in the port's
/// order: such a triangle's orientation is set by the first group that reaches it.
struct OrderedGroups {
    touched: Vec<bool>,
    /// Per good triangle corner (`3 g + i`): its group, or `NONE`.
    assigned: Vec<u32>,
    groups: Vec<(bool, Vec<u32>)>,
}

impl OrderedGroups {
    fn new(mesh: &Mesh) -> OrderedGroups {
        let mut touched = Vec::new();
        let mut assigned = Vec::new();
        let mut groups = Vec::new();
        if mesh.faces.iter().any(|f| f.any) {
            touched = vec![false; mesh.fans.offsets.len() - 1];
            for (g, f) in mesh.faces.iter().enumerate() {
                if f.any {
                    for &v in &mesh.corners[g] {
                        touched[v as usize] = true;
                    }
                }
            }
            assigned = vec![NONE; mesh.faces.len() * 3];
            let mut orientation: Vec<bool> = mesh.faces.iter().map(|f| f.orientation).collect();
            let mut stack = Vec::new();
            for g in 0..mesh.faces.len() {
                for i in 0..3 {
                    let v = mesh.corners[g][i];
                    if !touched[v as usize] || mesh.faces[g].any || assigned[g * 3 + i] != NONE {
                        continue;
                    }
                    let id = groups.len() as u32;
                    let o = orientation[g];
                    let mut members = vec![g as u32];
                    assigned[g * 3 + i] = id;
                    stack.clear();
                    stack.extend(
                        [(i + 2) % 3, i]
                            .map(|e| neighbour(mesh.fans, mesh.corners, g as u32, e, v)),
                    );
                    while let Some(h) = stack.pop() {
                        if h == NONE {
                            continue;
                        }
                        let h = h as usize;
                        let k = mesh.corner(h as u32, v);
                        if assigned[h * 3 + k] != NONE {
                            continue;
                        }
                        if mesh.faces[h].any
                            && assigned[h * 3..h * 3 + 3].iter().all(|&a| a == NONE)
                        {
                            orientation[h] = o;
                        }
                        if orientation[h] != o {
                            continue;
                        }
                        members.push(h as u32);
                        assigned[h * 3 + k] = id;
                        // Which triangles join does not depend on the order they are visited in
                        // (a corner at `v` is only taken by this walk), so a stack will do.
                        stack.extend(
                            [k, (k + 2) % 3]
                                .map(|e| neighbour(mesh.fans, mesh.corners, h as u32, e, v)),
                        );
                    }
                    members.sort_unstable();
                    groups.push((o, members));
                }
            }
        }
        OrderedGroups {
            touched,
            assigned,
            groups,
        }
    }

    fn touches(&self, v: u32) -> bool {
        self.touched.get(v as usize).copied().unwrap_or(false)
    }

    fn group_of(&self, g: u32, corner: usize) -> Option<(bool, &[u32])> {
        let id = self.assigned[g as usize * 3 + corner];
        (id != NONE).then(|| {
            let (o, members) = &self.groups[id as usize];
            (*o, members.as_slice())
        })
    }
}

/// Each vertex's representative: the lowest-numbered vertex with the same position, normal
/// and texture coordinate (`==` on each float, as the port's default welding: -0 equals 0,
/// NaN equals nothing).
fn weld(positions: &[[f32; 3]], normals: &[[f32; 3]], uvs: &[[f32; 2]]) -> Vec<u32> {
    let key = |v: usize| -> Option<[u32; 8]> {
        let p = positions[v];
        let n = normals[v];
        let t = uvs[v];
        let all = [p[0], p[1], p[2], n[0], n[1], n[2], t[0], t[1]];
        if all.iter().any(|x| x.is_nan()) {
            return None;
        }
        Some(all.map(|x| if x == 0.0 { 0 } else { x.to_bits() }))
    };
    let mut order: Vec<(u64, u32)> = (0..positions.len())
        .into_par_iter()
        .filter_map(|v| {
            let k = key(v)?;
            let hash = k.iter().fold(0u64, |h, &x| {
                (h.rotate_left(5) ^ u64::from(x)).wrapping_mul(0x517c_c1b7_2722_0a95)
            });
            Some((hash, v as u32))
        })
        .collect();
    order.par_sort_unstable();
    let mut welded: Vec<u32> = (0..positions.len() as u32).collect();
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        for (j, &(_, b)) in run.iter().enumerate().skip(1) {
            let kb = key(b as usize);
            if let Some(&(_, a)) = run[..j].iter().find(|&&(_, a)| key(a as usize) == kb) {
                welded[b as usize] = welded[a as usize];
            }
        }
    }
    welded
}

// The port's float arithmetic, operation for operation (the same bits).

#[inline(always)]
fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}

#[inline(always)]
fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn scale(a: [f32; 3], k: f32) -> [f32; 3] {
    [k * a[0], k * a[1], k * a[2]]
}

#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn length(a: [f32; 3]) -> f32 {
    dot(a, a).sqrt()
}

#[inline(always)]
fn normalized_or_zero(a: [f32; 3]) -> [f32; 3] {
    if not_zero(a[0]) || not_zero(a[1]) || not_zero(a[2]) {
        scale(a, length(a).recip())
    } else {
        a
    }
}

/// `a` without its component along the unit vector `n`.
#[inline(always)]
fn reject(a: [f32; 3], n: [f32; 3]) -> [f32; 3] {
    sub(a, scale(n, dot(n, a)))
}

#[cfg(test)]
mod tests {
    use super::generate;

    /// `bevy_mikktspace`'s tangents, kept per vertex as the scene writer kept them: each
    /// triangle's corners set in order, the last value given stays.
    struct Reference<'a> {
        positions: &'a [[f32; 3]],
        normals: &'a [[f32; 3]],
        uvs: &'a [[f32; 2]],
        triangles: &'a [[u32; 3]],
        out: Vec<Option<[f32; 4]>>,
    }

    impl bevy_mikktspace::Geometry for Reference<'_> {
        fn num_faces(&self) -> usize {
            self.triangles.len()
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.positions[self.triangles[face][vert] as usize]
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.normals[self.triangles[face][vert] as usize]
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            self.uvs[self.triangles[face][vert] as usize]
        }
        fn set_tangent(
            &mut self,
            tangent: Option<bevy_mikktspace::TangentSpace>,
            face: usize,
            vert: usize,
        ) {
            if let Some(t) = tangent {
                self.out[self.triangles[face][vert] as usize] = Some(t.tangent_encoded());
            }
        }
    }

    fn reference(
        positions: &[[f32; 3]],
        normals: &[[f32; 3]],
        uvs: &[[f32; 2]],
        triangles: &[[u32; 3]],
    ) -> Vec<Option<[f32; 4]>> {
        let mut geometry = Reference {
            positions,
            normals,
            uvs,
            triangles,
            out: vec![None; positions.len()],
        };
        bevy_mikktspace::generate_tangents(&mut geometry).expect("the reference runs");
        geometry.out
    }

    /// Compares with the reference bit for bit; returns the number of vertices with a tangent.
    fn check(
        name: &str,
        positions: &[[f32; 3]],
        normals: &[[f32; 3]],
        uvs: &[[f32; 2]],
        triangles: &[[u32; 3]],
    ) -> usize {
        let ours = generate(positions, normals, uvs, triangles);
        let theirs = reference(positions, normals, uvs, triangles);
        let bits = |t: &Option<[f32; 4]>| t.map(|t| t.map(f32::to_bits));
        let differ: Vec<usize> = (0..ours.len())
            .filter(|&v| bits(&ours[v]) != bits(&theirs[v]))
            .collect();
        assert!(
            differ.is_empty(),
            "{name}: {} of {} vertices differ from bevy_mikktspace, first {:?}: ours {:?}, reference {:?}",
            differ.len(),
            ours.len(),
            differ.first(),
            ours[differ[0]],
            theirs[differ[0]],
        );
        ours.iter().filter(|t| t.is_some()).count()
    }

    /// A latitude-longitude sphere: a uv seam (the first and last columns are separate
    /// vertices), poles of `k + 1` vertices at one point (so each pole quad has a degenerate
    /// triangle), positions pushed by `bump` so no two triangles are alike.
    /// Positions, normals, texture coordinates, triangles.
    type Arrays = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[u32; 3]>);

    fn sphere(k: usize, bump: f32) -> Arrays {
        let (mut p, mut n, mut uv, mut t) = (vec![], vec![], vec![], vec![]);
        for j in 0..=k {
            for i in 0..=k {
                let (u, v) = (i as f32 / k as f32, j as f32 / k as f32);
                let (a, b) = (u * std::f32::consts::TAU, v * std::f32::consts::PI);
                let r = 1.0 + bump * ((i * 7 + j * 13) % 5) as f32;
                let q = [b.sin() * a.cos(), b.sin() * a.sin(), b.cos()];
                p.push(if j == 0 || j == k {
                    [0.0, 0.0, q[2]]
                } else {
                    q.map(|c| c * r)
                });
                n.push(if j == 0 || j == k {
                    [0.0, 0.0, q[2].signum()]
                } else {
                    q
                });
                uv.push([u, v]);
            }
        }
        for j in 0..k {
            for i in 0..k {
                let a = (j * (k + 1) + i) as u32;
                let (b, c) = (a + 1, a + k as u32 + 1);
                t.push([a, b, c + 1]);
                t.push([a, c + 1, c]);
            }
        }
        (p, n, uv, t)
    }

    #[test]
    fn a_sphere_with_a_seam_and_degenerate_poles_matches_the_port() {
        let (p, n, uv, t) = sphere(24, 0.01);
        let given = check("sphere", &p, &n, &uv, &t);
        // The comparison is of tangents, not of their absence (a pole corner that only
        // degenerate triangles use gets none, in both).
        assert!(
            given > p.len() * 9 / 10,
            "{given} of {} vertices have a tangent",
            p.len()
        );
    }

    #[test]
    fn a_finer_bumpy_sphere_matches_the_port() {
        let (p, n, uv, t) = sphere(100, 0.003);
        check("fine sphere", &p, &n, &uv, &t);
    }

    #[test]
    fn mirrored_texture_coordinates_match_the_port() {
        // u mirrored about the middle column: two orientations meet at the vertices there.
        let (p, n, mut uv, t) = sphere(20, 0.0);
        for c in &mut uv {
            c[0] = (c[0] - 0.5).abs();
        }
        check("mirrored", &p, &n, &uv, &t);
    }

    #[test]
    fn triangles_without_usable_uvs_take_their_neighbours_group() {
        // Collapsed and collinear uvs on some triangles: they group with anything.
        let (p, n, mut uv, t) = sphere(16, 0.02);
        for (f, tri) in t.iter().enumerate() {
            if f % 7 == 3 {
                let c = uv[tri[0] as usize];
                uv[tri[1] as usize] = c;
                uv[tri[2] as usize] = c;
            }
        }
        check("collapsed uvs", &p, &n, &uv, &t);
    }

    #[test]
    fn a_triangle_soup_is_welded_by_value_as_the_port_welds_it() {
        let (p, n, uv, t) = sphere(12, 0.01);
        let (mut sp, mut sn, mut suv, mut st) = (vec![], vec![], vec![], vec![]);
        for tri in &t {
            let base = sp.len() as u32;
            for &i in tri {
                sp.push(p[i as usize]);
                sn.push(n[i as usize]);
                suv.push(uv[i as usize]);
            }
            st.push([base, base + 1, base + 2]);
        }
        // -0.0 equals 0.0 when welding.
        for q in &mut sp {
            for c in q.iter_mut() {
                if *c == 0.0 {
                    *c = -0.0;
                }
            }
        }
        check("soup", &sp, &sn, &suv, &st);
    }

    #[test]
    fn edges_shared_by_three_triangles_pair_as_the_port_pairs_them() {
        // A fin: three triangles on the edge 0-1, two windings.
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.1],
            [0.5, 0.2, 1.0],
        ];
        let n = [[0.0, 0.0, 1.0]; 5];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [0.5, -1.0], [0.6, 0.7]];
        let t = [[0, 1, 2], [1, 0, 3], [0, 1, 4], [4, 1, 2]];
        check("fin", &p, &n, &uv, &t);
    }

    /// The recomputed tangents of a refined scene are MikkTSpace's, bit for bit: the port run
    /// on the written file's own positions, normals, indices and normal-map uvs (v flipped to
    /// MikkTSpace's convention), then made orthogonal to the normal as the writer documents,
    /// gives the file's TANGENT exactly. The sample scene's normal-mapped primitives, levels 1
    /// and 4; the output is read back through the scene reader.
    #[test]
    fn recomputed_tangents_of_a_refined_scene_are_the_ports_bit_for_bit() {
        use super::super::accessor::{read_f32, read_u32};
        use super::super::{Scene, SceneLevels, SceneOptions};
        use crate::gltf::Buffers;
        use tessella_core::{RefineOptions, Scheme};
        let input = crate::sample_scene(false);
        let scene = Scene::from_bytes("in.glb", &input, Buffers::Given(&[])).unwrap();
        for level in [1, 4] {
            let options = SceneOptions::new(
                RefineOptions::new(Scheme::Pn, 1),
                SceneLevels::Uniform(level),
            );
            let glb = scene.refine(&options).unwrap().to_glb().unwrap();
            let out = Scene::from_bytes("out.glb", &glb, Buffers::Given(&[])).unwrap();
            let mut checked = 0;
            for primitive in out.document.meshes().flat_map(|m| m.primitives()) {
                let attribute = |semantic: gltf::Semantic| {
                    let accessor = primitive.get(&semantic).expect("the attribute");
                    read_f32(&accessor, &out.buffers).unwrap()
                };
                if primitive.get(&gltf::Semantic::Tangents).is_none() {
                    continue;
                }
                let set = primitive
                    .material()
                    .normal_texture()
                    .map_or(0, |t| t.tex_coord());
                let positions: Vec<[f32; 3]> = attribute(gltf::Semantic::Positions)
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect();
                let normals: Vec<[f32; 3]> = attribute(gltf::Semantic::Normals)
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect();
                let uvs: Vec<[f32; 2]> = attribute(gltf::Semantic::TexCoords(set))
                    .chunks_exact(2)
                    .map(|c| [c[0], 1.0 - c[1]])
                    .collect();
                let triangles: Vec<[u32; 3]> =
                    read_u32(&primitive.indices().unwrap(), &out.buffers)
                        .unwrap()
                        .chunks_exact(3)
                        .map(|c| [c[0], c[1], c[2]])
                        .collect();
                let expected: Vec<f32> = reference(&positions, &normals, &uvs, &triangles)
                    .iter()
                    .zip(&normals)
                    .flat_map(|(t, n)| {
                        let t = t.unwrap_or([1.0, 0.0, 0.0, 1.0]);
                        let n = glam::Vec3::from(*n);
                        let v = glam::Vec3::new(t[0], t[1], t[2]);
                        let v = (v - n * n.dot(v))
                            .try_normalize()
                            .unwrap_or_else(|| n.any_orthonormal_vector());
                        [v.x, v.y, v.z, if t[3] < 0.0 { -1.0 } else { 1.0 }]
                    })
                    .collect();
                let got = attribute(gltf::Semantic::Tangents);
                let differ = got
                    .iter()
                    .zip(&expected)
                    .filter(|(a, b)| a.to_bits() != b.to_bits())
                    .count();
                assert_eq!(got.len(), expected.len());
                assert_eq!(
                    differ,
                    0,
                    "level {level}: {differ} of {} tangent floats differ",
                    got.len()
                );
                checked += positions.len();
            }
            assert!(
                checked > 400,
                "level {level}: only {checked} vertices checked"
            );
        }
    }
}
