//! Copies into the caller's output with non-temporal (streaming) stores, for outputs larger
//! than the last-level cache. A plain store to a line that is not cached first reads the line
//! from memory (read for ownership), so writing a large output moves its bytes twice; a
//! streaming store writes whole lines without reading them. On this project's 2-core machine
//! a two-thread fill ran at 29 GB/s with plain stores and 39 GB/s with streaming ones. Outputs
//! that fit in the cache keep plain stores: the caller reads the vertices next, from cache.
//!
//! Only whole 64-byte lines are streamed. A run's last partial line is held back
//! ([`LineCarry`]) until the next run completes it; a partial line nobody completes (the end
//! of a task's slots, whose line another thread may share) is written with plain stores. The
//! values are the same either way: only how the bytes travel to memory changes.

/// Outputs of more bytes than this are written with streaming stores: twice the 32 MiB
/// last-level cache of the machine this was measured on, where a frame of 63 MB still ran
/// faster with plain stores (part of it stays cached from the frame before) and one of 98 MB
/// already ran faster streamed.
pub(crate) const STREAM_ABOVE_BYTES: usize = 32 << 20;

/// Bytes in a cache line.
const LINE: usize = 64;
/// `f32`s in a cache line.
const LINE_FLOATS: usize = LINE / 4;

/// A streamed array's last line, not yet written: the floats of a run that stopped short of a
/// line's end. The next run usually continues where this one stopped (a task writes its
/// blocks in slot order), so the line is completed and streamed whole then, instead of being
/// written in two parts with plain stores, each of which would first read the line. One per
/// streamed array of a sink; [`LineCarry::flush`] writes what is left with plain stores.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineCarry {
    /// Index (in the array) of the line's first float: always the start of a cache line.
    start: usize,
    len: usize,
    buf: [f32; LINE_FLOATS],
}

impl LineCarry {
    pub const fn new() -> LineCarry {
        LineCarry {
            start: 0,
            len: 0,
            buf: [0.0; LINE_FLOATS],
        }
    }

    /// True when nothing is held back.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// `dst[at..at + src.len()] = src`: the whole cache lines with streaming stores, a run's
    /// first partial line with plain ones, its last partial line held back for the next run
    /// (written once that run completes it, or by [`LineCarry::flush`]). `dst` must be the
    /// same array at every call until the flush. Call [`fence`] after the flush before another
    /// thread may read `dst`.
    #[inline(always)]
    pub fn write(&mut self, dst: &mut [f32], at: usize, src: &[f32]) {
        assert!(at + src.len() <= dst.len(), "a run within the array");
        if self.len > 0 && self.start + self.len != at {
            self.flush(dst);
        }
        let (mut at, mut src) = (at, src);
        if self.len > 0 {
            let take = (LINE_FLOATS - self.len).min(src.len());
            self.buf[self.len..self.len + take].copy_from_slice(&src[..take]);
            self.len += take;
            (at, src) = (at + take, &src[take..]);
            if self.len < LINE_FLOATS {
                return;
            }
            let line = self.buf;
            stream_lines(&mut dst[self.start..self.start + LINE_FLOATS], &line);
            self.len = 0;
        } else {
            // f32s are 4-byte aligned, so the distance to the next line is whole floats.
            let misalign = (dst.as_ptr() as usize + 4 * at) % LINE;
            let head = ((LINE - misalign) % LINE / 4).min(src.len());
            dst[at..at + head].copy_from_slice(&src[..head]);
            (at, src) = (at + head, &src[head..]);
        }
        let whole = src.len() / LINE_FLOATS * LINE_FLOATS;
        stream_lines(&mut dst[at..at + whole], &src[..whole]);
        let rest = src.len() - whole;
        if rest > 0 {
            self.start = at + whole;
            self.len = rest;
            self.buf[..rest].copy_from_slice(&src[whole..]);
        }
    }

    /// Writes the held-back floats with plain stores.
    #[inline(always)]
    pub fn flush(&mut self, dst: &mut [f32]) {
        if self.len > 0 {
            dst[self.start..self.start + self.len].copy_from_slice(&self.buf[..self.len]);
            self.len = 0;
        }
    }
}

