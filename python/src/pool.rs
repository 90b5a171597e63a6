//! Memory that `tessella.refine` reuses between calls.
//!
//! A program that calls `refine` in a loop (batch conversion) would otherwise pay for fresh
//! pages on every call: each output array of more than a few tens of MB is a new `mmap`, and
//! every 4 KiB page of it is faulted in and zeroed by the kernel before the first write, which
//! costs more than the refinement itself. So the arrays `refine` returns are numpy views of
//! buffers owned by a small Python object, a [`Lease`]; when numpy frees the last array or
//! view of a buffer, the lease gives it back to this pool instead of to the allocator, pages
//! still mapped, and the next call of about the same size writes into it.
//!
//! A first call (nothing in the pool fits) allocates as numpy does for its own arrays: memory
//! of 4 MiB or more is advised to use transparent huge pages (`madvise`), one fault and one
//! zeroing per 2 MiB instead of per 4 KiB, whenever numpy's own setting for that is on
//! (`numpy._core.multiarray._set_madvise_hugepage`, on by default on Linux).
//!
//! Only buffers nobody can reach any more are reused: numpy drops the lease after the last
//! array or view that points into the buffer. The pool holds at most [`Pool::limit`] bytes
//! (`tessella.set_memory_reuse`), the most recently returned first; `tessella.release_memory`
//! frees it all.

use numpy::ndarray::ArrayView2;
use numpy::{Element, PyArray2};
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use tessella_core::refine::Refiner;
use tessella_core::RefinedMesh;

/// Buffers smaller than this are left to the allocator, which keeps small blocks itself.
const SMALLEST: usize = 1 << 20;
/// The pool's default limit: enough for a level-32 refinement of an 80k-triangle mesh's
/// positions and normals, well under the memory of any machine that makes one.
const DEFAULT_LIMIT: usize = 2 << 30;

/// New buffers of at least this many bytes are advised to use huge pages (numpy's threshold).
const HUGE_FROM: usize = 4 << 20;
/// The size of a transparent huge page on x86-64 and most arm64 kernels.
const HUGE_PAGE: usize = 2 << 20;

/// Whether new buffers get huge pages: numpy's setting, read at each `refine` call.
static HUGE_PAGES: AtomicBool = AtomicBool::new(cfg!(target_os = "linux"));

/// Follows numpy's huge-page setting for the buffers of the call about to run. Where numpy
/// does not say (an older or newer numpy without the private getter), Linux's default stands.
pub fn follow_numpy(py: Python<'_>) {
    let numpy_says = ["numpy._core.multiarray", "numpy.core.multiarray"]
        .iter()
        .find_map(|module| {
            let getter = py
                .import(*module)
                .ok()?
                .getattr("_get_madvise_hugepage")
                .ok()?;
            getter.call0().ok()?.extract::<bool>().ok()
        });
    HUGE_PAGES.store(
        numpy_says.unwrap_or(cfg!(target_os = "linux")),
        Ordering::Relaxed,
    );
}

/// One buffer of output rows.
pub enum Buffer {
    F32x3(Vec<[f32; 3]>),
    F32x2(Vec<[f32; 2]>),
    U32x3(Vec<[u32; 3]>),
}

impl Buffer {
    fn bytes(&self) -> usize {
        match self {
            Buffer::F32x3(v) => v.capacity() * 12,
            Buffer::F32x2(v) => v.capacity() * 8,
            Buffer::U32x3(v) => v.capacity() * 12,
        }
    }
}

/// Rows the pool can hold: how to wrap and unwrap them as a [`Buffer`]. Only rows of `f32`
/// and `u32`, for which all-zero bytes are a value ([`fresh`] relies on it).
pub trait Rows: Sized {
    fn wrap(rows: Vec<Self>) -> Buffer;
    /// The rows, if `buffer` holds this kind.
    fn unwrap(buffer: Buffer) -> Option<Vec<Self>>;
    /// How many rows `buffer` has room for, if it holds this kind.
    fn room(buffer: &Buffer) -> Option<usize>;
}

