"""The result of a plan and its JSON file: the ``Plan`` value, saved and loaded.

A result file holds everything needed to re-check a plan without re-planning
it: the scenario, the timed trajectory, the waypoints, the grid and its
occupancy (bit-packed), the verification report and the metrics. Writing is
atomic (a temporary file beside the target, then a rename), so a crash or an
interrupt never leaves a half-written result or destroys the previous one.

References
----------
SRS of 2D-RAPP (seed 000): R5 (output the trajectory and its metrics).
"""

from __future__ import annotations

import base64
import json
import os
from dataclasses import dataclass, field as dc_field, replace
from typing import Any, Sequence

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.arm import Arm
from rapp.cspace import JointGrid
from rapp.errors import FileNotFound, InvalidFormat
from rapp.files import atomic_output
from rapp.scenario import Scenario, echo, load_scenario
from rapp.trajectory import PiecewisePolynomial
from rapp.verify import Report

__all__ = ["Plan", "save_result", "load_result", "motion_to_dict", "motion_from_dict",
           "RESULT_FORMAT", "RESULT_VERSION", "csv_columns", "save_csv", "joint_trajectory",
           "save_joint_trajectory"]

RESULT_FORMAT = "rapp-result"
RESULT_VERSION = 1


def motion_to_dict(motion: PiecewisePolynomial) -> dict:
    """The motion as a result file holds it: ``breaks`` (k + 1 times, s) and ``coefficients``
    (k pieces x n joints x (d + 1)); on ``[breaks[i], breaks[i+1]]`` joint ``j`` is
    ``sum_m coefficients[i][j][m] * (t - breaks[i])**m`` (lowest power first, radians).

    Examples
    --------
    >>> from rapp.time_scaling import time_path
    >>> d = motion_to_dict(time_path([[0.0, 0.0], [1.0, 2.0]], 2.0, "cubic"))
    >>> d["breaks"], d["coefficients"][0][1]
    ([0.0, 2.0], [0.0, 0.0, 1.5, -0.5])
    """
    return {"breaks": np.asarray(motion.breakpoints, float).tolist(),
            "coefficients": np.transpose(np.asarray(motion.local, float), (0, 2, 1)).tolist()}


def motion_from_dict(d, n: int) -> PiecewisePolynomial:
    """Inverse of :func:`motion_to_dict` for an arm of ``n`` joints; InvalidFormat naming
    ``motion`` when ``d`` is not one.

    Examples
    --------
    >>> from rapp.time_scaling import time_path
    >>> m = time_path([[0.0, 0.0], [1.0, 2.0]], 2.0, "quintic")
    >>> bool(np.array_equal(motion_from_dict(motion_to_dict(m), 2).local, m.local))
    True
    """
    try:
        bp = np.asarray(d["breaks"], dtype=float)
        c = np.asarray(d["coefficients"], dtype=float)
        if bp.ndim != 1 or c.ndim != 3 or c.shape[:2] != (bp.size - 1, n) or c.shape[2] < 1:
            raise ValueError(f"breaks {bp.shape} and coefficients {c.shape} do not make "
                             f"k pieces of {n} joints")
        return PiecewisePolynomial.from_local(bp, np.transpose(c, (0, 2, 1)))
    except (KeyError, TypeError, ValueError) as e:
        raise InvalidFormat(f"not a motion: {e}", field="motion") from None


