"""Edit scenarios (docs/scenarios.md) run through the C API the way the
``dualform`` tool runs them (tools/dualform/api_edit.cpp, cmd_deform.cpp),
so that ``python -m dualform deform`` gives the tool's result, report and
messages: the same ROI, the same targets to the last bit (the motion is
composed in glm's order of operations), one solve on the calling thread.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from typing import Callable, List, Optional, Sequence

import numpy as np

from . import _json
from .context import Context
from .errors import DualformError, Result
from .mesh import Mesh, Roi
from .scenario_format import (Ball, HandleSpec, PoseSpec, RoiSpec, Scenario, ScenarioError,
                              load_scenario)
from .session import Session
from .types import Camera, LogId, LogLevel, Method

__all__ = ["Edit", "ScenarioError", "SolveError", "WorkError", "load_scenario", "open_mesh",
           "pose_report", "report_json", "resolve_edit", "run_deform", "select_roi",
           "write_text_file"]


class SolveError(RuntimeError):
    """The scenario was fine but its solve failed: the tool's exit 1."""


class WorkError(ScenarioError):
    """A step of the work on an accepted scenario failed: the session, the
    save or an output file. As the tool's work_failure: bad input (exit 2)
    where the library refused what the scenario asked of it, else exit 1
    (an output it could not write, a breakdown, no memory)."""

    REFUSED = frozenset({Result.ERROR_INVALID_ARGUMENT, Result.ERROR_NOT_FOUND,
                         Result.ERROR_PARSE, Result.ERROR_OUT_OF_RANGE,
                         Result.ERROR_UNSUPPORTED})

    @property
    def bad_input(self) -> bool:
        return self.result in self.REFUSED


def _api(error: DualformError, what: str = "") -> ScenarioError:
    """A failing call as the tool words it: "what: dfm_...: message"."""
    return ScenarioError((what + ": " if what else "") + error.message, Result(error.result))


@dataclass
class Edit:
    """A scenario resolved against its mesh: ROI (vertices ascending; the
    Water-Filling's diagnosis with it), handle groups, one target per handle
    vertex in group order, and the solver's settings."""

    roi: Roi
    groups: List[np.ndarray]
    targets: np.ndarray
    solver: dict = field(default_factory=dict)


# glm's column-major 4x4 double matrices as four columns of four floats,
# composed exactly as glm::translate and glm::rotate compose them.
def _identity() -> List[List[float]]:
    return [[1.0 if i == j else 0.0 for i in range(4)] for j in range(4)]


def _translate(m, v):
    col = [m[0][i] * v[0] + m[1][i] * v[1] + m[2][i] * v[2] + m[3][i] for i in range(4)]
    return [m[0], m[1], m[2], col]


def _rotate(m, angle: float, v):
    c, s = math.cos(angle), math.sin(angle)
    inv = 1.0 / math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    axis = [v[0] * inv, v[1] * inv, v[2] * inv]
    t = [(1.0 - c) * a for a in axis]
    r = [
        [c + t[0] * axis[0], t[0] * axis[1] + s * axis[2], t[0] * axis[2] - s * axis[1]],
        [t[1] * axis[0] - s * axis[2], c + t[1] * axis[1], t[1] * axis[2] + s * axis[0]],
        [t[2] * axis[0] + s * axis[1], t[2] * axis[1] - s * axis[0], c + t[2] * axis[2]],
    ]
    cols = [[m[0][i] * r[j][0] + m[1][i] * r[j][1] + m[2][i] * r[j][2] for i in range(4)]
            for j in range(3)]
    return cols + [m[3]]


def _apply(m, points: np.ndarray) -> np.ndarray:
    """glm's mat4 * vec4(p, 1), elementwise in its order: (c0 x + c1 y) + (c2 z + c3)."""
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    out = np.empty_like(points)
    for i in range(3):
        out[:, i] = (m[0][i] * x + m[1][i] * y) + (m[2][i] * z + m[3][i] * 1.0)
    return out


# Rotation about the pivot first, then translation.
def _group_targets(spec: HandleSpec, group: np.ndarray, rest: np.ndarray,
                   diagonal: float) -> np.ndarray:
    if spec.targets:
        return np.asarray(spec.targets, dtype=np.float64).reshape(-1, 3)
    motion = _identity()
    if spec.translate is not None:
        motion = _translate(motion, [t * diagonal for t in spec.translate])
    if spec.rotate is not None:
        pivot = spec.rotate.pivot
        if pivot is None:
            total = [0.0, 0.0, 0.0]
            for v in group:
                for k in range(3):
                    total[k] += float(rest[v, k])
            pivot = [t / float(len(group)) for t in total]
        motion = _translate(motion, pivot)
        motion = _rotate(motion, spec.rotate.degrees * math.pi / 180.0, spec.rotate.axis)
        motion = _translate(motion, [-p for p in pivot])
    return _apply(motion, rest[group])


