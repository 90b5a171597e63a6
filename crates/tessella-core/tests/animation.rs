//! Posing against an independent f64 evaluation of the glTF 2.0 specification written here
//! (own quaternions, slerp, Hermite splines, 4×4 products and inverses), and the refusals of
//! bad input.

// The reference spells the specification's formulas out with indices and plain tuples.
#![allow(clippy::needless_range_loop, clippy::type_complexity)]

use tessella_core::animation::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Poser,
    Property, Sampler, Skin, Transform,
};
use tessella_core::AnimationError;

// ---------------------------------------------------------------- f64 reference of the spec

/// Column-major 4×4: `m[col * 4 + row]`.
type M4 = [f64; 16];

const IDENTITY: M4 = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

fn mul(a: &M4, b: &M4) -> M4 {
    let mut m = [0.0; 16];
    for col in 0..4 {
        for row in 0..4 {
            m[col * 4 + row] = (0..4).map(|k| a[k * 4 + row] * b[col * 4 + k]).sum();
        }
    }
    m
}

/// The inverse by cofactors (Laplace expansion), row-major-agnostic since
/// `inverse(transpose) = transpose(inverse)`.
fn inverse(m: &M4) -> M4 {
    let minor = |r: usize, c: usize| -> f64 {
        let mut s = [0.0; 9];
        let mut i = 0;
        for col in (0..4).filter(|&x| x != c) {
            for row in (0..4).filter(|&x| x != r) {
                s[i] = m[col * 4 + row];
                i += 1;
            }
        }
        s[0] * (s[4] * s[8] - s[7] * s[5]) - s[3] * (s[1] * s[8] - s[7] * s[2])
            + s[6] * (s[1] * s[5] - s[4] * s[2])
    };
    let mut cof = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            let sign = if (r + c) % 2 == 0 { 1.0 } else { -1.0 };
            cof[c * 4 + r] = sign * minor(r, c);
        }
    }
    let det: f64 = (0..4).map(|c| m[c * 4] * cof[c * 4]).sum();
    // inverse = adjugate / det, adjugate = transpose of the cofactors.
    let mut inv = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            inv[c * 4 + r] = cof[r * 4 + c] / det;
        }
    }
    inv
}

fn transform_point(m: &M4, p: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (row, o) in out.iter_mut().enumerate() {
        *o = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
    }
    out
}

/// `inverse(M3)ᵀ · n`, normalised, for `M3` the upper 3×3 of `m`.
fn transform_normal(m: &M4, n: [f64; 3]) -> [f64; 3] {
    let mut m3 = IDENTITY;
    for c in 0..3 {
        for r in 0..3 {
            m3[c * 4 + r] = m[c * 4 + r];
        }
    }
    let inv = inverse(&m3);
    // (inv)ᵀ · n: row r of invᵀ is column r of inv.
    let mut out = [0.0; 3];
    for (r, o) in out.iter_mut().enumerate() {
        *o = (0..3).map(|k| inv[r * 4 + k] * n[k]).sum();
    }
    normalize3(out)
}

