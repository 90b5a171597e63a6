//! The traced formulas are the CPU's formulas: the recorded tape, evaluated in f64, gives the
//! CPU's weights (so folding and selections changed nothing but the zero terms), and the
//! printed functions have the shape the shaders call.

use super::trace::{trace, Expr, Node, Tape, Traced, UExpr, UOp};
use super::*;
use crate::basis::png1::PNG1_LEN;

/// The tape's values in f64 with the inputs `l.x`, `l.y`, `l.z` (or `a`, `b`) set.
fn run(tape: &Tape, inputs: &[(&str, f64)]) -> Vec<f64> {
    run_with(tape, inputs, |name, _| panic!("no function {name} here"))
}

/// The tape's values (`u32` ones exactly, as f64) with named inputs and the including
/// shader's functions given by `call`.
fn run_with(tape: &Tape, inputs: &[(&str, f64)], call: impl Fn(&str, &[u32]) -> u32) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::with_capacity(tape.nodes.len());
    for node in &tape.nodes {
        let x = |e: &Expr| v[e.index()];
        let u = |e: &UExpr| v[e.index()] as u32;
        let input = |name: &String| inputs.iter().find(|(n, _)| n == name).expect("an input").1;
        let value = match node {
            Node::Input(name) | Node::UInput(name) => input(name),
            Node::Const(bits) => f64::from_bits(*bits),
            Node::Add(a, b) => x(a) + x(b),
            Node::Sub(a, b) => x(a) - x(b),
            Node::Mul(a, b) => x(a) * x(b),
            Node::Div(a, b) => x(a) / x(b),
            Node::Neg(a) => -x(a),
            Node::Sqrt(a) => x(a).sqrt(),
            Node::SelectPositiveFinite { test, yes, no } => {
                if x(test).is_finite() && x(test) > 0.0 {
                    x(yes)
                } else {
                    x(no)
                }
            }
            Node::SelectNonZero {
                test,
                nonzero,
                zero,
            } => {
                if x(test) != 0.0 {
                    x(nonzero)
                } else {
                    x(zero)
                }
            }
            Node::UConst(c) => f64::from(*c),
            Node::UBin(op, a, b) => f64::from(match op {
                UOp::Add => u(a).wrapping_add(u(b)),
                UOp::Sub => u(a).wrapping_sub(u(b)),
                UOp::Mul => u(a).wrapping_mul(u(b)),
                UOp::Rem => u(a) % u(b),
                UOp::Div => u(a) / u(b),
                UOp::And => u(a) & u(b),
            }),
            Node::UShr(a, bits) => f64::from(u(a) >> bits),
            Node::USelect { cmp, a, b, yes, no } => {
                f64::from(if cmp.holds(u(a), u(b)) { u(yes) } else { u(no) })
            }
            Node::UCall(name, args) => {
                let args: Vec<u32> = args.iter().map(u).collect();
                f64::from(call(name, &args))
            }
            Node::FromWord(a) => f64::from(u(a)),
            Node::Pick { cmp, a, b, yes, no } => {
                if cmp.holds(u(a), u(b)) {
                    x(yes)
                } else {
                    x(no)
                }
            }
            // A comparison rounds nothing: f64 evaluates it as f32 would.
            Node::PickGt { a, b, yes, no } => {
                if x(a) > x(b) {
                    x(yes)
                } else {
                    x(no)
                }
            }
            Node::Floor(_)
            | Node::Sin(_)
            | Node::IntWord(_)
            | Node::WordIfEq { .. }
            | Node::Call(..) => {
                panic!("noise nodes are evaluated by run_f32")
            }
        };
        v.push(value);
    }
    v
}

/// The tape's values computed as the shader computes them, every `f32` operation rounded to
/// `f32` (`u32` ones exactly), with the including shader's `u32` and `f32` functions.
fn run_f32(
    tape: &Tape,
    inputs: &[(&str, f32)],
    ucall: impl Fn(&str, &[u32]) -> u32,
    fcall: impl Fn(&str, &[u32]) -> f32,
) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::with_capacity(tape.nodes.len());
    for node in &tape.nodes {
        let x = |e: &Expr| v[e.index()] as f32;
        let u = |e: &UExpr| v[e.index()] as u32;
        let input = |name: &String| inputs.iter().find(|(n, _)| n == name).expect("an input").1;
        let value = match node {
            Node::Input(name) | Node::UInput(name) => f64::from(input(name)),
            Node::Const(bits) => f64::from(f64::from_bits(*bits) as f32),
            Node::Add(a, b) => f64::from(x(a) + x(b)),
            Node::Sub(a, b) => f64::from(x(a) - x(b)),
            Node::Mul(a, b) => f64::from(x(a) * x(b)),
            Node::Div(a, b) => f64::from(x(a) / x(b)),
            Node::Neg(a) => f64::from(-x(a)),
            Node::Sqrt(a) => f64::from(x(a).sqrt()),
            Node::SelectPositiveFinite { test, yes, no } => {
                let t = x(test);
                f64::from(if t.is_finite() && t > 0.0 {
                    x(yes)
                } else {
                    x(no)
                })
            }
            Node::SelectNonZero {
                test,
                nonzero,
                zero,
            } => f64::from(if x(test) != 0.0 { x(nonzero) } else { x(zero) }),
            Node::Floor(a) => f64::from(x(a).floor()),
            Node::Sin(a) => f64::from(x(a).sin()),
            Node::IntWord(a) => f64::from(x(a) as i32 as u32),
            Node::FromWord(a) => f64::from(u(a) as f32),
            Node::Pick { cmp, a, b, yes, no } => {
                f64::from(if cmp.holds(u(a), u(b)) { x(yes) } else { x(no) })
            }
            Node::PickGt { a, b, yes, no } => f64::from(if x(a) > x(b) { x(yes) } else { x(no) }),
            Node::WordIfEq { a, b, yes, no } => {
                f64::from(if x(a) == x(b) { u(yes) } else { u(no) })
            }
            Node::UConst(c) => f64::from(*c),
            Node::UBin(op, a, b) => f64::from(match op {
                UOp::Add => u(a).wrapping_add(u(b)),
                UOp::Sub => u(a).wrapping_sub(u(b)),
                UOp::Mul => u(a).wrapping_mul(u(b)),
                UOp::Rem => u(a) % u(b),
                UOp::Div => u(a) / u(b),
                UOp::And => u(a) & u(b),
            }),
            Node::UShr(a, bits) => f64::from(u(a) >> bits),
            Node::USelect { cmp, a, b, yes, no } => {
                f64::from(if cmp.holds(u(a), u(b)) { u(yes) } else { u(no) })
            }
            Node::UCall(name, args) => {
                f64::from(ucall(name, &args.iter().map(u).collect::<Vec<_>>()))
            }
            Node::Call(name, args) => {
                f64::from(fcall(name, &args.iter().map(u).collect::<Vec<_>>()))
            }
        };
        v.push(value);
    }
    v
}

/// A `u32` function of the including shader, for a trace that calls none.
fn no_ucall(name: &str, _: &[u32]) -> u32 {
    panic!("no function {name}")
}

/// An `f32` function of the including shader, for a trace that calls none.
fn no_fcall(name: &str, _: &[u32]) -> f32 {
    panic!("no function {name}")
}

