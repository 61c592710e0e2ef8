"""A verified motion is the motion the arm makes (issue 31): q(t) certified between samples.

The oracle throughout is the slow, obvious one: evaluate the motion at 10,000 times per second
and measure every link's clearance there (``rapp.collision.link_clearances``).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rapp
from rapp import Arm, Circle, Polygon, load_scenario, plan
from rapp.collision import link_clearances, segment_collision_free
from rapp.errors import RappError
from rapp.motion import certify_motion
from rapp.planners import PLANNERS
from rapp.results import save_result
from rapp.timing import sample_times
from rapp.time_scaling import time_path
from rapp.trajectory import PiecewisePolynomial

PER_SECOND = 10_000


def dense_clearance(arm, motion, obstacles, per_second=PER_SECOND):
    """The oracle: the smallest link clearance at ``per_second`` even times of the motion."""
    t = np.linspace(motion.t0, motion.tf, max(2, int(per_second * motion.duration) + 1))
    return float(link_clearances(arm, motion.evaluate(t), obstacles).min())


#: Issue 31's case: 6 links, 8 obstacles, prm seed 377, spline, 50 samples. Found by building
#: random cluttered scenes and adding a 2 mm disc just beside the spline where it bulges past
#: the chords between its samples; the chords stay clear of it, the spline does not.
ISSUE_SCENE = {
    "arm": {"link_lengths": [0.222138528, 0.342189358, 0.521532867, 0.208075995, 0.270923977,
                             0.401446995]},
    "obstacles": [
        {"type": "circle", "center": [0.828143749, -1.63373945], "radius": 0.308369288},
        {"type": "circle", "center": [1.10638638, -1.95001722], "radius": 0.340891853},
        {"type": "rectangle", "corner": [1.89594448, 1.06077656], "width": 0.246750358,
         "height": 0.237927067, "angle": 6.69119961},
        {"type": "rectangle", "corner": [0.188146915, 0.592139743], "width": 0.273704837,
         "height": 0.362734011, "angle": 52.1013185},
        {"type": "circle", "center": [-0.521622517, -0.567857526], "radius": 0.171505366},
        {"type": "circle", "center": [1.30127259, -0.573613905], "radius": 0.222174245},
        {"type": "circle", "center": [0.700585064, 0.648425892], "radius": 0.339350184},
        {"type": "circle", "center": [0.0927909738, 0.295885304], "radius": 0.002}],
    "start": [-1.85762255, 1.67564385, 2.77337292, 0.610048083, 2.73830493, 0.364232536],
    "goal": {"joints": [-0.0772319636, -1.71555431, -1.12885086, -0.882635753, -1.58512105,
                        0.713450967]},
    # The issue's run: a first batch of 500 samples, PRM's default then (it is 10 now, and
    # seed 377 then finds a path whose spline stays clear).
    "planner": {"algorithm": "prm", "seed": 377, "samples": 500},
    "trajectory": {"duration": 5.0, "profile": "spline", "samples": 50},
}


@pytest.mark.slow
def test_the_issues_spline_that_enters_an_obstacle_between_samples_is_never_returned():
    s = load_scenario(ISSUE_SCENE)
    p = plan(s)
    arm, obs = s.arm, s.obstacles
    # The scene is the issue's: the spline's samples and every chord between them are
    # certified free, yet the spline itself enters the disc between two samples.
    spline = time_path(p.shortcut, 5.0, "spline")
    t = sample_times(5.0, 50, spline.breakpoints)
    q = spline.evaluate(t)
    assert segment_collision_free(arm, q[:-1], q[1:], obs).all()
    assert dense_clearance(arm, spline, obs) < 0
    assert not certify_motion(arm, spline, obs).free
    # rapp falls back to rest-to-rest along the certified polyline; the oracle agrees.
    assert p.report.ok and p.profile.startswith("rest-to-rest")
    d = dense_clearance(arm, p.motion, obs)
    assert d > 0
    c = p.report["min clearance"]
    assert "whole motion" in c.detail
    # The reported clearance is the motion's: no dense time comes closer than it less 0.1 %,
    # and a dense time comes within 0.1 % of it.
    assert c.value * (1 - 1e-3) <= d <= c.value * (1 + 1e-3)


def test_certify_motion_finds_the_bulge_the_chords_miss():
    """Fast sibling of the issue's case: one cubic piece bulging past its chord onto a disc."""
    arm = Arm([1.0, 1.0])
    # From (0, 0) to (1, 0), the elbow bending to -1.2 on the way: the tip leaves the sector
    # that the straight chord (elbow straight) sweeps, and meets a small disc there.
    motion = time_path([[0.0, 0.0], [0.5, -1.2], [1.0, 0.0]], 1.0, "spline")
    tip = arm.end_effector(motion.evaluate(0.5))
    disc = [Circle(tuple(tip), 0.01)]
    q = motion.evaluate(np.array([0.0, 1.0]))
    # The two samples' chord misses the disc; the motion does not.
    assert segment_collision_free(arm, q[:1], q[1:], disc).all()
    assert dense_clearance(arm, motion, disc) < 0
    assert not certify_motion(arm, motion, disc).free