fn normalize3(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

fn normalize4(q: [f64; 4]) -> [f64; 4] {
    let l = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    q.map(|c| c / l)
}

/// T · R · S with R from the unit quaternion `[x, y, z, w]`.
fn trs(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> M4 {
    let [x, y, z, w] = normalize4(q);
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mut m = IDENTITY;
    for col in 0..3 {
        for row in 0..3 {
            m[col * 4 + row] = r[row][col] * s[col];
        }
        m[12 + col] = t[col];
    }
    m
}

fn slerp(a: [f64; 4], b: [f64; 4], s: f64) -> [f64; 4] {
    let a = normalize4(a);
    let mut b = normalize4(b);
    let mut dot: f64 = (0..4).map(|i| a[i] * b[i]).sum();
    if dot < 0.0 {
        b = b.map(|c| -c);
        dot = -dot;
    }
    let theta = dot.min(1.0).acos();
    if theta < 1e-12 {
        return b;
    }
    let (wa, wb) = (
        ((1.0 - s) * theta).sin() / theta.sin(),
        (s * theta).sin() / theta.sin(),
    );
    normalize4([0, 1, 2, 3].map(|i| wa * a[i] + wb * b[i]))
}

/// Appendix C of the glTF 2.0 specification, in f64.
fn sample(sampler: &Sampler, time: f32, c: usize, rotation: bool) -> Vec<f64> {
    let t: Vec<f64> = sampler.times.iter().map(|&x| x as f64).collect();
    let v: Vec<f64> = sampler.values.iter().map(|&x| x as f64).collect();
    let cubic = sampler.interpolation == Interpolation::CubicSpline;
    let value = |k: usize| -> Vec<f64> {
        let start = if cubic { (3 * k + 1) * c } else { k * c };
        v[start..start + c].to_vec()
    };
    let time = time as f64;
    let n = t.len();
    let out = if time <= t[0] {
        value(0)
    } else if time >= t[n - 1] {
        value(n - 1)
    } else {
        let k = (0..n - 1)
            .find(|&k| t[k] <= time && time < t[k + 1])
            .unwrap();
        let td = t[k + 1] - t[k];
        let s = (time - t[k]) / td;
        match sampler.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear if rotation => {
                let (a, b) = (value(k), value(k + 1));
                slerp([a[0], a[1], a[2], a[3]], [b[0], b[1], b[2], b[3]], s).to_vec()
            }
            Interpolation::Linear => {
                let (a, b) = (value(k), value(k + 1));
                (0..c).map(|i| (1.0 - s) * a[i] + s * b[i]).collect()
            }
            Interpolation::CubicSpline => (0..c)
                .map(|i| {
                    let vk = v[(3 * k + 1) * c + i];
                    let bk = v[(3 * k + 2) * c + i];
                    let ak1 = v[(3 * (k + 1)) * c + i];
                    let vk1 = v[(3 * (k + 1) + 1) * c + i];
                    (2.0 * s.powi(3) - 3.0 * s * s + 1.0) * vk
                        + td * (s.powi(3) - 2.0 * s * s + s) * bk
                        + (-2.0 * s.powi(3) + 3.0 * s * s) * vk1
                        + td * (s.powi(3) - s * s) * ak1
                })
                .collect(),
        }
    };
    if rotation {
        normalize4([out[0], out[1], out[2], out[3]]).to_vec()
    } else {
        out
    }
}

type Pose64 = (Vec<[f64; 3]>, Vec<[f64; 3]>);

/// The pose by the specification, in f64; normals only for instances that have them.
fn reference(model: &AnimatedMesh, clip: Option<usize>, time: f32) -> Pose64 {
    let f = |a: [f32; 3]| a.map(|x| x as f64);
    // Local transforms and weights.
    let mut trs_of: Vec<Option<([f64; 3], [f64; 4], [f64; 3])>> = Vec::new();
    let mut locals_fixed: Vec<M4> = Vec::new();
    for node in &model.nodes {
        match node.transform {
            Transform::Trs {
                translation,
                rotation,
                scale,
            } => {
                trs_of.push(Some((f(translation), rotation.map(|x| x as f64), f(scale))));
                locals_fixed.push(IDENTITY);
            }
            Transform::Matrix(m) => {
                trs_of.push(None);
                locals_fixed.push(m.map(|x| x as f64));
            }
        }
    }
    let mut weights: Vec<Option<Vec<f64>>> = model
        .nodes
        .iter()
        .map(|n| {
            n.weights
                .as_ref()
                .map(|w| w.iter().map(|&x| x as f64).collect())
        })
        .collect();
    if let Some(clip) = clip {
        for ch in &model.clips[clip].channels {
            let node = ch.node as usize;
            let c = match ch.property {
                Property::Translation | Property::Scale => 3,
                Property::Rotation => 4,
                Property::Weights => {
                    let per = if ch.sampler.interpolation == Interpolation::CubicSpline {
                        3
                    } else {
                        1
                    };
                    ch.sampler.values.len() / ch.sampler.times.len() / per
                }
            };
            let v = sample(&ch.sampler, time, c, ch.property == Property::Rotation);
            let entry = trs_of[node].as_mut();
            match (ch.property, entry) {
                (Property::Translation, Some(e)) => e.0 = [v[0], v[1], v[2]],
                (Property::Rotation, Some(e)) => e.1 = [v[0], v[1], v[2], v[3]],
                (Property::Scale, Some(e)) => e.2 = [v[0], v[1], v[2]],
                (Property::Weights, _) => weights[node] = Some(v),
                _ => panic!("animated matrix node"),
            }
        }
    }
    let local = |i: usize| match trs_of[i] {
        Some((t, r, s)) => trs(t, r, s),
        None => locals_fixed[i],
    };
    fn world(model: &AnimatedMesh, local: &dyn Fn(usize) -> M4, i: usize) -> M4 {
        match model.nodes[i].parent {
            Some(p) => mul(&world(model, local, p as usize), &local(i)),
            None => local(i),
        }
    }
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    for inst in &model.instances {
        let node = inst.node as usize;
        let w: Vec<f64> = weights[node]
            .clone()
            .unwrap_or_else(|| inst.default_weights.iter().map(|&x| x as f64).collect());
        let joints: Vec<M4> = inst
            .skin
            .map(|s| {
                let skin = &model.skins[s as usize];
                skin.joints
                    .iter()
                    .zip(&skin.inverse_binds)
                    .map(|(&j, ib)| mul(&world(model, &local, j as usize), &ib.map(|x| x as f64)))
                    .collect()
            })
            .unwrap_or_default();
        let node_world = world(model, &local, node);
        for v in 0..inst.positions.len() {
            let mut p = f(inst.positions[v]);
            let mut n = inst.normals.as_ref().map(|n| f(n[v]));
            for (t, target) in inst.targets.iter().enumerate() {
                for i in 0..3 {
                    p[i] += w[t] * target.positions[v][i] as f64;
                }
                if let (Some(n), Some(tn)) = (n.as_mut(), &target.normals) {
                    for i in 0..3 {
                        n[i] += w[t] * tn[v][i] as f64;
                    }
                }
            }
            let m = if inst.skin.is_some() {
                let mut m = [0.0; 16];
                let mut sum = 0.0;
                for set in &inst.influences {
                    for k in 0..4 {
                        let wk = set.weights[v][k] as f64;
                        let j = &joints[set.joints[v][k] as usize];
                        for e in 0..16 {
                            m[e] += wk * j[e];
                        }
                        sum += wk;
                    }
                }
                m.map(|e| e / sum)
            } else {
                node_world
            };
            positions.push(transform_point(&m, p));
            if let Some(n) = n {
                normals.push(transform_normal(&m, n));
            }
        }
    }
    (positions, normals)
}

// ---------------------------------------------------------------- scenes

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    /// Uniform in `lo..hi`.
    fn next(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
    }
    fn vec3(&mut self, lo: f32, hi: f32) -> [f32; 3] {
        [self.next(lo, hi), self.next(lo, hi), self.next(lo, hi)]
    }
    /// A unit quaternion of a rotation by up to `max` radians about a random axis.
    fn quat(&mut self, max: f32) -> [f32; 4] {
        let axis = self.vec3(-1.0, 1.0);
        let l = axis.iter().map(|c| c * c).sum::<f32>().sqrt();
        let angle = self.next(-max, max);
        let (s, c) = (angle / 2.0).sin_cos();
        [axis[0] / l * s, axis[1] / l * s, axis[2] / l * s, c]
    }
}

