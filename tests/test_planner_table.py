"""The planner contract, held by every planner of the table (rapp/planners.py).

Every entry's function takes ``(arm, start, goal, obstacles, *, <its settings>,
raise_on_failure)``, returns a PlannerResult whose path joins the exact start to a goal along
certified segments with ``cost`` its length, and says failure the same way. A planner added to
the table joins these tests by name.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

import rapp
from rapp import planners
from rapp.errors import NoPathFound
from rapp.paths import STATUSES, PlannerResult, path_length

NAMES = sorted(planners.PLANNERS)
#: Small settings for a unit test; each planner reads only its own.
SMALL = {"cells": 32, "max_iterations": 3000, "samples": 100, "step": 0.3, "goal_threshold": 0.3}
#: RRT* runs its whole budget: a smaller one keeps the test fast.
OWN = {"rrt_star": {"max_iterations": 800}}


@pytest.mark.parametrize("name", NAMES)
def test_the_leading_parameters_and_the_settings_are_the_contract(name):
    entry = planners.PLANNERS[name]
    params = inspect.signature(entry.function).parameters
    assert list(params)[:4] == ["arm", "start", "goal", "obstacles"]
    assert params["raise_on_failure"].kind is inspect.Parameter.KEYWORD_ONLY
    for key in entry.keys:   # every setting of the table is a keyword of the function
        assert params[key].kind is inspect.Parameter.KEYWORD_ONLY, key
    for s in entry.settings:  # and its default lies in its own range
        assert s.kind == "cells" or s.accepts(s.default), (name, s.key)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("seed", [0, 1])
def test_a_path_joins_the_start_to_a_goal_along_certified_segments(name, seed):
    # A complete planner must find the path; one that is not (``complete=""``) may fail, saying why.
    s = rapp.load_scenario("rectangles")
    goals = np.array([s.goal_q, np.asarray(s.goal_q) + [0.05, 0.0]])
    goals = goals[~rapp.collides(s.arm, goals, s.obstacles)]
    r = planners.run(name, s.arm, s.start_array, goals, s.obstacles, seed=seed,
                     raise_on_failure=False, **{**SMALL, **OWN.get(name, {})})
    assert isinstance(r, PlannerResult)
    if not planners.PLANNERS[name].complete and not r.success:
        assert r.status in STATUSES and r.status != "solved"
        return
    assert r.success and r.status == "solved"
    assert np.allclose(r.path[0], s.start_array)
    assert np.min(np.abs(s.arm.joint_delta(r.path[-1], goals)).max(axis=-1)) <= 1e-9
    assert rapp.path_collision_free(s.arm, r.path, s.obstacles)
    assert r.cost == pytest.approx(path_length(r.path))
    assert isinstance(r.details, dict) and r.waypoints is r.path


@pytest.mark.parametrize("name", NAMES)
def test_failure_is_said_the_same_way(name):
    s = rapp.load_scenario("no_solution")   # the goal is walled off (chapter 7)
    args = (s.arm, s.start_array, s.goal_q, s.obstacles)
    small = dict(SMALL, max_iterations=300)
    r = planners.run(name, *args, raise_on_failure=False, **small)
    assert not r.success and r.path.shape == (0, s.arm.n) and r.cost == np.inf
    # Why it stopped: a proof where the planner can give one, else the limit it spent.
    entry = planners.PLANNERS[name]
    if entry.proves_no_path:   # no path on this grid, or none it can prove at its resolution
        assert r.status in ("proved no path", "grid too coarse"), r.status
    else:
        assert r.status in ("iteration cap", "node cap"), r.status
    with pytest.raises(NoPathFound) as info:
        planners.run(name, *args, **small)
    if not entry.proves_no_path:   # a stop by a limit names the limit
        limit = "max_iterations 300 reached" if r.status == "iteration cap" else "max_samples"
        assert limit in str(info.value) and "stopped" in str(info.value)


def test_run_reads_only_the_planners_own_settings_and_names_an_unknown_planner():
    arm = rapp.Arm([1.0, 1.0])
    a = planners.run("rrt_connect", arm, [0.0, 0.0], [1.0, 0.5], [], seed=3, cells=7, samples=11)
    b = rapp.rrt_connect(arm, [0.0, 0.0], [1.0, 0.5], [], seed=3)
    assert np.array_equal(a.path, b.path) and a.iterations == b.iterations
    with pytest.raises(ValueError, match="unknown planner 'dstar'.*astar"):
        planners.run("dstar", arm, [0.0, 0.0], [1.0, 0.5])


def test_old_attribute_names_keep_working_and_an_absent_one_is_named():
    r = rapp.rrt(rapp.Arm([1.0, 1.0]), [0.0, 0.0], [0.5, 0.0], [], seed=0)
    assert isinstance(r, rapp.RRTResult) and r.nodes.shape[1] == 2 and r.parent[0] == -1
    assert r.iterations >= 1 and r.success and np.isfinite(r.cost)
    with pytest.raises(AttributeError, match="'grid'.*nodes, parent, iterations"):
        r.grid


@pytest.mark.parametrize("name", NAMES)
def test_the_table_and_a_direct_call_run_the_same_defaults(name):
    # One source of defaults: the entry reads its function's signature, so a scenario naming the
    # planner and a call of the function with no settings plan the same path.
    entry = planners.PLANNERS[name]
    params = inspect.signature(entry.function).parameters
    for s in entry.settings:
        expected = params[s.key].default
        assert s.default == (None if expected is inspect.Parameter.empty else expected), s.key
    arm, start, goal = rapp.Arm([1.0, 1.0]), [0.0, 0.0], [[1.0, 0.5]]
    obstacles = [rapp.Circle((0.0, 1.4), 0.3)]
    kw = {"max_iterations": 300} if entry.anytime else {}
    a = planners.run(name, arm, start, goal, obstacles, **kw)
    b = entry.function(arm, start, goal, obstacles, **kw)
    assert np.array_equal(a.path, b.path) and a.status == b.status == "solved"


def test_the_old_differing_defaults_are_gone():
    # rapp.rrt_star() used step 0.2, goal_bias 0.05, goal_threshold 0.05, 2000 iterations while
    # every scenario ran 0.1, 0.1, 0.01, 3000 (issue 36); rrt and rrt_connect 5000 iterations.
    assert [planners.PLANNERS["rrt_star"].default(k) for k in
            ("step", "goal_bias", "goal_threshold", "max_iterations")] == [0.1, 0.1, 0.01, 3000]
    assert planners.PLANNERS["rrt"].default("max_iterations") == 20000
    assert inspect.signature(rapp.rrt_star).parameters["step"].default == 0.1


def test_astar_without_cells_takes_its_default_grid():
    from rapp.grid_route import default_cells
    r = planners.run("astar", rapp.Arm([1.0, 1.0]), [0.0, 0.0], [[2.0, 0.5]],
                     [rapp.Circle((1.5, 0.5), 0.3)])
    assert r.success and r.grid.shape == (default_cells(2),) * 2


def test_a_stop_by_the_time_budget_says_so_and_names_it():
    s = rapp.load_scenario("no_solution")   # the goal is walled off (chapter 7)
    args = (s.arm, s.start_array, s.goal_q, s.obstacles)
    for name in ("rrt", "rrt_connect", "rrt_star", "prm"):
        r = planners.run(name, *args, max_iterations=10**7, time_budget=0.05,
                         raise_on_failure=False)
        assert r.status == "time budget spent", name
        with pytest.raises(NoPathFound, match=r"stopped: time_budget 0.05 s spent after \d+ "):
            planners.run(name, *args, max_iterations=10**7, time_budget=0.05)


@pytest.mark.parametrize("name", NAMES)
def test_the_flags_say_what_the_planner_guarantees(name):
    entry = planners.PLANNERS[name]
    assert entry.complete in ("resolution", "probabilistic", "")
    assert entry.optimizing in ("resolution", "asymptotically", "")
    # Only a grid planner can prove there is no path; an anytime planner runs every iteration.
    assert entry.proves_no_path <= entry.grid
    if entry.anytime:
        assert entry.optimizing


def test_a_failure_must_say_why_it_stopped():
    with pytest.raises(ValueError, match="status"):
        PlannerResult(np.empty((0, 2)), False, np.inf, {})
    with pytest.raises(ValueError, match="status"):
        PlannerResult(np.zeros((1, 2)), True, 0.0, {}, "iteration cap")