/// Copies the first `min(dst.len(), src.len())` floats of `src` into `dst` and returns how
/// many: the cache lines wholly inside that part of `dst` with streaming stores (the widest the
/// CPU has), its partial first and last lines with plain ones, then a fence (`sfence`). The
/// benchmarks' bandwidth baseline (feature `bandwidth`): the same stores as the evaluator's
/// sinks.
#[cfg(feature = "bandwidth")]
pub fn stream_copy(dst: &mut [f32], src: &[f32]) -> usize {
    let n = dst.len().min(src.len());
    let (dst, src) = (&mut dst[..n], &src[..n]);
    let (head, body) = whole_lines(dst);
    dst[..head].copy_from_slice(&src[..head]);
    stream_lines(&mut dst[head..head + body], &src[head..head + body]);
    dst[head + body..].copy_from_slice(&src[head + body..]);
    fence();
    n
}

/// Writes `value` over `dst` as [`stream_copy`] writes: whole lines streamed, then a fence
/// (feature `bandwidth`).
#[cfg(feature = "bandwidth")]
pub fn stream_fill(dst: &mut [f32], value: f32) {
    let (head, body) = whole_lines(dst);
    dst[..head].fill(value);
    dst[head + body..].fill(value);
    // A source of whole lines, copied over the body a chunk at a time.
    let src = [value; 64 * LINE_FLOATS];
    for chunk in dst[head..head + body].chunks_mut(src.len()) {
        let n = chunk.len();
        stream_lines(chunk, &src[..n]);
    }
    fence();
}

/// `(floats before the first cache line of dst, floats in its whole lines)`.
#[cfg(feature = "bandwidth")]
fn whole_lines(dst: &[f32]) -> (usize, usize) {
    let head = dst.as_ptr().align_offset(LINE).min(dst.len());
    (head, (dst.len() - head) / LINE_FLOATS * LINE_FLOATS)
}

/// `dst.copy_from_slice(src)` where `dst` is whole cache lines (starts on a line, a multiple
/// of 16 floats long), with streaming stores where the target has them: one 64-byte store a
/// line with AVX-512, two with AVX, four with SSE. (LLVM does not merge streaming stores, so
/// the width is chosen here; the check is a cached flag, once per run of lines.)
#[inline(always)]
fn stream_lines(dst: &mut [f32], src: &[f32]) {
    assert_eq!(dst.len(), src.len(), "copy between runs of one length");
    // Checked in release too (once per run of lines): the stores below rely on both. An empty
    // run may start anywhere: it stores nothing.
    assert!(
        dst.len().is_multiple_of(LINE_FLOATS)
            && (dst.is_empty() || (dst.as_ptr() as usize).is_multiple_of(LINE)),
        "whole cache lines"
    );
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512F; the lengths and alignment are checked above.
            unsafe { stream_lines_avx512(dst, src) };
            return;
        }
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX; the lengths and alignment are checked above.
            unsafe { stream_lines_avx(dst, src) };
            return;
        }
        stream_lines_sse(dst, src);
    }
    #[cfg(not(target_arch = "x86_64"))]
    dst.copy_from_slice(src);
}

/// [`stream_lines`] a quarter line at a time (SSE, part of x86-64).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn stream_lines_sse(dst: &mut [f32], src: &[f32]) {
    use std::arch::x86_64::{_mm_loadu_ps, _mm_stream_ps};
    assert!(
        dst.is_empty() || (dst.as_ptr() as usize).is_multiple_of(16),
        "aligned stores"
    );
    let whole = dst.len().min(src.len()) / 4 * 4;
    for q in (0..whole).step_by(4) {
        // SAFETY: `q + 4 <= len` for both slices, and `dst` is 16-byte aligned (checked), so
        // every `dst + q` is too, as `_mm_stream_ps` requires.
        unsafe { _mm_stream_ps(dst.as_mut_ptr().add(q), _mm_loadu_ps(src.as_ptr().add(q))) };
    }
}

