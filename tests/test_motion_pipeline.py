"""From path to motion through scenario files, rapp.plan and the command line.

Joint speed and acceleration limits (``trajectory.max_velocity``, ``max_acceleration``): the plan
keeps every joint within them and, without a duration, takes the shortest duration within them
for its profile; a duration too short is refused naming ``trajectory.duration`` and the shortest
feasible one. Straight lines (``goal.path: "line"``): the end effector stays within 1 mm of the
segment, also between samples, and a line that cannot be followed is exit code 1 with one line.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rapp import InvalidValue, MissingParameter, PathNotFollowable, ScenarioError, load_scenario, plan
from tests.helpers import one_line, run, write
from rapp.collision import segment_point_distance
from rapp.planner import DURATION_MARGIN, LINE_TOLERANCE
from rapp.scenario import echo
from rapp.time_scaling import minimum_duration, peak_rates
from rapp.verify import POSITION_TOL, RATE_TOL, verify

ROOT = Path(__file__).resolve().parent.parent
PROFILES = ("cubic", "quintic", "spline", "trapezoidal")
#: A peak within this relative distance of its limit counts as reaching it.
REACHED = 1e-6

LINE = {"arm": {"link_lengths": [1.0, 1.0]}, "start": [0.3, 1.2],
        "goal": {"position": [1.2, -0.4], "path": "line"},
        "trajectory": {"profile": "trapezoidal", "max_velocity": 1.0, "max_acceleration": 2.0}}

#: One line per reason the end effector cannot follow a line.
NOT_FOLLOWABLE = {
    "workspace": ({"arm": {"link_lengths": [1.0, 0.5]}, "start": [0.0, 1.0],
                   "goal": {"position": [-1.0, 0.2], "path": "line"}},
                  "the line leaves the workspace at s="),
    "singularity": ({"arm": {"link_lengths": [1.0, 1.0]}, "start": [0.0, 2.0],
                     "goal": {"position": [2.0, 0.0], "path": "line"}},
                    "the line passes a singularity at s="),
    "joint limits": ({"arm": {"link_lengths": [1.0, 1.0], "joint_limits": [[-0.5, 2.0], None]},
                      "start": [0.3, 1.2], "goal": {"position": [1.2, -0.4], "path": "line"}},
                     "θ1 (joint_limits[0]) leaves its limits"),
    "obstacle": ({"arm": {"link_lengths": [1.0, 1.0]},
                  "obstacles": [{"type": "circle", "center": [1.15, 0.1], "radius": 0.05}],
                  "start": [0.3, 1.2], "goal": {"position": [1.2, -0.4], "path": "line"}},
                 "the arm hits obstacle 0"),
}


def with_trajectory(name_or_dict, **trajectory):
    d = load_scenario(name_or_dict).to_dict() if isinstance(name_or_dict, str) else dict(name_or_dict)
    d["trajectory"] = trajectory
    return d


def ratios(p):
    """Exact peak / limit per joint: (velocity ratios or None, acceleration ratios or None)."""
    tr = p.scenario.trajectory
    v, a = peak_rates(p.motion)
    rv = None if tr.max_velocity is None else v / np.asarray(tr.max_velocity)
    ra = None if tr.max_acceleration is None else a / np.asarray(tr.max_acceleration)
    return rv, ra


# --------------------------------------------------------------------------- limits


@pytest.mark.parametrize("name", ["default", "rectangles"])
@pytest.mark.parametrize("profile", PROFILES)
def test_shortest_duration_within_the_limits_for_each_profile(name, profile):
    p = plan(with_trajectory(name, profile=profile, max_velocity=[1.0, 1.5],
                             max_acceleration=2.0))
    assert p.report.ok, str(p.report)
    assert p.profile == profile
    rv, ra = ratios(p)
    # Within the limits, exactly (the plan runs T_min (1 + 1e-9))...
    assert rv.max() <= 1.0 and ra.max() <= 1.0
    # ... and reached: some joint is at a limit, so no shorter duration keeps them all.
    assert max(rv.max(), ra.max()) >= 1.0 - REACHED
    if profile == "trapezoidal":
        assert ra.max() >= 1.0 - REACHED   # every segment blends at the acceleration limit
    # The duration is minimum_duration's along the path that was timed.
    T_min = minimum_duration(p.shortcut, profile, [1.0, 1.5], 2.0)
    assert p.t[-1] == pytest.approx(T_min * (1.0 + DURATION_MARGIN), rel=1e-12)
    assert p.metrics["min_duration_s"] == pytest.approx(T_min, rel=1e-12)
    # The report states both peaks against their limits.
    for check, r in (("peak velocity", rv), ("peak acceleration", ra)):
        c = p.report[check]
        assert c.ok and c.value / c.limit == pytest.approx(r.max(), rel=1e-12)
    assert p.report["time"].ok


@pytest.mark.parametrize("profile", ["cubic", "quintic", "spline"])
@pytest.mark.parametrize("given", ["max_velocity", "max_acceleration"])
def test_one_limit_leaves_the_other_unbounded(profile, given):
    p = plan(with_trajectory("srs_typical", profile=profile, **{given: 0.7}))
    assert p.report.ok
    rv, ra = ratios(p)
    r = rv if given == "max_velocity" else ra
    assert r.max() <= 1.0 and r.max() >= 1.0 - REACHED
    assert (ra if given == "max_velocity" else rv) is None
    names = [c.name for c in p.report.checks]
    assert ("peak velocity" in names) == (given == "max_velocity")
    assert ("peak acceleration" in names) == (given == "max_acceleration")


def test_no_limits_no_rate_checks_and_the_motion_is_still_the_plans():
    s = load_scenario("srs_typical")
    p = plan(s)
    # Every plan carries the motion its samples come from (issue 31), limits or not.
    assert p.motion is not None and "min_duration_s" not in p.metrics
    np.testing.assert_allclose(p.motion.evaluate(p.t), p.q, atol=1e-9)
    assert not {"peak velocity", "peak acceleration", "on the line"} & {c.name for c in p.report.checks}


def test_a_feasible_duration_is_kept_and_the_motion_stretched():
    fast = plan(with_trajectory("default", profile="trapezoidal", max_velocity=1.0,
                                max_acceleration=2.0))
    slow = plan(with_trajectory("default", profile="trapezoidal", max_velocity=1.0,
                                max_acceleration=2.0, duration=2 * fast.t[-1]))
    assert slow.report.ok and slow.t[-1] == 2 * fast.t[-1]
    (v1, a1), (v2, a2) = peak_rates(fast.motion), peak_rates(slow.motion)
    np.testing.assert_allclose(v2, v1 / 2, rtol=1e-9)
    np.testing.assert_allclose(a2, a1 / 4, rtol=1e-9)


@pytest.mark.parametrize("profile", PROFILES)
def test_too_short_a_duration_names_the_field_and_the_shortest(profile, tmp_path, capsys):
    d = with_trajectory("srs_typical", profile=profile, max_velocity=1.0, max_acceleration=2.0,
                        duration=0.5)
    with pytest.raises(InvalidValue) as info:
        plan(d)
    assert info.value.field == "trajectory.duration"
    shortest = float(re.search(r"at least ([0-9.e+-]+) s", str(info.value)).group(1))
    T_min = plan(with_trajectory("srs_typical", profile=profile, max_velocity=1.0,
                                 max_acceleration=2.0)).metrics["min_duration_s"]
    assert T_min <= shortest <= T_min * (1 + 1e-5)   # rounded up to 6 digits
    # The duration the message states is accepted.
    d["trajectory"]["duration"] = shortest
    assert plan(d).report.ok
    # The command line: exit 2, one line naming the field.
    d["trajectory"]["duration"] = 0.5
    code, out, err = run(capsys, "plan", write(tmp_path, d))
    assert code == 2
    assert one_line(err).startswith("rapp: error: trajectory.duration: 0.5 s is too short")


def test_the_documented_too_short_message_is_the_one_printed():
    page = (ROOT / "book" / "scenario_format.md").read_text(encoding="utf-8")
    shown = re.search(r"^rapp: error: trajectory\.duration: .*$", page, re.M).group(0)
    block = re.search(r":caption: Valid - the shortest trapezoidal motion within joint limits\n\n"
                      r"(.*?)^```$", page, re.M | re.S).group(1)
    d = json.loads(block)
    d["trajectory"]["duration"] = 2.0
    with pytest.raises(InvalidValue) as info:
        plan(d)
    assert shown == f"rapp: error: {info.value}"
    assert "0.9 mm" in page and LINE_TOLERANCE == 0.9e-3 and DURATION_MARGIN == 1e-9


def test_limits_in_degrees_are_converted():
    rad = with_trajectory("srs_typical", profile="quintic", max_velocity=[0.5, 1.0],
                          max_acceleration=1.5)
    deg = dict(rad, units={"angle": "deg"},
               start=[math.degrees(a) for a in rad["start"]],
               trajectory={"profile": "quintic", "max_velocity": [math.degrees(0.5), math.degrees(1.0)],
                           "max_acceleration": math.degrees(1.5)})
    s_rad, s_deg = load_scenario(rad), load_scenario(deg)
    np.testing.assert_allclose(s_deg.trajectory.max_velocity, [0.5, 1.0], rtol=1e-15)
    np.testing.assert_allclose(s_deg.trajectory.max_acceleration, [1.5, 1.5], rtol=1e-15)
    assert "= [28.65, 57.3] deg/s" in echo(s_deg) and "deg/s^2" in echo(s_deg)
    p_rad, p_deg = plan(s_rad), plan(s_deg)
    assert p_deg.report.ok and p_deg.t[-1] == pytest.approx(p_rad.t[-1], rel=1e-12)
    # 28.6 deg/s would be 28.6 rad/s if it were not converted: far faster.
    assert p_deg.report["peak velocity"].limit == pytest.approx(1.0)


def test_a_curve_that_leaves_the_free_path_falls_back_to_rest_to_rest_within_limits(monkeypatch):
    import rapp.planner
    import rapp.timing

    from rapp.motion import MotionCertificate

    calls = []

    def refuse_the_curve(arm, motion, obstacles, **kw):
        calls.append(1)
        pieces = np.zeros(len(motion.breakpoints) - 1, dtype=bool)
        return MotionCertificate(False, pieces, 0.0, 0.0, True, 1)

    monkeypatch.setattr(rapp.timing, "certify_motion", refuse_the_curve)
    monkeypatch.setattr(rapp.planner, "shortcut", lambda arm, w, obs: w)
    p = plan(with_trajectory("srs_typical", profile="spline", max_velocity=1.0,
                             max_acceleration=2.0))
    assert calls and p.profile.startswith("rest-to-rest quintic per segment")
    assert p.report.ok
    rv, ra = ratios(p)
    assert max(rv.max(), ra.max()) <= 1.0 and max(rv.max(), ra.max()) >= 1.0 - REACHED


def test_the_rate_checks_fail_beyond_the_limits():
    p = plan(with_trajectory("srs_typical", profile="quintic", max_velocity=1.0,
                             max_acceleration=2.0))
    tighter = load_scenario(with_trajectory("srs_typical", profile="quintic",
                                            max_velocity=0.9, max_acceleration=1.0,
                                            duration=float(p.t[-1])))
    r = verify(p, tighter)
    assert not r.ok and not r["peak velocity"].ok and not r["peak acceleration"].ok
    # At the limit, to rounding, it passes.
    v, a = peak_rates(p.motion)
    at = load_scenario(with_trajectory("srs_typical", profile="quintic",
                                       max_velocity=list(np.maximum(v, 1e-3) * (1 - RATE_TOL / 2)),
                                       max_acceleration=list(np.maximum(a, 1e-3) * (1 - RATE_TOL / 2)),
                                       duration=float(p.t[-1])))
    assert verify(p, at).ok
    # A plan without its motion (a result file) is judged on its samples.
    from dataclasses import replace
    assert verify(replace(p, motion=None), at)["peak velocity"].detail.endswith("at the samples")


# --------------------------------------------------------------------------- straight lines


def dense_distance(p, per_sample=20):
    """Largest distance from the segment of the tip along the timed motion, between samples too."""
    s = p.scenario
    a, b = s.arm.end_effector(s.start_array), np.asarray(s.goal_xy)
    t = np.unique(np.concatenate([np.linspace(t0, t1, per_sample, endpoint=False)
                                  for t0, t1 in zip(p.t[:-1], p.t[1:])] + [p.t[-1:]]))
    q = p.motion.evaluate(t)
    return float(segment_point_distance(a, b, s.arm.end_effector(q)).max()), \
        float(segment_point_distance(a, b, p.xy).max())


@pytest.mark.parametrize("trajectory", [
    {"profile": "trapezoidal", "max_velocity": 1.0, "max_acceleration": 2.0},
    {"profile": "quintic", "max_velocity": [1.0, 0.5], "max_acceleration": 3.0},
    {"profile": "cubic", "max_acceleration": 3.0},
    {"profile": "quintic", "duration": 4.0},
], ids=["trapezoidal", "quintic-limits", "cubic-acceleration", "quintic-duration"])
def test_a_line_goal_is_followed_within_1_mm(trajectory):
    p = plan(dict(LINE, trajectory=trajectory))
    assert p.report.ok, str(p.report)
    dense, sampled = dense_distance(p)
    assert sampled <= POSITION_TOL and dense <= POSITION_TOL
    assert p.report["on the line"].ok and p.report["on the line"].value >= dense - 1e-12
    assert np.linalg.norm(p.xy[-1] - LINE["goal"]["position"]) <= 1e-9
    assert p.metrics["line_waypoints"] == len(p.waypoints) >= 3
    assert "rest-to-rest" in p.profile
    if "duration" in trajectory:
        assert p.t[-1] == trajectory["duration"]
    else:   # the shortest rest-to-rest timing: a limit is reached
        rv, ra = ratios(p)
        peak = max(r.max() for r in (rv, ra) if r is not None)
        assert 1.0 - REACHED <= peak <= 1.0
    # At rest at every waypoint: the motion never leaves the joint-space edges.
    w_times = [t for t in p.motion.breakpoints
               if np.min(np.abs(p.waypoints - p.motion.evaluate(t)).max(axis=1)) < 1e-12]
    assert len(w_times) >= len(p.waypoints)
    np.testing.assert_allclose(p.motion.evaluate(np.array(w_times), 1), 0.0, atol=1e-12)


def test_the_line_check_fails_off_the_line():
    p = plan(LINE)
    q = p.q.copy()
    q[len(q) // 2:, 0] += 0.01
    from dataclasses import replace
    bad = replace(p, q=q, xy=p.scenario.arm.end_effector(q))
    assert not verify(bad, p.scenario)["on the line"].ok


@pytest.mark.parametrize("reason", list(NOT_FOLLOWABLE))
def test_a_line_that_cannot_be_followed_is_exit_1_with_one_line(reason, tmp_path, capsys):
    data, start = NOT_FOLLOWABLE[reason]
    with pytest.raises(PathNotFollowable) as info:
        plan(data)
    assert info.value.reason == reason and "\n" not in str(info.value)
    code, out, err = run(capsys, "plan", write(tmp_path, data))
    assert code == 1
    assert one_line(err) == f"rapp: no straight line: {info.value}"
    assert str(info.value).startswith(start)


def test_line_scenario_round_trips_and_echoes():
    s = load_scenario(dict(LINE, planner={"cells": 50}))
    assert s.goal_path == "line" and load_scenario(s.to_dict()) == s
    assert s.to_dict()["goal"] == {"position": [1.2, -0.4], "path": "line"}
    assert s.trajectory.duration is None and "duration" not in s.to_dict()["trajectory"]
    text = echo(s)
    assert "along a straight line from the start" in text
    assert "the shortest duration within the limits" in text
    assert any(w.startswith("planner is not used") for w in s.warnings)


# --------------------------------------------------------------------------- the command line


def test_cli_plans_with_limits(tmp_path, capsys):
    d = with_trajectory("srs_typical", profile="trapezoidal", max_velocity=1.0,
                        max_acceleration=2.0)
    out_file = tmp_path / "r.json"
    code, out, err = run(capsys, "plan", write(tmp_path, d), "--out", str(out_file))
    assert code == 0, err
    assert "peak velocity" in out and "peak acceleration" in out
    assert "trapezoidal, the shortest duration within the limits" in out
    assert out.rstrip().endswith("verified")
    saved = json.loads(out_file.read_text())
    assert saved["scenario"]["trajectory"]["max_velocity"] == [1.0, 1.0]
    assert saved["report"]["ok"]


def test_cli_line_goal_through_the_real_entry_point(tmp_path):
    path = write(tmp_path, LINE)
    proc = subprocess.run([sys.executable, "-m", "rapp", "plan", path, "--quiet"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.rstrip().endswith("verified") and proc.stderr == ""


# --------------------------------------------------------------------------- bad values

BASE = {"arm": {"link_lengths": [1.0, 1.0]}, "start": [0.0, 0.0], "goal": {"joints": [1.0, 0.0]}}


@pytest.mark.parametrize("trajectory, field", [
    ({"max_velocity": -1.0}, "trajectory.max_velocity"),
    ({"max_velocity": 0}, "trajectory.max_velocity"),
    ({"max_velocity": float("nan")}, "trajectory.max_velocity"),
    ({"max_acceleration": float("inf")}, "trajectory.max_acceleration"),
    ({"max_velocity": 1e7}, "trajectory.max_velocity"),
    ({"max_velocity": 1e-9}, "trajectory.max_velocity"),
    ({"max_velocity": "1"}, "trajectory.max_velocity"),
    ({"max_velocity": True}, "trajectory.max_velocity"),
    ({"max_velocity": {"a": 1}}, "trajectory.max_velocity"),
    ({"max_velocity": [1.0]}, "trajectory.max_velocity"),
    ({"max_velocity": []}, "trajectory.max_velocity"),
    ({"max_acceleration": [1.0, 2.0, 3.0]}, "trajectory.max_acceleration"),
    ({"max_acceleration": [1.0, -2.0]}, "trajectory.max_acceleration[1]"),
    ({"max_acceleration": [1.0, [2.0]]}, "trajectory.max_acceleration[1]"),
    ({"max_velocity": 1.0, "duration": 0.0}, "trajectory.duration"),
    ({"max_velocity": 1.0, "duration": None}, "trajectory.duration"),
    ({"profile": "trapezoidal"}, "trajectory.max_velocity"),
    ({"profile": "trapezoidal", "max_velocity": 1.0}, "trajectory.max_acceleration"),
    ({"profile": "trapezoidal", "max_acceleration": 1.0}, "trajectory.max_velocity"),
    ({"profile": "trapezoidal", "duration": 3.0}, "trajectory.max_velocity"),
    ({"profile": "lspb"}, "trajectory.profile"),
    ({"max_jerk": 1.0}, "trajectory.max_jerk"),
])
def test_bad_limits_name_the_field(trajectory, field, tmp_path, capsys):
    d = dict(BASE, trajectory=trajectory)
    with pytest.raises(ScenarioError) as info:
        load_scenario(d)
    assert info.value.field == field, str(info.value)
    if trajectory.get("profile") == "trapezoidal":
        assert isinstance(info.value, MissingParameter)
    code, out, err = run(capsys, "check", write(tmp_path, d))   # NaN, Infinity: JSON tokens
    assert code == 2 and one_line(err).startswith(f"rapp: error: {field}: ")


def test_a_bad_limit_in_degrees_quotes_the_files_unit():
    with pytest.raises(InvalidValue) as info:
        load_scenario(dict(BASE, units={"angle": "deg"}, start=[0, 0], goal={"joints": [45, 0]},
                           trajectory={"max_velocity": -5}))
    assert "deg/s" in str(info.value)


@pytest.mark.parametrize("goal, trajectory, field", [
    ({"joints": [1.0, 0.0], "path": "line"}, {}, "goal.path"),
    ({"position": [1.0, 1.0], "path": "arc"}, {}, "goal.path"),
    ({"position": [1.0, 1.0], "path": 1}, {}, "goal.path"),
    ({"position": [1.0, 1.0], "path": None}, {}, "goal.path"),
    ({"path": "line"}, {}, "goal"),
    ({"position": [1.0, 1.0], "path": "line"}, {"profile": "spline"}, "trajectory.profile"),
])
def test_bad_line_goals_name_the_field(goal, trajectory, field, tmp_path, capsys):
    d = dict(BASE, goal=goal, trajectory=trajectory)
    with pytest.raises(ScenarioError) as info:
        load_scenario(d)
    assert info.value.field == field, str(info.value)
    code, out, err = run(capsys, "check", write(tmp_path, d))
    assert code == 2 and one_line(err).startswith(f"rapp: error: {field}: ")


@pytest.mark.parametrize("profile", ["quintic", "trapezoidal"])
def test_a_shortest_duration_beyond_the_longest_names_the_limit(profile):
    # Within the limit ranges only a speed limit can push the duration past 1e6 s.
    d = with_trajectory("srs_typical", profile=profile, max_velocity=1e-6, max_acceleration=1e-6)
    with pytest.raises(InvalidValue) as info:
        plan(d)
    assert info.value.field == "trajectory.max_velocity" and "1e+06 s" in str(info.value)
