"""Blender meshes as Dualform edits: the part every operator shares.

A :class:`DragEdit` owns one Dualform session on an object's mesh: it is
started from the object's "Dualform ROI" and "Dualform Handle ..." vertex
groups, takes a motion of the active handle group (``move``), submits it
and returns at once; ``apply_latest`` copies the newest frame into the mesh
when one has arrived (never waiting), ``finish`` keeps the result in the
mesh or as a shape key, ``cancel`` puts back the exact original positions.
The modal drag and the scripted deform both run through it.
"""

from __future__ import annotations

import math
from typing import List, Optional, Sequence

import numpy as np

ROI_GROUP = "Dualform ROI"
HANDLE_PREFIX = "Dualform Handle"
SHAPE_KEY_NAME = "Dualform Edit"


def dualform():
    """The dualform package (found as __init__.find_package arranged)."""
    import dualform as package

    return package


def mesh_arrays(mesh) -> tuple:
    """(positions float32 (n, 3), triangles uint32 (m, 3)) of an object-mode
    mesh, in Blender's vertex order; faces with more corners are split as
    Blender's own loop triangles split them."""
    n = len(mesh.vertices)
    positions = np.empty(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    mesh.calc_loop_triangles()
    triangles = np.empty(len(mesh.loop_triangles) * 3, dtype=np.uint32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    return positions.reshape(n, 3), triangles.reshape(-1, 3)


def group_vertices(obj, name: str) -> np.ndarray:
    """The vertices of vertex group ``name`` (weight > 0), ascending."""
    group = obj.vertex_groups.get(name)
    if group is None:
        return np.empty(0, dtype=np.uint32)
    index = group.index
    found = [v.index for v in obj.data.vertices
             if any(g.group == index and g.weight > 0.0 for g in v.groups)]
    return np.asarray(found, dtype=np.uint32)


def handle_group_names(obj) -> List[str]:
    return [g.name for g in obj.vertex_groups if g.name.startswith(HANDLE_PREFIX)]


def motion_matrix(translate: Sequence[float] = (0.0, 0.0, 0.0),
                  axis: Sequence[float] = (0.0, 0.0, 1.0), degrees: float = 0.0,
                  pivot: Optional[Sequence[float]] = None) -> np.ndarray:
    """T(translate) R(axis, degrees about pivot), in double: the rotation
    applies first, then the translation (as in a scenario)."""
    m = np.eye(4)
    if degrees:
        a = np.asarray(axis, dtype=np.float64)
        a = a / np.linalg.norm(a)
        c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
        k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        r = np.eye(3) * c + s * k + (1.0 - c) * np.outer(a, a)
        p = np.zeros(3) if pivot is None else np.asarray(pivot, dtype=np.float64)
        m[:3, :3] = r
        m[:3, 3] = p - r @ p
    m[:3, 3] += np.asarray(translate, dtype=np.float64)
    return m


class DragEdit:
    """One Dualform session on ``obj``'s mesh (object mode), moving the
    handle group ``handle`` (a vertex group name; None: the last handle
    group) while the other handle groups stay put."""

    def __init__(self, obj, handle: Optional[str] = None, library: Optional[str] = None) -> None:
        dfm = dualform()
        if library:
            dfm.load_library(library)
        self.obj = obj
        mesh = obj.data
        self.original, triangles = mesh_arrays(mesh)
        roi = group_vertices(obj, ROI_GROUP)
        names = handle_group_names(obj)
        if roi.size == 0:
            raise ValueError(f"no '{ROI_GROUP}' vertex group: run Water-Fill ROI first")
        if not names:
            raise ValueError("no handle group: select vertices and run Add Handle first")
        self.handle = handle or names[-1]
        if self.handle not in names:
            raise ValueError(f"'{self.handle}' is not a handle group (one of {', '.join(names)})")
        self.group_index = names.index(self.handle)
        groups = [group_vertices(obj, name) for name in names]
        self.pivot = self.original[groups[self.group_index]].astype(np.float64).mean(axis=0)
        self._context = dfm.Context()
        try:
            self._mesh = dfm.Mesh.from_arrays(self._context, self.original, triangles)
            self._roi = self._mesh.roi_from_vertices(roi)
            self.session = dfm.Session(self._mesh, self._roi, groups)
        except Exception:
            self._context.close()
            raise
        self._buffer = self.original.copy()
        self.submitted = 0
        self.applied = 0
        self.last_info = None

    # The latest motion wins: earlier ones still queued are never solved.
    def move(self, matrix: np.ndarray) -> int:
        self.session.set_group_transform(self.group_index, matrix)
        self.submitted = self.session.submit()
        return self.submitted

    def apply_latest(self) -> bool:
        """Copies the newest frame into the mesh if it is newer than the one
        shown; never waits for the solver. True when the mesh changed."""
        info, is_new = self.session.poll(self.applied)
        if not is_new or info.preparing:
            return False
        _, info = self.session.read_positions(np.float32, out=self._buffer)
        self._write(self._buffer)
        self.applied = info.generation
        self.last_info = info
        return True

    @property
    def settled(self) -> bool:
        """The newest submitted motion's finished frame is in the mesh."""
        if self.submitted == 0:
            return True
        return (self.last_info is not None and self.applied >= self.submitted
                and not self.last_info.partial)

    def wait_and_apply(self) -> None:
        """For scripts: waits for the newest motion's solve and applies it."""
        self.session.wait(self.submitted)
        self.apply_latest()

    def _write(self, positions: np.ndarray) -> None:
        mesh = self.obj.data
        mesh.vertices.foreach_set("co", positions.reshape(-1))
        mesh.update()

    def finish(self, keep: str = "MESH") -> None:
        """Keeps the shown result: in the mesh ('MESH'), or as a shape key
        ('SHAPE_KEY', value 1) over the original positions as the basis."""
        result = self._buffer.copy()
        if keep == "SHAPE_KEY":
            self._write(self.original)
            obj = self.obj
            if obj.data.shape_keys is None:
                obj.shape_key_add(name="Basis", from_mix=False)
            key = obj.shape_key_add(name=SHAPE_KEY_NAME, from_mix=False)
            key.data.foreach_set("co", result.reshape(-1))
            key.value = 1.0
            obj.data.update()
        self.close()

    def cancel(self) -> None:
        """Puts the original positions back, bit for bit."""
        self.session.cancel()
        self._write(self.original)
        self.close()

    def close(self) -> None:
        for handle in (self.session, self._roi, self._mesh, self._context):
            handle.close()


def water_fill(obj, first: int, last: int):
    """Water-Filling of ``obj``'s mesh (object-mode data) from ``first`` to
    ``last``: (ROI vertices, diagnosis)."""
    dfm = dualform()
    positions, triangles = mesh_arrays(obj.data)
    with dfm.Context() as ctx, dfm.Mesh.from_arrays(ctx, positions, triangles) as mesh, \
            mesh.water_fill(first, last) as roi:
        return roi.vertices(), roi.diagnosis


def diagnosis_text(count: int, diagnosis) -> str:
    text = f"Water-Fill ROI: {count} vertices, {diagnosis.loops} cut loop(s)"
    if diagnosis.suspect:
        return text + "; SUSPECT: the fill most likely leaked past the intended limb"
    if not diagnosis.bounded_by_last_loop:
        return text + "; the loop through the end vertex does not bound it"
    return text
