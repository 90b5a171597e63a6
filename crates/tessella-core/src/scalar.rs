//! The arithmetic the shared formulas are written in.
//!
//! A formula that both the CPU and a shader need (the bases' weights, the normal net's weights,
//! a canonical edge's weights) is written once, generic over [`Real`]. On the CPU it runs with
//! `f64`; [`crate::shader`] runs the same function with a traced number that records each
//! operation, and prints the record as WGSL or GLSL. So the shaders are generated from the Rust
//! source, not typed again beside it.
//!
//! Branches on values cannot be traced, so a formula that needs one says it with
//! [`Real::select_nonzero`], which computes both sides and keeps one (or, for vectors,
//! [`V3::choose_nonzero`], which on the CPU computes only the side it keeps): the `f64` result
//! is the one an `if` would give, bit for bit (the side not taken may divide by zero; it is
//! dropped).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number a shared formula computes with: `f64` on the CPU, a traced expression when a
/// shader is generated.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A constant.
    fn lit(x: f64) -> Self;
    /// `nonzero` where `test != 0`, else `zero`; both sides are computed.
    fn select_nonzero(test: Self, nonzero: Self, zero: Self) -> Self;
    /// `self` to the power `n`, `n ≥ 1`.
    fn powi(self, n: u8) -> Self;
    /// The square root.
    fn sqrt(self) -> Self;
    /// `yes` where `test` is finite and positive, else `no`; both sides are computed.
    fn select_positive_finite(test: Self, yes: Self, no: Self) -> Self;
    /// `nonzero()` where `test != 0`, else `zero()`: a CPU number computes only the side it
    /// keeps; a traced one (unless `test` is a constant) computes both and joins them with
    /// `select(test, nonzero, zero)`, its selection ([`V3::choose_nonzero`]).
    fn choose_nonzero<R>(
        test: Self,
        nonzero: impl FnOnce() -> R,
        zero: impl FnOnce() -> R,
        select: impl FnOnce(Self, R, R) -> R,
    ) -> R;
    /// `yes()` where `test` is finite and positive, else `no()`, as [`Real::choose_nonzero`].
    fn choose_positive_finite<R>(
        test: Self,
        yes: impl FnOnce() -> R,
        no: impl FnOnce() -> R,
        select: impl FnOnce(Self, R, R) -> R,
    ) -> R;
}

/// `f64` (stencil weights) and `f32` (control nets: the coarse mesh's precision) compute as
/// themselves; a branch is an `if`.
macro_rules! real_float {
    ($t:ty) => {
        impl Real for $t {
            #[inline]
            fn lit(x: f64) -> $t {
                x as $t
            }
            #[inline]
            fn select_nonzero(test: $t, nonzero: $t, zero: $t) -> $t {
                if test != 0.0 {
                    nonzero
                } else {
                    zero
                }
            }
            #[inline]
            fn powi(self, n: u8) -> $t {
                <$t>::powi(self, i32::from(n))
            }
            #[inline]
            fn sqrt(self) -> $t {
                <$t>::sqrt(self)
            }
            #[inline]
            fn select_positive_finite(test: $t, yes: $t, no: $t) -> $t {
                if test.is_finite() && test > 0.0 {
                    yes
                } else {
                    no
                }
            }
            #[inline(always)]
            fn choose_nonzero<R>(
                test: $t,
                nonzero: impl FnOnce() -> R,
                zero: impl FnOnce() -> R,
                _select: impl FnOnce($t, R, R) -> R,
            ) -> R {
                if test != 0.0 {
                    nonzero()
                } else {
                    zero()
                }
            }
            #[inline(always)]
            fn choose_positive_finite<R>(
                test: $t,
                yes: impl FnOnce() -> R,
                no: impl FnOnce() -> R,
                _select: impl FnOnce($t, R, R) -> R,
            ) -> R {
                if test.is_finite() && test > 0.0 {
                    yes()
                } else {
                    no()
                }
            }
        }
    };
}

real_float!(f64);
real_float!(f32);

