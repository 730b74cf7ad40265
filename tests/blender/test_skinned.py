"""The add-on on skinned characters: one headless Blender run
(skinned_checks.py) imports the rigged glTF assets of tests/skin (made by
the fixture rigged_assets), edits each at a frame of its action through the
add-on's operators and bakes a corrective shape key; Blender's own evaluated
mesh must show the same edit as the dualform package makes on a static copy
of the posed mesh, within 1e-5 of the diagonal."""

from __future__ import annotations

import json
import os
import subprocess

import pytest

from conftest import BLENDER, HERE, blender_environment

ASSETS = ("arm", "arm-morph", "humanoid")


@pytest.fixture(scope="module")
def results(cow):
    assets = os.environ.get("DUALFORM_RIGGED_ASSETS")
    if not assets:
        pytest.fail("DUALFORM_RIGGED_ASSETS must name the rigged assets (CTest's fixture "
                    "rigged_assets makes them)")
    blender = subprocess.run(
        [BLENDER, "-b", "--factory-startup", "--python-exit-code", "1",
         "--python", str(HERE / "skinned_checks.py"), "--", assets, str(cow.work)],
        capture_output=True, text=True, env=blender_environment(cow.work, "skinned"),
        cwd=cow.addon.parent, timeout=300)
    assert blender.returncode == 0, blender.stdout[-4000:] + blender.stderr[-4000:]
    return json.loads((cow.work / "skinned.json").read_text())


@pytest.mark.parametrize("name", ASSETS)
def test_the_addon_poses_the_mesh_as_blender_s_armature_does(results, name):
    r = results[name]
    print(f"\n{name} {r['animation']} frame {r['frame']}: the pose moves the mesh by "
          f"{r['pose_moves']:.3f} of the diagonal; the add-on's skin ({r['joints']} joints) "
          f"shows it to {r['skin_error']:.1e}")
    assert r["pose_moves"] > 0.01
    assert r["skin_error"] < 1e-6
    assert not r["unweighted_joint"]


@pytest.mark.parametrize("name", ASSETS)
def test_water_fill_works_on_the_posed_surface(results, name):
    r = results[name]
    assert r["water_fill"] == ["FINISHED"]
    assert r["water_fill_static"]
    assert r["group_as_roi"] == ["FINISHED"] and r["group_as_handle"] == ["FINISHED"]


def test_water_fill_on_the_rest_mesh_would_differ_somewhere(results):
    # Otherwise the check above could not tell the posed surface from the rest.
    assert not all(results[name]["water_fill_rest"] for name in ASSETS)


@pytest.mark.parametrize("name", ASSETS)
def test_bake_corrective_shows_the_edit_in_blender_s_evaluated_mesh(results, name):
    r = results[name]
    print(f"\n{name}: the edit moves up to {r['edit_moves']:.4f} of the diagonal; Blender's "
          f"evaluated mesh with the corrective key shows it to {r['corrective_error']:.2e}; "
          f"the posed displacement copied into the key misses by {r['naive_error']:.4f}")
    assert r["deform"] == ["FINISHED"]
    assert r["edit_moves"] > 0.01
    assert r["corrective_error"] < 1e-5
    assert r["naive_error"] > 1e-4
    # The key holds only the edit: muted, the posed mesh is as it was.
    assert r["muted_error"] < 1e-6
    assert r["restored_error"] == 0.0
    assert r["outside_roi_moved"] == 0.0


@pytest.mark.parametrize("name", ASSETS)
def test_keys_already_there_keep_their_values(results, name):
    r = results[name]
    before, after = r["keys_before"], r["keys_after"]
    if name == "arm-morph":
        assert before == {"Basis": 0.0, "Flex": 0.25}
    for key, value in before.items():
        assert after[key] == value
    assert set(after) == set(before) | {"Basis", "Corrective"}


@pytest.mark.parametrize("name", ASSETS)
def test_the_corrective_is_driven_by_the_nearest_bone_s_angle(results, name):
    r = results[name]
    d = r["driver"]
    driven = r["driven"]
    between = [f for f, value, _ in driven if 0.01 < value < 0.99]
    print(f"\n{name}: driven by the bone {d['bone']}, 1 at frame {r['frame']}; over the "
          f"action's {len(driven)} frames, {len(between)} lie strictly between 0 and 1")
    assert d["simple"] and d["valid"]
    assert (d["space"], d["channel"]) == ("LOCAL_SPACE", "ROT_W")
    assert abs(r["driven_value"] - 1.0) < 1e-6
    # At every frame, the bone's angle over its angle at the bake's frame.
    for frame, value, expected in driven:
        assert abs(value - expected) < 1e-5, frame
    assert min(value for _, value, _ in driven) < 0.5


def test_some_corrective_fades_in_between_frames(results):
    assert any(0.01 < value < 0.99 for name in ASSETS for _, value, _ in results[name]["driven"])


def test_the_modal_drag_previews_and_bakes_on_the_posed_mesh(results):
    r = results["arm_extras"]
    print(f"\narm, dragged: the preview shows the session's frame to {r['preview_error']:.1e}, "
          f"the baked key to {r['enter_error']:.1e}")
    assert r["escape_moved"] > 1e-3 and r["escape"] == ["CANCELLED"] and r["escape_restored"]
    assert r["preview_error"] < 1e-5
    assert r["enter"] == ["FINISHED"] and r["enter_moved"] > 1e-3
    assert r["enter_error"] < 1e-5
    assert r["enter_keys"] == ["Basis", "Corrective"]


def test_an_edit_kept_in_the_mesh_is_its_rest_shape(results):
    r = results["arm_extras"]
    assert r["deform_mesh"] == ["FINISHED"]
    assert r["mesh_error"] < 1e-5


def test_preserve_volume_is_refused_with_the_reason(results):
    r = results["arm_extras"]
    for what in ("deform", "grow"):
        assert "Preserve Volume (dual quaternion skinning) is on" in r[f"preserve_volume_{what}"]
