"""The Blender add-on: one headless Blender run (blender_checks.py) does
what a user would, and the tests below compare what it produced with the
dualform tool on the same mesh and edits; a second run with a window under
Xvfb (modal_ui_checks.py) drives the modal drag with simulated events.
The zip is made, and installed in Blender, by docs/blender.md's commands."""

from __future__ import annotations

import json
import os
import subprocess
import types

import numpy as np
import pytest

import dualform as dfm
from conftest import BLENDER, HERE, SECOND_TRANSLATE, TRANSLATE, blender_environment


@pytest.fixture(scope="module")
def run(cow):
    work = cow.work
    cli = os.environ["DUALFORM_CLI"]
    scenario = work / "edit.json"
    scenario.write_text(json.dumps({
        "mesh": str(cow.ply),
        "roi": {"water_fill": {"first": 771, "last": 681}},
        "handles": [{"vertices": cow.hoof.tolist(),
                     "targets": (cow.rest[cow.hoof] + np.array(TRANSLATE)).tolist()}],
    }))
    subprocess.run([cli, "roi", str(scenario), "--out", str(work / "roi.txt")], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run([cli, "deform", str(scenario), "--out", str(work / "cli.ply")], check=True,
                   stdout=subprocess.DEVNULL)
    blender = subprocess.run(
        [BLENDER, "-b", "--factory-startup", "--python-exit-code", "1",
         "--python", str(HERE / "blender_checks.py"), "--", str(cow.ply), str(work),
         str(work / "hoof.txt"), *map(str, TRANSLATE + SECOND_TRANSLATE)],
        capture_output=True, text=True, env=blender_environment(work, "checks"),
        cwd=cow.addon.parent, timeout=300)
    assert blender.returncode == 0, blender.stdout + blender.stderr
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, work / "cli.ply") as result:
        expected = result.positions()
    return types.SimpleNamespace(
        work=work, addon=cow.addon, out=blender.stdout,
        results=json.loads((work / "results.json").read_text()),
        rest=cow.rest, hoof=cow.hoof, diagonal=cow.diagonal, expected=expected,
        cli_roi=np.loadtxt(work / "roi.txt", dtype=np.uint32))


def load(run, name):
    return np.load(run.work / f"{name}.npy")


def test_installs_and_enables_with_the_bundled_package(run):
    r = run.results
    assert r["enabled"]
    assert "/user-scripts-checks/addons/dualform_blender/vendor/dualform/" in r["package"]
    assert r["library"].endswith("vendor/dualform/lib/libdualform.so.0.2")


def test_ply_import_keeps_the_vertex_order_and_count(run):
    assert np.array_equal(load(run, "rest"), run.rest.astype(np.float32))


def test_two_vertex_water_fill_matches_dualform_roi(run):
    r = run.results
    assert r["water_fill"] == ["FINISHED"]
    assert r["diagnosis"] == {"count": 138, "loops": 1, "suspect": 0}
    assert len(run.cli_roi) == 138
    assert np.array_equal(load(run, "roi"), run.cli_roi)
    assert "Water-Fill ROI: 138 vertices, 1 cut loop(s)" in run.out
    assert "one after the other" in r["three_selected"]


def test_suspect_fill_is_named_as_such(run):
    r = run.results
    assert r["suspect_diagnosis"] == {"count": 684, "loops": 2, "suspect": 1}
    assert "Warning: Water-Fill ROI: 684 vertices, 2 cut loop(s); SUSPECT" in run.out


def test_add_handle_makes_the_group(run):
    assert run.results["add_handle"] == ["FINISHED"]
    assert np.array_equal(load(run, "handle"), run.hoof)


def test_scripted_deform_matches_the_cli(run):
    deformed = load(run, "deformed")
    assert run.results["deform"] == ["FINISHED"]
    assert np.linalg.norm(deformed[771] - run.rest[771]) > 0.09
    assert np.abs(deformed - run.expected).max() <= 1e-6 * run.diagonal


def test_shape_key_at_one_gives_the_same_positions(run):
    assert run.results["shape_keys"] == ["Basis", "Dualform Edit"]
    assert np.array_equal(load(run, "key_basis"), run.rest.astype(np.float32))
    assert np.abs(load(run, "key_evaluated") - run.expected).max() <= 1e-6 * run.diagonal


