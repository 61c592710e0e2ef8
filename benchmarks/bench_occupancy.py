"""The 3-link 128^3 occupancy against its floor, side by side in one run.

The problem is ``bench_core.py``'s 3-link one: links 1.0, 0.8, 0.5 and five obstacles (four
discs and a rectangle), on a grid of 128 cells per joint (2,097,152 cells).

What is timed (``time.perf_counter`` seconds per call, the best of 10 rounds of 7 calls in a row
of each function, the functions in turn within every round so that the machine's load hits
them alike):

* ``rapp``: ``rapp.occupancy(arm, obstacles, grid)``, the whole public call (argument checks,
  the compiled kernel of ``rapp.kernels.occupancy_numba``: every interval computed and painted, the
  result allocated). What depends only on the grid and the scene (the prefix geometry of the
  levels, the packed obstacles, their tolerances and reaches) is cached after the first
  call, as it is for a planner recomputing a grid; ``rapp, new scene`` times the call given
  fresh copies of the obstacles each time, so that it builds all of that again.
* ``floor``: the same kernel's painting alone (``cspace_kernel.paint``), given the intervals:
  for every link, every prefix cell and every obstacle, the interval of the link's joint
  angle in which it touches the obstacle (``start``, ``width``; ``width = -1`` where it
  does not), computed beforehand and outside the timing. It allocates the levels' arrays
  (the last one of ``128**3`` bytes), fills the rows where an earlier link already
  collides and clears the others, and cuts each interval of those into cell ranges and
  sets them. That is everything ``rapp`` does except computing the intervals (the
  closed-form geometry and its ``atan2``) and its Python set-up: the least any
  implementation painting one interval per obstacle per prefix cell does. A second,
  stricter floor is given only the intervals that are painted (non-empty, in rows not
  already full). Both outputs are checked equal to ``rapp``'s.
* ``memory``: writing ``128**3`` bytes (``numpy.ones``), for scale only.
* ``numpy``: ``rapp.cspace.occupancy_numpy``, the numpy version (the fallback without numba),
  which ``rapp.occupancy`` was before the kernel.

The goal (issue 27): ``rapp / floor <= 2``. The results are checked cell by cell: the compiled
occupancy against the numpy one and against ``rapp.collides`` on every configuration; cells
that differ are reported with the largest ``|clearance|`` among them (rounding at a touching
configuration). The 2-link grids of ``bench_core.py`` (M = 100, 360) are timed the same way,
compiled against numpy, to show they did not slow down. The first call in a fresh process
(numba imported, the kernel loaded from its on-disk cache, ``cache=True``) and, with an empty
cache directory, the compilation are timed in child processes.

Run from the repository root: ``PYTHONPATH=$PWD python benchmarks/bench_occupancy.py``.
Prints a table and writes ``rapp/recorded/occupancy.json``.
"""

from __future__ import annotations

import copy
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import rapp
from rapp import cspace
from rapp.kernels import occupancy_numba as cspace_kernel
from rapp.collision import check_obstacle

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import CIRCLES, LINKS, LINKS3, OBSTACLES3  # noqa: E402  the problems, defined once

HERE = Path(__file__).resolve().parent
M3 = 128
K = 7
ROUNDS = 10


def side_by_side(fns, k=K, rounds=ROUNDS):
    """Best seconds per call of each function: ``rounds`` rounds, in each of which every
    function in turn is called ``k`` times in a row (so that the machine's load hits them
    alike, and each is timed in its steady state, not in the wake of another's memory)."""
    best, outs = [np.inf] * len(fns), [None] * len(fns)
    for _ in range(rounds):
        for j, fn in enumerate(fns):
            for _ in range(k):
                t0 = time.perf_counter()
                outs[j] = fn()
                best[j] = min(best[j], time.perf_counter() - t0)
    return best, outs


def mismatches(arm, obstacles, grid, occ, other):
    """Cells where ``occ`` differs from ``other`` and from ``rapp.collides``, and the largest
    ``|clearance|`` over all of them (one slice of axis 0 at a time, for memory)."""
    axes = grid.axes
    rest = np.stack(np.meshgrid(*axes[1:], indexing="ij"), axis=-1)
    vs_other, vs_collides, worst = int((occ != other).sum()), 0, 0.0
    for i0, a0 in enumerate(axes[0]):
        q = np.concatenate([np.full(rest.shape[:-1] + (1,), a0), rest], axis=-1)
        d = occ[i0] != rapp.collides(arm, q, obstacles)
        vs_collides += int(d.sum())
        bad = d | (occ[i0] != other[i0])
        if bad.any():
            worst = max(worst, float(np.abs(rapp.clearance(arm, q[bad], obstacles)).max()))
    return {"mismatched_cells_vs_numpy": vs_other, "mismatched_cells_vs_collides": vs_collides,
            "mismatched_max_abs_clearance": worst}


