//! The animated test scene and an independent f64 evaluation of the glTF 2.0 specification
//! (own quaternions, slerp, Hermite splines, 4×4 products and inverses), shared by the core's
//! posing tests (`tests/animation.rs`) and tessella-gpu's skinning tests.

// The reference spells the specification's formulas out with indices and plain tuples.
#![allow(clippy::needless_range_loop, clippy::type_complexity, dead_code)]

use tessella_core::animation::{
    AnimatedMesh, Channel, Clip, Influences, Instance, Interpolation, MorphTarget, Node, Property,
    Sampler, Skin, Transform,
};

// ---------------------------------------------------------------- f64 reference of the spec

/// Column-major 4×4: `m[col * 4 + row]`.
pub type M4 = [f64; 16];

pub const IDENTITY: M4 = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

pub fn mul(a: &M4, b: &M4) -> M4 {
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
pub fn inverse(m: &M4) -> M4 {
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

pub fn transform_point(m: &M4, p: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (row, o) in out.iter_mut().enumerate() {
        *o = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
    }
    out
}

/// `inverse(M3)ᵀ · n`, normalised, for `M3` the upper 3×3 of `m`.
pub fn transform_normal(m: &M4, n: [f64; 3]) -> [f64; 3] {
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

pub fn normalize3(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

pub fn normalize4(q: [f64; 4]) -> [f64; 4] {
    let l = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    q.map(|c| c / l)
}

/// T · R · S with R from the unit quaternion `[x, y, z, w]`.
pub fn trs(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> M4 {
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

pub fn slerp(a: [f64; 4], b: [f64; 4], s: f64) -> [f64; 4] {
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
pub fn sample(sampler: &Sampler, time: f32, c: usize, rotation: bool) -> Vec<f64> {
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

pub type Pose64 = (Vec<[f64; 3]>, Vec<[f64; 3]>);

/// The pose by the specification, in f64; normals only for instances that have them.
pub fn reference(model: &AnimatedMesh, clip: Option<usize>, time: f32) -> Pose64 {
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
                other => panic!("the reference evaluator has no {other:?}"),
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
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in `lo..hi`.
    pub fn next(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
    }
    pub fn vec3(&mut self, lo: f32, hi: f32) -> [f32; 3] {
        [self.next(lo, hi), self.next(lo, hi), self.next(lo, hi)]
    }
    /// A unit quaternion of a rotation by up to `max` radians about a random axis.
    pub fn quat(&mut self, max: f32) -> [f32; 4] {
        let axis = self.vec3(-1.0, 1.0);
        let l = axis.iter().map(|c| c * c).sum::<f32>().sqrt();
        let angle = self.next(-max, max);
        let (s, c) = (angle / 2.0).sin_cos();
        [axis[0] / l * s, axis[1] / l * s, axis[2] / l * s, c]
    }
}

pub fn trs_node(parent: Option<u32>, t: [f32; 3], r: [f32; 4], s: [f32; 3]) -> Node {
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
pub fn grid(rng: &mut Lcg, n: usize, size: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[u32; 3]>) {
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
pub fn channel(
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

pub const ROOT: u32 = 0;
pub const MESH_NODE: u32 = 9;
pub const PROP_NODE: u32 = 10;

/// The test scene: a root above eight joints (a chain and branches), a skinned grid with two
/// influence sets (weights not summing to one, some zero) and two morph targets, and an
/// unskinned grid under a matrix node; one clip of `kind` animating translation, rotation,
/// scale and weights.
pub fn scene(kind: Interpolation) -> AnimatedMesh {
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
