"""The reference's accessor reading where Blender's files do not reach:
Blender writes float weights, one JOINTS/WEIGHTS set, tightly packed views,
dense morph targets and TRS nodes. Each test re-encodes a Blender asset the
other way glTF allows and checks that the reference poses it as before."""

from __future__ import annotations

import numpy as np
import pytest

import gltf_skinning as gs
from gltf_writer import GltfWriter
from rigged import Rigged


@pytest.fixture(scope="module")
def humanoid():
    return Rigged("humanoid")


@pytest.fixture(scope="module")
def arm_morph():
    return Rigged("arm-morph")


def rewritten(rigged):
    """A writer holding the asset's JSON and BIN, and its mesh's primitive."""
    asset = rigged.asset
    writer = GltfWriter(asset.gltf, asset.buffers[0])
    node = writer.gltf["nodes"][gs.mesh_node(asset, rigged.mesh)]
    primitives = writer.gltf["meshes"][node["mesh"]]["primitives"]
    assert len(primitives) == 1
    return writer, primitives[0]


def posed(asset, rigged, animation="Walk", time=7 / 24):
    return gs.posed_positions(asset, rigged.mesh, animation, time)


def influences(rigged):
    node = rigged.asset.gltf["nodes"][gs.mesh_node(rigged.asset, rigged.mesh)]
    return gs.vertex_influences(rigged.asset, node["mesh"])


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_interleaved_normalised_weights(humanoid, tmp_path, dtype):
    # POSITION, JOINTS_0 (unsigned short) and WEIGHTS_0 (normalised unsigned
    # byte or short) interleaved in one view with a byteStride, against the
    # same quantised weights stored as floats.
    joints, weights = influences(humanoid)
    scale = np.iinfo(dtype).max
    quantised = np.rint(weights * scale)
    position = humanoid.bind.astype(np.float32)

    floats, primitive = rewritten(humanoid)
    primitive["attributes"]["WEIGHTS_0"] = floats.array(quantised / scale)
    expected = posed(gs.load(str(floats.write_glb(tmp_path / "floats.glb"))), humanoid)

    packed, primitive = rewritten(humanoid)
    weight_bytes = 4 * np.dtype(dtype).itemsize
    stride = 12 + 8 + weight_bytes
    stride += -stride % 4
    record = np.zeros((len(position), stride), dtype=np.uint8)
    record[:, 0:12] = position.view(np.uint8).reshape(-1, 12)
    record[:, 12:20] = joints.astype(np.uint16).view(np.uint8).reshape(-1, 8)
    weight_record = quantised.astype(dtype).view(np.uint8).reshape(-1, weight_bytes)
    record[:, 20:20 + weight_bytes] = weight_record
    view = packed.view(record.tobytes(), stride=stride)
    n = len(position)
    primitive["attributes"]["POSITION"] = packed.accessor(
        view, np.float32, 3, n, min=position.min(axis=0).tolist(),
        max=position.max(axis=0).tolist())
    primitive["attributes"]["JOINTS_0"] = packed.accessor(view, np.uint16, 4, n, offset=12)
    primitive["attributes"]["WEIGHTS_0"] = packed.accessor(view, dtype, 4, n, offset=20,
                                                           normalized=True)
    got = posed(gs.load(str(packed.write_glb(tmp_path / "packed.glb"))), humanoid)

    error = np.linalg.norm(got - expected, axis=1).max() / humanoid.diagonal
    assert error < 1e-6
    # Quantising the weights does move the mesh: the check sees the weights.
    assert np.linalg.norm(expected - posed(humanoid.asset, humanoid), axis=1).max() > 1e-6


def test_influences_split_over_two_sets(humanoid):
    joints, weights = influences(humanoid)
    assert (weights[:, 2:] > 0).any(), "the humanoid should have vertices with 3 or 4 influences"
    writer, primitive = rewritten(humanoid)
    zeros = np.zeros((len(joints), 2))
    primitive["attributes"]["JOINTS_0"] = writer.array(np.hstack([joints[:, :2], zeros]), np.uint8)
    primitive["attributes"]["WEIGHTS_0"] = writer.array(np.hstack([weights[:, :2], zeros]))
    primitive["attributes"]["JOINTS_1"] = writer.array(np.hstack([joints[:, 2:], zeros]), np.uint8)
    primitive["attributes"]["WEIGHTS_1"] = writer.array(np.hstack([weights[:, 2:], zeros]))
    error = np.abs(posed(writer.asset(), humanoid) - posed(humanoid.asset, humanoid)).max()
    assert error < 1e-12 * humanoid.diagonal


def test_sparse_morph_target(arm_morph):
    asset = arm_morph.asset
    node = asset.gltf["nodes"][gs.mesh_node(asset, arm_morph.mesh)]
    primitive = asset.gltf["meshes"][node["mesh"]]["primitives"][0]
    target = asset.accessor(primitive["targets"][0]["POSITION"])
    moved = np.nonzero(np.abs(target).sum(axis=1))[0]
    assert 0 < len(moved) < len(target) // 2
    writer, primitive = rewritten(arm_morph)
    sparse = {
        "count": len(moved),
        "indices": {"bufferView": writer.view(moved.astype(np.uint16).tobytes()),
                    "componentType": 5123},
        "values": {"bufferView": writer.view(target[moved].astype(np.float32).tobytes())},
    }
    primitive["targets"][0]["POSITION"] = writer.accessor(None, np.float32, 3, len(target),
                                                          sparse=sparse)
    for weights in (None, [1.0]):
        got = gs.posed_positions(writer.asset(), arm_morph.mesh, "Wave", 0.5, morph_weights=weights)
        want = gs.posed_positions(asset, arm_morph.mesh, "Wave", 0.5, morph_weights=weights)
        assert np.abs(got - want).max() < 1e-12 * arm_morph.diagonal


def test_matrix_node(humanoid):
    # The rig's root node (moved and turned) given as a matrix instead of TRS.
    writer, _ = rewritten(humanoid)
    root = next(n for n in writer.gltf["nodes"] if n.get("name") == "HumanRig")
    assert "rotation" in root and "translation" in root
    m = gs.trs_matrix(*gs.node_trs(root))
    for key in ("translation", "rotation", "scale"):
        root.pop(key, None)
    root["matrix"] = m.T.reshape(-1).tolist()
    error = np.abs(posed(writer.asset(), humanoid) - posed(humanoid.asset, humanoid)).max()
    assert error < 1e-12 * humanoid.diagonal


def test_gltf_with_data_uri(humanoid, tmp_path):
    writer, _ = rewritten(humanoid)
    asset = gs.load(str(writer.write_gltf(tmp_path / "humanoid.gltf")))
    assert np.array_equal(posed(asset, humanoid), posed(humanoid.asset, humanoid))