def three_link():
    arm = rapp.Arm(LINKS3)
    grid = rapp.JointGrid(arm, M3)
    k = cspace_kernel.kernels()
    if k is None:
        raise SystemExit("numba is not installed: there is no compiled occupancy to time")
    obstacles = [check_obstacle(ob) for ob in OBSTACLES3]
    lv = cspace_kernel.levels(grid, [obstacles] * arm.n)
    _, kept = cspace_kernel.run(k, lv, keep=True)
    given = cspace_kernel.one_per_cell(lv, kept)
    cells = M3 ** 3
    # Fresh (equal) obstacles for every call of "new scene": its caches miss every time.
    fresh = iter([[copy.copy(ob) for ob in OBSTACLES3] for _ in range(K * ROUNDS)])
    (t_rapp, t_new, t_floor, t_list, t_mem, t_numpy), \
        (occ, occ_new, painted, painted_list, _, occ_numpy) = side_by_side([
            lambda: rapp.occupancy(arm, OBSTACLES3, grid),
            lambda: rapp.occupancy(arm, next(fresh), grid),
            lambda: cspace_kernel.paint(k, lv, given),
            lambda: cspace_kernel.paint(k, lv, kept),
            lambda: np.ones(cells, dtype=bool),
            lambda: cspace.occupancy_numpy(arm, OBSTACLES3, grid),
        ])
    res = {
        "cells": cells, "rapp_s": t_rapp, "rapp_new_scene_s": t_new, "floor_s": t_floor,
        "floor_nonempty_only_s": t_list, "ratio_rapp_new_scene_over_floor": t_new / t_floor,
        "memory_s": t_mem, "numpy_s": t_numpy,
        "ratio_rapp_over_floor": t_rapp / t_floor,
        "ratio_rapp_over_floor_nonempty_only": t_rapp / t_list,
        "ratio_numpy_over_rapp": t_numpy / t_rapp,
        "intervals": int(sum(w.size for _, _, w in given)),
        "intervals_painted": int(sum(w.size for _, _, w in kept)),
        "new_scene_equals_rapp": bool((occ_new == occ).all()),
        "floor_equals_rapp": bool((painted.reshape(grid.shape) == occ).all()
                                  and (painted_list.reshape(grid.shape) == occ).all()),
        "occupied_fraction": float(occ.mean()),
        "targets": {"ratio_rapp_over_floor_max": 2.0},
    }
    res.update(mismatches(arm, OBSTACLES3, grid, occ, occ_numpy))
    return res


def two_link():
    """The 2-link grids of bench_core.py, compiled against numpy."""
    arm, discs, out = rapp.Arm(LINKS), [rapp.Circle((x, y), r) for x, y, r in CIRCLES], {}
    for grid in (rapp.JointGrid(arm, 100), rapp.JointGrid(arm, 360)):
        # rapp.occupancy uses the kernel here because numba is loaded; a fresh process planning
        # a grid under cspace.COMPILE_FROM cells uses numpy (the same cells).
        (t_rapp, t_numpy), (occ, occ_numpy) = side_by_side([
            lambda: rapp.occupancy(arm, discs, grid),
            lambda: cspace.occupancy_numpy(arm, discs, grid)])
        res = {"cells": occ.size, "compiled_s": t_rapp, "numpy_s": t_numpy,
               "ratio_numpy_over_compiled": t_numpy / t_rapp,
               "uses_compiled_in_a_fresh_process": occ.size >= cspace.COMPILE_FROM}
        res.update(mismatches(arm, discs, grid, occ, occ_numpy))
        out[f"2link_M{grid.shape[0]}"] = res
    return out


FIRST_CALL = """
import time, sys
t0 = time.perf_counter()
import rapp
sys.path.insert(0, {here!r})
from bench_core import LINKS3, OBSTACLES3
arm = rapp.Arm(LINKS3)
grid = rapp.JointGrid(arm, {m})
t1 = time.perf_counter()
rapp.occupancy(arm, OBSTACLES3, grid)
t2 = time.perf_counter()
rapp.occupancy(arm, OBSTACLES3, grid)
t3 = time.perf_counter()
print(t2 - t1, t3 - t2)
"""


