"""plan() (IM1, MIS executePlanning): every embedded scenario plans and verifies; the
pieces (certified cells, shortcutting, polyline timing) keep their promises; random
scenarios either verify or fail only when breadth-first search agrees there is no path."""

from collections import deque

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, event, given, settings, strategies as st

from rapp import Arm, Circle, InvalidValue, NoPathFound, load_scenario, plan, wrap_angle
from rapp.collision import collides, segment_collision_free
from rapp.cspace import JointGrid, occupancy
from rapp.cspace import certified_free
from rapp.errors import GridTooCoarse
from rapp.paths import shortcut
from rapp.planner import PLANNERS, STAGES
from rapp.results import Plan, load_result, save_result
from rapp.trajectory import time_polyline
from rapp.scenario import list_scenarios
from rapp.grid_route import _route_on
from rapp.verify import verify

SOLVABLE = [n for n in list_scenarios() if n != "no_solution"]


def slow_bfs_reachable(occ, start, wraps):
    """Obviously correct breadth-first search, one cell at a time (the oracle)."""
    seen = {tuple(start)}
    todo = deque([tuple(start)])
    while todo:
        c = todo.popleft()
        for ax in range(occ.ndim):
            for d in (1, -1):
                nb = list(c)
                nb[ax] += d
                if wraps[ax]:
                    nb[ax] %= occ.shape[ax]
                elif not 0 <= nb[ax] < occ.shape[ax]:
                    continue
                nb = tuple(nb)
                if nb not in seen and not occ[nb]:
                    seen.add(nb)
                    todo.append(nb)
    return seen


@pytest.fixture(scope="module")
def plans():
    return {name: plan(name) for name in SOLVABLE}


@pytest.mark.parametrize("name", SOLVABLE)
def test_every_embedded_scenario_plans_and_verifies(plans, name):
    p = plans[name]
    s = p.scenario
    assert p.report.ok, str(p.report)
    assert verify(p, s) == p.report
    n = s.arm.n
    k = len(p.t)
    assert p.q.shape == p.qd.shape == p.qdd.shape == (k, n) and p.xy.shape == (k, 2)
    assert k >= s.trajectory.samples
    assert np.array_equal(p.q[0], s.start_array)
    assert np.allclose(p.xy, s.arm.end_effector(p.q), atol=0, rtol=0)
    # The timed polyline is certified free segment by segment, and shortcutting only shortens.
    assert segment_collision_free(s.arm, p.shortcut[:-1], p.shortcut[1:], s.obstacles).all()
    assert p.metrics["shortcut_length_rad"] <= p.metrics["waypoint_length_rad"] + 1e-12
    assert set(p.timings) == set(STAGES) == {"compile", "ik", "cspace", "search", "smoothing",
                                             "trajectory", "verify", "total"}
    if s.goal_xy is not None:
        assert np.hypot(*(p.xy[-1] - s.goal_xy)) <= 1e-3


def test_the_goal_is_the_nearest_reachable_ik_solution(plans):
    p = plans["default"]
    assert p.metrics["goal_candidates"] == 2 and p.metrics["ik_solutions"] == 2
    assert p.metrics["path_cells"] == p.metrics["bfs_optimum_cells"]


def test_no_solution_is_proved_by_exhausting_the_grid():
    s = load_scenario("no_solution")
    with pytest.raises(NoPathFound) as e:
        plan(s)
    assert not isinstance(e.value, GridTooCoarse)
    grid = JointGrid(s.arm, s.planner.cells)
    occ = occupancy(s.arm, s.obstacles, grid)
    reach = slow_bfs_reachable(occ, e.value.start_cell, grid.wraps)
    assert not any(tuple(g) in reach for g in e.value.goal_cells)
    assert len(reach) > 100  # the start is not simply boxed in: the wall is the proof


def test_result_round_trip(plans, tmp_path):
    p = plans["three_link"]
    path = tmp_path / "r.json"
    save_result(p, path)
    back = load_result(path)
    for name in ("t", "q", "qd", "qdd", "xy", "waypoints", "shortcut", "goal_q"):
        assert np.array_equal(getattr(back, name), getattr(p, name)), name
    assert np.array_equal(back.occupancy, p.occupancy) and back.grid == p.grid
    assert back.report == p.report and back.scenario == p.scenario
    assert back.metrics == p.metrics and back.profile == p.profile
    assert Plan.from_dict(back.to_dict()).to_dict() == p.to_dict()


def test_save_result_is_atomic(plans, tmp_path, monkeypatch):
    path = tmp_path / "r.json"
    save_result(plans["srs_typical"], path)
    before = path.read_bytes()

    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr("rapp.files.os.replace", boom)
    with pytest.raises(OSError):
        save_result(plans["default"], path)
    assert path.read_bytes() == before
    assert [f.name for f in tmp_path.iterdir()] == ["r.json"]  # no temporary left behind