fn trs_node(parent: Option<u32>, t: [f32; 3], r: [f32; 4], s: [f32; 3]) -> Node {
    Node {
        name: None,
        parent,
        transform: Transform::Trs {
            translation: t,
            rotation: r,
            scale: s,
        },
        weights: None,
    }
}

/// A grid of `n × n` vertices in the z = 0 plane, its normals tilted a little.
fn grid(rng: &mut Lcg, n: usize, size: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
            positions.push([size * (x - 0.5), size * y, rng.next(-0.05, 0.05)]);
            let t = rng.vec3(-0.2, 0.2);
            let n = [t[0], t[1], 1.0];
            let l = (n[0] * n[0] + n[1] * n[1] + 1.0).sqrt();
            normals.push(n.map(|c| c / l));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    (positions, normals, triangles)
}

/// A channel with keys at `times` for `kind`, `c` components per key, values from `value`.
fn channel(
    rng: &mut Lcg,
    node: u32,
    property: Property,
    kind: Interpolation,
    times: &[f32],
    c: usize,
    value: &mut dyn FnMut(&mut Lcg, usize) -> Vec<f32>,
) -> Channel {
    let mut values = Vec::new();
    for k in 0..times.len() {
        if kind == Interpolation::CubicSpline {
            let tangents = |rng: &mut Lcg| (0..c).map(|_| rng.next(-1.0, 1.0)).collect::<Vec<_>>();
            let a = tangents(rng);
            let v = value(rng, k);
            let b = tangents(rng);
            values.extend(a);
            values.extend(v);
            values.extend(b);
        } else {
            values.extend(value(rng, k));
        }
    }
    Channel {
        node,
        property,
        sampler: Sampler {
            interpolation: kind,
            times: times.to_vec(),
            values,
        },
    }
}

const ROOT: u32 = 0;
const MESH_NODE: u32 = 9;
const PROP_NODE: u32 = 10;

