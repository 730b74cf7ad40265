"""``python -m dualform deform`` reproduces ``dualform deform`` on every
scenario in tests/scenarios/ to 1e-12 of the diagonal. The subdivided
armadillo cases (tens of seconds each) are marked slow."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import dualform as dfm
from conftest import SCENARIOS

ALL = sorted(SCENARIOS.glob("*.json"))
HEAVY = {"scale-armadillo-x16-leg", "scale-armadillo-x4-all", "scale-armadillo-x4-leg"}


def _cases():
    for path in ALL:
        marks = [pytest.mark.slow] if path.stem in HEAVY else []
        yield pytest.param(path, id=path.stem, marks=marks)


def _positions(context, path):
    with dfm.Mesh.load(context, path) as mesh:
        return mesh.positions(), mesh.info.diagonal, mesh.triangles()


@pytest.mark.parametrize("scenario", _cases())
def test_reproduces_the_cli(scenario, cli, context, tmp_path):
    tool_out = tmp_path / "tool.ply"
    python_out = tmp_path / "python.ply"
    subprocess.run([cli, "deform", str(scenario), "--out", str(tool_out)], check=True,
                   stdout=subprocess.DEVNULL)
    report = dfm.scenario.run_deform(scenario, python_out)
    expected, diagonal, triangles = _positions(context, tool_out)
    got, _, got_triangles = _positions(context, python_out)
    assert np.array_equal(triangles, got_triangles)
    assert np.abs(got - expected).max() <= 1e-12 * diagonal
    assert report["n_vertices"] == len(expected)


def test_module_entry_point(tmp_path):
    out = tmp_path / "leg.off"
    report_path = tmp_path / "report.json"
    run = subprocess.run([sys.executable, "-m", "dualform", "deform",
                          str(SCENARIOS / "cow-front-leg-step.json"), "--out", str(out),
                          "--report", str(report_path), "--strict"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report == json.loads(report_path.read_text())
    assert report["n_roi"] == 138 and report["converged"] and out.exists()


def test_module_entry_point_reports_bad_input(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"mesh": "model:cow", "roi": {"all": True},
                               "handles": [{"vertices": [1], "tolerence": 1}]}))
    run = subprocess.run([sys.executable, "-m", "dualform", "deform", str(bad), "--out",
                          str(tmp_path / "x.ply")], capture_output=True, text=True)
    assert run.returncode == 2
    assert "handles[0].tolerence: unknown field" in run.stderr
    missing = subprocess.run([sys.executable, "-m", "dualform", "deform", str(bad).replace(
        "bad", "nope"), "--out", str(tmp_path / "x.ply")], capture_output=True, text=True)
    assert missing.returncode == 2 and "nope.json" in missing.stderr