@dataclass(frozen=True, eq=False)
class Plan:
    """A planned, timed and verified trajectory.

    Attributes
    ----------
    t : ndarray (k,)
        Sample times, 0 to the duration (s).
    q, qd, qdd : ndarray (k, n)
        Joint angles (rad, unwrapped: free joints may leave [-pi, pi) so that
        motion is continuous), velocities and accelerations.
    xy : ndarray (k, 2)
        End-effector positions, ``FK(q)`` (m).
    waypoints : ndarray (m, n)
        Exact start, grid path in angles, exact goal (unwrapped).
    shortcut : ndarray (p, n)
        The shortened polyline that was timed.
    goal_q : ndarray (n,)
        The goal configuration reached (unwrapped like ``q``).
    grid, occupancy
        The joint grid and its occupancy (None for a sampling planner).
    scenario : Scenario
    profile : str
        The time profile actually used.
    report : Report
    metrics : dict
        Counts and lengths: the same for the same scenario, run after run.
    timings : dict
        Wall-clock seconds per pipeline stage (``compile``, ``ik``, ``cspace``, ``search``,
        ``smoothing``, ``trajectory``, ``verify``, ``total``; ``compile`` is numba compiling a
        sampling planner's kernels before a time budget's clock starts). They differ
        between runs, so a result file holds them only when asked
        (``save_result(..., timings=True)``).
    expanded : ndarray of bool, optional
        The cells the grid search expanded, the search's closed set (grid planner only; figures
        use it, result files do not hold it: ``metrics["expansions"]`` counts it).
    motion : PiecewisePolynomial, optional
        The timed motion ``q(t)`` itself, which ``t, q, qd, qdd`` sample (every plan of
        :func:`rapp.plan` has one): :func:`rapp.verify` certifies it free over its whole time
        span and takes the exact peak speeds and accelerations from it. A result file holds it
        under ``motion`` (:func:`motion_to_dict`).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    xy: np.ndarray
    waypoints: np.ndarray
    shortcut: np.ndarray
    goal_q: np.ndarray
    scenario: Scenario
    grid: Any = None
    occupancy: np.ndarray | None = None
    profile: str = ""
    report: Report | None = None
    metrics: dict = dc_field(default_factory=dict)
    timings: dict = dc_field(default_factory=dict)
    expanded: np.ndarray | None = None
    motion: Any = None

    def to_dict(self, *, timings: bool = False) -> dict:
        """A JSON-ready mapping of everything (see :func:`save_result`); :meth:`from_dict` inverts it.

        The mapping depends only on the scenario, so two runs give the same
        one; with ``timings=True`` it also holds the wall-clock ``timings``.

        Examples
        --------
        >>> from rapp import plan
        >>> d = plan("default").to_dict()
        >>> d["format"], d["report"]["ok"], len(d["q"][0])
        ('rapp-result', True, 2)
        """
        occ = None
        if self.occupancy is not None:
            occ = {"shape": list(self.occupancy.shape),
                   "packbits_base64": base64.b64encode(
                       np.packbits(self.occupancy.ravel()).tobytes()).decode("ascii")}
        out = {
            "format": RESULT_FORMAT,
            "version": RESULT_VERSION,
            "scenario": self.scenario.to_dict(),
            "scenario_source": self.scenario.source,
            "scenario_angle_unit": self.scenario.angle_unit,
            "echo": echo(self.scenario).splitlines(),
            "profile": self.profile,
            "t": self.t, "q": self.q, "qd": self.qd, "qdd": self.qdd, "xy": self.xy,
            "waypoints": self.waypoints, "shortcut": self.shortcut, "goal_q": self.goal_q,
            "grid_cells": None if self.grid is None else list(self.grid.cells),
            "occupancy": occ,
            "report": None if self.report is None else self.report.to_dict(),
            "metrics": self.metrics,
        }
        if self.motion is not None:
            out["motion"] = motion_to_dict(self.motion)
        if timings:
            out["timings"] = self.timings
        return _jsonable(out)

    @classmethod
    def from_dict(cls, d) -> "Plan":
        """Rebuild a plan from :meth:`to_dict`'s mapping; raises InvalidFormat when it is not one.

        Examples
        --------
        >>> from rapp import plan
        >>> p = plan("default")
        >>> back = Plan.from_dict(p.to_dict())
        >>> bool(np.array_equal(back.q, p.q)), bool((back.occupancy == p.occupancy).all())
        (True, True)
        >>> Plan.from_dict({"format": "other"})
        Traceback (most recent call last):
        ...
        rapp.errors.InvalidFormat: format: not a rapp result (format 'other')
        """
        try:
            if d.get("format") != RESULT_FORMAT:
                raise InvalidFormat(f"not a rapp result (format {d.get('format')!r})", field="format")
            scenario = replace(load_scenario(d["scenario"], check=False),
                               source=str(d.get("scenario_source", "<result>")),
                               angle_unit="deg" if d.get("scenario_angle_unit") == "deg" else "rad")
            n = scenario.arm.n

            def arr(key, shape):
                a = np.asarray(d[key], dtype=float)
                if a.ndim != len(shape) or any(s is not None and s != a.shape[i]
                                               for i, s in enumerate(shape)):
                    raise InvalidFormat(f"expected shape {shape}, got {a.shape}", field=key)
                return a

            grid = occ = None
            if d.get("grid_cells") is not None:
                grid = JointGrid(scenario.arm, tuple(int(c) for c in d["grid_cells"]))
            if d.get("occupancy") is not None:
                o = d["occupancy"]
                shape = tuple(int(s) for s in o["shape"])
                bits = np.frombuffer(base64.b64decode(o["packbits_base64"]), dtype=np.uint8)
                occ = np.unpackbits(bits)[: int(np.prod(shape))].astype(bool).reshape(shape)
            report = None if d.get("report") is None else Report.from_dict(d["report"])
            motion = None if d.get("motion") is None else motion_from_dict(d["motion"], n)
            return cls(
                t=arr("t", (None,)), q=arr("q", (None, n)), qd=arr("qd", (None, n)),
                qdd=arr("qdd", (None, n)), xy=arr("xy", (None, 2)),
                waypoints=arr("waypoints", (None, n)), shortcut=arr("shortcut", (None, n)),
                goal_q=arr("goal_q", (n,)), scenario=scenario, grid=grid, occupancy=occ,
                profile=str(d.get("profile", "")), report=report, metrics=dict(d.get("metrics", {})),
                timings=dict(d.get("timings", {})), motion=motion,
            )
        except (KeyError, TypeError, ValueError, AttributeError) as e:
            if isinstance(e, InvalidFormat):
                raise
            raise InvalidFormat(f"malformed result: {type(e).__name__}: {e}", field="result") from None


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        x = float(x)
        return x if np.isfinite(x) else None
    return x


def save_result(plan: Plan, path: str | os.PathLike, *, timings: bool = False) -> None:
    """Write ``plan.to_dict()`` as JSON atomically (temporary file, then ``os.replace``).

    A crash while writing leaves any previous file at ``path`` intact. The
    file is the same byte for byte for the same scenario unless ``timings``
    asks for the wall-clock stage times too.

    Examples
    --------
    >>> import os, tempfile
    >>> from rapp import plan
    >>> p = plan(load_scenario("default"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_result(p, os.path.join(d, "r.json"))
    ...     back = load_result(os.path.join(d, "r.json"))
    >>> bool(np.array_equal(back.q, p.q)), back.report == p.report
    (True, True)
    """
    text = json.dumps(plan.to_dict(timings=timings), allow_nan=False, separators=(",", ":"))
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())


def load_result(path: str | os.PathLike) -> Plan:
    """Read a result file written by :func:`save_result`.

    Raises :class:`~rapp.errors.FileNotFound` or :class:`~rapp.errors.InvalidFormat`
    (field ``"result"``) for a missing, unreadable or malformed file.

    Examples
    --------
    >>> import os, tempfile
    >>> from rapp import plan
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = os.path.join(d, "r.json")
    ...     save_result(plan(load_scenario("srs_typical")), path)
    ...     back = load_result(path)
    >>> back.report.ok, back.q.shape[1]
    (True, 2)
    >>> load_result("no/such/result.json")
    Traceback (most recent call last):
    ...
    rapp.errors.FileNotFound: result: no such file 'no/such/result.json'
    """
    path = os.fspath(path)
    if os.path.isdir(path):
        raise FileNotFound(f"{path!r} is a directory, not a result file", field="result")
    try:
        with open(path, encoding="utf-8") as fh:
            d = json.load(fh)
    except FileNotFoundError:
        raise FileNotFound(f"no such file {path!r}", field="result") from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError, ValueError) as e:
        raise InvalidFormat(f"not a JSON result file: {str(e).splitlines()[0]}", field="result") from None
    except OSError as e:
        raise FileNotFound(f"cannot read {path!r}: {e.strerror or e}", field="result") from None
    if not isinstance(d, dict):
        raise InvalidFormat("a result file holds one JSON object", field="result")
    return Plan.from_dict(d)


# --------------------------------------------------------------------------- exports


def _rows(source: Plan | PiecewisePolynomial, dt: float | None, joint_names, arm):
    """``(t, q, qd, qdd, names)`` of a plan (its samples) or of a timed motion (sampled every
    ``dt`` from its start, and at its end); ``q`` as the encoders read it (``q - offsets``)."""
    if isinstance(source, Plan):
        arm = source.scenario.arm if arm is None else arm
        t, q, qd, qdd = (np.asarray(a, dtype=float) for a in (source.t, source.q, source.qd,
                                                               source.qdd))
    elif isinstance(source, PiecewisePolynomial):
        if dt is None or not (np.isfinite(dt) and dt > 0):
            raise ValueError(f"a timed motion is sampled every dt seconds: give dt > 0, got {dt!r}")
        t = np.append(np.arange(0.0, source.duration, dt), source.duration)
        t = source.t0 + t[np.concatenate((np.diff(t) > 1e-9 * dt, [True]))]
        q, qd, qdd = (np.asarray(a, dtype=float) for a in source.sample(t))
    else:
        raise ValueError(f"expected a Plan or a PiecewisePolynomial, got {type(source).__name__}")
    n = q.shape[1]
    if arm is not None:
        q = arm.to_encoder(q)
        names = list(arm.joint_names)
    else:
        names = [f"joint{i + 1}" for i in range(n)]
    if joint_names is not None:
        names = [str(s) for s in joint_names]
    if len(names) != n:
        raise ValueError(f"joint_names must hold {n} names, got {names!r}")
    return t, q, qd, qdd, names


def csv_columns(joint_names: Sequence[str]) -> list[str]:
    """The header of :func:`save_csv`: ``t``, then ``q``, ``qd``, ``qdd`` of each joint in turn.

    Examples
    --------
    >>> csv_columns(["shoulder", "elbow"])
    ['t', 'q_shoulder', 'qd_shoulder', 'qdd_shoulder', 'q_elbow', 'qd_elbow', 'qdd_elbow']
    """
    return ["t"] + [f"{kind}_{name}" for name in joint_names for kind in ("q", "qd", "qdd")]


def save_csv(source: Plan | PiecewisePolynomial, path: str | os.PathLike, *,
             dt: float | None = None, joint_names: Sequence[str] | None = None,
             arm: Arm | None = None) -> None:
    """Write a trajectory as CSV, atomically: a header (:func:`csv_columns`), one row per sample.

    ``t`` in seconds; per joint ``q`` (rad, as the joint's encoder reads it: ``q -
    arm.joint_offsets``), ``qd`` (rad/s) and ``qdd`` (rad/s²), each written with ``repr``'s
    17 significant digits, so the numbers read back exactly.

    Parameters
    ----------
    source : Plan or PiecewisePolynomial
        A plan (its samples, its scenario's arm) or a timed motion such as
        :func:`rapp.time_path` returns, sampled every ``dt`` seconds and at its end.
    path : str or path-like
    dt : float, optional
        The time step; required for a motion, not used for a plan.
    joint_names : sequence of str, optional
        Default: the arm's ``joint_names``, else ``joint1 .. jointn``.
    arm : Arm, optional
        For a motion: the arm whose ``joint_offsets`` and names apply.

    Examples
    --------
    >>> import csv, os, tempfile
    >>> from rapp import plan
    >>> p = plan("default")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_csv(p, os.path.join(d, "q.csv"))
    ...     with open(os.path.join(d, "q.csv"), newline="") as fh:
    ...         rows = list(csv.reader(fh))
    >>> rows[0]
    ['t', 'q_joint1', 'qd_joint1', 'qdd_joint1', 'q_joint2', 'qd_joint2', 'qdd_joint2']
    >>> len(rows) - 1 == len(p.t), float(rows[-1][0]) == float(p.t[-1])
    (True, True)
    """
    t, q, qd, qdd, names = _rows(source, dt, joint_names, arm)
    n = q.shape[1]
    table = np.empty((len(t), 1 + 3 * n))
    table[:, 0] = t
    table[:, 1::3], table[:, 2::3], table[:, 3::3] = q, qd, qdd
    lines = [",".join(csv_columns(names))]
    lines += [",".join(repr(float(x)) for x in row) for row in table]
    _write_text(path, "\n".join(lines) + "\n")


def joint_trajectory(source: Plan | PiecewisePolynomial, *, dt: float | None = None,
                     joint_names: Sequence[str] | None = None,
                     arm: Arm | None = None) -> dict:
    """A trajectory as a ROS ``trajectory_msgs/JointTrajectory``-shaped mapping.

    ``joint_names`` and ``points``, one per sample, each with ``positions`` (rad, as the
    encoders read them: ``q - arm.joint_offsets``), ``velocities`` (rad/s),
    ``accelerations`` (rad/s²) and ``time_from_start`` as ROS 2 writes a duration:
    ``{"sec": int, "nanosec": int}``. ``source``, ``dt``, ``joint_names`` and ``arm`` as in
    :func:`save_csv`.

    Examples
    --------
    >>> from rapp import plan, time_path
    >>> jt = joint_trajectory(plan("default"))
    >>> jt["joint_names"], sorted(jt["points"][1])
    (['joint1', 'joint2'], ['accelerations', 'positions', 'time_from_start', 'velocities'])
    >>> jt["points"][0]["time_from_start"]
    {'sec': 0, 'nanosec': 0}
    >>> m = joint_trajectory(time_path([[0.0], [1.0]], 2.0), dt=0.5, joint_names=["wrist"])
    >>> [p["time_from_start"] for p in m["points"]][-2:]
    [{'sec': 1, 'nanosec': 500000000}, {'sec': 2, 'nanosec': 0}]
    """
    t, q, qd, qdd, names = _rows(source, dt, joint_names, arm)
    points = []
    for i, ti in enumerate(t):
        ns = int(round(float(ti) * 1e9))
        points.append({"positions": q[i].tolist(), "velocities": qd[i].tolist(),
                       "accelerations": qdd[i].tolist(),
                       "time_from_start": {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}})
    return {"joint_names": names, "points": points}


def save_joint_trajectory(source: Plan | PiecewisePolynomial, path: str | os.PathLike, *,
                          dt: float | None = None, joint_names: Sequence[str] | None = None,
                          arm: Arm | None = None) -> None:
    """Write :func:`joint_trajectory` as JSON, atomically (arguments as :func:`save_csv`).

    Examples
    --------
    >>> import json, os, tempfile
    >>> from rapp import plan
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_joint_trajectory(plan("default"), os.path.join(d, "jt.json"))
    ...     with open(os.path.join(d, "jt.json"), encoding="utf-8") as fh:
    ...         sorted(json.load(fh))
    ['joint_names', 'points']
    """
    jt = joint_trajectory(source, dt=dt, joint_names=joint_names, arm=arm)
    _write_text(path, json.dumps(jt, allow_nan=False, separators=(",", ":")))


def _write_text(path, text: str) -> None:
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