macro_rules! rows {
    ($row:ty, $variant:ident) => {
        impl Rows for $row {
            fn wrap(rows: Vec<Self>) -> Buffer {
                Buffer::$variant(rows)
            }
            fn unwrap(buffer: Buffer) -> Option<Vec<Self>> {
                match buffer {
                    Buffer::$variant(v) => Some(v),
                    _ => None,
                }
            }
            fn room(buffer: &Buffer) -> Option<usize> {
                match buffer {
                    Buffer::$variant(v) => Some(v.capacity()),
                    _ => None,
                }
            }
        }
    };
}
rows!([f32; 3], F32x3);
rows!([f32; 2], F32x2);
rows!([u32; 3], U32x3);

/// Buffers given back, oldest first, and their bytes.
struct Pool {
    buffers: Vec<Buffer>,
    bytes: usize,
    limit: usize,
}

static POOL: Mutex<Pool> = Mutex::new(Pool {
    buffers: Vec::new(),
    bytes: 0,
    limit: DEFAULT_LIMIT,
});

/// The pool, even if a thread panicked while holding it (its fields stay consistent: every
/// change is a push or remove with its byte count).
fn pool() -> std::sync::MutexGuard<'static, Pool> {
    POOL.lock().unwrap_or_else(|e| e.into_inner())
}

impl Pool {
    /// Drops the oldest buffers until the pool is within its limit.
    fn trim(&mut self) -> Vec<Buffer> {
        let mut dropped = Vec::new();
        while self.bytes > self.limit {
            let b = self.buffers.remove(0);
            self.bytes -= b.bytes();
            dropped.push(b);
        }
        dropped
    }
}

/// A buffer of at least `n` rows from the pool, the smallest that fits and wastes at most
/// three quarters of itself; new memory ([`fresh`]) when none does. Its
/// length is at most `n`, so resizing it to `n` writes nothing but the missing tail.
pub fn take<T: Rows>(n: usize) -> Vec<T> {
    let need = n.saturating_mul(std::mem::size_of::<T>());
    let mut pool = pool();
    let best = pool
        .buffers
        .iter()
        .enumerate()
        .filter(|(_, b)| T::room(b).is_some_and(|room| room >= n) && b.bytes() / 4 <= need)
        .min_by_key(|(_, b)| b.bytes())
        .map(|(i, _)| i);
    let Some(i) = best else {
        drop(pool);
        return fresh(n);
    };
    let buffer = pool.buffers.remove(i);
    pool.bytes -= buffer.bytes();
    drop(pool);
    let mut rows = T::unwrap(buffer).expect("room() found this kind");
    rows.truncate(n);
    rows
}

/// `n` zeroed rows in new memory: zeroed by the kernel as it maps the pages, not written here
/// (`alloc_zeroed` of a large block is a fresh mapping), and advised to use huge pages before
/// the first write where [`HUGE_PAGES`] says so. Small buffers: an empty `Vec`, which the plan
/// sizes itself.
fn fresh<T: Rows>(n: usize) -> Vec<T> {
    let Ok(layout) = std::alloc::Layout::array::<T>(n) else {
        return Vec::new();
    };
    if layout.size() < HUGE_FROM || !HUGE_PAGES.load(Ordering::Relaxed) {
        return Vec::new();
    }
    // SAFETY: the layout is non-zero in size (at least HUGE_FROM bytes).
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<T>();
    if ptr.is_null() {
        // Out of memory: the plan's own allocation reports it as any other would.
        return Vec::new();
    }
    advise_huge_pages(ptr.cast(), layout.size());
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `n` rows of `T`,
    // and all-zero bytes are `n` valid rows of `f32` or `u32` (the only `Rows`).
    unsafe { Vec::from_raw_parts(ptr, n, n) }
}

