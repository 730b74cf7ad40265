"""The package on Blender-made rigged glTF assets (tests/skin/: a bent arm,
the arm with a shape key under its armature, a 19-bone humanoid with
LINEAR, STEP and CUBICSPLINE actions), checked against the independent
numpy glTF skinning tests/skin/gltf_skinning.py: posing from an animation
and from joint matrices with morph weights, a posed edit saved as a
corrective against the same edit of a static copy of the posed mesh, the
errors, and ``python -m dualform deform`` with a pose against the tool.

Marked ``rigged``: CTest's python_rigged runs them after the fixture
rigged_assets has made the assets ($DUALFORM_RIGGED_ASSETS)."""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

import dualform as dfm
from conftest import REPO
from test_parity import both, reports_of_both

sys.path.insert(0, str(REPO / "tests" / "skin"))
import gltf_skinning as gs  # noqa: E402

pytestmark = pytest.mark.rigged

SKINNED = ("arm", "arm-morph", "humanoid")
# The library normalises each vertex's float32 weights to sum 1 in double
# (as glTF says weights should); the reference uses them as stored, whose
# sums are 1 to float32 rounding: the poses agree to that, about 1e-7 of the
# diagonal, no closer.
FLOAT_WEIGHTS = 1e-6


def assets() -> Path:
    value = os.environ.get("DUALFORM_RIGGED_ASSETS")
    if not value or not (Path(value) / ".complete").is_file():
        pytest.fail("DUALFORM_RIGGED_ASSETS must name the finished rigged assets "
                    "(CTest's fixture rigged_assets makes them)")
    return Path(value)