def test_rrt_is_dispatched_by_name():
    assert set(PLANNERS) >= {"astar", "rrt"}
    s = load_scenario({**load_scenario("srs_typical").to_dict(),
                       "planner": {"algorithm": "rrt", "step": 0.2, "seed": 3,
                                   "goal_threshold": 0.01, "max_iterations": 5000}})
    p = plan(s)
    assert p.report.ok and p.grid is None


@settings(max_examples=40, deadline=None)
@given(st.integers(8, 24), st.integers(0, 2**32 - 1))
def test_certified_cells_certify_every_move_between_them(cells, seed):
    rng = np.random.default_rng(seed)
    arm = Arm(rng.uniform(0.3, 1.2, 2))
    obs = [Circle(rng.uniform(-1.5, 1.5, 2), rng.uniform(0.1, 0.5)) for _ in range(2)]
    grid = JointGrid(arm, cells)
    safe = certified_free(arm, obs, grid)
    assert not (safe & occupancy(arm, obs, grid)).any()
    a = np.argwhere(safe)
    assume(len(a))
    a = a[rng.integers(len(a), size=min(len(a), 40))]
    axis = rng.integers(2, size=len(a))
    b = a.copy()
    b[np.arange(len(a)), axis] = (b[np.arange(len(a)), axis] + 1) % cells
    both = safe[tuple(b.T)]
    qa = grid.angles(a[both])
    qb = qa + np.eye(2)[axis[both]] * grid.step  # the short way across the seam
    assert segment_collision_free(arm, qa, qb, obs).all()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(3, 12))
def test_shortcut_keeps_endpoints_order_and_freedom(seed, k):
    rng = np.random.default_rng(seed)
    arm = Arm([1.0, 0.7])
    obs = [Circle((1.0, 1.0), 0.3)]
    path = np.cumsum(rng.uniform(-0.15, 0.15, (k, 2)), axis=0)
    ok = segment_collision_free(arm, path[:-1], path[1:], obs)
    assume(ok.all() and not collides(arm, path, obs).any())
    out = shortcut(arm, path, obs)
    assert np.array_equal(out[0], path[0]) and np.array_equal(out[-1], path[-1])
    idx = [int(np.flatnonzero((path == r).all(axis=1))[0]) for r in out]
    assert idx == sorted(idx)
    assert segment_collision_free(arm, out[:-1], out[1:], obs).all()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 6), st.integers(2, 50))
