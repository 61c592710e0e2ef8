"""The planner comparison harness (rapp.compare, run by ``python -m rapp compare``) on a few scenarios.

The full run (30 scenarios x 20 seeds) is a benchmark, not a test; here a small run proves the
harness: scenarios are valid and reproducible, every run of every planner gives a record, a
success is a verified plan, any Executor works, and the intervals are right.
"""

import json
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import rapp
from rapp import compare as cp

from tests.helpers import load_script

cli = load_script("benchmarks/compare_planners.py")


def test_scenarios_are_valid_reproducible_and_varied():
    first, again = cp.make_scenarios(8, seed=5), cp.make_scenarios(8, seed=5)
    assert first == again and first != cp.make_scenarios(8, seed=6)
    kinds = {(len(s["arm"]["link_lengths"]), "position" in s["goal"]) for s in first}
    assert {n for n, _ in kinds} == {2, 3, 4} and {c for _, c in kinds} == {True, False}
    assert sum("narrow" in s["description"] for s in first) == 2
    types = {o["type"] for s in first for o in s["obstacles"]}
    assert types == {"circle", "polygon"}
    for s in first:
        scenario = rapp.load_scenario(s)  # valid input: start free, goal reachable
        assert not rapp.collides(scenario.arm, scenario.start_array, scenario.obstacles)


def test_a_small_run_on_a_thread_pool_records_every_task():
    with ThreadPoolExecutor(2) as pool:
        result = cp.run(scenarios=2, seeds=2, executor=pool, planners=["astar_24", "astar_16", "rrt_connect"])
    records = result["records"]
    # scenario 0 has 2 links (A* 24: once), scenario 1 has 3 links (A* 16: once); RRT-Connect twice each.
    assert sorted((r["scenario_index"], r["planner"]) for r in records) == [
        (0, "astar_24"), (0, "rrt_connect"), (0, "rrt_connect"), (1, "astar_16"), (1, "rrt_connect"),
        (1, "rrt_connect")]
    for r in records:
        if r["success"]:
            assert math.isfinite(r["time_s"]) and r["shortcut_length_rad"] <= r["length_rad"] + 1e-9
        else:
            assert r["error"]
    json.dumps(result)  # the result is what the harness writes
    summary = result["summary"]["rrt_connect"]["all"]
    assert summary["runs"] == 4 and 0.0 <= summary["success_interval"][0] <= summary["success_rate"]


def test_same_seed_same_path_length():
    task = cp.tasks(cp.make_scenarios(1), seeds=1, planners=["rrt_connect"])[0]
    a, b = cp.run_task(task), cp.run_task(task)
    assert a.success == b.success and (a.length_rad == b.length_rad or not a.success)


def test_intervals():
    lo, hi = cp.wilson(0, 20)
    assert lo == 0.0 and hi == pytest.approx(0.1611, abs=1e-4)
    lo, hi = cp.wilson(10, 20)
    assert (lo, hi) == pytest.approx((0.2993, 0.7007), abs=1e-4)
    for n in range(1, 400):  # the interval always holds the rate, to the last bit
        for k in {0, 1, n // 2, n - 1, n}:
            lo, hi = cp.wilson(k, n)
            assert 0.0 <= lo <= k / n <= hi <= 1.0
    m = cp.mean_interval([1.0, 2.0, 3.0, math.nan])
    assert m["mean"] == 2.0 and m["n"] == 3
    t = 0.95 * math.sqrt(2 / (4 * 0.975 * 0.025))  # Student's t, 97.5 %, 2 degrees of freedom
    assert (m["low"], m["high"]) == pytest.approx((2.0 - t / math.sqrt(3), 2.0 + t / math.sqrt(3)), rel=1e-12)
    assert math.isnan(cp.mean_interval([])["mean"])


def test_the_benchmark_runs_rapps_planners_through_the_package(capsys, tmp_path):
    task = cp.tasks(cp.make_scenarios(1), seeds=1, planners=["astar_24"])[0]
    a, b = cli.run_task(task), cp.run_task(task)
    assert a.success and (a.planner, a.length_rad, a.shortcut_length_rad) == (
        b.planner, b.length_rad, b.shortcut_length_rad)
    # It is python -m rapp compare: the same options and one-line refusals.
    assert cli.main(["--workers", "0", "--out", str(tmp_path / "r.jsonl")]) == 2
    assert "--workers" in capsys.readouterr().err


def test_the_recorded_results_ship_with_the_package():
    results = cp.recorded_results()
    settings = results["settings"]
    assert len(results["scenarios"]) == settings["scenarios"] == 30
    assert results["scenarios"] == cp.make_scenarios(30, settings["scenario_seed"])
    # Every (scenario, seed, planner) of the protocol exactly once, OMPL's planners included.
    todo = cp.tasks(results["scenarios"], settings["seeds"], settings["planners"], settings["extra"])
    assert sorted(cp.task_key(r) for r in results["records"]) == sorted(cp.task_key(t) for t in todo)
    # Its intervals are those of the records, with the exact t quantile.
    for planner, by_class in results["summary"].items():
        times = [r["time_s"] for r in results["records"] if r["planner"] == planner and r["success"]]
        assert by_class["all"]["time_s"] == pytest.approx(cp.mean_interval(times), nan_ok=True)


def test_separated_lists_exactly_the_comparisons_whose_intervals_lie_apart():
    from rapp.compare import group_runs, recorded_results
    g = group_runs(recorded_results())
    s = g.separated()
    fams = g.families

    def above(x, y):  # the definition, by hand: x's low end strictly above y's high end
        return np.isfinite(x[0]) and np.isfinite(y[1]) and x[0] > y[1]

    want_higher = [(f, h) for f in fams for h in fams
                   if f != h and above(g.stats[f, "all"]["interval"], g.stats[h, "all"]["interval"])]
    want_faster = [(f, h) for f in fams for h in fams
                   if f != h and above(g.interval(h, "time_s"), g.interval(f, "time_s"))]
    assert s.higher == want_higher and s.faster == want_faster
    assert s.pairs == len(fams) * (len(fams) - 1) // 2 == 36
    assert s.undecided == s.pairs - len(want_higher)
    assert all(above(g.interval(f, "length_rad"), g.interval(f, "shortcut_length_rad")) for f in s.shorter)
    assert len(s.lines().splitlines()) == 4
