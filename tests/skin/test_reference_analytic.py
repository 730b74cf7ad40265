"""The reference's interpolation, hierarchy and skinning against answers
known in closed form, on small assets built here: Blender's files sample
rotations only at keys and midpoints, where slerp and a normalised lerp
agree, so slerp's shape, the cubic spline's tangents, STEP's edges and the
weights channel's layout are checked here."""

from __future__ import annotations

import math

import numpy as np

import gltf_skinning as gs
from gltf_writer import GltfWriter


def z_turn(degrees):
    half = math.radians(degrees) / 2
    return [0.0, 0.0, math.sin(half), math.cos(half)]


def animated_node(samplers):
    """One node (a mesh of three vertices with two morph targets) and one
    animation of samplers: (path, interpolation, times, outputs)."""
    w = GltfWriter()
    w.gltf["meshes"] = [{"primitives": [{
        "attributes": {"POSITION": w.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]])},
        "targets": [{"POSITION": w.array([[1, 0, 0], [0, 0, 0], [0, 0, 0]])},
                    {"POSITION": w.array([[0, 0, 0], [0, 2, 0], [0, 0, 0]])}],
    }], "weights": [0.5, 0.25]}]
    w.gltf["nodes"] = [{"mesh": 0}]
    channels, built = [], []
    for i, (path, interpolation, times, outputs) in enumerate(samplers):
        times = np.asarray(times, dtype=np.float32).reshape(-1, 1)
        if path == "weights":
            outputs = np.asarray(outputs).reshape(-1, 1)
        built.append({"input": w.array(times), "output": w.array(outputs),
                      "interpolation": interpolation})
        channels.append({"sampler": i, "target": {"node": 0, "path": path}})
    w.gltf["animations"] = [{"name": "A", "samplers": built, "channels": channels}]
    return w.asset()


def sample(asset, path, time):
    return gs.animated_values(asset, "A", time)[(0, path)]


def test_linear_rotation_is_slerp_on_the_short_arc():
    asset = animated_node([("rotation", "LINEAR", [0.0, 2.0], [z_turn(0), z_turn(120)])])
    assert np.allclose(sample(asset, "rotation", 0.5), z_turn(30), atol=1e-7)
    assert np.allclose(sample(asset, "rotation", 1.5), z_turn(90), atol=1e-7)
    # The second key given as -q: the same rotation, interpolated the short way.
    asset = animated_node([("rotation", "LINEAR", [0.0, 1.0],
                            [z_turn(0), [-c for c in z_turn(60)]])])
    assert np.allclose(sample(asset, "rotation", 0.25), z_turn(15), atol=1e-7)


def test_step_holds_until_the_next_key_and_clamps():
    keys = [[1, 0, 0], [2, 0, 0], [3, 0, 0]]
    asset = animated_node([("translation", "STEP", [1.0, 2.0, 3.0], keys)])
    for time, x in ((0.0, 1), (1.0, 1), (1.999, 1), (2.0, 2), (2.5, 2), (3.0, 3), (9.0, 3)):
        assert sample(asset, "translation", time)[0] == x, time


def test_cubic_spline_reproduces_a_cubic():
    # Hermite interpolation with the derivative as tangents is exact on a
    # cubic, over uneven intervals too; outputs are (in, value, out) per key.
    def x(t):
        return t ** 3 - 2 * t

    def dx(t):
        return 3 * t ** 2 - 2

    times = [0.0, 0.5, 2.0]
    outputs = [[[dx(t), 0, 0], [x(t), 1, 0], [dx(t), 0, 0]] for t in times]
    asset = animated_node([("translation", "CUBICSPLINE", times, np.reshape(outputs, (-1, 3)))])
    for t in (0.1, 0.3, 0.5, 1.1, 1.9):
        assert np.allclose(sample(asset, "translation", t), [x(t), 1, 0], atol=1e-6), t
    # A linear interpolation of the same keys would miss.
    assert abs(sample(asset, "translation", 1.1)[0] - (x(0.5) + (x(2.0) - x(0.5)) * 0.4)) > 0.1


