//! PNG1 is G1: along every interior edge of randomly perturbed meshes with random unit normals,
//! the two adjacent patches' unit normals (`Du × Dv`, evaluated in f64) agree to rounding. The
//! same measurement on PN (computed here from Vlachos' formulas, independently of the crate)
//! finds large jumps, so the test can fail.

use glam::DVec3;
use tessella_core::basis::{Basis, CUBIC_ORDER};
use tessella_core::mesh::topology::NO_NEIGHBOR;
use tessella_core::scheme::{png1, png1_nets_f64};
use tessella_core::{samples, Mesh, Topology};

/// Small deterministic generator (xorshift64*), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn vec(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * 2.0 - DVec3::ONE
    }
    fn unit(&mut self) -> DVec3 {
        loop {
            let v = self.vec();
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// `base` with every position moved by up to `jitter` per axis and normals replaced by
/// `normal(rng, exact_normal)`.
fn perturbed(
    base: &Mesh,
    seed: u64,
    jitter: f64,
    normal: impl Fn(&mut Rng, DVec3) -> DVec3,
) -> Mesh {
    let mut rng = Rng(seed);
    let positions: Vec<[f32; 3]> = base
        .positions()
        .iter()
        .map(|p| {
            (DVec3::from(p.map(f64::from)) + jitter * rng.vec())
                .as_vec3()
                .into()
        })
        .collect();
    let smooth = Mesh::new(positions.clone(), None, None, base.triangles().to_vec()).unwrap();
    let normals = smooth
        .normals()
        .iter()
        .map(|n| {
            normal(&mut rng, DVec3::from(n.map(f64::from)))
                .as_vec3()
                .into()
        })
        .collect();
    Mesh::new(positions, Some(normals), None, base.triangles().to_vec()).unwrap()
}

/// Evaluates a patch in f64: `(position, Du, Dv)`.
type Eval<'a> = dyn Fn(usize, [f64; 3]) -> (DVec3, DVec3, DVec3) + 'a;

/// Largest angle (radians) between the two sides' unit normals over `samples` points of every
/// interior edge, and the largest position gap. `oriented = false` measures the angle between
/// tangent planes (normals up to sign).
fn edge_defects(mesh: &Mesh, topo: &Topology, eval: &Eval, oriented: bool) -> (f64, f64, usize) {
    let mut worst = 0.0f64;
    let mut gap = 0.0f64;
    let mut count = 0;
    let ts: Vec<f64> = (1..40)
        .map(|i| i as f64 / 40.0)
        .chain([1e-3, 0.999, 1e-6, 1.0 - 1e-6])
        .collect();
    for f in 0..mesh.face_count() {
        for k in 0..3 {
            let g = topo.neighbors[f][k];
            if g == NO_NEIGHBOR || (g as usize) < f {
                continue;
            }
            let g = g as usize;
            let tf = mesh.triangles()[f];
            let pid = |v: u32| topo.position_ids[v as usize];
            let (a, b) = (pid(tf[k]), pid(tf[(k + 1) % 3]));
            let tg = mesh.triangles()[g];
            let ca = (0..3).find(|&c| pid(tg[c]) == a).unwrap();
            let cb = (0..3).find(|&c| pid(tg[c]) == b).unwrap();
            for &t in &ts {
                let mut lf = [0.0; 3];
                lf[k] = 1.0 - t;
                lf[(k + 1) % 3] = t;
                let mut lg = [0.0; 3];
                lg[ca] = 1.0 - t;
                lg[cb] = t;
                let (pf, duf, dvf) = eval(f, lf);
                let (pg, dug, dvg) = eval(g, lg);
                let nf = duf.cross(dvf).normalize();
                let ng = dug.cross(dvg).normalize();
                let mut angle = nf.cross(ng).length().atan2(nf.dot(ng));
                if !oriented {
                    angle = angle.min(std::f64::consts::PI - angle);
                }
                worst = worst.max(angle);
                gap = gap.max((pf - pg).length());
                count += 1;
            }
        }
    }
    (worst, gap, count)
}

/// PN control points in f64 straight from Vlachos et al. (docs/formulas.md, PN triangles), in `CUBIC_ORDER`.
fn pn_net(p: [DVec3; 3], n: [DVec3; 3]) -> Vec<DVec3> {
    let edge = |i: usize, j: usize| (2.0 * p[i] + p[j] - (p[j] - p[i]).dot(n[i]) * n[i]) / 3.0;
    let e = [
        edge(0, 1),
        edge(1, 0),
        edge(1, 2),
        edge(2, 1),
        edge(2, 0),
        edge(0, 2),
    ];
    let centre = e.iter().sum::<DVec3>() / 4.0 - (p[0] + p[1] + p[2]) / 6.0;
    let mut net = vec![p[0], p[1], p[2]];
    net.extend(e);
    net.push(centre);
    assert_eq!(net.len(), CUBIC_ORDER.len());
    net
}

fn corners(mesh: &Mesh, f: usize) -> ([DVec3; 3], [DVec3; 3]) {
    (
        mesh.corner_positions(f).map(|v| v.as_dvec3()),
        mesh.corner_normals(f).map(|v| v.as_dvec3()),
    )
}

fn png1_defects(mesh: &Mesh, oriented: bool) -> (f64, f64, usize) {
    let topo = mesh.topology();
    let nets = png1_nets_f64(mesh, &topo, None);
    let eval = |f: usize, l: [f64; 3]| png1::eval_f64(&nets[f], l);
    edge_defects(mesh, &topo, &eval, oriented)
}

fn pn_defects(mesh: &Mesh, oriented: bool) -> (f64, f64, usize) {
    let topo = mesh.topology();
    let nets: Vec<Vec<DVec3>> = (0..mesh.face_count())
        .map(|f| {
            let (p, n) = corners(mesh, f);
            pn_net(p, n)
        })
        .collect();
    let eval = |f: usize, l: [f64; 3]| {
        let w = Basis::Cubic.weights(l);
        let mut out = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (k, c) in nets[f].iter().enumerate() {
            out.0 += w.value[k] * *c;
            out.1 += w.du[k] * *c;
            out.2 += w.dv[k] * *c;
        }
        out
    };
    edge_defects(mesh, &topo, &eval, oriented)
}

/// Normals tilted from the smooth ones by a random vector of length up to `amount`.
fn tilted(amount: f64) -> impl Fn(&mut Rng, DVec3) -> DVec3 {
    move |rng, n| (n + amount * rng.next() * rng.unit()).normalize()
}

#[test]
fn png1_is_g1_on_perturbed_meshes_and_pn_is_not() {
    let bases = [
        samples::icosphere(1),
        samples::torus(1.0, 0.4, 10, 7),
        samples::tetrahedron(),
    ];
    for (i, base) in bases.iter().enumerate() {
        for seed in 1..=3u64 {
            // The coarse tetrahedron folds (its patches turn over) under large tilts; the
            // unoriented test below covers folded patches.
            let tilt = if i == 2 { 0.25 } else { 0.7 };
            let mesh = perturbed(base, seed * 7919 + i as u64, 0.05, tilted(tilt));
            let (png1, gap, count) = png1_defects(&mesh, true);
            assert!(count > 1000 || i == 2, "too few samples: {count}");
            assert!(
                png1 <= 1e-9,
                "mesh {i} seed {seed}: PNG1 normal jump {png1:e} rad"
            );
            assert!(gap <= 1e-12, "mesh {i} seed {seed}: PNG1 gap {gap:e}");
            let (pn, pn_gap, _) = pn_defects(&mesh, true);
            eprintln!(
                "mesh {i} seed {seed}: PNG1 {png1:.2e} rad, PN {pn:.2e} rad over {count} points"
            );
            assert!(
                pn > 1e-2,
                "mesh {i} seed {seed}: PN normal jump only {pn:e} rad"
            );
            assert!(pn_gap <= 1e-12, "PN is C0: gap {pn_gap:e}");
        }
    }
}

#[test]
fn png1_tangent_planes_agree_with_uniformly_random_normals() {
    // Normals drawn uniformly on the sphere: patches may fold, but the tangent planes of the two
    // sides still coincide along every edge.
    let base = samples::icosphere(1);
    for seed in 1..=3u64 {
        let mesh = perturbed(&base, seed, 0.1, |rng, n| {
            let r = rng.unit();
            // Keep the normal off the exact tangent plane, where projections degenerate.
            if r.dot(n).abs() < 0.05 {
                (r + 0.1 * n).normalize()
            } else {
                r
            }
        });
        let (png1, gap, _) = png1_defects(&mesh, false);
        assert!(
            png1 <= 1e-9,
            "seed {seed}: PNG1 tangent planes differ by {png1:e} rad"
        );
        assert!(gap <= 1e-12);
        let (pn, _, _) = pn_defects(&mesh, false);
        assert!(
            pn > 0.1,
            "seed {seed}: PN tangent-plane jump only {pn:e} rad"
        );
    }
}