/// A 32-bit unsigned word a shared integer formula computes with (the tessellator's 16.16
/// placement): `u32` on the CPU, a traced expression when a shader is generated. Arithmetic
/// wraps, as the reference tessellator's and the shaders' `u32` do; a branch is a selection
/// on a comparison, both sides computed.
pub trait Word: Copy {
    /// A constant.
    fn lit(x: u32) -> Self;
    fn wadd(self, o: Self) -> Self;
    fn wsub(self, o: Self) -> Self;
    fn wmul(self, o: Self) -> Self;
    /// `self % o` (`o` never zero where it is used).
    fn rem(self, o: Self) -> Self;
    /// `self / o` (`o` never zero where it is used).
    fn div(self, o: Self) -> Self;
    fn shr(self, bits: u32) -> Self;
    fn and(self, o: Self) -> Self;
    /// `yes` where `a >= b`, else `no`.
    fn select_ge(a: Self, b: Self, yes: Self, no: Self) -> Self;
    /// `yes` where `a > b`, else `no`.
    fn select_gt(a: Self, b: Self, yes: Self, no: Self) -> Self;
    /// `yes` where `a == b`, else `no`.
    fn select_eq(a: Self, b: Self, yes: Self, no: Self) -> Self;
}

impl Word for u32 {
    #[inline]
    fn lit(x: u32) -> u32 {
        x
    }
    #[inline]
    fn wadd(self, o: u32) -> u32 {
        self.wrapping_add(o)
    }
    #[inline]
    fn wsub(self, o: u32) -> u32 {
        self.wrapping_sub(o)
    }
    #[inline]
    fn wmul(self, o: u32) -> u32 {
        self.wrapping_mul(o)
    }
    #[inline]
    fn rem(self, o: u32) -> u32 {
        self % o
    }
    #[inline]
    fn div(self, o: u32) -> u32 {
        self / o
    }
    #[inline]
    fn shr(self, bits: u32) -> u32 {
        self >> bits
    }
    #[inline]
    fn and(self, o: u32) -> u32 {
        self & o
    }
    #[inline]
    fn select_ge(a: u32, b: u32, yes: u32, no: u32) -> u32 {
        if a >= b {
            yes
        } else {
            no
        }
    }
    #[inline]
    fn select_gt(a: u32, b: u32, yes: u32, no: u32) -> u32 {
        if a > b {
            yes
        } else {
            no
        }
    }
    #[inline]
    fn select_eq(a: u32, b: u32, yes: u32, no: u32) -> u32 {
        if a == b {
            yes
        } else {
            no
        }
    }
}

/// A 3-vector of [`Real`]s, for the net builders written once for the CPU (`f32`, with the
/// same operations in the same order as `glam::Vec3`, so the bits are `glam`'s) and the shaders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<T> {
    pub x: T,
    pub y: T,
    pub z: T,
}

impl<T: Real> V3<T> {
    pub fn new(x: T, y: T, z: T) -> V3<T> {
        V3 { x, y, z }
    }
    pub fn zero() -> V3<T> {
        let z = T::lit(0.0);
        V3::new(z, z, z)
    }
    /// `x·x' + y·y' + z·z'`, summed left to right.
    pub fn dot(self, o: V3<T>) -> T {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }
    pub fn length_squared(self) -> T {
        self.dot(self)
    }
    /// `self × o` in `glam`'s order of operations.
    pub fn cross(self, o: V3<T>) -> V3<T> {
        V3::new(
            self.y * o.z - o.y * self.z,
            self.z * o.x - o.z * self.x,
            self.x * o.y - o.x * self.y,
        )
    }
    /// `|self|`: the square root of [`V3::dot`] with itself.
    pub fn length(self) -> T {
        self.dot(self).sqrt()
    }
    /// `self · (1 / |self|)`, or `fallback` where that reciprocal is not finite and positive
    /// (as `glam`'s `normalize_or`).
    #[inline(always)]
    pub fn normalize_or(self, fallback: V3<T>) -> V3<T> {
        let rcp = T::lit(1.0) / self.length();
        V3::choose_positive_finite(rcp, || self * rcp, || fallback)
    }
    /// `nonzero()` where `test != 0`, else `zero()`, each component: a CPU number computes
    /// the side it keeps, a traced one records both and a selection.
    #[inline(always)]
    pub fn choose_nonzero(
        test: T,
        nonzero: impl FnOnce() -> V3<T>,
        zero: impl FnOnce() -> V3<T>,
    ) -> V3<T> {
        T::choose_nonzero(test, nonzero, zero, |t, a, b| {
            V3::new(
                T::select_nonzero(t, a.x, b.x),
                T::select_nonzero(t, a.y, b.y),
                T::select_nonzero(t, a.z, b.z),
            )
        })
    }
    /// `yes()` where `test` is finite and positive, else `no()`, as [`V3::choose_nonzero`].
    #[inline(always)]
    pub fn choose_positive_finite(
        test: T,
        yes: impl FnOnce() -> V3<T>,
        no: impl FnOnce() -> V3<T>,
    ) -> V3<T> {
        T::choose_positive_finite(test, yes, no, |t, a, b| {
            V3::new(
                T::select_positive_finite(t, a.x, b.x),
                T::select_positive_finite(t, a.y, b.y),
                T::select_positive_finite(t, a.z, b.z),
            )
        })
    }
    /// `self · (1 / |self|)`, or zero where that reciprocal is not finite and positive (as
    /// `glam::Vec3::normalize_or_zero`).
    #[inline(always)]
    pub fn normalize_or_zero(self) -> V3<T> {
        let rcp = T::lit(1.0) / self.dot(self).sqrt();
        V3::choose_positive_finite(rcp, || self * rcp, V3::zero)
    }
}

