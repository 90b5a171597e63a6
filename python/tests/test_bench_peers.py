"""The peer benchmark compares equal outputs: every library it runs makes exactly the vertices
and triangles tessella makes (run small, with whichever peers are installed)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "examples" / "bench_peers.py"


def test_every_case_has_tessellas_output_size():
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--subdivisions", "1", "--level", "4", "--repeat", "1",
         "--json"],
        capture_output=True, text=True, timeout=600,
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["faces"] == 80 and report["level"] == 4
    rows = {r["case"]: r for r in report["rows"]}
    pn = rows["tessella pn"]
    # 80 faces to level 4: 80 * 16 triangles; V + E*3 + F*3 vertices (42 + 120*3 + 80*3).
    assert pn["triangles"] == 80 * 16
    assert pn["vertices"] == 42 + 120 * 3 + 80 * 3
    for name, row in rows.items():
        assert (row["vertices"], row["triangles"]) == (pn["vertices"], pn["triangles"]), name
        assert row["seconds"] > 0 and row["output_bytes"] > 0, name
    # trimesh is one of the test environment's packages, so one peer at least is compared.
    assert "trimesh midpoint" in rows


def test_fresh_and_reused_memory_are_put_against_the_fresh_memory_bound():
    """tessella's rows have their calls into fresh and into reused memory and the numpy
    fresh-memory fill measured in their process; the peers' rows have none; the text report
    prints that table."""
    args = [sys.executable, str(SCRIPT), "--subdivisions", "2", "--level", "8", "--repeat", "2"]
    done = subprocess.run(args + ["--json"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    rows = {r["case"]: r for r in json.loads(done.stdout)["rows"]}
    for name, row in rows.items():
        keys = {"fresh_seconds", "reused_seconds", "fresh_fill_bytes_per_s"}
        assert (keys <= set(row)) == name.startswith("tessella"), name
    pn = rows["tessella pn"]
    assert pn["fresh_seconds"] > 0 and pn["reused_seconds"] > 0
    assert pn["fresh_fill_bytes_per_s"] > 0
    text = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert text.returncode == 0, text.stderr
    table = text.stdout.split("against the fresh-memory bound")[1].splitlines()
    assert any(line.startswith("| tessella pn |") for line in table)
    assert not any(line.startswith("| trimesh") for line in table), "peers have no bound row"


def test_level_must_be_a_power_of_two():
    done = subprocess.run([sys.executable, str(SCRIPT), "--level", "6"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode != 0 and "power of two" in done.stderr


def test_bandwidth_check_reports_both_fills(cli):
    """`--bandwidth` runs numpy's fill and `tessella bench --bandwidth-only` in one run: every
    figure is there and positive, and the fill the tables divide by is the faster of the two
    fills tessella measured (no speed is asserted: it depends on the machine)."""
    done = subprocess.run([sys.executable, str(SCRIPT), "--bandwidth", cli, "--repeat", "1",
                           "--json"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert set(report["numpy_fill_bytes_per_s"]) == {"256 MiB", "1024 MiB"}
    assert all(r > 0 for r in report["numpy_fill_bytes_per_s"].values())
    t = report["tessella"]
    for key in ("fill_plain_bytes_per_s", "fill_nt_bytes_per_s",
                "fill_plain_one_thread_bytes_per_s", "copy_bytes_per_s",
                "copy_nt_bytes_per_s", "fresh_fill_bytes_per_s"):
        assert t[key] > 0, key
    assert t["fill_bytes_per_s"] == max(t["fill_plain_bytes_per_s"], t["fill_nt_bytes_per_s"])
    assert report["fill_over_numpy"] > 0
    assert report["one_thread_fill_over_numpy"] == pytest.approx(
        t["fill_plain_one_thread_bytes_per_s"] / max(report["numpy_fill_bytes_per_s"].values()))