def test_time_polyline_stays_on_the_polyline_and_rests_at_waypoints(seed, k, samples):
    rng = np.random.default_rng(seed)
    w = rng.uniform(-2, 2, (k, 3))
    t, q, qd, qdd = time_polyline(w, 3.0, samples)
    assert t[0] == 0 and t[-1] == 3.0 and np.all(np.diff(t) > 0)
    assert np.array_equal(q[0], w[0]) and np.array_equal(q[-1], w[-1])
    # Every sample lies on some segment of the polyline.
    a, b = w[:-1], w[1:]
    d = b - a
    u = np.clip(np.einsum("sij,ij->si", q[:, None] - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
    dist = np.linalg.norm(q[:, None] - (a + u[..., None] * d), axis=-1).min(axis=1)
    assert dist.max() < 1e-12
    # Every waypoint is a sample, exactly, at rest. (Matched within 1e-12 instead, a uniform
    # sample 1.5e-5 s before a waypoint, 5e-13 from it and still moving, was taken for it.)
    at = np.array([np.flatnonzero(np.all(q == p, axis=1))[0] for p in w])
    assert np.abs(qd[at]).max() < 1e-9
    # q' and q'' are the derivatives of q: finite differences on a fine sampling agree.
    t, q, qd, qdd = time_polyline(w, 3.0, 6000)
    scale = max(np.abs(qdd).max(), 1.0)
    assert np.abs(np.gradient(q, t, axis=0) - qd)[1:-1].max() < 1e-2 * scale
    assert np.abs(np.gradient(qd, t, axis=0) - qdd)[1:-1].max() < 2e-2 * scale


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.integers(0, 2**32 - 1), st.integers(16, 40), st.integers(1, 5),
       st.sampled_from(["cubic", "quintic", "spline"]), st.booleans())
def test_random_scenarios_verify_or_bfs_agrees_there_is_no_path(seed, cells, n_obs, profile,
                                                               limited):
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(0.4, 1.2, 2).round(3).tolist()
    reach = sum(lengths)
    obstacles = [{"type": "circle", "center": rng.uniform(-reach, reach, 2).round(3).tolist(),
                  "radius": round(float(rng.uniform(0.1, 0.7)), 3)} for _ in range(n_obs)]
    # A limited first joint turns the torus into a band that obstacles can cut in two.
    limits = [[-2.5, 2.5], None] if limited else None
    lo = -2.5 if limited else -np.pi
    data = {"arm": {"link_lengths": lengths, "joint_limits": limits}, "obstacles": obstacles,
            "start": [rng.uniform(lo, -lo), rng.uniform(-np.pi, np.pi)],
            "goal": {"joints": [rng.uniform(lo, -lo), rng.uniform(-np.pi, np.pi)]},
            "planner": {"cells": cells},
            "trajectory": {"duration": 2.0, "profile": profile, "samples": 60}}
    try:
        s = load_scenario(data)
    except InvalidValue:  # start or goal in collision
        assume(False)
    try:
        p = plan(s)
    except GridTooCoarse:
        event("grid too coarse")
        return  # the grid holds a path its moves could not certify: a resolution answer
    except NoPathFound as e:
        grid = JointGrid(s.arm, cells)
        occ = occupancy(s.arm, s.obstacles, grid)
        assert not occ[e.start_cell]
        reach_set = slow_bfs_reachable(occ, e.start_cell, grid.wraps)
        assert not any(tuple(g) in reach_set for g in e.goal_cells)
        event("no path (proved)")
        return
    event("planned")
    assert p.report.ok, str(p.report)


def test_search_on_the_plain_occupancy_repairs_uncertified_moves():
    # On the plain occupancy (cell centres only) a coarse grid offers moves that sweep an
    # obstacle; the fallback search must find them, block them and still end certified.
    s = load_scenario("rectangles")
    grid = JointGrid(s.arm, 40)
    occ = occupancy(s.arm, s.obstacles, grid)
    goals = np.array([s.goal_q])
    full, metrics, _ = _route_on(s.arm, s.obstacles, grid, occ, s.start_array, goals,
                                 certified=False, heuristic_weight=1.0, max_expansions=None)
    assert metrics["certification_repairs"] > 0
    assert segment_collision_free(s.arm, full[:-1], full[1:], s.obstacles).all()
    assert np.array_equal(full[0], s.start_array)
    assert np.allclose(wrap_angle(full[-1] - s.goal_q), 0)  # unwrapped: whole turns apart
    assert metrics["path_cells"] >= metrics["bfs_optimum_cells"]


# ------------------------------------------------------------ reliability: right answers

def test_a_coarse_grid_says_the_grid_may_be_the_cause():
    # Before: a 4x4 grid answered plain NoPathFound ("proved by exhausting the grid") where
    # 100 cells plan. One step of a 4x4 grid moves the arm metres; the grid proves nothing.
    d = load_scenario("rectangles").to_dict()
    d["planner"]["cells"] = 4
    with pytest.raises(GridTooCoarse) as e:
        plan(d)
    assert "planner.cells" in str(e.value)
    d["planner"]["cells"] = 100
    assert plan(d).report.ok
    # A grid fine enough for its obstacles still proves "no path".
    with pytest.raises(NoPathFound) as e:
        plan("no_solution")
    assert not isinstance(e.value, GridTooCoarse)


@pytest.mark.parametrize("name", SOLVABLE)
@pytest.mark.parametrize("profile", ["cubic", "quintic", "spline"])
@pytest.mark.parametrize("samples", [2, 3])
def test_few_samples_still_verify(name, profile, samples):
    # Before: samples = 2 failed the continuity check (a rest-to-rest piece seen only at its
    # ends looks like a jump); each piece is now seen inside as well.
    d = load_scenario(name).to_dict()
    d["trajectory"].update(samples=samples, profile=profile)
    p = plan(d)
    assert p.report.ok, str(p.report)
    assert len(p.t) >= samples


@pytest.mark.parametrize("name", ["default", "three_link"])
def test_results_are_identical_run_after_run(name, tmp_path):
    a, b = plan(name), plan(name)
    save_result(a, tmp_path / "a.json")
    save_result(b, tmp_path / "b.json")
    assert (tmp_path / "a.json").read_bytes() == (tmp_path / "b.json").read_bytes()
    assert "timings" not in a.to_dict() and set(a.to_dict(timings=True)["timings"]) == set(STAGES)


def test_rrt_with_a_wide_goal_region_ends_exactly_on_the_goal():
    # Before: goal_threshold >= 2 let the tree stop short of the goal when the last edge to it
    # was blocked; the plan then failed verification (exit 3).
    d = load_scenario("default").to_dict()
    d["planner"] = {"algorithm": "rrt", "goal_threshold": 1.0, "seed": 3}
    for seed in range(4):
        d["planner"]["seed"] = seed
        p = plan(d)
        assert p.report.ok and p.report["goal reached"].value <= 1e-9


@pytest.mark.slow
def test_defaults_plan_a_nine_link_arm():
    n = 9
    d = {"arm": {"link_lengths": [2.0 / n] * n}, "start": [0.0] * n,
         "goal": {"position": [-1.0, 0.8]},
         "obstacles": [{"type": "circle", "center": [0.9, 1.0], "radius": 0.25}]}
    p = plan(d)
    assert p.report.ok and p.scenario.planner.algorithm == "rrt"
