"""The worked example of docs/python.md runs and does what the page says."""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess

from conftest import REPO


def test_docs_example(tmp_path, monkeypatch, context, cli):
    page = (REPO / "docs" / "python.md").read_text()
    code = re.search(r"## A worked example.*?```python\n(.*?)```", page, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "docs/python.md", "exec"), {})
    lines = printed.getvalue().splitlines()
    assert lines[0].startswith("138 ROI vertices; WaterFillDiagnosis(loops=1, "
                               "bounded_by_last_loop=True, suspect=False)")
    assert "converged: True" in lines[1]
    assert lines[2].startswith("hoof moved by 0.1040")
    assert os.path.exists("cow-leg.ply")
    subprocess.run([cli, "deform", str(REPO / "tests" / "scenarios" / "cow-front-leg-step.json"),
                    "--out", "tool.ply"], check=True, stdout=subprocess.DEVNULL)
    with open("cow-leg.ply", "rb") as mine, open("tool.ply", "rb") as tool:
        assert mine.read() == tool.read()
