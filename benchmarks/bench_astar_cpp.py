"""rapp.astar (numba) against pyastar2d (A* in C++) on the 2-link grids, in one run.

The 2-link torus grids of ``bench_search.py`` (M = 360 and 720, the three discs of
``bench_core.py``). rapp searches the torus (every joint wraps, the toroidal Manhattan
heuristic). pyastar2d knows no wrap; it is timed twice:

* on the plain grid without wrap (the goal's comparison: a smaller graph, here with a
  path of the same length, so the harder case for rapp);
* on the torus unrolled: the occupancy tiled 3 x 3 with the start in the middle tile and the
  goal's nearest copy as its goal, which makes its shortest path the torus's.

Both 4-connected, unit steps (pyastar2d's weights 1 on free cells, inf on blocked ones);
path lengths must be equal. Each pyastar2d version is interleaved with rapp round by round,
in its own block, and the best of ``ROUNDS`` is kept for each; the machine's load is recorded. Expansions are rapp's (counted by
the teaching :func:`rapp.search.astar_search`, which expands the same cells); pyastar2d does not
report its own. Prints a table with both ratios and writes ``rapp/recorded/astar_cpp.json``;
without pyastar2d only rapp is timed.

Run from the repository root (pyastar2d from benchmarks/requirements.txt):
``PYTHONPATH=$PWD python benchmarks/bench_astar_cpp.py``.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import CIRCLES, GOAL_Q, LINKS, START_Q, side_by_side  # noqa: E402  the problem, defined once

import rapp  # noqa: E402
from rapp.search import astar_search  # noqa: E402

HERE = Path(__file__).resolve().parent
OUT = HERE.parent / "rapp" / "recorded" / "astar_cpp.json"
ROUNDS = {360: 41, 720: 15}


def unrolled(occ, start, goal):
    """The torus as a 3 x 3 tiling for a planner without wrap: weights, start, goal."""
    M0, M1 = occ.shape
    w = np.where(np.tile(occ, (3, 3)), np.inf, 1.0).astype(np.float32)
    s = (start[0] + M0, start[1] + M1)
    g = tuple(min((goal[a] + k * m for k in range(3)), key=lambda x: abs(x - s[a]))
              for a, m in enumerate((M0, M1)))
    return w, s, g


def time_grid(M, pyastar2d):
    """Best-of times of rapp and of pyastar2d (plain grid, then unrolled torus) on one grid.

    Each peer is timed in its own interleaved block with rapp, so the 3 x 3 tiling (nine
    times the cells, a copy of them per call) does not disturb the plain-grid comparison.
    """
    arm = rapp.Arm(LINKS)
    obstacles = [rapp.Circle((cx, cy), r) for cx, cy, r in CIRCLES]
    grid = rapp.JointGrid(arm, M)
    occ = rapp.occupancy(arm, obstacles, grid)
    s, g = tuple(grid.index(START_Q).tolist()), tuple(grid.index(GOAL_Q).tolist())
    path = rapp.astar(occ, s, g)  # loads the compiled kernel
    expansions = astar_search(occ, s, g).expansions
    mine = lambda: rapp.astar(occ, s, g)  # noqa: E731
    if pyastar2d is None:
        (alone,), _ = side_by_side(ROUNDS[M], [mine])
        return {"rapp_s": alone, "rapp_path_cells": len(path), "rapp_expansions": expansions,
                "rapp_ns_per_expansion": alone / expansions * 1e9}
    w1 = np.where(occ, np.inf, 1.0).astype(np.float32)
    (r1, p1), (_, plain_path) = side_by_side(ROUNDS[M], [
        mine, lambda: pyastar2d.astar_path(w1, s, g, allow_diagonal=False)])
    w3, s3, g3 = unrolled(occ, s, g)
    (r3, p3), (_, torus_path) = side_by_side(ROUNDS[M], [
        mine, lambda: pyastar2d.astar_path(w3, s3, g3, allow_diagonal=False)])
    assert len(plain_path) == len(torus_path) == len(path), "the path lengths differ"
    return {"rapp_s": r1, "rapp_path_cells": len(path), "rapp_expansions": expansions,
            "rapp_ns_per_expansion": r1 / expansions * 1e9,
            "pyastar2d_no_wrap_s": p1, "pyastar2d_no_wrap_path_cells": len(plain_path),
            "rapp_over_pyastar2d_no_wrap": r1 / p1, "pyastar2d_no_wrap_over_rapp": p1 / r1,
            "rapp_s_beside_torus": r3, "pyastar2d_s": p3,
            "rapp_over_pyastar2d": r3 / p3, "pyastar2d_over_rapp": p3 / r3}


def table(grids, before):
    """The printed table: times, both ratios, and the previous record's ratio beside."""
    lines = [f"{'grid':>6} {'rapp ms':>8} {'ns/exp':>7} {'peer':>22} {'peer ms':>8} "
             f"{'rapp/peer':>9} {'peer/rapp':>9} {'before':>7}"]
    for key, row in grids.items():
        for peer, label, mine in (("pyastar2d_no_wrap", "pyastar2d, plain grid", "rapp_s"),
                                  ("pyastar2d", "pyastar2d, 3x3 torus", "rapp_s_beside_torus")):
            if f"{peer}_s" not in row:
                continue
            old = before.get(key, {}).get(f"rapp_over_{peer}")
            lines.append(
                f"{key.split('_M')[1] + '²':>6} {row[mine] * 1e3:8.2f} "
                f"{row[mine] / row['rapp_expansions'] * 1e9:7.1f} {label:>22} "
                f"{row[f'{peer}_s'] * 1e3:8.2f} {row[f'rapp_over_{peer}']:9.2f} "
                f"{row[f'{peer}_over_rapp']:9.2f} " + (f"{old:7.2f}" if old else f"{'':>7}"))
    return "\n".join(lines)


def main() -> None:
    try:
        import pyastar2d
    except ImportError:
        pyastar2d = None
        print("pyastar2d is not installed (pip install -r benchmarks/requirements.txt): timing rapp only")
    before = json.loads(OUT.read_text())["grids"] if OUT.exists() else {}
    load_before = os.getloadavg()
    grids = {f"2link_M{M}": time_grid(M, pyastar2d) for M in ROUNDS}
    result = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "load_before": load_before,
                    "load_after": os.getloadavg()},
        "rounds": ROUNDS,
        "grids": grids,
    }
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(table(grids, before))
    print(f"(rapp/peer < 1: rapp faster; 'before': rapp/peer in the previous record; "
          f"best of {ROUNDS} interleaved rounds; load {load_before[0]:.1f} -> "
          f"{result['machine']['load_after'][0]:.1f} on {os.cpu_count()} CPUs)")
    print(f"wrote {OUT.relative_to(HERE.parent)}")


if __name__ == "__main__":
    main()
