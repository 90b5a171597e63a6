//! Turning large arrays into file bytes quickly. Writers used to hand the output one 4-byte
//! value at a time through `dyn Write` (about 0.4 GB/s); here records are encoded into blocks of
//! about a megabyte, in parallel where encoding costs more than copying (text), and each block
//! is written with one call. Blocks are written in order, and at most a few are held at once,
//! so memory stays small whatever the mesh size.

use rayon::prelude::*;
use std::io::Write;

/// Bytes per block handed to the writer.
const BLOCK_BYTES: usize = 1 << 20;

/// Writes `values` as little-endian bytes. On little-endian machines the memory already is the
/// file's bytes and is written as it is.
pub fn write_le<T: bytemuck::Pod + ToLe>(out: &mut dyn Write, values: &[T]) -> std::io::Result<()> {
    if cfg!(target_endian = "little") {
        return out.write_all(bytemuck::cast_slice(values));
    }
    let per_block = (BLOCK_BYTES / std::mem::size_of::<T>()).max(1);
    let mut block = Vec::with_capacity(per_block * std::mem::size_of::<T>());
    for chunk in values.chunks(per_block) {
        block.clear();
        chunk.iter().for_each(|v| v.push_le(&mut block));
        out.write_all(&block)?;
    }
    Ok(())
}

/// Values that append their little-endian bytes to a buffer.
pub trait ToLe: Copy {
    fn push_le(self, out: &mut Vec<u8>);
}

