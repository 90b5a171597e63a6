//! The traced formulas are the CPU's formulas: the recorded tape, evaluated in f64, gives the
//! CPU's weights (so folding and selections changed nothing but the zero terms), and the
//! printed functions have the shape the shaders call.

use super::trace::{trace, Cmp, Expr, Node, Tape, Traced, UExpr, UOp};
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
                let holds = match cmp {
                    Cmp::Ge => u(a) >= u(b),
                    Cmp::Gt => u(a) > u(b),
                    Cmp::Eq => u(a) == u(b),
                };
                f64::from(if holds { u(yes) } else { u(no) })
            }
            Node::UCall(name, args) => {
                let args: Vec<u32> = args.iter().map(u).collect();
                f64::from(call(name, &args))
            }
        };
        v.push(value);
    }
    v
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
    for text in [wgsl, glsl, sum, normal_net(Lang::Wgsl), edge_weights_wgsl()] {
        for line in text.lines() {
            for keyword in ["fn ", "struct ", "void "] {
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
    use crate::scheme::{flat, normal_net, phong, pn, Corners};
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
    let alpha = 0.75f32;
    for builder in NetBuilder::ALL {
        let (tape, net) = trace(|| {
            let (p, n, a) = traced_corners();
            builder.build(p, n, a)
        });
        for c in &corners {
            let mut inputs: Vec<(String, f64)> = vec![("alpha".into(), f64::from(alpha))];
            for (array, v) in [("p", c.p), ("n", c.n)] {
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
    }
}

#[test]
fn traced_tessellator_placement_evaluates_to_the_cpu_placement() {
    use crate::tessellator::parts::{locate_of, FaceRulers, NO_EDGE};
    use crate::tessellator::points::RULER_WORDS;
    use crate::tessellator::{process_levels, Spacing, TessLevels};
    let (tape, out) = traced_locate();
    let mut checked = 0;
    for (spacing, outer, inner) in [
        (Spacing::FractionalOdd, [3.3, 5.0, 1.7], 4.6),
        (Spacing::FractionalEven, [2.0, 7.5, 4.2], 6.1),
        (Spacing::Equal, [4.0, 4.0, 9.0], 3.0),
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
}
