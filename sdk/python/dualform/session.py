"""Edit sessions (dfm_session): staged transforms or targets, asynchronous
solves as the context's work, frames back as numpy arrays."""

from __future__ import annotations

import ctypes
import contextlib
import dataclasses
from typing import Callable, Iterator, Optional, Sequence, Tuple

import numpy as np

from . import _arrays, _native
from ._handle import Handle
from .errors import Result, as_result, check, error_for
from .mesh import Mesh, Roi
from .types import (FrameInfo, Method, Preconditioner, Quality, SessionMemory, SolveReport,
                    from_struct)

FrameCallback = Callable[["Session", FrameInfo], None]


def _info(struct: _native.FrameInfo) -> FrameInfo:
    info = from_struct(FrameInfo, struct)
    return dataclasses.replace(info, status=as_result(info.status))


def _raise_if_failed(info: FrameInfo) -> FrameInfo:
    """``info``, or the error of its status when its solve failed: the
    frame then holds the last good positions, and the error carries it as
    ``.frame``."""
    if info.status == Result.OK:
        return info
    error = error_for(int(info.status),
                      f"generation {info.generation}: the solve failed after {info.iterations} "
                      f"iterations (last update {info.last_update:g}); the frame keeps the last "
                      "good positions")
    error.frame = info
    raise error


def solver_settings(*, tolerance: Optional[float] = None, max_iterations: Optional[int] = None,
                    handle_weight: Optional[float] = None, hard_handles: bool = False,
                    method: Method = Method.DEFAULT,
                    preconditioner: Preconditioner = Preconditioner.DEFAULT,
                    disable_prediction: bool = False) -> _native.SolverSettings:
    """dfm_solver_settings; None keeps the library's default."""
    s = _native.SolverSettings()
    s.tolerance = tolerance or 0.0
    s.max_iterations = max_iterations or 0
    s.handle_weight = handle_weight or 0.0
    s.hard_handles = hard_handles
    s.method = int(method)
    s.preconditioner = int(preconditioner)
    s.disable_prediction = disable_prediction
    return s


class FrameView:
    """A frame lent without copying (dfm_session_acquire_frame): read-only
    numpy views of the session's own buffers, valid only until the ``with``
    block of :meth:`Session.acquire_frame` ends. Copy what you keep."""

    def __init__(self, view: _native.FrameView, info: FrameInfo) -> None:
        self.info = info
        n = view.roi_count
        k = view.normal_count

        def lend(pointer, shape):
            if not shape[0]:
                return np.empty(shape, dtype=np.dtype(pointer._type_))
            a = np.ctypeslib.as_array(pointer, shape=shape)
            a.flags.writeable = False
            return a

        self.roi_positions = lend(view.roi_positions, (n, 3))
        self.roi_positions_f64 = lend(view.roi_positions_f64, (n, 3))
        self.roi_vertices = lend(view.roi_vertices, (n,))
        self.normals = lend(view.normals, (k, 3))
        self.normal_vertices = lend(view.normal_vertices, (k,))


