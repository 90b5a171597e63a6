//! Printing a tape as straight-line WGSL or GLSL: one `let` (`float`) per recorded operation
//! that an output needs, in tape order, named `t<index>` (another prefix where two bodies share
//! a scope).

use super::lang::Lang;
use super::trace::{Cmp, Node, Tape, Traced, Ty, UOp};

/// The statements that compute `outputs`, and how to name any value of the tape.
pub(crate) struct Body<'t> {
    tape: &'t Tape,
    lang: Lang,
    /// GLSL in double precision (`double`, `1.0LF`): the OpenGL control shader's PNG1 net.
    double: bool,
    /// What the temporaries' names start with (`t`; another where two bodies share a scope).
    prefix: &'static str,
    /// One line per operation, indented by four spaces.
    pub(crate) statements: String,
}

impl<'t> Body<'t> {
    /// Statements computing every operation `outputs` depend on.
    pub(crate) fn new<V: Traced + Copy>(tape: &'t Tape, lang: Lang, outputs: &[V]) -> Body<'t> {
        Body::of(tape, lang, false, outputs.iter().map(Traced::index))
    }

    /// [`Body::new`] with temporaries named `<prefix><index>`, so that its statements can stand
    /// in one scope with another body's.
    pub(crate) fn prefixed<V: Traced + Copy>(
        tape: &'t Tape,
        lang: Lang,
        outputs: &[V],
        prefix: &'static str,
    ) -> Body<'t> {
        Body::with(tape, lang, false, prefix, outputs.iter().map(Traced::index))
    }

    /// [`Body::new`] for outputs of both types: `f32` ones and `u32` ones.
    pub(crate) fn mixed(
        tape: &'t Tape,
        lang: Lang,
        floats: &[super::trace::Expr],
        words: &[super::trace::UExpr],
    ) -> Body<'t> {
        let outputs = floats.iter().map(Traced::index);
        Body::of(
            tape,
            lang,
            false,
            outputs.chain(words.iter().map(Traced::index)),
        )
    }

    /// [`Body::new`] in GLSL's `double`s, for a formula the CPU computes in `f64`.
    pub(crate) fn doubles<V: Traced + Copy>(tape: &'t Tape, outputs: &[V]) -> Body<'t> {
        Body::of(tape, Lang::Glsl, true, outputs.iter().map(Traced::index))
    }

    fn of(
        tape: &'t Tape,
        lang: Lang,
        double: bool,
        outputs: impl Iterator<Item = usize>,
    ) -> Body<'t> {
        Body::with(tape, lang, double, "t", outputs)
    }

    fn with(
        tape: &'t Tape,
        lang: Lang,
        double: bool,
        prefix: &'static str,
        outputs: impl Iterator<Item = usize>,
    ) -> Body<'t> {
        let mut needed = vec![false; tape.nodes.len()];
        for e in outputs {
            needed[e] = true;
        }
        // Operands come before their uses, so one backward pass marks everything needed.
        for i in (0..tape.nodes.len()).rev() {
            if !needed[i] {
                continue;
            }
            for operand in operands(&tape.nodes[i]) {
                needed[operand] = true;
            }
        }
        let mut body = Body {
            tape,
            lang,
            double,
            prefix,
            statements: String::new(),
        };
        for (i, node) in tape.nodes.iter().enumerate() {
            if !needed[i]
                || operands(node).is_empty() && !matches!(node, Node::UCall(..) | Node::Call(..))
            {
                continue;
            }
            let value = body.operation(node);
            let decl = match (lang, node.ty()) {
                (Lang::Wgsl, _) => "let",
                (Lang::Glsl, Ty::F32) if double => "double",
                (Lang::Glsl, Ty::F32) => "float",
                (Lang::Glsl, Ty::U32) => "uint",
            };
            body.statements += &format!("    {decl} {prefix}{i} = {value};\n");
        }
        body
    }

    /// How the generated code names `e`: an input's text, a literal, or its `<prefix><index>`.
    pub(crate) fn name<V: Traced>(&self, e: V) -> String {
        self.name_at(e.index())
    }

    fn name_at(&self, i: usize) -> String {
        match &self.tape.nodes[i] {
            Node::Input(name) | Node::UInput(name) => name.clone(),
            Node::Const(bits) if self.double => double_literal(f64::from_bits(*bits)),
            Node::Const(bits) => literal(f64::from_bits(*bits)),
            Node::UConst(x) => format!("{x}u"),
            _ => format!("{}{i}", self.prefix),
        }
    }

    /// Whether `e` is the constant zero (a term the printed sums leave out).
    pub(crate) fn is_zero<V: Traced>(&self, e: V) -> bool {
        match self.tape.nodes[e.index()] {
            Node::Const(bits) => f64::from_bits(bits) == 0.0,
            Node::UConst(x) => x == 0,
            _ => false,
        }
    }

    fn operation(&self, node: &Node) -> String {
        let n = |e: &dyn Traced| self.name_at(e.index());
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
                let finite = match self.double {
                    true => format!("{t} > 0.0LF && {t} <= {F64_MAX}"),
                    false => format!("{t} > 0.0 && {t} <= {F32_MAX}"),
                };
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
                Lang::Glsl => {
                    let zero_literal = if self.double { "0.0LF" } else { "0.0" };
                    format!(
                        "({} != {zero_literal} ? {} : {})",
                        n(test),
                        n(nonzero),
                        n(zero)
                    )
                }
            },
            Node::UBin(op, a, b) => {
                let op = match op {
                    UOp::Add => "+",
                    UOp::Sub => "-",
                    UOp::Mul => "*",
                    UOp::Rem => "%",
                    UOp::Div => "/",
                    UOp::And => "&",
                };
                format!("{} {op} {}", n(a), n(b))
            }
            Node::UShr(a, bits) => format!("{} >> {bits}u", n(a)),
            Node::USelect { cmp, a, b, yes, no } => self.select(*cmp, n(a), n(b), n(yes), n(no)),
            Node::Pick { cmp, a, b, yes, no } => self.select(*cmp, n(a), n(b), n(yes), n(no)),
            Node::PickGt { a, b, yes, no } => self.select(Cmp::Gt, n(a), n(b), n(yes), n(no)),
            Node::WordIfEq { a, b, yes, no } => self.select(Cmp::Eq, n(a), n(b), n(yes), n(no)),
            Node::Floor(a) => format!("floor({})", n(a)),
            Node::Sin(a) => format!("sin({})", n(a)),
            Node::IntWord(a) => match self.lang {
                Lang::Wgsl => format!("bitcast<u32>(i32({}))", n(a)),
                Lang::Glsl => format!("uint(int({}))", n(a)),
            },
            Node::FromWord(a) => match (self.lang, self.double) {
                (Lang::Wgsl, _) => format!("f32({})", n(a)),
                (Lang::Glsl, false) => format!("float({})", n(a)),
                (Lang::Glsl, true) => format!("double({})", n(a)),
            },
            Node::UCall(name, args) | Node::Call(name, args) => {
                let args: Vec<String> = args.iter().map(|a| n(a)).collect();
                format!("{name}({})", args.join(", "))
            }
            Node::Input(_) | Node::Const(_) | Node::UInput(_) | Node::UConst(_) => {
                unreachable!("inputs and constants are inlined")
            }
        }
    }
}

