"""Checks for the exercises of chapter 7, "Path planning, stage by stage".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['7.1', '7.2', '7.3', '7.4', '7.5']
>>> _unwrap_ref(Arm([1.0]), np.array([[3.0], [-3.0]])).round(4).tolist()
[[3.0], [3.2832]]
>>> _smallest_cells(lambda m: 2 * np.pi / m <= 0.2)
32
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import io
import json
import os
import tempfile

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.cspace import JointGrid
from rapp.errors import GridTooCoarse, NoPathFound, RappError
from rapp.exercises.core import CLOSE_FACTOR, TOLERANCE, Exercise, Judgement, as_number_array, close, describe, implement, numeric
from rapp.grid_route import grid_step_motion, obstacle_size
from rapp.paths import unwrap_path

__all__ = ["EXERCISES"]


# --- 7.1: the other elbow at two resolutions -------------------------------------------------

@functools.cache
def _other_elbow(cells: int):
    """The chapter's ``v``: srs_typical with the other IK solution as a joint goal, on ``cells``."""
    from rapp.ik import ik
    from rapp.planner import plan
    from rapp.scenario import load_scenario

    s = load_scenario("srs_typical")
    goal_qs = ik(s.arm, np.array(s.goal_xy), q0=s.start_array)
    v = dataclasses.replace(s, goal_q=tuple(goal_qs[1]), goal_xy=None, name="srs_other_elbow")
    return plan(dataclasses.replace(v, planner=dataclasses.replace(v.planner, cells=(cells, cells))))


def _other_elbow_answer() -> np.ndarray:
    a, b = _other_elbow(50), _other_elbow(200)
    return np.array([a.metrics["path_cells"], b.metrics["path_cells"], a.metrics["shortcut_length_rad"]],
                    float)


def _judge_other_elbow(answer) -> Judgement:
    """Three numbers; each wrong one gets its own hint."""
    got = as_number_array(answer)
    if isinstance(got, str):
        return Judgement(False, got + ".")
    if got.shape != (3,):
        return Judgement(False, f"expected 3 numbers (steps on the coarser grid, steps on the finer "
                                f"grid, shortcut length in rad), got shape {got.shape}.")
    want = _other_elbow_answer()
    a, b = _other_elbow(50), _other_elbow(200)
    problems = []
    for k, (plan_, label) in enumerate(((a, "coarser"), (b, "finer"))):
        if got[k] == want[k]:
            continue
        if got[k] == len(plan_.waypoints) or got[k] == want[k] + 1:
            problems.append(f"the steps on the {label} grid count waypoints or cells; a step is a move "
                            "between two neighbouring cells")
        else:
            problems.append(f"the steps on the {label} grid are not right (how far round does each joint "
                            "turn, in steps of one cell?)")
    if not close(got[2], want[2]):
        if close(got[2], want[2], CLOSE_FACTOR):
            problems.append("the shortcut length is close but not within the tolerance; give more digits")
        elif close(got[2], a.metrics["waypoint_length_rad"]) or close(got[2], 2 * np.pi):
            problems.append("the length is that of the grid staircase, before shortcutting")
        elif close(got[2], np.hypot(np.pi / 2, np.pi / 2)):
            problems.append("the length is that of the short straight segment, which passes "
                            "through the disc; the planner goes the other way round on joint 1")
        else:
            problems.append("the shortcut length is not right (how many segments does the shortcut "
                            "keep, and how far does each joint turn along it?)")
    if not problems:
        return Judgement(True, f"{describe(answer)} is right (the length to three significant figures).")
    return Judgement(False, f"{describe(answer)}: " + "; ".join(problems) + ".")


_judge_other_elbow.expected = _other_elbow_answer
_judge_other_elbow.tolerance = TOLERANCE


# --- 7.2: unwrap a path -------------------------------------------------------------------

def _unwrap_ref(arm, path):
    return unwrap_path(arm, path)


def _free_walk(rng, k: int, start: float, max_step: float = np.pi - 0.1) -> np.ndarray:
    """k wrapped angles whose consecutive true moves are shorter than pi (not close to it)."""
    steps = rng.uniform(-max_step, max_step, k - 1)
    return wrap_angle(start + np.concatenate(([0.0], np.cumsum(steps))))


