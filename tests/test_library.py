"""rapp as a library engineers adopt (issue 34): packaging, the small frictions, composable
motion (planner -> shortcut -> timing under limits -> export), the exports' columns and keys,
an arm's base pose, joint offsets and names. Everything here needs only the library (no book
stack): scripts/smoke_pythons.py runs this file on every CPython the machine has."""

import csv
from importlib import resources
import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rapp
from rapp import planners
from rapp.cli import main
from rapp.results import csv_columns, joint_trajectory, save_csv, save_joint_trajectory
from rapp.time_scaling import minimum_duration, peak_rates

ROOT = Path(__file__).resolve().parents[1]


def project() -> dict:
    tomllib = pytest.importorskip("tomllib")   # Python 3.11+; the 3.10 smoke run skips these
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
SMALL = {"arm": {"link_lengths": [1.0, 1.0], "joint_names": ["shoulder", "elbow"],
                 "joint_offsets": [0.25, -0.5]},
         "obstacles": [{"type": "circle", "center": [1.75, 0.75], "radius": 0.4}],
         "start": [0.0, 0.0], "goal": {"joints": [2.0, 0.5]},
         "planner": {"cells": 40}, "trajectory": {"samples": 40}}


# --------------------------------------------------------------------------- packaging


def test_the_version_is_the_one_pyproject_declares_and_the_command_says_it(capsys):
    meta = project()
    assert rapp.__version__ == meta["version"]
    with pytest.raises(SystemExit):  # argparse's --version exits; main() turns it into 0
        rapp.cli.build_parser().parse_args(["--version"])
    capsys.readouterr()
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"rapp {rapp.__version__}"


def test_the_package_declares_its_license_extras_and_python_versions():
    meta = project()
    assert meta["license"] == "MIT" and "LICENSE" in meta["license-files"]
    assert (ROOT / "LICENSE").read_text(encoding="utf-8").startswith("MIT License")
    assert meta["optional-dependencies"]["fast"] == ["numba"]
    assert meta["scripts"]["rapp"] == "rapp.cli:command"
    versions = {c.rsplit(" ", 1)[1] for c in meta["classifiers"]
                if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c)}
    assert versions == {"3.10", "3.11", "3.12", "3.13"}
    assert meta["requires-python"] == ">=3.10"
    assert resources.files("rapp").joinpath("py.typed").is_file()   # the installed package


def test_the_changelog_has_an_entry_for_this_version():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert re.search(rf"^## \[{re.escape(rapp.__version__)}\] - \d{{4}}-\d\d-\d\d$", text, re.M)


# --------------------------------------------------------------------------- frictions


def test_rrt_refuses_a_colliding_goal_before_any_iteration():
    arm = rapp.Arm([1.0, 1.0])
    wall = [rapp.Circle((2.0, 0.0), 0.3)]            # the goal q = (0, 0) reaches into it
    with pytest.raises(rapp.NoPathFound, match="every goal configuration collides"):
        rapp.rrt(arm, [np.pi / 2, 0.0], [0.0, 0.0], wall, max_iterations=10**7)
    r = rapp.rrt(arm, [np.pi / 2, 0.0], [0.0, 0.0], wall, raise_on_failure=False)
    assert not r.success and r.iterations == 0
    # A colliding goal among free ones is dropped: the path ends on the free one.
    ok = rapp.rrt(arm, [np.pi / 2, 0.0], [[0.0, 0.0], [np.pi, 0.0]], wall, seed=3, step=0.2)
    assert ok.success and np.allclose(arm.wrap(ok.path[-1]), arm.wrap([np.pi, 0.0]))


def test_every_planner_of_the_table_refuses_a_colliding_goal_the_same_way():
    arm = rapp.Arm([1.0, 1.0])
    wall = [rapp.Circle((2.0, 0.0), 0.3)]
    for name in planners.names():
        if planners.entry(name).grid:
            continue
        with pytest.raises(rapp.NoPathFound, match="goal configuration collides"):
            planners.run(name, arm, [np.pi / 2, 0.0], [0.0, 0.0], wall, max_iterations=10**6)


