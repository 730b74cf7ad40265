"""The path a technical artist walks, on a real asset, in Blender with a
window under Xvfb (artist_path_checks.py): the add-on installed by the
documented commands; the cow UV-unwrapped by Blender, exported to glTF and
imported again (split at its seams); Water-Fill of the leg, a handle, two
edits into two named shape keys that do not add up, one undo, and the
keys through glTF and back. Every operator's undo restores exactly."""

from __future__ import annotations

import json
import subprocess
import types

import numpy as np
import pytest

from conftest import BLENDER, HERE, SECOND_TRANSLATE, TRANSLATE, blender_environment


@pytest.fixture(scope="module")
def path(cow):
    blender = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", BLENDER, "--factory-startup",
         "--python-exit-code", "1", "--python", str(HERE / "artist_path_checks.py"), "--",
         str(cow.ply), str(cow.work), str(cow.work / "hoof.txt"),
         *map(str, TRANSLATE + SECOND_TRANSLATE)],
        capture_output=True, text=True, env=blender_environment(cow.work, "artist"),
        cwd=cow.addon.parent, timeout=300)
    assert blender.returncode == 0, blender.stdout + blender.stderr
    results = json.loads((cow.work / "artist_path.json").read_text())

    def load(name):
        return np.load(cow.work / f"{name}.npy")

    return types.SimpleNamespace(results=results, load=load, out=blender.stdout, cow=cow)


def test_the_add_on_is_the_one_installed_by_the_documented_commands(path):
    assert "/user-scripts-artist/addons/dualform_blender/" in path.results["addon"]


def test_the_asset_is_split_at_its_uv_seams(path):
    # Blender's Smart UV Project of the cow: 5,029 vertices at 2,903
    # positions (two sheets of the cow touch at one position).
    assert path.results["asset"] == {"vertices": 5029, "positions": 2903}
    # Seams cross the leg and the hoof.
    assert len(path.load("roi")) > 138
    assert len(path.load("hoof_copies")) > len(path.cow.hoof)


def test_water_fill_from_seam_copies_gives_the_papers_leg_with_every_copy(path):
    r = path.results
    assert r["water_fill"] == ["FINISHED"]
    assert r["roi"] == {"count": 138, "loops": 1, "suspect": False}
    rest, roi = path.load("rest"), path.load("roi")
    assert len(np.unique(rest[roi], axis=0)) == 138
    # Every vertex at a ROI position is in the group: no copy left behind.
    at_roi = np.flatnonzero((rest[:, None, :] == np.unique(rest[roi], axis=0)[None]).all(-1).any(1))
    assert np.array_equal(roi, at_roi)
    assert "Water-Fill ROI: 138 vertices (" in path.out


def test_add_handle_takes_every_copy_of_the_selected_vertices(path):
    assert path.results["add_handle"] == ["FINISHED"]
    assert np.array_equal(path.load("handle"), np.sort(path.load("hoof_copies")))
    assert f"Dualform Handle 1: {len(path.cow.hoof)} vertices" in path.out


def test_roi_grow_shrink_and_vertex_groups(path):
    r = path.results
    assert r["grown"] > 138 and r["grown_then_shrunk"] < r["grown"]
    assert r["group_as_roi"] == 138
    assert r["back_to_the_leg"] == {"roi": True, "handles": ["Dualform Handle 1"],
                                    "leg_group": False}


def test_two_edits_make_two_named_keys_that_do_not_add_up(path):
    r = path.results
    assert r["undo"]["deform"]["returned"] == ["FINISHED"] and r["deform_lift"] == ["FINISHED"]
    assert r["keys_after_lift"] == {"Basis": 0.0, "Step": 0.0, "Lift": 1.0}
    rest, step, lift = path.load("rest"), path.load("step_key"), path.load("lift_key")
    diagonal = path.cow.diagonal
    # Shown: the last edit alone, which holds both motions.
    assert np.abs(path.load("lift_shown") - lift).max() <= 1e-6 * diagonal
    hoof = path.load("hoof_copies")
    moved_step = (step[hoof] - rest[hoof]).mean(axis=0)
    moved_lift = (lift[hoof] - rest[hoof]).mean(axis=0)
    assert np.abs(moved_step - TRANSLATE).max() < 1e-3 * diagonal
    assert np.abs(moved_lift - np.add(TRANSLATE, SECOND_TRANSLATE)).max() < 1e-3 * diagonal
    # Nothing outside the ROI moved; copies of one vertex stay together.
    outside = np.setdiff1d(np.arange(len(rest)), path.load("roi"))
    assert np.array_equal(lift[outside], rest[outside])
    for key in (step, lift):
        _, surface = np.unique(rest, axis=0, return_inverse=True)
        for s in np.unique(surface[hoof]):
            copies = key[surface == s]
            assert (copies == copies[0]).all()


def test_one_undo_restores_the_first_edit_exactly(path):
    assert path.results["one_undo"] == {"exact": True,
                                        "keys": {"Basis": 0.0, "Step": 1.0}}


def test_every_operator_undoes_exactly(path):
    undo = path.results["undo"]
    assert set(undo) == {"water_fill", "add_handle", "grow", "shrink", "group_as_roi",
                         "group_as_handle", "deform"}
    for label, record in undo.items():
        assert record == {"returned": ["FINISHED"], "changed": True, "undo_exact": True,
                          "undo_mode": True, "redo_exact": True}, label


def test_the_key_goes_through_gltf_and_back(path):
    r = path.results
    assert list(r["reimported_keys"]) == ["Basis", "Step"]
    assert r["reimported_basis_found"]
    expected, step = path.load("reimported_expected"), path.load("reimported_step")
    assert np.abs(step - expected).max() <= 1e-6 * path.cow.diagonal
    moved = np.linalg.norm(step - path.load("reimported_basis"), axis=1)
    assert moved.max() > 0.09
