"""What the rigged-asset tests share: the assets' folder, Blender's evaluated
meshes (NAME.frames.json) and the map from glTF vertices to Blender's."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

import gltf_skinning as gs

SKINNED = ("arm", "arm-morph", "humanoid")


def assets_dir() -> Path:
    """The folder make-rigged-assets wrote (CTest's fixture rigged_assets)."""
    value = os.environ.get("DUALFORM_RIGGED_ASSETS")
    if not value:
        raise RuntimeError("DUALFORM_RIGGED_ASSETS is not set: run these tests through CTest "
                           "(ctest -R skin), which makes the assets first")
    path = Path(value)
    if not (path / ".complete").is_file():
        raise RuntimeError(f"{path} holds no finished assets (tests/skin/make-rigged-assets)")
    return path


class Rigged:
    """One skinned asset: its glb (asset), Blender's record (frames), the
    bounding-box diagonal of Blender's rest mesh, and blender_of_gltf, the
    Blender vertex each glTF vertex is a copy of."""

    def __init__(self, name: str):
        folder = assets_dir()
        self.name = name
        self.asset = gs.load(str(folder / f"{name}.glb"))
        self.frames = json.loads((folder / f"{name}.frames.json").read_text())
        self.mesh = self.frames["mesh"]
        self.rest = np.array(self.frames["rest_positions"], dtype=np.float64)
        self.diagonal = float(np.linalg.norm(self.rest.max(axis=0) - self.rest.min(axis=0)))
        node = self.asset.gltf["nodes"][gs.mesh_node(self.asset, self.mesh)]
        self.bind = gs.mesh_attribute(self.asset, node["mesh"], "POSITION")
        self.blender_of_gltf = match_by_position(self.bind, self.rest, 1e-6 * self.diagonal)


def match_by_position(gltf_points: np.ndarray, blender_points: np.ndarray,
                      tolerance: float) -> np.ndarray:
    """For each glTF vertex, the one Blender vertex within tolerance of it.

    A skinned glTF from Blender holds its vertices in world space at the bind
    pose, as Blender's rest mesh in world space (Blender's float32 through the
    exporter's float32 matrix product, so equal to rounding, not bit for bit);
    glTF splits a vertex at every UV seam and sharp edge, so several glTF
    vertices may name the same Blender vertex. Points are hashed into cubes of
    side tolerance and looked up in the 27 cubes around; the match must be
    unique (the fixtures' vertices lie far further apart than tolerance) and
    every Blender vertex must be matched."""
    cells: dict[tuple[int, int, int], list[int]] = {}
    keys = np.floor(blender_points / tolerance).astype(np.int64)
    for i, key in enumerate(map(tuple, keys)):
        cells.setdefault(key, []).append(i)
    offsets = [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]
    out = np.empty(len(gltf_points), dtype=np.int64)
    gltf_keys = np.floor(gltf_points / tolerance).astype(np.int64)
    for g, (point, key) in enumerate(zip(gltf_points, gltf_keys)):
        candidates = [i for o in offsets
                      for i in cells.get((key[0] + o[0], key[1] + o[1], key[2] + o[2]), ())]
        near = [i for i in candidates if np.linalg.norm(blender_points[i] - point) <= tolerance]
        if len(near) != 1:
            raise AssertionError(f"glTF vertex {g} at {point} lies within {tolerance:.3g} of "
                                 f"{len(near)} Blender vertices, not one")
        out[g] = near[0]
    missing = np.setdiff1d(np.arange(len(blender_points)), out)
    if len(missing):
        raise AssertionError(f"{len(missing)} Blender vertices have no glTF copy "
                             f"(first {missing[:5]})")
    return out
