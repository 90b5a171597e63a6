//! Point placement along one level: the 1D "ruler" every edge and every inner ring uses.
//!
//! A level `f` (16.16) with a parity is split in two mirrored halves. Each half is laid out twice,
//! with `floor(h)` and `ceil(h)` segments where `h` is the half-level, and a point's position is
//! the lerp between the two layouts by `frac(h)`: as `f` grows, one pair of points (one per half)
//! grows out of a zero-length segment. Which segment splits is chosen by a ruler function (the
//! half-level without its top bit), so successive splits spread from the ends inward rather than
//! all crowding at one place.

use super::fixed::{self, ONE, ONE_HALF, RECIPROCAL};
use crate::scalar::Word;

/// `u32` words of one ruler as the GPU reads it ([`Ruler::words`]).
pub(crate) const RULER_WORDS: usize = 5;
/// The word of [`Ruler::words`] that packs `half_points | odd << 8 | points << 16`.
pub(crate) const RULER_PACKED_WORD: usize = 4;
/// Where the packed word holds the odd parity bit (half points below it, 8 bits).
pub(crate) const RULER_ODD_SHIFT: u32 = 8;
/// Where the packed word holds the layout's point count.
pub(crate) const RULER_POINTS_SHIFT: u32 = 16;

/// Per-level constants for placing points (the reference's `TESS_FACTOR_CONTEXT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ruler {
    /// Odd parity: an odd number of segments, a middle segment rather than a middle point.
    pub odd: bool,
    /// 1 / segments of the floor layout (16.16, from the hardware's table).
    inv_floor: u32,
    /// 1 / segments of the ceil layout.
    inv_ceil: u32,
    /// frac(half-level): 0 is the floor layout, 1 the ceil layout.
    fraction: u32,
    /// Points in one half, the middle point of an even level not counted.
    pub half_points: u32,
    /// Index (on the ceil layout) of the point that is new in the ceil layout; beyond it, floor
    /// indices lag by one. Larger than any index when floor = ceil.
    split: u32,
}

impl Ruler {
    /// Constants for level `level` (16.16, already clamped) with parity `odd`.
    pub fn new(level: u32, odd: bool) -> Ruler {
        // The reference adds one before halving so the halving rounds up.
        let mut half = level.wrapping_add(1) / 2;
        // A level of exactly 1 with even parity (equal spacing's inner 1) is treated as 2.
        if odd || half == ONE_HALF {
            half += ONE_HALF;
        }
        let floor = fixed::floor(half);
        let ceil = fixed::ceil(half);
        let half_points = ceil >> fixed::FRACTION_BITS;
        let split = if floor == ceil {
            half_points + 1
        } else if odd {
            if floor == ONE {
                0
            } else {
                (fixed::remove_msb((floor >> fixed::FRACTION_BITS) - 1) << 1) + 1
            }
        } else {
            (fixed::remove_msb(floor >> fixed::FRACTION_BITS) << 1) + 1
        };
        let mut floor_segments = (floor * 2) >> fixed::FRACTION_BITS;
        let mut ceil_segments = (ceil * 2) >> fixed::FRACTION_BITS;
        if odd {
            floor_segments -= 1;
            ceil_segments -= 1;
        }
        Ruler {
            odd,
            inv_floor: RECIPROCAL[floor_segments as usize],
            inv_ceil: RECIPROCAL[ceil_segments as usize],
            fraction: half - floor,
            half_points,
            split,
        }
    }

    /// The constants as the GPU reads them (`shaders/adaptive.wgsl`'s `place`): `1/floor`,
    /// `1/ceil`, the fraction, the split index, then `half_points | odd << 8 | points << 16`
    /// with `points` the caller's point count of the layout.
    pub fn words(&self, points: u32) -> [u32; RULER_WORDS] {
        debug_assert!(
            self.half_points < 1 << RULER_ODD_SHIFT,
            "levels are at most 64"
        );
        [
            self.inv_floor,
            self.inv_ceil,
            self.fraction,
            self.split,
            self.half_points
                | u32::from(self.odd) << RULER_ODD_SHIFT
                | points << RULER_POINTS_SHIFT,
        ]
    }

