"""Plain values that cross the C API: cameras, figures, frame infos."""

from __future__ import annotations

import ctypes
import enum
import math
from dataclasses import dataclass, fields
from typing import Optional, Sequence, Tuple, Type, TypeVar

import numpy as np

from . import _native

T = TypeVar("T")


class Method(enum.IntEnum):
    """dfm_method: the outer iteration (docs/method.md)."""

    DEFAULT = 0
    FITTED_ROTATIONS = 1
    PAPER = 2


class Preconditioner(enum.IntEnum):
    """dfm_preconditioner."""

    DEFAULT = 0
    CHOLESKY = 1
    INCOMPLETE_CHOLESKY = 2
    JACOBI = 3


class PlyEncoding(enum.IntEnum):
    """dfm_ply_encoding."""

    BINARY_LITTLE_ENDIAN = 0
    BINARY_BIG_ENDIAN = 1
    ASCII = 2


class WorkMode(enum.IntEnum):
    """dfm_work_mode: where a context's work runs (docs/python.md, "Work modes")."""

    POOL = 0
    JOB_SYSTEM = 1
    HOST_STEPPED = 2


class LogLevel(enum.IntEnum):
    DEBUG = 0
    INFO = 1
    WARNING = 2
    ERROR = 3


class LogId(enum.IntEnum):
    LOAD_WARNING = 1
    WATER_FILL_SUSPECT = 2
    SOLVE_NOT_CONVERGED = 3
    SOLVE_FAILED = 4
    CORRECTIVE_DAMPED = 5  # a bake in a pose met ill-conditioned skinning


Vec3 = Tuple[float, float, float]


@dataclass(frozen=True)
class Camera:
    """dfm_camera: a pinhole camera at ``eye`` looking at ``target``; pixel
    (0, 0) is the image's top-left corner, y grows downwards."""

    eye: Sequence[float]
    target: Sequence[float]
    up: Sequence[float]
    fov_y_degrees: float
    width: int
    height: int

    def to_c(self) -> _native.Camera:
        c = _native.Camera()
        c.eye[:] = [float(v) for v in self.eye]
        c.target[:] = [float(v) for v in self.target]
        c.up[:] = [float(v) for v in self.up]
        c.fov_y_degrees = float(self.fov_y_degrees)
        c.width = int(self.width)
        c.height = int(self.height)
        return c

    def project(self, point: Sequence[float]) -> Optional[Tuple[float, float]]:
        """The pixel where the camera sees ``point`` (None behind it): the
        inverse of the ray a pick casts."""
        eye = np.asarray(self.eye, dtype=np.float64)
        forward = np.asarray(self.target, dtype=np.float64) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, np.asarray(self.up, dtype=np.float64))
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        half_height = math.tan(self.fov_y_degrees * math.pi / 360.0)
        half_width = half_height * self.width / self.height
        d = np.asarray(point, dtype=np.float64) - eye
        depth = float(d @ forward)
        if not depth > 0.0:
            return None
        sx = float(d @ right) / depth / half_width
        sy = float(d @ up) / depth / half_height
        return ((sx + 1.0) * 0.5 * self.width, (1.0 - sy) * 0.5 * self.height)

    @classmethod
    def from_dict(cls, d: dict) -> "Camera":
        """From the CAMERA object of a scenario (docs/scenarios.md)."""
        return cls(tuple(d["eye"]), tuple(d["target"]), tuple(d["up"]), d["fov_y_degrees"],
                   d["width"], d["height"])


def _convert(value):
    if isinstance(value, ctypes.Array):
        return tuple(value)
    return value


def from_struct(cls: Type[T], struct: ctypes.Structure) -> T:
    """The dataclass ``cls`` with the same-named fields of ``struct``."""
    return cls(**{f.name: _convert(getattr(struct, f.name)) for f in fields(cls)})


