"""Edit scenarios (docs/scenarios.md) run through the C API, the way the
``dualform`` tool runs them, so that ``python -m dualform deform`` gives the
tool's result: the same ROI, the same targets to the last bit (the motion
is composed in glm's order of operations), one solve on the calling thread.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional, Sequence

import numpy as np

from .context import Context
from .mesh import Mesh, Roi
from .session import Session
from .types import Camera, Method

_TOP = {"mesh", "subdivide", "roi", "handles", "solver", "description", "comment"}
_HANDLE = {"vertices", "ball", "translate", "rotate", "targets"}
_SOLVER = {"tolerance", "max_iterations", "handle_weight", "method"}


class ScenarioError(ValueError):
    """A scenario that is malformed or does not fit its mesh; the message
    names the file and the field."""


def _known(obj: dict, allowed: set, where: str, source: str) -> None:
    if not isinstance(obj, dict):
        raise ScenarioError(f"{source}: {where or 'the scenario'}: expected an object")
    for key in obj:
        if key not in allowed:
            raise ScenarioError(f"{source}: {where + '.' if where else ''}{key}: unknown field "
                                f"(expected {' or '.join(sorted(allowed))})")


@dataclass
class Scenario:
    """A parsed scenario file: the JSON document and the folder that
    relative mesh paths start from."""

    document: dict
    base_dir: Path
    source: str

    @classmethod
    def load(cls, path: os.PathLike) -> "Scenario":
        p = Path(path)
        try:
            document = json.loads(p.read_text())
        except json.JSONDecodeError as error:
            raise ScenarioError(f"{p}:{error.lineno}:{error.colno}: {error.msg}") from None
        _known(document, _TOP, "", str(p))
        for required in ("mesh", "roi", "handles"):
            if required not in document:
                raise ScenarioError(f"{p}: {required}: required field is missing")
        for i, h in enumerate(document["handles"]):
            _known(h, _HANDLE, f"handles[{i}]", str(p))
        _known(document.get("solver", {}), _SOLVER, "solver", str(p))
        return cls(document, p.parent, str(p))

    @property
    def mesh_path(self) -> str:
        written = self.document["mesh"]
        if written.startswith("model:") or os.path.isabs(written):
            return written
        return str(self.base_dir / written)


@dataclass
class Edit:
    """A scenario resolved against its mesh: ROI, handle groups, one target
    per handle vertex in group order, and the solver's settings."""

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


def _group_targets(spec: dict, group: np.ndarray, rest: np.ndarray, diagonal: float) -> np.ndarray:
    if "targets" in spec:
        return np.asarray(spec["targets"], dtype=np.float64).reshape(-1, 3)
    motion = _identity()
    if "translate" in spec:
        motion = _translate(motion, [float(t) * diagonal for t in spec["translate"]])
    if "rotate" in spec:
        rotate = spec["rotate"]
        pivot = rotate.get("pivot", "centroid")
        if pivot == "centroid":
            total = [0.0, 0.0, 0.0]
            for v in group:
                for k in range(3):
                    total[k] += float(rest[v, k])
            pivot = [t / float(len(group)) for t in total]
        pivot = [float(p) for p in pivot]
        motion = _translate(motion, pivot)
        motion = _rotate(motion, float(rotate["degrees"]) * math.pi / 180.0,
                         [float(a) for a in rotate["axis"]])
        motion = _translate(motion, [-p for p in pivot])
    return _apply(motion, rest[group])


def open_mesh(scenario: Scenario, context: Context) -> Mesh:
    """The scenario's mesh, loaded and subdivided as it asks."""
    mesh = Mesh.load(context, scenario.mesh_path)
    steps = int(scenario.document.get("subdivide", 0))
    if steps > 0:
        with mesh:
            return mesh.subdivide(steps)
    return mesh


def _click_vertex(mesh: Mesh, camera: Camera, pixel: Sequence[float], what: str) -> int:
    hit = mesh.pick(camera, float(pixel[0]), float(pixel[1]))
    if hit is None:
        raise ScenarioError(f"{what}: the click at {list(pixel)} hits nothing")
    return hit.vertex


