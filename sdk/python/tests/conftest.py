"""Shared fixtures. The package comes from the source tree (PYTHONPATH) and
the library from $DUALFORM_LIBRARY (CTest sets both, and $DUALFORM_CLI for
the tool); real models from tools/fetch-models' cache ($DUALFORM_MODELS)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import dualform as dfm

REPO = Path(__file__).resolve().parents[3]
SCENARIOS = REPO / "tests" / "scenarios"


@pytest.fixture(scope="session")
def cli() -> str:
    path = os.path.abspath(os.environ.get("DUALFORM_CLI")
                           or REPO / "build" / "release" / "tools" / "dualform")
    if not os.access(path, os.X_OK):
        pytest.fail(f"the dualform tool is not built at {path} (set DUALFORM_CLI)")
    return path


@pytest.fixture()
def context():
    with dfm.Context() as ctx:
        yield ctx


@pytest.fixture()
def cow(context):
    with dfm.Mesh.load(context, "model:cow") as mesh:
        yield mesh


def tetrahedron() -> tuple:
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    triangles = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.uint32)
    return positions, triangles