/// The test scene: a root above eight joints (a chain and branches), a skinned grid with two
/// influence sets (weights not summing to one, some zero) and two morph targets, and an
/// unskinned grid under a matrix node; one clip of `kind` animating translation, rotation,
/// scale and weights.
fn scene(kind: Interpolation) -> AnimatedMesh {
    let mut rng = Lcg(7 + kind as u64);
    let mut nodes = vec![
        trs_node(None, [0.3, -0.2, 0.1], rng.quat(0.6), [1.2, 0.8, 1.0]), // 0 root
        trs_node(Some(0), [0.0, 0.2, 0.0], rng.quat(0.3), [1.0; 3]),      // 1 hip
        trs_node(Some(1), [0.0, 0.4, 0.0], rng.quat(0.3), [1.0; 3]),      // 2 knee
        trs_node(Some(2), [0.0, 0.4, 0.1], rng.quat(0.3), [1.0; 3]),      // 3 ankle
        trs_node(Some(1), [0.3, 0.1, 0.0], rng.quat(0.3), [1.0; 3]),      // 4
        trs_node(Some(4), [0.2, 0.3, 0.0], rng.quat(0.3), [0.9, 1.1, 1.0]), // 5
        trs_node(Some(1), [-0.3, 0.1, 0.0], rng.quat(0.3), [1.0; 3]),     // 6
        trs_node(Some(6), [-0.2, 0.3, 0.0], rng.quat(0.3), [1.0; 3]),     // 7
        trs_node(Some(3), [0.0, 0.2, 0.0], rng.quat(0.3), [1.0; 3]),      // 8
        // 9: the skinned mesh's node; its own transform is ignored.
        trs_node(None, [5.0, 5.0, 5.0], rng.quat(1.0), [3.0; 3]),
        trs_node(Some(11), [0.2, 0.0, 0.1], rng.quat(0.5), [0.5, 0.6, 0.7]), // 10 prop
        Node::default(),                                                     // 11 matrix
    ];
    let mut m = trs([0.1, 0.3, -0.2], [0.1, 0.2, 0.3, 0.9], [1.0, 1.3, 0.9]);
    m = mul(&m, &IDENTITY);
    nodes[11] = Node {
        name: Some("holder".into()),
        parent: Some(2),
        transform: Transform::Matrix(m.map(|x| x as f32)),
        weights: None,
    };
    nodes[PROP_NODE as usize].weights = Some(vec![0.25]);
    // Inverse binds: the inverse of each joint's rest world matrix, perturbed a little.
    let joints: Vec<u32> = (1..=8).collect();
    let rest = AnimatedMesh {
        nodes: nodes.clone(),
        ..AnimatedMesh::default()
    };
    let world = |i: usize| -> M4 {
        let mut chain = vec![i];
        while let Some(p) = rest.nodes[*chain.last().unwrap()].parent {
            chain.push(p as usize);
        }
        chain
            .iter()
            .rev()
            .fold(IDENTITY, |acc, &n| match rest.nodes[n].transform {
                Transform::Trs {
                    translation,
                    rotation,
                    scale,
                } => mul(
                    &acc,
                    &trs(
                        translation.map(|x| x as f64),
                        rotation.map(|x| x as f64),
                        scale.map(|x| x as f64),
                    ),
                ),
                Transform::Matrix(m) => mul(&acc, &m.map(|x| x as f64)),
            })
    };
    let inverse_binds = joints
        .iter()
        .map(|&j| {
            let mut ib = inverse(&world(j as usize));
            ib[12] += 0.05;
            ib.map(|x| x as f32)
        })
        .collect();
    let skin = Skin {
        name: Some("legs".into()),
        joints,
        inverse_binds,
        skeleton: Some(1),
    };

    let (positions, normals, triangles) = grid(&mut rng, 5, 1.0);
    let count = positions.len();
    let targets = vec![
        MorphTarget {
            positions: (0..count).map(|_| rng.vec3(-0.1, 0.1)).collect(),
            normals: Some((0..count).map(|_| rng.vec3(-0.2, 0.2)).collect()),
        },
        MorphTarget {
            positions: (0..count).map(|_| rng.vec3(-0.1, 0.1)).collect(),
            normals: None,
        },
    ];
    let mut influences = vec![Influences::default(), Influences::default()];
    for v in 0..count {
        for set in &mut influences {
            let mut j = [0u16; 4];
            let mut w = [0f32; 4];
            for k in 0..4 {
                j[k] = (rng.next(0.0, 8.0) as u16).min(7);
                w[k] = if rng.next(0.0, 1.0) < 0.2 {
                    0.0
                } else {
                    rng.next(0.0, 0.6)
                };
            }
            set.joints.push(j);
            set.weights.push(w);
        }
        influences[0].weights[v][0] += 0.1; // never all zero
    }
    let skinned = Instance {
        node: MESH_NODE,
        skin: Some(0),
        first_vertex: 0,
        positions,
        normals: Some(normals),
        targets,
        default_weights: vec![0.3, -0.2],
        influences,
    };
    let (p2, n2, t2) = grid(&mut rng, 3, 0.4);
    let prop = Instance {
        node: PROP_NODE,
        skin: None,
        first_vertex: count as u32,
        targets: vec![MorphTarget {
            positions: (0..p2.len()).map(|_| rng.vec3(-0.1, 0.1)).collect(),
            normals: Some((0..p2.len()).map(|_| rng.vec3(-0.2, 0.2)).collect()),
        }],
        positions: p2,
        normals: Some(n2),
        default_weights: vec![0.5],
        influences: Vec::new(),
    };
    let mut triangles = triangles;
    triangles.extend(t2.iter().map(|t| t.map(|i| i + count as u32)));

    let times = [0.0, 0.4, 1.0, 1.7];
    let late = [0.2, 0.9, 2.0];
    let r = &mut rng;
    let mut translation = |rng: &mut Lcg, _| rng.vec3(-0.3, 0.3).to_vec();
    let mut rotation = |rng: &mut Lcg, k: usize| {
        // Every other key negated: the same rotation, reached along the shorter arc.
        let q = rng.quat(2.0);
        if k % 2 == 1 { q.map(|c| -c) } else { q }.to_vec()
    };
    let mut scale = |rng: &mut Lcg, _| rng.vec3(0.7, 1.3).to_vec();
    let mut weights2 = |rng: &mut Lcg, _| vec![rng.next(-0.5, 1.0), rng.next(0.0, 1.0)];
    let mut weights1 = |rng: &mut Lcg, _| vec![rng.next(0.0, 1.0)];
    let channels = vec![
        channel(r, ROOT, Property::Rotation, kind, &times, 4, &mut rotation),
        channel(
            r,
            1,
            Property::Translation,
            kind,
            &late,
            3,
            &mut translation,
        ),
        channel(r, 2, Property::Rotation, kind, &late, 4, &mut rotation),
        channel(r, 3, Property::Scale, kind, &times, 3, &mut scale),
        channel(
            r,
            4,
            Property::Translation,
            kind,
            &times,
            3,
            &mut translation,
        ),
        channel(r, 5, Property::Rotation, kind, &times, 4, &mut rotation),
        channel(r, 7, Property::Scale, kind, &late, 3, &mut scale),
        channel(
            r,
            MESH_NODE,
            Property::Weights,
            kind,
            &times,
            2,
            &mut weights2,
        ),
        channel(
            r,
            PROP_NODE,
            Property::Translation,
            kind,
            &late,
            3,
            &mut translation,
        ),
        channel(
            r,
            PROP_NODE,
            Property::Rotation,
            kind,
            &times,
            4,
            &mut rotation,
        ),
        channel(r, PROP_NODE, Property::Scale, kind, &times, 3, &mut scale),
        channel(
            r,
            PROP_NODE,
            Property::Weights,
            kind,
            &late,
            1,
            &mut weights1,
        ),
    ];
    AnimatedMesh {
        triangles,
        uvs: None,
        nodes,
        skins: vec![skin],
        instances: vec![skinned, prop],
        clips: vec![Clip {
            name: "anim".into(),
            channels,
        }],
    }
}

// ---------------------------------------------------------------- comparisons

fn diagonal(points: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::MAX; 3];
    let mut hi = [f64::MIN; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt()
}

