"""The planning pipeline of 2D-RAPP (IM1; MIS ``executePlanning``).

``plan(scenario)`` runs, in order:

1. **IK** — a Cartesian goal becomes every goal configuration :func:`rapp.ik`
   finds that is within the limits and free of obstacles;
2. **C-space** — the joint grid and its occupancy (:mod:`rapp.cspace`);
3. **search** — breadth-first distances from the start cell pick the goal
   configuration that is *reachable* and nearest in grid steps, and A* finds
   the path to it (one BFS answers "which goal" and proves "no path" at once);
4. **certification** — the exact start and goal are joined to free cells by
   certified segments, and every grid move is checked by the continuous
   certified test (occupancy samples cell centres only; a move whose segment
   cannot be certified blocks its cell and the search is repeated);
5. **smoothing** — greedy shortcutting: from each waypoint jump to the farthest
   later waypoint whose straight joint-space segment is certified free;
6. **trajectory** — the shortcut polyline is timed into ``q(t)``, ``q'(t)``,
   ``q''(t)`` (:func:`rapp.trajectory.time_path`); if the smooth curve leaves
   the certified polyline and collides (or breaks a limit), each segment is
   timed rest-to-rest instead, which follows the polyline exactly;
7. **verification** — :func:`rapp.verify.verify` fills ``plan.report``.

Planners are looked up by name in :data:`PLANNERS`, so a new search method
plugs in without touching the pipeline. ``plan()`` never prints.
"""

from __future__ import annotations

import base64
import json
import os
import tempfile
import time
from dataclasses import dataclass, field as dc_field, replace
from types import MappingProxyType
from typing import Any, Callable, Mapping

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.collision import _segment_clearances, collides, motion_bounds, segment_collision_free
from rapp.errors import FileNotFound, InvalidFormat, InvalidValue, NoPathFound
from rapp.rrt import plan_rrt
from rapp.scenario import Scenario, echo, load_scenario
from rapp.trajectory import time_path
from rapp.verify import Report, verify

__all__ = [
    "Plan",
    "plan",
    "PLANNERS",
    "GridTooCoarse",
    "certified_free",
    "shortcut",
    "time_polyline",
    "save_result",
    "load_result",
]

RESULT_FORMAT = "rapp-result"
RESULT_VERSION = 1


class GridTooCoarse(NoPathFound):
    """The occupancy grid has a path, but its moves could not be certified collision-free.

    The grid marks cell *centres*; a move between two free centres can still
    sweep an obstacle. A finer grid (``planner.cells``) usually finds a path.
    """


