#!/usr/bin/env python3
"""Writes small skinned glTF assets for the glTF fuzz target's seed corpus
(tools/fuzz): every part the skin reader parses in a few hundred bytes of
buffer, so that mutations reach it. A strip of quads bound to three joints
in a chain, two JOINTS/WEIGHTS sets (unsigned bytes and shorts, float and
normalised weights), inverse bind matrices, a morph target with default
weights, and one animation with a LINEAR rotation, a STEP translation, a
CUBICSPLINE scale and a weights channel.

usage: make_fuzz_seed.py OUT_DIR   (writes skinned.glb and skinned.gltf)
"""

import sys
from pathlib import Path

import numpy as np

from gltf_writer import GltfWriter


def skinned_strip(joint_override=None, weights_scale=1.0) -> GltfWriter:
    """The asset; `joint_override` (vertex, joint) and `weights_scale` make
    the malformed variants of tests/data/malformed."""
    rows = 4
    positions = np.array([(x, y, 0.0) for y in range(rows) for x in (0.0, 1.0)], np.float32)
    triangles = []
    for y in range(rows - 1):
        a, b, c, d = 2 * y, 2 * y + 1, 2 * y + 3, 2 * y + 2
        triangles += [a, b, c, a, c, d]
    # Each vertex: its row's joint at 3/4 (set 0, floats) and the next
    # joint at 1/4 (set 1, normalised shorts); valid as the validator reads it.
    joints0 = np.array([(min(v // 2, 2), 0, 0, 0) for v in range(len(positions))], np.uint8)
    joints1 = np.array([((min(v // 2, 2) + 1) % 3, 0, 0, 0) for v in range(len(positions))],
                       np.uint16)
    weights1 = np.array([(16384, 0, 0, 0)] * len(positions), np.uint16)
    quarter = np.float32(16384 / 65535)
    weights0 = np.array([(np.float32(1) - quarter, 0.0, 0.0, 0.0)] * len(positions), np.float32)
    if joint_override is not None:
        joints0[joint_override[0], 0] = joint_override[1]
    weights0 *= np.float32(weights_scale)
    weights1 = (weights1 * weights_scale).astype(np.uint16)
    inverse_bind = np.array([np.eye(4)] * 3, np.float32)
    for j in range(3):
        inverse_bind[j][1, 3] = -float(j)
    bulge = np.zeros_like(positions)
    bulge[:, 2] = 0.1
    w = GltfWriter()
    attributes = {
        "POSITION": w.array(positions),
        "JOINTS_0": w.array(joints0, np.uint8),
        "WEIGHTS_0": w.array(weights0),
        "JOINTS_1": w.array(joints1, np.uint16),
        "WEIGHTS_1": w.array(weights1, np.uint16, normalized=True),
    }
    indices = w.array(np.array(triangles, np.uint16), np.uint16)
    target = w.array(bulge)
    ibm = w.matrices(inverse_bind)
    times = w.array(np.array([0.0, 0.5], np.float32))
    rotation = w.array(np.array([(0, 0, 0, 1), (0, 0, 0.38268343, 0.9238795)], np.float32))
    translation = w.array(np.array([(0, 1, 0), (0.2, 1, 0)], np.float32))
    scale = w.array(np.array([(0, 0, 0), (1, 1, 1), (0, 0, 0),
                              (0, 0, 0), (1.5, 1, 1), (0, 0, 0)], np.float32))
    weights = w.array(np.array([0.0, 1.0], np.float32))
    w.gltf.update({
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "Strip", "mesh": 0, "skin": 0, "weights": [0.5]},
                  {"name": "Root", "children": [2]},
                  {"name": "Middle", "translation": [0, 1, 0], "children": [3]},
                  {"name": "Tip", "translation": [0, 1, 0]}],
        "skins": [{"joints": [1, 2, 3], "inverseBindMatrices": ibm}],
        "meshes": [{"name": "Strip", "weights": [0.0], "extras": {"targetNames": ["Bulge"]},
                    "primitives": [{"attributes": attributes, "indices": indices,
                                    "targets": [{"POSITION": target}]}]}],
        "animations": [{"name": "Bend",
                        "samplers": [{"input": times, "output": rotation},
                                     {"input": times, "output": translation,
                                      "interpolation": "STEP"},
                                     {"input": times, "output": scale,
                                      "interpolation": "CUBICSPLINE"},
                                     {"input": times, "output": weights}],
                        "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}},
                                     {"sampler": 1, "target": {"node": 3, "path": "translation"}},
                                     {"sampler": 2, "target": {"node": 3, "path": "scale"}},
                                     {"sampler": 3, "target": {"node": 0, "path": "weights"}}]}],
    })
    return w


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    w = skinned_strip()
    w.write_glb(out / "skinned.glb")
    w.write_gltf(out / "skinned.gltf")


if __name__ == "__main__":
    main()
