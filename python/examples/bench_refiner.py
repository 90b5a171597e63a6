"""Times a deforming mesh refined frame after frame: ``Refiner.refine(..., out=)`` against a
fresh ``tessella.refine`` per frame, on a 5120-triangle icosphere that twists and grows.

    python python/examples/bench_refiner.py [--frames 20] [--levels 8 16 32] [--scheme pn]

Prints milliseconds per frame (median of the frames) and the speed-up. Both give the same
arrays (checked on the last frame). Times depend on the machine; nothing here is asserted.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import tessella


def icosphere(subdivisions: int):
    """Unit icosphere: 20 * 4**subdivisions counter-clockwise outward triangles."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    v = [list(np.array(p) / np.linalg.norm(p)) for p in v]
    for _ in range(subdivisions):
        mids: dict = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                p = np.array(v[a]) + np.array(v[b])
                v.append(list(p / np.linalg.norm(p)))
                mids[key] = len(v) - 1
            return mids[key]

        nf = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    return np.array(v, np.float32), np.array(f, np.int64)


def deform(v: np.ndarray, k: int) -> np.ndarray:
    """Frame k: twisted about z by 0.05 k z radians and scaled by 1 + 0.01 k."""
    a = 0.05 * k * v[:, 2]
    c, s = np.cos(a), np.sin(a)
    out = np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]], axis=1)
    return ((1.0 + 0.01 * k) * out).astype(np.float32)


def per_frame(fn, frames) -> float:
    times = []
    for vk in frames:
        t0 = time.perf_counter()
        fn(vk)
        times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--levels", type=int, nargs="+", default=[8, 16, 32])
    ap.add_argument("--scheme", default="pn")
    args = ap.parse_args()

    v, f = icosphere(4)
    frames = [deform(v, k) for k in range(1, args.frames + 1)]
    print(f"icosphere: {len(v)} vertices, {len(f)} triangles; scheme {args.scheme}; "
          f"{args.frames} frames; {os.cpu_count()} CPUs; tessella {tessella.__version__}")
    print(f"{'level':>5} {'refined tris':>13} {'refine() ms':>12} {'Refiner ms':>11} "
          f"{'Refiner out= ms':>16} {'speed-up (out=)':>16}")
    for level in args.levels:
        r = tessella.Refiner(f, scheme=args.scheme, level=level, backend="cpu")
        rv, rf, rn = r.refine(v)  # builds the plan (not timed)
        out = (np.empty_like(rv), np.empty_like(rn))
        fresh = per_frame(
            lambda vk: tessella.refine(vk, f, scheme=args.scheme, level=level, backend="cpu"),
            frames)
        alloc = per_frame(lambda vk: r.refine(vk), frames)
        inplace = per_frame(lambda vk: r.refine(vk, out=out), frames)
        want = tessella.refine(frames[-1], f, scheme=args.scheme, level=level, backend="cpu")
        got = r.refine(frames[-1], out=out)
        assert np.array_equal(got[0], want[0]) and np.array_equal(got[2], want[2])
        print(f"{level:>5} {len(rf):>13} {fresh:>12.2f} {alloc:>11.2f} {inplace:>16.2f} "
              f"{fresh / inplace:>15.2f}x")


if __name__ == "__main__":
    main()