def test_prm_takes_neighbors_as_well_as_neighbours():
    arm = rapp.Arm([1.0, 1.0])
    obstacles = [rapp.Circle((0.0, 1.2), 0.3)]
    a = rapp.prm(arm, [0.0, 0.0], [2.5, 0.0], obstacles, samples=100, neighbours=5, seed=1)
    b = rapp.prm(arm, [0.0, 0.0], [2.5, 0.0], obstacles, samples=100, neighbors=5, seed=1)
    c = planners.run("prm", arm, [0.0, 0.0], [2.5, 0.0], obstacles, samples=100, neighbors=5, seed=1)
    assert np.array_equal(a.path, b.path) and np.array_equal(a.path, c.path)
    d = rapp.prm(arm, [0.0, 0.0], [2.5, 0.0], obstacles, samples=100, seed=1)  # 10 neighbours
    assert not np.array_equal(a.nodes.shape, ()) and d.success
    with pytest.raises(rapp.errors.InvalidSetting, match="neighbors"):
        rapp.prm(arm, [0.0, 0.0], [2.5, 0.0], obstacles, neighbours=4, neighbors=5)


# --------------------------------------------------------------------------- composable motion


def test_shortcut_and_the_timing_names_are_exported():
    for name in ("shortcut", "trapezoidal_path", "minimum_duration", "peak_rates"):
        assert name in rapp.__all__ and callable(getattr(rapp, name))
    assert rapp.shortcut is rapp.paths.shortcut


waypoints = st.lists(st.lists(st.floats(-3, 3), min_size=2, max_size=2), min_size=2, max_size=6)


@settings(max_examples=30, deadline=None)
@given(waypoints, st.sampled_from(["cubic", "quintic", "spline"]), st.floats(0.2, 5.0),
       st.floats(0.2, 5.0))
def test_time_path_under_limits_is_the_shortest_within_them(w, profile, v, a):
    w = np.array(w)
    if np.all(np.abs(np.diff(w, axis=0)) < 1e-3):
        return
    check_shortest_within(w, profile, v, a)


def check_shortest_within(w, profile, v, a):
    pp = rapp.time_path(w, profile=profile, vmax=v, amax=a)
    vp, ap = peak_rates(pp)
    assert np.all(vp <= v * (1 + 1e-9)) and np.all(ap <= a * (1 + 1e-9))
    # Shortest: some joint reaches one of its limits (the oracle: minimum_duration).
    assert pp.duration == pytest.approx(minimum_duration(w, profile, v, a), rel=1e-9)
    assert max(np.max(vp / v), np.max(ap / a)) == pytest.approx(1.0, rel=1e-6)
    assert np.allclose(pp.evaluate([pp.t0, pp.tf]), w[[0, -1]])


@pytest.mark.parametrize("w,kept", [
    # Found by hypothesis: a step of one float64 (or 1e-89 rad) beside a path of radians. Its
    # piece timed the whole motion (an acceleration 1.5x the limit, or a motion 5x too slow);
    # such a step is now a repeat (rapp.time_scaling.drop_repeats).
    ([[2.0, 1.625], [0.0, 0.0], [0.0, 2.220446049250313e-16]], [[2.0, 1.625], [0.0, 2.220446049250313e-16]]),
    ([[0.0, 2.0], [0.0, 2.220446049250313e-16], [0.0, 0.0]], [[0.0, 2.0], [0.0, 0.0]]),
    ([[0.0, 0.0], [1.0, 0.0], [1.0, 1e-89], [1.0, 1.0]], [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]),
    ([[0.0, 0.0], [1e-46, 0.0], [1.0, 0.5]], [[0.0, 0.0], [1.0, 0.5]])])
@pytest.mark.parametrize("profile", ["cubic", "quintic", "spline"])
def test_a_step_of_one_float64_is_a_repeat_under_limits(w, kept, profile):
    check_shortest_within(np.array(w), profile, 1.0, 1.0)
    # The motion is the one without that step, from and to the same ends.
    got = rapp.time_path(w, profile=profile, vmax=1.0, amax=1.0)
    want = rapp.time_path(kept, profile=profile, vmax=1.0, amax=1.0)
    assert got.breakpoints.tolist() == want.breakpoints.tolist()
    assert np.allclose(got.evaluate([got.t0, got.tf]), [w[0], w[-1]], rtol=0, atol=1e-12)