impl ToLe for f32 {
    #[inline(always)]
    fn push_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
impl ToLe for u32 {
    #[inline(always)]
    fn push_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
impl ToLe for i32 {
    #[inline(always)]
    fn push_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
impl<T: ToLe, const N: usize> ToLe for [T; N] {
    #[inline(always)]
    fn push_le(self, out: &mut Vec<u8>) {
        self.into_iter().for_each(|v| v.push_le(out));
    }
}

/// Writes `count` records, record `i` encoded by `encode(i, buffer)` (which appends about
/// `record_bytes` bytes), in parallel blocks written in order. Meant for both binary records
/// (a PLY vertex) and lines of text (an OBJ `v` line), where encoding is the cost.
pub fn write_records(
    out: &mut dyn Write,
    count: usize,
    record_bytes: usize,
    encode: impl Fn(usize, &mut Vec<u8>) + Sync,
) -> std::io::Result<()> {
    in_blocks(out, count, record_bytes, |block, records| {
        block.clear();
        block.reserve(records.len() * record_bytes);
        records.for_each(|i| encode(i, block));
    })
}

/// Writes `count` records of exactly `record_bytes` bytes each (binary records: a PLY vertex
/// or face, an STL facet), record `i` written by `encode(i, slot)` into its own slot of a
/// block, in parallel blocks written in order. Storing into fixed slots costs a few
/// instructions a value; appending to a `Vec` (what [`write_records`] does for text, whose
/// records vary in length) checks and grows the length at every value.
pub fn write_fixed_records(
    out: &mut dyn Write,
    count: usize,
    record_bytes: usize,
    encode: impl Fn(usize, &mut [u8]) + Sync,
) -> std::io::Result<()> {
    let record_bytes = record_bytes.max(1);
    in_blocks(out, count, record_bytes, |block, records| {
        // Every byte of every slot is written below: the zeros are only filled once.
        block.resize(records.len() * record_bytes, 0);
        for (i, slot) in records.zip(block.chunks_exact_mut(record_bytes)) {
            encode(i, slot);
        }
    })
}

/// The rounds both record writers share: blocks of about [`BLOCK_BYTES`] (records of about
/// `record_bytes`), a few per thread filled at once by `fill(block, its records)`, then
/// written in order; the blocks' memory is reused from round to round.
fn in_blocks(
    out: &mut dyn Write,
    count: usize,
    record_bytes: usize,
    fill: impl Fn(&mut Vec<u8>, std::ops::Range<usize>) + Sync,
) -> std::io::Result<()> {
    let per_block = (BLOCK_BYTES / record_bytes.max(1)).max(1);
    let per_round = per_block * 2 * rayon::current_num_threads().max(1);
    let mut blocks: Vec<Vec<u8>> = Vec::new();
    for round in (0..count).step_by(per_round) {
        let end = (round + per_round).min(count);
        let starts: Vec<usize> = (round..end).step_by(per_block).collect();
        blocks.resize_with(starts.len().max(blocks.len()), Vec::new);
        blocks[..starts.len()]
            .par_iter_mut()
            .zip(&starts)
            .for_each(|(block, &start)| fill(block, start..(start + per_block).min(end)));
        for block in &blocks[..starts.len()] {
            out.write_all(block)?;
        }
    }
    Ok(())
}

/// Fills a record slot with 4-byte little-endian words, one `put` at a time (panics if the
/// record holds more words than the slot: a writer's size bug).
pub struct Words<'a>(std::slice::ChunksExactMut<'a, u8>);

impl<'a> Words<'a> {
    pub fn new(slot: &'a mut [u8]) -> Words<'a> {
        Words(slot.chunks_exact_mut(4))
    }
    #[inline(always)]
    pub fn put(&mut self, bytes: [u8; 4]) {
        self.0
            .next()
            .expect("the record's size counts every word")
            .copy_from_slice(&bytes);
    }
    #[inline(always)]
    pub fn floats<const N: usize>(&mut self, values: [f32; N]) {
        values.iter().for_each(|x| self.put(x.to_le_bytes()));
    }
}

/// Appends the shortest decimal text that reads back as the same `f32` (`1`, `0.5`, `1e-7`;
/// exponents as `e-7`/`e+20`, which every OBJ and PLY reader parses). NaN and infinities, which
/// the writers refuse before they start, would print as `NaN`, `inf`, `-inf`.
#[inline]
pub fn push_f32(out: &mut Vec<u8>, x: f32) {
    if x.is_finite() {
        let mut buffer = zmij::Buffer::new();
        let text = buffer.format_finite(x);
        // zmij writes integers as `1.0`; the trailing `.0` is noise in a mesh file.
        out.extend_from_slice(text.strip_suffix(".0").unwrap_or(text).as_bytes());
    } else {
        out.extend_from_slice(x.to_string().as_bytes());
    }
}

/// Appends the decimal text of an integer.
#[inline]
pub fn push_int(out: &mut Vec<u8>, i: impl itoa::Integer) {
    out.extend_from_slice(itoa::Buffer::new().format(i).as_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_back_exactly_and_print_short() {
        let mut seed = 1u32;
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -2.0,
            0.5,
            1e-7,
            3.4e38,
            f32::MIN_POSITIVE,
            1e-45,
        ];
        for _ in 0..10_000 {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            let x = f32::from_bits(seed);
            if x.is_finite() {
                values.push(x);
            }
        }
        for x in values {
            let mut out = Vec::new();
            push_f32(&mut out, x);
            let text = std::str::from_utf8(&out).unwrap();
            let back: f32 = text.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} printed as {text}");
            // Shortest digits, and short text: `-1.2345678e-38` and `-0.0000023670093` are
            // the longest kinds.
            assert!(text.len() <= 16, "{x:e} printed as {text}");
        }
        let text = |x: f32| {
            let mut out = Vec::new();
            push_f32(&mut out, x);
            String::from_utf8(out).unwrap()
        };
        assert_eq!(text(1.0), "1");
        assert_eq!(text(0.25), "0.25");
        assert_eq!(text(-3.0), "-3");
    }

    #[test]
    fn records_come_out_in_order_whatever_the_block_size() {
        for (count, record_bytes) in [(0, 8), (1, 8), (1000, 1 << 19), (300_000, 4)] {
            let mut out = Vec::new();
            write_records(&mut out, count, record_bytes, |i, b| {
                b.extend_from_slice(&(i as u32).to_le_bytes())
            })
            .unwrap();
            let want: Vec<u8> = (0..count as u32).flat_map(u32::to_le_bytes).collect();
            assert_eq!(out, want, "{count} records of {record_bytes} bytes");
        }
    }

    #[test]
    fn little_endian_arrays_match_per_value_encoding() {
        let values: Vec<[f32; 3]> = (0..5000)
            .map(|i| [i as f32, -0.5 * i as f32, 1e-3])
            .collect();
        let mut fast = Vec::new();
        write_le(&mut fast, &values).unwrap();
        let slow: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        assert_eq!(fast, slow);
    }
}
