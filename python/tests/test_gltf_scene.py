"""`tessella.refine_gltf` / `refine_gltf_bytes`: whole glTF scenes refined and written back.

The outputs are read here with struct and json (the GLB container, glTF 2.0 section 4.4), not
with tessella: every node, material, image, animation and camera is kept, every primitive
keeps its material and mode, each triangle primitive has level² times its triangles (index
accessor counts); bytes in/bytes out equals the file written; broken files and bad options
raise the package's classes and leave no output.
"""

import json
import struct
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import tessella
from conftest import REPO

SAMPLES = REPO / "samples"
SCENE = SAMPLES / "scene.glb"
KEPT = ("scenes", "nodes", "materials", "textures", "images", "samplers", "skins", "animations", "cameras")
TRIANGLES, STRIP, FAN = 4, 5, 6


def read_glb(data):
    """(json, bin) of a GLB container, checked as the specification lays it out."""
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    chunks, at = {}, 12
    while at < len(data):
        size, kind = struct.unpack_from("<I4s", data, at)
        assert size % 4 == 0
        chunks[kind] = data[at + 8 : at + 8 + size]
        at += 8 + size
    assert at == len(data)
    return json.loads(chunks[b"JSON"]), chunks.get(b"BIN\0", b"")


def glb(doc, bin_chunk):
    """A GLB container of `doc` and `bin_chunk`, written here."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    bin_chunk += b"\0" * (-len(bin_chunk) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text
    if bin_chunk:
        body += struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def primitives(doc):
    """((mesh, primitive), primitive's JSON) in the document's order."""
    return [((m, p), prim) for m, mesh in enumerate(doc["meshes"]) for p, prim in enumerate(mesh["primitives"])]


def triangle_count(doc, prim):
    """Triangles of a triangle primitive, from its index accessor's count (or its positions')."""
    accessor = prim["indices"] if "indices" in prim else prim["attributes"]["POSITION"]
    count = doc["accessors"][accessor]["count"]
    mode = prim.get("mode", TRIANGLES)
    return count // 3 if mode == TRIANGLES else max(count - 2, 0)


@pytest.mark.parametrize("sample", ["scene.glb", "scene-quantized.glb", "animated-creature.glb"])
def test_level_2_keeps_the_scene_and_multiplies_triangles(tmp_path, sample):
    src, dst = SAMPLES / sample, tmp_path / "out.glb"
    report = tessella.refine_gltf(src, dst, level=2)
    assert dst.is_file() and isinstance(report, tessella.SceneReport)
    before, _ = read_glb(src.read_bytes())
    after, bin_chunk = read_glb(dst.read_bytes())
    for key in KEPT:
        assert len(after.get(key, [])) == len(before.get(key, [])), key
    for key in ("nodes", "materials", "cameras", "scene"):
        assert after.get(key) == before.get(key), key  # they name no accessor: kept as they were
    assert after.get("extensions") == before.get("extensions")  # KHR_lights_punctual's lights
    assert len(after["meshes"]) == len(before["meshes"])
    assert [k for k, _ in primitives(after)] == [k for k, _ in primitives(before)]
    assert len(bin_chunk) >= after["buffers"][0]["byteLength"] and "uri" not in after["buffers"][0]

    refined = []
    for (key, old), (_, new) in zip(primitives(before), primitives(after)):
        assert new.get("material") == old.get("material"), key
        assert len(new.get("targets", [])) == len(old.get("targets", [])), key
        mode = old.get("mode", TRIANGLES)
        if mode in (TRIANGLES, STRIP, FAN):
            assert new.get("mode", TRIANGLES) == TRIANGLES, key
            assert set(old["attributes"]) <= set(new["attributes"]), key
            coarse = triangle_count(before, old)
            assert triangle_count(after, new) == 4 * coarse, key
            refined.append((key, coarse, triangle_count(after, new)))
        else:  # points and lines are copied
            assert new.get("mode") == mode
            count = lambda doc, prim: doc["accessors"][prim["attributes"]["POSITION"]]["count"]  # noqa: E731
            assert count(after, new) == count(before, old), key
    assert refined, "the sample has triangle primitives"

    # The report: one row per triangle primitive, in the document's order.
    assert [((r.mesh, r.primitive), r.coarse_triangles, r.triangles) for r in report] == refined
    assert all(r.level == 2 and r.triangles == r.coarse_triangles * 4 for r in report)
    assert all(0 <= r.degenerate <= r.coarse_triangles and r.vertices > 0 for r in report)
    assert report.levels == [2] and report.path == str(dst) and report.warnings == []
    assert report.triangles == 4 * report.coarse_triangles == sum(t for _, _, t in refined)
    assert "level 2" in repr(report) and report[0] == report.primitives[0]
    assert report[0]._asdict()["mesh"] == report[0].mesh


def test_bytes_in_bytes_out_is_the_file_the_path_form_writes(tmp_path):
    dst = tmp_path / "out.glb"
    tessella.refine_gltf(SCENE, dst, level=3, scheme="phong", alpha=0.6)
    data = tessella.refine_gltf_bytes(SCENE.read_bytes(), level=3, scheme="phong", alpha=0.6)
    assert isinstance(data, bytes)
    assert data == dst.read_bytes()
    # Any bytes-like object; and the default level is 8 in both forms.
    assert tessella.refine_gltf_bytes(memoryview(SCENE.read_bytes()), level=3, scheme="phong", alpha=0.6) == data
    report = tessella.refine_gltf(str(SCENE), str(dst))
    assert report.levels == [8]
    assert tessella.refine_gltf_bytes(bytearray(SCENE.read_bytes())) == dst.read_bytes()


def test_gltf_output_and_gltf_bytes_with_buffers(tmp_path):
    dst = tmp_path / "out.gltf"
    report = tessella.refine_gltf(SCENE, dst, level=1, sync=False)
    doc = json.loads(dst.read_text())
    assert doc["buffers"][0]["uri"] == "out.bin" and (tmp_path / "out.bin").is_file()
    assert [r.triangles for r in report] == [r.coarse_triangles for r in report]
    again = tessella.refine_gltf_bytes(
        dst.read_bytes(), name="out.gltf", buffers={"out.bin": (tmp_path / "out.bin").read_bytes()}, level=2
    )
    after, _ = read_glb(again)
    tris = [triangle_count(after, p) for _, p in primitives(after) if p.get("mode", TRIANGLES) == TRIANGLES]
    assert tris == [4 * r.coarse_triangles for r in report]
    with pytest.raises(tessella.FileFormatError, match="out.bin"):
        tessella.refine_gltf_bytes(dst.read_bytes(), name="out.gltf")


def test_images_named_by_uri_are_copied_beside_the_output_or_reported(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    tessella.refine_gltf(SCENE, tmp_path / "a" / "in.gltf", level=1)
    doc = json.loads((tmp_path / "a" / "in.gltf").read_text())
    doc["images"][0] = {"uri": "textures/tex%20one.png"}  # percent-encoded, in a subfolder
    (tmp_path / "a" / "in.gltf").write_text(json.dumps(doc))
    (tmp_path / "a" / "textures").mkdir()
    (tmp_path / "a" / "textures" / "tex one.png").write_bytes(b"not really a png")
    report = tessella.refine_gltf(tmp_path / "a" / "in.gltf", tmp_path / "b" / "out.glb", level=2)
    assert report.warnings == []
    assert (tmp_path / "b" / "textures" / "tex one.png").read_bytes() == b"not really a png"
    after, _ = read_glb((tmp_path / "b" / "out.glb").read_bytes())
    assert after["images"] == doc["images"]

    (tmp_path / "a" / "textures" / "tex one.png").unlink()
    with pytest.warns(RuntimeWarning, match="tex one.png"):
        report = tessella.refine_gltf(tmp_path / "a" / "in.gltf", tmp_path / "b" / "again.glb", level=2)
    assert len(report.warnings) == 1 and "missing" in report.warnings[0]
    assert (tmp_path / "b" / "again.glb").is_file()  # the geometry is written all the same


def test_max_edge_gives_each_primitive_its_level(tmp_path):
    report = tessella.refine_gltf(SCENE, tmp_path / "out.glb", max_edge=0.05)
    assert all(1 <= r.level <= 64 and r.triangles == r.coarse_triangles * r.level**2 for r in report)
    finer = tessella.refine_gltf(SCENE, tmp_path / "finer.glb", max_edge=0.025)
    assert all(f.level >= r.level for f, r in zip(finer, report))
    assert finer.triangles > report.triangles


def _no_output(folder, name):
    """Nothing named `name`, and no temporary file, was left in `folder`."""
    assert not (folder / name).exists()
    assert [p.name for p in folder.iterdir() if p.name != "in.glb"] == []


def test_a_truncated_glb_raises_and_leaves_no_file(tmp_path):
    data = SCENE.read_bytes()
    for cut in (len(data) // 2, 30, 11):
        src = tmp_path / "in.glb"
        src.write_bytes(data[:cut])
        with pytest.raises(tessella.FileFormatError) as e:
            tessella.refine_gltf(src, tmp_path / "out.glb", level=2)
        assert "in.glb" in str(e.value) and e.value.message
        _no_output(tmp_path, "out.glb")
        with pytest.raises(tessella.FileFormatError, match="truncated.glb"):
            tessella.refine_gltf_bytes(data[:cut], name="truncated.glb")


@pytest.mark.parametrize(
    "break_it, words",
    [
        (lambda doc: doc["meshes"][0]["primitives"][0].update(indices=len(doc["accessors"]) + 5), "accessor|index|indices"),
        (lambda doc: doc["meshes"][0]["primitives"][0].update(material=len(doc["materials"])), "material|index"),
        (lambda doc: doc["nodes"][0].update(mesh=99), "mesh|index"),
        (lambda doc: doc["accessors"][0].update(count=10**7), "accessor|buffer|length|bytes"),
    ],
    ids=["indices", "material", "node-mesh", "accessor-count"],
)
def test_an_index_past_the_end_raises_and_leaves_no_file(tmp_path, break_it, words):
    doc, bin_chunk = read_glb(SCENE.read_bytes())
    break_it(doc)
    src = tmp_path / "in.glb"
    src.write_bytes(glb(doc, bin_chunk))
    with pytest.raises(tessella.FileFormatError, match=words) as e:
        tessella.refine_gltf(src, tmp_path / "out.glb", level=2)
    assert "in.glb" in str(e.value)
    _no_output(tmp_path, "out.glb")
    with pytest.raises(tessella.FileFormatError, match=words):
        tessella.refine_gltf_bytes(src.read_bytes())


def test_level_and_max_edge_together_raise(tmp_path):
    with pytest.raises(tessella.OptionError, match=r"level=.*cannot be combined with max_edge="):
        tessella.refine_gltf(SCENE, tmp_path / "out.glb", level=2, max_edge=0.1)
    with pytest.raises(tessella.OptionError, match=r"level=.*cannot be combined with max_edge="):
        tessella.refine_gltf_bytes(SCENE.read_bytes(), level=2, max_edge=0.1)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "options, named",
    [
        (dict(lod="tolerance:0.01"), "lod="),
        (dict(lod=tessella.Lod.tolerance(0.01)), "lod="),
        (dict(spacing="equal"), "spacing='equal'"),
        (dict(level=2.5), "a fractional level"),
        (dict(displace=("sine", 0.1, 1.0)), "displace="),
        (dict(origin=True), "origin=True"),
        (dict(tags={"edges": []}), "tags="),
        (dict(crease_angle=30.0), "crease_angle="),
        (dict(weld=False), "weld=False"),
        (dict(backend="gpu"), "backend='gpu'"),
        (dict(uvs=[[0.0, 0.0]]), "uvs="),
    ],
)
def test_merged_mesh_options_are_refused_as_the_cli_refuses_them(tmp_path, options, named):
    for call in (
        lambda: tessella.refine_gltf(SCENE, tmp_path / "out.glb", **options),
        lambda: tessella.refine_gltf_bytes(SCENE.read_bytes(), **options),
    ):
        with pytest.raises(tessella.OptionError) as e:
            call()
        message = str(e.value)
        assert named in message and "works on one merged mesh" in message, message
        assert "level= or max_edge=" in message and "tessella.refine_file()" in message
    assert list(tmp_path.iterdir()) == []


def test_defaults_of_refused_options_and_whole_float_levels_are_accepted(tmp_path):
    a = tessella.refine_gltf_bytes(SCENE.read_bytes(), level=2)
    b = tessella.refine_gltf_bytes(
        SCENE.read_bytes(), level=2.0, weld=True, backend="cpu", spacing="grid", lod=None, origin=False
    )
    assert a == b
    assert tessella.refine_gltf_bytes(SCENE.read_bytes(), level=np.int64(2)) == a
    with pytest.raises(TypeError, match="level must be a whole number"):
        tessella.refine_gltf_bytes(SCENE.read_bytes(), level="2")


@pytest.mark.parametrize(
    "options, error, words",
    [
        (dict(level=0), tessella.OptionError, "level must be 1 or more"),
        (dict(max_edge=-1.0), tessella.OptionError, "max_edge must be a positive length"),
        (dict(max_edge=float("nan")), tessella.OptionError, "max_edge must be a positive length"),
        (dict(scheme="bezier"), tessella.OptionError, "schemes()"),
        (dict(normals_mode="cubic"), tessella.OptionError, "normals_mode"),
        (dict(alpha=float("inf")), tessella.OptionError, "alpha"),
        (dict(colour="red"), tessella.OptionError, "unknown option"),
        (dict(tangents="guessed"), tessella.OptionError, "tangents="),
        (dict(joint_sets=0), tessella.OptionError, "joint_sets=0: give None"),
        (dict(joint_sets=9), tessella.OptionError, "from 1 to 8"),
        (dict(joint_sets=-1), tessella.OptionError, "joint_sets=-1"),
    ],
)
def test_bad_options_raise(tmp_path, options, error, words):
    with pytest.raises(error, match=words):
        tessella.refine_gltf(SCENE, tmp_path / "out.glb", **options)
    assert list(tmp_path.iterdir()) == []


def test_paths_that_are_not_gltf_scenes(tmp_path):
    with pytest.raises(tessella.FileFormatError, match=r"\.gltf and \.glb"):
        tessella.refine_gltf(SCENE, tmp_path / "out.ply")
    with pytest.raises(tessella.FileFormatError, match="unknown mesh file extension"):
        tessella.refine_gltf(SCENE, tmp_path / "out.xyz")
    with pytest.raises(tessella.FileFormatError, match=r"\.gltf and \.glb"):
        tessella.refine_gltf(SAMPLES / "creature.obj", tmp_path / "out.glb")
    with pytest.raises(tessella.FileFormatError, match=r"\.gltf and \.glb"):
        tessella.refine_gltf_bytes(SCENE.read_bytes(), name="scene.obj")
    with pytest.raises(FileNotFoundError):
        tessella.refine_gltf(tmp_path / "missing.glb", tmp_path / "out.glb")
    with pytest.raises(TypeError, match="refine_gltf_bytes"):
        tessella.refine_gltf(SCENE.read_bytes(), tmp_path / "out.glb")  # type: ignore[arg-type]
    assert list(tmp_path.iterdir()) == []


def test_another_thread_runs_while_the_scene_is_refined():
    data = SCENE.read_bytes()
    stamps = {}
    started = threading.Event()

    def worker():
        started.set()
        stamps["start"] = time.perf_counter()
        tessella.refine_gltf_bytes(data, level=12)
        stamps["end"] = time.perf_counter()

    old = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)  # the main thread runs only while the worker released the GIL
    try:
        t = threading.Thread(target=worker)
        t.start()
        started.wait()
        ours = [time.perf_counter() for _ in range(2000)]
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert stamps["start"] < ours[0]
    assert ours[-1] < stamps["end"], "the main thread could not run while the scene was refined"


def test_tangents_recomputed_or_carried():
    """Both tangent modes give the same surface; only the TANGENT accessor differs."""
    data = SCENE.read_bytes()
    recomputed = tessella.refine_gltf_bytes(data, level=2)
    carried = tessella.refine_gltf_bytes(data, level=2, tangents="carried")
    assert recomputed == tessella.refine_gltf_bytes(data, level=2, tangents="recomputed")
    assert carried != recomputed
    a, b = read_glb(recomputed)[0], read_glb(carried)[0]
    assert [sorted(p["attributes"]) for _, p in primitives(a)] == [sorted(p["attributes"]) for _, p in primitives(b)]


def test_joint_sets_reach_the_scene():
    """joint_sets=N adds sets only where a vertex needs them: the creature's seven joints fit its
    two sets, so the bytes are the default's (the widening itself is tested in Rust)."""
    creature = SAMPLES / "animated-creature.glb"
    default = tessella.refine_gltf_bytes(creature.read_bytes(), level=2)
    wide = tessella.refine_gltf_bytes(creature.read_bytes(), level=2, joint_sets=4)
    json, _ = read_glb(wide)
    attributes = json["meshes"][0]["primitives"][0]["attributes"]
    assert "JOINTS_1" in attributes and "JOINTS_2" not in attributes  # seven joints fit two sets
    assert wide == default