/// Poses `model` and compares with the reference: positions within 1e-6 of the bounding box's
/// diagonal, normals within 1e-5.
fn assert_matches(model: &AnimatedMesh, clip: Option<usize>, time: f32) {
    let poser = Poser::new(model.clone()).expect("valid scene");
    let (positions, normals) = poser.pose(clip, time).expect("pose");
    let (want_p, want_n) = reference(model, clip, time);
    let tolerance = 1e-6 * diagonal(&want_p);
    assert_eq!(positions.len(), want_p.len());
    for (v, (got, want)) in positions.iter().zip(&want_p).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= tolerance,
            "clip {clip:?} t={time} vertex {v}: {got:?} vs {want:?} ({d:e} > {tolerance:e})"
        );
    }
    let normals = normals.expect("the scene has normals");
    assert_eq!(normals.len(), want_n.len());
    for (v, (got, want)) in normals.iter().zip(&want_n).enumerate() {
        let d = (0..3)
            .map(|i| (got[i] as f64 - want[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            d <= 1e-5,
            "clip {clip:?} t={time} normal {v}: {got:?} vs {want:?} ({d:e})"
        );
    }
}

/// Before the first key, on keys, between keys, after the last.
const TIMES: [f32; 10] = [-1.0, 0.0, 0.1, 0.2, 0.4, 0.77, 1.0, 1.5, 1.95, 7.0];

#[test]
fn linear_matches_the_spec() {
    let model = scene(Interpolation::Linear);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn step_matches_the_spec() {
    let model = scene(Interpolation::Step);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn cubic_spline_matches_the_spec() {
    let model = scene(Interpolation::CubicSpline);
    for t in TIMES {
        assert_matches(&model, Some(0), t);
    }
}

#[test]
fn rest_pose_matches_the_spec() {
    let mut model = scene(Interpolation::Linear);
    assert_matches(&model, None, 0.0);
    // Node weights override the mesh's default weights.
    model.nodes[MESH_NODE as usize].weights = Some(vec![0.7, 0.4]);
    assert_matches(&model, None, 0.0);
}

#[test]
fn before_the_first_key_and_after_the_last_hold_the_end_poses() {
    let model = scene(Interpolation::CubicSpline);
    let poser = Poser::new(model.clone()).unwrap();
    assert_eq!(poser.duration(0).unwrap(), 2.0);
    // Every channel starts at 0 or 0.2 and ends at 1.7 or 2.0.
    assert_eq!(
        poser.pose(Some(0), -3.0).unwrap(),
        poser.pose(Some(0), 0.0).unwrap()
    );
    assert_eq!(
        poser.pose(Some(0), 2.0).unwrap(),
        poser.pose(Some(0), 100.0).unwrap()
    );
    assert_matches(&model, Some(0), -3.0);
    assert_matches(&model, Some(0), 100.0);
}

/// A skinned node's own transform is ignored; the root above the joints moves the mesh.
#[test]
fn skinned_node_transform_ignored_and_parent_above_joints_applies() {
    let model = scene(Interpolation::Linear);
    let base = Poser::new(model.clone()).unwrap().pose(None, 0.0).unwrap();
    let mut moved = model.clone();
    moved.nodes[MESH_NODE as usize].transform = Transform::default();
    assert_eq!(Poser::new(moved).unwrap().pose(None, 0.0).unwrap(), base);

    let mut shifted = model.clone();
    shifted.nodes[ROOT as usize].transform = Transform::Trs {
        translation: [1.0, 2.0, 3.0],
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
    };
    let (p, _) = Poser::new(shifted.clone())
        .unwrap()
        .pose(None, 0.0)
        .unwrap();
    assert_ne!(p[0], base.0[0]);
    assert_matches(&shifted, None, 0.0);
}

/// Weights are divided by their sum: doubling every weight changes nothing.
#[test]
fn weights_are_normalised_by_their_sum() {
    let model = scene(Interpolation::Linear);
    let mut doubled = model.clone();
    for set in &mut doubled.instances[0].influences {
        for w in &mut set.weights {
            *w = w.map(|x| 2.0 * x);
        }
    }
    let a = Poser::new(model).unwrap().pose(Some(0), 0.6).unwrap();
    let b = Poser::new(doubled.clone())
        .unwrap()
        .pose(Some(0), 0.6)
        .unwrap();
    for (p, q) in a.0.iter().zip(&b.0) {
        for i in 0..3 {
            assert!((p[i] - q[i]).abs() < 1e-5, "{p:?} vs {q:?}");
        }
    }
    assert_matches(&doubled, Some(0), 0.6);
}

/// Eight joints per vertex across two influence sets, each set alone giving another pose.
#[test]
fn two_influence_sets_both_count() {
    let model = scene(Interpolation::Linear);
    let mut first_only = model.clone();
    first_only.instances[0].influences.truncate(1);
    let a = Poser::new(model).unwrap().pose(Some(0), 0.5).unwrap();
    let b = Poser::new(first_only.clone())
        .unwrap()
        .pose(Some(0), 0.5)
        .unwrap();
    assert_ne!(a.0, b.0);
    assert_matches(&first_only, Some(0), 0.5);
}

/// An unskinned instance follows its node's world matrix, through a matrix node.
#[test]
fn unskinned_instance_follows_its_node() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    let first = model.instances[1].first_vertex as usize;
    let (p0, _) = poser.pose(Some(0), 0.2).unwrap();
    let (p1, _) = poser.pose(Some(0), 1.2).unwrap();
    assert_ne!(p0[first], p1[first]);
    assert_matches(&model, Some(0), 0.2);
    assert_matches(&model, Some(0), 1.2);
}

/// Morph targets alone: a node with no skin at the origin, weights animated linearly.
#[test]
fn morph_targets_move_positions_and_normals() {
    let mut rng = Lcg(99);
    let (positions, normals, triangles) = grid(&mut rng, 3, 1.0);
    let n = positions.len();
    let model = AnimatedMesh {
        triangles,
        uvs: None,
        nodes: vec![Node::default()],
        skins: Vec::new(),
        instances: vec![Instance {
            node: 0,
            positions,
            normals: Some(normals),
            targets: vec![
                MorphTarget {
                    positions: (0..n).map(|_| rng.vec3(-0.2, 0.2)).collect(),
                    normals: Some((0..n).map(|_| rng.vec3(-0.3, 0.3)).collect()),
                },
                MorphTarget {
                    positions: (0..n).map(|_| rng.vec3(-0.2, 0.2)).collect(),
                    normals: Some((0..n).map(|_| rng.vec3(-0.3, 0.3)).collect()),
                },
            ],
            default_weights: vec![0.0, 0.0],
            ..Instance::default()
        }],
        clips: vec![Clip {
            name: "morph".into(),
            channels: vec![Channel {
                node: 0,
                property: Property::Weights,
                sampler: Sampler {
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 1.0],
                    values: vec![0.0, 0.0, 1.0, 0.5],
                },
            }],
        }],
    };
    let poser = Poser::new(model.clone()).unwrap();
    let (rest, _) = poser.pose(None, 0.0).unwrap();
    assert_eq!(rest, model.instances[0].positions);
    let (p, _) = poser.pose(Some(0), 0.5).unwrap();
    let t = &model.instances[0].targets;
    for v in 0..n {
        for i in 0..3 {
            let want = model.instances[0].positions[v][i]
                + 0.5 * t[0].positions[v][i]
                + 0.25 * t[1].positions[v][i];
            assert!((p[v][i] - want).abs() < 1e-6);
        }
    }
    for time in [0.25, 0.5, 1.0, 3.0] {
        assert_matches(&model, Some(0), time);
    }
}

#[test]
fn pose_into_mesh_and_clip_lookup() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    assert_eq!(poser.vertex_count(), 34);
    assert!(poser.has_normals());
    assert_eq!(poser.clip_index("anim").unwrap(), 0);
    assert_eq!(poser.clip_index("0").unwrap(), 0);
    let mut p = vec![[0.0; 3]; 34];
    let mut n = vec![[0.0; 3]; 34];
    poser.pose_into(Some(0), 0.3, &mut p, Some(&mut n)).unwrap();
    let (p2, n2) = poser.pose(Some(0), 0.3).unwrap();
    assert_eq!((p.clone(), Some(n.clone())), (p2, n2));
    let mut only = vec![[0.0; 3]; 34];
    poser.pose_into(Some(0), 0.3, &mut only, None).unwrap();
    assert_eq!(only, p);
    let mesh = poser.mesh(Some(0), 0.3).unwrap();
    assert_eq!(mesh.positions(), &p[..]);
    assert_eq!(mesh.triangles(), &model.triangles[..]);

    // Without normals on some instance, poses carry positions only and the mesh computes them.
    let mut bare = model.clone();
    bare.instances[1].normals = None;
    let poser = Poser::new(bare).unwrap();
    assert!(!poser.has_normals());
    let (q, none) = poser.pose(Some(0), 0.3).unwrap();
    assert_eq!((q, none), (p, None));
    assert!(poser.mesh(Some(0), 0.3).unwrap().normals_computed());
    let err = poser
        .pose_into(Some(0), 0.3, &mut only, Some(&mut n))
        .unwrap_err();
    assert_eq!(err, AnimationError::NoNormals);
}

