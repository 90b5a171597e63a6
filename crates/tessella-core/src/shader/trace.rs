//! A traced number: running a [`Real`]-generic formula with [`Expr`] (or a [`Word`]-generic
//! one with [`UExpr`]) records each operation on a tape instead of computing it, and the tape
//! is then printed as shader code (`emit.rs`).
//!
//! The tape is thread-local and lives for one [`trace`] call, so an `Expr` is a plain index
//! (`Copy`, as `Real` needs). Identical operations are recorded once, and operations on
//! constants are folded (`0 · x = 0`, `1 · x = x`, `x + 0 = x`, constants with constants), so
//! the printed code is what a hand-written shader would compute, without the zero terms of a
//! general formula.

use crate::scalar::{Noise, Real, Word};
use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// One recorded `f32` value: an index into the current tape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Expr(u32);

/// One recorded `u32` value: an index into the current tape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct UExpr(u32);

/// A comparison a `u32` selection makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Cmp {
    Ge,
    Gt,
    Eq,
}

impl Cmp {
    /// Whether `a cmp b` holds (how a selection on constants folds, and how tests evaluate one).
    pub(crate) fn holds<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            Cmp::Ge => a >= b,
            Cmp::Gt => a > b,
            Cmp::Eq => a == b,
        }
    }
}

/// The type of a recorded value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ty {
    F32,
    U32,
}

/// An operation on the tape. Constants are held as `f64` bits so nodes can be hashed.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) enum Node {
    /// A named input of the generated function (`l.x`, a parameter).
    Input(String),
    Const(u64),
    Add(Expr, Expr),
    Sub(Expr, Expr),
    Mul(Expr, Expr),
    Div(Expr, Expr),
    Neg(Expr),
    Sqrt(Expr),
    /// `yes` where `test` is finite and positive, else `no`.
    SelectPositiveFinite {
        test: Expr,
        yes: Expr,
        no: Expr,
    },
    /// `nonzero` where `test != 0`, else `zero`.
    SelectNonZero {
        test: Expr,
        nonzero: Expr,
        zero: Expr,
    },
    /// A named `u32` input.
    UInput(String),
    UConst(u32),
    /// Wrapping `u32` arithmetic: `+ - *`, and `% / & >>`.
    UBin(UOp, UExpr, UExpr),
    UShr(UExpr, u32),
    /// `yes` where `a cmp b`, else `no`.
    USelect {
        cmp: Cmp,
        a: UExpr,
        b: UExpr,
        yes: UExpr,
        no: UExpr,
    },
    /// A `u32` function of the including shader (a record read, say).
    UCall(String, Vec<UExpr>),
    Floor(Expr),
    Sin(Expr),
    /// A whole `f32` as an `i32`, its bits as a `u32` ([`Noise::int_word`]).
    IntWord(Expr),
    /// A `u32`'s value as an `f32` ([`Noise::from_word`]).
    FromWord(UExpr),
    /// The `f32` `yes` where the words compare `a cmp b`, else `no`.
    Pick {
        cmp: Cmp,
        a: UExpr,
        b: UExpr,
        yes: Expr,
        no: Expr,
    },
    /// An `f32` function of the including shader with word arguments (a texel read).
    Call(String, Vec<UExpr>),
    /// The `f32` `yes` where `a > b`, else `no`.
    PickGt {
        a: Expr,
        b: Expr,
        yes: Expr,
        no: Expr,
    },
    /// The word `yes` where the `f32`s `a == b`, else `no`.
    WordIfEq {
        a: Expr,
        b: Expr,
        yes: UExpr,
        no: UExpr,
    },
}

/// A binary `u32` operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum UOp {
    Add,
    Sub,
    Mul,
    Rem,
    Div,
    And,
}

impl Node {
    /// The type of the value the node records.
    pub(crate) fn ty(&self) -> Ty {
        match self {
            Node::UInput(_)
            | Node::UConst(_)
            | Node::UBin(..)
            | Node::UShr(..)
            | Node::USelect { .. }
            | Node::UCall(..)
            | Node::IntWord(_)
            | Node::WordIfEq { .. } => Ty::U32,
            _ => Ty::F32,
        }
    }
}

