"""Skinned meshes from numpy arrays: posing from joint matrices against an
independent linear blend skinning written here, the joints' and weights'
layouts, a posed edit kept as the exact bind-space corrective, and the
errors bad input raises. The rigged glTF assets are tests/python/skinned/."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dualform as dfm

RINGS, AROUND = 33, 12


def rotation(axis: str, degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    m = np.eye(4)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def translation(*t: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = t
    return m


class Limb:
    """A closed-ended tube along x (0 to 2) bound to three joints: the upper
    arm (bound turned about x, so that its inverse bind matrix is no mere
    translation), the forearm from x = 1 and a hand joint from x = 1.8 that
    only the tip's vertices name, with a zero weight elsewhere."""

    def __init__(self) -> None:
        x = np.repeat(np.linspace(0.0, 2.0, RINGS), AROUND)
        turn = np.tile(np.linspace(0.0, 2.0 * np.pi, AROUND, endpoint=False), RINGS)
        side = np.stack([x, 0.12 * np.cos(turn), 0.12 * np.sin(turn)], axis=1)
        self.positions = np.vstack([side, [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]])
        tris = []
        for r in range(RINGS - 1):
            for k in range(AROUND):
                a, b = r * AROUND + k, r * AROUND + (k + 1) % AROUND
                tris += [[a, b, b + AROUND], [a, b + AROUND, a + AROUND]]
        start, end = RINGS * AROUND, RINGS * AROUND + 1
        last = (RINGS - 1) * AROUND
        for k in range(AROUND):
            tris.append([start, (k + 1) % AROUND, k])
            tris.append([end, last + k, last + (k + 1) % AROUND])
        self.triangles = np.asarray(tris, dtype=np.uint32)
        px = self.positions[:, 0]
        forearm = np.clip((px - 0.75) / 0.5, 0.0, 1.0)
        hand = np.clip((px - 1.8) / 0.2, 0.0, 1.0) * forearm
        self.joints = np.tile(np.array([0, 1, 2], dtype=np.uint32), (len(px), 1))
        self.weights = np.stack([1.0 - forearm, forearm - hand, hand], axis=1)
        self.bind = np.stack([rotation("x", 30.0), translation(1.0, 0.0, 0.0),
                              translation(1.8, 0.0, 0.0)])
        self.inverse_bind = np.linalg.inv(self.bind)
        self.tip = end

    def pose(self, elbow: float = 70.0, shoulder: float = 20.0) -> np.ndarray:
        """Joint world matrices: the shoulder turned about y and moved, the
        elbow bent about z, the hand following the forearm."""
        upper = translation(0.1, -0.2, 0.05) @ rotation("y", shoulder) @ self.bind[0]
        forearm = upper @ np.linalg.inv(self.bind[0]) @ self.bind[1] @ rotation("z", elbow)
        hand = forearm @ np.linalg.inv(self.bind[1]) @ self.bind[2]
        return np.stack([upper, forearm, hand])

    def skin(self, joint_world: np.ndarray, bind_positions: np.ndarray) -> np.ndarray:
        """The reference: sum_k w_k J_k IBM_k p, weights normalised."""
        w = self.weights / self.weights.sum(axis=1, keepdims=True)
        skinning = joint_world @ self.inverse_bind
        blended = np.einsum("vk,vkij->vij", w, skinning[self.joints.astype(np.int64)])
        return np.einsum("vij,vj->vi", blended[:, :3, :3], bind_positions) + blended[:, :3, 3]

    def mesh(self, context, **overrides) -> dfm.Mesh:
        arrays = dict(joints=self.joints, weights=self.weights,
                      inverse_bind_matrices=self.inverse_bind)
        arrays.update(overrides)
        return dfm.Mesh.from_arrays(context, self.positions, self.triangles, **arrays)


@pytest.fixture(scope="module")
def limb() -> Limb:
    return Limb()


def diagonal(p: np.ndarray) -> float:
    return float(np.linalg.norm(p.max(axis=0) - p.min(axis=0)))


