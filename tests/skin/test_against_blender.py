"""The numpy reference (gltf_skinning.py) against Blender's own evaluated
mesh: the glb's vertices posed by the reference at each recorded frame land
where Blender's Armature modifier put them, within 1e-5 of the diagonal.
This is what makes the reference a reference."""

from __future__ import annotations

import numpy as np

import gltf_skinning as gs

TOLERANCE = 1e-5  # of the bounding-box diagonal


def test_reference_poses_the_glb_as_blender_evaluates_it(rigged):
    asset = rigged.asset
    print(f"\n{rigged.name}: {len(rigged.bind)} glTF vertices, {len(rigged.rest)} Blender vertices "
          f"({len(rigged.bind) - len(rigged.rest)} seam copies), diagonal {rigged.diagonal:.4f}")
    assert len(rigged.frames["frames"]) >= 2
    for record in rigged.frames["frames"]:
        posed = gs.posed_positions(asset, rigged.mesh, record["animation"], record["time_seconds"])
        blender = np.array(record["positions"], dtype=np.float64)[rigged.blender_of_gltf]
        error = np.linalg.norm(posed - blender, axis=1).max() / rigged.diagonal
        rest = rigged.rest[rigged.blender_of_gltf]
        moved = np.linalg.norm(blender - rest, axis=1).max() / rigged.diagonal
        print(f"  {record['animation']} frame {record['frame']} "
              f"(t={record['time_seconds']:.6f} s): "
              f"reference vs Blender {error:.2e} of the diagonal; the pose moves vertices up to "
              f"{moved:.3f} of it")
        assert error < TOLERANCE, f"{rigged.name} {record['animation']} frame {record['frame']}"


def test_each_frame_is_a_real_pose(rigged):
    # A frame that leaves the mesh at rest would check nothing of skinning.
    for record in rigged.frames["frames"]:
        blender = np.array(record["positions"], dtype=np.float64)
        moved = np.linalg.norm(blender - rigged.rest, axis=1).max() / rigged.diagonal
        assert moved > 0.02, (f"{rigged.name} {record['animation']} frame {record['frame']} "
                              f"moves {moved:.2e}")


def test_file_default_pose_is_blender_rest(rigged):
    # The nodes' own TRS (no animation, no morph weight) pose the mesh at
    # Blender's rest: the bind pose is the rest pose.
    node = gs.mesh_node(rigged.asset, rigged.mesh)
    no_morph = np.zeros_like(gs.morph_weights_of(rigged.asset, node, {}))
    posed = gs.posed_positions(rigged.asset, node, morph_weights=no_morph)
    rest = rigged.rest[rigged.blender_of_gltf]
    error = np.linalg.norm(posed - rest, axis=1).max() / rigged.diagonal
    assert error < TOLERANCE