class Asset:
    """A rigged glb: the reference's view of it, its skinned mesh's node and
    mesh, and the animations Blender evaluated frames of."""

    def __init__(self, name: str) -> None:
        self.path = assets() / f"{name}.glb"
        self.frames = json.loads((assets() / f"{name}.frames.json").read_text())
        self.gltf = gs.load(str(self.path))
        self.node = gs.mesh_node(self.gltf, self.frames["mesh"])
        self.mesh_index = self.gltf.gltf["nodes"][self.node]["mesh"]
        self.animations = gs.animation_names(self.gltf)

    def posed(self, animation, time, **kwargs) -> np.ndarray:
        return gs.posed_positions(self.gltf, self.node, animation, time, **kwargs)

    def joint_world(self, animation, time) -> np.ndarray:
        world = gs.world_matrices(self.gltf, gs.animated_values(self.gltf, animation, time))
        skin = self.gltf.gltf["skins"][self.gltf.gltf["nodes"][self.node]["skin"]]
        return np.stack([world[j] for j in skin["joints"]])

    def triangles(self) -> np.ndarray:
        out, base = [], 0
        for p in self.gltf.gltf["meshes"][self.mesh_index]["primitives"]:
            count = self.gltf.gltf["accessors"][p["attributes"]["POSITION"]]["count"]
            out.append(gs.read_accessor(self.gltf, p["indices"], as_float=False).reshape(-1, 3)
                       + base)
            base += count
        return np.concatenate(out)

    def middle_frame(self, animation) -> float:
        frames = [f for f in self.frames["frames"] if f["animation"] == animation]
        return frames[len(frames) // 2]["time_seconds"]


_loaded: dict = {}


def asset(name: str) -> Asset:
    if name not in _loaded:
        _loaded[name] = Asset(name)
    return _loaded[name]


def diagonal(p: np.ndarray) -> float:
    return float(np.linalg.norm(p.max(axis=0) - p.min(axis=0)))


# (asset, animation): every animation Blender evaluated frames of (the
# humanoid's cover LINEAR, STEP and CUBICSPLINE keys).
CASES = [("arm", "Wave"), ("arm-morph", "Wave"), ("humanoid", "Walk"), ("humanoid", "Hold"),
         ("humanoid", "Sway")]


def test_the_cases_are_the_animations_blender_evaluated():
    evaluated = []
    for name in SKINNED:
        frames = asset(name).frames["frames"]
        evaluated += [(name, a) for a in dict.fromkeys(f["animation"] for f in frames)]
    assert CASES == evaluated


@pytest.mark.parametrize("name", SKINNED)
def test_the_skin_is_described(context, name):
    a = asset(name)
    with dfm.Mesh.load(context, a.path) as mesh:
        info = mesh.skin_info()
        skin = a.gltf.gltf["skins"][0]
        assert info.joint_count == len(skin["joints"])
        assert [j.name for j in mesh.joints()] == [a.gltf.gltf["nodes"][j]["name"]
                                                   for j in skin["joints"]]
        assert [x.name for x in mesh.animations()] == a.animations
        for x in mesh.animations():
            assert (x.start, x.end) == pytest.approx(gs.animation_range(a.gltf, x.name),
                                                     abs=1e-12)
        targets = a.gltf.gltf["meshes"][a.mesh_index].get("extras", {}).get("targetNames", [])
        assert [t.name for t in mesh.morph_targets()] == targets


@pytest.mark.parametrize("name,animation", CASES)
def test_an_animation_poses_the_mesh_as_the_reference_does(context, name, animation):
    a = asset(name)
    start, end = gs.animation_range(a.gltf, animation)
    with dfm.Mesh.load(context, a.path) as mesh:
        index = mesh.find_animation(animation)
        # Before the first key, between keys, on a key, after the last key.
        for time in (start - 0.5, start + 0.37 * (end - start), a.middle_frame(animation),
                     end + 1.0):
            mesh.set_pose(animation, time)
            expected = a.posed(animation, time)
            error = np.abs(mesh.positions() - expected).max() / diagonal(expected)
            assert error <= FLOAT_WEIGHTS, (time, error)
            info = mesh.skin_info()
            assert info.posed and info.pose_animation == index
            assert info.pose_time == pytest.approx(min(max(time, start), end), abs=1e-12)
            world = a.joint_world(animation, min(max(time, start), end))
            # To the float32 rounding of the file's quaternions (unit to
            # about 1e-7, one side normalising them), down the hierarchy.
            assert np.abs(mesh.joint_matrices() - world).max() <= 1e-6
        # By index, the same pose.
        shown = mesh.positions()
        mesh.set_pose(index, end + 1.0)
        assert np.array_equal(mesh.positions(), shown)


def test_joint_matrices_and_morph_weights_pose_as_the_reference_does(context):
    a = asset("arm-morph")
    animation = a.animations[0]
    time = a.middle_frame(animation)
    world = a.joint_world(animation, time)
    with dfm.Mesh.load(context, a.path) as mesh:
        assert [(t.name, t.default_weight) for t in mesh.morph_targets()] == [("Flex", 0.25)]
        for weights in (None, [1.0], [0.0]):
            mesh.set_pose_joints(world, morph_weights=weights)
            expected = a.posed(animation, time,
                               morph_weights=[0.25] if weights is None else weights)
            error = np.abs(mesh.positions() - expected).max() / diagonal(expected)
            assert error <= FLOAT_WEIGHTS, (weights, error)
            assert mesh.skin_info().pose_animation == -1
        # The bind shape stays the file's: morph targets are not baked in.
        mesh.clear_pose()
        bind = gs.mesh_attribute(a.gltf, a.mesh_index, "POSITION")
        assert np.abs(mesh.bind_positions() - bind).max() == 0.0


def test_bad_poses_raise_the_library_s_errors(context):
    a = asset("humanoid")
    with dfm.Mesh.load(context, a.path) as mesh:
        with pytest.raises(dfm.NumericalError, match="not finite"):
            mesh.set_pose("Walk", math.nan)
        with pytest.raises(dfm.NotFoundError,
                           match=r"no animation named 'Run' \(the mesh has 3: 'Hold', "
                                 r"'Sway', 'Walk'\)"):
            mesh.set_pose("Run", 0.0)
        with pytest.raises(dfm.OutOfRangeError, match="animation 3 does not exist"):
            mesh.set_pose(3, 0.0)
        with pytest.raises(dfm.InvalidArgumentError, match="the skin has 19 joints"):
            mesh.set_pose_joints(np.stack([np.eye(4)] * 18))
        assert not mesh.skin_info().posed


def edit_of(mesh: dfm.Mesh, handle: int, *, bake: bool) -> np.ndarray:
    """The CLI test's edit: a 0.2 ball around the handle vertex, its 0.03
    ball lifted by (0, 0.04, 0.03) of the diagonal; the solved positions
    (baked into the mesh when asked)."""
    lift = np.array([0.0, 0.04, 0.03]) * mesh.info.diagonal
    with mesh.roi_ball(handle, 0.2) as roi, mesh.roi_ball(handle, 0.03) as grip, \
            dfm.Session(mesh, roi, [grip.vertices()]) as session:
        session.set_translation(0, lift)
        session.solve()
        solved, _ = session.read_positions()
        if bake:
            session.bake()
    return solved


@pytest.mark.parametrize("name,animation", CASES)
def test_a_posed_edit_saved_as_a_corrective_matches_the_static_edit(context, tmp_path, name,
                                                                     animation):
    a = asset(name)
    time = a.middle_frame(animation)
    posed = a.posed(animation, time)
    d = diagonal(posed)
    handle = int(np.argmax(np.linalg.norm(posed - posed.mean(axis=0), axis=1)))
    with dfm.Mesh.from_arrays(context, posed, a.triangles(), weld=0) as static:
        static_edit = edit_of(static, handle, bake=False)
    with dfm.Mesh.load(context, a.path) as mesh:
        mesh.set_pose(animation, time)
        edited = edit_of(mesh, handle, bake=True)
        info = mesh.skin_info()
        mesh.save(tmp_path / "corrective.glb", morph_target="Corrective")
    assert info.corrective_vertex_count > 0 and info.corrective_damped_count == 0
    saved = gs.load(str(tmp_path / "corrective.glb"))
    weights = list(gs.morph_weights_of(saved, a.node, gs.animated_values(saved, animation, time)))
    assert weights[-1] == 0.0
    weights[-1] = 1.0
    replayed = gs.posed_positions(saved, a.node, animation, time, morph_weights=weights)
    error = np.linalg.norm(replayed - static_edit, axis=1).max() / d
    moved = np.linalg.norm(static_edit - posed, axis=1).max() / d
    naive = a.posed(animation, time, extra_target=static_edit - posed)
    naive_error = np.linalg.norm(naive - static_edit, axis=1).max() / d
    print(f"\n{name} {animation} t={time:.4f}: the edit moves up to {moved:.4f} of the "
          f"diagonal; saved from Python, the corrective replays it to {error:.2e}, the "
          f"bind-space copy misses by {naive_error:.4f}")
    assert np.abs(edited - static_edit).max() <= 1e-6 * d
    assert moved > 0.01
    assert error < 1e-5
    assert naive_error > 1e-4


def test_a_posed_scenario_gives_the_tool_s_files_and_report(cli, tmp_path, monkeypatch):
    a = asset("humanoid")
    posed = a.posed("Walk", 0.5)
    handle = int(np.argmax(np.linalg.norm(posed - posed.mean(axis=0), axis=1)))
    (tmp_path / "posed.json").write_text(json.dumps({
        "mesh": str(a.path), "pose": {"animation": "Walk", "time": 0.5},
        "roi": {"ball": {"center": handle, "radius": 0.2}},
        "handles": [{"ball": {"center": handle, "radius": 0.03},
                     "translate": [0.0, 0.04, 0.03]}]}))
    outputs = {who: [tmp_path / f"{who}.glb", tmp_path / f"{who}-roi.txt"]
               for who in ("tool", "package")}
    args = {who: ["posed.json", "--out", str(o[0]), "--roi-out", str(o[1]),
                  "--morph-target", "Corrective"] for who, o in outputs.items()}
    reports = reports_of_both(cli, args, tmp_path, monkeypatch)
    assert list(reports[0])[-2:] == ["pose", "corrective"]
    assert reports[1]["pose"] == {"animation": "Walk", "time": 0.5}
    assert reports[1]["corrective"]["vertices"] > 0
    for mine, theirs in zip(outputs["package"], outputs["tool"]):
        assert mine.read_bytes() == theirs.read_bytes()


@pytest.mark.parametrize("pose,expected", [
    ({"animation": "Run", "time": 0.0},
     "error: pose.animation: dfm_mesh_find_animation: no animation named 'Run'"),
    ({"animation": 3, "time": 0.0},
     "error: pose: dfm_mesh_set_pose_animation: animation 3 does not exist"),
])
def test_a_pose_the_asset_does_not_have_answers_as_the_tool(cli, tmp_path, monkeypatch, pose,
                                                           expected):
    (tmp_path / "bad.json").write_text(json.dumps({
        "mesh": str(asset("humanoid").path), "pose": pose, "roi": {"all": True},
        "handles": [{"vertices": [0]}]}))
    tool, package = both(cli, ["bad.json", "--out", "out.glb"], tmp_path, monkeypatch)
    assert tool[0] == 2 and tool[2].startswith(expected)
    assert package == tool
