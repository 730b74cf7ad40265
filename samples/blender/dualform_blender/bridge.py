"""Blender meshes as Dualform edits: the part every operator shares.

Real assets come split: a glTF import, UV seams and hard edges give one
position several Blender vertices. Every Dualform mesh here is made with
the library's exact weld (``Mesh.from_arrays(..., weld=0)``), so Water-
Filling and the solve see one surface, and the library's surface map takes
its answers back to every copy (docs/gltf.md, "The numbering rule").

A :class:`DragEdit` owns one Dualform session on an object's mesh: it is
started from the object's "Dualform ROI" and "Dualform Handle ..." vertex
groups, takes a motion of the active handle group (``move``), submits it
and returns at once; ``apply_latest`` copies the newest frame into the
mesh when one has arrived (never waiting), ``finish`` keeps the result,
``cancel`` puts everything back exactly as it was. The modal drag and the
scripted deform both run through it.
"""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

ROI_GROUP = "Dualform ROI"
HANDLE_PREFIX = "Dualform Handle"
SHAPE_KEY_NAME = "Dualform Edit"


def dualform():
    """The dualform package (found as __init__.find_package arranged)."""
    import dualform as package

    return package


def mesh_arrays(mesh) -> Tuple[np.ndarray, np.ndarray]:
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


def welded_mesh(context, positions: np.ndarray, triangles: np.ndarray):
    """A Dualform mesh of Blender's arrays, split copies at equal positions
    welded into one surface vertex; Blender's numbering stays."""
    return dualform().Mesh.from_arrays(context, positions, triangles, weld=0)


class Surface:
    """An object-mode mesh as Dualform sees it: the welded mesh and each
    Blender vertex's surface vertex (its lowest copy)."""

    def __init__(self, obj, positions: Optional[np.ndarray] = None) -> None:
        dfm = dualform()
        rest, self.triangles = mesh_arrays(obj.data)
        self.positions = rest if positions is None else positions
        self.context = dfm.Context()
        try:
            self.mesh = welded_mesh(self.context, self.positions, self.triangles)
            self.lowest = self.mesh.surface_map()
        except Exception:
            self.context.close()
            raise

    def copies(self, vertices: np.ndarray) -> np.ndarray:
        """Every Blender vertex that is one of ``vertices``' surface vertices."""
        if vertices.size == 0:
            return np.empty(0, dtype=np.uint32)
        return np.flatnonzero(np.isin(self.lowest, self.lowest[vertices])).astype(np.uint32)

    def surface_vertices(self, vertices: np.ndarray) -> np.ndarray:
        """``vertices`` as surface vertices, each once (ascending lowest copies)."""
        return np.unique(self.lowest[vertices])

    def close(self) -> None:
        self.mesh.close()
        self.context.close()

    def __enter__(self) -> "Surface":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def group_vertices(obj, name: str) -> np.ndarray:
    """The vertices of vertex group ``name`` (weight > 0), ascending."""
    group = obj.vertex_groups.get(name)
    if group is None:
        return np.empty(0, dtype=np.uint32)
    index = group.index
    found = [v.index for v in obj.data.vertices
             if any(g.group == index and g.weight > 0.0 for g in v.groups)]
    return np.asarray(found, dtype=np.uint32)


def set_group(obj, name: str, vertices: np.ndarray):
    """Makes vertex group ``name`` exactly ``vertices`` (weight 1), in object mode."""
    group = obj.vertex_groups.get(name)
    if group is None:
        group = obj.vertex_groups.new(name=name)
    else:
        group.remove(list(range(len(obj.data.vertices))))
    group.add(vertices.tolist(), 1.0, "REPLACE")
    return group


def handle_group_names(obj) -> List[str]:
    return [g.name for g in obj.vertex_groups if g.name.startswith(HANDLE_PREFIX)]


def next_handle_name(obj) -> str:
    taken = set(handle_group_names(obj))
    n = len(taken) + 1
    while f"{HANDLE_PREFIX} {n}" in taken:
        n += 1
    return f"{HANDLE_PREFIX} {n}"


def motion_matrix(translate: Sequence[float] = (0.0, 0.0, 0.0),
                  axis: Sequence[float] = (0.0, 0.0, 1.0), degrees: float = 0.0,
                  pivot: Optional[Sequence[float]] = None) -> np.ndarray:
    """T(translate) R(axis, degrees about pivot), in double: the rotation
    applies first, then the translation (as in a scenario)."""
    m = np.eye(4)
    if degrees:
        a = np.asarray(axis, dtype=np.float64)
        length = np.linalg.norm(a)
        if not length > 0.0:
            raise ValueError("the rotation axis must not be the zero vector")
        a = a / length
        c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
        k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        r = np.eye(3) * c + s * k + (1.0 - c) * np.outer(a, a)
        p = np.zeros(3) if pivot is None else np.asarray(pivot, dtype=np.float64)
        m[:3, :3] = r
        m[:3, 3] = p - r @ p
    m[:3, 3] += np.asarray(translate, dtype=np.float64)
    return m