polys = st.integers(1, 3).flatmap(lambda k: st.tuples(
    st.just(k), st.integers(1, 3), st.sampled_from([1, 3, 5]),
    st.lists(st.floats(-1.5, 1.5), min_size=6 * k * 3, max_size=6 * k * 3),
    st.lists(st.floats(0.2, 1.0), min_size=k, max_size=k)))


@settings(max_examples=40, deadline=None)
@given(polys, st.floats(-1.5, 1.5), st.floats(-1.5, 1.5), st.floats(0.05, 0.6),
       st.floats(0.0, 0.05))
def test_certified_means_the_dense_oracle_agrees(poly, cx, cy, radius, margin):
    k, n, deg, coeffs, lengths = poly
    local = np.array(coeffs[: k * (deg + 1) * n]).reshape(k, deg + 1, n)
    bp = np.concatenate(([0.0], np.cumsum(lengths)))
    motion = PiecewisePolynomial.from_local(bp, local)
    arm = Arm([0.6] * n)
    obs = [Circle((cx, cy), radius), Polygon.rectangle((-1.8, -1.8), 0.4, 0.3)]
    c = certify_motion(arm, motion, obs, margin=margin, rtol=1e-3)
    d = dense_clearance(arm, motion, obs, per_second=2000)
    if c.free:
        assert d > margin and c.lower > margin
        assert c.lower <= d + 1e-12 and d >= c.clearance * (1 - 1e-3) - 1e-12
    if d <= margin:
        assert not c.free


def test_certify_motion_holds_the_joint_limits_between_samples():
    arm = Arm([1.0, 1.0], joint_limits=[(-1.0, 1.0), None])
    inside = time_path([[0.0, 0.0], [0.9, 0.0]], 1.0, "cubic")
    assert certify_motion(arm, inside).within_limits and certify_motion(arm, inside).free
    # Every knot within the limit, but the spline overshoots it between its knots.
    knots = np.array([[0.0, 0.0], [0.9, 0.0], [0.99, 0.0], [0.99, 1.0]])
    assert (knots[:, 0] < 1.0).all()
    over = time_path(knots, 1.0, "spline")
    peak = over.evaluate(np.linspace(0, 1, 10001))[:, 0].max()
    assert peak > 1.0
    c = certify_motion(arm, over)
    assert not c.free and not c.within_limits


@settings(max_examples=200, deadline=None)
@given(st.floats(1e-3, 1e4), st.integers(2, 300), st.lists(st.floats(1e-6, 1.0), min_size=1,
                                                          max_size=30))
def test_sample_times_increase_and_end_exactly_at_the_duration(duration, samples, shares):
    s = np.cumsum(shares)
    # Breakpoints that rounding may put an ulp either side of the duration.
    bp = np.concatenate(([0.0], duration * s / s[-1]))
    for last in (duration, np.nextafter(duration, np.inf), np.nextafter(duration, 0)):
        bp[-1] = last
        t = sample_times(duration, samples, bp)
        assert t[0] == 0.0 and t[-1] == duration and np.all(np.diff(t) > 0)


