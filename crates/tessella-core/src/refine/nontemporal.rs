//! Copies into the caller's output with non-temporal (streaming) stores, for outputs larger
//! than the last-level cache. A plain store to a line that is not cached first reads the line
//! from memory (read for ownership), so writing a large output moves its bytes twice; a
//! streaming store writes whole lines without reading them. On this project's 2-core machine
//! a two-thread fill ran at 29 GB/s with plain stores and 39 GB/s with streaming ones. Outputs
//! that fit in the cache keep plain stores: the caller reads the vertices next, from cache.
//!
//! Only the whole 64-byte lines of a run are streamed; the partial lines at either end are
//! written with plain stores, so neighbouring runs (another thread's, or the next tile's)
//! never stream into the same line. The values and their order are the same either way: only
//! how the bytes travel to memory changes.

/// Outputs of more bytes than this are written with streaming stores: twice the 32 MiB
/// last-level cache of the machine this was measured on, where a frame of 63 MB still ran
/// faster with plain stores (part of it stays cached from the frame before) and one of 98 MB
/// already ran faster streamed.
pub(crate) const STREAM_ABOVE_BYTES: usize = 64 << 20;

/// Bytes in a cache line.
#[cfg(target_arch = "x86_64")]
const LINE: usize = 64;

/// `dst.copy_from_slice(src)`, with the whole cache lines of `dst` written by streaming
/// stores where the target has them. Call [`fence`] before another thread may read `dst`.
#[inline(always)]
pub(crate) fn copy(dst: &mut [f32], src: &[f32]) {
    assert_eq!(dst.len(), src.len(), "copy between runs of one length");
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_loadu_ps, _mm_stream_ps};
        const FLOATS: usize = LINE / 4;
        // f32s are 4-byte aligned, so the distance to the next line is whole floats.
        let misalign = dst.as_ptr() as usize % LINE;
        let head = ((LINE - misalign) % LINE / 4).min(dst.len());
        let lines = (dst.len() - head) / FLOATS;
        let end = head + lines * FLOATS;
        dst[..head].copy_from_slice(&src[..head]);
        for line in 0..lines {
            let at = head + line * FLOATS;
            for q in (0..FLOATS).step_by(4) {
                // SAFETY: `at + q + 4 <= end <= len` for both slices, and `dst + at` is the
                // start of a cache line, so every `dst + at + q` is 16-byte aligned as
                // `_mm_stream_ps` requires; SSE is part of x86-64.
                unsafe {
                    _mm_stream_ps(
                        dst.as_mut_ptr().add(at + q),
                        _mm_loadu_ps(src.as_ptr().add(at + q)),
                    )
                };
            }
        }
        dst[end..].copy_from_slice(&src[end..]);
    }
    #[cfg(not(target_arch = "x86_64"))]
    dst.copy_from_slice(src);
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

    #[test]
    fn every_offset_and_length_copies_the_same_values() {
        let src: Vec<f32> = (0..200).map(|i| i as f32 * 0.5 - 7.0).collect();
        for offset in 0..20 {
            for len in [0, 1, 3, 15, 16, 17, 31, 32, 33, 100, 180] {
                let mut dst = vec![-1.0f32; 220];
                copy(&mut dst[offset..offset + len], &src[..len]);
                fence();
                assert_eq!(&dst[offset..offset + len], &src[..len], "{offset} {len}");
                assert!(dst[..offset].iter().all(|&x| x == -1.0));
                assert!(dst[offset + len..].iter().all(|&x| x == -1.0));
            }
        }
    }
}