def select_roi(spec: dict, mesh: Mesh) -> Roi:
    """The ROI a scenario's ``roi`` object selects."""
    (kind, value), = spec.items()
    if kind == "water_fill":
        return mesh.water_fill(int(value["first"]), int(value["last"]))
    if kind == "water_fill_clicks":
        camera = Camera.from_dict(value["camera"])
        first = _click_vertex(mesh, camera, value["first"], "roi.water_fill_clicks.first")
        last = _click_vertex(mesh, camera, value["last"], "roi.water_fill_clicks.last")
        return mesh.water_fill(first, last)
    if kind == "ball":
        return mesh.roi_ball(int(value["center"]), float(value["radius"]))
    if kind == "vertices":
        return mesh.roi_from_vertices(value)
    if kind == "all":
        return mesh.roi_all()
    raise ScenarioError(f"roi: unknown kind {kind!r}")


def resolve_edit(scenario: Scenario, mesh: Mesh) -> Edit:
    """The scenario's ROI, groups and targets on ``mesh``."""
    info = mesh.info
    rest = mesh.positions(np.float64)
    roi = select_roi(scenario.document["roi"], mesh)
    inside = roi.vertices()
    groups, targets = [], []
    for g, spec in enumerate(scenario.document["handles"]):
        if "ball" in spec:
            with mesh.roi_ball(int(spec["ball"]["center"]), float(spec["ball"]["radius"])) as b:
                group = b.vertices()
        else:
            group = np.asarray(spec["vertices"], dtype=np.uint32)
        outside = np.setdiff1d(group, inside)
        if outside.size:
            roi.close()
            raise ScenarioError(f"handles[{g}]: vertex {outside[0]} is outside the ROI")
        targets.append(_group_targets(spec, group, rest, info.diagonal))
        groups.append(group)
    solver = {}
    s = scenario.document.get("solver", {})
    for key in ("tolerance", "max_iterations", "handle_weight"):
        if key in s:
            solver[key] = s[key]
    if "method" in s:
        solver["method"] = Method.PAPER if s["method"] == "paper" else Method.FITTED_ROTATIONS
    return Edit(roi, groups, np.concatenate(targets), solver)


def run_deform(scenario_path: os.PathLike, out_path: os.PathLike, *,
               hard_handles: bool = False, method: Optional[Method] = None,
               context: Optional[Context] = None) -> dict:
    """``dualform deform SCENARIO --out MESH``: solves the edit on this
    thread, writes the deformed mesh and returns the report's main figures."""
    scenario = Scenario.load(scenario_path)
    own = context is None
    ctx = Context() if own else context
    try:
        with open_mesh(scenario, ctx) as mesh:
            edit = resolve_edit(scenario, mesh)
            solver = dict(edit.solver, hard_handles=hard_handles)
            if method is not None:
                solver["method"] = method
            with edit.roi, Session(mesh, edit.roi, edit.groups, **solver) as session:
                session.set_targets(edit.targets)
                session.solve()
                quality, solved = session.measure_quality()
                if solved.status != 0:
                    raise ScenarioError(f"the solve broke down (status {solved.status})")
                positions, _ = session.read_positions()
                with Mesh.from_arrays(ctx, positions, mesh.triangles()) as result:
                    result.save(out_path)
                info = mesh.info
                return {
                    "mesh": scenario.document["mesh"],
                    "n_vertices": info.vertex_count,
                    "n_faces": info.triangle_count,
                    "n_roi": len(edit.roi),
                    "n_handles": len(edit.targets),
                    "n_handle_groups": len(edit.groups),
                    "method": "paper" if solver.get("method") == Method.PAPER
                    else "fitted_rotations",
                    "iterations": solved.iterations,
                    "converged": solved.converged,
                    "last_update": solved.last_update,
                    "solve_ms": solved.solve_ms,
                    "max_handle_error": quality.max_handle_error,
                    "flipped_faces": quality.flipped_faces,
                }
    finally:
        if own:
            ctx.close()
