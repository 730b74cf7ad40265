"""The install of docs/python.md, its commands run as written in a fresh
virtual environment on Debian's Python (no package index), in a copy of
the checkout's layout; and the message an install gives without the
library."""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import dualform as dfm
from conftest import REPO

PACKAGE = REPO / "sdk" / "python"


def documented_install() -> str:
    page = (REPO / "docs" / "python.md").read_text()
    section = page[page.index("## Installing"):page.index("### How the library is found")]
    blocks = re.findall(r"```sh\n(.*?)```", section, re.S)
    # The first block builds the library (CTest built it); the second installs.
    assert blocks[0].splitlines() == ["cmake --preset release",
                                      "cmake --build --preset release --target dualform_sdk"]
    return blocks[1]


def test_the_documented_install_works_as_written(tmp_path):
    checkout = tmp_path / "dualform"
    shutil.copytree(PACKAGE, checkout / "sdk" / "python", ignore=shutil.ignore_patterns(
        "__pycache__", "tests", "build", "*.egg-info"))
    library = checkout / "build" / "release" / "sdk" / "libdualform.so"
    library.parent.mkdir(parents=True)
    library.symlink_to(dfm.load_library()._name)
    env = {k: v for k, v in os.environ.items()
           if k not in ("DUALFORM_LIBRARY", "PYTHONPATH", "VIRTUAL_ENV", "PIP_INDEX_URL")}
    env["PATH"] = "/usr/bin:/bin"  # Debian's python3, as on a fresh machine
    env["HOME"] = str(tmp_path)  # pip's cache stays in here
    script = "set -e\n" + documented_install()
    run = subprocess.run(["bash", "-c", script], cwd=checkout, env=env, capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.splitlines()[-1] == str(dfm.library_version())
    venv_python = checkout / ".venv" / "bin" / "python"
    where = subprocess.run([str(venv_python), "-c", "import dualform; print(dualform.__file__)"],
                           cwd=tmp_path, env=env, capture_output=True, text=True)
    assert where.stdout.startswith(str(checkout / ".venv" / "lib")), where.stderr

    # Without DUALFORM_LIBRARY, the installed package says how to point at one.
    missing = subprocess.run([str(venv_python), "-c", "import dualform; dualform.Context()"],
                             cwd=tmp_path, env=env, capture_output=True, text=True)
    assert missing.returncode == 1
    last = missing.stderr.strip().splitlines()
    message = "\n".join(last[last.index(next(l for l in last if l.startswith("OSError"))):])
    assert "set DUALFORM_LIBRARY to its path" in message
    assert "dualform.load_library(PATH)" in message
    assert "libdualform.so.0.2" in message