impl Body<'_> {
    /// `yes` where `a cmp b`, else `no`.
    fn select(&self, cmp: Cmp, a: String, b: String, yes: String, no: String) -> String {
        let cmp = match cmp {
            Cmp::Ge => ">=",
            Cmp::Gt => ">",
            Cmp::Eq => "==",
        };
        let test = format!("{a} {cmp} {b}");
        match self.lang {
            Lang::Wgsl => format!("select({no}, {yes}, {test})"),
            Lang::Glsl => format!("({test} ? {yes} : {no})"),
        }
    }
}

/// The largest finite `f32`, as a literal both languages read: its exact value (WGSL reads a
/// literal as an abstract float and refuses, in Tint, one past `f32`'s range, as the shortest
/// `3.4028235e38` is).
const F32_MAX: &str = "3.4028234663852886e38";

/// The largest finite `f64`, as a GLSL double literal.
const F64_MAX: &str = "1.7976931348623157e308LF";

/// The tape indices a node reads.
fn operands(node: &Node) -> Vec<usize> {
    let i = |e: &dyn Traced| e.index();
    match node {
        Node::Input(_) | Node::Const(_) | Node::UInput(_) | Node::UConst(_) => vec![],
        Node::Neg(a) | Node::Sqrt(a) | Node::Floor(a) | Node::Sin(a) | Node::IntWord(a) => {
            vec![i(a)]
        }
        Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => vec![i(a), i(b)],
        Node::SelectPositiveFinite { test, yes, no } => vec![i(test), i(yes), i(no)],
        Node::SelectNonZero {
            test,
            nonzero,
            zero,
        } => vec![i(test), i(nonzero), i(zero)],
        Node::UBin(_, a, b) => vec![i(a), i(b)],
        Node::UShr(a, _) | Node::FromWord(a) => vec![i(a)],
        Node::USelect { a, b, yes, no, .. } => vec![i(a), i(b), i(yes), i(no)],
        Node::Pick { a, b, yes, no, .. } => vec![i(a), i(b), i(yes), i(no)],
        Node::PickGt { a, b, yes, no } => vec![i(a), i(b), i(yes), i(no)],
        Node::WordIfEq { a, b, yes, no } => vec![i(a), i(b), i(yes), i(no)],
        Node::UCall(_, args) | Node::Call(_, args) => args.iter().map(|a| a.index()).collect(),
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

/// A GLSL `double` literal, exactly the `f64`: `3.0LF`, `1e-300LF`, negatives in parentheses.
pub(crate) fn double_literal(x: f64) -> String {
    assert!(x.is_finite(), "a generated constant is not finite: {x}");
    let mut s = format!("{x:?}");
    if !s.contains(['.', 'e']) {
        s.push_str(".0");
    }
    s.push_str("LF");
    if x < 0.0 {
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
        assert_eq!(double_literal(1.0 / 3.0), "0.3333333333333333LF");
        assert_eq!(double_literal(-1.0), "(-1.0LF)");
        assert_eq!(double_literal(1e-300), "1e-300LF");
    }
}
