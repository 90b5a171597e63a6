"""Outputs larger than memory and many files: tessella.refine_to_file (streamed, bounded memory,
the bytes of the whole refinement), tessella.batch (broken files, resume) and tessella.dask on
a 2-worker LocalCluster with a worker killed while it works."""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import tessella
from conftest import icosphere
from tessella._errors import FileFormatError, MeshError, OptionError, TessellaError


def write_folder(root: Path, copies: int, level_sub: int = 2):
    """Good meshes (some in a subfolder) and broken ones; returns (relative name, faces)."""
    (root / "sub").mkdir(parents=True)
    good = []
    for i in range(copies):
        v, f = icosphere(level_sub + i % 2)
        name = f"sphere-{i}.ply" if i % 2 == 0 else f"sub/sphere-{i}.obj"
        tessella.save(str(root / name), v, f, v)
        good.append((name, len(f)))
    (root / "garbage.obj").write_text("this is not a mesh\n")
    (root / "sub" / "truncated.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\n")
    return good


def temporaries(root: Path):
    return sorted(str(p) for p in root.rglob(".tessella-*"))


@pytest.mark.parametrize("weld", [True, False])
@pytest.mark.parametrize("name", ["a.ply", "b.obj", "c.glb", "d.stl", "e.gltf"])
def test_streamed_file_has_the_bytes_of_the_whole_refinement(tmp_path, name, weld):
    v, f = icosphere(2)
    # Independent path: the whole refinement in memory, written by tessella.save.
    rv, rf, rn = tessella.refine(v, f, v, level=9, scheme="pn", weld=weld)
    tessella.save(str(tmp_path / ("want-" + name)), rv, rf, None if name.endswith(".stl") else rn)
    done = tessella.refine_to_file(v, f, tmp_path / name, v, level=9, scheme="pn", weld=weld,
                                   max_memory=1 << 20)
    assert done["streamed"] and done["triangles"] == len(f) * 81 == len(rf)
    assert done["vertices"] == len(rv)
    assert (tmp_path / name).read_bytes() == (tmp_path / ("want-" + name)).read_bytes()


def read_ply_vertices(path: Path) -> np.ndarray:
    """The vertex records of a binary PLY as a structured array, read here with numpy alone."""
    data = path.read_bytes()
    head, _, body = data.partition(b"end_header\n")
    fields, count, in_vertex = [], 0, False
    for line in head.decode().splitlines():
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count, in_vertex = int(words[2]), True
        elif words[:1] == ["element"]:
            in_vertex = False
        elif in_vertex and words[:1] == ["property"]:
            fields.append((words[2], {"float": "<f4", "int": "<i4"}[words[1]]))
    return np.frombuffer(body, dtype=np.dtype(fields), count=count)


@pytest.mark.parametrize("weld", [True, False])
def test_fields_and_origins_stream_into_the_file(tmp_path, weld):
    v, f = icosphere(2)
    temperature = (v[:, 0] + 2 * v[:, 1]).astype(np.float64)
    height = v[:, 2].astype(np.float32)
    # Independent path: the whole refinement in memory, its fields and origins.
    whole = tessella.refine(v, f, v, level=9, weld=weld, origin=True,
                            point_data={"temperature": temperature, "height": height})
    done = tessella.refine_to_file(v, f, tmp_path / "a.ply", v, level=9, weld=weld, origin=True,
                                   max_memory=1 << 20,
                                   point_data={"temperature": temperature, "height": height})
    assert done["streamed"] and done["vertices"] == len(whole.vertices)
    got = read_ply_vertices(tmp_path / "a.ply")
    assert got.dtype.names[-6:] == ("temperature", "height", "face", "bary1", "bary2", "bary3")
    xyz = np.stack([got["x"], got["y"], got["z"]], axis=1)
    np.testing.assert_array_equal(xyz, whole.vertices)
    for name in ("temperature", "height"):
        np.testing.assert_array_equal(got[name], whole.point_data[name].reshape(-1))
    faces, bary = whole.origin
    np.testing.assert_array_equal(got["face"], faces)
    np.testing.assert_array_equal(np.stack([got["bary1"], got["bary2"], got["bary3"]], 1), bary)
    # A file read back carries its fields into the next file (PLY to glTF here).
    again = tessella.refine_file(tmp_path / "a.ply", tmp_path / "b.gltf", level=2)
    assert again["streamed"]
    assert b'"_temperature"' in (tmp_path / "b.gltf").read_bytes()
    # Formats without fields or origins refuse them, leaving nothing.
    with pytest.raises(FileFormatError, match="cannot hold per-vertex fields"):
        tessella.refine_to_file(v, f, tmp_path / "c.obj", point_data={"t": temperature})
    with pytest.raises(FileFormatError, match="origins"):
        tessella.refine_to_file(v, f, tmp_path / "c.glb", origin=True)
    with pytest.raises(MeshError, match="components"):
        tessella.refine_to_file(v, f, tmp_path / "c.ply", point_data={"t": np.zeros((len(v), 2))})
    with pytest.raises(MeshError, match="rows"):
        tessella.refine_to_file(v, f, tmp_path / "c.ply", point_data={"t": np.zeros(3)})
    assert not list(tmp_path.glob("c.*"))


