"""Edit scenario files (docs/scenarios.md) read and checked for form as the
``dualform`` tool reads them (tools/dualform/scenario.cpp): the same
required, typed and unknown fields, and the same located messages
("cow.json:7:12: handles[1].rotate.degrees: expected a number, found a
string"). Vertex indices are checked later, against the mesh."""

from __future__ import annotations

import errno
import math
import os
import stat
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple, Union

from . import _json
from ._json import ARRAY, BOOLEAN, NUMBER, OBJECT, STRING, Value
from .errors import Result

MAX_SUBDIVISIONS = 3
# 2^32 - 1 is the library's "no vertex", so indices stop one short of it.
MAX_VERTEX_INDEX = 4294967294
INDEX_RULE = "a vertex index (an integer from 0 to 4294967294)"


class ScenarioError(ValueError):
    """A scenario that is malformed or does not fit its mesh. The message
    names the file, the line and column, and the field; ``result`` is the
    dfm_result the tool gives the same failure."""

    def __init__(self, message: str, result: Result = Result.ERROR_PARSE) -> None:
        super().__init__(message)
        self.result = result


@dataclass
class Ball:
    """Every vertex reachable from ``center`` along edges without leaving
    the ball of radius ``radius`` x the diagonal."""

    center: int
    radius: float


@dataclass
class Camera:
    eye: Tuple[float, float, float]
    target: Tuple[float, float, float]
    up: Tuple[float, float, float]
    fov_y_degrees: float
    width: int
    height: int


@dataclass
class RoiSpec:
    kind: str  # water_fill, water_fill_clicks, ball, vertices or all
    first: int = 0
    last: int = 0
    camera: Optional[Camera] = None
    first_pixel: Tuple[float, float] = (0.0, 0.0)
    last_pixel: Tuple[float, float] = (0.0, 0.0)
    ball: Optional[Ball] = None
    vertices: List[int] = field(default_factory=list)


@dataclass
class Rotate:
    axis: Tuple[float, float, float]
    degrees: float
    pivot: Optional[Tuple[float, float, float]] = None  # None: the group's centroid


@dataclass
class HandleSpec:
    ball: Optional[Ball] = None
    vertices: List[int] = field(default_factory=list)
    translate: Optional[Tuple[float, float, float]] = None  # fractions of the diagonal
    rotate: Optional[Rotate] = None
    targets: List[Tuple[float, float, float]] = field(default_factory=list)


@dataclass
class SolverSpec:
    tolerance: Optional[float] = None
    max_iterations: Optional[int] = None
    handle_weight: Optional[float] = None
    method: Optional[str] = None


@dataclass
class PoseSpec:
    """The pose a skinned mesh is edited in: an animation of the file, by
    name or index, at a time in seconds."""

    animation: Union[str, int]
    time: float


@dataclass
class Scenario:
    mesh: str  # as written: a path or model:NAME
    roi: RoiSpec
    handles: List[HandleSpec]
    solver: SolverSpec
    subdivide: int = 0
    # With a pose, every position of the scenario is in the posed world
    # space; vertex indices stay the file's.
    pose: Optional[PoseSpec] = None
    base_dir: str = ""  # the file's folder, for relative mesh paths
    source: str = ""

    @property
    def mesh_path(self) -> str:
        """The mesh to load: relative paths start from the scenario's folder."""
        if self.mesh.startswith("model:") or os.path.isabs(self.mesh):
            return self.mesh
        return os.path.join(self.base_dir, self.mesh)


@dataclass
class _Field:
    """A field of the document: its value (None when missing), where to
    point (the value, or the enclosing object when missing) and its path."""

    value: Optional[Value]
    at: Tuple[int, int]
    path: str


def _member_path(obj: _Field, key: str) -> str:
    return (obj.path + "." if obj.path else "") + _json.printable(key)


def _member(obj: _Field, key: str) -> _Field:
    m = obj.value.find(key)
    return _Field(m.value if m else None, m.value.at if m else obj.at, _member_path(obj, key))


def _item(array: _Field, index: int) -> _Field:
    v = array.value.items[index]
    return _Field(v, v.at, f"{array.path}[{index}]")


def _join(names: Sequence[str], last: str) -> str:
    return "".join((("" if i == 0 else last if i + 1 == len(names) else ", ") + n)
                   for i, n in enumerate(names))


def _number_text(v: float, written_as_integer: bool) -> str:
    out = _json.number_text(v)
    # "1.0" or "1e2" must not read back as the integer they equal.
    if not written_as_integer and "." not in out and "e" not in out:
        out += ".0"
    return out