def test_a_skin_from_arrays_poses_as_linear_blend_skinning(context, limb):
    with limb.mesh(context) as mesh:
        info = mesh.skin_info()
        # At most two weights of a vertex are not zero.
        assert (info.joint_count, info.max_influences, info.skinned_vertex_count) == (
            3, 2, len(limb.positions))
        assert not info.posed and info.pose_animation == -1
        assert [j.name for j in mesh.joints()] == ["joint_0", "joint_1", "joint_2"]
        assert mesh.animations() == [] and mesh.morph_targets() == []
        # Unposed, the mesh is its bind shape.
        assert np.array_equal(mesh.positions(), limb.positions)
        pose = limb.pose()
        mesh.set_pose_joints(pose)
        expected = limb.skin(pose, limb.positions)
        posed = mesh.positions()
        assert np.abs(posed - expected).max() <= 1e-12 * diagonal(expected)
        assert np.abs(posed - limb.positions).max() > 0.3
        info = mesh.skin_info()
        assert info.posed and info.pose_animation == -1
        # The info follows the pose: the posed surface's bounding box.
        assert mesh.info.bounds_max == pytest.approx(tuple(expected.max(axis=0)), abs=1e-12)
        # The matrices come back in the convention they went in (M @ p).
        assert np.array_equal(mesh.joint_matrices(), pose)
        # Posing keeps the bind shape; clearing the pose shows it again.
        assert np.array_equal(mesh.bind_positions(), limb.positions)
        mesh.clear_pose()
        assert not mesh.skin_info().posed
        assert np.array_equal(mesh.positions(), limb.positions)


def test_joints_and_weights_in_every_layout_pose_alike(context, limb):
    pose = limb.pose()
    with limb.mesh(context) as reference:
        reference.set_pose_joints(pose)
        expected = reference.positions()
    wide = np.zeros((len(limb.positions), 5), dtype=np.uint16)
    wide[:, 1:4] = limb.joints
    wide_weights = np.zeros((len(limb.positions), 4), dtype=np.float64)
    wide_weights[:, :3] = limb.weights
    layouts = [
        dict(joints=limb.joints.astype(np.uint8), weights=limb.weights.astype(np.float32)),
        dict(joints=limb.joints.astype(np.uint16)),
        dict(joints=limb.joints.astype(np.int64)),  # converted after a range check
        dict(joints=wide[:, 1:4], weights=wide_weights[:, :3]),  # strided rows, in place
        dict(weights=3.0 * limb.weights),  # normalised by the library
        dict(inverse_bind_matrices=list(limb.inverse_bind)),
    ]
    for layout in layouts:
        with limb.mesh(context, **layout) as mesh:
            mesh.set_pose_joints(pose)
            tolerance = 1e-6 if layout.get("weights", limb.weights).dtype == np.float32 else 1e-12
            assert np.abs(mesh.positions() - expected).max() <= tolerance, layout


def test_a_posed_edit_bakes_into_the_exact_bind_space_corrective(context, limb):
    pose = limb.pose()
    lift = np.array([0.0, 0.12, 0.08])
    posed_rest = limb.skin(pose, limb.positions)
    # The same edit on a static copy of the posed mesh.
    with dfm.Mesh.from_arrays(context, posed_rest, limb.triangles) as static, \
            static.roi_ball(limb.tip, 0.3) as roi, static.roi_ball(limb.tip, 0.05) as grip, \
            dfm.Session(static, roi, [grip.vertices()]) as session:
        session.set_translation(0, lift)
        session.solve()
        static_edit, _ = session.read_positions()
        static_roi = roi.vertices()
    with limb.mesh(context) as mesh:
        mesh.set_pose_joints(pose)
        with mesh.roi_ball(limb.tip, 0.3) as roi, mesh.roi_ball(limb.tip, 0.05) as grip, \
                dfm.Session(mesh, roi, [grip.vertices()]) as session:
            assert np.array_equal(roi.vertices(), static_roi)
            session.set_translation(0, lift)
            session.solve()
            session.bake()
        edited = mesh.positions()
        corrected = mesh.bind_positions()
        info = mesh.skin_info()
    d = diagonal(posed_rest)
    moved = np.linalg.norm(static_edit - posed_rest, axis=1)
    assert moved.max() > 0.05 * d
    assert np.abs(edited - static_edit).max() <= 1e-9 * d
    # Skinning the corrected bind shape at the pose gives the edit; the
    # posed displacement copied into bind space does not.
    assert np.abs(limb.skin(pose, corrected) - static_edit).max() <= 1e-9 * d
    naive = limb.skin(pose, limb.positions + (static_edit - posed_rest))
    assert np.abs(naive - static_edit).max() > 1e-2 * d
    assert info.corrective_vertex_count == np.count_nonzero(moved)
    assert 1.0 <= info.corrective_worst_condition < 10.0 and info.corrective_damped_count == 0
    # Vertices the edit left alone keep their bind positions bit for bit.
    still = moved == 0.0
    assert np.array_equal(corrected[still], limb.positions[still])