def test_time_path_under_limits_one_limit_a_duration_and_the_trapezoid():
    w = [[0.0, 0.0], [1.0, 0.5], [2.0, 0.0]]
    only_v = rapp.time_path(w, vmax=1.0)
    assert np.max(peak_rates(only_v)[0]) == pytest.approx(1.0)
    slow = rapp.time_path(w, 2 * only_v.duration, vmax=1.0)
    assert slow.duration == pytest.approx(2 * only_v.duration)
    with pytest.raises(ValueError, match="too short"):
        rapp.time_path(w, 0.5 * only_v.duration, vmax=1.0)
    trap = rapp.time_path(w, profile="trapezoidal", vmax=1.0, amax=2.0)
    assert trap.duration == pytest.approx(rapp.trapezoidal_path(w, 1.0, 2.0).duration)
    with pytest.raises(ValueError, match="needs both"):
        rapp.time_path(w, profile="trapezoidal", vmax=1.0)
    with pytest.raises(ValueError, match="give a duration"):
        rapp.time_path(w)


def test_planner_shortcut_and_timing_compose_to_plans_speed():
    s = rapp.load_scenario("rectangles")
    raw = rapp.rrt_connect(s.arm, s.start_array, s.goal_q, s.obstacles, seed=0).path
    short = rapp.shortcut(s.arm, raw, s.obstacles)
    assert rapp.path_collision_free(s.arm, short, s.obstacles)
    slow = rapp.time_path(raw, vmax=1.0, amax=2.0).duration
    fast = rapp.time_path(short, vmax=1.0, amax=2.0).duration
    assert 3 * fast < slow      # the README: 'several times longer' without the shortcut


# --------------------------------------------------------------------------- exports


@pytest.fixture(scope="module")
def small_plan():
    return rapp.plan(rapp.load_scenario(SMALL))


def test_csv_holds_t_and_each_joints_q_qd_qdd_with_a_header(small_plan, tmp_path):
    p = small_plan
    save_csv(p, tmp_path / "q.csv")
    with open(tmp_path / "q.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["t", "q_shoulder", "qd_shoulder", "qdd_shoulder",
                       "q_elbow", "qd_elbow", "qdd_elbow"] == csv_columns(p.scenario.arm.joint_names)
    table = np.array(rows[1:], dtype=float)
    assert np.array_equal(table[:, 0], p.t)
    assert np.array_equal(table[:, 1::3], p.q - [0.25, -0.5])   # encoder angles
    assert np.array_equal(table[:, 2::3], p.qd) and np.array_equal(table[:, 3::3], p.qdd)


def test_joint_trajectory_holds_the_documented_keys(small_plan, tmp_path):
    p = small_plan
    save_joint_trajectory(p, tmp_path / "jt.json")
    jt = json.loads((tmp_path / "jt.json").read_text())
    assert jt == json.loads(json.dumps(joint_trajectory(p)))
    assert set(jt) == {"joint_names", "points"} and jt["joint_names"] == ["shoulder", "elbow"]
    assert len(jt["points"]) == len(p.t)
    for point, t, q, qd, qdd in zip(jt["points"], p.t, p.q, p.qd, p.qdd):
        assert set(point) == {"positions", "velocities", "accelerations", "time_from_start"}
        assert np.allclose(point["positions"], q - [0.25, -0.5], rtol=0, atol=0)
        assert point["velocities"] == qd.tolist() and point["accelerations"] == qdd.tolist()
        stamp = point["time_from_start"]
        assert 0 <= stamp["nanosec"] < 10**9
        assert abs(stamp["sec"] + stamp["nanosec"] * 1e-9 - t) <= 1e-9


def test_the_command_line_writes_csv_and_joint_trajectory(tmp_path, capsys):
    scen = tmp_path / "s.json"
    scen.write_text(json.dumps(SMALL))
    assert main(["plan", str(scen), "-q", "--out", str(tmp_path / "a.csv")]) == 0
    assert (tmp_path / "a.csv").read_text().startswith("t,q_shoulder,qd_shoulder,")
    assert main(["plan", str(scen), "-q", "--out", str(tmp_path / "b.json"),
                 "--format", "joint-trajectory"]) == 0
    assert set(json.loads((tmp_path / "b.json").read_text())) == {"joint_names", "points"}
    assert main(["plan", str(scen), "-q", "--out", str(tmp_path / "c.json")]) == 0
    assert json.loads((tmp_path / "c.json").read_text())["format"] == "rapp-result"
    capsys.readouterr()


