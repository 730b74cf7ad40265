"""The worked examples of docs/python.md run and do what the page says."""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess

import dualform as dfm
from conftest import REPO


def run_block(heading: str) -> list:
    """Runs the page's Python block under ``heading``; its printed lines."""
    page = (REPO / "docs" / "python.md").read_text()
    code = re.search(re.escape(heading) + r".*?```python\n(.*?)```", page, re.S).group(1)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "docs/python.md", "exec"), {})
    return printed.getvalue().splitlines()


def test_docs_example(tmp_path, monkeypatch, cli):
    monkeypatch.chdir(tmp_path)
    lines = run_block("## A worked example")
    assert lines[0].startswith("138 ROI vertices; WaterFillDiagnosis(loops=1, "
                               "bounded_by_last_loop=True, suspect=False)")
    assert "converged: True" in lines[1]
    assert lines[2].startswith("hoof moved by 0.10399")
    assert os.path.exists("cow-leg.ply")
    subprocess.run([cli, "deform", str(REPO / "tests" / "scenarios" / "cow-front-leg-step.json"),
                    "--out", "tool.ply"], check=True, stdout=subprocess.DEVNULL)
    with open("cow-leg.ply", "rb") as mine, open("tool.ply", "rb") as tool:
        assert mine.read() == tool.read()


def test_docs_gltf_morph_target_example(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run_block("## A glTF asset") == ["cow ['Step']"]
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, "cow.glb") as asset, \
            dfm.Mesh.load(ctx, "cow-step.glb") as saved, dfm.Mesh.load(ctx, "model:cow") as cow:
        # The asset keeps its rest pose (the cow's, in float); the edit is the target.
        assert (saved.positions() == asset.positions()).all()
        assert abs(saved.positions() - cow.positions()).max() < 1e-6


def test_docs_skinned_example(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    lines = run_block("## Skinned meshes")
    assert lines[:2] == ["2 joints: ['joint_0', 'joint_1']",
                         "168 vertices corrected, damped: 0"]
    assert lines[2].startswith("replayed to ") and float(lines[2].split()[-1]) < 1e-12
    assert lines[3] == "the posed displacement copied misses by 0.09"