def test_the_result_files_motion_reproduces_its_samples_with_numpy_alone(tmp_path):
    for name, traj in (("default", None),
                       ("srs_typical", {"profile": "trapezoidal", "max_velocity": 1.0,
                                        "max_acceleration": 2.0})):
        d = load_scenario(name).to_dict()
        if traj:
            d["trajectory"] = traj
        path = tmp_path / f"{name}.json"
        save_result(plan(d), path)
        r = json.loads(path.read_text())
        breaks = np.array(r["motion"]["breaks"])
        coef = np.array(r["motion"]["coefficients"])            # pieces x joints x (d + 1)
        t, q = np.array(r["t"]), np.array(r["q"])
        assert coef.shape[:2] == (len(breaks) - 1, q.shape[1])
        assert breaks[0] == t[0] == 0.0 and breaks[-1] == t[-1]
        i = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, len(coef) - 1)
        tau = t - breaks[i]
        powers = tau[:, None] ** np.arange(coef.shape[2])       # (samples, d + 1)
        mine = np.einsum("sjm,sm->sj", coef[i], powers)
        np.testing.assert_allclose(mine, q, rtol=0, atol=1e-9)


def random_scene(rng, n, m):
    lengths = rng.uniform(0.2, 0.6, n)
    reach = lengths.sum()
    obs = []
    for _ in range(m):
        c = rng.uniform(-reach, reach, 2)
        if rng.random() < 0.5:
            obs.append({"type": "circle", "center": c.tolist(), "radius": float(rng.uniform(0.05, 0.3))})
        else:
            obs.append({"type": "rectangle", "corner": c.tolist(),
                        "width": float(rng.uniform(0.1, 0.4)), "height": float(rng.uniform(0.1, 0.4)),
                        "angle": float(rng.uniform(0, 90))})
    return lengths, obs


def plans_of_random_scenes(seed, count, links=(2, 6), planners=tuple(PLANNERS),
                           profiles=("cubic", "quintic", "spline", "trapezoidal"), thick=False):
    """Plans of cluttered random scenes, every planner and profile in turn, limited or not;
    ``thick``: links of random radii, a safety margin and, for 3 links or more, links that
    must not cross."""
    rng = np.random.default_rng(seed)
    found = 0
    while found < count:
        n = int(rng.integers(links[0], links[1] + 1))
        lengths, obs = random_scene(rng, n, int(rng.integers(2, 9)))
        planner = planners[found % len(planners)]
        profile = profiles[(found // len(planners)) % len(profiles)]
        traj = {"profile": profile, "samples": int(rng.choice([2, 3, 7, 50]))}
        if profile == "trapezoidal" or rng.random() < 0.4:
            traj.update(max_velocity=float(rng.uniform(0.5, 2)), max_acceleration=float(rng.uniform(1, 4)))
        else:
            traj["duration"] = float(rng.uniform(1, 6))
        settings_ = {"algorithm": planner, "seed": int(rng.integers(1000))}
        if planner == "astar":
            settings_["cells"] = 24 if n <= 2 else (12 if n == 3 else 6)
        d = {"arm": {"link_lengths": lengths.tolist()}, "obstacles": obs,
             "start": rng.uniform(-np.pi, np.pi, n).tolist(),
             "goal": {"joints": rng.uniform(-np.pi, np.pi, n).tolist()},
             "planner": settings_, "trajectory": traj}
        if thick:
            d["arm"]["link_radius"] = rng.uniform(0.005, 0.03, n).round(4).tolist()
            d["safety_margin"] = round(float(rng.uniform(0.002, 0.02)), 4)
            d["arm"]["self_collision"] = bool(n >= 3)
        try:
            s = load_scenario(d)
            p = plan(s)
        except RappError:
            continue
        found += 1
        yield s, p


def check_against_the_oracle(s, p):
    assert p.report.ok, (p.report, s.to_dict())
    assert p.t[-1] == p.motion.tf and p.t[0] == p.motion.t0 == 0.0
    d = dense_clearance(s.arm, p.motion, s.obstacles)
    assert d > 0, s.to_dict()
    c = p.report["min clearance"].value
    assert c * (1 - 1e-3) <= d <= c * (1 + 1e-3) + 1e-12


def check_thick_against_the_oracle(s, p):
    """The motion of thick links at 10,000 times per second: each zero-width centre line keeps
    its link's radius plus the margin from every obstacle, and non-adjacent links their two
    radii plus the margin from each other."""
    assert p.report.ok, (p.report, s.to_dict())
    arm, m = s.arm, s.safety_margin
    t = np.linspace(p.motion.t0, p.motion.tf, max(2, int(PER_SECOND * p.motion.duration) + 1))
    q = p.motion.evaluate(t)
    centre = Arm(arm.lengths)
    need = np.asarray(arm.link_radius) + m
    assert (link_clearances(centre, q, s.obstacles) > need).all(), s.to_dict()
    if arm.self_collision:
        from rapp.collision import self_gaps
        i, j = rapp.collision.self_pairs(arm.n)
        r = np.asarray(arm.link_radius)
        assert (self_gaps(centre, q) > r[i] + r[j] + m).all(), s.to_dict()


def test_thick_links_move_clear_by_the_required_margin_at_every_dense_time_fast():
    for s, p in plans_of_random_scenes(7, 2, links=(2, 3), planners=("rrt_connect",), thick=True):
        check_thick_against_the_oracle(s, p)


@pytest.mark.slow
def test_thick_links_move_clear_by_the_required_margin_at_every_dense_time():
    """Every planner, every profile, 2-6 links with radii, a margin and self-collision."""
    for s, p in plans_of_random_scenes(4031, 2 * len(PLANNERS) * 2, thick=True):
        check_thick_against_the_oracle(s, p)


def test_random_cluttered_scenes_move_clear_at_every_dense_time_fast():
    for s, p in plans_of_random_scenes(31, 3, links=(2, 3), planners=("rrt_connect",)):
        check_against_the_oracle(s, p)


@pytest.mark.slow
def test_random_cluttered_scenes_move_clear_at_every_dense_time():
    """Every planner, every profile, 2-6 links, 2 to 50 samples, limits or not."""
    for s, p in plans_of_random_scenes(2031, 4 * len(PLANNERS) * 2):
        check_against_the_oracle(s, p)


@pytest.mark.slow
def test_a_cold_numba_cache_does_not_eat_the_time_budget():
    """Right after installing, a trivial rrt_connect solves within its 5 s budget: the
    kernels are compiled before the planner's clock starts."""
    scene = {"arm": {"link_lengths": [1.0, 0.8, 0.5]},
             "obstacles": [{"type": "circle", "center": [-1.5, -1.2], "radius": 0.2}],
             "start": [0.0, 0.0, 0.0], "goal": {"joints": [0.5, 0.3, 0.2]},
             "planner": {"algorithm": "rrt_connect", "seed": 0, "time_budget": 5.0}}
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "s.json")
        with open(path, "w") as fh:
            json.dump(scene, fh)
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        r = subprocess.run([sys.executable, "-m", "rapp", "plan", path, "--timings", "-q"],
                           capture_output=True, text=True, env=env, timeout=900)
        assert r.returncode == 0, r.stdout + r.stderr
        assert "compilation: " in r.stdout
        assert os.listdir(cache), "numba wrote nothing: the cache directory was not used"


def _scenario_file(tmp_path, name, planner):
    d = load_scenario("default").to_dict()
    d["planner"] = planner
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(d))
    return str(path)