@dataclass(frozen=True, eq=False)
class Plan:
    """A planned, timed and verified trajectory (R5).

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
        Counts, lengths, and ``stage_times`` in seconds.
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

    def to_dict(self) -> dict:
        """A JSON-ready mapping of everything (see :func:`save_result`); :meth:`from_dict` inverts it.

        Examples
        --------
        >>> d = plan("default").to_dict()
        >>> d["format"], d["report"]["ok"], len(d["q"][0])
        ('rapp-result', True, 2)
        """
        occ = None
        if self.occupancy is not None:
            occ = {"shape": list(self.occupancy.shape),
                   "packbits_base64": base64.b64encode(
                       np.packbits(self.occupancy.ravel()).tobytes()).decode("ascii")}
        return _jsonable({
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
        })

    @classmethod
    def from_dict(cls, d) -> "Plan":
        """Rebuild a plan from :meth:`to_dict`'s mapping; raises InvalidFormat when it is not one.

        Examples
        --------
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
                from rapp.cspace import JointGrid
                grid = JointGrid(scenario.arm, tuple(int(c) for c in d["grid_cells"]))
            if d.get("occupancy") is not None:
                o = d["occupancy"]
                shape = tuple(int(s) for s in o["shape"])
                bits = np.frombuffer(base64.b64decode(o["packbits_base64"]), dtype=np.uint8)
                occ = np.unpackbits(bits)[: int(np.prod(shape))].astype(bool).reshape(shape)
            report = None if d.get("report") is None else Report.from_dict(d["report"])
            return cls(
                t=arr("t", (None,)), q=arr("q", (None, n)), qd=arr("qd", (None, n)),
                qdd=arr("qdd", (None, n)), xy=arr("xy", (None, 2)),
                waypoints=arr("waypoints", (None, n)), shortcut=arr("shortcut", (None, n)),
                goal_q=arr("goal_q", (n,)), scenario=scenario, grid=grid, occupancy=occ,
                profile=str(d.get("profile", "")), report=report, metrics=dict(d.get("metrics", {})),
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


def save_result(plan: Plan, path) -> None:
    """Write ``plan.to_dict()`` as JSON atomically (temporary file, then ``os.replace``).

    A crash while writing leaves any previous file at ``path`` intact.

    Examples
    --------
    >>> import os, tempfile
    >>> p = plan(load_scenario("default"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_result(p, os.path.join(d, "r.json"))
    ...     back = load_result(os.path.join(d, "r.json"))
    >>> bool(np.array_equal(back.q, p.q)), back.report == p.report
    (True, True)
    """
    path = os.fspath(path)
    text = json.dumps(plan.to_dict(), allow_nan=False, separators=(",", ":"))
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".rapp-", suffix=".tmp", dir=folder)
    try:
        mode = os.stat(path).st_mode & 0o777 if os.path.exists(path) else 0o644
        os.chmod(tmp, mode)  # mkstemp makes 0600; keep what a plain open() would give
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def load_result(path) -> Plan:
    """Read a result file written by :func:`save_result`.

    Raises :class:`~rapp.errors.FileNotFound` or :class:`~rapp.errors.InvalidFormat`
    (field ``"result"``) for a missing, unreadable or malformed file.

    Examples
    --------
    >>> import os, tempfile
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


# --------------------------------------------------------------------------- geometry helpers


def _unwrap_near(arm: Arm, q, ref) -> np.ndarray:
    """``q`` moved by whole turns on free joints to lie within pi of ``ref``."""
    q = np.asarray(q, float)
    return np.where(arm.limited, q, ref + wrap_angle(q - ref))


def _unwrap_path(arm: Arm, path) -> np.ndarray:
    """Unwrap free-joint columns so consecutive configurations differ by the short way."""
    path = np.asarray(path, float).copy()
    free = ~arm.limited
    if free.any() and len(path) > 1:
        path[:, free] = np.unwrap(path[:, free], axis=0)
    return path


def _dedupe(path) -> np.ndarray:
    """Drop consecutive repeats (zero-length segments)."""
    path = np.asarray(path, float)
    if len(path) < 2:
        return path
    keep = np.concatenate(([True], np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-12))
    keep[-1] = True
    out = path[keep]
    if len(out) >= 2 and np.linalg.norm(out[-1] - out[-2]) <= 1e-12:
        out = np.delete(out, -2, axis=0)
    return out


def shortcut(arm: Arm, path, obstacles) -> np.ndarray:
    """Greedy shortcutting: from each kept waypoint, jump to the farthest certified-free one.

    ``path`` (m, n) must be unwrapped with every consecutive segment certified
    free; the result keeps the first and last waypoints and every segment of it
    is certified free too. Each step tests all later waypoints in one batch.

    Examples
    --------
    >>> from rapp import Circle
    >>> arm = Arm([1.0, 1.0])
    >>> shortcut(arm, [[0, 0], [0.1, 0], [0.2, 0], [0.3, 0]], [Circle((0, 1.5), 0.3)]).tolist()
    [[0.0, 0.0], [0.3, 0.0]]
    """
    path = np.asarray(path, float)
    if len(path) <= 2:
        return path.copy()
    keep = [0]
    i = 0
    while i < len(path) - 1:
        free = segment_collision_free(arm, path[i], path[i + 1:], obstacles)
        ahead = np.flatnonzero(free)
        i = i + 1 + (int(ahead[-1]) if ahead.size else 0)
        keep.append(i)
    return path[keep]


_SMOOTHSTEP = (lambda s: s**3 * (10 - 15 * s + 6 * s**2),
               lambda s: 30 * s**2 * (1 - s) ** 2,
               lambda s: 60 * s - 180 * s**2 + 120 * s**3)


def time_polyline(waypoints, duration: float, samples: int):
    """Rest-to-rest timing of a polyline: follows its straight segments exactly.

    Segment ``j`` gets a time share proportional to its joint-space length and
    is traversed with the quintic smoothstep ``s = 10 u^3 - 15 u^4 + 6 u^5``,
    so velocity and acceleration are zero at every waypoint and continuous
    everywhere. The sample times are ``samples`` even times, every waypoint
    time, and three times inside each segment (so each segment is sampled).

    Returns
    -------
    t (k,), q (k, n), qd (k, n), qdd (k, n)

    Examples
    --------
    >>> t, q, qd, qdd = time_polyline([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], 2.0, 5)
    >>> t.tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0]
    >>> q[4].tolist(), qd[4].tolist()
    ([1.0, 0.0], [0.0, 0.0])
    """
    w = np.asarray(waypoints, float)
    if w.ndim != 2 or len(w) < 1:
        raise ValueError(f"waypoints must have shape (m, n), got {w.shape}")
    T = float(duration)
    t = np.linspace(0.0, T, samples)
    n = w.shape[1]
    seg = np.linalg.norm(np.diff(w, axis=0), axis=1) if len(w) > 1 else np.zeros(0)
    total = float(seg.sum())
    if total <= 0.0:
        z = np.zeros((len(t), n))
        return t, np.broadcast_to(w[0], (len(t), n)).copy(), z, z.copy()
    dur = T * seg / total
    bp = np.concatenate(([0.0], np.cumsum(dur)))
    bp[-1] = T
    inner = (bp[:-1, None] + dur[:, None] * np.array([0.25, 0.5, 0.75])).ravel()
    t = np.unique(np.concatenate((t, bp, inner)))
    j = np.clip(np.searchsorted(bp, t, side="right") - 1, 0, len(dur) - 1)
    live = dur[j] > 0
    T_j = np.where(live, dur[j], 1.0)
    u = np.clip((t - bp[j]) / T_j, 0.0, 1.0)
    d = w[j + 1] - w[j]
    s, sd, sdd = (f(u)[:, None] for f in _SMOOTHSTEP)
    q = w[j] + np.where(live[:, None], s, 1.0) * d
    qd = np.where(live[:, None], sd * d / T_j[:, None], 0.0)
    qdd = np.where(live[:, None], sdd * d / T_j[:, None] ** 2, 0.0)
    q[-1] = w[-1]
    return t, q, qd, qdd


# --------------------------------------------------------------------------- goals


def _goal_configurations(scenario: Scenario) -> tuple[np.ndarray, int]:
    """Free goal configurations (g, n) and how many IK solutions there were."""
    arm, obs = scenario.arm, scenario.obstacles
    if scenario.goal_q is not None:
        return np.array([scenario.goal_q], float), 1
    from rapp.ik import ik

    sols = np.atleast_2d(ik(arm, np.array(scenario.goal_xy), q0=scenario.start_array))
    sols = sols[arm.within_limits(sols, 1e-12)]
    free = sols[~collides(arm, sols, obs)] if len(sols) and obs else sols
    if len(free) == 0:
        raise NoPathFound(
            f"every one of the {len(sols)} IK solutions for the goal "
            f"({scenario.goal_xy[0]:g}, {scenario.goal_xy[1]:g}) collides with an obstacle")
    return free, len(sols)


# --------------------------------------------------------------------------- planners


@dataclass(frozen=True)
class _Route:
    """What a planner hands back: a certified unwrapped polyline from start to a goal."""

    waypoints: np.ndarray
    goal_q: np.ndarray
    grid: Any = None
    occupancy: np.ndarray | None = None
    metrics: dict = dc_field(default_factory=dict)
    times: dict = dc_field(default_factory=dict)


def _anchor(arm, obstacles, grid, occ, q) -> np.ndarray | None:
    """A free grid cell joined to the exact configuration ``q`` by a certified segment.

    Candidates: the nearest cell, its axis neighbours and (for n <= 8) the
    corners of the grid box around ``q``; the nearest certified one wins.
    """
    from itertools import product

    n = arm.n
    m = np.array(grid.shape)
    wr = np.array(grid.wraps)
    near = grid.index(q)
    cands = [near]
    eye = np.eye(n, dtype=int)
    cands += list(near + eye) + list(near - eye)
    if n <= 8:
        base = np.where(wr, wrap_angle(q) + np.pi, q - grid.lower) / grid.step
        floor = np.floor(base).astype(int)
        cands += [floor + np.array(c) for c in product((0, 1), repeat=n)]
    c = np.array(cands)
    c = np.where(wr, c % m, c)
    c = c[np.all((c >= 0) & (c < m), axis=1)]
    c = np.unique(c, axis=0)
    c = c[~occ[tuple(c.T)]]
    if len(c) == 0:
        return None
    centres = _unwrap_near(arm, grid.angles(c), q)
    ok = segment_collision_free(arm, q, centres, obstacles)
    if not ok.any():
        return None
    c, centres = c[ok], centres[ok]
    return c[np.argmin(np.linalg.norm(centres - q, axis=1))]


def certified_free(arm: Arm, obstacles, grid, *, chunk: int = 200_000) -> np.ndarray:
    """Cells from which every move to an axis neighbour is certified collision-free.

    Along a move of one grid step on axis ``k`` a point of link ``j`` travels
    at most ``B_jk`` (:func:`rapp.collision.motion_bounds`). If at both ends of
    the move link ``j`` has clearance above ``B_jk / 2``, each half of the move
    stays inside the clearance ball of its own end, so the whole move is free.
    A cell is marked True when its clearances exceed half the bound for every
    axis; a search on these cells needs no further check of its moves. It is
    the occupancy inflated by half a step: conservative, so a narrow passage
    may close (the planner then falls back to the plain occupancy).

    Examples
    --------
    >>> from rapp import Circle
    >>> from rapp.cspace import JointGrid, occupancy
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)]
    >>> grid = JointGrid(arm, 32)
    >>> safe = certified_free(arm, obs, grid)
    >>> bool(np.all(~safe | ~occupancy(arm, obs, grid))), int(safe.sum()) < int((~occupancy(arm, obs, grid)).sum())
    (True, True)
    """
    n = arm.n
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)  # (n,) per link
    axes = grid.axes
    out = np.ones(grid.shape, bool)
    for j in range(n):
        # Link j depends on joints 0..j only: test it on that prefix grid and broadcast.
        sub = np.stack(np.meshgrid(*axes[: j + 1], indexing="ij"), axis=-1).reshape(-1, j + 1)
        q = np.zeros((sub.shape[0], n))
        q[:, : j + 1] = sub
        ok = np.empty(q.shape[0], bool)
        for lo in range(0, q.shape[0], chunk):  # chunks bound the memory, not a loop over cells
            pts = arm.joint_positions(q[lo:lo + chunk])
            d = _segment_clearances(pts[:, j, :], pts[:, j + 1, :], obstacles)
            ok[lo:lo + chunk] = d > need[j]
        out &= ok.reshape(grid.shape[: j + 1] + (1,) * (n - j - 1))
    return out


def _route_on(arm, obs, grid, work, start, goal_qs, p, *, certified: bool):
    """Search ``work`` (True = blocked) from the exact start to the nearest reachable goal.

    Returns (full unwrapped path, metrics) or raises NoPathFound / GridTooCoarse.
    With ``certified`` the grid moves are known to be free; otherwise each new
    move is checked and a failing one blocks its cell and the search repeats.
    """
    from rapp.search import astar_search, bfs_distances

    shape_txt = "x".join(map(str, grid.shape))
    s_cell = _anchor(arm, obs, grid, work, start)
    if s_cell is None:
        raise GridTooCoarse(
            "no free grid cell next to the start can be joined to it by a collision-free "
            f"segment on the {shape_txt} grid; try more planner.cells")
    anchors = [(_anchor(arm, obs, grid, work, g), g) for g in goal_qs]
    anchors = [(a, g) for a, g in anchors if a is not None]
    if not anchors:
        raise GridTooCoarse(
            "no free grid cell next to the goal can be joined to it by a collision-free "
            f"segment on the {shape_txt} grid; try more planner.cells")
    g_cells = np.array([a for a, _ in anchors])
    g_qs = np.array([g for _, g in anchors])
    work = work.copy()
    repairs = expansions = 0
    size = work.size
    seen_keys = np.zeros(0, np.int64)  # certified moves, as keys min*size + max of flat indices
    best = None
    while True:
        if best is None:
            # One BFS picks the reachable goal nearest in steps, or proves there is none.
            dist = bfs_distances(work, tuple(s_cell), grid.wraps)
            d_goal = dist[tuple(g_cells.T)]
            if not np.any(d_goal >= 0):
                msg = (f"no collision-free path: the {shape_txt} grid holds no path from the "
                       f"start to any of the {len(g_cells)} goal configuration(s) "
                       f"({int((dist >= 0).sum())} cells are reachable)")
                err = GridTooCoarse(msg) if repairs or certified else NoPathFound(msg)
                # What was searched, so that a test can re-check the proof independently.
                err.start_cell, err.goal_cells = tuple(int(i) for i in s_cell), g_cells.copy()
                raise err
            best = int(np.argmin(np.where(d_goal >= 0, d_goal, np.iinfo(np.int64).max)))
            bfs_optimum = int(d_goal[best])
        try:
            res = astar_search(work, tuple(s_cell), tuple(g_cells[best]), wraps=grid.wraps,
                               heuristic_weight=p.heuristic_weight,
                               max_expansions=p.max_expansions)
        except NoPathFound:
            if repairs == 0 or p.max_expansions is not None:
                raise
            best = None  # blocking cut this goal off: let BFS choose again
            continue
        expansions += res.expansions
        cells = np.asarray(res.path)
        goal_q = np.asarray(g_qs[best], float)
        full = _unwrap_path(arm, np.vstack([start, grid.angles(cells), goal_q]))
        if certified:
            break
        flat = np.ravel_multi_index(tuple(cells.T), grid.shape)
        keys = np.minimum(flat[:-1], flat[1:]) * size + np.maximum(flat[:-1], flat[1:])
        todo = np.flatnonzero(~np.isin(keys, seen_keys))
        # Segments 0 and -1 of ``full`` join the exact start and goal to their anchors
        # (certified by _anchor); grid move i is segment i + 1.
        ok = np.ones(len(keys), bool)
        if todo.size:
            ok[todo] = segment_collision_free(arm, full[todo + 1], full[todo + 2], obs)
            seen_keys = np.union1d(seen_keys, keys[todo[ok[todo]]])
        bad = np.flatnonzero(~ok)
        if bad.size == 0:
            break
        # Block the cell a failing move enters (or leaves, if it enters the goal anchor).
        entered = cells[bad + 1]
        left = cells[bad]
        is_goal = np.all(entered == g_cells[best], axis=1)
        block = np.where(is_goal[:, None], left, entered)
        block = block[~np.all(block == s_cell, axis=1)]
        if block.size == 0:
            raise GridTooCoarse("the move between the start and goal cells cannot be certified "
                                "collision-free; try more planner.cells")
        work[tuple(block.T)] = True
        repairs += 1
    metrics = {
        "expansions": int(res.expansions),
        "expansions_total": int(expansions),
        "path_cells": int(len(cells) - 1),
        "bfs_optimum_cells": bfs_optimum,
        "certification_repairs": int(repairs),
        "goal_candidates": int(len(g_cells)),
    }
    return full, metrics


def _plan_astar(scenario: Scenario, goal_qs: np.ndarray) -> _Route:
    """A* first on the certified cells (no move needs checking); if they hold no path,
    on the plain occupancy with each move checked, which also proves "no path"."""
    from rapp.cspace import JointGrid, occupancy

    arm, obs, p = scenario.arm, scenario.obstacles, scenario.planner
    start = scenario.start_array
    times = {}
    t0 = time.perf_counter()
    grid = JointGrid(arm, p.cells)
    occ = occupancy(arm, obs, grid)
    safe = certified_free(arm, obs, grid) if obs else ~occ
    times["cspace"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        try:
            full, metrics = _route_on(arm, obs, grid, ~safe, start, goal_qs, p, certified=True)
            metrics["search_grid"] = "certified cells"
        except GridTooCoarse:
            full, metrics = _route_on(arm, obs, grid, occ, start, goal_qs, p, certified=False)
            metrics["search_grid"] = "occupancy, moves checked"
    finally:
        times["search"] = time.perf_counter() - t0
    metrics.update({"grid_cells": int(occ.size), "free_fraction": float(1.0 - occ.mean()),
                    "certified_fraction": float(safe.mean())})
    return _Route(full, full[-1], grid, occ, metrics, times)


def _plan_rrt(scenario: Scenario, goal_qs: np.ndarray) -> _Route:
    """RRT from the exact start to the goal configurations; its path is certified edge by edge."""
    p = scenario.planner
    t0 = time.perf_counter()
    settings = {"step": p.step, "goal_bias": p.goal_bias, "goal_threshold": p.goal_threshold,
                "max_iterations": p.max_iterations, "seed": p.seed}
    path = np.asarray(plan_rrt(scenario.arm, scenario.obstacles, scenario.start_array, goal_qs,
                               settings=settings), float)
    if path.ndim != 2 or len(path) == 0:
        raise NoPathFound("RRT found no path")
    path = _unwrap_path(scenario.arm, path)
    metrics = {"tree_path_nodes": int(len(path)), "goal_candidates": int(len(goal_qs))}
    return _Route(path, path[-1], None, None, metrics, {"cspace": 0.0,
                                                        "search": time.perf_counter() - t0})


#: Planner name -> function(scenario, goal configurations (g, n)) -> _Route.
#: Read-only: a new planner is added here, in code, not registered at run time.
PLANNERS: Mapping[str, Callable] = MappingProxyType({"astar": _plan_astar, "rrt": _plan_rrt})


# --------------------------------------------------------------------------- the pipeline


def _time_smooth(arm, obs, path, tr):
    """The requested smooth profile of ``tr`` (TrajectorySettings) if it stays free and within
    limits, else ``time_polyline``."""
    if len(path) >= 2:
        t = np.linspace(0.0, tr.duration, tr.samples)
        pp = time_path(path, tr.duration, profile=tr.profile)
        q, qd, qdd = (np.asarray(a, float) for a in pp.sample(t))
        good = (np.isfinite(q).all() and np.isfinite(qd).all() and np.isfinite(qdd).all()
                and np.abs(q[0] - path[0]).max() <= 1e-9
                and np.abs(q[-1] - path[-1]).max() <= 1e-9
                and arm.within_limits(q, 1e-9).all()
                and segment_collision_free(arm, q[:-1], q[1:], obs).all())
        if good:
            q[0], q[-1] = path[0], path[-1]
            return t, q, qd, qdd, tr.profile
        fallback = f"rest-to-rest per segment (the {tr.profile} curve left the free polyline)"
    else:
        fallback = "rest (start is the goal)"
    t, q, qd, qdd = time_polyline(path, tr.duration, tr.samples)
    return t, q, qd, qdd, fallback


def plan(scenario) -> Plan:
    """Plan, time and verify a collision-free trajectory (IM1, MIS ``executePlanning``).

    Parameters
    ----------
    scenario : Scenario, or anything :func:`rapp.load_scenario` accepts

    Returns
    -------
    Plan
        With ``report`` filled by :func:`rapp.verify` and ``metrics``.

    Raises
    ------
    NoIKSolution
        The Cartesian goal has no joint solution within the limits.
    NoPathFound
        No collision-free path exists on the grid (proved by exhausting it),
        every IK solution collides, or the search limit was hit.
    ScenarioError
        From loading, when ``scenario`` is not already a Scenario.

    Examples
    --------
    >>> p = plan("default")
    >>> p.report.ok, p.q.shape[1], bool(np.allclose(p.xy[-1], [-1.2, 0.8], atol=1e-3))
    (True, 2, True)
    """
    scenario = load_scenario(scenario)
    algorithm = scenario.planner.algorithm
    if algorithm not in PLANNERS:
        raise InvalidValue(f"unknown planner {algorithm!r}", field="planner.algorithm")
    arm, obs = scenario.arm, scenario.obstacles
    times = {}
    t_all = time.perf_counter()

    t0 = time.perf_counter()
    goal_qs, n_ik = _goal_configurations(scenario)
    times["ik"] = time.perf_counter() - t0

    route = PLANNERS[algorithm](scenario, goal_qs)
    times.update(route.times)

    t0 = time.perf_counter()
    waypoints = route.waypoints
    short = shortcut(arm, _dedupe(waypoints), obs)
    times["smoothing"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    t, q, qd, qdd, profile = _time_smooth(arm, obs, short, scenario.trajectory)
    xy = arm.end_effector(q)
    times["trajectory"] = time.perf_counter() - t0

    def length(path):
        return float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()) if len(path) > 1 else 0.0

    metrics = dict(route.metrics)
    metrics.update({
        "ik_solutions": int(n_ik),
        "waypoints": int(len(waypoints)),
        "shortcut_waypoints": int(len(short)),
        "joint_length_rad": length(q),
        "waypoint_length_rad": length(waypoints),
        "shortcut_length_rad": length(short),
        "ee_length_m": length(xy),
        "samples": int(len(t)),
    })
    result = Plan(t=t, q=q, qd=qd, qdd=qdd, xy=xy, waypoints=waypoints, shortcut=short,
                  goal_q=np.asarray(route.goal_q, float), scenario=scenario, grid=route.grid,
                  occupancy=route.occupancy, profile=profile, metrics=metrics)
    t0 = time.perf_counter()
    report = verify(result, scenario)
    times["verify"] = time.perf_counter() - t0
    times["total"] = time.perf_counter() - t_all
    metrics["stage_times"] = {k: float(times.get(k, 0.0)) for k in
                              ("ik", "cspace", "search", "smoothing", "trajectory", "verify",
                               "total")}
    return replace(result, report=report, metrics=metrics)
