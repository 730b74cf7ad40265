"""``python -m dualform deform`` and ``dualform deform`` answer alike: every
malformed scenario (tests/data/malformed-scenarios) and every malformed
mesh file (tests/data/malformed, each the mesh of a scenario) gives the
same stderr, stdout and exit code from both; a good edit gives a report
with the same keys in the same order and the same mesh files, glTF
morph targets and ROI lists included."""

from __future__ import annotations

import contextlib
import io
import json
import subprocess

import pytest

import dualform as dfm
from dualform.__main__ import main
from conftest import REPO, SCENARIOS

DATA = REPO / "tests" / "data"
MALFORMED_SCENARIOS = sorted((DATA / "malformed-scenarios").glob("*.json"))
MALFORMED_MESHES = sorted(p for p in (DATA / "malformed").iterdir() if p.name != "EXPECTED.tsv")
TIMINGS = {"setup_ms", "solve_ms", "ms_per_iteration", "load_ms"}


def both(cli, args, cwd, monkeypatch):
    """(tool, package): each (exit code, stdout, stderr) of ``deform ARGS``."""
    tool = subprocess.run([cli, "deform", *args], capture_output=True, text=True, cwd=cwd)
    monkeypatch.chdir(cwd)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["deform", *args])
    return (tool.returncode, tool.stdout, tool.stderr), (code, out.getvalue(), err.getvalue())


def reports_of_both(cli, args: dict, cwd, monkeypatch) -> list:
    """Runs ``deform`` with the tool's and the package's own arguments
    (``args["tool"]``, ``args["package"]``) in ``cwd``; both succeed, and
    their reports have the same keys in the same order and the same values
    but for the timings. Returns the two reports."""
    tool = subprocess.run([cli, "deform", *args["tool"]], capture_output=True, text=True,
                          cwd=cwd)
    _, package = both(cli, args["package"], cwd, monkeypatch)
    assert tool.returncode == 0 and package[0] == 0, tool.stderr + package[2]
    reports = [json.loads(tool.stdout), json.loads(package[1])]
    assert list(reports[0]) == list(reports[1])
    for key in reports[0].keys() - TIMINGS:
        assert reports[0][key] == reports[1][key], key
    return reports


@pytest.mark.parametrize("scenario", MALFORMED_SCENARIOS, ids=lambda p: p.stem)
def test_malformed_scenarios_answer_alike(scenario, cli, tmp_path, monkeypatch):
    tool, package = both(cli, [scenario.name, "--out", str(tmp_path / "out.ply")],
                         scenario.parent, monkeypatch)
    assert tool[0] in (1, 2) and tool[1] == "" and tool[2].startswith("error: ")
    assert package == tool


def test_the_corpus_covers_every_stage(cli, tmp_path, monkeypatch):
    # Form (located in the file), the mesh, its pose, the ROI and handles on
    # the mesh, the session, and the solve (exit 1) each refuse some case.
    seen = set()
    for scenario in MALFORMED_SCENARIOS:
        code, _, err = both(cli, [scenario.name, "--out", str(tmp_path / "out.ply")],
                            scenario.parent, monkeypatch)[1]
        name = scenario.name
        if err.startswith(f"error: {name}:") and err[len(f"error: {name}:")].isdigit():
            seen.add("form")
        elif err.startswith("error: mesh: dfm_mesh_load: "):
            seen.add("mesh")
        elif err.startswith(("error: pose: dfm_", "error: pose.animation: dfm_")):
            seen.add("pose")
        elif err.startswith(f"error: {name}: dfm_session_create: "):
            seen.add("session")
        elif err.startswith(f"error: {name}: "):
            seen.add("edit")
        elif code == 1:
            seen.add("solve")
    assert seen == {"form", "mesh", "pose", "edit", "session", "solve"}


@pytest.mark.parametrize("mesh", MALFORMED_MESHES, ids=lambda p: p.name)
def test_malformed_meshes_answer_alike(mesh, cli, tmp_path, monkeypatch):
    scenario = tmp_path / "s.json"
    scenario.write_text(json.dumps({"mesh": str(mesh), "roi": {"all": True},
                                    "handles": [{"vertices": [0]}]}))
    tool, package = both(cli, [scenario.name, "--out", "out.ply"], tmp_path, monkeypatch)
    assert tool[0] == 2 and tool[2].startswith(f"error: mesh: dfm_mesh_load: {mesh}")
    assert package == tool


def test_an_output_that_cannot_be_written_exits_1_from_both(cli, tmp_path, monkeypatch):
    scenario = str(SCENARIOS / "scale-cow-leg.json")
    nowhere = tmp_path / "no-such-folder"
    for args in ([scenario, "--out", str(nowhere / "x.off")],
                 [scenario, "--out", str(tmp_path / "x.off"), "--roi-out", str(nowhere / "r.txt")]):
        tool, package = both(cli, args, tmp_path, monkeypatch)
        assert tool[0] == 1 and tool[2].startswith("error: ") and "no-such-folder" in tool[2]
        assert package == tool
    # An output format the library does not write stays bad input.
    tool, package = both(cli, [scenario, "--out", str(tmp_path / "x.stl")], tmp_path, monkeypatch)
    assert tool[0] == 2 and package == tool


def test_a_glTF_morph_target_edit_gives_the_same_files_and_report(cli, tmp_path, monkeypatch):
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, "model:cow") as cow:
        cow.save(tmp_path / "cow.glb")
    edit = json.loads((SCENARIOS / "cow-front-leg-step.json").read_text())
    edit["mesh"] = "cow.glb"
    (tmp_path / "edit.json").write_text(json.dumps(edit))
    outputs = {}
    for who in ("tool", "package"):
        outputs[who] = [tmp_path / f"{who}.glb", tmp_path / f"{who}-roi.txt",
                        tmp_path / f"{who}-report.json"]
    args = {who: ["edit.json", "--out", str(o[0]), "--roi-out", str(o[1]), "--report", str(o[2]),
                  "--morph-target", "Step", "--strict"] for who, o in outputs.items()}
    reports = reports_of_both(cli, args, tmp_path, monkeypatch)
    assert len(reports[0]) == 19 and list(reports[0]["quality"]) == list(reports[1]["quality"])
    assert json.loads(outputs["package"][2].read_text()) == reports[1]
    for mine, theirs in zip(outputs["package"][:2], outputs["tool"][:2]):
        assert mine.read_bytes() == theirs.read_bytes()
    assert len(outputs["tool"][1].read_text().split()) == 138
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, outputs["package"][0]) as saved:
        # The asset keeps its rest pose; the edit is the morph target.
        with dfm.Mesh.load(ctx, tmp_path / "cow.glb") as rest:
            assert (saved.positions() == rest.positions()).all()
    assert b'"targetNames":["Step"]' in outputs["package"][0].read_bytes()
