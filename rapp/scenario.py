"""Scenario files: the JSON input set of 2D-RAPP, its validation and its echo.

A scenario is one JSON object (every key, unit, default and range: the book's "Scenario
files" page, ``book/scenario_format.md``)::

    {"arm": {"link_lengths": [1, 1], "joint_limits": null},
     "obstacles": [{"type": "circle", "center": [1.75, 0.75], "radius": 0.6}],
     "start": [0, 0],
     "goal": {"position": [-1.2, 0.8]},
     "units": {"angle": "rad", "length": "m"},
     "planner": {"algorithm": "astar", "cells": 100},
     "trajectory": {"duration": 5.0, "profile": "quintic", "samples": 200}}

:func:`load_scenario` raises :class:`~rapp.errors.FileNotFound`,
:class:`~rapp.errors.InvalidFormat` (not JSON, wrong types, unknown keys),
:class:`~rapp.errors.MissingParameter` and :class:`~rapp.errors.InvalidValue`
(a physical constraint broken), each with ``.field`` naming the entry as a
dotted path such as ``"obstacles[2].radius"``. The software ranges of SRS
Table 4 are not errors: they become ``scenario.warnings`` and are echoed,
because the other seeds use arms outside them.

References
----------
SRS of 2D-RAPP (seed 000): R1 (input), R2 (validate and echo), NFR5, Table 4 (software ranges).
MIS of 2D-RAPP (seed 001): ``loadParams`` and its exceptions.
"""

from __future__ import annotations

import json
import math
import os
import stat
from dataclasses import dataclass, field as dc_field
from importlib import resources
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.arm import Arm
from rapp.errors import FileNotFound, InvalidFormat, InvalidValue, MissingParameter
from rapp.collision import clearance, collides, segment_point_distance
from rapp.cspace import check_extent
from rapp.obstacles import Circle, Polygon
from rapp import planners as planner_table
from rapp.grid_route import default_cells
from rapp.prm import MAX_SAMPLES, MEMORY_BUDGET as PRM_MEMORY_BUDGET, largest_roadmap, roadmap_bytes

__all__ = [
    "Scenario",
    "PlannerSettings",
    "TrajectorySettings",
    "load_scenario",
    "list_scenarios",
    "echo",
    "preflight",
    "L_MIN",
    "L_MAX",
    "R_MAX",
    "max_cells",
    "bytes_per_cell",
    "MEMORY_BUDGET",
    "MIN_LENGTH",
    "MAX_LENGTH",
    "MAX_COORDINATE",
    "MAX_ANGLE",
    "MIN_DURATION",
    "MAX_DURATION",
    "MIN_RATE_LIMIT",
    "MAX_RATE_LIMIT",
    "PROFILES",
    "GOAL_PATHS",
    "MAX_LINKS",
    "MAX_OBSTACLES",
    "ALGORITHMS",
    "check_limits",
    "SETTINGS_OF",
    "TOP_KEYS",
    "TRAJECTORY_KEYS",
    "ARM_OPTIONAL_KEYS",
]

#: SRS Table 4 software ranges (warnings, not errors).
L_MIN, L_MAX, R_MAX = 0.1, 2.0, 0.5
#: Physical ranges (errors): every length (link, radius, width, height) in metres, every
#: coordinate, every angle in radians, the duration in seconds. Wide enough for any arm a
#: planar planner is used on (millimetres to kilometres), narrow enough that every number the
#: pipeline derives from them stays far from overflow and rounding trouble.
MIN_LENGTH, MAX_LENGTH = 1e-3, 1e3
#: Smallest non-zero link radius or safety margin (m): a polygon's edge (at most a few 1e4 m
#: in a scenario) grown by less than 1e-12 of its length flattens to a line in float64.
MIN_GAP = 1e-6
MAX_COORDINATE = 1e4
MAX_ANGLE = 100.0
MIN_DURATION, MAX_DURATION = 1e-3, 1e6
#: Range (errors) of every joint speed limit (rad/s) and acceleration limit (rad/s^2), after
#: conversion from degrees: slow or fast enough for any arm, and far from overflow.
MIN_RATE_LIMIT, MAX_RATE_LIMIT = 1e-6, 1e6
MAX_LINKS = 16
#: Peak resident memory the grid pipeline may use (bytes). Every accepted scenario stays
#: under 2 GB: the budget leaves room for Python, numpy and the rest of the process.
MEMORY_BUDGET = 1.5e9
#: Peak bytes per grid cell of the whole pipeline (occupancy, certified cells, search,
#: shortcut, timing, verification), measured by ``benchmarks/bench_memory.py`` and recorded
#: in ``rapp/recorded/memory.json``; an arm with n joints needs at most about
#: ``bytes_per_cell(n)`` (the search's neighbour tables grow with n, hence the square).
BYTES_PER_CELL_FIXED = 60
BYTES_PER_CELL_PER_JOINT = 40
BYTES_PER_CELL_PER_JOINT_SQUARED = 10
#: Joints up to which A* on a grid is the default planner; above it the default is RRT,
#: because a grid fine enough to plan on would not fit in memory.
GRID_DEFAULT_MAX_JOINTS = 6
MAX_FILE_BYTES = 10_000_000
MAX_SAMPLES = 1_000_000
#: The planners' names and the settings each reads, as the planner table
#: (:data:`rapp.planners.PLANNERS`) says when rapp is imported; the loader reads the table itself.
ALGORITHMS = planner_table.names()
SETTINGS_OF = MappingProxyType({name: p.keys for name, p in planner_table.PLANNERS.items()})
#: Samples per second of motion at most (above SAMPLES_ANY_RATE): a robot's servo loop runs at
#: about 1 kHz, so denser samples describe nothing a controller could follow, and each costs
#: about 15 us of timing and verification (a million take 15 s).
MAX_SAMPLE_RATE = 1000.0
#: Samples any trajectory may have, whatever its duration.
SAMPLES_ANY_RATE = 10_000
#: Obstacles at most. Every stage (occupancy, certification, shortcut, timing, verification)
#: costs time linear in the number of obstacles: about 1.5 ms each on a default 100 x 100 plan
#: (measured: 1,000 far-away discs add 1.4 s, 10,000 add 15 s), so this keeps a plan within a
#: couple of seconds of its obstacle-free time. A file can hold 100,000 (MAX_FILE_BYTES).
MAX_OBSTACLES = 1000


def bytes_per_cell(n: int) -> int:
    """Peak bytes per grid cell of the planning pipeline for an arm of ``n`` joints (a bound).

    Examples
    --------
    >>> bytes_per_cell(2), bytes_per_cell(8)
    (180, 1020)
    """
    return BYTES_PER_CELL_FIXED + BYTES_PER_CELL_PER_JOINT * n + BYTES_PER_CELL_PER_JOINT_SQUARED * n * n


