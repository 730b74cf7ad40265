"""Blender meshes as Dualform edits: the part every operator shares.

Real assets come split: a glTF import, UV seams and hard edges give one
position several Blender vertices. Every Dualform mesh here is made with
the library's exact weld (``Mesh.from_arrays(..., weld=0)``), so Water-
Filling and the solve see one surface, and the library's surface map takes
its answers back to every copy (docs/gltf.md, "The numbering rule").

A mesh object posed by an Armature modifier is edited as Blender shows it
at the current frame: the Dualform mesh is its shape-key mix with the
modifier's skin (skin.py), posed at the bones' current matrices, so that
Water-Filling, handles and the solve all work on the posed surface. What
is kept goes back into the armature's input, in rest space: the library
bakes the posed result into its exact bind-space corrective
(``Mesh.bind_positions``), which the armature, playing it at this pose,
shows as the edit.

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

from .skin import ArmatureSkin

ROI_GROUP = "Dualform ROI"
HANDLE_PREFIX = "Dualform Handle"
SHAPE_KEY_NAME = "Dualform Edit"
CORRECTIVE_NAME = "Dualform Corrective"


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


def welded_mesh(context, positions: np.ndarray, triangles: np.ndarray,
                skin: Optional[ArmatureSkin] = None):
    """A Dualform mesh of Blender's arrays, split copies at equal positions
    welded into one surface vertex; Blender's numbering stays. With a skin,
    posed at its joints' matrices, as Blender shows it."""
    dfm = dualform()
    if skin is None:
        return dfm.Mesh.from_arrays(context, positions, triangles, weld=0)
    mesh = dfm.Mesh.from_arrays(context, positions, triangles, weld=0, joints=skin.joints,
                                weights=skin.weights, inverse_bind_matrices=skin.inverse_bind)
    try:
        mesh.set_pose_joints(skin.joint_world)
    except Exception:
        mesh.close()
        raise
    return mesh


def posing_skin(obj) -> Optional[ArmatureSkin]:
    """The skin of the Armature modifier that poses ``obj`` at the current
    frame, or None; ValueError for a setup Dualform cannot pose exactly."""
    import bpy

    return ArmatureSkin.of(obj, bpy.context.evaluated_depsgraph_get())


def shape_key_mix(obj) -> np.ndarray:
    """What Blender hands the modifiers, float32 (n, 3): the shape keys'
    current mix (as New Shape from Mix takes it), or the mesh's vertices."""
    if obj.data.shape_keys is None:
        return mesh_arrays(obj.data)[0]
    active = obj.active_shape_key_index
    key = obj.shape_key_add(name="Dualform Mix", from_mix=True)
    mix = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    key.data.foreach_get("co", mix)
    obj.shape_key_remove(key)
    obj.active_shape_key_index = active
    return mix.reshape(-1, 3)


