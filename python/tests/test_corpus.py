"""The bad-input corpus shared with the CLI tests (tests/corpus/, described by expected.json):
every bad file raises the tessella exception named for it in expected.json's
"python_exception" column (MeshError or FileFormatError), carrying its expected message (never
a crash); every good file loads with its expected counts. Also: the default backend prints nothing on a machine
without a display."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import tessella

CORPUS = Path(__file__).resolve().parents[2] / "tests" / "corpus"
EXPECTED = json.loads((CORPUS / "expected.json").read_text())


def test_the_corpus_is_large():
    assert len(EXPECTED["bad"]) >= 40
    assert len(EXPECTED["good"]) >= 10
    assert sorted(EXPECTED["python_exception"]) == sorted(EXPECTED["bad"])


@pytest.mark.parametrize("name", sorted(EXPECTED["bad"]))
def test_bad_file_raises_its_exception_and_message(name):
    # load() refuses malformed files; geometry it returns as stored (NaN, zero normals,
    # degenerate triangles), which refine() then refuses: the message comes from one of them.
    with pytest.raises(Exception) as info:
        v, f, n = tessella.load(str(CORPUS / "bad" / name))
        tessella.refine(v, f, n, level=2)
    expected = getattr(tessella, EXPECTED["python_exception"][name])
    assert type(info.value) is expected, repr(info.value)
    assert isinstance(info.value, (tessella.TessellaError, ValueError))
    assert EXPECTED["bad"][name] in str(info.value), str(info.value)


@pytest.mark.parametrize("name", sorted(EXPECTED["good"]))
def test_good_file_loads(name):
    v, f, _ = tessella.load(str(CORPUS / "good" / name))
    assert len(v) == EXPECTED["good"][name]["vertices"]
    assert len(f) == EXPECTED["good"][name]["triangles"]


def test_the_default_backend_prints_nothing_without_a_display():
    code = (
        "import numpy as np, tessella\n"
        "v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)\n"
        "f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.uint32)\n"
        "for level in (2, 8, 32):\n"
        "    tessella.refine(v, f, level=level)\n"
        "print('done')\n"
    )
    env = {k: val for k, val in os.environ.items() if k not in ("XDG_RUNTIME_DIR", "WAYLAND_DISPLAY", "DISPLAY")}
    env["VK_LOADER_DEBUG"] = "all"  # any Vulkan instance would print here
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "done"
    assert run.stderr == "", run.stderr
