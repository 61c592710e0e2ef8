"""``rapp.collides`` on one configuration against a minimal compiled test called from Python.

The problem is ``bench_core.py``'s 3-link arm (links 1.0, 0.8, 0.5) among four discs and a
rectangle. The peer, :func:`minimal`, is the smallest numba function that answers the same
question: forward kinematics, the clipped-projection disc test and the separating-axis test
of one convex polygon, twenty lines, its arrays packed by hand beforehand and passed as four
arguments. It checks nothing and knows nothing of link radii, margins, obstacles for some
links only or self-collision; it is the floor of a call from Python into compiled code.

Both are called from Python in one process, in turn within each of 7 rounds of 20,000 calls
(CPU time, ``time.process_time``; the best round of each). Also recorded: the compiled
kernel's own call with the arrays already packed (what the sampling planners pay, from their
compiled loops they pay less), and ``rapp.collides`` with the obstacles as a list (the
identity of each obstacle is then looked up on every call, since a list can change). The two
agree on 10,000 random configurations (checked before timing).

Run from the repository root: ``PYTHONPATH=$PWD python benchmarks/bench_collides.py``; writes
``rapp/recorded/collides.json``.
"""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import numba

import rapp
from rapp import Polygon

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import LINKS3, OBSTACLES3  # noqa: E402  the problem, defined once

HERE = Path(__file__).resolve().parent
ROUNDS, CALLS = 7, 20_000


@numba.njit(cache=True)
def minimal(lengths, q, discs, poly):
    """True when a link of the arm at ``q`` touches a disc ``(x, y, r)`` or the convex polygon."""
    x = y = phi = 0.0
    for j in range(q.shape[0]):
        phi += q[j]
        ax, ay, x, y = x, y, x + math.cos(phi) * lengths[j], y + math.sin(phi) * lengths[j]
        dx, dy = x - ax, y - ay
        for c in range(discs.shape[0]):
            t = min(max(((discs[c, 0] - ax) * dx + (discs[c, 1] - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
            if (ax + t * dx - discs[c, 0]) ** 2 + (ay + t * dy - discs[c, 1]) ** 2 <= discs[c, 2] ** 2:
                return True
        separated = False  # separating axes: the polygon's edge normals, then the link's normal
        for k in range(poly.shape[0] + 1):
            m = poly.shape[0]
            nx, ny = (poly[k, 1] - poly[(k + 1) % m, 1], poly[(k + 1) % m, 0] - poly[k, 0]) if k < m else (-dy, dx)
            lo, hi = math.inf, -math.inf
            for v in range(m):
                lo, hi = min(lo, poly[v, 0] * nx + poly[v, 1] * ny), max(hi, poly[v, 0] * nx + poly[v, 1] * ny)
            sa, sb = ax * nx + ay * ny, x * nx + y * ny
            separated = separated or max(sa, sb) < lo or min(sa, sb) > hi
        if not separated:
            return True
    return False


def cpu_per_call(fns, calls=CALLS, rounds=ROUNDS):
    """CPU seconds per call of each function: the best of ``rounds``, the functions in turn."""
    best = [math.inf] * len(fns)
    for _ in range(rounds):
        for j, fn in enumerate(fns):
            t0 = time.process_time()
            for _ in range(calls):
                fn()
            best[j] = min(best[j], (time.process_time() - t0) / calls)
    return best


def main() -> None:
    arm = rapp.Arm(LINKS3)
    obstacles = tuple(OBSTACLES3)
    obstacle_list = list(OBSTACLES3)
    lengths = np.array(LINKS3)
    discs = np.array([(*ob.center, ob.radius) for ob in obstacles if not isinstance(ob, Polygon)])
    poly = np.array([ob for ob in obstacles if isinstance(ob, Polygon)][0].vertices, dtype=float)
    qs = np.random.default_rng(0).uniform(-np.pi, np.pi, (10_000, 3))
    theirs = np.array([minimal(lengths, q, discs, poly) for q in qs])
    ours = np.array([rapp.collides(arm, q, obstacles) for q in qs])
    assert (theirs == ours).all() and (ours == rapp.collides(arm, qs, obstacles)).all()
    kernels = rapp.kernels.collision.kernels()  # noqa: SLF001  the floor rapp's own call could reach
    packed = rapp.kernels.collision.pack(obstacles)
    q = np.array([0.3, -0.4, 0.9])
    load_before = os.getloadavg()
    t = cpu_per_call([lambda: rapp.collides(arm, q, obstacles),
                      lambda: minimal(lengths, q, discs, poly),
                      lambda: rapp.collides(arm, q, obstacle_list),
                      lambda: kernels.collides_one(lengths, q, *packed, 1e100)])
    us = [v * 1e6 for v in t]
    result = {
        "date": datetime.datetime.now().isoformat(timespec="minutes"),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "numba": numba.__version__,
                    "load_before": load_before, "load_after": os.getloadavg()},
        "timing": f"time.process_time, best of {ROUNDS} rounds of {CALLS} calls, in turn",
        "problem": {"links": LINKS3, "obstacles": len(obstacles), "q": q.tolist(),
                    "agree_on_random_configurations": len(qs)},
        "cpu_us": {"rapp_collides": us[0], "minimal_numba": us[1], "rapp_collides_list": us[2],
                   "kernel_packed": us[3]},
        "ratio_rapp_over_minimal": us[0] / us[1],
        "ratio_rapp_list_over_minimal": us[2] / us[1],
    }
    print(json.dumps(result, indent=2))
    (HERE.parent / "rapp" / "recorded" / "collides.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
