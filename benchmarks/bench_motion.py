"""The cost of certifying the motion itself: ``rapp.plan`` CPU time before and after, side by side.

*After* is ``rapp.plan`` as it is: the timing certifies the smooth motion over its whole time
span (:func:`rapp.motion.certify_motion`) before keeping it, and the verification certifies
it again and measures its smallest clearance to 0.1 %. *Before* is the same pipeline with
both certificates replaced by what they were until issue 31: the straight joint-space chords
between consecutive samples certified (:func:`rapp.collision.segment_collision_free`) and the
clearance taken at the samples, which misses a motion that bulges between samples.

Each case is planned alternately before and after, ``ROUNDS`` times, and the smallest CPU time
(``time.process_time``) of each kept. Both give the same plan wherever the chords' answer and
the motion's agree (checked: same profile).

Run from the repository root: ``PYTHONPATH=$PWD python benchmarks/bench_motion.py``; writes
``rapp/recorded/motion.json``, which the performance chapter reads.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import time
from pathlib import Path
from unittest import mock

import numpy as np

import importlib

import rapp
from rapp.collision import clearance, segment_collision_free
from rapp.motion import MotionCertificate
from rapp.timing import sample_times

ROOT = Path(__file__).resolve().parent.parent
# The modules (rapp.verify is also the function's name on the package).
TIMING, VERIFY = importlib.import_module("rapp.timing"), importlib.import_module("rapp.verify")
ROUNDS = 5

#: name -> (scenario, trajectory settings or None to keep the scenario's)
CASES = {
    "default (as given: quintic)": ("default", None),
    "srs_typical (as given: quintic)": ("srs_typical", None),
    "rectangles (spline, 100 samples)": ("rectangles", {"profile": "spline", "duration": 5.0,
                                                         "samples": 100}),
    "three_link (as given: quintic)": ("three_link", None),
    "three_link (trapezoidal, limits)": ("three_link", {"profile": "trapezoidal",
                                                        "max_velocity": 1.0,
                                                        "max_acceleration": 2.0}),
    "default (spline, 2 samples)": ("default", {"profile": "spline", "duration": 5.0,
                                                 "samples": 2}),
}


def chord_certificate(samples):
    """What the timing and the verification certified before: the chords between samples."""
    def certify(arm, motion, obstacles=(), **_):
        t = sample_times(motion.tf, samples, motion.breakpoints)
        q = motion.evaluate(t)
        obstacles = list(obstacles)
        free = bool(segment_collision_free(arm, q[:-1], q[1:], obstacles).all())
        within = bool(arm.within_limits(q, 1e-9).all())
        c = float(clearance(arm, q, obstacles).min()) if obstacles else np.inf
        pieces = np.full(len(motion.breakpoints) - 1, free)
        return MotionCertificate(free and within, pieces, c, c, within, len(t))
    return certify


def scenario_of(name, trajectory):
    d = rapp.load_scenario(name).to_dict()
    if trajectory is not None:
        d["trajectory"] = trajectory
    return rapp.load_scenario(d)


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def main():
    load_before = os.getloadavg()
    rapp.plan("default")                       # imports and kernels loaded once, outside
    results = {}
    for case, (name, trajectory) in CASES.items():
        s = scenario_of(name, trajectory)
        chords = chord_certificate(s.trajectory.samples)
        best = {"before": np.inf, "after": np.inf}
        profiles = {}
        for _ in range(ROUNDS):
            with mock.patch.object(TIMING, "certify_motion", chords), \
                    mock.patch.object(VERIFY, "certify_motion", chords):
                dt, p = cpu(lambda: rapp.plan(s))
            best["before"] = min(best["before"], dt)
            profiles["before"] = p.profile
            dt, p = cpu(lambda: rapp.plan(s))
            best["after"] = min(best["after"], dt)
            profiles["after"] = p.profile
            assert p.report.ok
        results[case] = {"before_ms": best["before"] * 1e3, "after_ms": best["after"] * 1e3,
                         "ratio": best["after"] / best["before"],
                         "same_profile": profiles["before"] == profiles["after"],
                         "profile_after": profiles["after"]}
        print(f"{case:40s} before {best['before'] * 1e3:8.1f} ms  after "
              f"{best['after'] * 1e3:8.1f} ms  ratio {best['after'] / best['before']:.2f}")
    ratios = [r["ratio"] for r in results.values()]
    out = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "load_before": list(load_before),
                    "load_after": list(os.getloadavg())},
        "what": "rapp.plan CPU time (best of %d), before: chords between samples certified; "
                "after: the motion certified over its whole time span" % ROUNDS,
        "results": results,
        "median_ratio": float(np.median(ratios)),
        "max_ratio": float(np.max(ratios)),
    }
    path = ROOT / "rapp" / "recorded" / "motion.json"
    path.write_text(json.dumps(out, indent=2) + "\n", encoding="utf-8")
    print(f"median ratio {out['median_ratio']:.2f}, max {out['max_ratio']:.2f}; wrote {path}")


if __name__ == "__main__":
    main()