@pytest.mark.parametrize("levels", [
    {"level": 5.5},
    {"level": 4.3, "spacing": "fractional-odd"},
    {"level": 1, "lod": "tolerance:0.002"},
])
def test_adaptive_refinements_stream_into_the_file(tmp_path, levels):
    v, f = icosphere(2)
    # Independent path: the whole adaptive refinement in memory, written by tessella.save.
    whole = tessella.refine(v, f, v, **levels)
    tessella.save(str(tmp_path / "want.ply"), whole.vertices, whole.faces, whole.normals)
    done = tessella.refine_to_file(v, f, tmp_path / "got.ply", v, max_memory=1 << 20, **levels)
    assert done["streamed"] and done["vertices"] == len(whole.vertices)
    assert (tmp_path / "got.ply").read_bytes() == (tmp_path / "want.ply").read_bytes()


def test_refine_to_file_errors_are_typed_and_leave_nothing(tmp_path):
    v, f = icosphere(0)
    with pytest.raises(OptionError, match="level"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", level=0)
    with pytest.raises(OptionError, match="scheme"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", scheme="nope")
    with pytest.raises(OptionError, match="spacing"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", spacing="wobbly")
    with pytest.raises(OptionError, match="lod"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", lod="screen:4")
    with pytest.raises(OptionError, match="level"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", level=float("nan"))
    with pytest.raises(OptionError, match="unknown option"):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", colour="red")
    with pytest.raises(MeshError):
        tessella.refine_to_file(v, np.array([[0, 1, 99]]), tmp_path / "x.ply")
    with pytest.raises(FileFormatError, match="extension"):
        tessella.refine_to_file(v, f, tmp_path / "x.fbx")
    with pytest.raises(FileNotFoundError):
        tessella.refine_file(tmp_path / "missing.obj", tmp_path / "x.ply")
    assert issubclass(OptionError, TessellaError) and issubclass(TessellaError, ValueError)
    assert list(tmp_path.iterdir()) == []



def test_unsynced_writes_land_whole_and_sync_folder_flushes_them(tmp_path):
    v, f = icosphere(2)
    tessella.refine_to_file(v, f, tmp_path / "synced.ply", v, level=6)
    tessella.refine_to_file(v, f, tmp_path / "cached.ply", v, level=6, sync=False)
    assert (tmp_path / "cached.ply").read_bytes() == (tmp_path / "synced.ply").read_bytes()
    tessella.sync_folder(tmp_path)
    with pytest.raises(FileNotFoundError):
        tessella.sync_folder(tmp_path / "missing")
    with pytest.raises(TypeError):
        tessella.refine_to_file(v, f, tmp_path / "x.ply", sync="yes")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cached.ply", "synced.ply"]

PEAK_SCRIPT = """
import resource, sys
sys.path.insert(0, {tests!r})
import numpy as np, tessella
from conftest import icosphere
v, f = icosphere(4)
level = int(sys.argv[1])
if level > 1:
    tessella.refine_to_file(v, f, sys.argv[2], v, level=level, max_memory=8 << 20)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def test_streaming_several_times_the_budget_keeps_memory_bounded(tmp_path):
    script = PEAK_SCRIPT.format(tests=str(Path(__file__).parent))
    run = lambda *a: int(subprocess.run([sys.executable, "-c", script, *a], check=True,
                                        capture_output=True, text=True).stdout.split()[-1])
    baseline = run("1", "unused")
    out = tmp_path / "big.ply"
    peak = run("20", str(out))
    size = out.stat().st_size
    assert size > 48 << 20, size  # 5120 faces x 400: 2M triangles, 1M vertices
    # The whole output in memory would take more than the file; the stream holds pieces of
    # about a megabyte (8 MiB budget) and the encoders' blocks.
    assert peak - baseline < size / 4, (peak, baseline, size)
    # Correct: equal to the whole refinement at the same size, written by save.
    v, f = icosphere(4)
    rv, rf, rn = tessella.refine(v, f, v, level=20)
    tessella.save(str(tmp_path / "want.ply"), rv, rf, rn)
    assert (tmp_path / "want.ply").read_bytes() == out.read_bytes()


def test_batch_reports_broken_files_and_resumes(tmp_path):
    src, out = tmp_path / "in", tmp_path / "out"
    good = write_folder(src, 6)
    rows = tessella.batch([src], out, level=3)
    assert len(rows) == len(good) + 2
    by_input = {Path(r["input"]).relative_to(src).as_posix(): r for r in rows}
    for name in ["garbage.obj", "sub/truncated.ply"]:
        assert by_input[name]["status"] == "failed" and name.split("/")[-1] in by_input[name]["error"]
    for name, faces in good:
        row = by_input[name]
        assert row["status"] == "ok" and row["triangles"] == faces * 9, row
        back_v, back_f, _ = tessella.load(str(out / Path(name).with_suffix(".ply")))
        assert len(back_f) == faces * 9
    manifest = [json.loads(l) for l in (out / "manifest.jsonl").read_text().splitlines()]
    assert sorted(r["input"] for r in manifest) == sorted(r["input"] for r in rows)
    # A second run redoes nothing that exists (modification times unchanged).
    mtimes = {p: p.stat().st_mtime_ns for p in out.rglob("*.ply")}
    again = tessella.batch([src], out, level=3)
    assert sorted(r["status"] for r in again) == ["failed"] * 2 + ["skipped"] * len(good)
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.ply")} == mtimes
    with pytest.raises(OptionError, match="no such file"):
        tessella.batch([tmp_path / "nothing"], out)
    with pytest.raises(OptionError, match="format"):
        tessella.batch([src], out, format="fbx")
    # A batch flushes its files itself: sync= is refused, pointing to sync_each.
    from tessella.dask import refine_partition

    with pytest.raises(OptionError, match="sync_each"):
        tessella.batch([src], out, sync=False)
    with pytest.raises(OptionError, match="sync_each"):
        refine_partition([src], out, sync=True)
    assert temporaries(out) == []


def test_dask_cluster_survives_a_killed_worker(tmp_path):
    distributed = pytest.importorskip("distributed")
    import tessella.dask

    src, out = tmp_path / "in", tmp_path / "out"
    good = write_folder(src, 12, level_sub=3)
    level = 24  # a few tenths of a second per file, so the kill lands while files are in work
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        pids = client.run(os.getpid)
        assert len(pids) == 2
        killed = []

        out_real = os.path.realpath(out)

        def writing(pid):
            """The output file worker `pid` holds open in the output folder, if any: unnamed
            (`/out/#123 (deleted)`, Linux's O_TMPFILE) or a named temporary file."""
            try:
                links = [os.readlink(f"/proc/{pid}/fd/{fd}") for fd in os.listdir(f"/proc/{pid}/fd")]
            except OSError:
                return None
            return next((l for l in links if l.startswith(out_real + os.sep)), None)

        def kill_one_worker_mid_run():
            deadline = time.time() + 120
            while time.time() < deadline:
                for pid in pids.values():
                    temp = writing(pid)
                    if temp:
                        os.kill(pid, 9)  # SIGKILL, in the middle of writing its file
                        killed.append((pid, temp))
                        return
                time.sleep(0.002)

        killer = threading.Thread(target=kill_one_worker_mid_run)
        killer.start()
        rows = tessella.dask.refine_files([src], out, client, level=level)
        killer.join()
    assert killed, "no worker was caught writing"
    # The killed worker's file had no name (O_TMPFILE) and went with it; where the system
    # has no unnamed files, its named temporary file stays behind and the run removes it.
    by_input = {Path(r["input"]).relative_to(src).as_posix(): r for r in rows}
    assert len(rows) == len(good) + 2
    assert by_input["garbage.obj"]["status"] == "failed"
    assert by_input["sub/truncated.ply"]["status"] == "failed"
    for name, faces in good:
        assert by_input[name]["status"] == "ok", by_input[name]
        _, back_f, _ = tessella.load(str(out / Path(name).with_suffix(".ply")))
        assert len(back_f) == faces * level * level, name  # complete
    assert temporaries(out) == []
    manifest = [json.loads(l) for l in (out / "manifest.jsonl").read_text().splitlines()]
    assert len(manifest) == len(rows)


def test_dask_bag_partitions_of_paths_and_bytes(tmp_path):
    pytest.importorskip("distributed")
    import dask
    import dask.bag as db
    import tessella.dask

    src, out = tmp_path / "in", tmp_path / "out"
    good = write_folder(src, 4)
    paths = [str(src / name) for name, _ in good]
    items = paths[:2] + [(Path(p).name, Path(p).read_bytes()) for p in paths[2:]]
    with dask.config.set(scheduler="synchronous"):
        rows = db.from_sequence(items, npartitions=2).map_partitions(
            tessella.dask.refine_partition, str(out), level=2).compute()
    assert [r["status"] for r in rows] == ["ok"] * 4
    for (name, faces), row in zip(good, rows):
        assert row["triangles"] == faces * 4
        assert Path(row["output"]).exists()


def test_dask_files_per_task_gives_the_same_files_and_rows(tmp_path):
    distributed = pytest.importorskip("distributed")
    import tessella.dask

    src = tmp_path / "in"
    good = write_folder(src, 5)
    # Independent of Dask: tessella.batch in this process.
    want = {r["input"]: r for r in tessella.batch([src], tmp_path / "want", level=3)}
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=2,
                            dashboard_address=None) as client:
        for per_task in (1, 3, 100, None):
            out = tmp_path / f"out-{per_task}"
            rows = tessella.dask.refine_files([src], out, client, level=3, files_per_task=per_task)
            assert sorted(r["input"] for r in rows) == sorted(want), per_task
            for row in rows:
                w = want[row["input"]]
                assert (row["status"], row["triangles"]) == (w["status"], w["triangles"]), row
                if row["status"] == "ok":
                    got = Path(row["output"]).read_bytes()
                    assert got == Path(w["output"]).read_bytes(), row["input"]
            manifest = (out / "manifest.jsonl").read_text().splitlines()
            assert len(manifest) == len(good) + 2
        with pytest.raises(OptionError, match="files_per_task"):
            tessella.dask.refine_files([src], tmp_path / "bad", client, files_per_task=0)


def test_dask_default_task_size_follows_the_estimated_output(tmp_path):
    pytest.importorskip("distributed")
    from tessella.dask import TASK_BYTES, _files_per_task

    class Client:  # what _files_per_task asks of a client: its workers' threads
        def nthreads(self):
            return {"a": 1, "b": 1}

    small = tmp_path / "small.ply"
    small.write_bytes(b"x" * 8000)
    todo = [(str(small), "out")] * 200  # 1.6 MB of inputs
    # 1.6 MB x 4² = 26 MB of output: under two tasks' worth, so one task per thread.
    assert _files_per_task(Client(), todo, 4) == 100
    # x 8² = 102 MB: six tasks of about 16 MB.
    assert _files_per_task(Client(), todo, 8) == -(-200 // int(200 * 8000 * 64 // TASK_BYTES))
    # x 16² = 410 MB: capped at four tasks per thread.
    assert _files_per_task(Client(), todo, 16.0) == 25
    # Missing inputs count for nothing (refining them reports them); a bad level counts as
    # the default level 8 (refining refuses it).
    assert _files_per_task(Client(), [("missing", "out")] * 10, 4) == 5
    assert _files_per_task(Client(), todo, "x") == _files_per_task(Client(), todo, 8)
