//! Unsigned 16.16 fixed-point numbers, the arithmetic the D3D11 reference tessellator (and so
//! Mesa's GL tessellator) does all placement in.
//!
//! A value `x` is stored as the `u32` `round(x · 2¹⁶)`. Everything here mirrors the reference's
//! integer operations bit for bit, including its wrapping `u32` arithmetic.

/// Fractional bits.
pub const FRACTION_BITS: u32 = 16;
/// 1.0
pub const ONE: u32 = 1 << FRACTION_BITS;
/// 0.5
pub const ONE_HALF: u32 = ONE / 2;
/// 1/3, truncated (0x5555): the centre point of an even inner ring.
pub const ONE_THIRD: u32 = 0x5555;
/// 2/3, truncated (0xaaaa): the scale from a 1D position to an inner ring's distance from its edge.
pub const TWO_THIRDS: u32 = 0xaaaa;

use crate::scalar::{Noise, Word};

const FRACTION_MASK: u32 = ONE - 1;
const INTEGER_MASK: u32 = 0x7fff_0000;

/// `1/n` in 16.16 for `n` segments, `n = 1..=64`, as the hardware's table holds it (rounded to
/// nearest; entry 0 is unused), the reference tessellator's table.
pub const RECIPROCAL: [u32; 65] = [
    0xffff_ffff, // 1/0, never used
    0x10000,
    0x8000,
    0x5555,
    0x4000,
    0x3333,
    0x2aab,
    0x2492,
    0x2000, //
    0x1c72,
    0x199a,
    0x1746,
    0x1555,
    0x13b1,
    0x1249,
    0x1111,
    0x1000, //
    0xf0f,
    0xe39,
    0xd79,
    0xccd,
    0xc31,
    0xba3,
    0xb21,
    0xaab, //
    0xa3d,
    0x9d9,
    0x97b,
    0x925,
    0x8d4,
    0x889,
    0x842,
    0x800, //
    0x7c2,
    0x788,
    0x750,
    0x71c,
    0x6eb,
    0x6bd,
    0x690,
    0x666, //
    0x63e,
    0x618,
    0x5f4,
    0x5d1,
    0x5b0,
    0x591,
    0x572,
    0x555, //
    0x539,
    0x51f,
    0x505,
    0x4ec,
    0x4d5,
    0x4be,
    0x4a8,
    0x492, //
    0x47e,
    0x46a,
    0x457,
    0x444,
    0x432,
    0x421,
    0x410,
    0x400, //
];

/// `f32` to unsigned 15.16 fixed point: round to nearest, ties to even; NaN and values ≤ 0 give
/// 0, values from 2¹⁵ up saturate to `u32::MAX` (the reference's `floatToFixed`).
pub fn from_f32(x: f32) -> u32 {
    if x.is_nan() || x <= 0.0 {
        0
    } else if x >= 32768.0 {
        u32::MAX
    } else {
        // x · 2¹⁶ is exact in f64 (24 significant bits), so one rounding, as in the reference.
        (f64::from(x) * f64::from(ONE)).round_ties_even() as u32
    }
}

/// The exact value of a 16.16 number (the patterns take theirs from [`barycentric_of`]).
#[cfg(test)]
pub fn to_f64(x: u32) -> f64 {
    f64::from(x) / f64::from(ONE)
}

/// The barycentric point `(u, v, 1 − u − v)` of a pattern point at 16.16 `(u, v)` (`u + v ≤ 1`),
/// each coordinate exact, for any [`Noise`] number: the CPU's patterns in `f64`, and traced for
/// the adaptive shaders, which place the point in 16.16 (`crate::shader::tessellator_point`).
pub fn barycentric_of<R: Noise>(u: R::W, v: R::W) -> [R; 3] {
    let w = R::W::lit(ONE).wsub(u).wsub(v);
    let scale = R::lit(f64::from(ONE));
    [u, v, w].map(|x| R::from_word(x) / scale)
}

/// Smallest integer ≥ `x` (in 16.16).
pub fn ceil(x: u32) -> u32 {
    if x & FRACTION_MASK != 0 {
        (x & INTEGER_MASK).wrapping_add(ONE)
    } else {
        x
    }
}

/// Largest integer ≤ `x` (in 16.16).
pub fn floor(x: u32) -> u32 {
    x & INTEGER_MASK
}

/// `v` without its most significant set bit (0 stays 0). Applied to a half-level count, this is
/// the step of the ruler function that says where the next pair of points splits off.
pub fn remove_msb(v: u32) -> u32 {
    if v == 0 {
        0
    } else {
        v & !(1 << (31 - v.leading_zeros()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversion_rounds_to_nearest_even() {
        assert_eq!(from_f32(1.0), ONE);
        assert_eq!(from_f32(64.0), 64 << 16);
        assert_eq!(from_f32(f32::NAN), 0);
        assert_eq!(from_f32(-3.0), 0);
        assert_eq!(from_f32(1e9), u32::MAX);
        // 1 + 2⁻¹⁷ is exactly half an ulp above 1: ties to the even neighbour, 1.
        assert_eq!(from_f32(1.0 + 2f32.powi(-17)), ONE);
        // 1 + 3·2⁻¹⁷ is halfway between 1 + 2⁻¹⁶ (odd) and 1 + 2·2⁻¹⁶ (even).
        assert_eq!(from_f32(1.0 + 3.0 * 2f32.powi(-17)), ONE + 2);
    }

    #[test]
    fn reciprocals_are_within_half_an_ulp() {
        for (n, &r) in RECIPROCAL.iter().enumerate().skip(1) {
            let exact = 65536.0 / n as f64;
            assert!((r as f64 - exact).abs() <= 0.5, "1/{n}");
        }
    }

    #[test]
    fn msb_removal() {
        assert_eq!(remove_msb(0), 0);
        assert_eq!(remove_msb(1), 0);
        assert_eq!(remove_msb(6), 2);
        assert_eq!(remove_msb(31), 15);
        assert_eq!(remove_msb(32), 0);
        assert_eq!(ceil(ONE + 1), 2 * ONE);
        assert_eq!(floor(2 * ONE - 1), ONE);
    }
}