def first_call():
    """Seconds of the first and the second 128^3 call in a fresh process: with numba's on-disk
    cache as it is (normally warm), and with an empty cache directory (compilation)."""
    code = FIRST_CALL.format(here=str(HERE), m=M3)
    out = {}
    with tempfile.TemporaryDirectory() as empty:
        for name, extra in (("cached", {}), ("uncached", {"NUMBA_CACHE_DIR": empty})):
            env = dict(os.environ, **extra)
            r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                               text=True, check=True)
            first, second = map(float, r.stdout.split())
            out[f"first_call_{name}_s"] = first
            out[f"second_call_{name}_s"] = second
    return out


def run():
    load_before = os.getloadavg()[0]
    results = {"3link_M128": three_link()}
    results.update(two_link())
    results["3link_M128"].update(first_call())
    info = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu_count": os.cpu_count(),
        "load_average_1min_before": load_before,
        "load_average_1min_after": os.getloadavg()[0],
        "machine": platform.machine(), "platform": platform.platform(),
        "python": platform.python_version(), "numpy": np.__version__,
        "scenario": {"links3": LINKS3, "obstacles3": [repr(o) for o in OBSTACLES3],
                     "links": LINKS, "circles": CIRCLES},
        "timing": f"time.perf_counter seconds per call, best of {ROUNDS} rounds of {K} calls in a "
                  "row of each function, the functions in turn within every round",
        "floor": "the kernel painting intervals computed beforehand (every link, prefix cell "
                 "and obstacle), with the allocation; see benchmarks/bench_occupancy.py",
    }
    (HERE.parent / "rapp" / "recorded" / "occupancy.json").write_text(
        json.dumps({"machine": info, "results": results}, indent=2) + "\n")

    r = results["3link_M128"]
    print(f"3-link {M3}^3 occupancy ({r['cells']:,} cells; {r['intervals']:,} intervals, one per "
          f"prefix cell and obstacle, {r['intervals_painted']:,} of them painted)")
    print(f"  {'rapp.occupancy (compiled)':34s} {r['rapp_s'] * 1e3:9.3f} ms")
    print(f"  {'  the same, a new scene every call':34s} {r['rapp_new_scene_s'] * 1e3:9.3f} ms")
    print(f"  {'floor (paint given intervals)':34s} {r['floor_s'] * 1e3:9.3f} ms")
    print(f"  {'  given only the painted ones':34s} {r['floor_nonempty_only_s'] * 1e3:9.3f} ms")
    print(f"  {'memory (write 128^3 bytes)':34s} {r['memory_s'] * 1e3:9.3f} ms")
    print(f"  {'occupancy_numpy':34s} {r['numpy_s'] * 1e3:9.3f} ms")
    print(f"  rapp / floor = {r['ratio_rapp_over_floor']:.2f} (goal <= 2; "
          f"{r['ratio_rapp_over_floor_nonempty_only']:.2f} against the second; "
          f"{r['ratio_rapp_new_scene_over_floor']:.2f} with a new scene), "
          f"numpy / rapp = {r['ratio_numpy_over_rapp']:.1f}, floor output == rapp's: "
          f"{r['floor_equals_rapp']}, new scene's == rapp's: {r['new_scene_equals_rapp']}")
    print(f"  first call in a fresh process: {r['first_call_cached_s']:.3f} s with numba's cache, "
          f"{r['first_call_uncached_s']:.3f} s compiling (second call "
          f"{r['second_call_cached_s'] * 1e3:.2f} ms)")
    for key, res in results.items():
        if key.startswith("2link"):
            print(f"{key}: compiled {res['compiled_s'] * 1e3:.3f} ms, "
                  f"numpy {res['numpy_s'] * 1e3:.3f} ms ({res['ratio_numpy_over_compiled']:.1f}x)")
    for key, res in results.items():
        print(key, {k: v for k, v in res.items() if "mismatch" in k})
    print(f"cpu_count={info['cpu_count']} load={load_before:.2f} -> "
          f"{info['load_average_1min_after']:.2f} python={info['python']} numpy={info['numpy']}")


if __name__ == "__main__":
    run()