class Session(Handle):
    """dfm_session: one edit of ``mesh`` over ``roi`` with handle ``groups``
    (one sequence of vertex ids per group; group g is transform g).

    Creation returns at once; the set-up is queued as the context's work.
    ``on_frame(session, info)`` (optional) runs on the thread that publishes
    each frame, with the GIL held: keep it short, and never wait, cancel,
    solve, bake or close the session from it."""

    _kind = "session"

    def __init__(self, mesh: Mesh, roi: Roi, groups: Sequence[Sequence[int]], *,
                 on_frame: Optional[FrameCallback] = None, **solver) -> None:
        lib = _native.lib()
        self.mesh = mesh
        self.roi = roi
        self._groups = [_arrays.index_array(g, f"groups[{i}]") for i, g in enumerate(groups)]
        c_groups = (_native.HandleGroup * max(len(self._groups), 1))()
        for i, g in enumerate(self._groups):
            c_groups[i].vertices = g.ctypes.data
            c_groups[i].count = g.size
        desc = _native.SessionDesc()
        desc.struct_size = ctypes.sizeof(desc)
        desc.roi = roi.pointer
        desc.groups = c_groups
        desc.group_count = len(self._groups)
        desc.solver = solver_settings(**solver)
        self._on_frame = on_frame
        self._frame_fn = _native.FRAME_FN(self._frame_ready) if on_frame else _native.FRAME_FN()
        desc.on_frame = self._frame_fn
        out = ctypes.c_void_p()
        check(lib.dfm_session_create(mesh.pointer, ctypes.byref(desc), ctypes.byref(out)))
        self._vertex_count = mesh.vertex_count
        self._roi_count = len(roi)
        self._held = False
        super().__init__(out.value, lib.dfm_session_destroy, *mesh.context.keep_alive,
                         self._frame_fn)

    def _frame_ready(self, user, session, info) -> None:
        self._on_frame(self, _info(info.contents))

    @property
    def handle_count(self) -> int:
        """Handle vertices (targets), over all groups in order."""
        out = ctypes.c_size_t()
        check(_native.lib().dfm_session_get_handle_count(self.pointer, ctypes.byref(out)))
        return out.value

    # -------------------------------------------------------------- staging

    def set_group_transform(self, group: int, matrix) -> None:
        """Stages group ``group``'s transform: a 4x4 affine matrix M acting
        on column vectors (M @ [x, y, z, 1]; translation in M[:3, 3]) applied
        to the group's rest positions."""
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape != (4, 4):
            raise ValueError(f"matrix: expected a 4x4 array, found shape {m.shape}")
        column_major = (ctypes.c_double * 16)(*m.T.reshape(-1))
        check(_native.lib().dfm_session_set_group_transform(
            self.pointer, _arrays.unsigned(group, "group", 0xFFFFFFFF), column_major))

    def set_translation(self, group: int, offset: Sequence[float]) -> None:
        """Stages a pure translation of group ``group``."""
        m = np.eye(4)
        m[:3, 3] = offset
        self.set_group_transform(group, m)

    def set_targets(self, targets) -> None:
        """Stages explicit targets, (handle_count, 3), in group order."""
        v, _kept = _arrays.vec3_input(targets, "targets")
        check(_native.lib().dfm_session_set_targets(self.pointer, ctypes.byref(v)))

    def set_solver(self, **solver) -> None:
        """Changes the tolerance and iteration cap for later solves."""
        s = solver_settings(**solver)
        check(_native.lib().dfm_session_set_solver(self.pointer, ctypes.byref(s)))

    # -------------------------------------------------------------- solving

    def submit(self) -> int:
        """Queues the staged targets as the context's work; returns their
        generation at once (never blocks)."""
        g = ctypes.c_uint64()
        check(_native.lib().dfm_session_submit(self.pointer, ctypes.byref(g)))
        return g.value

    def solve(self) -> int:
        """Solves the staged targets on this thread (bit for bit the
        context's work's result) and publishes the frame; returns its generation. A
        solve that fails raises (:class:`NumericalError`); its frame, with
        the last good positions, stays readable (``poll``, ``read_positions``)."""
        g = ctypes.c_uint64()
        check(_native.lib().dfm_session_solve(self.pointer, ctypes.byref(g)))
        return g.value

    def cancel(self) -> None:
        """Drops queued targets, stops the running solve; returns when idle."""
        check(_native.lib().dfm_session_cancel(self.pointer))

    def poll(self, known_generation: int = 0) -> Tuple[FrameInfo, bool]:
        """The newest frame's info, and whether it is newer than
        ``known_generation``; never blocks."""
        out = _native.FrameInfo()
        is_new = ctypes.c_bool()
        check(_native.lib().dfm_session_poll(self.pointer,
                                             _arrays.unsigned(known_generation, "known_generation"),
                                             ctypes.byref(out), ctypes.byref(is_new)))
        return _info(out), is_new.value

    def wait(self, generation: int = 0, timeout: Optional[float] = None, *,
             check_status: bool = True) -> FrameInfo:
        """Waits, without holding the GIL, until a finished frame of at least
        ``generation`` is published (0: the set-up's end). ``timeout`` in
        seconds (None: no limit); a timeout raises :class:`BusyError`. A
        frame whose solve failed (``status`` not ``Result.OK``) raises its
        error (:class:`NumericalError`, with the frame as ``.frame``) unless
        ``check_status=False`` asks for the frame as it is."""
        ms = -1 if timeout is None else int(timeout * 1000)
        out = _native.FrameInfo()
        generation = _arrays.unsigned(generation, "generation")
        check(_native.lib().dfm_session_wait(self.pointer, generation, ms, ctypes.byref(out)))
        info = _info(out)
        return _raise_if_failed(info) if check_status else info

    # -------------------------------------------------------------- frames

    def _read(self, call, count: int, dtype, out: Optional[np.ndarray]):
        array = _arrays.new_vec3(count, dtype, out)
        info = _native.FrameInfo()
        check(call(self.pointer, ctypes.byref(_arrays.vec3_output(array)), ctypes.byref(info)))
        return array, _info(info)

    def read_positions(self, dtype=np.float64,
                       out: Optional[np.ndarray] = None) -> Tuple[np.ndarray, FrameInfo]:
        """The newest frame's positions of the whole mesh, written straight
        into ``out`` (or a new array), and which frame it is. Never torn."""
        return self._read(_native.lib().dfm_session_read_positions, self._vertex_count, dtype, out)

    def read_normals(self, dtype=np.float64,
                     out: Optional[np.ndarray] = None) -> Tuple[np.ndarray, FrameInfo]:
        """The newest frame's unit vertex normals of the whole mesh."""
        return self._read(_native.lib().dfm_session_read_normals, self._vertex_count, dtype, out)

    def read_roi_positions(self, dtype=np.float64,
                           out: Optional[np.ndarray] = None) -> Tuple[np.ndarray, FrameInfo]:
        """Only the ROI's vertices, in ``roi.vertices()`` order; in float64
        these are the bytes the frame's checksum covers."""
        return self._read(_native.lib().dfm_session_read_roi_positions, self._roi_count, dtype, out)

    @contextlib.contextmanager
    def acquire_frame(self) -> Iterator[FrameView]:
        """Lends the newest frame without copying, for the ``with`` block::

            with session.acquire_frame() as frame:
                mine = frame.roi_positions.copy()

        The views must not be used after the block (the session reuses the
        buffers). One frame may be held at a time (:class:`BusyError`)."""
        view = _native.FrameView()
        info = _native.FrameInfo()
        check(_native.lib().dfm_session_acquire_frame(self.pointer, ctypes.byref(view),
                                                      ctypes.byref(info)))
        try:
            yield FrameView(view, _info(info))
        finally:
            check(_native.lib().dfm_session_release_frame(self.pointer))

    # -------------------------------------------------------------- results

    def bake(self, generation: Optional[int] = None) -> None:
        """Bakes the newest finished frame into the mesh's rest pose (only if
        it is ``generation``, when given); undo with ``mesh.undo_bake()``."""
        if generation is None:
            check(_native.lib().dfm_session_bake(self.pointer))
        else:
            check(_native.lib().dfm_session_bake_generation(
                self.pointer, _arrays.unsigned(generation, "generation")))
        self.mesh.forget_info()

    def measure_quality(self) -> Tuple[Quality, FrameInfo]:
        """The newest frame's quality figures against the staged targets."""
        out = _native.Quality()
        info = _native.FrameInfo()
        check(_native.lib().dfm_session_measure_quality(self.pointer, ctypes.byref(out),
                                                        ctypes.byref(info)))
        return from_struct(Quality, out), _info(info)

    def solve_report(self) -> Tuple[SolveReport, FrameInfo]:
        out = _native.SolveReport()
        info = _native.FrameInfo()
        check(_native.lib().dfm_session_get_solve_report(self.pointer, ctypes.byref(out),
                                                         ctypes.byref(info)))
        return from_struct(SolveReport, out), _info(info)

    @property
    def memory(self) -> SessionMemory:
        out = _native.SessionMemory()
        check(_native.lib().dfm_session_get_memory(self.pointer, ctypes.byref(out)))
        return from_struct(SessionMemory, out)


def frame_checksum(roi_positions_f64: np.ndarray) -> int:
    """FNV-1a over the 64-bit words of packed float64 ROI positions (each
    double's bits): what ``FrameInfo.checksum`` holds for an untorn frame.
    Pure Python, a word at a time: for checks on small ROIs, not per frame
    on large ones."""
    h = 14695981039346656037
    words = np.ascontiguousarray(roi_positions_f64, dtype=np.float64).view(np.uint64)
    for w in words.ravel().tolist():
        h = ((h ^ w) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h

