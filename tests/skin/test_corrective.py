"""Why a posed edit must be stored as d = L_v^-1 D' (issue 46): engines apply
morph targets before skinning, and linear blend skinning is affine in the
bind position, so a posed-space displacement D' copied unchanged into a
bind-space morph target lands rotated and scaled by the pose, while the
corrective d = L_v^-1 D' (L_v the 3x3 part of sum_i w_i jointMatrix_i)
lands exactly. Both are played back by the numpy reference."""

from __future__ import annotations

import numpy as np

import gltf_skinning as gs

LIFT = 0.05  # of the diagonal, straight up (+Y in glTF) in posed world space
HANDFUL = 10  # Blender vertices (with their glTF seam copies)

# The pose and the end joint of each asset: the forearm's tip at the wave's
# highest elbow, the left hand mid-stride.
POSES = {
    "arm": ("Wave", 13, "Forearm"),
    "arm-morph": ("Wave", 13, "Forearm"),
    "humanoid": ("Walk", 7, "Hand.L"),
}


def hand_vertices(rigged, animation, time, joint_name):
    """The glTF vertices of the HANDFUL Blender vertices bound mostly to the
    joint and farthest from its origin at the pose: the fingertips."""
    asset = rigged.asset
    node_index = gs.mesh_node(asset, rigged.mesh)
    node = asset.gltf["nodes"][node_index]
    skin = asset.gltf["skins"][node["skin"]]
    joint_node = next(j for j in skin["joints"] if asset.gltf["nodes"][j].get("name") == joint_name)
    joint = skin["joints"].index(joint_node)
    joints, weights = gs.vertex_influences(asset, node["mesh"])
    dominant = joints[np.arange(len(joints)), weights.argmax(axis=1)] == joint
    world = gs.world_matrices(asset, gs.animated_values(asset, animation, time))
    posed = gs.posed_positions(asset, rigged.mesh, animation, time)
    reach = np.linalg.norm(posed - world[joint_node][:3, 3], axis=1)
    reach[~dominant] = -1.0
    chosen = []
    for g in np.argsort(-reach, kind="stable"):
        if rigged.blender_of_gltf[g] not in chosen:
            chosen.append(rigged.blender_of_gltf[g])
        if len(chosen) == HANDFUL:
            break
    return np.nonzero(np.isin(rigged.blender_of_gltf, chosen))[0]


def test_naive_copy_misses_and_exact_corrective_lands(rigged):
    animation, frame, joint_name = POSES[rigged.name]
    record = next(r for r in rigged.frames["frames"]
                  if r["animation"] == animation and r["frame"] == frame)
    time = record["time_seconds"]
    asset = rigged.asset
    posed = gs.posed_positions(asset, rigged.mesh, animation, time)
    lifted = hand_vertices(rigged, animation, time, joint_name)
    displacement = np.zeros_like(posed)
    displacement[lifted, 1] = LIFT * rigged.diagonal
    wanted = posed + displacement

    naive = gs.posed_positions(asset, rigged.mesh, animation, time, extra_target=displacement)
    naive_miss = np.linalg.norm(naive - wanted, axis=1).max() / rigged.diagonal

    corrective = gs.corrective(asset, rigged.mesh, animation, time, displacement)
    exact = gs.posed_positions(asset, rigged.mesh, animation, time, extra_target=corrective)
    exact_miss = np.linalg.norm(exact - wanted, axis=1).max() / rigged.diagonal
    # As a file stores it: float32.
    stored = gs.posed_positions(asset, rigged.mesh, animation, time,
                                extra_target=corrective.astype(np.float32))
    stored_miss = np.linalg.norm(stored - wanted, axis=1).max() / rigged.diagonal

    print(f"\n{rigged.name}, {animation} frame {frame}: {len(lifted)} glTF vertices "
          f"({HANDFUL} Blender vertices) lifted by {LIFT} of the diagonal; "
          f"posed D' copied as a morph target misses by {naive_miss:.3f} of the diagonal "
          f"({naive_miss / LIFT:.2f}x the lift), d = L_v^-1 D' by {exact_miss:.1e} "
          f"({stored_miss:.1e} with d stored as float32)")
    assert naive_miss > 0.2 * LIFT
    assert exact_miss < 1e-7
    assert stored_miss < 1e-7
    # Vertices the edit leaves alone keep a zero delta.
    untouched = np.setdiff1d(np.arange(len(posed)), lifted)
    assert not corrective[untouched].any()
