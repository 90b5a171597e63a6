"""tessella.load_animated: glTF skins, morph targets and clips posed into arrays for Refiner.

Checked against data tessella did not make: the positions three.js r187 itself computed for
`crates/tessella-io/tests/fixtures/three/skinned.gltf` (`skinned-poses.json`, made by
`fixtures/three/make.mjs`), and the bundled creature sample against its static OBJ.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import tessella
from conftest import REPO

THREE = REPO / "crates" / "tessella-io" / "tests" / "fixtures" / "three"
CREATURE = REPO / "samples" / "animated-creature.glb"
CREATURE_OBJ = REPO / "samples" / "creature.obj"


def diagonal(points: np.ndarray) -> float:
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def assert_close(got: np.ndarray, want: np.ndarray, what: str) -> None:
    """Every coordinate within 1e-6 of the expected points' bounding-box diagonal."""
    assert got.shape == want.shape, what
    tolerance = 1e-6 * diagonal(want)
    worst = float(np.abs(got.astype(np.float64) - want).max())
    assert worst <= tolerance, f"{what}: off by {worst} > {tolerance}"


@pytest.fixture(scope="module")
def three():
    expected = json.loads((THREE / "skinned-poses.json").read_text())
    return tessella.load_animated(THREE / "skinned.gltf"), expected


@pytest.fixture(scope="module")
def creature():
    return tessella.load_animated(str(CREATURE))


def test_three_js_poses(three):
    anim, expected = three
    assert anim.vertex_count == expected["vertex_count"]
    assert expected["clip"] in anim.clips
    # No clip: the rest pose three.js binds the skin in.
    rest, rest_normals = anim.pose(None, 0.0)
    assert rest.dtype == np.float32 and rest.shape == (anim.vertex_count, 3)
    assert rest_normals.dtype == np.float32 and rest_normals.shape == rest.shape
    assert_close(rest, np.array(expected["bind_positions"]), "bind pose")
    moved = 0.0
    for t, want in zip(expected["times"], expected["positions"]):
        want = np.array(want, dtype=np.float64)
        positions, normals = anim.pose(expected["clip"], t)
        assert_close(positions, want, f"t = {t}")
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
        moved = max(moved, float(np.abs(want - rest).max()))
        # The clip by index poses the same.
        by_index, _ = anim.pose(anim.clips.index(expected["clip"]), t)
        np.testing.assert_array_equal(by_index, positions)
    assert moved > 1.0  # the clip really moves the mesh


def test_creature_clips_durations_and_faces(creature):
    assert creature.clips == ["wave", "hop", "breathe"]
    for clip, seconds in [("wave", 2.0), ("hop", 0.8), ("breathe", 2.0)]:
        assert creature.duration(clip) == seconds
        assert creature.duration(creature.clips.index(clip)) == creature.duration(clip)
    assert creature.has_normals
    f = creature.faces
    assert f.dtype == np.uint32 and f.ndim == 2 and f.shape[1] == 3
    assert f is creature.faces and not f.flags.writeable
    assert int(f.max()) < creature.vertex_count
    text = repr(creature)
    assert text.startswith("tessella.AnimatedMesh(") and '"wave"' in text
    assert f"vertex_count={creature.vertex_count}" in text


def read_obj(path):
    """The OBJ's ``v``/``vn`` rows and its ``f`` rows (``a//a`` corners), parsed here, in the
    file's order (``tessella.load`` renumbers OBJ corners)."""
    v, vn, f = [], [], []
    for line in path.read_text().splitlines():
        head, *rest = line.split()
        if head == "v":
            v.append([float(x) for x in rest])
        elif head == "vn":
            vn.append([float(x) for x in rest])
        elif head == "f":
            f.append([int(c.split("/")[0]) - 1 for c in rest])
    return np.array(v), np.array(vn), np.array(f)


def test_creature_rest_pose_is_the_obj(creature):
    v, vn, f = read_obj(CREATURE_OBJ)
    rest, normals = creature.pose()
    assert rest.shape == v.shape == (creature.vertex_count, 3)
    np.testing.assert_allclose(rest, v, rtol=0, atol=1e-5)
    np.testing.assert_allclose(normals, vn, rtol=0, atol=1e-5)
    np.testing.assert_array_equal(creature.faces, f)
    # tessella's own reader gives the same surface (corners renumbered).
    lv, lf, _ = tessella.load(CREATURE_OBJ)
    np.testing.assert_allclose(lv[lf], rest[creature.faces], rtol=0, atol=1e-5)