def _describe(v: Value) -> str:
    if v.kind == BOOLEAN:
        return "true" if v.boolean else "false"
    if v.kind == NUMBER:
        return _number_text(v.number, v.integer)
    if v.kind == ARRAY:
        n = len(v.items)
        return "an empty array" if n == 0 else f"an array of {n} value{'' if n == 1 else 's'}"
    return _json.TYPE_PHRASES[v.kind]


def _length(v: Sequence[float]) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def _cross(a: Sequence[float], b: Sequence[float]) -> Tuple[float, float, float]:
    return (a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1])


def _parallel(a: Sequence[float], b: Sequence[float]) -> bool:
    """Parallel or either zero, on copies scaled to a largest component of 1
    so that no product overflows."""
    def scaled(v):
        m = max(abs(v[0]), abs(v[1]), abs(v[2]))
        return tuple(c / m for c in v) if m > 0.0 else tuple(v)

    a, b = scaled(a), scaled(b)
    return _length(_cross(a, b)) <= 1e-9 * _length(a) * _length(b)


class _Reader:
    def __init__(self, source: str) -> None:
        self.source = source

    # -- messages
    def error(self, f: _Field, what: str, at: Optional[Tuple[int, int]] = None,
              path: Optional[str] = None) -> ScenarioError:
        path = f.path if path is None else path
        return ScenarioError(_json.location(self.source, at or f.at)
                             + (path + ": " if path else "") + what)

    def expected(self, f: _Field, what: str) -> ScenarioError:
        return self.error(f, f"expected {what}, found {_describe(f.value)}")

    # -- shapes
    def typed(self, f: _Field, kind: int, what: str) -> None:
        if f.value is None:
            raise self.error(f, "required field is missing")
        if f.value.kind != kind:
            raise self.expected(f, what)
        if f.value.beyond_double:
            raise self.error(f, f"the number {_json.printable(f.value.text)} is beyond the range "
                                "of a double")

    def object(self, f: _Field, known: Sequence[str]) -> None:
        self.typed(f, OBJECT, "an object")
        for m in f.value.members:
            if m.key not in known:
                raise self.error(f, f"unknown field (expected {_join(known, ' or ')})", m.at,
                                 _member_path(f, m.key))

    def exactly_one(self, f: _Field, names: Sequence[str], kind: str) -> str:
        found = None
        for m in f.value.members:
            if m.key not in names:
                continue
            if found is not None:
                raise self.error(f, f"only one {kind} is allowed, and {found} is already given",
                                 m.at, _member_path(f, m.key))
            found = m.key
        if found is None:
            raise self.error(f, f"expected one {kind} ({_join(names, ' or ')}), found none")
        return found

    def number(self, f: _Field, what: str = "a number", accept=lambda v: True) -> float:
        self.typed(f, NUMBER, what)
        if not accept(f.value):
            raise self.expected(f, what)
        return f.value.number

    def positive(self, f: _Field) -> float:
        return self.number(f, "a number greater than 0", lambda v: v.number > 0.0)

    def count(self, f: _Field, limit: int) -> int:
        what = f"a positive integer (at most {_number_text(float(limit), True)})"
        return int(self.number(f, what, lambda v: v.integer and 1.0 <= v.number <= limit))

    @staticmethod
    def optional(obj: _Field, key: str, parse, absent=None):
        """``parse`` of the member ``key`` of ``obj`` when it is there."""
        m = _member(obj, key)
        return absent if m.value is None else parse(m)

    def index(self, f: _Field) -> int:
        return int(self.number(f, INDEX_RULE,
                               lambda v: v.integer and 0.0 <= v.number <= MAX_VERTEX_INDEX))

    def index_list(self, f: _Field) -> List[int]:
        self.typed(f, ARRAY, "an array of vertex indices")
        if not f.value.items:
            raise self.expected(f, "at least one vertex index")
        out, first_seen = [], {}
        for i in range(len(f.value.items)):
            e = _item(f, i)
            v = self.index(e)
            if v in first_seen:
                raise self.error(e, f"vertex {v} is listed twice (first at [{first_seen[v]}])")
            first_seen[v] = i
            out.append(v)
        return out

    def vec(self, f: _Field, n: int) -> tuple:
        what = "an array of 2 numbers [x, y]" if n == 2 else "an array of 3 numbers [x, y, z]"
        self.typed(f, ARRAY, what)
        if len(f.value.items) != n:
            raise self.expected(f, what)
        return tuple(self.number(_item(f, i)) for i in range(n))

    # -- the format
    def scenario(self, root: Value) -> Scenario:
        top = _Field(root, root.at, "")
        self.object(top, ("mesh", "subdivide", "pose", "roi", "handles", "solver",
                          "description", "comment"))
        for note in ("description", "comment"):
            f = _member(top, note)
            if f.value is not None and f.value.kind != STRING:
                raise self.expected(f, "a string")
        mesh = self.mesh(_member(top, "mesh"))
        subdivide = self.optional(top, "subdivide", lambda f: int(self.number(
            f, "an integer from 0 to 3",
            lambda v: v.integer and 0.0 <= v.number <= MAX_SUBDIVISIONS)), 0)
        pose = None
        pose_field = _member(top, "pose")
        if pose_field.value is not None:
            if subdivide > 0:
                raise self.error(pose_field, "a pose cannot be combined with subdivide (a "
                                             "subdivided mesh has no skin)")
            pose = self.pose(pose_field)
        roi = self.roi(_member(top, "roi"))
        handles = self.handles(_member(top, "handles"))
        solver = self.optional(top, "solver", self.solver, SolverSpec())
        return Scenario(mesh, roi, handles, solver, subdivide, pose=pose, source=self.source)

    def pose(self, f: _Field) -> PoseSpec:
        self.object(f, ("animation", "time"))
        animation_field = _member(f, "animation")
        if animation_field.value is None:
            raise self.error(animation_field, "required field is missing")
        if animation_field.value.kind == STRING:
            animation: Union[str, int] = animation_field.value.text
        else:
            animation = int(self.number(
                animation_field, "an animation's name or index",
                lambda v: v.integer and 0.0 <= v.number <= 4294967295.0))
        return PoseSpec(animation, self.number(_member(f, "time")))

    def mesh(self, f: _Field) -> str:
        self.typed(f, STRING, "a string (a mesh file path or model:NAME)")
        text = f.value.text
        if not text:
            raise self.error(f, 'expected a mesh file path or model:NAME, found ""')
        if text == "model:":
            raise self.error(f, 'expected a model name after "model:"')
        if "\0" in text:
            raise self.error(f, "a mesh path cannot contain a NUL character")
        return text

    def roi(self, f: _Field) -> RoiSpec:
        kinds = ("water_fill", "water_fill_clicks", "ball", "vertices", "all")
        self.object(f, kinds)
        kind = self.exactly_one(f, kinds, "ROI kind")
        k = _member(f, kind)
        if kind == "water_fill":
            self.object(k, ("first", "last"))
            first = self.index(_member(k, "first"))
            last_field = _member(k, "last")
            last = self.index(last_field)
            # The cut plane's normal is the direction from first to last.
            if last == first:
                raise self.error(last_field, "must differ from first")
            return RoiSpec(kind, first=first, last=last)
        if kind == "water_fill_clicks":
            self.object(k, ("camera", "first", "last"))
            camera = self.camera(_member(k, "camera"))
            first = self.pixel(_member(k, "first"), camera)
            return RoiSpec(kind, camera=camera, first_pixel=first,
                           last_pixel=self.pixel(_member(k, "last"), camera))
        if kind == "ball":
            return RoiSpec(kind, ball=self.ball(k))
        if kind == "vertices":
            return RoiSpec(kind, vertices=self.index_list(k))
        if k.value.kind != BOOLEAN or not k.value.boolean:
            raise self.expected(k, "true")
        return RoiSpec(kind)

    def pixel(self, f: _Field, camera: Camera) -> Tuple[float, float]:
        x, y = self.vec(f, 2)
        w, h = float(camera.width), float(camera.height)
        if x < 0.0 or x > w or y < 0.0 or y > h:
            raise self.error(f, "the pixel lies outside the image, which runs from [0, 0] to "
                                f"[{_number_text(w, True)}, {_number_text(h, True)}]")
        return (x, y)

    def camera(self, f: _Field) -> Camera:
        self.object(f, ("eye", "target", "up", "fov_y_degrees", "width", "height"))
        eye = self.vec(_member(f, "eye"), 3)
        target_field = _member(f, "target")
        target = self.vec(target_field, 3)
        if target == eye:
            raise self.error(target_field, "must differ from eye")
        up_field = _member(f, "up")
        up = self.vec(up_field, 3)
        if _parallel(up, tuple(t - e for t, e in zip(target, eye))):
            raise self.error(up_field, "must be non-zero and not parallel to the view direction "
                                       "(target - eye)")
        fov = self.number(_member(f, "fov_y_degrees"),
                          "an angle in degrees between 0 and 180, both excluded",
                          lambda v: 0.0 < v.number < 180.0)
        width = self.count(_member(f, "width"), 4294967295)
        height = self.count(_member(f, "height"), 4294967295)
        return Camera(eye, target, up, fov, width, height)

    def ball(self, f: _Field) -> Ball:
        self.object(f, ("center", "radius"))
        center = self.index(_member(f, "center"))
        return Ball(center, self.positive(_member(f, "radius")))

    def handles(self, f: _Field) -> List[HandleSpec]:
        self.typed(f, ARRAY, "an array of handle groups")
        if not f.value.items:
            raise self.expected(f, "at least one handle group")
        return [self.handle(_item(f, i)) for i in range(len(f.value.items))]

    def handle(self, f: _Field) -> HandleSpec:
        self.object(f, ("vertices", "ball", "translate", "rotate", "targets"))
        out = HandleSpec()
        if self.exactly_one(f, ("vertices", "ball"), "selection") == "ball":
            out.ball = self.ball(_member(f, "ball"))
        else:
            out.vertices = self.index_list(_member(f, "vertices"))
        out.translate = self.optional(f, "translate", lambda t: self.vec(t, 3))
        out.rotate = self.optional(f, "rotate", self.rotate)
        targets = _member(f, "targets")
        if targets.value is None:
            return out
        if out.ball is not None:
            raise self.error(targets, "needs a vertices list (one target per vertex), not a ball")
        # Absolute positions leave nothing for a relative motion to do.
        if out.translate is not None or out.rotate is not None:
            raise self.error(targets, "cannot be combined with translate or rotate")
        n = len(out.vertices)
        self.typed(targets, ARRAY, "an array of [x, y, z] targets")
        if len(targets.value.items) != n:
            raise self.expected(targets, f"{n} target{'' if n == 1 else 's'}, one per vertex")
        out.targets = [self.vec(_item(targets, i), 3) for i in range(n)]
        return out

    def rotate(self, f: _Field) -> Rotate:
        self.object(f, ("axis", "degrees", "pivot"))
        axis_field = _member(f, "axis")
        axis = self.vec(axis_field, 3)
        if axis == (0.0, 0.0, 0.0):
            raise self.error(axis_field, "must not be the zero vector")
        out = Rotate(axis, self.number(_member(f, "degrees")))
        pivot = _member(f, "pivot")
        if pivot.value is None:
            return out
        if pivot.value.kind == STRING:
            if pivot.value.text == "centroid":
                return out
            raise self.error(pivot, 'expected [x, y, z] or "centroid", found "'
                                    + _json.printable(pivot.value.text) + '"')
        if pivot.value.kind != ARRAY:
            raise self.expected(pivot, '[x, y, z] or "centroid"')
        out.pivot = self.vec(pivot, 3)
        return out

    def solver(self, f: _Field) -> SolverSpec:
        self.object(f, ("tolerance", "max_iterations", "handle_weight", "method"))
        out = SolverSpec()
        out.tolerance = self.optional(f, "tolerance", self.positive)
        out.max_iterations = self.optional(f, "max_iterations", lambda m: self.count(m, 2147483647))
        out.handle_weight = self.optional(f, "handle_weight", self.positive)
        m = _member(f, "method")
        if m.value is not None:
            if m.value.kind != STRING or m.value.text not in ("fitted_rotations", "paper"):
                raise self.expected(m, '"fitted_rotations" or "paper"')
            out.method = m.value.text
        return out