def test_cubic_spline_rotation_is_normalised():
    q0, q1 = np.array(z_turn(0)), np.array(z_turn(90))
    zero = [0.0] * 4
    keys = [zero, q0, zero, zero, q1, zero]
    asset = animated_node([("rotation", "CUBICSPLINE", [0.0, 1.0], keys)])
    mid = (q0 + q1) / 2
    assert np.allclose(sample(asset, "rotation", 0.5), mid / np.linalg.norm(mid), atol=1e-7)
    assert np.allclose(sample(asset, "rotation", 0.5), z_turn(45), atol=1e-7)


def test_weights_channel_drives_the_morph_targets():
    # Two targets: w0(t) = t^2, w1(t) = 1 - t, as CUBICSPLINE (per key: both
    # in-tangents, both values, both out-tangents) and as LINEAR.
    cubic = []
    for t in (0.0, 1.0):
        cubic += [2 * t, -1.0, t * t, 1 - t, 2 * t, -1.0]
    for interpolation, outputs, time, want in (
            ("CUBICSPLINE", cubic, 0.25, (0.0625, 0.75)),
            ("LINEAR", [0.0, 1.0, 1.0, 0.0], 0.25, (0.25, 0.75))):
        asset = animated_node([("weights", interpolation, [0.0, 1.0], outputs)])
        got = gs.posed_positions(asset, 0, "A", time)
        expected = [[1 + want[0], 0, 0], [0, 1 + 2 * want[1], 0], [0, 0, 1]]
        assert np.allclose(got, expected, atol=1e-6)
    # Without an animation: the mesh's default weights.
    assert np.allclose(gs.posed_positions(asset, 0), [[1.5, 0, 0], [0, 1.5, 0], [0, 0, 1]])


def test_hierarchy_and_skinning():
    # A parent (scaled, turned) above a static mesh; then two joints under
    # it, the second turned 90 degrees about Z, and one vertex weighted half
    # to each: half way between the vertex and its turned copy.
    w = GltfWriter()
    w.gltf["meshes"] = [
        {"primitives": [{"attributes": {"POSITION": w.array([[1, 0, 0]])}}]},
        {"primitives": [{"attributes": {"POSITION": w.array([[1, 0, 0]]),
                                        "JOINTS_0": w.array([[0, 1, 0, 0]], np.uint8),
                                        "WEIGHTS_0": w.array([[0.5, 0.5, 0, 0]])}}]},
    ]
    w.gltf["nodes"] = [
        {"children": [1, 2, 3], "scale": [2, 2, 2], "rotation": z_turn(90),
         "translation": [0, 0, 5]},
        {"mesh": 0, "translation": [1, 0, 0]},
        {"name": "j0"},
        {"name": "j1", "rotation": z_turn(90)},
        {"mesh": 1, "skin": 0, "translation": [100, 100, 100]},  # ignored: skinned
    ]
    bind = np.stack([np.linalg.inv(gs.trs_matrix([0, 0, 5], z_turn(90), [2, 2, 2]))] * 2)
    w.gltf["skins"] = [{"joints": [2, 3], "inverseBindMatrices": w.matrices(bind)}]
    asset = w.asset()
    # Static: parent * child * (1, 0, 0) = parent * (2, 0, 0) = (0, 4, 5).
    assert np.allclose(gs.posed_positions(asset, 1), [[0, 4, 5]])
    # Skinned: world(j) * IBM = parent * local(j) * parent^-1.
    parent = gs.trs_matrix([0, 0, 5], z_turn(90), [2, 2, 2])
    turned = parent @ gs.trs_matrix([0, 0, 0], z_turn(90), [1, 1, 1]) @ np.linalg.inv(parent)
    want = 0.5 * np.array([1, 0, 0]) + 0.5 * (turned @ [1, 0, 0, 1])[:3]
    assert np.allclose(gs.posed_positions(asset, 4), [want])
    assert not np.allclose(want, [1, 0, 0])