/// The operations one [`trace`] recorded, in order (every operand before its use).
#[derive(Debug, Default)]
pub(crate) struct Tape {
    pub(crate) nodes: Vec<Node>,
    seen: HashMap<Node, u32>,
}

thread_local! {
    static TAPE: RefCell<Option<Tape>> = const { RefCell::new(None) };
}

/// Runs `f` with a fresh tape and returns the tape with `f`'s result.
///
/// # Panics
/// When called inside another `trace` on the same thread (a bug in the generator).
pub(crate) fn trace<R>(f: impl FnOnce() -> R) -> (Tape, R) {
    TAPE.with(|t| {
        let mut t = t.borrow_mut();
        assert!(t.is_none(), "shader traces do not nest");
        *t = Some(Tape::default());
    });
    let out = f();
    let tape = TAPE
        .with(|t| t.borrow_mut().take())
        .expect("the tape set above");
    (tape, out)
}

impl Expr {
    /// A call of the including shader's `name(args)`, returning `f32`.
    pub(crate) fn call(name: &str, args: &[UExpr]) -> Expr {
        Expr::push(Node::Call(name.to_string(), args.to_vec()))
    }

    fn pick(cmp: Cmp, a: UExpr, b: UExpr, yes: Expr, no: Expr) -> Expr {
        if yes == no {
            return no;
        }
        if let (Some(x), Some(y)) = (a.value(), b.value()) {
            return if cmp.holds(x, y) { yes } else { no };
        }
        Expr::push(Node::Pick { cmp, a, b, yes, no })
    }

    /// A named input; its name is printed as it is (`l.x`, `a`).
    pub(crate) fn input(name: &str) -> Expr {
        Expr::push(Node::Input(name.to_string()))
    }

    fn constant(x: f64) -> Expr {
        // -0.0 and 0.0 print alike; keep one node.
        let x = if x == 0.0 { 0.0 } else { x };
        Expr::push(Node::Const(x.to_bits()))
    }

    /// The constant this expression is, if it is one.
    fn value(self) -> Option<f64> {
        TAPE.with(
            |t| match t.borrow().as_ref().expect(OUTSIDE).nodes[self.0 as usize] {
                Node::Const(bits) => Some(f64::from_bits(bits)),
                _ => None,
            },
        )
    }

    fn push(node: Node) -> Expr {
        Expr(push(node))
    }
}

const OUTSIDE: &str = "a traced number is used outside `shader::trace`";

/// Records `node` (or finds it recorded) and returns its index.
fn push(node: Node) -> u32 {
    TAPE.with(|t| {
        let mut t = t.borrow_mut();
        let tape = t.as_mut().expect(OUTSIDE);
        if let Some(&e) = tape.seen.get(&node) {
            return e;
        }
        let e = tape.nodes.len() as u32;
        tape.nodes.push(node.clone());
        tape.seen.insert(node, e);
        e
    })
}

/// A recorded value of either type, by its index on the tape.
pub(crate) trait Traced {
    fn index(&self) -> usize;
}

impl Traced for Expr {
    fn index(&self) -> usize {
        self.0 as usize
    }
}

impl Traced for UExpr {
    fn index(&self) -> usize {
        self.0 as usize
    }
}

impl UExpr {
    /// A named `u32` input.
    pub(crate) fn input(name: &str) -> UExpr {
        UExpr(push(Node::UInput(name.to_string())))
    }

    /// A call of the including shader's `name(args)`, returning `u32`.
    pub(crate) fn call(name: &str, args: &[UExpr]) -> UExpr {
        UExpr(push(Node::UCall(name.to_string(), args.to_vec())))
    }

    fn value(self) -> Option<u32> {
        TAPE.with(
            |t| match t.borrow().as_ref().expect(OUTSIDE).nodes[self.0 as usize] {
                Node::UConst(x) => Some(x),
                _ => None,
            },
        )
    }