REFUSED = {
    "rrt_connect_step": {"algorithm": "rrt_connect", "step": 1e-6},
    "rrt_step": {"algorithm": "rrt", "step": 1e-6, "max_iterations": 10},
    "prm_memory": {"algorithm": "prm", "samples": 100000, "neighbours": 500},
}


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_check_refuses_what_plan_refuses_with_the_same_line(tmp_path, capsys, name):
    from rapp.cli import main

    path = _scenario_file(tmp_path, name, REFUSED[name])
    answers = []
    for command in ("check", "plan"):
        code = main([command, path])
        err = capsys.readouterr().err.strip().splitlines()
        answers.append((code, err[-1] if err else ""))
    assert answers[0] == answers[1] and answers[0][0] == 2, answers
    assert answers[0][1].startswith("rapp: error: planner.")


def test_check_accepts_what_plan_accepts(tmp_path, capsys):
    from rapp.cli import main

    path = _scenario_file(tmp_path, "fine", {"algorithm": "rrt_connect", "step": 0.2})
    assert main(["check", path]) == 0
    assert capsys.readouterr().out.rstrip().endswith("scenario is valid")


def test_measuring_the_clearance_tightly_never_uncertifies_a_motion():
    """Refining for ``rtol`` stops at the interval cap, keeping what is already proved."""
    arm, obs = Arm([1.0, 1.0]), [Circle((-1.0, 1.0), 0.3)]
    motion = time_path([[0.0, 0.0], [1.0, 0.5], [1.5, 0.0]], 2.0, "spline")
    plain = certify_motion(arm, motion, obs)
    tight = certify_motion(arm, motion, obs, rtol=1e-12, max_intervals=64)
    assert plain.free and tight.free
    d = dense_clearance(arm, motion, obs)
    assert plain.lower <= tight.lower <= d <= tight.clearance