// ---------------------------------------------------------------- refusals

/// `Poser::new` refuses `model` with an error matching `pattern` whose message holds every
/// one of `words`.
macro_rules! refuses {
    ($model:expr, $pattern:pat, $($word:expr),+) => {{
        let err = Poser::new($model).expect_err("bad input accepted");
        assert!(matches!(err, $pattern), "wrong error: {err:?}");
        let message = err.to_string();
        $(assert!(message.contains($word), "{message:?} does not name {:?}", $word);)+
    }};
}

fn base() -> AnimatedMesh {
    scene(Interpolation::Linear)
}

#[test]
fn refuses_joint_index_past_the_skin() {
    let mut m = base();
    m.instances[0].influences[1].joints[5][2] = 8;
    refuses!(
        m,
        AnimationError::JointOutOfRange {
            instance: 0,
            vertex: 5,
            set: 1,
            joint: 8,
            ..
        },
        "instance 0",
        "vertex 5",
        "joint 8"
    );
}

#[test]
fn refuses_nan_negative_and_all_zero_weights() {
    let mut m = base();
    m.instances[0].influences[0].weights[3][1] = f32::NAN;
    refuses!(
        m,
        AnimationError::BadWeight {
            instance: 0,
            vertex: 3,
            ..
        },
        "vertex 3",
        "NaN"
    );
    let mut m = base();
    m.instances[0].influences[1].weights[4][0] = -0.5;
    refuses!(
        m,
        AnimationError::BadWeight {
            instance: 0,
            vertex: 4,
            set: 1,
            ..
        },
        "vertex 4",
        "-0.5"
    );
    let mut m = base();
    for set in &mut m.instances[0].influences {
        set.weights[6] = [0.0; 4];
    }
    refuses!(
        m,
        AnimationError::ZeroWeights {
            instance: 0,
            vertex: 6
        },
        "instance 0",
        "vertex 6"
    );
}