class ShapeKeyTarget:
    """Where an edit kept as a shape key goes. A new key starts from the
    shape the user sees (the keys' current mix, Blender's "from mix"); it
    holds the whole edited shape, relative to the basis, at value 1, and
    every other key is set to 0 so that the mix shows exactly the edit:
    two edits never add up. ``undo`` puts the keys back as they were."""

    def __init__(self, obj, name: str) -> None:
        self.obj = obj
        keys = obj.data.shape_keys
        self.values: Dict[str, float] = (
            {} if keys is None else {k.name: k.value for k in keys.key_blocks})
        self.active_index = obj.active_shape_key_index
        self.made_basis = keys is None
        if self.made_basis:
            obj.shape_key_add(name="Basis", from_mix=False)
        self.key = obj.shape_key_add(name=name or SHAPE_KEY_NAME, from_mix=True)
        for k in obj.data.shape_keys.key_blocks:
            if k != self.key:
                k.value = 0.0
        self.key.value = 1.0
        obj.active_shape_key_index = len(obj.data.shape_keys.key_blocks) - 1
        n = len(obj.data.vertices)
        start = np.empty(n * 3, dtype=np.float32)
        self.key.data.foreach_get("co", start)
        self.start = start.reshape(n, 3)

    def write(self, positions: np.ndarray) -> None:
        self.key.data.foreach_set("co", positions.reshape(-1))
        self.obj.data.update()

    def zeroed(self) -> List[str]:
        """The keys this edit set to 0 from another value."""
        return [name for name, value in self.values.items() if value != 0.0 and name != "Basis"]

    def undo(self) -> None:
        obj = self.obj
        if self.made_basis:
            obj.shape_key_clear()
        else:
            obj.shape_key_remove(self.key)
            for k in obj.data.shape_keys.key_blocks:
                k.value = self.values[k.name]
            obj.active_shape_key_index = self.active_index
        obj.data.update()


class MeshTarget:
    """An edit kept in the mesh itself (only without shape keys: Blender
    shows the keys' mix, not the mesh, once there are any)."""

    def __init__(self, obj) -> None:
        if obj.data.shape_keys is not None:
            raise ValueError("this mesh has shape keys, so Blender shows their mix and not the "
                             "mesh: keep the edit as a shape key")
        self.obj = obj
        n = len(obj.data.vertices)
        start = np.empty(n * 3, dtype=np.float32)
        obj.data.vertices.foreach_get("co", start)
        self.start = start.reshape(n, 3)

    def write(self, positions: np.ndarray) -> None:
        self.obj.data.vertices.foreach_set("co", positions.reshape(-1))
        self.obj.data.update()

    def undo(self) -> None:
        self.write(self.start)


class DragEdit:
    """One Dualform session on ``obj``'s mesh (object mode), moving the
    handle group ``handle`` (a vertex group name; None: the last handle
    group) while the other handle groups stay put. ``keep``: 'MESH', or
    'SHAPE_KEY' into a new key named ``key_name``."""

    def __init__(self, obj, handle: Optional[str] = None, library: Optional[str] = None,
                 keep: str = "MESH", key_name: str = SHAPE_KEY_NAME) -> None:
        dfm = dualform()
        if library:
            dfm.load_library(library)
        self.obj = obj
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
        self.target = ShapeKeyTarget(obj, key_name) if keep == "SHAPE_KEY" else MeshTarget(obj)
        self.original = self.target.start
        try:
            self.surface = Surface(obj, self.original)
            try:
                groups = [self.surface.surface_vertices(group_vertices(obj, n)) for n in names]
                self.pivot = self.original[groups[self.group_index]].astype(np.float64).mean(axis=0)
                self._roi = self.surface.mesh.roi_from_vertices(roi)
                self.session = dfm.Session(self.surface.mesh, self._roi, groups)
            except Exception:
                self.surface.close()
                raise
        except Exception:
            self.target.undo()
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
        self.target.write(self._buffer)
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
        """For scripts: waits for the newest motion's solve and applies it;
        a solve that fails raises (the mesh keeps the last good frame)."""
        self.session.wait(self.submitted)
        self.apply_latest()

    def finish(self) -> None:
        """Keeps the shown result."""
        self.close()

    def cancel(self) -> None:
        """Puts the mesh and its shape keys back as they were, bit for bit."""
        self.session.cancel()
        self.target.undo()
        self.close()

    def close(self) -> None:
        for handle in (self.session, self._roi):
            handle.close()
        self.surface.close()


def water_fill(obj, first: int, last: int):
    """Water-Filling of ``obj``'s mesh (object-mode data) from ``first`` to
    ``last`` (any seam copies): (every Blender vertex of the ROI, the
    surface vertex count, the diagnosis)."""
    with Surface(obj) as surface, surface.mesh.water_fill(first, last) as roi:
        return surface.copies(roi.vertices()), len(roi), roi.diagnosis


def grow(obj, vertices: np.ndarray, rings: int) -> Tuple[np.ndarray, int]:
    """``vertices`` grown (rings > 0) or shrunk (rings < 0) by whole edge
    rings of the surface: (with every seam copy, how many surface vertices)."""
    with Surface(obj) as surface, surface.mesh.roi_from_vertices(vertices) as roi, \
            roi.grow(rings) as grown:
        return surface.copies(grown.vertices()), len(grown)


def with_copies(obj, vertices: np.ndarray) -> Tuple[np.ndarray, int]:
    """(``vertices`` and every seam copy of them, how many surface vertices)."""
    with Surface(obj) as surface:
        return surface.copies(vertices), len(surface.surface_vertices(vertices))


def diagnosis_text(count: int, copies: int, diagnosis) -> str:
    seams = f" ({copies} with their seam copies)" if copies != count else ""
    text = f"Water-Fill ROI: {count} vertices{seams}, {diagnosis.loops} cut loop(s)"
    if diagnosis.suspect:
        return text + "; SUSPECT: the fill most likely leaked past the intended limb"
    if not diagnosis.bounded_by_last_loop:
        return text + "; the loop through the end vertex does not bound it"
    return text