def test_a_fixed_time_step_samples_every_dt():
    d = dict(SMALL, trajectory={"duration": 2.0, "dt": 0.05})
    p = rapp.plan(rapp.load_scenario(d))
    even = p.t[np.isin(p.t, np.arange(0, 41) * 0.05)]
    assert np.allclose(np.diff(even), 0.05) and p.t[-1] == 2.0 and len(even) == 41
    limited = dict(SMALL, trajectory={"dt": 0.01, "max_velocity": 1.0, "max_acceleration": 2.0})
    p = rapp.plan(rapp.load_scenario(limited))
    steps = np.diff(p.t)
    assert np.all(steps <= 0.01 + 1e-12) and np.isclose(np.median(steps), 0.01)
    with pytest.raises(rapp.InvalidFormat, match="trajectory.dt"):
        rapp.load_scenario(dict(SMALL, trajectory={"samples": 10, "dt": 0.1}))
    with pytest.raises(rapp.InvalidValue, match="trajectory.dt"):
        rapp.load_scenario(dict(SMALL, trajectory={"dt": 0.0}))


# --------------------------------------------------------------------------- base pose, offsets


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.1, 2.0), min_size=1, max_size=4).flatmap(
    lambda L: st.tuples(st.just(L), st.lists(st.floats(-4, 4), min_size=len(L), max_size=len(L)))),
    st.floats(-5, 5), st.floats(-5, 5), st.floats(-4, 4))
def test_a_base_pose_moves_the_arm_as_forward_kinematics_say(arm_q, x, y, heading):
    lengths, q = arm_q
    arm = rapp.Arm(lengths, base=(x, y, heading))
    # The oracle: forward kinematics written out, the base's heading added to the first joint.
    phi = heading + np.cumsum(q)
    expected = np.vstack([[x, y], [x, y] + np.cumsum(np.c_[np.cos(phi), np.sin(phi)] * np.c_[lengths], axis=0)])
    assert np.allclose(arm.world_positions(q), expected, atol=1e-9)
    assert np.allclose(arm.from_world(arm.world_positions(q)), arm.joint_positions(q), atol=1e-9)
    assert np.allclose(rapp.Arm(lengths).joint_positions(q), arm.joint_positions(q))


def test_offsets_names_and_base_come_from_the_scenario_and_go_back_to_it():
    d = dict(SMALL, arm=dict(SMALL["arm"], base={"x": 1.0, "y": -2.0, "heading": 90}),
             units={"angle": "deg"})
    s = rapp.load_scenario(d)
    assert s.arm.joint_names == ("shoulder", "elbow")
    assert s.arm.base == pytest.approx((1.0, -2.0, np.pi / 2))
    assert s.arm.joint_offsets == pytest.approx(np.radians([0.25, -0.5]))
    assert rapp.load_scenario(s.to_dict()) == s
    assert np.allclose(s.arm.from_encoder(s.arm.to_encoder([0.3, 0.4])), [0.3, 0.4])
    for bad, field in (({"joint_names": ["a", "a"]}, "arm.joint_names[1]"),
                       ({"joint_names": ["a"]}, "arm.joint_names"),
                       ({"joint_offsets": [0.0]}, "arm.joint_offsets"),
                       ({"base": {"x": 1e9}}, "arm.base")):
        with pytest.raises(rapp.ScenarioError, match=re.escape(field)):
            rapp.load_scenario(dict(SMALL, arm=dict(SMALL["arm"], **bad)))
    with pytest.raises(ValueError, match="joint_names"):
        rapp.Arm([1.0, 1.0], joint_names=["a"])


def test_ci_runs_the_smoke_test_of_the_library_on_other_pythons():
    if not (ROOT / ".ci" / "run").is_file():
        pytest.skip("a copy of the library's tests (the smoke test itself), not the repository")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert "scripts/smoke_pythons.py" in ci
    script = (ROOT / "scripts" / "smoke_pythons.py").read_text(encoding="utf-8")
    tests = re.search(r"^TESTS = \((.*?)\)$", script, re.M | re.S).group(1)
    for name in re.findall(r'"(tests/[\w.]+)"', tests):
        text = (ROOT / name).read_text(encoding="utf-8")
        # The library's own tests: no notebook, Jupyter or browser machinery.
        assert not re.search(r"^\s*(import|from) (nbformat|nbval|jupyter|playwright|notebook_kernels)",
                             text, re.M), name