/// [`stream_lines`] a line at a time (the whole lines of the shorter slice). Safety: the CPU
/// has AVX-512F and `dst` starts on a cache line.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn stream_lines_avx512(dst: &mut [f32], src: &[f32]) {
    use std::arch::x86_64::{_mm512_loadu_ps, _mm512_stream_ps};
    let whole = dst.len().min(src.len()) / LINE_FLOATS * LINE_FLOATS;
    for q in (0..whole).step_by(LINE_FLOATS) {
        // SAFETY: `q + 16 <= len` for both, `dst + q` starts a line (64-byte aligned).
        unsafe {
            _mm512_stream_ps(
                dst.as_mut_ptr().add(q),
                _mm512_loadu_ps(src.as_ptr().add(q)),
            )
        };
    }
}

/// [`stream_lines`] half a line at a time. Safety: as [`stream_lines_avx512`], with AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn stream_lines_avx(dst: &mut [f32], src: &[f32]) {
    use std::arch::x86_64::{_mm256_loadu_ps, _mm256_stream_ps};
    let whole = dst.len().min(src.len()) / LINE_FLOATS * LINE_FLOATS;
    for q in (0..whole).step_by(LINE_FLOATS) {
        // SAFETY: `q + 16 <= len` for both, `dst + q` starts a line (64-byte aligned).
        unsafe {
            let (d, s) = (dst.as_mut_ptr().add(q), src.as_ptr().add(q));
            _mm256_stream_ps(d, _mm256_loadu_ps(s));
            _mm256_stream_ps(d.add(8), _mm256_loadu_ps(s.add(8)));
        }
    }
}

/// Orders this thread's streaming stores before its later stores (`sfence`): after it, the
/// lines are visible to any thread that synchronises with this one, like plain stores.
#[inline(always)]
pub(crate) fn fence() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of x86-64.
    unsafe {
        std::arch::x86_64::_mm_sfence()
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each width the CPU has copies whole lines exactly (the dispatch takes only the widest).
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn every_width_copies_whole_lines() {
        let src: Vec<f32> = (0..5 * LINE_FLOATS).map(|i| i as f32 - 3.5).collect();
        type Copy = fn(&mut [f32], &[f32]);
        let mut widths: Vec<(&str, Copy)> = vec![("sse", stream_lines_sse)];
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX (checked); the test's slices are whole aligned lines.
            widths.push(("avx", |d, s| unsafe { stream_lines_avx(d, s) }));
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512F (checked); the slices are whole aligned lines.
            widths.push(("avx512", |d, s| unsafe { stream_lines_avx512(d, s) }));
        }
        for (name, copy) in widths {
            let mut buf = vec![-1.0f32; 7 * LINE_FLOATS];
            let skip = buf.as_ptr().align_offset(LINE);
            let dst = &mut buf[skip..skip + src.len()];
            copy(dst, &src);
            fence();
            assert_eq!(dst, &src[..], "{name}");
            assert!(buf[..skip].iter().all(|&x| x == -1.0), "{name}");
            assert!(buf[skip + src.len()..].iter().all(|&x| x == -1.0), "{name}");
        }
    }

    #[test]
    fn runs_in_any_order_write_the_same_values() {
        let src: Vec<f32> = (0..400).map(|i| i as f32 * 0.5 - 7.0).collect();
        for offset in 0..20 {
            // Consecutive runs (the usual case), a gap, a jump back, and runs within a line.
            for runs in [
                vec![(0, 37), (37, 100), (137, 3), (140, 60)],
                vec![(0, 5), (5, 4), (9, 2), (50, 90), (11, 39)],
                vec![(200, 100), (0, 200), (300, 17)],
                vec![(0, 317)],
            ] {
                let mut dst = vec![-1.0f32; 360];
                let end = runs.iter().map(|&(a, n)| a + n).max().unwrap();
                let mut carry = LineCarry::new();
                let array = &mut dst[offset..offset + end];
                for &(at, n) in &runs {
                    carry.write(array, at, &src[at..at + n]);
                }
                carry.flush(array);
                fence();
                assert!(carry.is_empty());
                assert_eq!(&dst[offset..offset + end], &src[..end], "{offset} {runs:?}");
                assert!(dst[..offset].iter().all(|&x| x == -1.0));
                assert!(dst[offset + end..].iter().all(|&x| x == -1.0));
            }
        }
    }
}