#[test]
fn refuses_bad_inverse_binds() {
    let mut m = base();
    m.skins[0].inverse_binds[2] = [0.0; 16];
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 2,
            ..
        },
        "skin 0",
        "joint 2",
        "singular"
    );
    let mut m = base();
    let mut flat = [1.0; 16]; // rank one
    flat[15] = 1.0;
    m.skins[0].inverse_binds[3] = flat;
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 3,
            ..
        },
        "joint 3",
        "singular"
    );
    let mut m = base();
    m.skins[0].inverse_binds[1][5] = f32::INFINITY;
    refuses!(
        m,
        AnimationError::BadInverseBind {
            skin: 0,
            joint: 1,
            ..
        },
        "joint 1",
        "not finite"
    );
    let mut m = base();
    m.skins[0].inverse_binds.pop();
    refuses!(
        m,
        AnimationError::InverseBindCount {
            skin: 0,
            got: 7,
            expected: 8
        },
        "skin 0"
    );
    let mut m = base();
    m.skins[0].joints[4] = 40;
    refuses!(
        m,
        AnimationError::JointNodeOutOfRange {
            skin: 0,
            joint: 4,
            node: 40,
            ..
        },
        "node 40"
    );
}

#[test]
fn refuses_bad_key_times() {
    let mut m = base();
    m.clips[0].channels[1].sampler.times[2] = 0.9; // equal to the key before
    refuses!(
        m,
        AnimationError::BadKeyTime {
            clip: 0,
            channel: 1,
            key: 2,
            ..
        },
        "clip 0 \"anim\"",
        "channel 1",
        "key time 2",
        "strictly increasing"
    );
    let mut m = base();
    m.clips[0].channels[3].sampler.times[1] = 0.0;
    refuses!(
        m,
        AnimationError::BadKeyTime {
            channel: 3,
            key: 1,
            ..
        },
        "channel 3"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.times[3] = f32::INFINITY;
    refuses!(
        m,
        AnimationError::BadKeyTime {
            channel: 0,
            key: 3,
            ..
        },
        "channel 0",
        "not finite"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.times.clear();
    m.clips[0].channels[0].sampler.values.clear();
    refuses!(
        m,
        AnimationError::NoKeys { channel: 0, .. },
        "channel 0",
        "no keys"
    );
    let mut m = base();
    m.clips[0].channels[2].sampler.values[1] = f32::NAN;
    refuses!(
        m,
        AnimationError::NonFiniteValue {
            channel: 2,
            index: 1,
            ..
        },
        "channel 2",
        "value 1"
    );
}

#[test]
fn refuses_value_counts_other_than_keys_times_components() {
    let mut m = base();
    m.clips[0].channels[1].sampler.values.pop(); // translation, 3 keys × 3
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 1,
            got: 8,
            expected: 9,
            ..
        },
        "channel 1",
        "8 values",
        "expected 9"
    );
    let mut m = base();
    m.clips[0].channels[7].sampler.values.push(0.0); // weights of 2 targets, 4 keys
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 7,
            components: 2,
            expected: 8,
            ..
        },
        "channel 7",
        "2 components"
    );
    let mut m = scene(Interpolation::CubicSpline);
    m.clips[0].channels[0].sampler.values.truncate(16); // rotation: 4 keys × 4 × 3 = 48
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 0,
            expected: 48,
            cubic: true,
            ..
        },
        "CUBICSPLINE",
        "expected 48"
    );
    let mut m = base();
    m.clips[0].channels[0].sampler.interpolation = Interpolation::CubicSpline;
    refuses!(
        m,
        AnimationError::ValueCount {
            channel: 0,
            got: 16,
            expected: 48,
            ..
        },
        "channel 0"
    );
}

#[test]
fn refuses_channels_on_missing_matrix_or_meshless_nodes() {
    let mut m = base();
    m.clips[0].channels[4].node = 12;
    refuses!(
        m,
        AnimationError::ChannelNode {
            clip: 0,
            channel: 4,
            node: 12,
            nodes: 12,
            ..
        },
        "channel 4",
        "node 12"
    );
    let mut m = base();
    m.clips[0].channels[4].node = 11;
    refuses!(
        m,
        AnimationError::ChannelOnMatrix {
            channel: 4,
            node: 11,
            ..
        },
        "node 11",
        "matrix"
    );
    let mut m = base();
    m.clips[0].channels[7].node = 3;
    refuses!(
        m,
        AnimationError::WeightsWithoutMesh {
            channel: 7,
            node: 3,
            ..
        },
        "node 3",
        "no mesh"
    );
}

#[test]
fn refuses_bad_parents() {
    let mut m = base();
    m.nodes[4].parent = Some(99);
    refuses!(
        m,
        AnimationError::ParentOutOfRange {
            node: 4,
            parent: 99,
            ..
        },
        "node 4",
        "node 99"
    );
    let mut m = base();
    m.nodes[1].parent = Some(3); // 1 → 3 → 2 → 1
    refuses!(m, AnimationError::ParentCycle { .. }, "cycle");
    let mut m = base();
    m.nodes[6].parent = Some(6);
    refuses!(m, AnimationError::ParentCycle { node: 6 }, "node 6");
    let mut m = base();
    m.nodes[2].transform = Transform::Trs {
        translation: [0.0, f32::NAN, 0.0],
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
    };
    refuses!(
        m,
        AnimationError::NonFiniteTransform {
            node: 2,
            what: "translation"
        },
        "node 2"
    );
}