    fn bin(op: UOp, a: UExpr, b: UExpr) -> UExpr {
        let folded = match (op, a.value(), b.value()) {
            (_, Some(x), Some(y)) => match op {
                UOp::Add => Some(x.wrapping_add(y)),
                UOp::Sub => Some(x.wrapping_sub(y)),
                UOp::Mul => Some(x.wrapping_mul(y)),
                UOp::Rem if y != 0 => Some(x % y),
                UOp::Div if y != 0 => Some(x / y),
                UOp::And => Some(x & y),
                _ => None,
            },
            (UOp::Add | UOp::Sub, _, Some(0)) | (UOp::Mul | UOp::Div, _, Some(1)) => {
                return a;
            }
            (UOp::Add, Some(0), _) | (UOp::Mul, Some(1), _) => return b,
            _ => None,
        };
        match folded {
            Some(x) => UExpr::lit(x),
            None => UExpr(push(Node::UBin(op, a, b))),
        }
    }

    fn select(cmp: Cmp, a: UExpr, b: UExpr, yes: UExpr, no: UExpr) -> UExpr {
        if yes == no {
            return no;
        }
        if let (Some(x), Some(y)) = (a.value(), b.value()) {
            return if cmp.holds(x, y) { yes } else { no };
        }
        UExpr(push(Node::USelect { cmp, a, b, yes, no }))
    }
}

impl Word for UExpr {
    fn lit(x: u32) -> UExpr {
        UExpr(push(Node::UConst(x)))
    }
    fn wadd(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::Add, self, o)
    }
    fn wsub(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::Sub, self, o)
    }
    fn wmul(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::Mul, self, o)
    }
    fn rem(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::Rem, self, o)
    }
    fn div(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::Div, self, o)
    }
    fn shr(self, bits: u32) -> UExpr {
        match self.value() {
            Some(x) => UExpr::lit(x >> bits),
            None if bits == 0 => self,
            None => UExpr(push(Node::UShr(self, bits))),
        }
    }
    fn and(self, o: UExpr) -> UExpr {
        UExpr::bin(UOp::And, self, o)
    }
    fn select_ge(a: UExpr, b: UExpr, yes: UExpr, no: UExpr) -> UExpr {
        UExpr::select(Cmp::Ge, a, b, yes, no)
    }
    fn select_gt(a: UExpr, b: UExpr, yes: UExpr, no: UExpr) -> UExpr {
        UExpr::select(Cmp::Gt, a, b, yes, no)
    }
    fn select_eq(a: UExpr, b: UExpr, yes: UExpr, no: UExpr) -> UExpr {
        UExpr::select(Cmp::Eq, a, b, yes, no)
    }
}

impl Add for Expr {
    type Output = Expr;
    fn add(self, o: Expr) -> Expr {
        match (self.value(), o.value()) {
            (Some(a), Some(b)) => Expr::constant(a + b),
            (Some(0.0), None) => o,
            (None, Some(0.0)) => self,
            _ => Expr::push(Node::Add(self, o)),
        }
    }
}

impl Sub for Expr {
    type Output = Expr;
    fn sub(self, o: Expr) -> Expr {
        match (self.value(), o.value()) {
            (Some(a), Some(b)) => Expr::constant(a - b),
            (Some(0.0), None) => -o,
            (None, Some(0.0)) => self,
            _ => Expr::push(Node::Sub(self, o)),
        }
    }
}

impl Mul for Expr {
    type Output = Expr;
    fn mul(self, o: Expr) -> Expr {
        match (self.value(), o.value()) {
            (Some(a), Some(b)) => Expr::constant(a * b),
            (Some(0.0), _) | (_, Some(0.0)) => Expr::constant(0.0),
            (Some(1.0), None) => o,
            (None, Some(1.0)) => self,
            (Some(-1.0), None) => -o,
            (None, Some(-1.0)) => -self,
            _ => Expr::push(Node::Mul(self, o)),
        }
    }
}

impl Div for Expr {
    type Output = Expr;
    fn div(self, o: Expr) -> Expr {
        match (self.value(), o.value()) {
            (Some(a), Some(b)) if b != 0.0 => Expr::constant(a / b),
            (None, Some(1.0)) => self,
            _ => Expr::push(Node::Div(self, o)),
        }
    }
}

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        match self.value() {
            Some(a) => Expr::constant(-a),
            None => Expr::push(Node::Neg(self)),
        }
    }
}

impl Real for Expr {
    fn lit(x: f64) -> Expr {
        Expr::constant(x)
    }

    fn select_nonzero(test: Expr, nonzero: Expr, zero: Expr) -> Expr {
        if nonzero == zero {
            return zero;
        }
        match test.value() {
            Some(t) if t != 0.0 => nonzero,
            Some(_) => zero,
            None => Expr::push(Node::SelectNonZero {
                test,
                nonzero,
                zero,
            }),
        }
    }