impl<T: Real> Add for V3<T> {
    type Output = V3<T>;
    fn add(self, o: V3<T>) -> V3<T> {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<T: Real> Sub for V3<T> {
    type Output = V3<T>;
    fn sub(self, o: V3<T>) -> V3<T> {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

/// `v · s`, each component.
impl<T: Real> Mul<T> for V3<T> {
    type Output = V3<T>;
    fn mul(self, s: T) -> V3<T> {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}

/// `v / s`, each component.
impl<T: Real> Div<T> for V3<T> {
    type Output = V3<T>;
    fn div(self, s: T) -> V3<T> {
        V3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl From<glam::Vec3> for V3<f32> {
    fn from(v: glam::Vec3) -> V3<f32> {
        V3::new(v.x, v.y, v.z)
    }
}

impl From<V3<f32>> for glam::Vec3 {
    fn from(v: V3<f32>) -> glam::Vec3 {
        glam::Vec3::new(v.x, v.y, v.z)
    }
}

impl From<glam::DVec3> for V3<f64> {
    fn from(v: glam::DVec3) -> V3<f64> {
        V3::new(v.x, v.y, v.z)
    }
}

impl From<V3<f64>> for glam::DVec3 {
    fn from(v: V3<f64>) -> glam::DVec3 {
        glam::DVec3::new(v.x, v.y, v.z)
    }
}

/// A number with its two partial derivatives along `u` (P1 → P2) and `v` (P1 → P3):
/// forward-mode differentiation, so a formula's `Du`, `Dv` are exact to rounding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual<T> {
    pub v: T,
    pub du: T,
    pub dv: T,
}

impl<T: Real> Dual<T> {
    /// A constant (zero derivatives).
    pub fn c(v: f64) -> Dual<T> {
        Dual {
            v: T::lit(v),
            du: T::lit(0.0),
            dv: T::lit(0.0),
        }
    }

    /// Barycentric `(l1, l2, l3)` as duals: `l1 = 1 − u − v`, `l2 = u`, `l3 = v` (the given
    /// values are kept, so exact zeros stay exact).
    pub fn barycentric(l: [T; 3]) -> [Dual<T>; 3] {
        let (one, zero) = (T::lit(1.0), T::lit(0.0));
        [
            Dual {
                v: l[0],
                du: -one,
                dv: -one,
            },
            Dual {
                v: l[1],
                du: one,
                dv: zero,
            },
            Dual {
                v: l[2],
                du: zero,
                dv: one,
            },
        ]
    }

    /// `s · self` for a constant `s`.
    pub fn scale(self, s: f64) -> Dual<T> {
        let s = T::lit(s);
        Dual {
            v: s * self.v,
            du: s * self.du,
            dv: s * self.dv,
        }
    }

    /// [`Real::select_nonzero`] on each part, by the value of `test`.
    pub fn select_nonzero(test: T, nonzero: Dual<T>, zero: Dual<T>) -> Dual<T> {
        Dual {
            v: T::select_nonzero(test, nonzero.v, zero.v),
            du: T::select_nonzero(test, nonzero.du, zero.du),
            dv: T::select_nonzero(test, nonzero.dv, zero.dv),
        }
    }
}

impl<T: Real> Add for Dual<T> {
    type Output = Dual<T>;
    fn add(self, o: Dual<T>) -> Dual<T> {
        Dual {
            v: self.v + o.v,
            du: self.du + o.du,
            dv: self.dv + o.dv,
        }
    }
}

impl<T: Real> Sub for Dual<T> {
    type Output = Dual<T>;
    fn sub(self, o: Dual<T>) -> Dual<T> {
        Dual {
            v: self.v - o.v,
            du: self.du - o.du,
            dv: self.dv - o.dv,
        }
    }
}

impl<T: Real> Mul for Dual<T> {
    type Output = Dual<T>;
    fn mul(self, o: Dual<T>) -> Dual<T> {
        Dual {
            v: self.v * o.v,
            du: self.du * o.v + self.v * o.du,
            dv: self.dv * o.v + self.v * o.dv,
        }
    }
}

impl<T: Real> Div for Dual<T> {
    type Output = Dual<T>;
    fn div(self, o: Dual<T>) -> Dual<T> {
        let q = self.v / o.v;
        Dual {
            v: q,
            du: (self.du - q * o.du) / o.v,
            dv: (self.dv - q * o.dv) / o.v,
        }
    }
}

/// What the displacement offsets (Perlin noise, a height map's bilinear sample, a sine) and a
/// grid point's geomorph (`refine::grid_point`) need beyond [`Real`]: floors and sines,
/// integer lattice coordinates and grid steps as [`Word`]s, and branches on those words
/// (Perlin's gradient hash, which edge a grid point lies on). `f32` or `f64` with `u32` on the
/// CPU; traced when a shader is generated.
pub trait Noise: Real {
    /// The word type its lattice coordinates are.
    type W: Word;
    fn floor(self) -> Self;
    fn sin(self) -> Self;
    /// A whole value (already floored) as an `i32`, its bits as a word: `x as i32 as u32`.
    fn int_word(self) -> Self::W;
    /// A word's value as a number: `w as f32` (a grid step over its segment count, say).
    fn from_word(w: Self::W) -> Self;
    /// `yes` where `a >= b`, else `no`; both sides are computed.
    fn pick_ge(a: Self::W, b: Self::W, yes: Self, no: Self) -> Self;
    /// `yes` where `a == b`, else `no`; both sides are computed.
    fn pick_eq(a: Self::W, b: Self::W, yes: Self, no: Self) -> Self;
    /// `yes` where `a > b` (false for NaN), else `no`; both sides are computed.
    fn pick_gt(a: Self, b: Self, yes: Self, no: Self) -> Self;
    /// The word `yes` where `a == b`, else `no`.
    fn word_if_eq(a: Self, b: Self, yes: Self::W, no: Self::W) -> Self::W;
}

/// `f32` (displacement) and `f64` (PNG1's nets) with `u32` words; a branch is an `if`.
macro_rules! noise_float {
    ($t:ty) => {
        impl Noise for $t {
            type W = u32;
            #[inline]
            fn floor(self) -> $t {
                <$t>::floor(self)
            }
            #[inline]
            fn sin(self) -> $t {
                <$t>::sin(self)
            }
            #[inline]
            fn int_word(self) -> u32 {
                self as i32 as u32
            }
            #[inline]
            fn from_word(w: u32) -> $t {
                w as $t
            }
            #[inline]
            fn pick_ge(a: u32, b: u32, yes: $t, no: $t) -> $t {
                if a >= b {
                    yes
                } else {
                    no
                }
            }
            #[inline]
            fn pick_eq(a: u32, b: u32, yes: $t, no: $t) -> $t {
                if a == b {
                    yes
                } else {
                    no
                }
            }
            #[inline]
            fn pick_gt(a: $t, b: $t, yes: $t, no: $t) -> $t {
                if a > b {
                    yes
                } else {
                    no
                }
            }
            #[inline]
            fn word_if_eq(a: $t, b: $t, yes: u32, no: u32) -> u32 {
                if a == b {
                    yes
                } else {
                    no
                }
            }
        }
    };
}

noise_float!(f32);
noise_float!(f64);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn select_nonzero_keeps_the_side_an_if_would() {
        assert_eq!(f64::select_nonzero(2.0, 1.0, 3.0), 1.0);
        assert_eq!(f64::select_nonzero(0.0, f64::NAN, 3.0), 3.0);
        assert_eq!(f64::select_nonzero(-0.0, f64::INFINITY, 3.0), 3.0);
    }

    #[test]
    fn dual_products_and_quotients_differentiate() {
        // f(u, v) = l2 · l3 / l1 at (l1, l2, l3) = (0.5, 0.2, 0.3).
        let [a, b, c] = Dual::barycentric([0.5, 0.2, 0.3]);
        let f = b * c / a;
        let g = |u: f64, v: f64| u * v / (1.0 - u - v);
        let h = 1e-6;
        assert!((f.v - g(0.2, 0.3)).abs() < 1e-15);
        assert!((f.du - (g(0.2 + h, 0.3) - g(0.2 - h, 0.3)) / (2.0 * h)).abs() < 1e-8);
        assert!((f.dv - (g(0.2, 0.3 + h) - g(0.2, 0.3 - h)) / (2.0 * h)).abs() < 1e-8);
    }
}