def test_a_second_edit_starts_from_the_shape_shown_and_never_adds_up(run):
    r = run.results
    assert r["deform_lift"] == ["FINISHED"]
    assert r["lift_keys"] == {"Basis": 0.0, "Dualform Edit": 0.0, "Lift": 1.0}
    lift = load(run, "lift_key")
    # What Blender shows is the new key alone, not the two edits' sum.
    assert np.abs(load(run, "lift_evaluated") - lift).max() <= 1e-6 * run.diagonal
    # The first key still holds the first edit.
    assert np.abs(load(run, "first_key") - run.expected).max() <= 1e-6 * run.diagonal
    # The tool, editing the shape shown before (the first result) with the
    # same ROI and hoof, gives the new key.
    mix = load(run, "mix_before_lift").astype(np.float64)
    work = run.work
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, work / "cow.ply") as cow, \
            dfm.Mesh.from_arrays(ctx, mix, cow.triangles()) as shown:
        shown.save(work / "shown.ply", ply_float=True)
    (work / "lift.json").write_text(json.dumps({
        "mesh": str(work / "shown.ply"),
        "roi": {"vertices": run.cli_roi.tolist()},
        "handles": [{"vertices": run.hoof.tolist(),
                     "targets": (mix[run.hoof] + np.array(SECOND_TRANSLATE)).tolist()}],
    }))
    subprocess.run([os.environ["DUALFORM_CLI"], "deform", str(work / "lift.json"), "--out",
                    str(work / "lift.ply")], check=True, stdout=subprocess.DEVNULL)
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, work / "lift.ply") as tool:
        assert np.abs(lift - tool.positions()).max() <= 1e-6 * run.diagonal
    hoof_moved = np.linalg.norm(lift[771] - run.rest[771])
    assert hoof_moved > np.linalg.norm(np.add(TRANSLATE, SECOND_TRANSLATE)) * 0.95


def test_keeping_in_a_mesh_with_shape_keys_is_refused_with_the_reason(run):
    assert "this mesh has shape keys" in run.results["mesh_with_keys"]


def test_modal_drag_enter_keeps_the_edit(run):
    # The drag's last frame starts from the frames before it, so it agrees
    # with a fresh solve to the solver's tolerance, not bit for bit.
    assert run.results["modal_enter"] == ["FINISHED"]
    assert np.abs(load(run, "modal") - run.expected).max() <= 1e-3 * run.diagonal


def test_modal_drag_escape_restores_bit_for_bit(run):
    r = run.results
    assert r["escape_moved_first"]
    assert r["modal_escape"] == ["CANCELLED"]
    assert r["escape_restored_bitwise"]


@pytest.fixture(scope="module")
def modal_ui(run):
    """The modal drag in a real 3D view under Xvfb, driven by simulated
    mouse moves, Enter and Escape (modal_ui_checks.py)."""
    blender = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", BLENDER, "--factory-startup",
         "--enable-event-simulate", "--window-geometry", "0", "0", "1280", "800",
         "--python-exit-code", "1", "--python", str(HERE / "modal_ui_checks.py"), "--",
         str(run.work / "cow.ply"), str(run.work), str(run.work / "hoof.txt")],
        capture_output=True, text=True, env=blender_environment(run.work, "ui"),
        cwd=run.addon.parent, timeout=300)
    assert blender.returncode == 0, blender.stdout + blender.stderr
    return json.loads((run.work / "modal_ui.json").read_text())


def test_modal_drag_in_a_3d_view_follows_the_mouse_and_enter_keeps_it(modal_ui, run):
    assert modal_ui["invoke"] == [["RUNNING_MODAL"], ["RUNNING_MODAL"]]
    assert modal_ui["moving_while_dragging"]
    assert modal_ui["enter_hoof_moved"] > 0.01 * run.diagonal
    assert modal_ui["enter_outside_moved"] == 0.0
    assert modal_ui["enter_undo_restored_bitwise"]


def test_modal_drag_in_a_3d_view_escape_restores_bit_for_bit(modal_ui):
    assert modal_ui["escape_moving_while_dragging"]
    assert modal_ui["escape_restored_bitwise"]