#[test]
fn refuses_instance_attribute_lengths_that_disagree() {
    let mut m = base();
    m.instances[0].normals.as_mut().unwrap().pop();
    refuses!(
        m,
        AnimationError::AttributeLength {
            instance: 0,
            got: 24,
            expected: 25,
            ..
        },
        "instance 0",
        "normals",
        "24"
    );
    let mut m = base();
    m.instances[1].targets[0].positions.push([0.0; 3]);
    refuses!(
        m,
        AnimationError::AttributeLength {
            instance: 1,
            got: 10,
            expected: 9,
            ..
        },
        "instance 1",
        "morph target 0's positions"
    );
    let mut m = base();
    m.instances[0].targets[0].normals.as_mut().unwrap().pop();
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "morph target 0's normals"
    );
    let mut m = base();
    m.instances[0].influences[1].joints.pop();
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "influence set 1's joints"
    );
    let mut m = base();
    m.instances[0].influences[0].weights.push([1.0; 4]);
    refuses!(
        m,
        AnimationError::AttributeLength { instance: 0, .. },
        "influence set 0's weights"
    );
    let mut m = base();
    m.instances[0].default_weights.pop();
    refuses!(
        m,
        AnimationError::WeightCount {
            got: 1,
            expected: 2,
            ..
        },
        "instance 0's default weights"
    );
    let mut m = base();
    m.nodes[PROP_NODE as usize].weights = Some(vec![1.0, 2.0]);
    refuses!(
        m,
        AnimationError::WeightCount {
            got: 2,
            expected: 1,
            ..
        },
        "node 10"
    );
    let mut m = base();
    m.instances[1].first_vertex = 3;
    refuses!(
        m,
        AnimationError::InstanceRange {
            instance: 1,
            first_vertex: 3,
            expected: 25
        },
        "instance 1"
    );
    let mut m = base();
    m.instances[1].positions[2][0] = f32::NAN;
    m.instances[1].positions.truncate(9);
    refuses!(
        m,
        AnimationError::NonFiniteAttribute {
            instance: 1,
            vertex: 2,
            ..
        },
        "vertex 2"
    );
    let mut m = base();
    m.uvs = Some(vec![[0.0; 2]; 3]);
    refuses!(
        m,
        AnimationError::UvCount {
            got: 3,
            expected: 34
        },
        "34"
    );
    let mut m = base();
    m.instances[0].influences.clear();
    refuses!(
        m,
        AnimationError::NoInfluences {
            instance: 0,
            skin: 0
        },
        "instance 0"
    );
}

#[test]
fn refuses_skin_and_node_indices_out_of_range() {
    let mut m = base();
    m.instances[0].skin = Some(1);
    refuses!(
        m,
        AnimationError::SkinOutOfRange {
            instance: 0,
            skin: 1,
            skins: 1
        },
        "instance 0",
        "skin 1"
    );
    let mut m = base();
    m.instances[1].node = 50;
    refuses!(
        m,
        AnimationError::InstanceNodeOutOfRange {
            instance: 1,
            node: 50,
            ..
        },
        "node 50"
    );
}

#[test]
fn refuses_triangles_past_the_vertices() {
    let mut m = base();
    m.triangles[7][1] = 34;
    refuses!(
        m,
        AnimationError::TriangleIndex {
            face: 7,
            index: 34,
            count: 34
        },
        "triangle 7",
        "vertex 34"
    );
}

#[test]
fn accepts_valid_but_odd_input() {
    let mut m = base();
    m.skins[0].joints.push(11); // an unused joint
    m.skins[0].inverse_binds.push(IDENTITY.map(|x| x as f32));
    m.instances[1].influences = vec![Influences {
        joints: vec![[0; 4]; 9],
        weights: vec![[0.0; 4]; 9],
    }]; // influences on an unskinned instance: unused
    m.instances[0].influences[0].weights[0] = [0.0, 0.0, 0.0, 3.0]; // sums to 3
    assert!(Poser::new(m.clone()).is_ok());
    assert_matches(&m, Some(0), 0.5);
}

#[test]
fn bad_arguments_leave_the_buffers_untouched() {
    let poser = Poser::new(base()).unwrap();
    let sentinel = [[7.0f32, 8.0, 9.0]; 34];
    let (mut p, mut n) = (sentinel, sentinel);
    let err = poser
        .pose_into(Some(1), 0.0, &mut p, Some(&mut n))
        .unwrap_err();
    assert!(matches!(err, AnimationError::UnknownClip { .. }));
    assert!(err.to_string().contains("\"anim\""), "{err}");
    let err = poser
        .pose_into(Some(0), f32::NAN, &mut p, Some(&mut n))
        .unwrap_err();
    assert!(matches!(err, AnimationError::BadTime(_)));
    let err = poser
        .pose_into(Some(0), f32::INFINITY, &mut p, None)
        .unwrap_err();
    assert!(matches!(err, AnimationError::BadTime(_)));
    let err = poser
        .pose_into(Some(0), 0.5, &mut p, Some(&mut n[..33]))
        .unwrap_err();
    assert!(matches!(
        err,
        AnimationError::BufferLength {
            what: "normals",
            got: 33,
            expected: 34
        }
    ));
    let err = poser
        .pose_into(None, 0.5, &mut p[..30], Some(&mut n))
        .unwrap_err();
    assert!(matches!(
        err,
        AnimationError::BufferLength {
            what: "positions",
            got: 30,
            ..
        }
    ));
    assert_eq!((p, n), (sentinel, sentinel));

    assert!(matches!(
        poser.clip_index("walk"),
        Err(AnimationError::UnknownClip { .. })
    ));
    assert!(matches!(
        poser.clip_index("1"),
        Err(AnimationError::UnknownClip { .. })
    ));
    assert!(poser.duration(3).is_err());
    assert!(poser.mesh(Some(2), 0.0).is_err());
}