class Surface:
    """An object-mode mesh as Dualform sees it: the welded mesh and each
    Blender vertex's surface vertex (its lowest copy). ``positions`` are
    the shape as Blender stores it (the mesh's vertices unless given);
    with a ``skin`` the mesh is posed, and ``shown`` (float64) is what the
    armature makes of them."""

    def __init__(self, obj, positions: Optional[np.ndarray] = None,
                 skin: Optional[ArmatureSkin] = None) -> None:
        dfm = dualform()
        rest, self.triangles = mesh_arrays(obj.data)
        self.positions = rest if positions is None else positions
        self.skin = skin
        self.context = dfm.Context()
        try:
            self.mesh = welded_mesh(self.context, self.positions, self.triangles, skin)
            self.lowest = self.mesh.surface_map()
            self.shown = (self.positions.astype(np.float64) if skin is None
                          else self.mesh.positions())
        except Exception:
            self.context.close()
            raise

    @classmethod
    def as_shown(cls, obj) -> "Surface":
        """``obj``'s mesh as the viewport shows it: posed by its Armature
        modifier, from its shape-key mix, where one poses it; else its
        vertices."""
        skin = posing_skin(obj)
        return cls(obj) if skin is None else cls(obj, shape_key_mix(obj), skin)

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
    two edits never add up. ``undo`` puts the keys back as they were.

    ``additive``: a corrective key instead, holding only the edit (the
    basis plus the edited shape minus the mix it started from), at value 1
    beside the other keys, which keep their values: the mix is the shape
    shown plus the edit, and the key can be driven by the pose."""

    def __init__(self, obj, name: str, additive: bool = False) -> None:
        self.obj = obj
        keys = obj.data.shape_keys
        if additive and keys is not None and not keys.use_relative:
            raise ValueError(f"'{obj.name}' has absolute shape keys (Relative is off): a "
                             "corrective key adds to relative ones")
        self.values: Dict[str, float] = (
            {} if keys is None else {k.name: k.value for k in keys.key_blocks})
        self.active_index = obj.active_shape_key_index
        self.made_basis = keys is None
        if self.made_basis:
            obj.shape_key_add(name="Basis", from_mix=False)
        default = CORRECTIVE_NAME if additive else SHAPE_KEY_NAME
        self.key = obj.shape_key_add(name=name or default, from_mix=True)
        n = len(obj.data.vertices)
        start = np.empty(n * 3, dtype=np.float32)
        self.key.data.foreach_get("co", start)
        self.start = start.reshape(n, 3)
        self.additive = additive
        if additive:
            reference = obj.data.shape_keys.reference_key
            basis = np.empty(n * 3, dtype=np.float32)
            reference.data.foreach_get("co", basis)
            self.key.relative_key = reference
            self.offset = basis.reshape(n, 3).astype(np.float64) - self.start
            self.write(self.start)  # the key adds nothing yet
        else:
            for k in obj.data.shape_keys.key_blocks:
                if k != self.key:
                    k.value = 0.0
        self.key.value = 1.0
        obj.active_shape_key_index = len(obj.data.shape_keys.key_blocks) - 1

    def write(self, positions: np.ndarray) -> None:
        """Makes the mix ``positions`` (float32 (n, 3))."""
        if self.additive:
            positions = (positions + self.offset).astype(np.float32)
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


class PosedPreview:
    """A posed session's frames shown while dragging: Blender shows the
    armature's pose of the keys' mix (or the mesh), so each frame goes back
    to rest space first, vertex by vertex of the ROI, by the inverse of
    L_v (pseudo-inverse where L_v is singular). What is kept is the
    library's bake, not this: the same corrective to rounding, damped where
    L_v is ill-conditioned (``DragEdit.finish``)."""

    def __init__(self, skin: ArmatureSkin, vertices: np.ndarray, bind: np.ndarray,
                 shown: np.ndarray) -> None:
        self.vertices = vertices
        self.inverse = np.linalg.pinv(skin.blended_linear(vertices))
        self.start = bind[vertices].astype(np.float64)
        self.shown = shown[vertices]
        self.out = bind.copy()

    def bind_of(self, frame: np.ndarray) -> np.ndarray:
        """The rest-space shape whose pose is ``frame`` (float32 (n, 3))."""
        moved = frame[self.vertices] - self.shown
        self.out[self.vertices] = self.start + np.einsum("vij,vj->vi", self.inverse, moved)
        return self.out


class DragEdit:
    """One Dualform session on ``obj``'s mesh (object mode), moving the
    handle group ``handle`` (a vertex group name; None: the last handle
    group) while the other handle groups stay put. ``keep``: 'MESH',
    'SHAPE_KEY' into a new key named ``key_name``, or 'CORRECTIVE' (a
    mesh an Armature modifier poses) into a new corrective key of that
    name, driven by the angle of the bone nearest the ROI when ``driver``.

    On a posed mesh the session edits the posed surface (``pivot`` and the
    motions are in the object's space, as shown); frames are shown through
    a :class:`PosedPreview`, and ``finish`` bakes the newest into the exact
    rest-space corrective."""

    def __init__(self, obj, handle: Optional[str] = None, library: Optional[str] = None,
                 keep: str = "MESH", key_name: str = SHAPE_KEY_NAME,
                 driver: bool = False) -> None:
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
        skin = posing_skin(obj)
        if keep == "CORRECTIVE" and skin is None:
            raise ValueError(f"no Armature modifier poses '{obj.name}': a corrective key is for a "
                             "posed mesh; keep a Shape Key")
        if keep == "MESH":
            self.target = MeshTarget(obj)
        else:
            self.target = ShapeKeyTarget(obj, key_name, additive=keep == "CORRECTIVE")
        self.original = self.target.start
        self.driver = driver and keep == "CORRECTIVE"
        try:
            self.surface = Surface(obj, self.original, skin)
            try:
                groups = [self.surface.surface_vertices(group_vertices(obj, n)) for n in names]
                shown = self.surface.shown
                self.pivot = shown[groups[self.group_index]].mean(axis=0)
                self._roi = self.surface.mesh.roi_from_vertices(roi)
                self.session = dfm.Session(self.surface.mesh, self._roi, groups)
                self.roi_vertices = self.surface.copies(roi)
                self.preview = (None if skin is None else
                                PosedPreview(skin, self.roi_vertices, self.original, shown))
            except Exception:
                self.surface.close()
                raise
        except Exception:
            self.target.undo()
            raise
        self._buffer = self.original.copy() if skin is None else shown.copy()
        self.submitted = 0
        self.applied = 0
        self.last_info = None
        self.corrective = None  # the bake's SkinInfo, once kept on a posed mesh
        self.driven_by: List[str] = []  # [bone, degrees] of the corrective's driver

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
        _, info = self.session.read_positions(self._buffer.dtype, out=self._buffer)
        self.target.write(self._buffer if self.preview is None
                          else self.preview.bind_of(self._buffer))
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
        """Keeps the shown result: on a posed mesh, the newest frame baked
        into its exact rest-space corrective (and the corrective key's
        driver added, when asked)."""
        try:
            if self.preview is not None and self.applied:
                self.session.bake(self.applied)
                mesh = self.surface.mesh
                self.target.write(mesh.bind_positions(np.float32))
                self.corrective = mesh.skin_info()
                if self.driver:
                    shown = self.surface.shown[self.roi_vertices]
                    self.driven_by = self.surface.skin.drive_by_angle(self.target.key, shown)
        finally:
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
    with Surface.as_shown(obj) as surface, surface.mesh.water_fill(first, last) as roi:
        return surface.copies(roi.vertices()), len(roi), roi.diagnosis


def grow(obj, vertices: np.ndarray, rings: int) -> Tuple[np.ndarray, int]:
    """``vertices`` grown (rings > 0) or shrunk (rings < 0) by whole edge
    rings of the surface: (with every seam copy, how many surface vertices)."""
    with Surface.as_shown(obj) as surface, surface.mesh.roi_from_vertices(vertices) as roi, \
            roi.grow(rings) as grown:
        return surface.copies(grown.vertices()), len(grown)


def with_copies(obj, vertices: np.ndarray) -> Tuple[np.ndarray, int]:
    """(``vertices`` and every seam copy of them, how many surface vertices)."""
    with Surface.as_shown(obj) as surface:
        return surface.copies(vertices), len(surface.surface_vertices(vertices))


def diagnosis_text(count: int, copies: int, diagnosis) -> str:
    seams = f" ({copies} with their seam copies)" if copies != count else ""
    text = f"Water-Fill ROI: {count} vertices{seams}, {diagnosis.loops} cut loop(s)"
    if diagnosis.suspect:
        return text + "; SUSPECT: the fill most likely leaked past the intended limb"
    if not diagnosis.bounded_by_last_loop:
        return text + "; the loop through the end vertex does not bound it"
    return text