    /// Position of point `point` (0 = start, 16.16 in `[0, 1]`). The second half is the first
    /// mirrored, `1 − t` computed exactly, so both directions along an edge agree bit for bit.
    pub fn place(&self, point: u32) -> u32 {
        place_of(self.words(0), point)
    }
}

/// [`Ruler::place`] from the ruler's words ([`Ruler::words`]), for any [`Word`]: the CPU's
/// `u32` and the adaptive renderer's generated shader code (`tessella_core::shader`) run this
/// one function. Branches are selections, both sides computed (wrapping, so harmless).
pub(crate) fn place_of<W: Word>(words: [W; RULER_WORDS], point: W) -> W {
    let [inv_floor, inv_ceil, fraction, split, packed] = words;
    let half = packed.and(W::lit((1 << RULER_ODD_SHIFT) - 1));
    let odd = packed.shr(RULER_ODD_SHIFT).and(W::lit(1));
    let one = W::lit(ONE);
    // The second half is the first mirrored.
    let p = W::select_ge(point, half, half.wadd(half).wsub(point).wsub(odd), point);
    let on_floor = W::select_gt(p, split, p.wsub(W::lit(1)), p);
    let floor_pos = on_floor.wmul(inv_floor);
    let ceil_pos = p.wmul(inv_ceil);
    let lerp = floor_pos
        .wmul(one.wsub(fraction))
        .wadd(ceil_pos.wmul(fraction));
    let t = lerp.wadd(W::lit(ONE_HALF)).shr(fixed::FRACTION_BITS);
    let placed = W::select_ge(point, half, one.wsub(t), t);
    // The middle of an even level: exactly 1/2 (the lerp cannot reach it).
    W::select_eq(p, half, W::lit(ONE_HALF), placed)
}

/// Points on a level's 1D layout, both ends included (the reference's `NumPointsForTessFactor`).
pub fn point_count(level: u32, odd: bool) -> u32 {
    let half = level.wrapping_add(1) / 2;
    if odd {
        (fixed::ceil(ONE_HALF + half) * 2) >> fixed::FRACTION_BITS
    } else {
        ((fixed::ceil(half) * 2) >> fixed::FRACTION_BITS) + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(level: f32, odd: bool) -> Vec<f64> {
        let l = fixed::from_f32(level);
        let r = Ruler::new(l, odd);
        (0..point_count(l, odd))
            .map(|p| fixed::to_f64(r.place(p)))
            .collect()
    }

    #[test]
    fn integer_levels_are_even_layouts() {
        assert_eq!(layout(2.0, false), [0.0, 0.5, 1.0]);
        assert_eq!(layout(4.0, false), [0.0, 0.25, 0.5, 0.75, 1.0]);
        assert_eq!(layout(1.0, true), [0.0, 1.0]);
        // 1/3 is 0x5555 / 2¹⁶ from the table, 2/3 its mirror.
        let third = 21845.0 / 65536.0;
        assert_eq!(layout(3.0, true), [0.0, third, 1.0 - third, 1.0]);
    }

    #[test]
    fn fractional_odd_one_and_a_half() {
        // Odd 1.5: half-level 1.25 → floor 1 (one segment), ceil 2 (three segments), fraction
        // 1/4. The new point pair starts at the ends: point 1 lerps from 0 (floor layout) to 1/3
        // (ceil layout) by 1/4: 0x5555 · 0x4000 / 2¹⁶ rounded = 0x1555 (≈ 1/12).
        let t = 0x1555 as f64 / 65536.0;
        assert_eq!(layout(1.5, true), [0.0, t, 1.0 - t, 1.0]);
    }
}