def open_mesh(scenario: Scenario, context: Context) -> Mesh:
    """The scenario's mesh, loaded, subdivided and posed as it asks."""
    try:
        mesh = Mesh.load(context, scenario.mesh_path)
    except DualformError as error:
        raise _api(error, "mesh") from None
    if scenario.subdivide > 0:
        with mesh:
            try:
                return mesh.subdivide(scenario.subdivide)
            except DualformError as error:
                raise _api(error, "subdivide") from None
    if scenario.pose is not None:
        try:
            _pose(scenario.pose, mesh)
        except BaseException:
            mesh.close()
            raise
    return mesh


def _pose(spec: PoseSpec, mesh: Mesh) -> None:
    animation = spec.animation
    if isinstance(animation, str):
        try:
            animation = mesh.find_animation(animation)
        except DualformError as error:
            raise _api(error, "pose.animation") from None
    try:
        mesh.set_pose(animation, spec.time)
    except DualformError as error:
        raise _api(error, "pose") from None


def pose_report(mesh: Mesh) -> dict:
    """The report's "pose" and "corrective" of a posed edit: the animation
    and time (as clamped), and the vertices the bake's corrective moved,
    their worst condition number and how many took the damped inverse."""
    skin = mesh.skin_info()
    animation = mesh.animations()[skin.pose_animation]
    return {
        "pose": {"animation": animation.name, "time": skin.pose_time},
        "corrective": {"vertices": skin.corrective_vertex_count,
                       "worst_condition": skin.corrective_worst_condition,
                       "damped": skin.corrective_damped_count},
    }


def _check_vertex(v: int, mesh: Mesh, what: str) -> None:
    n = mesh.info.vertex_count
    if v >= n:
        raise ScenarioError(f"{what}: vertex {v} is out of range (the mesh has {n} vertices)",
                            Result.ERROR_OUT_OF_RANGE)


def _ball(spec: Ball, mesh: Mesh, what: str) -> Roi:
    _check_vertex(spec.center, mesh, what + ".ball.center")
    try:
        return mesh.roi_ball(spec.center, spec.radius)
    except DualformError as error:
        raise _api(error, what) from None


def _click_vertex(mesh: Mesh, camera: Camera, pixel: Sequence[float], what: str) -> int:
    """The vertex a click picks: the nearest corner of the face it hits."""
    try:
        hit = mesh.pick(camera, pixel[0], pixel[1])
    except DualformError as error:
        raise _api(error, what) from None
    if hit is None:
        raise ScenarioError(f"{what}: the click at [{_json.number_text(pixel[0])}, "
                            f"{_json.number_text(pixel[1])}] hits nothing",
                            Result.ERROR_INVALID_ARGUMENT)
    return hit.vertex


def select_roi(spec: RoiSpec, mesh: Mesh) -> Roi:
    """The ROI a scenario's ``roi`` selects; errors name the field."""
    try:
        if spec.kind == "water_fill":
            return mesh.water_fill(spec.first, spec.last)
        if spec.kind == "water_fill_clicks":
            what = "roi.water_fill_clicks"
            c = spec.camera
            camera = Camera(c.eye, c.target, c.up, c.fov_y_degrees, c.width, c.height)
            first = _click_vertex(mesh, camera, spec.first_pixel, what + ".first")
            last = _click_vertex(mesh, camera, spec.last_pixel, what + ".last")
            try:
                return mesh.water_fill(first, last)
            except DualformError as error:
                raise _api(error, what) from None
        if spec.kind == "ball":
            return _ball(spec.ball, mesh, "roi")
        if spec.kind == "vertices":
            for v in spec.vertices:
                _check_vertex(v, mesh, "roi.vertices")
            try:
                return mesh.roi_from_vertices(spec.vertices)
            except DualformError as error:
                raise _api(error, "roi.vertices") from None
        return mesh.roi_all()
    except DualformError as error:
        raise _api(error, "roi") from None


def resolve_edit(scenario: Scenario, mesh: Mesh) -> Edit:
    """The scenario's ROI, groups and targets on ``mesh``. A handle vertex
    may name any seam-split copy; it must lie in the ROI, whose reads give
    each surface vertex's lowest copy."""
    info = mesh.info
    rest = mesh.positions(np.float64)
    lowest_copy = mesh.surface_map()
    roi = select_roi(scenario.roi, mesh)
    try:
        inside = roi.vertices()
        groups, targets = [], []
        for g, spec in enumerate(scenario.handles):
            what = f"handles[{g}]"
            if spec.ball is not None:
                with _ball(spec.ball, mesh, what) as selected:
                    group = selected.vertices()
            else:
                for v in spec.vertices:
                    _check_vertex(v, mesh, what + ".vertices")
                group = np.asarray(spec.vertices, dtype=np.uint32)
            outside = group[~np.isin(lowest_copy[group], inside)]
            if outside.size:
                raise ScenarioError(f"{what}: vertex {outside[0]} is outside the ROI",
                                    Result.ERROR_INVALID_ARGUMENT)
            targets.append(_group_targets(spec, group, rest, info.diagonal))
            groups.append(group)
    except BaseException:
        roi.close()
        raise
    solver = {}
    s = scenario.solver
    for key in ("tolerance", "max_iterations", "handle_weight"):
        if getattr(s, key) is not None:
            solver[key] = getattr(s, key)
    if s.method is not None:
        solver["method"] = Method.PAPER if s.method == "paper" else Method.FITTED_ROTATIONS
    return Edit(roi, groups, np.concatenate(targets), solver)


