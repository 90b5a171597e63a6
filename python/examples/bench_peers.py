"""tessella next to the libraries people would otherwise use to make a coarse mesh finer:
trimesh, Open3D and libigl (each when installed), on the same mesh at the same output size.

    python python/examples/bench_peers.py [--subdivisions 6] [--level 32] [--repeat 3] [--json]
                                          [--no-huge-pages]
    python python/examples/bench_peers.py --bandwidth path/to/tessella [--repeat 5] [--json]

`--bandwidth` checks the yardstick the speed tables divide by: numpy's one-thread
`ndarray.fill` on 256 MiB and 1 GiB, and `tessella bench --bandwidth-only` run right after it
in the same process tree, so both see the same machine load.

A level-L refinement pattern (L a power of two) gives exactly the triangles and vertices of
log2(L) rounds of midpoint (or Loop) subdivision, so the rows compare equal outputs: numpy in,
numpy out, welded. Every case runs in a fresh process, so its peak memory (the process's peak
resident size above what it held once its input was ready) is its own. Nothing here is
asserted: the numbers depend on the machine, and the table says which one.

A second table puts tessella into fresh memory (what a first call gets) and into reused memory
(later calls write into the memory the previous result freed, `tessella.set_memory_reuse`)
against the fresh-memory bound: its output bytes over numpy's fill of as many freshly allocated
bytes, measured in the same process.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time

import numpy as np


def icosphere(subdivisions: int):
    """Unit icosphere: 20 * 4**subdivisions counter-clockwise outward triangles, numpy only."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]])
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]])
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(subdivisions):
        edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = v[unique[:, 0]] + v[unique[:, 1]]
        mid /= np.linalg.norm(mid, axis=1, keepdims=True)
        m = inverse.reshape(3, -1).T + len(v)
        v = np.concatenate([v, mid])
        a, b, c = f.T
        ab, bc, ca = m.T
        f = np.concatenate([np.stack(x, axis=1) for x in
                            ([a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca])])
    return v.astype(np.float32), f.astype(np.int64)


def rss_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def run_case(name: str, subdivisions: int, level: int, repeat: int) -> dict:
    """Runs one case in this process; returns its times and peak memory."""
    v, f = icosphere(subdivisions)
    n = v.copy()  # unit sphere: the normals are the positions
    rounds = level.bit_length() - 1
    if name.startswith("tessella"):
        import tessella

        scheme = name.split(" ")[1]
        run = lambda: tessella.refine(v, f, n, scheme=scheme, level=level)  # noqa: E731
    elif name == "trimesh midpoint":
        import trimesh.remesh

        def run():
            vv, ff = v.astype(np.float64), f
            for _ in range(rounds):
                vv, ff = trimesh.remesh.subdivide(vv, ff)
            return vv, ff
    elif name == "trimesh loop":
        import trimesh.remesh

        run = lambda: trimesh.remesh.subdivide_loop(v.astype(np.float64), f, iterations=rounds)  # noqa: E731
    elif name == "libigl upsample":
        import igl

        run = lambda: igl.upsample(v.astype(np.float64), f, number_of_subdivs=rounds)  # noqa: E731
    elif name.startswith("open3d"):
        import open3d as o3d

        mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(v.astype(np.float64)),
                                         o3d.utility.Vector3iVector(f.astype(np.int32)))

        def run():
            if name == "open3d midpoint":
                m = mesh.subdivide_midpoint(number_of_iterations=rounds)
            else:
                m = mesh.subdivide_loop(number_of_iterations=rounds)
            return np.asarray(m.vertices), np.asarray(m.triangles)
    else:
        raise SystemExit(f"unknown case {name}")
    before = rss_bytes()
    times = []
    result = None
    for _ in range(repeat):
        result = None
        t0 = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - t0)
    arrays = result
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    output_bytes = int(sum(a.nbytes for a in arrays))
    row = {
        "case": name,
        "seconds": float(np.median(times)),
        "vertices": int(len(arrays[0])),
        "triangles": int(len(arrays[1])),
        "output_bytes": output_bytes,
        "peak_bytes": int(peak - before),
    }
    if name.startswith("tessella"):
        del arrays, result
        row.update(fresh_and_reused(run, output_bytes, repeat))
    return row