    fn powi(self, n: u8) -> Expr {
        (1..n).fold(self, |acc, _| acc * self)
    }

    fn sqrt(self) -> Expr {
        match self.value() {
            Some(a) => Expr::constant(a.sqrt()),
            None => Expr::push(Node::Sqrt(self)),
        }
    }

    fn choose_nonzero<R>(
        test: Expr,
        nonzero: impl FnOnce() -> R,
        zero: impl FnOnce() -> R,
        select: impl FnOnce(Expr, R, R) -> R,
    ) -> R {
        match test.value() {
            Some(t) if t != 0.0 => nonzero(),
            Some(_) => zero(),
            None => {
                let (a, b) = (nonzero(), zero());
                select(test, a, b)
            }
        }
    }

    fn choose_positive_finite<R>(
        test: Expr,
        yes: impl FnOnce() -> R,
        no: impl FnOnce() -> R,
        select: impl FnOnce(Expr, R, R) -> R,
    ) -> R {
        match test.value() {
            Some(t) if t.is_finite() && t > 0.0 => yes(),
            Some(_) => no(),
            None => {
                let (a, b) = (yes(), no());
                select(test, a, b)
            }
        }
    }

    fn select_positive_finite(test: Expr, yes: Expr, no: Expr) -> Expr {
        if yes == no {
            return no;
        }
        match test.value() {
            Some(t) if t.is_finite() && t > 0.0 => yes,
            Some(_) => no,
            None => Expr::push(Node::SelectPositiveFinite { test, yes, no }),
        }
    }
}

impl Noise for Expr {
    type W = UExpr;
    fn floor(self) -> Expr {
        match self.value() {
            Some(a) => Expr::constant(a.floor()),
            None => Expr::push(Node::Floor(self)),
        }
    }
    fn sin(self) -> Expr {
        Expr::push(Node::Sin(self))
    }
    fn int_word(self) -> UExpr {
        UExpr(push(Node::IntWord(self)))
    }
    fn from_word(w: UExpr) -> Expr {
        match w.value() {
            Some(x) => Expr::constant(f64::from(x as f32)),
            None => Expr::push(Node::FromWord(w)),
        }
    }
    fn pick_ge(a: UExpr, b: UExpr, yes: Expr, no: Expr) -> Expr {
        Expr::pick(Cmp::Ge, a, b, yes, no)
    }
    fn pick_eq(a: UExpr, b: UExpr, yes: Expr, no: Expr) -> Expr {
        Expr::pick(Cmp::Eq, a, b, yes, no)
    }
    fn pick_gt(a: Expr, b: Expr, yes: Expr, no: Expr) -> Expr {
        if yes == no {
            return no;
        }
        Expr::push(Node::PickGt { a, b, yes, no })
    }
    fn word_if_eq(a: Expr, b: Expr, yes: UExpr, no: UExpr) -> UExpr {
        if yes == no {
            return no;
        }
        UExpr(push(Node::WordIfEq { a, b, yes, no }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_fold_and_repeats_are_recorded_once() {
        let (tape, (a, b)) = trace(|| {
            let x = Expr::input("x");
            let a = Expr::lit(2.0) * x + Expr::lit(0.0) * x;
            let b = x * Expr::lit(2.0) / Expr::lit(1.0);
            (Expr::lit(2.0) * x == a, b)
        });
        assert!(a, "0 · x folds away and 2 · x is recorded once");
        // x, 2, 2·x, 0, x·2 (operand order is kept), 1: the sum and the division by one are
        // folded away.
        assert_eq!(tape.nodes.len(), 6, "{:?}", tape.nodes);
        assert_eq!(b.index(), 4);
    }

    #[test]
    fn selections_on_constant_tests_pick_their_side() {
        let (_, picked) = trace(|| {
            let x = Expr::input("x");
            let y = Expr::input("y");
            (
                Expr::select_nonzero(Expr::lit(1.0), x, y) == x,
                Expr::select_nonzero(Expr::lit(0.0), x, y) == y,
                Expr::select_nonzero(x, y, y) == y,
            )
        });
        assert_eq!(picked, (true, true, true));
    }
}
