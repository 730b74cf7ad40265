"""What the Blender tests share: the add-on's zip made by docs/blender.md's
command, the cow as a float PLY with its hoof, and each Blender run's own
environment.

The cow goes to Blender as a PLY with float coordinates: Blender keeps
vertices in float, so both sides then start from the same rest pose
exactly, and the tool's double result rounded to float is Blender's."""

from __future__ import annotations

import os
import re
import subprocess
import types
from pathlib import Path

import pytest

import dualform as dfm

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
# Exact in float, as Blender's operator properties hold them.
TRANSLATE = (0.09375, 0.03125, 0.0)
SECOND_TRANSLATE = (0.0, 0.0625, 0.03125)


def make_zip_as_documented(work: Path) -> Path:
    """Runs docs/blender.md's packaging command as written, in a folder
    laid out as a checkout (its samples/ and the built library linked in);
    the lines before it build the library, which CTest has done."""
    page = (REPO / "docs" / "blender.md").read_text()
    lines = re.search(r"## Installing.*?```sh\n(.*?)```", page, re.S).group(1).splitlines()
    assert lines[:2] == ["cmake --preset release",
                         "cmake --build --preset release --target dualform_sdk"]
    checkout = work / "checkout"
    (checkout / "build" / "release" / "sdk").mkdir(parents=True)
    (checkout / "samples").symlink_to(REPO / "samples")
    (checkout / "build" / "release" / "sdk" / "libdualform.so").symlink_to(
        os.environ["DUALFORM_LIBRARY"])
    subprocess.run(["bash", "-ec", "\n".join(lines[2:])], cwd=checkout, check=True,
                   stdout=subprocess.DEVNULL)
    return checkout / "dualform_blender.zip"


def blender_environment(work: Path, name: str) -> dict:
    """Blender's own Python runs the bundled package and library: nothing
    from this process's environment points it at them. Its user folders
    and temporary files (the quit.blend a windowed Blender leaves) are the
    test's."""
    env = {k: v for k, v in os.environ.items() if k not in ("DUALFORM_LIBRARY", "PYTHONPATH")}
    temp = work / f"temp-{name}"
    temp.mkdir(exist_ok=True)
    env.update(BLENDER_USER_SCRIPTS=str(work / f"user-scripts-{name}"),
               BLENDER_USER_CONFIG=str(work / f"user-config-{name}"), TMPDIR=str(temp))
    return env


BLENDER = os.environ.get("DUALFORM_BLENDER", "blender")


@pytest.fixture(scope="session")
def cow(tmp_path_factory):
    """The cow as a float PLY, its hoof (a 0.03 ball at 771), rest pose and
    diagonal, and the zip, in one folder."""
    work = tmp_path_factory.mktemp("blender")
    ply = work / "cow.ply"
    with dfm.Context() as ctx:
        with dfm.Mesh.load(ctx, "model:cow") as mesh:
            mesh.save(ply, ply_float=True)
        with dfm.Mesh.load(ctx, ply) as mesh, mesh.roi_ball(771, 0.03) as ball:
            hoof = ball.vertices()
            rest = mesh.positions()
            diagonal = mesh.info.diagonal
    (work / "hoof.txt").write_text(" ".join(map(str, hoof)))
    return types.SimpleNamespace(work=work, ply=ply, hoof=hoof, rest=rest, diagonal=diagonal,
                                 addon=make_zip_as_documented(work))