#[test]
fn traced_displacement_offsets_give_the_cpus_bits() {
    use crate::displace::{height_map_of, perlin, perlin_of, permutation, sine_of, HeightMap};
    let perm = permutation(7);
    let p = || [Expr::input("p.x"), Expr::input("p.y"), Expr::input("p.z")];
    let (tape, out) = trace(|| perlin_of(|i| UExpr::call("tessella_perm", &[i]), p()));
    let read = |name: &str, args: &[u32]| {
        assert_eq!(name, "tessella_perm");
        assert!(
            args[0] < 512,
            "a permutation index {} past the table",
            args[0]
        );
        perm[args[0] as usize]
    };
    // Lattice points, negative cells and large coordinates, where the integer part matters.
    let mut checked = 0;
    for i in -40..40 {
        let q = [
            i as f32 * 0.37 + 0.01,
            -(i as f32) * 1.91,
            i as f32 * 13.3 - 0.5,
        ];
        let v = run_f32(
            &tape,
            &[("p.x", q[0]), ("p.y", q[1]), ("p.z", q[2])],
            read,
            no_fcall,
        );
        let got = v[out.index()] as f32;
        assert_eq!(got.to_bits(), perlin(&perm, q).to_bits(), "{q:?}");
        checked += 1;
    }
    assert_eq!(checked, 80);
    let map = HeightMap::new(3, 2, vec![0.0, 0.5, 1.0, 0.25, -0.75, 2.0]).unwrap();
    let (tape, out) = trace(|| {
        height_map_of(
            |x, y| Expr::call("tessella_height_texel", &[x, y]),
            [Expr::input("size.x"), Expr::input("size.y")],
            [Expr::input("uv.x"), Expr::input("uv.y")],
        )
    });
    let texel = |name: &str, args: &[u32]| {
        assert_eq!(name, "tessella_height_texel");
        // The CPU's own repeating read, through its public sample at the texel's centre.
        let (x, y) = (args[0] as i32, args[1] as i32);
        let (w, h) = (3, 2);
        let (xx, yy) = (x.rem_euclid(w), y.rem_euclid(h));
        map.sample([
            (xx as f32 + 0.5) / w as f32,
            1.0 - (yy as f32 + 0.5) / h as f32,
        ])
    };
    for uv in [
        [0.1f32, 0.2],
        [0.9, 0.95],
        [-0.3, 1.7],
        [0.5, 0.5],
        [2.25, -1.1],
    ] {
        let inputs = [
            ("uv.x", uv[0]),
            ("uv.y", uv[1]),
            ("size.x", 3.0),
            ("size.y", 2.0),
        ];
        let v = run_f32(&tape, &inputs, no_ucall, texel);
        assert_eq!(
            (v[out.index()] as f32).to_bits(),
            map.sample(uv).to_bits(),
            "{uv:?}"
        );
    }
    let (tape, out) = trace(|| sine_of(Expr::input("a"), Expr::input("f"), p()));
    for q in [[0.3f32, -0.4, 1.2], [0.0, 0.0, 0.0], [5.0, 6.0, -7.0]] {
        let inputs = [
            ("a", 0.05f32),
            ("f", 25.0),
            ("p.x", q[0]),
            ("p.y", q[1]),
            ("p.z", q[2]),
        ];
        let v = run_f32(&tape, &inputs, no_ucall, no_fcall);
        assert_eq!(
            (v[out.index()] as f32).to_bits(),
            sine_of(0.05f32, 25.0, q).to_bits()
        );
    }
    let frames = [
        [[0.0f32, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        // Means that cancel at the midpoint of edge 0: the normal there.
        [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    ];
    let (tape, out) = trace(|| {
        let v3 = |name: &str| ["x", "y", "z"].map(|c| Expr::input(&format!("{name}.{c}")));
        crate::displace::direction_of(
            UExpr::input("mask"),
            [v3("m1"), v3("m2"), v3("m3")],
            v3("l"),
            v3("n"),
        )
    });
    let pattern = crate::Pattern::uniform(4);
    let mut split_moves = 0;
    for means in frames {
        for mask in 0u8..64 {
            let frame = crate::displace::FaceFrame { means, mask };
            for b in &pattern.points {
                let l = b.map(|x| x as f32);
                let n = [0.0f32, 0.6, 0.8];
                let mut inputs = vec![("mask", f32::from(mask))];
                let names = ["m1", "m2", "m3", "l", "n"];
                let vectors = [means[0], means[1], means[2], l, n];
                let keys: Vec<String> = names
                    .iter()
                    .flat_map(|v| ["x", "y", "z"].map(|c| format!("{v}.{c}")))
                    .collect();
                for (k, x) in keys.iter().zip(vectors.iter().flatten()) {
                    inputs.push((k.as_str(), *x));
                }
                let v = run_f32(&tape, &inputs, no_ucall, no_fcall);
                let got = out.map(|e| (v[e.index()] as f32).to_bits());
                let want = frame.direction(l, n);
                assert_eq!(got, want.map(f32::to_bits), "mask {mask} l {l:?}");
                split_moves += usize::from(want != n);
            }
        }
    }
    assert!(
        split_moves > 100,
        "the cases move split points ({split_moves})"
    );
    let wgsl = displace_wgsl();
    for head in [
        "fn tessella_perlin(p: vec3<f32>) -> f32 {",
        "fn tessella_height_map(uv: vec2<f32>, size: vec2<f32>) -> f32 {",
        "fn tessella_sine(a: f32, f: f32, p: vec3<f32>) -> f32 {",
    ] {
        assert!(wgsl.contains(head), "{head} missing from\n{wgsl}");
    }
}

/// Points inside, on the edges and at the corners (where PNG1's selections matter).
const POINTS: [[f64; 3]; 7] = [
    [0.2, 0.3, 0.5],
    [0.6, 0.3, 0.1],
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.25, 0.75],
    [1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0],
];

#[test]
fn traced_basis_weights_evaluate_to_the_cpu_weights() {
    for basis in [Basis::Cubic, Basis::Png1] {
        let (tape, w) = trace(|| basis.weights_of(traced_l()));
        for l in POINTS {
            let v = run(&tape, &[("l.x", l[0]), ("l.y", l[1]), ("l.z", l[2])]);
            let cpu = basis.weights(l);
            for (k, d) in w.iter().enumerate() {
                let got = [v[d.v.index()], v[d.du.index()], v[d.dv.index()]];
                let want = [cpu.value[k], cpu.du[k], cpu.dv[k]];
                for (g, e) in got.iter().zip(want) {
                    assert!(g.is_finite(), "{basis:?} {l:?} k={k}: {g}");
                    assert!((g - e).abs() <= 1e-14, "{basis:?} {l:?} k={k}: {g} vs {e}");
                }
            }
        }
    }
}

#[test]
fn traced_normal_and_edge_weights_evaluate_to_the_cpu_weights() {
    let (tape, w) = trace(|| normal_weights(traced_l()));
    for l in POINTS {
        let v = run(&tape, &[("l.x", l[0]), ("l.y", l[1]), ("l.z", l[2])]);
        let got: Vec<f64> = w.iter().map(|e| v[e.index()]).collect();
        assert_eq!(got, normal_weights(l).to_vec(), "{l:?}");
    }
    let (tape, p2) = trace(|| shape_functions(traced_l()));
    for l in POINTS {
        let v = run(&tape, &[("l.x", l[0]), ("l.y", l[1]), ("l.z", l[2])]);
        assert_eq!(p2.map(|e| v[e.index()]), shape_functions(l), "{l:?}");
    }
    let (tape, (value, normal)) = trace(|| EdgeWeights::new_of(Expr::input("a"), Expr::input("b")));
    for (a, b) in [(0.25, 0.75), (1.0, 0.0), (0.6, 0.4)] {
        let v = run(&tape, &[("a", a), ("b", b)]);
        let (cpu_value, cpu_normal) = EdgeWeights::new_f64(a, b);
        assert_eq!(value.map(|e| v[e.index()]), cpu_value, "({a}, {b})");
        assert_eq!(normal.map(|e| v[e.index()]), cpu_normal, "({a}, {b})");
    }
}

#[test]
fn printed_functions_declare_only_tessella_names_and_cover_every_weight() {
    let wgsl = weights(Lang::Wgsl, Basis::Png1);
    assert_eq!(wgsl.matches("vec3<f32>(").count(), PNG1_LEN, "{wgsl}");
    let glsl = weights(Lang::Glsl, Basis::Cubic);
    for k in 0..10 {
        assert!(glsl.contains(&format!("    w[{k}] = vec3(")), "{glsl}");
    }
    assert!(glsl.starts_with("void tessella_cubic_weights(vec3 l, out vec3 w[21])"));
    let sum = patch_sum_wgsl(Basis::Cubic);
    // b300's weight is l1³ and its Du, Dv are -3 l1²: every control point enters each sum.
    for field in ["p", "du", "dv"] {
        let line = sum
            .lines()
            .find(|l| l.starts_with(&format!("    s.{field} = ")))
            .expect("a sum");
        let terms = line.matches(" * c").count();
        assert!(terms >= 7, "{field}: {line}");
    }
    let p2 = p2_weights_wgsl();
    assert_eq!(p2.matches("array<f32, 6>").count(), 2, "{p2}");
    let normal = normal_net_sum_wgsl();
    assert!(normal.starts_with("fn tessella_normal_net_sum(face: u32, l: vec3<f32>) -> vec3<f32>"));
    // Six entries summed (the weights' values are the traced tape's, checked above), with
    // temporaries apart from the patch sum's.
    let returned = normal.lines().find(|l| l.starts_with("    n = ")).unwrap();
    assert_eq!(returned.matches(" * m").count(), 6, "{normal}");
    assert!(normal.contains("    let tn3 = l.x * l.x;\n"), "{normal}");
    for text in [
        wgsl,
        glsl,
        sum,
        edge_weights_wgsl(),
        p2,
        normal,
        tessellator_point(Lang::Wgsl),
        tessellator_point(Lang::Glsl),
        canonical_edge_point(
            Lang::Glsl,
            &EdgeSources {
                context: ("", ""),
                net_normals: "true",
            },
        ),
    ] {
        for line in text.lines() {
            for keyword in ["fn ", "struct ", "void ", "bool "] {
                if let Some(rest) = line.strip_prefix(keyword) {
                    assert!(
                        rest.starts_with("tessella_") || rest.starts_with("Tessella"),
                        "{line}"
                    );
                }
            }
        }
    }
}

#[test]
fn traced_net_builders_evaluate_to_the_cpu_nets() {
    use crate::scheme::{flat, normal_net, phong, pn, pn_aen, Corners};
    use glam::Vec3;
    let corners = [
        Corners {
            p: [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.1, 0.2),
                Vec3::new(0.2, 0.9, -0.1),
            ],
            n: [
                Vec3::new(-0.3, -0.2, 0.93).normalize(),
                Vec3::new(0.4, 0.1, 0.9).normalize(),
                Vec3::new(0.0, 0.5, 0.87).normalize(),
            ],
        },
        // A collapsed edge (P1 = P2) with opposite normals there: the quadratic normal net's
        // division by |P2 - P1|² and its vanishing sum take the fallbacks.
        Corners {
            p: [Vec3::ZERO, Vec3::ZERO, Vec3::X],
            n: [Vec3::Z, -Vec3::Z, Vec3::Y],
        },
    ];
    // PN-AEN's other sides' normals: turned away from the corners' own on the first triangle;
    // the own corner normals (no neighbours) on the second, where PN-AEN is PN.
    let across = [
        [
            Vec3::new(0.3, -0.2, 0.93).normalize(),
            Vec3::new(-0.4, 0.3, 0.86).normalize(),
            Vec3::new(0.1, 0.1, 0.99).normalize(),
            Vec3::new(0.5, 0.5, 0.7).normalize(),
            Vec3::Z,
            Vec3::new(-0.6, 0.0, 0.8),
        ],
        [Vec3::Z, -Vec3::Z, -Vec3::Z, Vec3::Y, Vec3::Y, Vec3::Z],
    ];
    let alpha = 0.75f32;
    for builder in NetBuilder::ALL {
        let (tape, net) = trace(|| {
            let NetInputs { p, n, alpha, m } = traced_corners();
            builder.build(p, n, alpha, m)
        });
        for (c, m) in corners.iter().zip(&across) {
            let mut inputs: Vec<(String, f64)> = vec![("alpha".into(), f64::from(alpha))];
            for (array, v) in [("p", &c.p[..]), ("n", &c.n[..]), ("m", &m[..])] {
                for (i, x) in v.iter().enumerate() {
                    for (axis, value) in ["x", "y", "z"].iter().zip(x.to_array()) {
                        inputs.push((format!("{array}[{i}].{axis}"), f64::from(value)));
                    }
                }
            }
            let named: Vec<(&str, f64)> = inputs.iter().map(|(n, v)| (n.as_str(), *v)).collect();
            let v = run(&tape, &named);
            let cpu: Vec<Vec3> = match builder {
                NetBuilder::FlatPoints => flat::control_points(c).to_vec(),
                NetBuilder::PhongPoints => phong::control_points(c, alpha).to_vec(),
                NetBuilder::PnPoints => pn::control_points(c).to_vec(),
                NetBuilder::LinearNormals => normal_net::linear(c).to_vec(),
                NetBuilder::QuadraticNormals => normal_net::quadratic(c).to_vec(),
                NetBuilder::PnAenPoints => {
                    let aen = pn_aen::points(c.p.map(V3::from), c.n.map(V3::from), m.map(V3::from))
                        .map(Vec3::from);
                    // Own normals on every edge: PN's net, bit for bit.
                    let pn_net = pn::control_points(c);
                    assert_eq!(
                        aen == pn_net,
                        m[0] == c.n[0],
                        "PN-AEN is PN only without other sides"
                    );
                    aen.to_vec()
                }
            };
            assert_eq!(net.len(), cpu.len(), "{builder:?}");
            for (k, (t, want)) in net.iter().zip(&cpu).enumerate() {
                let got = Vec3::new(
                    v[t.x.index()] as f32,
                    v[t.y.index()] as f32,
                    v[t.z.index()] as f32,
                );
                assert!(
                    (got - *want).length() <= 1e-6 * (1.0 + want.length()),
                    "{builder:?} k={k}: {got} vs {want}"
                );
            }
        }
        let glsl = net_builder(Lang::Glsl, builder);
        assert!(glsl.starts_with(&format!(
            "void {}(vec3 p[3], vec3 n[3]",
            builder.function_name()
        )));
        let wgsl = net_builder(Lang::Wgsl, builder);
        assert!(wgsl.starts_with(&format!(
            "fn {}(p: array<vec3<f32>, 3>",
            builder.function_name()
        )));
        if builder == NetBuilder::PnAenPoints {
            assert!(wgsl.contains("m: array<vec3<f32>, 6>) -> array<vec3<f32>, 10>"));
            assert!(glsl.contains("vec3 m[6], out vec3 c[10])"), "{glsl}");
            // Every other side's normal enters the net.
            for i in 0..6 {
                assert!(wgsl.contains(&format!("m[{i}].x")), "m[{i}] unused: {wgsl}");
            }
        }
    }
}

#[test]
fn traced_tessellator_placement_evaluates_to_the_cpu_placement() {
    use crate::tessellator::parts::{locate_of, FaceRulers, NO_EDGE};
    use crate::tessellator::points::RULER_WORDS;
    use crate::tessellator::{process_levels, Partitioning, TessLevels};
    let (tape, out) = traced_locate();
    let mut checked = 0;
    for (spacing, outer, inner) in [
        (Partitioning::FractionalOdd, [3.3, 5.0, 1.7], 4.6),
        (Partitioning::FractionalEven, [2.0, 7.5, 4.2], 6.1),
        (Partitioning::Equal, [4.0, 4.0, 9.0], 3.0),
    ] {
        let levels = TessLevels { outer, inner };
        let p = process_levels(spacing, levels).expect("levels that draw");
        let rulers = FaceRulers::new(&p);
        let words = rulers.words();
        // Every code a part can name: rings, sides, indices along a side.
        for ring in 0..=rulers.inner_points / 2 {
            for side in 0..3u32 {
                for i in 0..rulers.inner_points.max(rulers.outer_points[side as usize]) {
                    let code = ring << 10 | side << 8 | i;
                    for side_offset in 0..3 {
                        let v = run_with(
                            &tape,
                            &[
                                ("rec", 0.0),
                                ("code", f64::from(code)),
                                ("side_offset", f64::from(side_offset)),
                            ],
                            |name, args| {
                                assert_eq!(name, "tessella_ruler_word");
                                words[RULER_WORDS * args[1] as usize + args[2] as usize]
                            },
                        );
                        let got = out.map(|e| v[e.index()] as u32);
                        let cpu = locate_of(
                            |r: u32, k| words[RULER_WORDS * r as usize + k],
                            code,
                            side_offset,
                        );
                        assert_eq!(got, cpu, "{spacing:?} code {code:#x} side {side_offset}");
                        assert_eq!((got[0], got[1]), rulers.locate(code, side_offset));
                        if ring > 0 {
                            assert_eq!(got[2], NO_EDGE);
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 300, "{checked}");
    let wgsl = locate_wgsl();
    assert!(
        wgsl.starts_with("fn tessella_locate(rec: u32, code: u32, side_offset: u32) -> vec3<u32>")
    );
    assert!(wgsl.contains("tessella_ruler_word(rec, "), "{wgsl}");
    // The GLSL is the same trace: as many operations, GLSL declarations.
    let glsl = locate_glsl();
    assert!(glsl.starts_with("uvec3 tessella_locate(uint rec, uint code, uint side_offset)"));
    assert_eq!(
        glsl.matches("    uint t").count(),
        wgsl.matches("    let t").count()
    );
    assert!(
        !glsl.contains("let ") && !glsl.contains("select("),
        "{glsl}"
    );
    let edge = edge_weights_glsl();
    assert!(edge.starts_with(
        "void tessella_edge_weights(float a, float b, out vec4 value, out vec3 normal)"
    ));
    assert_eq!(
        edge.matches("    float t").count(),
        edge_weights_wgsl().matches("    let t").count()
    );
}

/// The traced skin normal, run as a shader runs it (every operation in `f32`), gives the bits
/// of `animation::skin_normal_of` in `f32` (which the CPU pose's glam normal equals bit for
/// bit: `animation::deform`'s tests): matrices with either determinant sign, singular ones,
/// zero normals.
#[test]
fn traced_skin_normal_gives_the_cpus_bits() {
    use crate::animation::skin_normal_of;
    let (tape, out) = trace(|| {
        let m = [0, 1, 2].map(|c| ["x", "y", "z"].map(|x| Expr::input(&format!("m[{c}].{x}"))));
        skin_normal_of(m, ["n.x", "n.y", "n.z"].map(Expr::input))
    });
    let none = |name: &str, _: &[u32]| -> u32 { panic!("no function {name}") };
    let fnone = |name: &str, _: &[u32]| -> f32 { panic!("no function {name}") };
    let mut state = 3u32;
    let mut next = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    };
    for case in 0..2000 {
        let mut m: [[f32; 3]; 3] = std::array::from_fn(|_| [next(), next(), next()]);
        if case % 5 == 0 {
            m[1] = m[0];
        }
        let n = if case % 9 == 0 {
            [0.0; 3]
        } else {
            [next(), next(), next()]
        };
        let mut inputs: Vec<(String, f32)> = Vec::new();
        for (c, col) in m.iter().enumerate() {
            for (x, v) in ["x", "y", "z"].iter().zip(col) {
                inputs.push((format!("m[{c}].{x}"), *v));
            }
        }
        for (x, v) in ["n.x", "n.y", "n.z"].iter().zip(n) {
            inputs.push((x.to_string(), v));
        }
        let inputs: Vec<(&str, f32)> = inputs.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let v = run_f32(&tape, &inputs, none, fnone);
        let got = out.map(|e| (v[e.index()] as f32).to_bits());
        assert_eq!(got, skin_normal_of(m, n).map(f32::to_bits), "{m:?} {n:?}");
    }
    let wgsl = skin_normal(Lang::Wgsl);
    assert!(wgsl.starts_with("fn tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>"));
    assert!(wgsl.contains("sqrt("), "{wgsl}");
}

#[test]
fn the_gpu_builds_the_nets_of_flat_phong_pn_and_pn_aen_with_the_mode_s_normal_net() {
    use crate::Scheme;
    let cases = [
        (Scheme::Flat, Some(NetBuilder::FlatPoints)),
        (Scheme::PHONG, Some(NetBuilder::PhongPoints)),
        (Scheme::Pn, Some(NetBuilder::PnPoints)),
        (Scheme::PnAen, Some(NetBuilder::PnAenPoints)),
        (Scheme::Png1, None),
    ];
    for (scheme, builder) in cases {
        assert_eq!(NetBuilder::points_for(&scheme), builder, "{scheme:?}");
    }
    assert_eq!(
        NetBuilder::normals_for(NormalMode::Quadratic),
        NetBuilder::QuadraticNormals
    );
    for mode in [NormalMode::Linear, NormalMode::Real] {
        assert_eq!(NetBuilder::normals_for(mode), NetBuilder::LinearNormals);
    }
    // The skinned normal for WebGL2: the same traced formula as the WGSL's.
    let glsl = skin_normal(Lang::Glsl);
    assert!(glsl.starts_with("vec3 tessella_skin_normal(mat3 m, vec3 n) {"));
    assert!(glsl.contains("sqrt(") && glsl.contains("m[2].z"), "{glsl}");
}

/// The traced normal glue, run as a shader runs it (every operation in `f32`), gives the CPU
/// kernels' bits: derivatives parallel or not, vanishing and non-finite normals, degenerate
/// corner triangles; and each backend's text declares the three functions once.
#[test]
fn traced_surface_normal_gives_the_cpus_bits() {
    use crate::basis::surface_normal::{corner_normal_of, real_normal_of, unit_or_zero_of};
    let v3 = |name: &str| ["x", "y", "z"].map(|c| Expr::input(&format!("{name}.{c}")));
    let real = trace(|| real_normal_of(v3("du"), v3("dv")));
    let unit = trace(|| unit_or_zero_of(v3("n")));
    let corner = trace(|| corner_normal_of([v3("a"), v3("b"), v3("c")]));
    let none = |name: &str, _: &[u32]| -> u32 { panic!("no function {name}") };
    let fnone = |name: &str, _: &[u32]| -> f32 { panic!("no function {name}") };
    let run = |(tape, out): &(Tape, [Expr; 3]), args: &[(&str, [f32; 3])]| {
        let mut inputs: Vec<(String, f32)> = Vec::new();
        for (name, v) in args {
            for (c, x) in ["x", "y", "z"].iter().zip(v) {
                inputs.push((format!("{name}.{c}"), *x));
            }
        }
        let inputs: Vec<(&str, f32)> = inputs.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let v = run_f32(tape, &inputs, none, fnone);
        out.map(|e| (v[e.index()] as f32).to_bits())
    };
    let mut state = 11u32;
    let mut next = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    };
    let bits = |v: [f32; 3]| v.map(f32::to_bits);
    for case in 0..2000 {
        let a = [next(), next(), next()];
        let mut b = [next(), next(), next()];
        match case % 7 {
            0 => b = a.map(|x| 3.0 * x),
            1 => b = [0.0; 3],
            2 => b[0] = f32::NAN,
            3 => b = a.map(|x| x * 1e-25),
            _ => {}
        }
        let c = [next(), next(), next()];
        assert_eq!(
            run(&real, &[("du", a), ("dv", b)]),
            bits(real_normal_of(a, b)),
            "{a:?} {b:?}"
        );
        assert_eq!(run(&unit, &[("n", b)]), bits(unit_or_zero_of(b)), "{b:?}");
        let corners = [a, if case % 5 == 0 { a } else { b }, c];
        assert_eq!(
            run(
                &corner,
                &[("a", corners[0]), ("b", corners[1]), ("c", corners[2])]
            ),
            bits(corner_normal_of(corners)),
            "{corners:?}"
        );
    }
    for (lang, head) in [
        (
            Lang::Wgsl,
            "fn tessella_real_normal(du: vec3<f32>, dv: vec3<f32>) -> vec3<f32> {",
        ),
        (Lang::Glsl, "vec3 tessella_real_normal(vec3 du, vec3 dv) {"),
    ] {
        let text = surface_normal(lang);
        assert!(text.starts_with(head), "{text}");
        assert_eq!(text.matches("tessella_unit_or_zero(").count(), 1);
        assert_eq!(text.matches("tessella_corner_normal(").count(), 1);
        assert!(text.contains("1e-12"), "{text}");
    }
}

/// The glue takes the core's steps in their order, each source only under its step's test.
#[test]
fn normal_glue_takes_the_steps_in_order() {
    let real = RealNormalSource {
        when: Some("MODE_IS_REAL"),
        du: "DU",
        dv: "DV",
    };
    for lang in [Lang::Wgsl, Lang::Glsl] {
        let zero = match lang {
            Lang::Wgsl => "if (all(n == vec3<f32>(0.0))) {",
            Lang::Glsl => "if (n == vec3(0.0)) {",
        };
        for real in [
            None,
            Some(real),
            Some(RealNormalSource { when: None, ..real }),
        ] {
            let text = normal_glue(
                lang,
                &NormalSources {
                    real,
                    net: "NET_1\nNET_2",
                    corners: ["C0", "C1", "C2"],
                },
            );
            let at = |needle: &str| {
                assert_eq!(text.matches(needle).count(), 1, "{needle} in\n{text}");
                text.find(needle).unwrap()
            };
            let net = at("NET_1\n");
            let unit = at("    n = tessella_unit_or_zero(n);\n");
            let corner = at("n = tessella_corner_normal(C0, C1, C2);");
            assert!(net < unit && unit < corner && text[net..].contains("NET_2"));
            // The corner only where the unit normal vanished.
            assert!(text[unit..corner].contains(zero));
            match real {
                None => {
                    assert!(!text.contains("tessella_real_normal") && !text[..net].contains(zero));
                }
                Some(r) => {
                    let real = at("n = tessella_real_normal(DU, DV);");
                    assert!(real < net && text[real..net].contains(zero));
                    assert_eq!(text.contains("if (MODE_IS_REAL) {"), r.when.is_some());
                }
            }
        }
    }
}

/// A whole point's evaluation sets what the host asks for and nothing else: the point's sum
/// where asked, the derivatives (declared here) only for a normal that may be real, the normal
/// net and the corners only for a normal, the real normal's condition where the host has one.
#[test]
fn evaluate_sets_what_the_host_asks_for() {
    let point = |k: usize| format!("P({k})");
    let net_normal = |k: usize| format!("N({k})");
    for lang in [Lang::Wgsl, Lang::Glsl] {
        for basis in [Basis::Cubic, Basis::Png1] {
            for real in [
                RealNormal::Never,
                RealNormal::Always,
                RealNormal::When("IS_REAL"),
            ] {
                for into in [
                    [Some("POS"), Some("NRM")],
                    [Some("POS"), None],
                    [None, Some("NRM")],
                ] {
                    let text = evaluate(
                        lang,
                        basis,
                        &EvalSources {
                            point: &point,
                            net_normal: &net_normal,
                            real,
                            into,
                        },
                    );
                    let what = format!("{lang:?} {basis:?} {real:?} {into:?}:\n{text}");
                    let normal = into[1].is_some();
                    let derivatives = normal && real != RealNormal::Never;
                    assert_eq!(text.contains("    POS = "), into[0].is_some(), "{what}");
                    assert_eq!(text.contains("    du = "), derivatives, "{what}");
                    assert_eq!(text.contains("    dv = "), derivatives, "{what}");
                    assert_eq!(
                        text.contains("tessella_real_normal(du, dv)"),
                        derivatives,
                        "{what}"
                    );
                    assert_eq!(
                        text.contains("if (IS_REAL)"),
                        derivatives && matches!(real, RealNormal::When(_)),
                        "{what}"
                    );
                    assert_eq!(text.contains("N(5)"), normal, "{what}");
                    assert_eq!(
                        text.contains("tessella_corner_normal(c0, c1, c2)"),
                        normal,
                        "{what}"
                    );
                    assert_eq!(text.ends_with("    NRM = n;\n"), normal, "{what}");
                    // Every control point is read once, whatever is asked (the corners are
                    // the first three).
                    for k in 0..basis.len() {
                        assert_eq!(text.matches(&format!("P({k});")).count(), 1, "{what}");
                    }
                }
            }
        }
    }
}

/// The adaptive point takes the CPU's steps in the CPU's order: placement, read-back, the
/// host's evaluation at `l`, then on a coarse edge the canonical edge point in its place, from
/// the face's bits and the edge's own parameter; the host's names where it gives them.
#[test]
fn adaptive_point_takes_the_cpus_steps_in_order() {
    for lang in [Lang::Wgsl, Lang::Glsl] {
        let text = adaptive_point(
            lang,
            &PointSources {
                face: "FACE",
                context: "CTX, ",
                record: "REC",
                code: "CODE",
                side: "SIDE",
                forward_bits: "BITS",
                evaluate: "EVAL_1\nEVAL_2",
            },
        );
        let at = |needle: &str| {
            assert_eq!(text.matches(needle).count(), 1, "{needle} in\n{text}");
            text.find(needle).unwrap()
        };
        let order = [
            at("tessella_locate(REC, CODE, SIDE);"),
            at(" = BITS;"),
            at("tessella_tessellator_point(p, bits"),
            at("    EVAL_1\n    EVAL_2\n"),
            at("if (p.z != TESSELLA_NO_EDGE) {"),
            at("tessella_edge_weights("),
            at("tessella_canonical_edge_point(CTX, FACE, p.z, tessella_edge_forward(bits, p.z), "),
        ];
        assert!(order.windows(2).all(|w| w[0] < w[1]), "{text}");
        // The edge point replaces the patch's point and normal, from the patch's normal.
        match lang {
            Lang::Wgsl => {
                at("w.value, w.normal, normal);");
                assert!(text.contains("position = e.p;") && text.contains("normal = e.n;"));
            }
            Lang::Glsl => {
                at("ew, en, normal, position, normal);");
            }
        }
    }
}

/// The packed record's traced reader gives back every word the placement reads and the
/// canonical bits, from real records of every spacing; and it is printed with the names the
/// placement calls.
#[test]
fn traced_packed_record_reader_gives_back_the_records_words() {
    use crate::mesh::Topology;
    use crate::refine::instanced::{frame_instances, PartTable, FORWARD_WORD, RECORD_WORDS};
    use crate::refine::packed::pack_record;
    use crate::refine::Spacing;
    use crate::tessellator::points::RULER_WORDS;
    let [(ruler_tape, word), (bits_tape, bits)] = traced_packed_record();
    let mesh = crate::samples::by_name("icosphere").expect("a bundled sample");
    let topology = Topology::new(&mesh);
    let mut checked = 0;
    for spacing in [
        Spacing::Equal,
        Spacing::FractionalOdd,
        Spacing::FractionalEven,
    ] {
        let table = PartTable::new(spacing);
        for level in [1.0, 2.5, 7.3, 16.0, 33.9, 64.0] {
            let levels: Vec<f32> = (0..topology.edges.len())
                .map(|e| (level + e as f32 * 0.37) % 64.0 + 1.0)
                .collect();
            let frame = frame_instances(
                &table,
                &topology,
                mesh.triangles(),
                &topology.position_ids,
                &levels,
                None,
            )
            .expect("levels in range");
            for record in frame.records.chunks_exact(RECORD_WORDS).step_by(7) {
                let packed = pack_record(record);
                let read = |name: &str, args: &[u32]| {
                    assert_eq!(name, "tessella_packed");
                    packed[args[0] as usize]
                };
                for (i, &want) in record[..4 * RULER_WORDS].iter().enumerate() {
                    let inputs = [
                        ("r", (i / RULER_WORDS) as f64),
                        ("k", (i % RULER_WORDS) as f64),
                    ];
                    let v = run_with(&ruler_tape, &inputs, read);
                    assert_eq!(v[word.index()] as u32, want, "{spacing:?} {level} word {i}");
                }
                let v = run_with(&bits_tape, &[], read);
                assert_eq!(v[bits.index()] as u32, record[FORWARD_WORD]);
                checked += 1;
            }
        }
    }
    assert!(checked > 100, "{checked}");
    for lang in [Lang::Wgsl, Lang::Glsl] {
        let text = packed_record(lang);
        assert_eq!(text.matches("tessella_ruler_word(").count(), 1, "{text}");
        assert_eq!(text.matches("tessella_forward_bits(").count(), 1, "{text}");
        assert!(text.contains("tessella_packed("), "{text}");
    }
}

/// The packed net the per-texel function reads from: its floats, run in f32 as a shader runs
/// them, are the CPU's `f32` nets (points then normal net) bit for bit, for every builder the
/// GPU has; and each texel's branch returns floats `4j..4j+4` of it (zeros past the end).
#[test]
fn net_texels_pack_the_cpus_nets() {
    let none = |name: &str, _: &[u32]| -> u32 { panic!("no function {name}") };
    let fnone = |name: &str, _: &[u32]| -> f32 { panic!("no function {name}") };
    let mut state = 5u32;
    let mut next = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    };
    for points in [
        NetBuilder::FlatPoints,
        NetBuilder::PhongPoints,
        NetBuilder::PnPoints,
        NetBuilder::PnAenPoints,
    ] {
        for normals in [NetBuilder::LinearNormals, NetBuilder::QuadraticNormals] {
            let (tape, floats) = traced_packed_net(points, normals);
            for _ in 0..50 {
                let v3 = |f: &mut dyn FnMut() -> f32| V3::new(f(), f(), f());
                let p = [v3(&mut next), v3(&mut next), v3(&mut next)];
                let n = [v3(&mut next), v3(&mut next), v3(&mut next)];
                let m = [0; 6].map(|_| v3(&mut next));
                let alpha = 0.75f32;
                let mut inputs: Vec<(String, f32)> = vec![("alpha".into(), alpha)];
                for (name, vs) in [("p", &p[..]), ("n", &n[..]), ("m", &m[..])] {
                    for (i, v) in vs.iter().enumerate() {
                        for (c, x) in ["x", "y", "z"].iter().zip([v.x, v.y, v.z]) {
                            inputs.push((format!("{name}[{i}].{c}"), x));
                        }
                    }
                }
                let inputs: Vec<(&str, f32)> =
                    inputs.iter().map(|(k, v)| (k.as_str(), *v)).collect();
                let values = run_f32(&tape, &inputs, none, fnone);
                let cpu: Vec<u32> = points
                    .build(p, n, alpha, m)
                    .iter()
                    .chain(&normals.build(p, n, alpha, m))
                    .flat_map(|v| [v.x, v.y, v.z])
                    .map(f32::to_bits)
                    .collect();
                let got: Vec<u32> = floats
                    .iter()
                    .map(|e| (values[e.index()] as f32).to_bits())
                    .collect();
                assert_eq!(got, cpu, "{points:?} {normals:?}");
            }
            let texels = floats.len().div_ceil(4);
            let text = net_texel_glsl(points, normals, texels);
            assert!(text.starts_with(
                "vec4 tessella_net_texel(vec3 p[3], vec3 n[3], float alpha, vec3 m[6], int j) {"
            ));
            assert_eq!(text.matches("    if (j == ").count(), texels);
            // A texel computes less than the whole net: its branch is shorter than the builders.
            let whole = Body::new(&tape, Lang::Glsl, &floats)
                .statements
                .lines()
                .count();
            for j in 0..texels {
                let chunk = &floats[4 * j..(4 * j + 4).min(floats.len())];
                let body = Body::new(&tape, Lang::Glsl, chunk);
                let names: Vec<String> = chunk.iter().map(|&e| body.name(e)).collect();
                assert!(text.contains(&format!("return vec4({}", names.join(", "))));
                assert!(body.statements.lines().count() <= whole);
            }
        }
    }
}

/// The OpenGL control shader's PNG1 net, run in f64 as its doubles compute, gives the CPU's
/// `f64` net bit for bit: smooth, boundary and sharp edges, a folded neighbour and an edge
/// along a corner normal (whose fallbacks the selections take).
#[test]
fn traced_png1_net_gives_the_cpus_bits() {
    use crate::scheme::png1::{control_points_f64, smoothed_normal_net, Png1Edge};
    use glam::DVec3;
    let (tape, net) = traced_png1_net();
    let (normal_tape, normals) = traced_png1_normals();
    let mut seed = 3u32;
    let mut r = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f64 / (1u32 << 24) as f64 * 2.0 - 1.0
    };
    for case in 0..400 {
        let mut v = || DVec3::new(r(), r(), r());
        let mut p = [v(), v(), v()];
        let n = [v(), v(), v()];
        let q = [v(), v(), v()];
        if case % 5 == 1 {
            p[1] = p[0] + n[0] * 0.5;
        }
        let edges: [Png1Edge; 3] = std::array::from_fn(|k| Png1Edge {
            opposite: match (case + k) % 4 {
                0 => None,
                _ if case % 5 == 2 => Some(p[(k + 2) % 3]),
                _ => Some(q[k]),
            },
            sharp: match (case / 2 + k) % 5 {
                0 => Some(0.0),
                1 => Some(0.15),
                _ => None,
            },
        });
        let mut named: Vec<(String, f64)> = Vec::new();
        for (array, vs) in [("p", p), ("n", n)] {
            for (i, x) in vs.iter().enumerate() {
                for (axis, c) in ["x", "y", "z"].iter().zip(x.to_array()) {
                    named.push((format!("{array}[{i}].{axis}"), c));
                }
            }
        }
        for (k, edge) in edges.iter().enumerate() {
            let e = edge.numbers();
            for (axis, c) in ["x", "y", "z"]
                .iter()
                .zip([e.opposite.x, e.opposite.y, e.opposite.z])
            {
                named.push((format!("q[{k}].{axis}"), c));
            }
            named.push((format!("smooth_edge[{k}]"), e.smooth));
            named.push((format!("sharp[{k}]"), e.sharp));
            named.push((format!("kappa[{k}]"), e.kappa));
        }
        let inputs: Vec<(&str, f64)> = named.iter().map(|(k, x)| (k.as_str(), *x)).collect();
        let values = run(&tape, &inputs);
        let want = control_points_f64(p, n, edges);
        for (i, (traced, cpu)) in net.iter().zip(want).enumerate() {
            let got = [traced.x, traced.y, traced.z].map(|e| values[e.index()].to_bits());
            assert_eq!(
                got,
                cpu.to_array().map(f64::to_bits),
                "case {case}, point {i}"
            );
        }
        // The smoothed normal net from that net. Its sums skip the zero weights' terms, so
        // a zero's sign may differ; the values are equal.
        let mut named: Vec<(String, f64)> = Vec::new();
        for (array, vs) in [("c", &want[..]), ("n", &n[..])] {
            for (i, x) in vs.iter().enumerate() {
                for (axis, c) in ["x", "y", "z"].iter().zip(x.to_array()) {
                    named.push((format!("{array}[{i}].{axis}"), c));
                }
            }
        }
        let inputs: Vec<(&str, f64)> = named.iter().map(|(k, x)| (k.as_str(), *x)).collect();
        let values = run(&normal_tape, &inputs);
        let cpu = smoothed_normal_net(&want, n);
        for (i, (traced, cpu)) in normals.iter().zip(cpu).enumerate() {
            let got = [traced.x, traced.y, traced.z].map(|e| values[e.index()]);
            assert_eq!(got, cpu.to_array(), "case {case}, normal {i}");
        }
    }
    let glsl = png1_net_glsl();
    assert!(glsl.starts_with("void tessella_png1_net(dvec3 p[3], dvec3 n[3], dvec3 q[3]"));
    assert!(
        glsl.contains("double t") && !glsl.contains("float "),
        "doubles only"
    );
    let glsl = png1_normals_glsl();
    assert!(glsl.starts_with("void tessella_png1_normals(dvec3 c[21], dvec3 n[3]"));
    assert!(!glsl.contains("float "), "doubles only");
}

/// The traced grid plan, computed as the shader computes it (every `f32` operation rounded,
/// the edge first, then the plan of its case), gives the bits of `grid_point_of` run on the
/// CPU in `f32`, for every point of faces with snapped edges, geomorphs and both directions of
/// each edge.
#[test]
fn traced_grid_plan_gives_the_cpus_bits() {
    use crate::refine::grid_point::grid_point_of;
    use crate::tessellator::parts::NO_EDGE;
    let (edge_tape, edge_out) = traced_grid_edge();
    let (edge_plan_tape, edge_plan) = traced_grid_edge_plan();
    let (inner_tape, inner_plan) = traced_grid_inner_plan();
    let mut checked = [0; 2];
    for (segments, big) in [
        ([3u32, 5, 2], 5u32),
        ([1, 4, 4], 4),
        ([7, 7, 7], 7),
        ([2, 9, 5], 11),
        ([1, 1, 1], 1),
    ] {
        for (alpha, inner) in [
            ([1.0f32; 3], 1.0f32),
            ([0.3, 0.55, 1.0], 0.4),
            ([0.125; 3], 0.9),
        ] {
            for forward in [0u32, 5, 7] {
                for j in 0..=big {
                    for i in 0..=big - j {
                        let want = grid_point_of::<f32>(big, i, j, segments, alpha, inner, forward);
                        let case = format!("{segments:?} {big} {i} {j} {alpha:?} {forward}");
                        let mut inputs: Vec<(&str, f32)> = vec![
                            ("big", big as f32),
                            ("i", i as f32),
                            ("j", j as f32),
                            ("segments.x", segments[0] as f32),
                            ("segments.y", segments[1] as f32),
                            ("segments.z", segments[2] as f32),
                            ("forward", forward as f32),
                            ("alpha.x", alpha[0]),
                            ("alpha.y", alpha[1]),
                            ("alpha.z", alpha[2]),
                            ("alpha_inner", inner),
                        ];
                        let e = run_f32(&edge_tape, &inputs, no_ucall, no_fcall)[edge_out.index()]
                            as u32;
                        inputs.push(("edge", e as f32));
                        let (tape, plan) = match e {
                            NO_EDGE => (&inner_tape, &inner_plan),
                            _ => (&edge_plan_tape, &edge_plan),
                        };
                        checked[usize::from(e != NO_EDGE)] += 1;
                        let v = run_f32(tape, &inputs, no_ucall, no_fcall);
                        let f = |e: Expr| (v[e.index()] as f32).to_bits();
                        assert_eq!(plan.l.map(f), want.l.map(f32::to_bits), "{case}");
                        assert_eq!(v[plan.edge.index()] as u32, want.edge, "{case}");
                        for (got, want) in plan.points.iter().zip(&want.points) {
                            assert_eq!(f(got.1), want.1.to_bits(), "{case}");
                            if want.1 != 0.0 {
                                assert_eq!(got.0.map(f), want.0.map(f32::to_bits), "{case}");
                            }
                        }
                        for (got, want) in plan.edge_points.iter().zip(&want.edge_points) {
                            assert_eq!(f(got.1), want.1.to_bits(), "{case}");
                            if want.1 != 0.0 {
                                assert_eq!(got.0.map(f), want.0.map(f32::to_bits), "{case}");
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    let wgsl = grid_plan_wgsl();
    for head in [
        "fn tessella_grid_edge(big: u32, i: u32, j: u32) -> u32 {",
        "fn tessella_grid_edge_plan(edge: u32, big: u32, i: u32, j: u32, segments: vec3<u32>, alpha: vec3<f32>, forward: u32) -> TessellaGridPlan {",
        "fn tessella_grid_inner_plan(big: u32, i: u32, j: u32, alpha_inner: f32) -> TessellaGridPlan {",
    ] {
        assert!(wgsl.contains(head), "{head}");
    }
}

/// The traced canonical edge point, computed as the shader computes it, gives the CPU's
/// `canonical::position` and `canonical::net_normal` bits (a vanished normal as zero).
#[test]
fn traced_canonical_edge_gives_the_cpus_bits() {
    use crate::refine::canonical::{net_normal, position, EdgeWeights};
    let (tape, (p, n)) = traced_canonical_edge();
    let mut seed = 7u32;
    let mut next = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1 << 24) as f32 * 4.0 - 2.0
    };
    let mut checked = 0;
    for case in 0..300 {
        let a = f64::from(next().abs() / 2.0);
        let w = EdgeWeights::new(a, 1.0 - a);
        let c: [[f32; 3]; 4] = std::array::from_fn(|_| [next(), next(), next()]);
        // Every tenth case a normal restriction that vanishes.
        let m: [[f32; 3]; 3] = match case % 10 {
            0 => [[0.0; 3]; 3],
            _ => std::array::from_fn(|_| [next(), next(), next()]),
        };
        let mut inputs: Vec<(String, f32)> = Vec::new();
        for (i, x) in w.value.iter().enumerate() {
            inputs.push((format!("value.{}", ["x", "y", "z", "w"][i]), *x));
        }
        for (i, x) in w.normal.iter().enumerate() {
            inputs.push((format!("normal.{}", ["x", "y", "z"][i]), *x));
        }
        for (name, rows) in [("c", &c[..]), ("m", &m[..])] {
            for (i, row) in rows.iter().enumerate() {
                for (axis, x) in ["x", "y", "z"].iter().zip(row) {
                    inputs.push((format!("{name}[{i}].{axis}"), *x));
                }
            }
        }
        let named: Vec<(&str, f32)> = inputs.iter().map(|(n, x)| (n.as_str(), *x)).collect();
        let v = run_f32(&tape, &named, no_ucall, no_fcall);
        let f = |e: Expr| (v[e.index()] as f32).to_bits();
        assert_eq!(p.map(f), position(&w, &c).map(f32::to_bits), "case {case}");
        let want = net_normal(&w, &m).unwrap_or([0.0; 3]);
        assert_eq!(n.map(f), want.map(f32::to_bits), "case {case}");
        checked += 1;
    }
    assert_eq!(checked, 300);
    assert!(canonical_edge(Lang::Glsl).starts_with(
        "void tessella_canonical_edge(vec4 value, vec3 normal, vec3 c[4], vec3 m[3], out vec3 p, out vec3 n) {"
    ));
}

/// The traced tessellator point, run on every point the CPU's placement gives (each ring, side
/// and side offset), is the exact
/// barycentric point of its 16.16 `u`, `v`, and on a coarse edge the canonical parameter the
/// CPU's tiles take (`Tile::edge_weights`: the start corner's and the end corner's weights,
/// swapped where the edge runs against the face), for every combination of canonical bits.
#[test]
fn traced_tessellator_point_gives_the_cpus_barycentrics_and_canonical_parameter() {
    use crate::tessellator::parts::{locate_of, FaceRulers, NO_EDGE};
    use crate::tessellator::points::RULER_WORDS;
    use crate::tessellator::{process_levels, Partitioning, TessLevels};
    let (tape, (l, ab)) = trace(|| {
        let u = UExpr::input;
        crate::refine::canonical::fixed_point_of::<Expr>(u("p.x"), u("p.y"), u("p.z"), u("forward"))
    });
    let one = f64::from(crate::tessellator::fixed::ONE);
    let (mut checked, mut on_edges) = (0, 0);
    for (spacing, outer, inner) in [
        (Partitioning::FractionalOdd, [3.3, 5.0, 1.7], 4.6),
        (Partitioning::Equal, [4.0, 4.0, 9.0], 3.0),
    ] {
        let p = process_levels(spacing, TessLevels { outer, inner }).expect("levels that draw");
        let rulers = FaceRulers::new(&p);
        let words = rulers.words();
        // Every code a part can name (rings, sides, indices along a side), each side offset.
        let codes = (0..=rulers.inner_points / 2).flat_map(|ring| {
            (0..3u32).flat_map(move |side| {
                let along = rulers.inner_points.max(rulers.outer_points[side as usize]);
                (0..along).flat_map(move |i| (0..3).map(move |o| (ring << 10 | side << 8 | i, o)))
            })
        });
        for (code, side_offset) in codes {
            {
                let [u, v, edge] = locate_of(
                    |r: u32, k| words[RULER_WORDS * r as usize + k],
                    code,
                    side_offset,
                );
                if u64::from(u) + u64::from(v) > u64::from(crate::tessellator::fixed::ONE) {
                    continue; // an index past its ring's side: no point a part names
                }
                // Independent of the traced code: the i64 sum the patterns once took.
                let want_l = [u, v].map(f64::from).map(|x| x / one);
                let w = (i64::from(crate::tessellator::fixed::ONE) - i64::from(u) - i64::from(v))
                    as f64
                    / one;
                for forward in 0..8u32 {
                    let got = run(
                        &tape,
                        &[
                            ("p.x", f64::from(u)),
                            ("p.y", f64::from(v)),
                            ("p.z", f64::from(edge)),
                            ("forward", f64::from(forward)),
                        ],
                    );
                    let l = l.map(|e| got[e.index()]);
                    assert_eq!(l, [want_l[0], want_l[1], w], "{spacing:?} code {code:#x}");
                    assert_eq!(l, crate::tessellator::fixed::barycentric_of::<f64>(u, v));
                    checked += 1;
                    if edge == NO_EDGE {
                        continue;
                    }
                    let k = edge as usize;
                    let (start, end) = (l[k], l[(k + 1) % 3]);
                    let want = if forward >> k & 1 == 1 {
                        [start, end]
                    } else {
                        [end, start]
                    };
                    assert_eq!(
                        ab.map(|e| got[e.index()]),
                        want,
                        "code {code:#x} bits {forward}"
                    );
                    on_edges += 1;
                }
            }
        }
    }
    assert!(checked > 1000 && on_edges > 300, "{checked} {on_edges}");
    assert!(tessellator_point(Lang::Wgsl).contains(
        "fn tessella_tessellator_point(p: vec3<u32>, forward: u32) -> TessellaTessellatorPoint {"
    ));
    assert!(tessellator_point(Lang::Glsl).starts_with(
        "void tessella_tessellator_point(uvec3 p, uint forward, out vec3 l, out vec2 ab) {"
    ));
}

/// The canonical edge point reads the edge's entries in the face's direction or reversed, as
/// `canonical_points` and `canonical_normals` order them, passes the host's context on, and
/// keeps the face's normal where the mode or a vanished net says so.
#[test]
fn canonical_edge_point_reads_in_canonical_order_and_keeps_the_faces_normal_where_due() {
    let sources = EdgeSources {
        context: ("nets: texture_2d<f32>, ", "nets, "),
        net_normals: "!TESSELLA_REAL_NORMALS",
    };
    let wgsl = canonical_edge_point(Lang::Wgsl, &sources);
    assert!(wgsl.contains(
        "fn tessella_canonical_edge_point(nets: texture_2d<f32>, face: u32, edge: u32, forward: bool, \
         value: vec4<f32>, normal: vec3<f32>, face_normal: vec3<f32>) -> TessellaCanonicalEdge {"
    ));
    // The reversal is the CPU's: entry i of the reversed list is entry n - 1 - i.
    let mut c = crate::refine::canonical::canonical_points(
        Basis::Cubic,
        &std::array::from_fn::<_, 10, _>(|i| [i as f32; 3]),
        1,
        false,
    )
    .map(|p| p[0] as usize);
    assert_eq!(c, {
        let mut e = crate::refine::canonical::edge_controls(Basis::Cubic, 1);
        e.reverse();
        e
    });
    c.reverse();
    assert_eq!(c, crate::refine::canonical::edge_controls(Basis::Cubic, 1));
    for want in [
        "c[i] = tessella_net_point(nets, face, tessella_edge_control(edge, select(3u - i, i, forward)));",
        "m[i] = tessella_net_normal(nets, face, tessella_edge_normal_control(edge, select(2u - i, i, forward)));",
        "if (!(!TESSELLA_REAL_NORMALS) || all(e.n == vec3<f32>(0.0))) {\n        e.n = face_normal;",
        "fn tessella_edge_forward(bits: u32, edge: u32) -> bool {\n    return ((bits >> edge) & 1u) != 0u;",
    ] {
        assert!(wgsl.contains(want), "{want}\n{wgsl}");
    }
    let glsl = canonical_edge_point(
        Lang::Glsl,
        &EdgeSources {
            context: ("", ""),
            net_normals: "!TESSELLA_REAL_NORMALS",
        },
    );
    for want in [
        "void tessella_canonical_edge_point(uint face, uint edge, bool forward, vec4 value, vec3 normal, vec3 face_normal, out vec3 p, out vec3 n) {",
        "c[i] = tessella_net_point(face, tessella_edge_control(edge, (forward ? i : 3u - i)));",
        "tessella_canonical_edge(value, normal, c, m, p, n);",
        "if (!(!TESSELLA_REAL_NORMALS) || n == vec3(0.0)) {\n        n = face_normal;",
    ] {
        assert!(glsl.contains(want), "{want}\n{glsl}");
    }
    assert!(!glsl.contains("let ") && !glsl.contains("select("));
}
