"""The C API as ctypes declarations: the structs of ``dualform.h`` and the
prototypes of its functions. Everything else in the package goes through
:func:`lib`.

ctypes releases the GIL around every call into a ``CDLL``, so a thread
waiting in ``dfm_session_wait`` lets the others run; callbacks from the
library's threads (allocator, log, frame) take the GIL back while they run.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import threading
from ctypes import (
    CFUNCTYPE,
    POINTER,
    Structure,
    c_bool,
    c_char_p,
    c_double,
    c_float,
    c_int,
    c_int32,
    c_int64,
    c_size_t,
    c_uint16,
    c_uint32,
    c_uint64,
    c_void_p,
)
from pathlib import Path
from typing import Optional

#: The header version this package is written against (DFM_VERSION of 0.2.0).
HEADER_VERSION = 200

#: The environment variable that names the library file, read first.
LIBRARY_VARIABLE = "DUALFORM_LIBRARY"

_SONAME = "libdualform.so.0.2"


class Camera(Structure):
    _fields_ = [
        ("eye", c_double * 3),
        ("target", c_double * 3),
        ("up", c_double * 3),
        ("fov_y_degrees", c_double),
        ("width", c_uint32),
        ("height", c_uint32),
    ]


class Vec3Input(Structure):
    _fields_ = [("data", c_void_p), ("count", c_size_t), ("stride", c_size_t), ("type", c_int)]


class Vec3Output(Structure):
    _fields_ = [("data", c_void_p), ("count", c_size_t), ("stride", c_size_t), ("type", c_int)]


ALLOC_FN = CFUNCTYPE(c_void_p, c_void_p, c_size_t, c_size_t)
FREE_FN = CFUNCTYPE(None, c_void_p, c_void_p, c_size_t)
LOG_FN = CFUNCTYPE(None, c_void_p, c_int, c_int, c_char_p)
ENQUEUE_FN = CFUNCTYPE(None, c_void_p, c_void_p)


class Allocator(Structure):
    _fields_ = [("alloc", ALLOC_FN), ("free", FREE_FN), ("user", c_void_p)]


class JobSystem(Structure):
    _fields_ = [("enqueue", ENQUEUE_FN), ("user", c_void_p)]


class ContextDesc(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("header_version", c_uint32),
        ("allocator", Allocator),
        ("log", LOG_FN),
        ("log_user", c_void_p),
        ("worker_count", c_uint32),
        ("pick_thread_count", c_uint32),
        ("models_directory", c_char_p),
        ("reference_folder", c_char_p),
        ("work_mode", c_int),
        ("job_system", JobSystem),
    ]


class SkinInput(Structure):
    _fields_ = [
        ("joint_count", c_uint32),
        ("inverse_bind_matrices", POINTER(c_double)),
        ("influence_count", c_uint32),
        ("joints", c_void_p),
        ("joint_stride", c_size_t),
        ("joint_type", c_int),
        ("weights", c_void_p),
        ("weight_stride", c_size_t),
        ("weight_type", c_int),
    ]


class MeshDesc(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("positions", Vec3Input),
        ("indices", c_void_p),
        ("triangle_count", c_size_t),
        ("index_stride", c_size_t),
        ("weld", c_int),
        ("weld_tolerance", c_double),
        ("skin", SkinInput),
    ]


class MeshInfo(Structure):
    _fields_ = [
        ("vertex_count", c_size_t),
        ("triangle_count", c_size_t),
        ("bounds_min", c_double * 3),
        ("bounds_max", c_double * 3),
        ("diagonal", c_double),
        ("components", c_size_t),
        ("boundary_edges", c_size_t),
        ("bake_count", c_size_t),
        ("redo_count", c_size_t),
        ("surface_vertex_count", c_size_t),
    ]


class MeshMemory(Structure):
    _fields_ = [
        (name, c_size_t)
        for name in ("rest_pose", "adjacency", "model", "history", "pick_scene", "total")
    ]


class SkinInfo(Structure):
    _fields_ = [
        ("joint_count", c_uint32),
        ("max_influences", c_uint32),
        ("skinned_vertex_count", c_size_t),
        ("animation_count", c_uint32),
        ("morph_target_count", c_uint32),
        ("posed", c_bool),
        ("pose_animation", c_int32),
        ("pose_time", c_double),
        ("corrective_vertex_count", c_size_t),
        ("corrective_worst_condition", c_double),
        ("corrective_damped_count", c_size_t),
    ]


class JointInfo(Structure):
    _fields_ = [("name", c_char_p), ("parent", c_uint32)]


class AnimationInfo(Structure):
    _fields_ = [
        ("name", c_char_p),
        ("start", c_double),
        ("end", c_double),
        ("translation_channels", c_uint32),
        ("rotation_channels", c_uint32),
        ("scale_channels", c_uint32),
        ("weight_channels", c_uint32),
    ]


class MorphTargetInfo(Structure):
    _fields_ = [("name", c_char_p), ("default_weight", c_double), ("vertex_count", c_size_t)]


class Hit(Structure):
    _fields_ = [
        ("hit", c_bool),
        ("face", c_uint32),
        ("vertex", c_uint32),
        ("point", c_double * 3),
        ("distance", c_double),
        ("barycentric", c_double * 3),
    ]


class WaterFillDiagnosis(Structure):
    _fields_ = [("loops", c_size_t), ("bounded_by_last_loop", c_bool), ("suspect", c_bool)]


class SolverSettings(Structure):
    _fields_ = [
        ("tolerance", c_double),
        ("max_iterations", c_uint32),
        ("handle_weight", c_double),
        ("hard_handles", c_bool),
        ("method", c_int),
        ("preconditioner", c_int),
        ("disable_prediction", c_bool),
        ("reserved", c_uint32 * 5),
    ]


class HandleGroup(Structure):
    _fields_ = [("vertices", c_void_p), ("count", c_size_t)]


class FrameInfo(Structure):
    _fields_ = [
        ("generation", c_uint64),
        ("status", c_int),
        ("converged", c_bool),
        ("partial", c_bool),
        ("iterations", c_uint32),
        ("last_update", c_double),
        ("solve_ms", c_double),
        ("checksum", c_uint64),
        ("preparing", c_bool),
    ]


FRAME_FN = CFUNCTYPE(None, c_void_p, c_void_p, POINTER(FrameInfo))


class SessionDesc(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("roi", c_void_p),
        ("groups", POINTER(HandleGroup)),
        ("group_count", c_size_t),
        ("solver", SolverSettings),
        ("on_frame", FRAME_FN),
        ("on_frame_user", c_void_p),
    ]


class VertexOutput(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("data", c_void_p),
        ("count", c_size_t),
        ("stride", c_size_t),
        ("position_offset", c_size_t),
        ("normal_offset", c_size_t),
        ("write_positions", c_bool),
        ("write_normals", c_bool),
        ("changed_only", c_bool),
    ]


class FrameView(Structure):
    _fields_ = [
        ("roi_positions", POINTER(c_float)),
        ("roi_positions_f64", POINTER(c_double)),
        ("roi_vertices", POINTER(c_uint32)),
        ("roi_count", c_size_t),
        ("normals", POINTER(c_float)),
        ("normal_vertices", POINTER(c_uint32)),
        ("normal_count", c_size_t),
    ]


class SessionMemory(Structure):
    _fields_ = [
        (name, c_size_t)
        for name in ("factor", "normal_matrix", "iteration", "frames", "staging", "total")
    ]


class Quality(Structure):
    _fields_ = [
        ("max_handle_error", c_double),
        ("mean_abs_log_edge", c_double),
        ("max_abs_log_edge", c_double),
        ("mean_normal_change_deg", c_double),
        ("max_fixed_move", c_double),
        ("dual_magnitude_error", c_double),
        ("flipped_faces", c_size_t),
        ("creased_edges", c_size_t),
    ]


class SolveReport(Structure):
    _fields_ = [
        ("unknowns", c_size_t),
        ("rows", c_size_t),
        ("normal_nonzeros", c_size_t),
        ("setup_ms", c_double),
        ("krylov_iterations", c_size_t),
        ("linear_residual", c_double),
        ("linear_converged", c_bool),
    ]


class LoadReport(Structure):
    _fields_ = [
        ("polygons", c_size_t),
        ("triangulated_polygons", c_size_t),
        ("dropped_faces", c_size_t),
    ]


class MeshSummary(Structure):
    _fields_ = [
        (name, c_size_t)
        for name in (
            "edges",
            "boundary_edges",
            "non_manifold_edges",
            "inconsistent_edges",
            "components",
            "isolated_vertices",
            "degenerate_triangles",
        )
    ] + [("closed", c_bool)]


class SaveOptions(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("ply_encoding", c_int),
        ("ply_float", c_bool),
        ("obj_normals", c_bool),
        ("morph_target_name", c_char_p),
    ]


_p = c_void_p
_R = c_int  # dfm_result
_PROTOTYPES = {
    "dfm_result_name": (c_char_p, [c_int]),
    "dfm_last_error_message": (c_char_p, []),
    "dfm_last_error_code": (_R, []),
    "dfm_version": (c_uint32, []),
    "dfm_version_compatible": (c_bool, [c_uint32]),
    "dfm_context_create": (_R, [POINTER(ContextDesc), POINTER(_p)]),
    "dfm_context_destroy": (None, [_p]),
    "dfm_context_step": (_R, [_p, c_uint64, POINTER(c_bool)]),
    "dfm_job_run": (None, [_p]),
    "dfm_mesh_create": (_R, [_p, POINTER(MeshDesc), POINTER(_p)]),
    "dfm_mesh_load": (_R, [_p, c_char_p, POINTER(_p)]),
    "dfm_mesh_load_with_report": (_R, [_p, c_char_p, POINTER(LoadReport), POINTER(_p)]),
    "dfm_mesh_save": (_R, [_p, c_char_p]),
    "dfm_mesh_save_with_options": (_R, [_p, c_char_p, POINTER(SaveOptions)]),
    "dfm_mesh_destroy": (None, [_p]),
    "dfm_mesh_get_info": (_R, [_p, POINTER(MeshInfo)]),
    "dfm_mesh_get_memory": (_R, [_p, POINTER(MeshMemory)]),
    "dfm_mesh_get_summary": (_R, [_p, POINTER(MeshSummary)]),
    "dfm_mesh_read_positions": (_R, [_p, POINTER(Vec3Output)]),
    "dfm_mesh_read_indices": (_R, [_p, POINTER(c_uint32), c_size_t]),
    "dfm_mesh_read_indices16": (_R, [_p, POINTER(c_uint16), c_size_t]),
    "dfm_mesh_read_surface_map": (_R, [_p, POINTER(c_uint32), c_size_t]),
    "dfm_mesh_read_normals": (_R, [_p, POINTER(Vec3Output)]),
    "dfm_mesh_set_positions": (_R, [_p, POINTER(Vec3Input)]),
    "dfm_mesh_undo_bake": (_R, [_p]),
    "dfm_mesh_redo_bake": (_R, [_p]),
    "dfm_mesh_subdivide": (_R, [_p, c_uint32, POINTER(_p)]),
    "dfm_mesh_get_skin_info": (_R, [_p, POINTER(SkinInfo)]),
    "dfm_mesh_get_joint_info": (_R, [_p, c_uint32, POINTER(JointInfo)]),
    "dfm_mesh_get_animation_info": (_R, [_p, c_uint32, POINTER(AnimationInfo)]),
    "dfm_mesh_find_animation": (_R, [_p, c_char_p, POINTER(c_uint32)]),
    "dfm_mesh_get_morph_target_info": (_R, [_p, c_uint32, POINTER(MorphTargetInfo)]),
    "dfm_mesh_set_pose_animation": (_R, [_p, c_uint32, c_double]),
    "dfm_mesh_set_pose_joints": (_R, [_p, POINTER(c_double), c_size_t, POINTER(c_double),
                                      c_size_t]),
    "dfm_mesh_clear_pose": (_R, [_p]),
    "dfm_mesh_read_joint_matrices": (_R, [_p, POINTER(c_double), c_size_t]),
    "dfm_mesh_read_bind_positions": (_R, [_p, POINTER(Vec3Output)]),
    "dfm_mesh_pick": (_R, [_p, POINTER(Camera), c_double, c_double, POINTER(Hit)]),
    "dfm_mesh_pick_ray": (_R, [_p, POINTER(c_double), POINTER(c_double), POINTER(Hit)]),
    "dfm_roi_water_fill": (_R, [_p, c_uint32, c_uint32, POINTER(_p), POINTER(WaterFillDiagnosis)]),
    "dfm_roi_water_fill_clicks": (
        _R,
        [_p, POINTER(Camera), POINTER(c_double), POINTER(c_double), POINTER(_p),
         POINTER(WaterFillDiagnosis)],
    ),
    "dfm_roi_from_vertices": (_R, [_p, POINTER(c_uint32), c_size_t, POINTER(_p)]),
    "dfm_roi_ball": (_R, [_p, c_uint32, c_double, POINTER(_p)]),
    "dfm_roi_all": (_R, [_p, POINTER(_p)]),
    "dfm_roi_grow": (_R, [_p, c_int, POINTER(_p)]),
    "dfm_roi_union": (_R, [_p, _p, POINTER(_p)]),
    "dfm_roi_difference": (_R, [_p, _p, POINTER(_p)]),
    "dfm_roi_boundary": (_R, [_p, POINTER(_p)]),
    "dfm_roi_count": (_R, [_p, POINTER(c_size_t)]),
    "dfm_roi_read": (_R, [_p, POINTER(c_uint32), c_size_t]),
    "dfm_roi_destroy": (None, [_p]),
    "dfm_session_create": (_R, [_p, POINTER(SessionDesc), POINTER(_p)]),
    "dfm_session_destroy": (None, [_p]),
    "dfm_session_set_group_transform": (_R, [_p, c_uint32, POINTER(c_double)]),
    "dfm_session_set_targets": (_R, [_p, POINTER(Vec3Input)]),
    "dfm_session_get_handle_count": (_R, [_p, POINTER(c_size_t)]),
    "dfm_session_get_memory": (_R, [_p, POINTER(SessionMemory)]),
    "dfm_session_set_solver": (_R, [_p, POINTER(SolverSettings)]),
    "dfm_session_submit": (_R, [_p, POINTER(c_uint64)]),
    "dfm_session_solve": (_R, [_p, POINTER(c_uint64)]),
    "dfm_session_cancel": (_R, [_p]),
    "dfm_session_poll": (_R, [_p, c_uint64, POINTER(FrameInfo), POINTER(c_bool)]),
    "dfm_session_wait": (_R, [_p, c_uint64, c_int64, POINTER(FrameInfo)]),
    "dfm_session_read_positions": (_R, [_p, POINTER(Vec3Output), POINTER(FrameInfo)]),
    "dfm_session_read_normals": (_R, [_p, POINTER(Vec3Output), POINTER(FrameInfo)]),
    "dfm_session_read_roi_positions": (_R, [_p, POINTER(Vec3Output), POINTER(FrameInfo)]),
    "dfm_session_read_vertices": (_R, [_p, POINTER(VertexOutput), POINTER(FrameInfo)]),
    "dfm_session_acquire_frame": (_R, [_p, POINTER(FrameView), POINTER(FrameInfo)]),
    "dfm_session_release_frame": (_R, [_p]),
    "dfm_session_bake": (_R, [_p]),
    "dfm_session_bake_generation": (_R, [_p, c_uint64]),
    "dfm_session_measure_quality": (_R, [_p, POINTER(Quality), POINTER(FrameInfo)]),
    "dfm_session_get_solve_report": (_R, [_p, POINTER(SolveReport), POINTER(FrameInfo)]),
}


def _candidates() -> list[str]:
    """Where the library is looked for, in order (docs/python.md)."""
    found = []
    named = os.environ.get(LIBRARY_VARIABLE)
    if named:
        return [named]
    here = Path(__file__).resolve().parent
    bundled = here / "lib" / _SONAME
    if bundled.exists():
        found.append(str(bundled))
    root = here.parents[2]
    if root / "sdk" / "python" / "dualform" == here:  # imported from the source tree
        for preset in ("release", "debug"):
            built = root / "build" / preset / "sdk" / "libdualform.so"
            if built.exists():
                found.append(str(built))
    found.append(_SONAME)
    system = ctypes.util.find_library("dualform")
    if system:
        found.append(system)
    return found


_lock = threading.Lock()
_lib: Optional[ctypes.CDLL] = None


def _declare(library: ctypes.CDLL) -> ctypes.CDLL:
    for name, (restype, argtypes) in _PROTOTYPES.items():
        fn = getattr(library, name)
        fn.restype = restype
        fn.argtypes = argtypes
    return library


def load_library(path: Optional[str] = None) -> ctypes.CDLL:
    """Loads libdualform once: from ``path`` if given, else by the rule of
    :func:`library_candidates`. Later calls return the loaded library; a
    different ``path`` after loading raises RuntimeError."""
    global _lib
    with _lock:
        if _lib is not None:
            if path is not None and Path(path).resolve() != Path(_lib._name).resolve():
                raise RuntimeError(f"libdualform is already loaded from {_lib._name}")
            return _lib
        tried = [path] if path is not None else _candidates()
        errors = []
        for candidate in tried:
            try:
                library = ctypes.CDLL(candidate)
            except OSError as error:
                errors.append(f"{candidate}: {error}")
                continue
            _declare(library)
            if not library.dfm_version_compatible(HEADER_VERSION):
                errors.append(f"{candidate}: version {library.dfm_version()} does not serve "
                              f"this package (written for {HEADER_VERSION})")
                continue
            _lib = library
            return library
        raise OSError(
            "libdualform not found. This package does not bundle the library: set "
            + LIBRARY_VARIABLE + " to its path (the file a build made, e.g. export "
            + LIBRARY_VARIABLE + "=/path/to/dualform/build/release/sdk/libdualform.so), "
            "or call dualform.load_library(PATH) before any other call (docs/python.md, "
            "'How the library is found'). Tried:\n  " + "\n  ".join(errors))


def library_candidates() -> list[str]:
    """The paths and names tried, in order, when no path is given:
    $DUALFORM_LIBRARY alone if set; else ``dualform/lib/libdualform.so.0.2``
    beside the package, the source tree's ``build/{release,debug}/sdk/libdualform.so``,
    then the system loader (``libdualform.so.0.2``, ``find_library``)."""
    return _candidates()


def lib() -> ctypes.CDLL:
    """The loaded library (loading it on first use)."""
    return _lib if _lib is not None else load_library()
