"""Meshes (dfm_mesh) and regions of interest (dfm_roi)."""

from __future__ import annotations

import ctypes
import os
from typing import Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _arrays, _native, _skin
from ._handle import Handle
from .context import Context
from .errors import check
from .types import (AnimationInfo, Camera, Hit, JointInfo, LoadReport, MeshInfo, MeshMemory,
                    MeshSummary, MorphTargetInfo, PlyEncoding, SkinInfo, WaterFillDiagnosis,
                    from_struct)

PathLike = Union[str, os.PathLike]


def _out_handle() -> ctypes.c_void_p:
    return ctypes.c_void_p()


class Mesh(Handle):
    """dfm_mesh: a triangle mesh and its bake history. Make one with
    :meth:`from_arrays` or :meth:`load`; close it (or use ``with``) when done.
    Sessions on the mesh keep its C object alive after ``close()``."""

    _kind = "mesh"

    def __init__(self, context: Context, pointer: int) -> None:
        self.context = context
        self._info: Optional[MeshInfo] = None
        super().__init__(pointer, _native.lib().dfm_mesh_destroy, *context.keep_alive)

    # -------------------------------------------------------------- making

    @classmethod
    def from_arrays(cls, context: Context, positions, triangles, *,
                    weld: Optional[float] = None, joints=None, weights=None,
                    inverse_bind_matrices=None) -> "Mesh":
        """Copies a mesh from ``positions`` (float32 or float64, shape (n, 3),
        read in place) and ``triangles`` (uint32 (m, 3); other integer types
        are converted). ``weld`` joins a renderer's seam-split copies of a
        vertex into one surface vertex: 0 for copies at equal positions, a
        positive fraction of the bounding-box diagonal for copies that close;
        None keeps every vertex apart. The arrays' numbering stays the
        caller's (docs/gltf.md). A triangle that repeats a vertex is dropped
        with a load warning (the context's log), as the file loaders drop
        it; ``triangles()`` then lists the kept ones.

        A linear blend skin, all three or none: ``joints`` (n, K) joint
        indices (uint8, uint16 or uint32 read in place; other integers
        converted), ``weights`` (n, K) (float32 or float64; normalised to
        sum 1 by the library) and ``inverse_bind_matrices`` (J, 4, 4), each
        acting on column vectors (M @ [x, y, z, 1]). Posed at joint world
        matrices J_j (:meth:`set_pose_joints`), vertex v shows at
        sum_k w_vk J[j_vk] inverse_bind[j_vk] p_v. Copies are welded only
        where their skins agree. A negative or non-finite weight or weights
        summing to 0 raise :class:`NumericalError`, a joint index of J or
        more :class:`OutOfRangeError`, each naming the vertex and slot; an
        inverse bind matrix that is not invertible :class:`NumericalError`."""
        pos_in, _kept = _arrays.vec3_input(positions, "positions")
        tri = _arrays.index_array(triangles, "triangles", columns=3)
        skin, _skin_kept = _skin.skin_input(pos_in.count, joints, weights, inverse_bind_matrices)
        desc = _native.MeshDesc()
        desc.struct_size = ctypes.sizeof(desc)
        desc.positions = pos_in
        desc.indices = tri.ctypes.data
        desc.triangle_count = tri.shape[0]
        desc.skin = skin
        if weld is not None:
            desc.weld = 1 if weld == 0 else 2
            desc.weld_tolerance = float(weld)
        out = _out_handle()
        check(_native.lib().dfm_mesh_create(context.pointer, ctypes.byref(desc), ctypes.byref(out)))
        return cls(context, out.value)

    @classmethod
    def load(cls, context: Context, path: PathLike) -> "Mesh":
        """Loads an OFF, OBJ, PLY, glTF (.gltf, .glb, ``FILE.glb#mesh=NAME``)
        or FBX (.fbx, binary or ASCII 7.x; docs/fbx.md) file, or
        ``model:NAME`` from the context's models folder."""
        out = _out_handle()
        check(_native.lib().dfm_mesh_load(context.pointer, os.fsencode(path), ctypes.byref(out)))
        return cls(context, out.value)

    @classmethod
    def load_with_report(cls, context: Context, path: PathLike) -> Tuple["Mesh", LoadReport]:
        """:meth:`load`, and what the file held besides the mesh."""
        out = _out_handle()
        report = _native.LoadReport()
        check(_native.lib().dfm_mesh_load_with_report(context.pointer, os.fsencode(path),
                                                      ctypes.byref(report), ctypes.byref(out)))
        return cls(context, out.value), from_struct(LoadReport, report)

    def subdivide(self, steps: int) -> "Mesh":
        """A new mesh: ``steps`` (1-3) rounds of Loop subdivision; coarse
        vertices keep their indices."""
        out = _out_handle()
        steps = _arrays.unsigned(steps, "steps", 0xFFFFFFFF)
        check(_native.lib().dfm_mesh_subdivide(self.pointer, steps, ctypes.byref(out)))
        return Mesh(self.context, out.value)

    def save(self, path: PathLike, *, ply_encoding: Optional[PlyEncoding] = None,
             ply_float: bool = False, obj_normals: bool = False,
             morph_target: Optional[str] = None) -> None:
        """Writes the rest pose to .off, .obj, .ply, .gltf, .glb or, for a
        mesh loaded from binary FBX, back into its .fbx (atomically). PLY is
        binary little-endian with double coordinates unless told otherwise.
        ``morph_target``: for a mesh loaded from glTF or FBX, keep the asset's
        positions and add the edit as a morph target (FBX: blend shape
        channel) of that name."""
        options = _native.SaveOptions()
        options.struct_size = ctypes.sizeof(options)
        options.ply_encoding = int(ply_encoding or 0)
        options.ply_float = ply_float
        options.obj_normals = obj_normals
        name = morph_target.encode() if morph_target else None
        options.morph_target_name = name
        check(_native.lib().dfm_mesh_save_with_options(self.pointer, os.fsencode(path),
                                                       ctypes.byref(options)))

    # -------------------------------------------------------------- reading

    @property
    def info(self) -> MeshInfo:
        """The mesh's figures. The first read computes them (the topology's
        components and boundary: milliseconds on a large mesh); later reads
        return that result until this package changes the rest pose
        (``set_positions``, a session's ``bake``, ``undo_bake``,
        ``redo_bake``, ``set_pose``, ``set_pose_joints``, ``clear_pose``)."""
        pointer = self.pointer  # a closed mesh raises, kept figures or not
        info = self._info
        if info is None:
            out = _native.MeshInfo()
            check(_native.lib().dfm_mesh_get_info(pointer, ctypes.byref(out)))
            info = self._info = from_struct(MeshInfo, out)
        return info

    def forget_info(self) -> None:
        """Drops the kept :attr:`info`: the next read asks the library again."""
        self._info = None

    @property
    def vertex_count(self) -> int:
        return self.info.vertex_count

    @property
    def memory(self) -> MeshMemory:
        out = _native.MeshMemory()
        check(_native.lib().dfm_mesh_get_memory(self.pointer, ctypes.byref(out)))
        return from_struct(MeshMemory, out)

    @property
    def summary(self) -> MeshSummary:
        out = _native.MeshSummary()
        check(_native.lib().dfm_mesh_get_summary(self.pointer, ctypes.byref(out)))
        return from_struct(MeshSummary, out)

    def positions(self, dtype=np.float64, out: Optional[np.ndarray] = None) -> np.ndarray:
        """The rest positions, (n, 3), written straight into ``out`` (or a
        new array of ``dtype``); posed, when a pose is set."""
        n = self.vertex_count
        array = _arrays.new_vec3(n, dtype, out)
        check(_native.lib().dfm_mesh_read_positions(self.pointer,
                                                    ctypes.byref(_arrays.vec3_output(array))))
        return array

    def normals(self, dtype=np.float64, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Area-weighted unit vertex normals of the rest pose, (n, 3)."""
        array = _arrays.new_vec3(self.vertex_count, dtype, out)
        check(_native.lib().dfm_mesh_read_normals(self.pointer,
                                                  ctypes.byref(_arrays.vec3_output(array))))
        return array

    def triangles(self) -> np.ndarray:
        """The triangles' vertex indices, uint32 (m, 3)."""
        m = self.info.triangle_count
        array = np.empty((m, 3), dtype=np.uint32)
        check(_native.lib().dfm_mesh_read_indices(self.pointer, _arrays.uint32_pointer(array),
                                                  array.size))
        return array

    def surface_map(self) -> np.ndarray:
        """For each vertex, the lowest index of its surface vertex (the
        index the library returns for every seam-split copy of it), uint32."""
        array = np.empty(self.vertex_count, dtype=np.uint32)
        check(_native.lib().dfm_mesh_read_surface_map(self.pointer, _arrays.uint32_pointer(array),
                                                      array.size))
        return array

    # -------------------------------------------------------------- history

    def set_positions(self, positions) -> None:
        """Replaces the rest pose (an undoable step); earlier sessions can no
        longer bake."""
        v, _kept = _arrays.vec3_input(positions)
        self.forget_info()
        check(_native.lib().dfm_mesh_set_positions(self.pointer, ctypes.byref(v)))

    def undo_bake(self) -> None:
        self.forget_info()
        check(_native.lib().dfm_mesh_undo_bake(self.pointer))

    def redo_bake(self) -> None:
        self.forget_info()
        check(_native.lib().dfm_mesh_redo_bake(self.pointer))

    # -------------------------------------------------------------- skin and pose

    def skin_info(self) -> SkinInfo:
        """What poses the mesh, the pose set, and what the last bake in a
        pose found of its corrective (all zeros, ``pose_animation`` -1,
        without a skin or morph targets)."""
        out = _native.SkinInfo()
        check(_native.lib().dfm_mesh_get_skin_info(self.pointer, ctypes.byref(out)))
        return from_struct(SkinInfo, out)

    def joints(self) -> List[JointInfo]:
        """The skin's joints in order: their node names and parents."""
        out = []
        for j in range(self.skin_info().joint_count):
            c = _native.JointInfo()
            check(_native.lib().dfm_mesh_get_joint_info(self.pointer, j, ctypes.byref(c)))
            out.append(JointInfo(c.name.decode(), None if c.parent == 0xFFFFFFFF else c.parent))
        return out

    def animations(self) -> List[AnimationInfo]:
        """The file's animations in order (glTF)."""
        out = []
        for a in range(self.skin_info().animation_count):
            c = _native.AnimationInfo()
            check(_native.lib().dfm_mesh_get_animation_info(self.pointer, a, ctypes.byref(c)))
            out.append(AnimationInfo(c.name.decode(), c.start, c.end, c.translation_channels,
                                     c.rotation_channels, c.scale_channels, c.weight_channels))
        return out

    def morph_targets(self) -> List[MorphTargetInfo]:
        """The loaded meshes' morph targets in order, with their default weights."""
        out = []
        for t in range(self.skin_info().morph_target_count):
            c = _native.MorphTargetInfo()
            check(_native.lib().dfm_mesh_get_morph_target_info(self.pointer, t,
                                                               ctypes.byref(c)))
            out.append(MorphTargetInfo(c.name.decode(), c.default_weight, c.vertex_count))
        return out

    def find_animation(self, name: str) -> int:
        """The index of the first animation called ``name``; NotFoundError
        (naming the animations there are) when none is."""
        out = ctypes.c_uint32()
        check(_native.lib().dfm_mesh_find_animation(self.pointer, name.encode(),
                                                    ctypes.byref(out)))
        return out.value

    def set_pose(self, animation: Union[str, int], time: float) -> None:
        """Poses the mesh at ``animation`` (a name or an index) at ``time``
        seconds, clamped to the animation's first and last key. From then
        on everything that reads or edits the rest pose sees it posed
        (:meth:`positions`, :attr:`info`, picks, ROIs, sessions), and a bake
        keeps the edit as its exact bind-space corrective. NotFoundError for
        a name the file does not have, OutOfRangeError for an index past the
        last, NumericalError for a time that is not finite, UnsupportedError
        for a mesh without a skin or morph targets. Earlier sessions can no
        longer bake."""
        index = (self.find_animation(animation) if isinstance(animation, str)
                 else _arrays.unsigned(animation, "animation", 0xFFFFFFFF))
        self.forget_info()
        check(_native.lib().dfm_mesh_set_pose_animation(self.pointer, index, float(time)))

    def set_pose_joints(self, joint_matrices, morph_weights=None) -> None:
        """Poses the mesh from joint world matrices, (J, 4, 4), each acting
        on column vectors (M @ [x, y, z, 1]; the library multiplies it by
        its joint's inverse bind matrix), and ``morph_weights`` (one per
        morph target; None: their defaults). A count that does not match
        the skin's is InvalidArgumentError; a matrix or weight that is not
        finite, or a matrix whose last row is not 0 0 0 1, NumericalError
        naming it; nothing changes on an error."""
        m = _skin.column_major(joint_matrices, "joint_matrices")
        w = None
        if morph_weights is not None:
            w = np.ascontiguousarray(morph_weights, dtype=np.float64)
            if w.ndim != 1:
                raise ValueError(f"morph_weights: expected a 1-D array, found shape {w.shape}")
        self.forget_info()
        check(_native.lib().dfm_mesh_set_pose_joints(
            self.pointer, _skin.double_pointer(m), m.shape[0], _skin.double_pointer(w),
            0 if w is None else w.size))

    def clear_pose(self) -> None:
        """Back to the bind space: the rest pose shows unposed again."""
        self.forget_info()
        check(_native.lib().dfm_mesh_clear_pose(self.pointer))

    def joint_matrices(self) -> np.ndarray:
        """The pose's joint world matrices, (J, 4, 4) acting on column
        vectors: those of the pose set, or of the file's nodes at rest."""
        values = np.empty(16 * self.skin_info().joint_count, dtype=np.float64)
        check(_native.lib().dfm_mesh_read_joint_matrices(self.pointer,
                                                         _skin.double_pointer(values),
                                                         values.size))
        return _skin.from_column_major(values)

    def bind_positions(self, dtype=np.float64, out: Optional[np.ndarray] = None) -> np.ndarray:
        """The bind-space rest positions after the bakes, (n, 3): on a posed
        mesh what a save writes (minus the positions as created or loaded:
        the corrective); :meth:`positions` on a mesh that is not posed."""
        array = _arrays.new_vec3(self.vertex_count, dtype, out)
        check(_native.lib().dfm_mesh_read_bind_positions(
            self.pointer, ctypes.byref(_arrays.vec3_output(array))))
        return array

    # -------------------------------------------------------------- picking

    def pick(self, camera: Camera, x: float, y: float) -> Optional[Hit]:
        """What pixel (x, y) of ``camera`` sees on the rest pose; None on a miss."""
        out = _native.Hit()
        c = camera.to_c()
        check(_native.lib().dfm_mesh_pick(self.pointer, ctypes.byref(c), x, y, ctypes.byref(out)))
        return _hit(out)

    def pick_ray(self, origin: Sequence[float], direction: Sequence[float]) -> Optional[Hit]:
        """The first hit along a ray; None on a miss."""
        o = (ctypes.c_double * 3)(*origin)
        d = (ctypes.c_double * 3)(*direction)
        out = _native.Hit()
        check(_native.lib().dfm_mesh_pick_ray(self.pointer, o, d, ctypes.byref(out)))
        return _hit(out)

    # -------------------------------------------------------------- ROIs

    def water_fill(self, first: int, last: int) -> "Roi":
        """The paper's Water-Filling from vertex ``first`` up to the cut
        through ``last``; the ROI's ``diagnosis`` says whether it is suspect."""
        out = _out_handle()
        d = _native.WaterFillDiagnosis()
        check(_native.lib().dfm_roi_water_fill(self.pointer, _arrays.vertex_index(first, "first"),
                                               _arrays.vertex_index(last, "last"),
                                               ctypes.byref(out), ctypes.byref(d)))
        return Roi(self, out.value, from_struct(WaterFillDiagnosis, d))

    def water_fill_clicks(self, camera: Camera, first_pixel: Sequence[float],
                          last_pixel: Sequence[float]) -> "Roi":
        """Water-Filling from two pixels picked through ``camera``."""
        out = _out_handle()
        d = _native.WaterFillDiagnosis()
        c = camera.to_c()
        a = (ctypes.c_double * 2)(*first_pixel)
        b = (ctypes.c_double * 2)(*last_pixel)
        check(_native.lib().dfm_roi_water_fill_clicks(self.pointer, ctypes.byref(c), a, b,
                                                      ctypes.byref(out), ctypes.byref(d)))
        return Roi(self, out.value, from_struct(WaterFillDiagnosis, d))

    def roi_from_vertices(self, vertices: Iterable[int]) -> "Roi":
        """An explicit list (duplicates merged)."""
        v = _arrays.index_array(vertices if isinstance(vertices, np.ndarray) else list(vertices),
                                "vertices")
        out = _out_handle()
        check(_native.lib().dfm_roi_from_vertices(self.pointer, _arrays.uint32_pointer(v), v.size,
                                                  ctypes.byref(out)))
        return Roi(self, out.value)

    def roi_ball(self, center: int, radius: float) -> "Roi":
        """Vertices reachable from ``center`` inside the ball of ``radius`` x
        diagonal."""
        out = _out_handle()
        check(_native.lib().dfm_roi_ball(self.pointer, _arrays.vertex_index(center, "center"),
                                         radius, ctypes.byref(out)))
        return Roi(self, out.value)

    def roi_all(self) -> "Roi":
        out = _out_handle()
        check(_native.lib().dfm_roi_all(self.pointer, ctypes.byref(out)))
        return Roi(self, out.value)


def _hit(h: _native.Hit) -> Optional[Hit]:
    if not h.hit:
        return None
    return Hit(h.face, h.vertex, tuple(h.point), h.distance, tuple(h.barycentric))


class Roi(Handle):
    """dfm_roi: an immutable set of vertices of one mesh. ``diagnosis`` is
    the Water-Filling's (None for the other kinds)."""

    _kind = "ROI"

    def __init__(self, mesh: Mesh, pointer: int,
                 diagnosis: Optional[WaterFillDiagnosis] = None) -> None:
        self.mesh = mesh
        self.diagnosis = diagnosis
        super().__init__(pointer, _native.lib().dfm_roi_destroy, *mesh.context.keep_alive)

    def __len__(self) -> int:
        out = ctypes.c_size_t()
        check(_native.lib().dfm_roi_count(self.pointer, ctypes.byref(out)))
        return out.value

    def vertices(self) -> np.ndarray:
        """The vertex indices, ascending, uint32."""
        array = np.empty(len(self), dtype=np.uint32)
        check(_native.lib().dfm_roi_read(self.pointer, _arrays.uint32_pointer(array), array.size))
        return array

    def _derived(self, call, *args) -> "Roi":
        out = _out_handle()
        check(call(*args, ctypes.byref(out)))
        return Roi(self.mesh, out.value)

    def grow(self, rings: int) -> "Roi":
        """Grown (rings > 0) or shrunk (rings < 0) by whole edge rings."""
        return self._derived(_native.lib().dfm_roi_grow, self.pointer, rings)

    def union(self, other: "Roi") -> "Roi":
        return self._derived(_native.lib().dfm_roi_union, self.pointer, other.pointer)

    def difference(self, other: "Roi") -> "Roi":
        return self._derived(_native.lib().dfm_roi_difference, self.pointer, other.pointer)

    def boundary(self) -> "Roi":
        """The vertices with a neighbour outside: what stays fixed."""
        return self._derived(_native.lib().dfm_roi_boundary, self.pointer)
