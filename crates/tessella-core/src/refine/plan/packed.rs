//! The adaptive record packed for hosts that read it from a texture (WebGL2 has no storage
//! buffers): of a record's [`RECORD_WORDS`](super::instanced::RECORD_WORDS) words the
//! tessellator's placement reads 21 (four rulers of five words and the canonical edge bits);
//! they pack into [`PACKED_WORDS`], three `RGBA32UI` texels a face, so that a frame uploads 48
//! bytes of records a coarse triangle. The shaders' reader ([`crate::shader::packed_record`])
//! is traced from `ruler_word_of` and `forward_bits_of`, the functions that give the words back
//! here ([`ruler_word`], [`forward_bits`]).

use super::instanced::FORWARD_WORD;
use crate::scalar::Word;
use crate::tessellator::points::{RULER_ODD_SHIFT, RULER_POINTS_SHIFT, RULER_WORDS};

/// Words of a packed record: three per ruler.
pub const PACKED_WORDS: usize = 12;
/// Bits of a 16.16 value in `[0, 1]` (1.0 is `1 << 16`).
const FIXED_BITS: u32 = 17;
const FIXED_MASK: u32 = (1 << FIXED_BITS) - 1;
/// Where a ruler's half-point count sits in its first word, above its 16.16 value and split.
const HALF_SHIFT: u32 = 24;
/// A ruler's split, between its 16.16 value and its half-point count.
const SPLIT_MASK: u32 = (1 << (HALF_SHIFT - FIXED_BITS)) - 1;
/// Where the canonical edge bits sit in ruler 0's third word (above its fraction and odd bit).
pub const PACKED_FORWARD_SHIFT: u32 = FIXED_BITS + 1;

/// Packs a record's four rulers and canonical bits into [`PACKED_WORDS`] words. Ruler `r`'s five
/// words `[inv_floor, inv_ceil, fraction, split, half | odd << 8 | points << 16]` become
/// `inv_floor | split << 17 | half << 24`, `inv_ceil | points << 17`, `fraction | odd << 17`;
/// the canonical bits go above ruler 0's third word (`<< PACKED_FORWARD_SHIFT`). Every 16.16
/// value is at most 1.0 (17 bits), `split` below 128, `half` below 256 (levels are at most 64).
pub fn pack_record(record: &[u32]) -> [u32; PACKED_WORDS] {
    let mut out = [0u32; PACKED_WORDS];
    for r in 0..4 {
        let w = &record[RULER_WORDS * r..RULER_WORDS * (r + 1)];
        let half = w[4] & ((1 << RULER_ODD_SHIFT) - 1);
        let odd = (w[4] >> RULER_ODD_SHIFT) & 1;
        let points = w[4] >> RULER_POINTS_SHIFT;
        debug_assert!(
            w[..3].iter().all(|&x| x <= FIXED_MASK) && w[3] <= SPLIT_MASK && points < 1 << 15
        );
        out[3 * r] = w[0] | w[3] << FIXED_BITS | half << HALF_SHIFT;
        out[3 * r + 1] = w[1] | points << FIXED_BITS;
        out[3 * r + 2] = w[2] | odd << FIXED_BITS;
    }
    out[2] |= record[FORWARD_WORD] << PACKED_FORWARD_SHIFT;
    out
}

/// Word `k` of a ruler from its three packed words `a`, `b`, `c`: what [`pack_record`] packed,
/// given back (the fields of the last word do not overlap, so they add).
pub(crate) fn ruler_word_of<W: Word>(a: W, b: W, c: W, k: W) -> W {
    let fixed = W::lit(FIXED_MASK);
    let split = a.shr(FIXED_BITS).and(W::lit(SPLIT_MASK));
    let packed = a
        .shr(HALF_SHIFT)
        .wadd(
            c.shr(FIXED_BITS)
                .and(W::lit(1))
                .wmul(W::lit(1 << RULER_ODD_SHIFT)),
        )
        .wadd(b.shr(FIXED_BITS).wmul(W::lit(1 << RULER_POINTS_SHIFT)));
    let words = [a.and(fixed), b.and(fixed), c.and(fixed), split];
    // Word 4 where `k` is none of 0 to 3.
    (0..words.len()).rev().fold(packed, |other, i| {
        W::select_eq(k, W::lit(i as u32), words[i], other)
    })
}

/// The canonical edge bits from ruler 0's third packed word.
pub(crate) fn forward_bits_of<W: Word>(c: W) -> W {
    c.shr(PACKED_FORWARD_SHIFT)
}

/// Word `k` of ruler `r` of a packed record, as the shaders read it.
pub fn ruler_word(packed: &[u32; PACKED_WORDS], r: usize, k: usize) -> u32 {
    let [a, b, c] = [packed[3 * r], packed[3 * r + 1], packed[3 * r + 2]];
    ruler_word_of(a, b, c, k as u32)
}

/// The canonical edge bits of a packed record, as the shaders read them.
pub fn forward_bits(packed: &[u32; PACKED_WORDS]) -> u32 {
    forward_bits_of(packed[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Mesh, Topology};
    use crate::refine::instanced::{frame_instances, PartTable, RECORD_WORDS};
    use crate::refine::Spacing;

    /// Every word the placement reads comes back from the packed record, for every spacing
    /// and a sweep of levels up to 65 (clamped to 64).
    #[test]
    fn packed_records_give_back_every_word_the_placement_reads() {
        let mesh = crate::samples::by_name("icosphere").expect("a bundled sample");
        let topology = Topology::new(&mesh);
        for spacing in [
            Spacing::Equal,
            Spacing::FractionalOdd,
            Spacing::FractionalEven,
        ] {
            let table = PartTable::new(spacing);
            for step in 0..=252 {
                let level = 1.0 + step as f32 / 4.0;
                let levels: Vec<f32> = (0..topology.edges.len())
                    .map(|e| 1.0 + ((level - 1.0) + e as f32 * 0.7) % 64.0)
                    .collect();
                let frame = frame_instances(
                    &table,
                    &topology,
                    Mesh::triangles(&mesh),
                    &topology.position_ids,
                    &levels,
                    None,
                )
                .expect("levels in range");
                for record in frame.records.chunks_exact(RECORD_WORDS) {
                    let packed = pack_record(record);
                    for (i, &word) in record[..4 * RULER_WORDS].iter().enumerate() {
                        assert_eq!(ruler_word(&packed, i / RULER_WORDS, i % RULER_WORDS), word);
                    }
                    assert_eq!(forward_bits(&packed), record[FORWARD_WORD]);
                }
            }
        }
    }
}