def max_cells(n: int) -> int:
    """The largest joint grid (total cells) accepted for an arm of ``n`` joints.

    The memory budget divided by the measured peak bytes per cell.

    Examples
    --------
    >>> max_cells(2), max_cells(3)
    (8333333, 5555555)
    """
    return int(MEMORY_BUDGET // bytes_per_cell(n))


#: The time profiles of ``trajectory.profile``: the three of :func:`rapp.time_scaling.time_path`
#: and the trapezoid (LSPB) of :func:`rapp.time_scaling.trapezoidal_path`.
PROFILES = ("cubic", "quintic", "spline", "trapezoidal")
#: The values of ``goal.path``: ``"line"`` moves the end effector along the straight segment
#: from its start position to ``goal.position`` (:func:`rapp.cartesian.line_path`).
GOAL_PATHS = ("line",)

#: The keys of a scenario file's top level (rapp.schema builds the JSON Schema from these).
TOP_KEYS = ("arm", "obstacles", "start", "goal", "units", "planner", "trajectory", "name",
            "description", "safety_margin")
_TOP_KEYS = TOP_KEYS
#: The keys of ``trajectory``.
TRAJECTORY_KEYS = ("duration", "profile", "samples", "dt", "max_velocity", "max_acceleration")
_TRAJECTORY_KEYS = TRAJECTORY_KEYS
#: The keys ``arm`` accepts besides ``link_lengths``.
ARM_OPTIONAL_KEYS = ("joint_limits", "link_radius", "self_collision", "joint_names", "base",
                     "joint_offsets")
#: The keys ``planner`` accepts and those only sampling planners read (A* validates them, then
#: warns they are ignored), from the planner table at import (the loader reads the table).
_PLANNER_KEYS = ("algorithm",) + tuple(planner_table.all_settings())
_SAMPLING_KEYS = tuple(k for k, v in planner_table.all_settings().items() if v.warns_when_ignored)


@dataclass(frozen=True)
class PlannerSettings:
    """How to search: ``algorithm`` (one of :data:`ALGORITHMS`) and its settings (radians, seconds)."""

    algorithm: str = "astar"
    cells: tuple = (100, 100)
    heuristic_weight: float = 1.0
    max_expansions: int | None = None
    seed: int = 0
    step: float = 0.1
    goal_bias: float = 0.1
    goal_threshold: float = 0.01
    max_iterations: int = 20000
    time_budget: float | None = None
    samples: int = 10
    neighbours: int = 10
    #: ``(key, value)`` pairs of settings that are not fields above: those of a planner added to
    #: the table with a setting of its own. Read as attributes too.
    extra: tuple = ()

    def __getattr__(self, name):
        if name.startswith("__") or name == "extra":
            raise AttributeError(name)
        for key, value in self.extra:
            if key == name:
                return value
        raise AttributeError(f"no planner setting {name!r}")

    def values(self) -> dict:
        """The settings ``algorithm`` reads, by key: what :func:`rapp.plan` passes to it.

        Examples
        --------
        >>> PlannerSettings(algorithm="prm").values()
        {'samples': 10, 'neighbours': 10, 'max_iterations': 20000, 'seed': 0, 'time_budget': None}
        """
        return {k: getattr(self, k) for k in planner_table.entry(self.algorithm).keys}


@dataclass(frozen=True)
class TrajectorySettings:
    """How to time the path: total ``duration`` (s), ``profile``, number of ``samples``, and
    optional joint limits ``max_velocity`` (rad/s) and ``max_acceleration`` (rad/s^2), one
    per joint (``None``: unbounded).

    ``duration`` is ``None`` when limits are given without it: the plan then takes the
    shortest duration within the limits (:func:`rapp.plan`).
    """

    duration: float | None = 5.0
    profile: str = "quintic"
    samples: int = 200
    max_velocity: tuple | None = None
    max_acceleration: tuple | None = None
    #: A fixed time step (s) instead of a sample count: samples at ``0, dt, 2 dt, ...`` and the
    #: end (:func:`rapp.timing.sample_times`); ``None``: ``samples`` even times.
    dt: float | None = None

    @property
    def limited(self) -> bool:
        """Whether a velocity or an acceleration limit is given.

        Examples
        --------
        >>> TrajectorySettings().limited, TrajectorySettings(max_velocity=(1.0,)).limited
        (False, True)
        """
        return self.max_velocity is not None or self.max_acceleration is not None


@dataclass(frozen=True, eq=False)
class Scenario:
    """A validated scenario, every angle in radians and every length in metres.

    Exactly one of ``goal_q`` (joint goal) and ``goal_xy`` (Cartesian goal,
    solved by IK in :func:`rapp.plan`) is set. ``goal_path`` is ``"line"`` when
    the end effector must follow the straight segment to ``goal_xy``, else ``None``.

    Examples
    --------
    >>> s = load_scenario("default")
    >>> s.arm.link_lengths, len(s.obstacles), s.goal_xy is not None
    ((1.0, 1.0), 3, True)
    >>> load_scenario(s.to_dict()) == s
    True
    """

    arm: Arm
    obstacles: tuple
    start: tuple
    goal_q: tuple | None = None
    goal_xy: tuple | None = None
    planner: PlannerSettings = dc_field(default_factory=PlannerSettings)
    trajectory: TrajectorySettings = dc_field(default_factory=TrajectorySettings)
    name: str = ""
    description: str = ""
    angle_unit: str = "rad"
    warnings: tuple = ()
    source: str = "<mapping>"
    goal_path: str | None = None
    #: Metres every link keeps beyond its radius (``arm.link_radius``) from every obstacle.
    safety_margin: float = 0.0

    def __eq__(self, other):
        # The source and the declared unit say where the values came from, not what they are.
        return isinstance(other, Scenario) and self.to_dict() == other.to_dict()

    __hash__ = None

    @property
    def start_array(self) -> np.ndarray:
        """``start`` as a float array of shape ``(n,)``.

        Examples
        --------
        >>> load_scenario("default").start_array.shape
        (2,)
        """
        return np.array(self.start, dtype=float)

    def to_dict(self) -> dict:
        """The canonical JSON mapping (radians), accepted again by :func:`load_scenario`.

        Examples
        --------
        >>> d = load_scenario({"arm": {"link_lengths": [1, 1]}, "start": [0, 0],
        ...                    "goal": {"joints": [90, 0]}, "units": {"angle": "deg"}}).to_dict()
        >>> d["units"], round(d["goal"]["joints"][0], 6)
        ({'angle': 'rad', 'length': 'm'}, 1.570796)
        """
        obs = []
        for ob in self.obstacles:
            if isinstance(ob, Circle):
                obs.append({"type": "circle", "center": list(ob.center), "radius": ob.radius})
            else:
                obs.append({"type": "polygon", "vertices": [list(v) for v in ob.vertices]})
        limits = self.arm.joint_limits
        p = self.planner
        keys = ("cells", "heuristic_weight", "max_expansions", "seed") + tuple(p.values())
        planner = {"algorithm": p.algorithm, **{k: getattr(p, k) for k in dict.fromkeys(keys)}}
        planner["cells"] = list(p.cells)
        arm = {
            "link_lengths": list(self.arm.link_lengths),
            "joint_limits": None if all(x is None for x in limits)
            else [None if x is None else list(x) for x in limits],
        }
        if any(self.arm.link_radius):  # written only when set: older files round-trip unchanged
            arm["link_radius"] = list(self.arm.link_radius)
        if self.arm.self_collision:  # written only when set, as link_radius
            arm["self_collision"] = True
        extra = {"safety_margin": self.safety_margin} if self.safety_margin else {}
        return {
            "name": self.name,
            "description": self.description,
            "arm": {**arm, **self._frame_dict()},
            **extra,
            "obstacles": obs,
            "start": list(self.start),
            "goal": self._goal_dict(),
            "units": {"angle": "rad", "length": "m"},
            "planner": planner,
            "trajectory": self._trajectory_dict(),
        }

    def _frame_dict(self) -> dict:
        """The arm's names, base and offsets, each only when it is not the default."""
        arm, out = self.arm, {}
        if arm.joint_names != tuple(f"joint{i + 1}" for i in range(arm.n)):
            out["joint_names"] = list(arm.joint_names)
        if any(arm.base):
            out["base"] = dict(zip(("x", "y", "heading"), arm.base))
        if any(arm.joint_offsets):
            out["joint_offsets"] = list(arm.joint_offsets)
        return out

    def _goal_dict(self) -> dict:
        if self.goal_q is not None:
            return {"joints": list(self.goal_q)}
        goal = {"position": list(self.goal_xy)}
        if self.goal_path is not None:
            goal["path"] = self.goal_path
        return goal

    def _trajectory_dict(self) -> dict:
        t = self.trajectory
        out = {} if t.duration is None else {"duration": t.duration}
        out.update(profile=t.profile, **({"samples": t.samples} if t.dt is None else {"dt": t.dt}))
        if t.max_velocity is not None:
            out["max_velocity"] = list(t.max_velocity)
        if t.max_acceleration is not None:
            out["max_acceleration"] = list(t.max_acceleration)
        return out


# --------------------------------------------------------------------------- reading


class _NonFinite:
    """Stands for a NaN/Infinity token so that validation can name its field."""

    def __init__(self, token):
        self.token = token


class _HugeInteger(_NonFinite):
    """Stands for an integer literal too long to be a number of any scenario field.

    Python refuses to convert integers of more than 4300 digits, which would
    otherwise surface as a parse error of the whole file instead of the field.
    """

    def __init__(self, digits: str):
        super().__init__(f"an integer of {len(digits.lstrip('-'))} digits")


def _parse_int(digits: str):
    return int(digits) if len(digits) <= 400 else _HugeInteger(digits)


def _pairs(pairs):
    out = {}
    for k, v in pairs:
        if k in out:
            raise InvalidFormat(f"duplicate key {k!r}", field=k)
        out[k] = v
    return out


def _read_json(path) -> Any:
    name = os.fspath(path)
    try:
        info = os.stat(name)
    except FileNotFoundError:
        raise FileNotFound(f"no such file {name!r}", field="scenario") from None
    except (OSError, ValueError) as e:  # ValueError: an embedded NUL byte
        raise FileNotFound(f"cannot read {name!r}: {_why(e)}", field="scenario") from None
    if stat.S_ISDIR(info.st_mode):
        raise FileNotFound(f"{name!r} is a directory, not a scenario file", field="scenario")
    if not stat.S_ISREG(info.st_mode):
        # A FIFO would block until someone writes to it, a device may never end: refuse both.
        raise FileNotFound(f"{name!r} is not a regular file ({_file_kind(info.st_mode)})",
                           field="scenario")
    try:
        # O_NONBLOCK: should the name be swapped for a FIFO after the check, open() still
        # returns at once, and fstat below refuses it.
        fd = os.open(name, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise FileNotFound(f"no such file {name!r}", field="scenario") from None
    except (OSError, ValueError) as e:
        raise FileNotFound(f"cannot read {name!r}: {_why(e)}", field="scenario") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise FileNotFound(f"{name!r} is not a regular file", field="scenario")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        with os.fdopen(fd, "rb") as fh:
            fd = -1
            raw = fh.read(MAX_FILE_BYTES + 1)
    except OSError as e:
        raise FileNotFound(f"cannot read {name!r}: {_why(e)}", field="scenario") from None
    finally:
        if fd >= 0:
            os.close(fd)
    if len(raw) > MAX_FILE_BYTES:
        raise InvalidFormat(f"file is larger than {MAX_FILE_BYTES} bytes", field="scenario")
    return _parse_bytes(raw)


def _why(e: Exception) -> str:
    return (getattr(e, "strerror", None) or str(e) or type(e).__name__).splitlines()[0]


def _file_kind(mode: int) -> str:
    for test, kind in ((stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return kind
    return "not a file"


def _parse_bytes(raw: bytes) -> Any:
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise InvalidFormat(
            f"not UTF-8 text (byte 0x{raw[e.start]:02x} at offset {e.start})", field="scenario"
        ) from None
    if not text.strip():
        raise InvalidFormat("the file is empty; expected a JSON object", field="scenario")
    try:
        return json.loads(text, parse_constant=_NonFinite, parse_int=_parse_int,
                          object_pairs_hook=_pairs)
    except json.JSONDecodeError as e:
        raise InvalidFormat(
            f"not valid JSON: {e.msg} at line {e.lineno} column {e.colno}", field="scenario"
        ) from None
    except RecursionError:
        raise InvalidFormat("JSON is nested too deeply", field="scenario") from None
    except ValueError as e:  # e.g. an integer literal with too many digits
        raise InvalidFormat(f"not valid JSON: {str(e).splitlines()[0]}", field="scenario") from None


def _embedded(name: str):
    return resources.files("rapp").joinpath("scenarios", f"{name}.json")


def list_scenarios() -> list:
    """Names of the embedded scenarios (package data in ``rapp/scenarios``).

    Examples
    --------
    >>> "default" in list_scenarios()
    True
    """
    folder = resources.files("rapp").joinpath("scenarios")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".json"))


# --------------------------------------------------------------------------- typed fields


def _type_name(v) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, str):
        return "a string"
    if isinstance(v, (list, tuple)):
        return "a list"
    if isinstance(v, Mapping):
        return "an object"
    if isinstance(v, _NonFinite):
        return v.token
    return type(v).__name__


def _number(v, field: str) -> float:
    if isinstance(v, _HugeInteger):
        raise InvalidValue(f"{v.token} is too large", field=field)
    if isinstance(v, _NonFinite):
        raise InvalidValue(f"{v.token} is not a finite number", field=field)
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise InvalidFormat(f"expected a number, got {_type_name(v)}", field=field)
    try:
        x = float(v)
    except OverflowError:
        raise InvalidValue("number is too large", field=field) from None
    if not math.isfinite(x):
        raise InvalidValue(f"{x} is not a finite number", field=field)
    return x


def _integer(v, field: str, lo: int, hi: int | None = None) -> int:
    if isinstance(v, float) and math.isfinite(v) and v == int(v):
        v = int(v)
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
        if isinstance(v, (float, _NonFinite)):
            _number(v, field)
            raise InvalidValue(f"expected an integer, got {v}", field=field)
        raise InvalidFormat(f"expected an integer, got {_type_name(v)}", field=field)
    v = int(v)
    if v < lo or (hi is not None and v > hi):
        rng = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise InvalidValue(f"must be an integer {rng}, got {v}", field=field)
    return v


def _string(v, field: str, choices=None) -> str:
    if not isinstance(v, str):
        raise InvalidFormat(f"expected a string, got {_type_name(v)}", field=field)
    if choices is not None and v not in choices:
        raise InvalidValue(f"must be one of {', '.join(map(repr, choices))}, got {v!r}", field=field)
    return v


def _list(v, field: str, length: int | None = None, what: str = "entries") -> list:
    if not isinstance(v, (list, tuple)):
        raise InvalidFormat(f"expected a list, got {_type_name(v)}", field=field)
    if length is not None and len(v) != length:
        raise InvalidValue(f"expected {length} {what}, got {len(v)}", field=field)
    return list(v)


def _numbers(v, field: str, length: int | None = None, what: str = "numbers") -> list:
    items = _list(v, field, length, what)
    return [_number(x, f"{field}[{i}]") for i, x in enumerate(items)]


def _distance_from_base(poly: Polygon) -> float:
    """Distance from the arm's base (the origin) to a convex polygon; 0 when it holds the base.

    The nearest point of a polygon can lie on an edge, far from every vertex,
    so the vertices alone would call a long wall that passes near the base
    unreachable.

    Examples
    --------
    >>> wall = Polygon.rectangle((-5.0, 1.5), 10.0, 0.2)
    >>> round(_distance_from_base(wall), 12)
    1.5
    """
    if poly.contains((0.0, 0.0)):
        return 0.0
    v = poly.array
    return float(segment_point_distance(v, np.roll(v, -1, axis=0), np.zeros(2)).min())


def _object(v, field: str, required=(), optional=()) -> dict:
    where = field or "scenario"
    if not isinstance(v, Mapping):
        raise InvalidFormat(f"expected a JSON object, got {_type_name(v)}", field=where)
    prefix = f"{field}." if field else ""
    for k in v:
        if not isinstance(k, str) or k not in required and k not in optional:
            known = ", ".join(dict.fromkeys(list(required) + list(optional)))
            # A key that is empty or not a plain word is shown quoted so the field is never blank.
            name = k if isinstance(k, str) and k.isidentifier() else repr(k)
            raise InvalidFormat(f"unknown key {k!r} (known keys: {known})", field=f"{prefix}{name}")
    for k in required:
        if k not in v:
            raise MissingParameter(f"required key {k!r} is missing", field=f"{prefix}{k}")
    return dict(v)


# --------------------------------------------------------------------------- validation


class _Reader:
    """Reads the typed fields of one scenario mapping; collects the Table 4 warnings.

    ``k`` converts the file's angle unit to radians.
    """

    def __init__(self, k: float):
        self.k = k
        self.warnings: list = []

    def angle(self, v, field: str) -> float:
        a = _number(v, field)
        if not -MAX_ANGLE <= a * self.k <= MAX_ANGLE:
            raise InvalidValue(f"|angle| must be at most {MAX_ANGLE:g} rad, got {a:.4g}", field=field)
        return a * self.k

    def angles(self, values, field: str) -> list:
        return [self.angle(v, f"{field}[{i}]") for i, v in enumerate(values)]

    def warn_outside_pi(self, values, field: str) -> None:
        for i, a in enumerate(values):
            if not -math.pi - 1e-12 <= a <= math.pi + 1e-12:
                self.warnings.append(f"{field}[{i}] = {a:.4g} rad is outside the SRS range [-pi, pi]")

    def length(self, v, field: str, what: str = "length") -> float:
        x = _number(v, field)
        if x <= 0:
            raise InvalidValue(f"{what} must be > 0 m, got {x:g}", field=field)
        if not MIN_LENGTH <= x <= MAX_LENGTH:
            raise InvalidValue(f"{what} must lie in [{MIN_LENGTH:g}, {MAX_LENGTH:g}] m, got {x:g}",
                               field=field)
        return x

    def point(self, v, field: str) -> list:
        xy = _numbers(v, field, 2)
        for i, c in enumerate(xy):
            if abs(c) > MAX_COORDINATE:
                raise InvalidValue(f"coordinates must lie within +-{MAX_COORDINATE:g} m, got {c:g}",
                                   field=f"{field}[{i}]")
        return xy


def _parse_arm(r: _Reader, v) -> Arm:
    arm_d = _object(v, "arm", required=("link_lengths",), optional=ARM_OPTIONAL_KEYS)
    items = _list(arm_d["link_lengths"], "arm.link_lengths")
    if not items:
        raise InvalidValue("the arm needs at least one link", field="arm.link_lengths")
    if len(items) > MAX_LINKS:
        raise InvalidValue(f"at most {MAX_LINKS} links are supported, got {len(items)}",
                           field="arm.link_lengths")
    lengths = [r.length(x, f"arm.link_lengths[{i}]", "link length") for i, x in enumerate(items)]
    for i, L in enumerate(lengths):
        if not L_MIN <= L <= L_MAX:
            r.warnings.append(f"arm.link_lengths[{i}] = {L:g} m is outside the SRS range "
                              f"[{L_MIN}, {L_MAX}] m")
    n = len(lengths)
    radius = _link_radius(r, arm_d.get("link_radius", 0.0), n)
    self_collision = arm_d.get("self_collision", False)
    if not isinstance(self_collision, bool):
        raise InvalidValue(f"must be true or false, got {self_collision!r}", field="arm.self_collision")
    frame = _parse_frame(r, arm_d, n)
    limits_v = arm_d.get("joint_limits")
    if limits_v is None:
        return Arm(lengths, link_radius=radius, self_collision=self_collision, **frame)
    items = _list(limits_v, "arm.joint_limits", n, f"entries (one per joint; the arm has {n})")
    limits = []
    for i, lim in enumerate(items):
        f = f"arm.joint_limits[{i}]"
        if lim is None:
            limits.append(None)
            continue
        lo, hi = r.angles(_list(lim, f, 2, "numbers [lo, hi]"), f)
        if not lo < hi:
            raise InvalidValue(f"needs lo < hi, got [{lo:.4g}, {hi:.4g}] rad", field=f)
        if hi - lo > 2 * math.pi + 1e-9:
            raise InvalidValue(f"spans {hi - lo:.4g} rad > 2 pi; use null for a free joint", field=f)
        r.warn_outside_pi([lo, hi], f)
        limits.append((lo, hi))
    return Arm(lengths, limits, link_radius=radius, self_collision=self_collision, **frame)


def _gap(v, field: str) -> float:
    """A width or margin in metres: finite, >= 0 and at most MAX_LENGTH."""
    x = _number(v, field)
    if not (x == 0 or MIN_GAP <= x <= MAX_LENGTH):
        raise InvalidValue(f"must be 0 or lie in [{MIN_GAP:g}, {MAX_LENGTH:g}] m, got {x:g}",
                           field=field)
    return x


def _link_radius(r: "_Reader", v, n: int) -> list:
    """``arm.link_radius``: one number for every link, or a list of one per link."""
    if isinstance(v, list):
        items = _list(v, "arm.link_radius", n, f"entries (one per link; the arm has {n})")
        return [_gap(x, f"arm.link_radius[{i}]") for i, x in enumerate(items)]
    return [_gap(v, "arm.link_radius")] * n


def _parse_frame(r: _Reader, arm_d: dict, n: int) -> dict:
    """``joint_names``, ``base`` and ``joint_offsets`` of ``arm`` as :class:`rapp.Arm` takes them."""
    out: dict = {}
    if arm_d.get("joint_names") is not None:
        names = _list(arm_d["joint_names"], "arm.joint_names", n, f"names (one per joint; the arm has {n})")
        out["joint_names"] = [_string(s, f"arm.joint_names[{i}]") for i, s in enumerate(names)]
        for i, s in enumerate(out["joint_names"]):
            if not s or s in out["joint_names"][:i]:
                raise InvalidValue(f"must be a non-empty name, distinct from the others, got {s!r}",
                                   field=f"arm.joint_names[{i}]")
    if arm_d.get("base") is not None:
        base = _object(arm_d["base"], "arm.base", optional=("x", "y", "heading"))
        x, y = r.point([base.get("x", 0.0), base.get("y", 0.0)], "arm.base")
        out["base"] = (x, y, r.angle(base.get("heading", 0.0), "arm.base.heading"))
    if arm_d.get("joint_offsets") is not None:
        items = _list(arm_d["joint_offsets"], "arm.joint_offsets", n,
                      f"angles (one per joint; the arm has {n})")
        out["joint_offsets"] = r.angles(items, "arm.joint_offsets")
    return out


def _build(constructor, field: str, *args):
    """``constructor(*args)``; its ValueError (e.g. a 1e-3 x 1e3 sliver) becomes InvalidValue at
    ``field.<the argument it names>`` when the message starts with one, else at ``field``."""
    try:
        return constructor(*args)
    except ValueError as e:
        first = str(e).split(" ", 1)[0]
        sub = first if first in ("center", "radius", "corner", "width", "height", "angle") else ""
        raise InvalidValue(str(e), field=f"{field}.{sub}" if sub else field) from None


def _parse_obstacle(r: _Reader, ob, f: str):
    """One obstacle and its distance from the base (for the out-of-reach warning)."""
    if not isinstance(ob, Mapping):
        raise InvalidFormat(f"expected a JSON object, got {_type_name(ob)}", field=f)
    if "type" not in ob:
        raise MissingParameter("required key 'type' is missing "
                               "('circle', 'rectangle' or 'polygon')", field=f"{f}.type")
    kind = _string(ob["type"], f"{f}.type", ("circle", "rectangle", "polygon"))
    if kind == "circle":
        d = _object(ob, f, required=("type", "center", "radius"))
        c = r.point(d["center"], f"{f}.center")
        rad = r.length(d["radius"], f"{f}.radius", "radius")
        if rad > R_MAX:
            r.warnings.append(f"{f}.radius = {rad:g} m is above the SRS r_max = {R_MAX} m")
        return _build(Circle, f, c, rad), math.hypot(*c) - rad
    if kind == "rectangle":
        d = _object(ob, f, required=("type", "corner", "width", "height"), optional=("angle",))
        c = r.point(d["corner"], f"{f}.corner")
        w = r.length(d["width"], f"{f}.width", "width")
        h = r.length(d["height"], f"{f}.height", "height")
        poly = _build(Polygon.rectangle, f, c, w, h, r.angle(d.get("angle", 0.0), f"{f}.angle"))
        return poly, _distance_from_base(poly)
    d = _object(ob, f, required=("type", "vertices"))
    verts = _list(d["vertices"], f"{f}.vertices")
    if len(verts) < 3:
        raise InvalidValue(f"a polygon needs at least 3 vertices, got {len(verts)}",
                           field=f"{f}.vertices")
    pts = [r.point(v, f"{f}.vertices[{j}]") for j, v in enumerate(verts)]
    try:
        poly = Polygon(pts)
    except ValueError as e:
        raise InvalidValue(str(e), field=f"{f}.vertices") from None
    return poly, _distance_from_base(poly)


def _parse_obstacles(r: _Reader, v, arm: Arm) -> tuple:
    out = []
    items = _list(v, "obstacles")
    _check_obstacle_count(len(items))
    for i, ob in enumerate(items):
        f = f"obstacles[{i}]"
        obstacle, far = _parse_obstacle(r, ob, f)
        if far > arm.reach[1]:
            r.warnings.append(f"{f} lies beyond the arm's reach ({arm.reach[1]:g} m); it cannot collide")
        out.append(obstacle)
    return tuple(out)


def _check_obstacle_count(k: int) -> None:
    if k > MAX_OBSTACLES:
        raise InvalidValue(f"at most {MAX_OBSTACLES} obstacles are supported, got {k} (each "
                           "adds about 1.5 ms to every plan)", field="obstacles")


def _parse_joints(r: _Reader, v, arm: Arm, field: str) -> tuple:
    n = arm.n
    q = r.angles(_list(v, field, n, f"joint angles (the arm has {n} joints)"), field)
    _within_limits(arm, q, field)
    r.warn_outside_pi(q, field)
    return tuple(q)


def _parse_goal(r: _Reader, v, arm: Arm):
    """``(goal_q, goal_xy, goal_path)``, exactly one of the first two set."""
    goal_d = _object(v, "goal", optional=("joints", "position", "path"))
    if ("joints" in goal_d) == ("position" in goal_d):
        raise (InvalidFormat if goal_d else MissingParameter)(
            "give exactly one of 'joints' or 'position'", field="goal")
    path = None
    if "path" in goal_d:
        path = _string(goal_d["path"], "goal.path", GOAL_PATHS)
        if "joints" in goal_d:
            raise InvalidValue(f"{path!r} needs a Cartesian goal 'position' (the end effector "
                               "follows a straight line to a point); a joint goal is planned "
                               "in joint space", field="goal.path")
    if "joints" in goal_d:
        return _parse_joints(r, goal_d["joints"], arm, "goal.joints"), None, None
    goal_xy = r.point(goal_d["position"], "goal.position")
    dist = math.hypot(*goal_xy)
    r_in, r_out = arm.reach
    if dist > r_out * (1 + 1e-12) or dist < r_in * (1 - 1e-12):
        raise InvalidValue(
            f"({goal_xy[0]:g}, {goal_xy[1]:g}) is out of reach: its distance {dist:.4g} m from "
            f"the base is outside the workspace annulus [{r_in:g}, {r_out:g}] m",
            field="goal.position")
    return None, tuple(goal_xy), path


def _rate(r: _Reader, v, field: str, unit: str) -> float:
    """One positive joint limit in the file's unit, returned in radians."""
    x = _number(v, field)
    shown = unit.replace("rad", "deg") if r.k != 1.0 else unit
    if x <= 0:
        raise InvalidValue(f"must be > 0 {shown}, got {x:g}", field=field)
    if not MIN_RATE_LIMIT <= x * r.k <= MAX_RATE_LIMIT:
        rng = f"[{MIN_RATE_LIMIT:g}, {MAX_RATE_LIMIT:g}] {unit}"
        raise InvalidValue(f"must lie in {rng}" + (f" (converted from {shown})" if r.k != 1.0
                                                   else "") + f", got {x:g} {shown}", field=field)
    return x * r.k


def _rate_limits(r: _Reader, v, field: str, n: int, unit: str):
    """``None`` (absent or null), or one limit per joint (rad/s or rad/s^2) from a number
    (every joint) or a list of ``n`` numbers."""
    if v is None:
        return None
    if isinstance(v, (list, tuple)):
        items = _list(v, field, n, f"numbers (one per joint; the arm has {n} joints)")
        return tuple(_rate(r, x, f"{field}[{i}]", unit) for i, x in enumerate(items))
    return (_rate(r, v, field, unit),) * n


def _parse_trajectory(r: _Reader, v, n: int) -> TrajectorySettings:
    d = _object(v, "trajectory", optional=_TRAJECTORY_KEYS)
    vmax = _rate_limits(r, d.get("max_velocity"), "trajectory.max_velocity", n, "rad/s")
    amax = _rate_limits(r, d.get("max_acceleration"), "trajectory.max_acceleration", n,
                        "rad/s^2")
    profile = _string(d.get("profile", "quintic"), "trajectory.profile", PROFILES)
    if profile == "trapezoidal":
        for key, value in (("max_velocity", vmax), ("max_acceleration", amax)):
            if value is None:
                raise MissingParameter(
                    "the trapezoidal profile is the fastest motion within both limits: give "
                    "max_velocity and max_acceleration", field=f"trajectory.{key}")
    if "duration" in d or (vmax is None and amax is None):
        duration = _number(d.get("duration", 5.0), "trajectory.duration")
        if not MIN_DURATION <= duration <= MAX_DURATION:
            raise InvalidValue(f"must lie in [{MIN_DURATION:g}, {MAX_DURATION:g}] s, got "
                               f"{duration:g}", field="trajectory.duration")
    else:
        duration = None   # the shortest within the limits, found by rapp.plan
    dt = None
    if "dt" in d:
        if "samples" in d:
            raise InvalidFormat("give samples or dt (a fixed time step), not both",
                                field="trajectory.dt")
        dt = _number(d["dt"], "trajectory.dt")
        if not 1.0 / MAX_SAMPLE_RATE <= dt <= MAX_DURATION:
            raise InvalidValue(f"must lie in [{1.0 / MAX_SAMPLE_RATE:g}, {MAX_DURATION:g}] s, got "
                               f"{dt:g}", field="trajectory.dt")
        if duration is not None and duration / dt + 1 > max(SAMPLES_ANY_RATE, MAX_SAMPLES):
            raise InvalidValue(f"{duration:g} s in steps of {dt:g} s is too many samples",
                               field="trajectory.dt")
        # The sample count the step gives (the motion under limits sets its own duration).
        samples = max(2, math.ceil(duration / dt - 1e-9) + 1) if duration is not None else 200
    else:
        samples = _integer(d.get("samples", 200), "trajectory.samples", 2, MAX_SAMPLES)
    _check_sample_rate(samples, duration)
    return TrajectorySettings(duration=duration, profile=profile, samples=samples,
                              max_velocity=vmax, max_acceleration=amax, dt=dt)


def _check_sample_rate(samples: int, duration) -> None:
    if duration is not None and samples > max(SAMPLES_ANY_RATE, MAX_SAMPLE_RATE * duration):
        raise InvalidValue(
            f"{samples} samples over {duration:g} s is {samples / duration:.3g} per second; "
            f"at most {MAX_SAMPLE_RATE:g} per second (a servo loop's rate) or "
            f"{SAMPLES_ANY_RATE} in all", field="trajectory.samples")


def _parse(data: Any, source: str, preflight_checks: bool) -> Scenario:
    top = _object(data, "", required=("arm", "start", "goal"), optional=_TOP_KEYS)
    units = _object(top.get("units", {}), "units", optional=("angle", "length"))
    angle_unit = _string(units.get("angle", "rad"), "units.angle", ("rad", "deg"))
    _string(units.get("length", "m"), "units.length", ("m",))
    r = _Reader(math.pi / 180.0 if angle_unit == "deg" else 1.0)
    arm = _parse_arm(r, top["arm"])
    obstacles = _parse_obstacles(r, top.get("obstacles", []), arm)
    start = _parse_joints(r, top["start"], arm, "start")
    goal_q, goal_xy, goal_path = _parse_goal(r, top["goal"], arm)
    planner = _planner(top.get("planner", {}), arm.n, r.warnings)
    trajectory = _parse_trajectory(r, top.get("trajectory", {}), arm.n)
    if goal_path == "line":
        if trajectory.profile == "spline":
            raise InvalidValue(
                "a line goal is timed rest-to-rest along the waypoints that keep the end "
                "effector on the line; a spline through them would cut their corners and leave "
                "it: use 'cubic', 'quintic' or 'trapezoidal'", field="trajectory.profile")
        if "planner" in top:
            r.warnings.append("planner is not used: a line goal (goal.path 'line') is followed "
                              "by rapp.cartesian.line_path, not searched")
    scenario = Scenario(
        arm=arm, obstacles=obstacles, start=start, goal_q=goal_q, goal_xy=goal_xy,
        planner=planner, trajectory=trajectory, name=_string(top.get("name", ""), "name"),
        description=_string(top.get("description", ""), "description"),
        angle_unit=angle_unit, warnings=tuple(r.warnings), source=source, goal_path=goal_path,
        safety_margin=_gap(top.get("safety_margin", 0.0), "safety_margin"),
    )
    try:  # an obstacle within reach but vastly larger than the arm: the C-space loses its digits
        check_extent(arm, obstacles, scenario.safety_margin)
    except ValueError as e:
        field, _, message = str(e).partition(" ")
        raise InvalidValue(message, field=field) from None
    if preflight_checks:
        preflight(scenario)
    return scenario


def _within_limits(arm: Arm, q, field: str) -> None:
    for i, (a, lim) in enumerate(zip(q, arm.joint_limits)):
        if lim is not None and not lim[0] <= a <= lim[1]:
            raise InvalidValue(
                f"joint {i} angle {a:.4g} rad is outside its limits [{lim[0]:.4g}, {lim[1]:.4g}] rad",
                field=f"{field}[{i}]")


def _grid_cells(d, n: int) -> tuple:
    cells_v = d.get("cells", default_cells(n))
    limit = max_cells(n)
    if isinstance(cells_v, (list, tuple)):
        return tuple(_integer(c, f"planner.cells[{i}]", 3, limit) for i, c in enumerate(
            _list(cells_v, "planner.cells", n, f"entries (one per joint; the arm has {n})")))
    return (_integer(cells_v, "planner.cells", 3, limit),) * n


def _planner(v, n: int, warnings: list) -> PlannerSettings:
    """The ``planner`` object, checked against the planner table (:mod:`rapp.planners`)."""
    table = planner_table.all_settings()
    if isinstance(v, dict):
        for key in planner_table.USER_CHECK:   # keywords of the planner functions only
            if key.key in v:
                raise InvalidValue(f"a scenario file cannot carry a user's checker: pass "
                                   f"{key.key}= to the planner function in Python "
                                   "(rapp.validity)", field=f"planner.{key.key}")
    d = _object(v, "planner", optional=("algorithm",) + tuple(table))
    # A* by default; RRT for arms whose grid would not fit (said in the echo).
    fallback = "astar" if n <= GRID_DEFAULT_MAX_JOINTS or "cells" in d else "rrt"
    algorithm = _string(d.get("algorithm", fallback), "planner.algorithm", planner_table.names())
    entry = planner_table.entry(algorithm)
    values = {}
    for key, spec in table.items():   # every key is checked, read or not
        default = entry.default(key) if key in entry.keys else spec.default
        values[key] = _setting(spec, d[key] if key in d else default, d, n, entry.grid)
        if key in d and key not in entry.keys and spec.warns_when_ignored:
            warnings.append(f"planner.{key} is not a setting of {algorithm} and is ignored")
    if algorithm == "prm":   # refused up front, as the grid is (rapp.prm checks it exactly)
        nodes = largest_roadmap(values["samples"]) + 1
        peak = roadmap_bytes(n, nodes, values["neighbours"])
        if peak > PRM_MEMORY_BUDGET:
            raise InvalidValue(
                f"a roadmap of up to {nodes} nodes (the larger of {MAX_SAMPLES} and 20 x samples) with {values['neighbours']} neighbours "
                f"each would need about {peak / 1e9:.3g} GB, over the "
                f"{PRM_MEMORY_BUDGET / 1e9:g} GB budget: lower planner.samples or "
                "planner.neighbours", field="planner.samples")
    if algorithm == "rrt" and "algorithm" not in d:
        warnings.append(f"planner.algorithm: rrt, the default for more than "
                        f"{GRID_DEFAULT_MAX_JOINTS} joints (a grid fine enough to plan on would "
                        "not fit in memory)")
    fields = set(PlannerSettings.__dataclass_fields__)
    extra = tuple((k, v) for k, v in values.items() if k not in fields)
    return PlannerSettings(algorithm=algorithm, extra=extra,
                           **{k: v for k, v in values.items() if k in fields})


def _setting(spec, raw, d, n: int, grid: bool):
    """One planner setting checked against its :class:`rapp.planners.Setting`."""
    field = f"planner.{spec.key}"
    if spec.kind == "cells":
        cells = _grid_cells(d, n)
        total = math.prod(cells)
        if grid and total > max_cells(n):
            raise InvalidValue(
                f"a grid of {total:.3g} cells would need about {total * bytes_per_cell(n) / 1e9:.3g} "
                f"GB; the limit for {n} joints is {max_cells(n):.3g} cells "
                f"({MEMORY_BUDGET / 1e9:g} GB)", field=field)
        return cells
    if raw is None and spec.nullable:
        return None
    if spec.kind == "integer":
        return _integer(raw, field, int(spec.low), None if math.isinf(spec.high) else int(spec.high))
    x = _number(raw, field)
    if not spec.accepts(x):
        raise InvalidValue(f"must lie in {spec.range_text}, got {x:g}", field=field)
    return x


def check_limits(scenario: Scenario) -> None:
    """Refuse a :class:`Scenario` built in code that a scenario file could not hold.

    The file reader bounds every count and setting that decides how long a plan takes or how
    much memory it needs (obstacles, links, trajectory samples, every planner setting);
    :func:`load_scenario` applies the same bounds to a Scenario it is given, counts first, so
    that :func:`rapp.plan` refuses a million obstacles at once instead of working through them.

    Raises
    ------
    InvalidValue
        Naming the field, as the file reader would.

    Examples
    --------
    >>> import dataclasses
    >>> s = load_scenario("default")
    >>> check_limits(s) is None
    True
    >>> check_limits(dataclasses.replace(s, obstacles=s.obstacles * 400))
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidValue: obstacles: at most 1000 obstacles are supported, got 1200 (each adds about 1.5 ms to every plan)
    """
    _check_obstacle_count(len(scenario.obstacles))
    n = scenario.arm.n
    if n > MAX_LINKS:
        raise InvalidValue(f"at most {MAX_LINKS} links are supported, got {n}",
                           field="arm.link_lengths")
    t = scenario.trajectory
    _check_sample_rate(_integer(t.samples, "trajectory.samples", 2, MAX_SAMPLES), t.duration)
    p = scenario.planner
    settings = {k: getattr(p, k) for k in _PLANNER_KEYS if hasattr(p, k)}
    settings["cells"] = list(p.cells) if isinstance(p.cells, (tuple, list)) else p.cells
    _planner(settings, n, [])


def preflight(scenario: Scenario) -> None:
    """Refuse a scenario that cannot succeed, before any search.

    Raises :class:`~rapp.errors.InvalidValue` naming ``start`` or
    ``goal.joints`` when that configuration collides.

    Examples
    --------
    >>> s = load_scenario("default")
    >>> preflight(s) is None
    True
    """

    obs = scenario.obstacles
    if not obs:
        return
    checks = [("start", scenario.start)]
    if scenario.goal_q is not None:
        checks.append(("goal.joints", scenario.goal_q))
    for field, q in checks:
        if bool(collides(scenario.arm, np.array(q), obs)):
            d = float(clearance(scenario.arm, np.array(q), obs))
            raise InvalidValue(
                f"this configuration collides with an obstacle (clearance {d:.3g} m)", field=field)


def load_scenario(source: str | os.PathLike | Mapping[str, Any] | Scenario, *,
                  check: bool = True) -> Scenario:
    """Load and validate a scenario.

    Parameters
    ----------
    source : str, os.PathLike, Mapping or Scenario
        A path to a JSON file, the name of an embedded scenario (see
        :func:`list_scenarios`), or an already parsed mapping.
    check : bool, default True
        Also run :func:`preflight` (start and joint goal must not collide).

    Returns
    -------
    Scenario

    Raises
    ------
    FileNotFound, InvalidFormat, MissingParameter, InvalidValue
        Each with ``.field`` naming the offending entry.

    Examples
    --------
    >>> s = load_scenario({"arm": {"link_lengths": [1, 1]}, "start": [0, 0],
    ...                    "goal": {"joints": [90, 0]}, "units": {"angle": "deg"}})
    >>> round(s.goal_q[0], 6)
    1.570796
    >>> load_scenario({"arm": {"link_lengths": [1, -1]}, "start": [0, 0], "goal": {"joints": [0, 0]}})
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidValue: arm.link_lengths[1]: link length must be > 0 m, got -1
    """
    if isinstance(source, Scenario):
        check_limits(source)
        return source
    if isinstance(source, Mapping):
        data, src = source, "<mapping>"
    elif isinstance(source, (str, os.PathLike)):
        try:
            src = os.fspath(source)
            if isinstance(src, bytes):
                src = os.fsdecode(src)
        except (TypeError, ValueError) as e:  # a PathLike whose __fspath__ misbehaves
            raise FileNotFound(f"not a usable path: {_why(e)}", field="scenario") from None
        if not os.path.exists(src) and src.isidentifier() and _embedded(src).is_file():
            data = _parse_bytes(_embedded(src).read_bytes())
            src = f"rapp:scenarios/{src}.json"
        else:
            data = _read_json(src)
    else:
        raise InvalidFormat(
            f"expected a path, a scenario name or a mapping, got {type(source).__name__}",
            field="scenario")
    try:
        return _parse(data, src, check)
    except RecursionError:
        raise InvalidFormat("the scenario is nested too deeply", field="scenario") from None


# --------------------------------------------------------------------------- echo (R2)


def _fmt(v, digits=4) -> str:
    return f"{v:.{digits}g}"


def _echo_setting(spec, value) -> str:
    """A planner setting as the echo shows it (:class:`rapp.planners.Setting`)."""
    if value is None:
        return spec.null_text
    if spec.kind == "cells":
        return " x ".join(map(str, value)) + f" = {math.prod(value)}"
    if spec.kind == "integer":
        return str(value)
    return _fmt(value) + (f" {spec.unit}" if spec.unit else "")


def echo(scenario: Scenario) -> str:
    """Every input of the scenario as a readable table with units, warnings last.

    Angles are shown in radians, and in degrees when the file declared degrees.

    Examples
    --------
    >>> print(echo(load_scenario("default")).splitlines()[0])
    scenario      default
    """
    s = scenario
    deg = s.angle_unit == "deg"

    def ang(values):
        txt = "[" + ", ".join(_fmt(v) for v in values) + "] rad"
        if deg:
            txt += "  = [" + ", ".join(_fmt(math.degrees(v)) for v in values) + "] deg"
        return txt

    rows = [("scenario", s.name or "(unnamed)"), ("source", s.source)]
    if s.description:
        rows.append(("description", s.description))
    rows.append(("links", f"{s.arm.n}: [" + ", ".join(_fmt(v) for v in s.arm.link_lengths)
                 + "] m"))
    if any(s.arm.link_radius):
        rows.append(("link radius", "[" + ", ".join(_fmt(v) for v in s.arm.link_radius) + "] m"))
    if s.arm.self_collision:
        rows.append(("self-collision", "non-adjacent links keep their radii + margin apart"))
    if s.safety_margin:
        rows.append(("safety margin", f"{_fmt(s.safety_margin)} m from every obstacle"))
    for i, lim in enumerate(s.arm.joint_limits):
        rows.append((f"joint {i}", "free (wraps)" if lim is None else "limits " + ang(lim)))
    r_in, r_out = s.arm.reach
    rows.append(("reach", f"annulus [{_fmt(r_in)}, {_fmt(r_out)}] m"))
    rows.append(("obstacles", str(len(s.obstacles))))
    for i, ob in enumerate(s.obstacles):
        if isinstance(ob, Circle):
            txt = f"circle centre ({_fmt(ob.center[0])}, {_fmt(ob.center[1])}) m, radius {_fmt(ob.radius)} m"
        else:
            txt = "polygon " + " ".join(f"({_fmt(x)}, {_fmt(y)})" for x, y in ob.vertices) + " m"
        rows.append((f"  [{i}]", txt))
    rows.append(("start", ang(s.start)))
    if s.goal_q is not None:
        rows.append(("goal (joints)", ang(s.goal_q)))
    else:
        rows.append(("goal (x, y)", f"({_fmt(s.goal_xy[0])}, {_fmt(s.goal_xy[1])}) m"
                     + (", along a straight line from the start" if s.goal_path == "line"
                        else "")))
    p = s.planner
    rows.append(("planner", "none: the line is followed, not searched"
                 if s.goal_path == "line" else p.algorithm))
    if s.goal_path != "line":   # a line is followed, not searched: no search settings
        uses = planner_table.entry(p.algorithm).keys
        rows.extend(("  " + spec.label, _echo_setting(spec, getattr(p, key)))
                    for key, spec in planner_table.all_settings().items() if key in uses)
    t = s.trajectory
    length = ("the shortest duration within the limits" if t.duration is None
              else f"{_fmt(t.duration)} s")
    rows.append(("trajectory", f"{t.profile}, {length}, "
                 + (f"{t.samples} samples" if t.dt is None else f"a sample every {_fmt(t.dt)} s")))

    def rates(values, unit):
        txt = "[" + ", ".join(_fmt(v) for v in values) + f"] rad/{unit}"
        if deg:
            txt += "  = [" + ", ".join(_fmt(math.degrees(v)) for v in values) + f"] deg/{unit}"
        return txt

    if t.max_velocity is not None:
        rows.append(("  max speed", rates(t.max_velocity, "s")))
    if t.max_acceleration is not None:
        rows.append(("  max accel", rates(t.max_acceleration, "s^2")))
    width = max(len(k) for k, _ in rows) + 2
    lines = [f"{k:<{width}}{v}" for k, v in rows]
    for w in s.warnings:
        lines.append(f"warning: {w}")
    return "\n".join(lines)
