//! Printing a tape as straight-line WGSL or GLSL: one `let` (`float`) per recorded operation
//! that an output needs, in tape order, named `t<index>`.

use super::trace::{Expr, Node, Tape};
use super::Lang;

/// The statements that compute `outputs`, and how to name any value of the tape.
pub(crate) struct Body<'t> {
    tape: &'t Tape,
    lang: Lang,
    /// One line per operation, indented by four spaces.
    pub(crate) statements: String,
}

impl<'t> Body<'t> {
    /// Statements computing every operation `outputs` depend on.
    pub(crate) fn new(tape: &'t Tape, lang: Lang, outputs: &[Expr]) -> Body<'t> {
        let mut needed = vec![false; tape.nodes.len()];
        for e in outputs {
            needed[e.index()] = true;
        }
        // Operands come before their uses, so one backward pass marks everything needed.
        for i in (0..tape.nodes.len()).rev() {
            if !needed[i] {
                continue;
            }
            for operand in operands(&tape.nodes[i]) {
                needed[operand.index()] = true;
            }
        }
        let mut body = Body {
            tape,
            lang,
            statements: String::new(),
        };
        for (i, node) in tape.nodes.iter().enumerate() {
            if !needed[i] || matches!(node, Node::Input(_) | Node::Const(_)) {
                continue;
            }
            let value = body.operation(node);
            let decl = match lang {
                Lang::Wgsl => "let",
                Lang::Glsl => "float",
            };
            body.statements += &format!("    {decl} t{i} = {value};\n");
        }
        body
    }

    /// How the generated code names `e`: an input's text, a literal, or its `t<index>`.
    pub(crate) fn name(&self, e: Expr) -> String {
        match &self.tape.nodes[e.index()] {
            Node::Input(name) => name.clone(),
            Node::Const(bits) => literal(f64::from_bits(*bits)),
            _ => format!("t{}", e.index()),
        }
    }

    /// Whether `e` is the constant zero (a term the printed sums leave out).
    pub(crate) fn is_zero(&self, e: Expr) -> bool {
        matches!(self.tape.nodes[e.index()], Node::Const(bits) if f64::from_bits(bits) == 0.0)
    }

    fn operation(&self, node: &Node) -> String {
        let n = |e: &Expr| self.name(*e);
        match node {
            Node::Add(a, b) => format!("{} + {}", n(a), n(b)),
            Node::Sub(a, b) => format!("{} - {}", n(a), n(b)),
            Node::Mul(a, b) => format!("{} * {}", n(a), n(b)),
            Node::Div(a, b) => format!("{} / {}", n(a), n(b)),
            Node::Neg(a) => format!("-{}", n(a)),
            Node::Sqrt(a) => format!("sqrt({})", n(a)),
            // NaN fails both comparisons and infinity the second: "finite and positive"
            // without isnan/isinf, which WGSL does not have.
            Node::SelectPositiveFinite { test, yes, no } => {
                let t = n(test);
                let finite = format!("{t} > 0.0 && {t} <= {F32_MAX}");
                match self.lang {
                    Lang::Wgsl => format!("select({}, {}, {finite})", n(no), n(yes)),
                    Lang::Glsl => format!("({finite} ? {} : {})", n(yes), n(no)),
                }
            }
            Node::SelectNonZero {
                test,
                nonzero,
                zero,
            } => match self.lang {
                Lang::Wgsl => format!("select({}, {}, {} != 0.0)", n(zero), n(nonzero), n(test)),
                Lang::Glsl => format!("({} != 0.0 ? {} : {})", n(test), n(nonzero), n(zero)),
            },
            Node::Input(_) | Node::Const(_) => unreachable!("inputs and constants are inlined"),
        }
    }
}

/// The largest finite `f32`, as a literal both languages read.
const F32_MAX: &str = "3.4028235e38";

fn operands(node: &Node) -> Vec<Expr> {
    match *node {
        Node::Input(_) | Node::Const(_) => vec![],
        Node::Neg(a) | Node::Sqrt(a) => vec![a],
        Node::SelectPositiveFinite { test, yes, no } => vec![test, yes, no],
        Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => vec![a, b],
        Node::SelectNonZero {
            test,
            nonzero,
            zero,
        } => vec![test, nonzero, zero],
    }
}

/// An `f32` literal both languages read: `3.0`, `0.16666667`, `1e-12`, negatives in
/// parentheses.
pub(crate) fn literal(x: f64) -> String {
    let f = x as f32;
    assert!(f.is_finite(), "a generated constant is not finite: {x}");
    let mut s = format!("{f:?}");
    if !s.contains(['.', 'e']) {
        s.push_str(".0");
    }
    if f < 0.0 {
        format!("({s})")
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_read_as_floats_in_both_languages() {
        assert_eq!(literal(3.0), "3.0");
        assert_eq!(literal(-1.0), "(-1.0)");
        assert_eq!(literal(1e-12), "1e-12");
        assert_eq!(literal(1.0 / 3.0), "0.33333334");
    }
}
