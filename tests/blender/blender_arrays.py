"""Positions out of Blender as numpy arrays, for the scripts that run inside
it (blender_checks.py, artist_path_checks.py, modal_ui_checks.py)."""

import bpy
import numpy as np


def mesh_positions(mesh) -> np.ndarray:
    """A mesh's vertex positions, float32 (n, 3)."""
    a = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", a)
    return a.reshape(-1, 3)


def positions(obj) -> np.ndarray:
    """An object's mesh vertices (not its shape keys' mix)."""
    return mesh_positions(obj.data)


def key_positions(obj, name: str) -> np.ndarray:
    """Shape key ``name``'s positions, float32 (n, 3)."""
    key = obj.data.shape_keys.key_blocks[name]
    a = np.empty(len(key.data) * 3, dtype=np.float32)
    key.data.foreach_get("co", a)
    return a.reshape(-1, 3)


def shown(obj) -> np.ndarray:
    """The positions Blender shows: the shape keys' mix."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = mesh_positions(obj.evaluated_get(depsgraph).to_mesh())
    obj.evaluated_get(depsgraph).to_mesh_clear()
    return evaluated