def write_text_file(path: os.PathLike, text: str) -> None:
    """The text and a newline, as the tool writes its report and ROI files."""
    try:
        with open(path, "w") as f:
            f.write(text + "\n")
    except OSError:
        raise WorkError(f"{os.fspath(path)}: cannot write", Result.ERROR_IO) from None


def _quality(quality) -> dict:
    return {k: getattr(quality, k) for k in (
        "max_handle_error", "mean_abs_log_edge", "max_abs_log_edge", "mean_normal_change_deg",
        "max_fixed_move", "dual_magnitude_error", "flipped_faces", "creased_edges")}


def _warn_loads(level: LogLevel, log_id: LogId, message: str, warn: Callable[[str], None]) -> None:
    if level >= LogLevel.WARNING and log_id == LogId.LOAD_WARNING:
        warn(message)


def run_deform(scenario_path: os.PathLike, out_path: os.PathLike, *,
               hard_handles: bool = False, method: Optional[Method] = None,
               morph_target: Optional[str] = None, roi_out: Optional[os.PathLike] = None,
               warn: Optional[Callable[[str], None]] = None) -> dict:
    """``dualform deform SCENARIO --out MESH``: solves the edit on this
    thread, writes the deformed mesh (into its own glTF asset when it came
    from one; with ``morph_target``, as a morph target of that name) and,
    with ``roi_out``, the ROI's vertices one a line. Returns the tool's
    report (the same keys, in its order). Bad input raises
    :class:`ScenarioError`, a failed step of the work (the session, the
    save, an output file) :class:`WorkError` (a ScenarioError), a failed
    solve :class:`SolveError`, each with the tool's message; ``warn`` hears
    each load warning."""
    source = os.fspath(scenario_path)
    scenario = load_scenario(source)
    start = time.perf_counter()
    log = (lambda *entry: _warn_loads(*entry, warn)) if warn else None
    with Context(log=log) as ctx, open_mesh(scenario, ctx) as mesh:
        info = mesh.info
        load_ms = (time.perf_counter() - start) * 1000.0
        setup_start = time.perf_counter()
        try:
            edit = resolve_edit(scenario, mesh)
        except ScenarioError as error:
            raise ScenarioError(f"{source}: {error}", error.result) from None
        solver = dict(edit.solver, hard_handles=hard_handles)
        if method is not None:
            solver["method"] = method
        with edit.roi:
            try:
                session = Session(mesh, edit.roi, edit.groups, **solver)
            except DualformError as error:
                raise WorkError(f"{source}: {error.message}", Result(error.result)) from None
            with session:
                try:
                    session.set_targets(edit.targets)
                except DualformError as error:
                    raise WorkError(f"{source}: {error.message}", Result(error.result)) from None
                setup_ms = (time.perf_counter() - setup_start) * 1000.0
                try:
                    session.solve()
                    quality, solved = session.measure_quality()
                except DualformError as error:
                    raise SolveError(error.message) from None
                if solved.status != Result.OK:
                    raise SolveError(f"the solve broke down ({solved.status})")
                try:
                    report, _ = session.solve_report()
                    positions, _ = session.read_positions()
                except DualformError as error:
                    raise SolveError(error.message) from None
            try:
                mesh.set_positions(positions)
                mesh.save(out_path, morph_target=morph_target)
            except DualformError as error:
                raise WorkError(error.message, Result(error.result)) from None
            roi_vertices = edit.roi.vertices()
        if roi_out is not None:
            write_text_file(roi_out, "\n".join(map(str, roi_vertices.tolist())))
        paper = solver.get("method") == Method.PAPER
        out = {
            "mesh": scenario.mesh,
            "n_vertices": info.vertex_count,
            "n_faces": info.triangle_count,
            "n_roi": len(roi_vertices),
            "n_handles": len(edit.targets),
            "n_handle_groups": len(edit.groups),
            "n_unknowns": report.unknowns,
            "method": "paper" if paper else "fitted_rotations",
            "iterations": solved.iterations,
            "converged": solved.converged,
            "last_update": solved.last_update,
            "setup_ms": setup_ms,
            "solve_ms": solved.solve_ms,
            "ms_per_iteration": solved.solve_ms / solved.iterations if solved.iterations else 0.0,
            "krylov_iterations": report.krylov_iterations,
            "linear_residual": report.linear_residual,
            "linear_converged": report.linear_converged,
            "load_ms": load_ms,
            "quality": _quality(quality),
        }
        if scenario.pose is not None:
            try:
                out.update(pose_report(mesh))
            except DualformError as error:
                raise SolveError(error.message) from None
        return out


def report_json(report: dict) -> str:
    """The report as the tool prints it: one line of compact JSON."""
    writer = _json.Writer()

    def put(value) -> None:
        if isinstance(value, dict):
            writer.begin_object()
            for k, v in value.items():
                writer.key(k)
                put(v)
            writer.end_object()
        else:
            writer.value(value)

    put(report)
    return writer.text()
