"""rapp's trapezoidal timing against ruckig (phase-synchronized, jerk unbounded), in one run.

Random rest-to-rest moves of a 3-joint arm (seeded): start and goal uniform in [-pi, pi],
limits per joint uniform in [0.5, 3] rad/s and [1, 8] rad/s^2. Timed per move, alternately:

* ``ruckig``: an ``InputParameter`` filled from Python, ``Ruckig.calculate`` (its C++ takes
  a few microseconds; the Python set-up is counted, as rapp's is);
* ``trapezoidal_moves`` for one move at a time (its arguments checked on every call), and
  for all moves in one call (time divided by the number of moves);
* ``trapezoidal`` itself (a ``PiecewisePolynomial`` per move, built in Python floats for one
  move: the same arrays, bit for bit, as the numpy construction it replaced).

Every time is CPU time (``time.process_time``), the best of 3 rounds over all moves, the
functions in turn within each of 2 passes.

Durations: rapp's synchronized trapezoid keeps the arm on the straight joint-space segment
(the one the planner certified). Ruckig's phase synchronization does too when it can; where
its move stays on the segment (checked on 50 samples) the durations must be equal. Where it
cannot, ruckig falls back to time synchronization, which leaves the segment and may be
shorter; those moves are counted and their gain reported.

Run from the repository root with ruckig installed:
``PYTHONPATH=$PWD python benchmarks/bench_time_scaling.py``; writes
``rapp/recorded/time_scaling.json``. Without ruckig, only rapp's two paths are timed.
"""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import time
from pathlib import Path

import numpy as np

from rapp.time_scaling import trapezoidal, trapezoidal_moves

HERE = Path(__file__).resolve().parent
MOVES, N = 500, 3


def problem(seed=0):
    rng = np.random.default_rng(seed)
    p0 = rng.uniform(-np.pi, np.pi, (MOVES, N))
    pf = rng.uniform(-np.pi, np.pi, (MOVES, N))
    vmax = rng.uniform(0.5, 3.0, N)
    amax = rng.uniform(1.0, 8.0, N)
    return p0, pf, vmax, amax


def ruckig_move(ruckig, p0, pf, vmax, amax):
    inp = ruckig.InputParameter(N)
    inp.current_position = p0
    inp.target_position = pf
    inp.max_velocity = vmax
    inp.max_acceleration = amax
    inp.max_jerk = [math.inf] * N
    inp.synchronization = ruckig.Synchronization.Phase
    traj = ruckig.Trajectory(N)
    result = ruckig.Ruckig(N).calculate(inp, traj)
    if result not in (ruckig.Result.Working, ruckig.Result.Finished):
        raise RuntimeError(f"ruckig: {result}")
    return traj


def on_segment(traj, p0, pf, samples=50):
    """True when every sample of ruckig's move lies on the segment p0 -> pf (to 1e-9)."""
    d = pf - p0
    for t in np.linspace(0.0, traj.duration, samples):
        q = np.array(traj.at_time(t)[0])
        s = float((q - p0) @ d / (d @ d))
        if np.abs(q - (p0 + s * d)).max() > 1e-9 * (1 + np.abs(d).max()):
            return False
    return True


def per_move(fn, rows, rounds=3):
    """Best over ``rounds`` of the mean CPU time of ``fn(i)`` over every move ``i``."""
    best = np.inf
    for _ in range(rounds):
        t0 = time.process_time()
        for i in rows:
            fn(i)
        best = min(best, (time.process_time() - t0) / len(rows))
    return best


def main() -> None:
    p0, pf, vmax, amax = problem()
    load_before = os.getloadavg()
    rows = range(MOVES)
    vl, al = vmax.tolist(), amax.tolist()
    p0l, pfl = p0.tolist(), pf.tolist()
    try:
        import ruckig
    except ImportError:
        ruckig = None
        print("ruckig is not installed (pip install -r benchmarks/requirements.txt): timing rapp only")
    times = {}
    for _ in range(2):  # two alternating passes; the best of each is kept
        if ruckig is not None:
            t = per_move(lambda i: ruckig_move(ruckig, p0l[i], pfl[i], vl, al).duration, rows)
            times["ruckig_us"] = min(times.get("ruckig_us", np.inf), t * 1e6)
        t = per_move(lambda i: trapezoidal_moves(p0[i], pf[i], vmax, amax).duration, rows)
        times["rapp_moves_one_us"] = min(times.get("rapp_moves_one_us", np.inf), t * 1e6)
        t0 = time.process_time()
        for _ in range(20):
            batch = trapezoidal_moves(p0, pf, vmax, amax)
        t = (time.process_time() - t0) / MOVES / 20
        times["rapp_moves_batch_us"] = min(times.get("rapp_moves_batch_us", np.inf), t * 1e6)
        t = per_move(lambda i: trapezoidal(p0[i], pf[i], vmax, amax).duration, rows)
        times["rapp_trapezoidal_us"] = min(times.get("rapp_trapezoidal_us", np.inf), t * 1e6)
    # Durations: the fast path equals trapezoidal exactly, move by move.
    old = np.array([trapezoidal(p0[i], pf[i], vmax, amax).duration for i in rows])
    assert np.array_equal(batch.duration, old), "trapezoidal_moves changed a duration"
    result = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "load_before": load_before},
        "problem": {"moves": MOVES, "joints": N, "seed": 0},
        "timing": "time.process_time, best of 3 rounds over every move, 2 alternating passes",
        "per_move_us": times,
        "durations_equal_to_trapezoidal": True,
    }
    if ruckig is not None:
        r_dur = np.empty(MOVES)
        straight = np.zeros(MOVES, dtype=bool)
        for i in rows:
            traj = ruckig_move(ruckig, p0l[i], pfl[i], vl, al)
            r_dur[i] = traj.duration
            straight[i] = on_segment(traj, p0[i], pf[i])
        rel = np.abs(batch.duration - r_dur) / r_dur
        gain = 1.0 - r_dur[~straight] / batch.duration[~straight]
        result["ruckig"] = {
            "moves_on_segment": int(straight.sum()),
            "max_relative_duration_difference_on_segment": float(rel[straight].max())
            if straight.any() else None,
            "moves_leaving_segment": int((~straight).sum()),
            "their_duration_gain_max": float(gain.max()) if gain.size else None,
            "their_duration_gain_median": float(np.median(gain)) if gain.size else None,
        }
        result["ratios"] = {
            "rapp_moves_one_over_ruckig": times["rapp_moves_one_us"] / times["ruckig_us"],
            "rapp_moves_batch_over_ruckig": times["rapp_moves_batch_us"] / times["ruckig_us"],
            "rapp_trapezoidal_over_ruckig": times["rapp_trapezoidal_us"] / times["ruckig_us"],
        }
    result["machine"]["load_after"] = os.getloadavg()
    print(json.dumps(result, indent=2))
    (HERE.parent / "rapp" / "recorded" / "time_scaling.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
