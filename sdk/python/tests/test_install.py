"""``pip install --no-build-isolation`` builds and installs the package
with Debian's setuptools (no package index needed)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import dualform as dfm

PACKAGE = Path(__file__).resolve().parents[1]


def test_pip_install_no_build_isolation(tmp_path):
    # From a copy, so that the build's by-products stay out of the tree.
    source = tmp_path / "source"
    shutil.copytree(PACKAGE, source, ignore=shutil.ignore_patterns(
        "__pycache__", "tests", "build", "*.egg-info"))
    target = tmp_path / "site"
    run = subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation",
                          "--no-deps", "--no-index", "--target", str(target), str(source)],
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert (target / "dualform" / "__init__.py").exists()
    # Outside the source tree the library is named, as an installed host would.
    env = dict(os.environ, PYTHONPATH=str(target), DUALFORM_LIBRARY=dfm.load_library()._name)
    check = subprocess.run([sys.executable, "-c",
                            "import dualform, sys; print(dualform.__file__); "
                            "print(dualform.library_version())"],
                           capture_output=True, text=True, env=env, cwd=tmp_path)
    assert check.returncode == 0, check.stderr
    assert check.stdout.splitlines()[0].startswith(str(target))