def parse_scenario(text: bytes, source: str) -> Scenario:
    """Parses scenario JSON; ``source`` names it in messages. Raises
    :class:`ScenarioError`."""
    try:
        root = _json.parse(text, source, keep_huge_numbers=True)
    except _json.JsonError as error:
        raise ScenarioError(str(error)) from None
    return _Reader(source).scenario(root)


def _read_file(name: str) -> bytes:
    try:
        st = os.stat(name)
    except (FileNotFoundError, NotADirectoryError):
        raise ScenarioError(f"{name}: no such scenario file", Result.ERROR_NOT_FOUND) from None
    except OSError as error:
        raise ScenarioError(f"{name}: cannot access: {error.strerror}", Result.ERROR_IO) from None
    if stat.S_ISDIR(st.st_mode):
        raise ScenarioError(f"{name}: is a directory, not a scenario file", Result.ERROR_IO)
    # A device or pipe could feed bytes forever.
    if not stat.S_ISREG(st.st_mode):
        raise ScenarioError(f"{name}: is not a regular file", Result.ERROR_IO)
    try:
        with open(name, "rb") as f:
            return f.read()
    except OSError as error:
        reason = os.strerror(error.errno or errno.EIO)
        raise ScenarioError(f"{name}: cannot open: {reason}", Result.ERROR_IO) from None


def load_scenario(path: os.PathLike) -> Scenario:
    """Reads and parses a scenario file, named in messages as given."""
    name = os.fspath(path)
    scenario = parse_scenario(_read_file(name), name)
    scenario.base_dir = os.path.dirname(name)
    return scenario
