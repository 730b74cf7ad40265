"""Dualform for Python: the C API (libdualform) through ctypes, with numpy
arrays in and out. See docs/python.md.

    import dualform as dfm
    with dfm.Context() as ctx, dfm.Mesh.load(ctx, "model:cow") as cow:
        roi = cow.water_fill(771, 681)
"""

from ._native import LIBRARY_VARIABLE, library_candidates, load_library
from .batch import deform_batch
from .context import Context, CountingAllocator, JobQueue, default_models_directory, run_job
from .errors import (BusyError, CancelledError, DeviceError, DualformError, InternalError,
                     InvalidArgumentError, InvalidHandleError, IOFailedError, NotFoundError,
                     NumericalError, OutOfMemoryError, OutOfRangeError, ParseError, Result,
                     UnsupportedError, result_name)
from .mesh import Mesh, Roi
from .session import FrameView, Session, frame_checksum
from . import scenario
from .types import (AnimationInfo, Camera, FrameInfo, Hit, JointInfo, LoadReport, LogId, LogLevel,
                    MeshInfo, MeshMemory, MeshSummary, Method, MorphTargetInfo, PlyEncoding,
                    Preconditioner, Quality, SessionMemory, SkinInfo, SolveReport,
                    WaterFillDiagnosis, WorkMode)

__version__ = "0.2.0"


def library_version() -> int:
    """dfm_version() of the loaded library (major * 10000 + minor * 100 + patch)."""
    return load_library().dfm_version()


__all__ = [
    "AnimationInfo", "BusyError", "Camera", "CancelledError", "Context", "CountingAllocator",
    "DeviceError", "DualformError", "FrameInfo", "FrameView", "Hit", "IOFailedError",
    "InternalError", "InvalidArgumentError", "InvalidHandleError", "JobQueue", "JointInfo",
    "LIBRARY_VARIABLE", "LoadReport", "LogId", "LogLevel", "Mesh", "MeshInfo", "MeshMemory",
    "MeshSummary", "Method", "MorphTargetInfo", "NotFoundError", "NumericalError",
    "OutOfMemoryError", "OutOfRangeError", "ParseError", "PlyEncoding", "Preconditioner", "Quality",
    "Result", "Roi", "Session", "SessionMemory", "SkinInfo", "SolveReport", "UnsupportedError",
    "WaterFillDiagnosis", "WorkMode", "default_models_directory", "deform_batch", "frame_checksum",
    "library_candidates", "library_version", "load_library", "result_name", "run_job", "scenario",
]