@dataclass(frozen=True)
class MeshInfo:
    """dfm_mesh_info: the rest pose's figures."""

    vertex_count: int
    triangle_count: int
    bounds_min: Vec3
    bounds_max: Vec3
    diagonal: float
    components: int
    boundary_edges: int
    bake_count: int
    redo_count: int
    surface_vertex_count: int  # after the seam weld; vertex_count without one


@dataclass(frozen=True)
class MeshMemory:
    """dfm_mesh_memory, bytes by part."""

    rest_pose: int
    adjacency: int
    model: int
    history: int
    pick_scene: int
    total: int


@dataclass(frozen=True)
class MeshSummary:
    """dfm_mesh_summary: topology counts."""

    edges: int
    boundary_edges: int
    non_manifold_edges: int
    inconsistent_edges: int
    components: int
    isolated_vertices: int
    degenerate_triangles: int
    closed: bool


@dataclass(frozen=True)
class LoadReport:
    """dfm_load_report."""

    polygons: int
    triangulated_polygons: int
    dropped_faces: int


@dataclass(frozen=True)
class SkinInfo:
    """dfm_skin_info: what poses a mesh, the pose set, and what the last
    bake in a pose found of its corrective (docs/python.md, "Skinned
    meshes")."""

    joint_count: int  # 0 without a skin
    max_influences: int
    skinned_vertex_count: int
    animation_count: int
    morph_target_count: int
    posed: bool
    pose_animation: int  # -1: joint matrices, or no pose
    pose_time: float  # seconds, as clamped
    corrective_vertex_count: int  # vertices the last bake in a pose moved
    corrective_worst_condition: float  # the largest condition number of their L_v
    corrective_damped_count: int  # how many took the damped inverse


@dataclass(frozen=True)
class JointInfo:
    """dfm_joint_info: a joint's node name and the nearest ancestor that is
    a joint (None for none)."""

    name: str
    parent: Optional[int]


@dataclass(frozen=True)
class AnimationInfo:
    """dfm_animation_info: an animation's name, first and last key (seconds)
    and its channels by what they animate."""

    name: str
    start: float
    end: float
    translation_channels: int
    rotation_channels: int
    scale_channels: int
    weight_channels: int


@dataclass(frozen=True)
class MorphTargetInfo:
    """dfm_morph_target_info: a morph target's name, default weight and the
    surface vertices it moves."""

    name: str
    default_weight: float
    vertex_count: int


@dataclass(frozen=True)
class Hit:
    """dfm_hit of a pick that hit (a miss is ``None``)."""

    face: int
    vertex: int
    point: Vec3
    distance: float
    barycentric: Vec3


@dataclass(frozen=True)
class WaterFillDiagnosis:
    """dfm_water_fill_diagnosis: ``suspect`` means the fill most likely
    leaked past the intended limb."""

    loops: int
    bounded_by_last_loop: bool
    suspect: bool


@dataclass(frozen=True)
class FrameInfo:
    """dfm_frame_info: what a published frame is. ``status`` is a
    :class:`Result`: ``Result.ERROR_NUMERICAL`` when the solve broke down
    (the frame keeps the last good positions)."""

    generation: int
    status: int  # a Result
    converged: bool
    partial: bool
    iterations: int
    last_update: float
    solve_ms: float
    checksum: int
    preparing: bool


@dataclass(frozen=True)
class Quality:
    """dfm_quality of a frame; lengths in fractions of the diagonal."""

    max_handle_error: float
    mean_abs_log_edge: float
    max_abs_log_edge: float
    mean_normal_change_deg: float
    max_fixed_move: float
    dual_magnitude_error: float
    flipped_faces: int
    creased_edges: int


@dataclass(frozen=True)
class SolveReport:
    """dfm_solve_report."""

    unknowns: int
    rows: int
    normal_nonzeros: int
    setup_ms: float
    krylov_iterations: int
    linear_residual: float
    linear_converged: bool


@dataclass(frozen=True)
class SessionMemory:
    """dfm_session_memory, bytes by part."""

    factor: int
    normal_matrix: int
    iteration: int
    frames: int
    staging: int
    total: int
