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
from rapp.paths import PlannerResult, path_length

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
    s = rapp.load_scenario("rectangles")
    goals = np.array([s.goal_q, np.asarray(s.goal_q) + [0.05, 0.0]])
    goals = goals[~rapp.collides(s.arm, goals, s.obstacles)]
    r = planners.run(name, s.arm, s.start_array, goals, s.obstacles, seed=seed,
                     **{**SMALL, **OWN.get(name, {})})
    assert isinstance(r, PlannerResult) and r.success
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
    with pytest.raises(NoPathFound):
        planners.run(name, *args, **small)


def test_run_reads_only_the_planners_own_settings_and_names_an_unknown_planner():
    arm = rapp.Arm([1.0, 1.0])
    a = planners.run("rrt_connect", arm, [0.0, 0.0], [1.0, 0.5], [], seed=3, cells=7, samples=11)
    b = rapp.rrt_connect(arm, [0.0, 0.0], [1.0, 0.5], [], seed=3, step=planners.STEP.default,
                         max_iterations=planners.PLANNERS["rrt_connect"].default("max_iterations"))
    assert np.array_equal(a.path, b.path) and a.iterations == b.iterations
    with pytest.raises(ValueError, match="unknown planner 'dstar'.*astar"):
        planners.run("dstar", arm, [0.0, 0.0], [1.0, 0.5])


def test_old_attribute_names_keep_working_and_an_absent_one_is_named():
    r = rapp.rrt(rapp.Arm([1.0, 1.0]), [0.0, 0.0], [0.5, 0.0], [], seed=0)
    assert isinstance(r, rapp.RRTResult) and r.nodes.shape[1] == 2 and r.parent[0] == -1
    assert r.iterations >= 1 and r.success and np.isfinite(r.cost)
    with pytest.raises(AttributeError, match="'grid'.*nodes, parent, iterations"):
        r.grid