def _paths(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (one row, the seam both ways, two whole turns, a limited joint with a big jump),
    then random arms of 1 to 3 joints and random paths."""
    a1 = Arm([1.0])
    a2 = Arm([1.0, 1.0])
    lim = Arm([1.0, 1.0], [None, (-3.0, 3.0)])
    turns = wrap_angle(np.linspace(0.0, 4 * np.pi, 17))[:, None]
    cases: list[tuple] = [
        (a2, np.array([[0.5, -0.5]])),                                 # one configuration
        (a1, np.array([[3.0], [-3.0]])),                               # across the seam, upwards
        (a1, np.array([[-3.0], [3.0], [2.0]])),                        # across the seam, downwards
        (a1, turns),                                                   # two whole turns
        (lim, np.array([[3.0, -2.9], [-3.1, 2.9], [-2.5, 0.0]])),      # a limited joint jumps by 5.8
        (a2, np.array([[0.0, 0.0], [1.0, -1.0], [2.0, -2.0]])),        # nothing to unwrap
    ]
    for _ in range(50):
        n = int(rng.integers(1, 4))
        limits = [None if rng.random() < 0.6 else (-3.0, 3.0) for _ in range(n)]
        arm = Arm([1.0] * n, limits)
        k = int(rng.integers(2, 25))
        cols = [_free_walk(rng, k, float(rng.uniform(-np.pi, np.pi))) if lim_ is None
                else rng.uniform(-3.0, 3.0, k) for lim_ in limits]
        cases.append((arm, np.stack(cols, axis=1)))
    return cases


def _compare_unwrap(got, want, args) -> str | None:
    arm, path = args
    if got is None:
        return "returned None (a missing return?)."
    g = as_number_array(got)
    if isinstance(g, str):
        return f"returned {describe(got)}, not an array of angles."
    w = np.asarray(want, float)
    if g.shape != w.shape:
        return f"returned shape {g.shape}; expected the path's own shape {w.shape}."
    if np.allclose(g, w, rtol=0.0, atol=1e-9):
        return None
    if not np.allclose(g[0], path[0], rtol=0.0, atol=1e-9):
        return "moved the first configuration; unwrapping keeps the path's start where it is."
    limited = np.asarray(arm.limited)
    if limited.any() and not np.allclose(g[:, limited], path[:, limited], rtol=0.0, atol=1e-9):
        return ("changed a limited joint's column; a limited joint lives on an interval, not a circle "
                "(arm.limited says which joints wrap).")
    turns = (g - path) / (2 * np.pi)
    if not np.allclose(turns, np.round(turns), rtol=0.0, atol=1e-9):
        return "changed an angle by something other than whole turns (2 pi)."
    jumps = np.abs(np.diff(g[:, ~limited], axis=0))
    if jumps.size and jumps.max() > np.pi + 1e-9:
        return ("returned a path whose consecutive configurations still differ by more than pi on a "
                "free joint: that is the long way round (the wrap is forgotten, or unwrapped along "
                "the wrong axis).")
    return "returned whole-turn shifts that differ from the package's: keep each step the short way."


# --- 7.3: the resolution at which "no" means "no on a grid that sees every obstacle" -----------

def _smallest_cells(ok, start: int = 2, stop: int = 10_000) -> int:
    """The smallest number of cells per joint M >= start with ok(M)."""
    return next(m for m in range(start, stop) if ok(m))


def _no_solution():
    from rapp.scenario import load_scenario

    return load_scenario("no_solution")


def _trusted_cells() -> int:
    s = _no_solution()
    rho = min(obstacle_size(ob) for ob in s.obstacles)
    return _smallest_cells(lambda m: grid_step_motion(s.arm, JointGrid(s.arm, m)) <= rho)


def _cells_mistake(joint1_span, reach1) -> int:
    """The answer with joint 1's cell spacing ``joint1_span(M)`` and one joint-1 step moving the
    arm ``reach1`` times that spacing."""
    s = _no_solution()
    rho = min(obstacle_size(ob) for ob in s.obstacles)
    l2 = s.arm.link_lengths[1]
    return _smallest_cells(lambda m: max(reach1 * joint1_span(m), l2 * 2 * np.pi / m) <= rho)


# --- 7.4: a path the coarse grid misses ----------------------------------------------------

_MAX_FINE_CELLS = 40_000


def _outcome(scenario, cells):
    """A verified Plan, or the RappError ``rapp.plan`` raised."""
    from rapp.planner import plan

    d = scenario.to_dict()
    d["planner"]["cells"] = cells
    try:
        return plan(d)
    except RappError as exc:
        return exc


def _judge_coarse_miss(answer) -> Judgement:
    """``(scenario, coarse_cells, fine_cells)``: the coarse grid says no path, the fine one plans."""
    from rapp.scenario import load_scenario

    if answer is None:
        return Judgement(False, "no answer yet: pass (scenario, coarse_cells, fine_cells).")
    try:
        scenario, coarse, fine = answer
    except Exception:
        return Judgement(False, f"expected a tuple (scenario, coarse_cells, fine_cells); got {describe(answer)}.")
    try:
        s = load_scenario(scenario)
    except RappError as exc:
        return Judgement(False, f"the scenario does not load: {exc}.")
    except Exception as exc:
        return Judgement(False, f"the scenario does not load ({type(exc).__name__}); pass a dict, a "
                                "file name or a Scenario.")
    for name, c in (("coarse_cells", coarse), ("fine_cells", fine)):
        if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)) or c < 2:
            return Judgement(False, f"{name} must be one integer >= 2 (cells per joint), got {describe(c)}.")
    coarse, fine = int(coarse), int(fine)
    if coarse >= fine:
        return Judgement(False, "coarse_cells must be fewer than fine_cells.")
    if fine ** s.arm.n > _MAX_FINE_CELLS:
        return Judgement(False, f"the fine grid would have {fine ** s.arm.n:,} cells; keep it to "
                                f"{_MAX_FINE_CELLS:,} (for two joints, at most 200 per joint).")
    if s.planner.algorithm != "astar":
        return Judgement(False, "this exercise is about the grid planner: leave planner.algorithm at astar.")
    first = _outcome(s, coarse)
    if not isinstance(first, RappError):
        return Judgement(False, f"on {coarse} cells per joint the planner finds a path; the coarse grid "
                                "must say no.")
    if not isinstance(first, NoPathFound):
        return Judgement(False, f"on {coarse} cells the planner raised {type(first).__name__}: {first}; "
                                "that is not a 'no path' answer.")
    second = _outcome(s, fine)
    if isinstance(second, NoPathFound):
        return Judgement(False, f"on {fine} cells per joint the planner finds no path either: is there "
                                "a path in the scene at all? Try a finer grid, or another scene.")
    if isinstance(second, RappError):
        return Judgement(False, f"on {fine} cells the planner raised {type(second).__name__}: {second}.")
    if not second.report.ok:
        return Judgement(False, f"on {fine} cells the plan fails verification: {second.report}.")
    kind = ("GridTooCoarse: the planner itself warned that its grid was too coarse"
            if isinstance(first, GridTooCoarse) else
            "a plain NoPathFound, although its grid passed the delta <= rho rule: the stronger "
            "counterexample")
    return Judgement(True, f"on {coarse} cells per joint the planner said {kind}; on {fine} cells it "
                           "planned a verified path. The coarse 'no' was about the grid only.")


# --- 7.5: a link of length zero -------------------------------------------------------------

_ZERO_LINK = {"arm": {"link_lengths": [1.0, 0.0]}, "start": [0.0, 0.0], "goal": {"joints": [1.0, 0.0]}}


def _zero_link_exit_code() -> int:
    from rapp.cli import main

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "zero.json")
        with open(path, "w") as fh:
            json.dump(_ZERO_LINK, fh)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            return int(main(["plan", path]))


EXERCISES = (
    Exercise(
        "7.1", 7, "numeric", "The other elbow at two resolutions", 1,
        "three numbers: the grid steps on the coarser grid, on the finer grid, and the shortcut "
        "length on the coarser grid (rad)",
        _judge_other_elbow,
    ),
    Exercise(
        "7.2", 7, "implement", "Unwrap a path", 2,
        "a function unwrap(arm, path) returning the unwrapped (k, n) array",
        implement(_unwrap_ref, _paths, call="unwrap(arm, path)", names=("arm", "path"),
                  compare=_compare_unwrap, seed=72),
    ),
    Exercise(
        "7.3", 7, "numeric", "When a grid is fine enough to see the post", 2,
        "an integer: the smallest number of cells per joint",
        numeric(_trusted_cells, exact_integer=True,
                mistakes=[(lambda: _cells_mistake(lambda m: np.pi / m, 2.0),
                           "at that size one step of joint 1 still moves the tip more than the post's "
                           "radius. Joint 1 is limited: its grid has a cell at each limit, so how many "
                           "gaps between cells span its range? And a step of joint 1 turns both links."),
                          (lambda: _cells_mistake(lambda m: 2 * np.pi / m, 2.0),
                           "joint 1 is limited to [-pi/2, pi/2]; its cells span that range, not a "
                           "whole turn.")],
                hint="find delta(M), the most one step of either joint moves any point of the arm "
                     "(the tip is farthest), and solve delta(M) <= rho for the smallest whole M."),
    ),
    Exercise(
        "7.4", 7, "argue", "A path the coarse grid misses", 2,
        "a tuple (scenario, coarse_cells, fine_cells): rapp.plan says no path on the coarse grid "
        "and plans a verified path on the fine one",
        _judge_coarse_miss,
    ),
    Exercise(
        "7.5", 7, "numeric", "A link of length zero", 1,
        "an integer: the exit code of python -m rapp plan",
        numeric(_zero_link_exit_code, exact_integer=True,
                mistakes=[(lambda: 1, "1 is a planning answer (no path, no IK solution); does this "
                                      "scenario get as far as planning?"),
                          (lambda: 0, "0 means planned and verified; can an arm with a zero link be "
                                      "loaded at all?")],
                hint="the chapter's last section lists the three exit codes."),
    ),
)