def test_the_damped_corrective_is_logged(limb):
    # Joint 2 flattened onto a plane: the tip's L_v is singular there.
    log = []
    pose = limb.pose()
    pose[2, :3, 2] = 0.0
    with dfm.Context(log=lambda *entry: log.append(entry)) as ctx, limb.mesh(ctx) as mesh:
        mesh.set_pose_joints(pose)
        with mesh.roi_ball(limb.tip, 0.3) as roi, mesh.roi_ball(limb.tip, 0.05) as grip, \
                dfm.Session(mesh, roi, [grip.vertices()]) as session:
            session.set_translation(0, [0.0, 0.1, 0.0])
            session.solve()
            session.bake()
        info = mesh.skin_info()
    assert info.corrective_damped_count > 0 and info.corrective_worst_condition > 1e3
    damped = [m for level, log_id, m in log if log_id == dfm.LogId.CORRECTIVE_DAMPED]
    assert len(damped) == 1 and str(limb.tip) in damped[0]


def test_bad_skins_are_refused_with_the_library_s_messages(context, limb):
    negative = limb.weights.copy()
    negative[7, 1] = -0.25
    with pytest.raises(dfm.NumericalError, match=r"vertex 7 influence 1: weight -0.25.* "
                                                 "is negative or not finite"):
        limb.mesh(context, weights=negative)
    zero = limb.weights.copy()
    zero[5] = 0.0
    with pytest.raises(dfm.NumericalError, match="vertex 5: its weights sum to 0"):
        limb.mesh(context, weights=zero)
    beyond = limb.joints.copy()
    beyond[9, 2] = 3
    with pytest.raises(dfm.OutOfRangeError,
                       match="vertex 9 influence 2: joint 3 is beyond the skin's 3 joints"):
        limb.mesh(context, joints=beyond)
    singular = limb.inverse_bind.copy()
    singular[1, :3, :3] = 0.0
    with pytest.raises(dfm.NumericalError, match="joint 1's inverse bind matrix is not "
                                                 "invertible"):
        limb.mesh(context, inverse_bind_matrices=singular)


def test_shapes_and_types_are_refused_before_any_call(context, limb):
    with pytest.raises(ValueError, match="joints, weights and inverse_bind_matrices together"):
        limb.mesh(context, weights=None)
    with pytest.raises(ValueError, match=r"joints: expected a \(398, K\) array"):
        limb.mesh(context, joints=limb.joints[:-2])
    with pytest.raises(ValueError, match=r"weights: expected the joints' shape \(398, 3\)"):
        limb.mesh(context, weights=limb.weights[:, :2])
    with pytest.raises(ValueError, match=r"inverse_bind_matrices: expected a \(J, 4, 4\)"):
        limb.mesh(context, inverse_bind_matrices=limb.inverse_bind[:, :3])
    with pytest.raises(ValueError, match="joint indices must lie in 0"):
        limb.mesh(context, joints=limb.joints.astype(np.int64) - 1)
    with pytest.raises(TypeError, match="expected integer joint indices"):
        limb.mesh(context, joints=limb.joints.astype(np.float64))


def test_bad_poses_are_refused_and_change_nothing(context, limb, cow):
    with limb.mesh(context) as mesh:
        pose = limb.pose()
        mesh.set_pose_joints(pose)
        shown = mesh.positions()
        with pytest.raises(dfm.InvalidArgumentError,
                           match="joint_count is 2, the skin has 3 joints"):
            mesh.set_pose_joints(pose[:2])
        with pytest.raises(dfm.InvalidArgumentError, match="1 morph weights for 0 morph targets"):
            mesh.set_pose_joints(pose, morph_weights=[0.5])
        broken = pose.copy()
        broken[1, 2, 3] = math.nan
        with pytest.raises(dfm.NumericalError, match="joint 1's matrix is not finite"):
            mesh.set_pose_joints(broken)
        broken = pose.copy()
        broken[2, 3, 0] = 1.0
        with pytest.raises(dfm.NumericalError, match="joint 2's matrix is not affine"):
            mesh.set_pose_joints(broken)
        with pytest.raises(ValueError, match=r"joint_matrices: expected a \(J, 4, 4\) array"):
            mesh.set_pose_joints(pose[0])
        # A host's skin has no animations.
        with pytest.raises(dfm.OutOfRangeError, match="animation 0 does not exist"):
            mesh.set_pose(0, 0.0)
        with pytest.raises(dfm.NotFoundError, match="no animation named 'Walk'"):
            mesh.set_pose("Walk", 0.0)
        with pytest.raises(ValueError, match="animation: expected an integer from 0"):
            mesh.set_pose(-1, 0.0)
        assert np.array_equal(mesh.positions(), shown)
        assert np.array_equal(mesh.joint_matrices(), pose)
    # No skin: nothing poses the cow.
    for call in (lambda: cow.set_pose(0, 0.0), lambda: cow.set_pose_joints(np.eye(4)[None]),
                 cow.joint_matrices):
        with pytest.raises(dfm.UnsupportedError, match="no skin and no morph targets"):
            call()