def test_creature_posed_frames_refine(creature):
    r = tessella.Refiner(creature.faces, scheme="pn", level=3, backend="cpu")
    for clip in creature.clips:
        positions, normals = creature.pose(clip, 0.37 * creature.duration(clip))
        rv, rf, rn = r.refine(positions, normals)
        assert rv.dtype == np.float32 and rv.shape == (r.vertex_count, 3)
        assert rn.shape == rv.shape
        assert rf.shape == (len(creature.faces) * 9, 3)
    # Refiner.refine(*pose) directly, built from the rest pose; a pose moves the creature.
    r = tessella.Refiner(creature.faces, vertices=creature.pose()[0], scheme="pn", level=2, backend="cpu")
    rv, rf, rn = r.refine(*creature.pose("hop", 0.3))
    assert rv.shape == (r.vertex_count, 3) and rf.shape == (len(creature.faces) * 4, 3)
    p, n = creature.pose("wave", 0.5)
    out = tessella.refine(p, creature.faces, n, scheme="pn", level=2, backend="cpu")
    assert out[1].shape == (len(creature.faces) * 4, 3)
    assert float(np.abs(p - creature.pose()[0]).max()) > 1e-3


def test_computed_normals_when_the_file_has_none(tmp_path):
    v, _, f = read_obj(CREATURE_OBJ)
    v = v.astype(np.float32)
    path = tmp_path / "plain.gltf"
    tessella.save(path, v, f)
    anim = tessella.load_animated(path)
    assert anim.clips == [] and not anim.has_normals
    positions, normals = anim.pose(None, 0.0)
    np.testing.assert_allclose(positions, v, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    # The normals refine computes from the positions.
    given = tessella.refine(positions, f, normals, scheme="pn", level=2, backend="cpu")
    computed = tessella.refine(positions, f, None, scheme="pn", level=2, backend="cpu")
    np.testing.assert_allclose(given[0], computed[0], atol=1e-5)


def test_unknown_clip_name(creature):
    with pytest.raises(tessella.OptionError, match="dance") as e:
        creature.pose("dance", 0.0)
    assert "animated-creature.glb" in str(e.value) and "wave" in str(e.value)
    with pytest.raises(tessella.OptionError, match="dance"):
        creature.duration("dance")


@pytest.mark.parametrize("index", [3, 100, -1])
def test_clip_index_out_of_range(creature, index):
    with pytest.raises(tessella.OptionError, match=f"no clip \"?{index}"):
        creature.pose(index, 0.0)
    with pytest.raises(tessella.OptionError):
        creature.duration(index)


def test_bad_clip_type(creature):
    with pytest.raises(TypeError):
        creature.pose(1.5, 0.0)
    with pytest.raises(TypeError):
        creature.pose(True, 0.0)


@pytest.mark.parametrize("time", [math.nan, math.inf, -math.inf])
def test_non_finite_time(creature, time):
    with pytest.raises(tessella.OptionError, match="not a finite number") as e:
        creature.pose("wave", time)
    assert "animated-creature.glb" in str(e.value)


def test_not_gltf():
    with pytest.raises(tessella.FileFormatError, match="creature.obj"):
        tessella.load_animated(CREATURE_OBJ)


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothing.glb"):
        tessella.load_animated(tmp_path / "nothing.glb")


def test_broken_file(tmp_path):
    path = tmp_path / "garbage.glb"
    path.write_bytes(b"glTF\x02\x00\x00\x00 this is not a glb")
    with pytest.raises(tessella.FileFormatError, match="garbage.glb"):
        tessella.load_animated(path)


def test_invalid_animation(tmp_path):
    """A file that parses but whose animation the core refuses (a channel on a node with a
    matrix) is a broken file, named in the message."""
    doc = json.loads((THREE / "skinned.gltf").read_text())
    animated = doc["animations"][0]["channels"][0]["target"]["node"]
    node = doc["nodes"][animated]
    for key in ("translation", "rotation", "scale"):
        node.pop(key, None)
    node["matrix"] = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1]
    path = tmp_path / "matrix.gltf"
    path.write_text(json.dumps(doc))
    with pytest.raises(tessella.FileFormatError, match="matrix.gltf: .*has a matrix"):
        tessella.load_animated(path)
