"""tessella.refine writes into memory that earlier calls' arrays freed, never into memory an
array or view still uses, and gives the same bits as into fresh memory."""

import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh

import tessella


def sphere(scale=1.0):
    m = trimesh.creation.icosphere(subdivisions=3)
    return np.asarray(m.vertices, np.float32) * np.float32(scale), np.asarray(m.faces, np.uint32)


def address(a):
    return a.__array_interface__["data"][0]


@pytest.fixture(autouse=True)
def fresh_pool():
    previous = tessella.set_memory_reuse(1 << 30)
    tessella.release_memory()
    yield
    tessella.set_memory_reuse(previous)
    tessella.release_memory()


def test_freed_arrays_are_written_again_with_the_same_bits():
    v, f = sphere()
    first = tessella.refine(v, f, level=24)
    want = [a.copy() for a in first[:3]]
    addresses = {address(a) for a in first[:3]}
    assert tessella.reusable_bytes() == 0
    del first
    kept = tessella.reusable_bytes()
    # positions, normals (4.4 MB each) and triangles (8.8 MB) are kept for the next call
    assert kept >= sum(a.nbytes for a in want)
    second = tessella.refine(v, f, level=24)
    assert {address(a) for a in second[:3]} == addresses
    assert tessella.reusable_bytes() == kept - sum(a.nbytes for a in want)
    for got, w in zip(second[:3], want):
        assert got.dtype == w.dtype and got.shape == w.shape
        assert np.array_equal(got.view(np.uint32), w.view(np.uint32))


def test_the_origin_and_spacing_paths_reuse_memory_too():
    v, f = sphere()
    for options in [dict(origin=True), dict(spacing="fractional-odd", level=23.0)]:
        kwargs = dict(level=24, **options) if "spacing" not in options else options
        first = tessella.refine(v, f, **kwargs)
        want = [a.copy() for a in first[:3]]
        addresses = {address(a) for a in first[:3]}
        del first
        again = tessella.refine(v, f, **kwargs)
        assert {address(a) for a in again[:3]} == addresses, options
        for got, w in zip(again[:3], want):
            assert np.array_equal(got.view(np.uint32), w.view(np.uint32)), options
        del again
        tessella.release_memory()


def test_memory_still_in_use_is_never_handed_out():
    v, f = sphere()
    first = tessella.refine(v, f, level=24)
    view = first.vertices[::3]
    normals = first.normals
    saved_view, saved_normals = view.copy(), normals.copy()
    faces_address = address(first.faces)
    del first  # the faces are free now; the vertices live on in `view`, the normals as is
    v2, f2 = sphere(scale=2.0)
    second = tessella.refine(v2, f2, level=24)
    assert np.array_equal(view, saved_view)
    assert np.array_equal(normals, saved_normals)
    assert address(second.faces) == faces_address
    assert address(view) not in {address(a) for a in second[:3]}
    # and the new result is right: the same as with reuse turned off
    tessella.set_memory_reuse(0)
    fresh = tessella.refine(v2, f2, level=24)
    for got, w in zip(second[:3], fresh[:3]):
        assert np.array_equal(got.view(np.uint32), w.view(np.uint32))


def test_every_scheme_gives_the_same_bits_into_reused_memory():
    v, f = sphere()
    for scheme in ["pn", "png1", "phong", "pn-aen"]:
        for weld in [True, False]:
            tessella.set_memory_reuse(0)
            fresh = [a.copy() for a in tessella.refine(v, f, scheme=scheme, level=16, weld=weld)[:3]]
            tessella.set_memory_reuse(1 << 30)
            # the buffers of a first call, freed, then written by a second
            tessella.refine(v, f, scheme=scheme, level=16, weld=weld)
            again = tessella.refine(v, f, scheme=scheme, level=16, weld=weld)
            for got, w in zip(again[:3], fresh):
                assert np.array_equal(got.view(np.uint32), w.view(np.uint32)), (scheme, weld)


def test_the_limit_holds_and_release_frees_everything():
    v, f = sphere()
    tessella.set_memory_reuse(5_000_000)
    r = tessella.refine(v, f, level=24)
    del r
    # 4.4 + 4.4 + 8.8 MB given back: the oldest go until 5 MB or less are kept
    assert 0 < tessella.reusable_bytes() <= 5_000_000
    assert tessella.set_memory_reuse(0) == 5_000_000
    assert tessella.reusable_bytes() == 0
    tessella.set_memory_reuse(1 << 30)
    r = tessella.refine(v, f, level=24)
    nbytes = sum(a.nbytes for a in r[:3])
    del r
    assert tessella.release_memory() >= nbytes
    assert tessella.reusable_bytes() == 0
    with pytest.raises(tessella.OptionError, match="0 or more"):
        tessella.set_memory_reuse(-1)


def test_small_outputs_are_left_to_the_allocator():
    v, f = sphere()
    r = tessella.refine(v, f, level=2)
    assert sum(a.nbytes for a in r[:3]) < 1 << 20
    del r
    assert tessella.reusable_bytes() == 0


def vm_flags(addr):
    """The VmFlags of the mapping holding `addr` (Linux's /proc/self/smaps)."""
    with open("/proc/self/smaps") as f:
        inside = False
        for line in f:
            head = line.split()[0]
            if "-" in head and ":" not in head:
                lo, hi = (int(x, 16) for x in head.split("-"))
                inside = lo <= addr < hi
            elif inside and line.startswith("VmFlags:"):
                return line.split()[1:]
    raise AssertionError(f"no mapping holds {addr:#x}")


# Run in a fresh process: the allocator may serve a buffer from memory an earlier array used
# (and numpy or tessella advised), so only a process with no history shows the call's own advice.
HUGE_PAGE_PROBE = """
import sys
sys.path.insert(0, {tests!r})
try:
    from numpy._core import multiarray
except ImportError:  # numpy 1.x
    from numpy.core import multiarray
multiarray._set_madvise_hugepage({on})
import tessella
from test_memory_reuse import address, sphere, vm_flags
v, f = sphere()
r = tessella.refine(v, f, level=48)  # 1.5M vertices: 17 MB of positions
assert r.vertices.nbytes > 8 << 20
# The middle of the buffer: the advice covers its whole 2 MiB pages, so the first page (with
# the allocator's header) is a mapping of its own.
print("hg" in vm_flags(address(r.vertices) + r.vertices.nbytes // 2))
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="madvise is Linux's")
def test_new_buffers_take_numpys_huge_page_advice():
    tests = os.path.dirname(os.path.abspath(__file__))
    for on in [True, False]:
        done = subprocess.run(
            [sys.executable, "-c", HUGE_PAGE_PROBE.format(tests=tests, on=on)],
            capture_output=True, text=True, timeout=120,
        )
        assert done.returncode == 0, done.stderr
        assert done.stdout.strip() == str(on), (on, done.stdout)