def fresh_and_reused(run, output_bytes: int, repeat: int) -> dict:
    """tessella's calls into fresh memory (what a first call gets: the kept memory released
    before each) and into the memory the previous result freed (each result dropped before
    the next call, as a conversion loop does), and numpy's fill of as many fresh bytes, all
    in this process and each the median of `repeat`."""
    import tessella

    fresh, reused = [], []
    for _ in range(repeat):
        tessella.release_memory()
        t0 = time.perf_counter()
        result = run()
        fresh.append(time.perf_counter() - t0)
        del result
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = run()
        reused.append(time.perf_counter() - t0)
        del result
    tessella.release_memory()
    return {
        "fresh_seconds": float(np.median(fresh)),
        "reused_seconds": float(np.median(reused)),
        "fresh_fill_bytes_per_s": fresh_fill(output_bytes, repeat),
    }


def set_huge_pages(on: bool) -> None:
    """numpy's advice of transparent huge pages for large arrays (on by default on Linux), which
    tessella follows for its own new result buffers."""
    try:
        from numpy._core import multiarray
    except ImportError:  # numpy 1.x
        from numpy.core import multiarray
    multiarray._set_madvise_hugepage(on)


def fresh_fill(nbytes: int, repeat: int) -> float:
    """numpy's fill of `nbytes` of freshly allocated memory (page faults included): the
    bound for one call that returns that many bytes in new arrays. Median of `repeat`."""
    rates = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        a = np.empty(nbytes // 4, np.float32)
        a.fill(1.0)
        rates.append(a.nbytes / (time.perf_counter() - t0))
        del a
    return float(np.median(rates))


CASES = ["tessella pn", "tessella flat", "libigl upsample", "trimesh midpoint",
         "open3d midpoint", "trimesh loop", "open3d loop"]


def installed(name: str) -> bool:
    module = {"tessella": "tessella", "libigl": "igl", "trimesh": "trimesh",
              "open3d": "open3d"}[name.split(" ")[0]]
    try:
        __import__(module)
        return True
    except ImportError:
        return False


def numpy_fill(mib: int, repeat: int) -> float:
    """Bytes per second of numpy's `ndarray.fill` (one thread) on `mib` MiB of float32,
    median of `repeat` passes after one that faults the pages in."""
    a = np.empty(mib << 18, dtype=np.float32)
    a.fill(0.5)
    times = []
    for i in range(max(repeat, 3)):
        start = time.perf_counter()
        a.fill(1.0 + i)
        times.append(time.perf_counter() - start)
    return a.nbytes / sorted(times)[len(times) // 2]


def bandwidth(cli: str, repeat: int) -> dict:
    """numpy's fill and tessella's bandwidth figures, measured one after the other."""
    numpy = {f"{mib} MiB": numpy_fill(mib, repeat) for mib in (256, 1024)}
    done = subprocess.run([cli, "bench", "--bandwidth-only", "--json", "--repeat", str(repeat)],
                          capture_output=True, text=True, check=True)
    tessella = json.loads(done.stdout)
    best_numpy = max(numpy.values())
    return {"numpy_fill_bytes_per_s": numpy, "tessella": tessella,
            "fill_over_numpy": tessella["fill_bytes_per_s"] / best_numpy,
            # Like for like: one thread, plain stores, on both sides.
            "one_thread_fill_over_numpy":
                tessella["fill_plain_one_thread_bytes_per_s"] / best_numpy}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--subdivisions", type=int, default=6,
                    help="icosphere subdivisions of the coarse mesh (6: 81,920 triangles, "
                         "the size of the Stanford bunny)")
    ap.add_argument("--level", type=int, default=32, help="pattern level, a power of two")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true", help="print the rows as JSON")
    ap.add_argument("--bandwidth", metavar="TESSELLA",
                    help="compare `TESSELLA bench --bandwidth-only` with numpy's fill instead")
    ap.add_argument("--cases", help="comma-separated cases to run (default: all installed): "
                    + ", ".join(CASES))
    ap.add_argument("--no-huge-pages", action="store_true",
                    help="turn numpy's huge-page advice off in every case (tessella follows it): "
                         "fresh memory in 4 KiB pages")
    ap.add_argument("--one", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.no_huge_pages:
        set_huge_pages(False)
    if args.bandwidth:
        report = bandwidth(args.bandwidth, args.repeat)
        if args.json:
            print(json.dumps(report, indent=2))
            return
        t = report["tessella"]
        for size, rate in report["numpy_fill_bytes_per_s"].items():
            print(f"numpy ndarray.fill, 1 thread, {size}: {rate / 1e9:.1f} GB/s")
        print(f"tessella bench, {t['threads']} threads: fill {t['fill_bytes_per_s'] / 1e9:.1f} "
              f"GB/s (plain {t['fill_plain_bytes_per_s'] / 1e9:.1f}, non-temporal "
              f"{t['fill_nt_bytes_per_s'] / 1e9:.1f}), copy {t['copy_bytes_per_s'] / 1e9:.1f} "
              f"GB/s (non-temporal {t['copy_nt_bytes_per_s'] / 1e9:.1f})")
        print(f"tessella's one-thread plain fill "
              f"{t['fill_plain_one_thread_bytes_per_s'] / 1e9:.1f} GB/s over numpy's (like for "
              f"like): {report['one_thread_fill_over_numpy']:.2f}")
        print(f"tessella's fill ({t['threads']} threads, the tables' yardstick) over numpy's: "
              f"{report['fill_over_numpy']:.2f}")
        return
    if args.level < 2 or args.level & (args.level - 1):
        raise SystemExit("--level must be a power of two (2, 4, 8, ...)")
    if args.one:
        print(json.dumps(run_case(args.one, args.subdivisions, args.level, args.repeat)))
        return
    cases = CASES
    if args.cases:
        cases = [c.strip() for c in args.cases.split(",")]
        unknown = sorted(set(cases) - set(CASES))
        if unknown:
            raise SystemExit(f"unknown cases {unknown}; known: {', '.join(CASES)}")
    rows = []
    for case in cases:
        if not installed(case):
            print(f"{case}: not installed, skipped", file=sys.stderr)
            continue
        cmd = [sys.executable, __file__, "--one", case, "--subdivisions",
               str(args.subdivisions), "--level", str(args.level), "--repeat", str(args.repeat)]
        if args.no_huge_pages:
            cmd.append("--no-huge-pages")
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            print(f"{case}: failed: {done.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
            continue
        rows.append(json.loads(done.stdout))
    faces = 20 * 4**args.subdivisions
    if args.json:
        print(json.dumps({"faces": faces, "level": args.level, "rows": rows}, indent=2))
        return
    peers = [r for r in rows if not r["case"].startswith("tessella")]
    fastest = min(peers, key=lambda r: r["seconds"]) if peers else None
    print(f"{faces} coarse triangles to level {args.level} "
          f"({platform.processor() or platform.machine()}, {os.cpu_count()} cores, huge pages "
          f"{'off' if args.no_huge_pages else 'as numpy advises'}), median of {args.repeat}:\n")
    print("| library | vertices | triangles | seconds | M vertices/s | peak memory / output |"
          + (f" vs {fastest['case']} |" if fastest else ""))
    print("|---|---:|---:|---:|---:|---:|" + ("---:|" if fastest else ""))
    for r in rows:
        line = (f"| {r['case']} | {r['vertices']} | {r['triangles']} | {r['seconds']:.3f} | "
                f"{r['vertices'] / r['seconds'] / 1e6:.1f} | "
                f"{r['peak_bytes'] / r['output_bytes']:.2f} |")
        if fastest:
            line += f" {fastest['seconds'] / r['seconds']:.1f}x |"
        print(line)
    print("\nInto fresh memory and into reused memory, against the fresh-memory bound (output "
          "bytes over numpy's fill of as many freshly allocated bytes, same process), median of "
          f"{args.repeat}:\n")
    print("| library | fresh memory (s) | bound (s) | of the bound | reused memory (s) "
          "| reused over the bound |" + (f" fresh, vs {fastest['case']} |" if fastest else ""))
    print("|---|---:|---:|---:|---:|---:|" + ("---:|" if fastest else ""))
    for r in rows:
        if "fresh_fill_bytes_per_s" not in r:
            continue
        bound = r["output_bytes"] / r["fresh_fill_bytes_per_s"]
        line = (f"| {r['case']} | {r['fresh_seconds']:.4f} | {bound:.4f} | "
                f"{bound / r['fresh_seconds']:.0%} | {r['reused_seconds']:.4f} | "
                f"{bound / r['reused_seconds']:.1f}x |")
        if fastest:
            line += f" {fastest['seconds'] / r['fresh_seconds']:.1f}x |"
        print(line)


if __name__ == "__main__":
    main()