/// Advises the whole huge pages inside `bytes` bytes at `ptr` to be backed by huge pages.
#[cfg(target_os = "linux")]
fn advise_huge_pages(ptr: *mut u8, bytes: usize) {
    let start = (ptr as usize).next_multiple_of(HUGE_PAGE);
    let end = (ptr as usize + bytes) / HUGE_PAGE * HUGE_PAGE;
    if end <= start {
        return;
    }
    // SAFETY: the range lies inside the caller's allocation, and the advice changes only how
    // its pages are backed, never their contents.
    let advised = unsafe {
        rustix::mm::madvise(
            start as *mut std::ffi::c_void,
            end - start,
            rustix::mm::Advice::LinuxHugepage,
        )
    };
    if advised.is_err() {
        // A kernel without transparent huge pages refuses the advice: 4 KiB pages, as before.
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_ptr: *mut u8, _bytes: usize) {}

/// `refiner.refine()`, into buffers from the pool where it has some that fit: memory that
/// earlier calls' arrays held, pages already mapped.
pub fn refine(refiner: &Refiner) -> RefinedMesh {
    let layout = refiner.layout();
    let vertices = layout.vertex_count as usize;
    let mut out = RefinedMesh {
        positions: take(vertices),
        normals: take(vertices),
        uvs: refiner.mesh().uvs().is_some().then(|| take(vertices)),
        triangles: take(layout.triangle_count as usize),
    };
    refiner.refine_into(&mut out, &|_| {});
    out
}

/// Gives a buffer to the pool (or to the allocator when it is small, the pool is off, or it
/// alone is over the limit). Buffers pushed out of the pool are freed after the lock is let go.
fn give_back(buffer: Buffer) {
    let bytes = buffer.bytes();
    if bytes < SMALLEST {
        return;
    }
    let dropped = {
        let mut pool = pool();
        if bytes > pool.limit {
            return;
        }
        pool.bytes += bytes;
        pool.buffers.push(buffer);
        pool.trim()
    };
    drop(dropped);
}

/// Owns one output buffer while numpy arrays point into it (their `base`), and gives it back
/// to the pool when the last of them is freed. Not added to the module: Python code never
/// makes one, it only sees it as an array's `base`.
#[pyclass(frozen, name = "_Lease", module = "tessella._tessella")]
pub struct Lease {
    buffer: Option<Buffer>,
}

impl Drop for Lease {
    fn drop(&mut self) {
        if let Some(buffer) = self.buffer.take() {
            give_back(buffer);
        }
    }
}

/// Rows as a C-ordered `(n, K)` numpy array over their own buffer (no copy), which returns to
/// the pool once numpy is done with it.
pub fn to_numpy<'py, T: Element, const K: usize>(
    py: Python<'py>,
    rows: Vec<[T; K]>,
) -> PyResult<Bound<'py, PyArray2<T>>>
where
    [T; K]: Rows,
{
    let n = rows.len();
    // SAFETY: the view covers the `n * K` initialised elements of `rows`' heap buffer. Moving
    // the `Vec` into the lease below does not move that buffer, and the lease neither touches
    // nor frees it until numpy drops the lease, after the last array using it.
    let view = unsafe { ArrayView2::from_shape_ptr((n, K), rows.as_ptr().cast::<T>()) };
    let lease = Bound::new(
        py,
        Lease {
            buffer: Some(<[T; K]>::wrap(rows)),
        },
    )?;
    // SAFETY: the lease is the array's base object and owns the buffer (see above).
    Ok(unsafe { PyArray2::borrow_from_array(&view, lease.into_any()) })
}

/// Frees every buffer in the pool; returns how many bytes it held.
#[pyfunction]
#[pyo3(name = "_release_memory")]
pub fn release_memory() -> usize {
    let (buffers, held) = {
        let mut pool = pool();
        let held = std::mem::take(&mut pool.bytes);
        (std::mem::take(&mut pool.buffers), held)
    };
    // Freed here, after the lock is let go.
    drop(buffers);
    held
}

/// Sets how many bytes of freed output arrays the pool may keep for later calls (0: none, and
/// frees what it holds); returns the previous limit.
#[pyfunction]
#[pyo3(name = "_set_memory_reuse")]
pub fn set_memory_reuse(max_bytes: usize) -> usize {
    let (previous, dropped) = {
        let mut pool = pool();
        let previous = std::mem::replace(&mut pool.limit, max_bytes);
        (previous, pool.trim())
    };
    drop(dropped);
    previous
}

/// Bytes the pool holds now, ready for the next call.
#[pyfunction]
#[pyo3(name = "_reusable_bytes")]
pub fn reusable_bytes() -> usize {
    pool().bytes
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(release_memory, m)?)?;
    m.add_function(wrap_pyfunction!(set_memory_reuse, m)?)?;
    m.add_function(wrap_pyfunction!(reusable_bytes, m)?)?;
    Ok(())
}
