"""A roadmap built once, queried many times: what each query costs beside the build.

Problem: the 3-link arm and obstacles of ``bench_core.py`` (the book's benchmark problem).
``rapp.Roadmap`` is built with its defaults (500 samples, 10 neighbours) for each of SEEDS seeds,
then asked QUERIES queries in a row, each between two free configurations drawn uniformly (the
same ends for every seed). Every path is checked by ``rapp.path_collision_free``. The roadmap
certifies all its edges at the build, so a query certifies only the edges joining its own ends;
each query's CPU time (``time.process_time``) is recorded with the roadmap edges it certified
(none unless it grew the roadmap) and the build's. A one-query ``rapp.prm`` on the same problem is timed too
(what each query would cost without the roadmap).

Run from the repository root::

    PYTHONPATH=$PWD python benchmarks/bench_roadmap.py

Writes ``rapp/recorded/roadmap.json``.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np

import rapp

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import LINKS3, OBSTACLES3  # noqa: E402  the problem is defined once

SEEDS = int(os.environ.get("RAPP_BENCH_SEEDS", 10))
QUERIES = 20


def query_ends(arm, obstacles, count, seed=5):
    """``count + 1`` free configurations, drawn uniformly: query i goes from the i-th to the next."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (20 * count, arm.n))
    return q[~rapp.collides(arm, q, obstacles)][: count + 1]


def run(arm, obstacles, ends, seed):
    t0 = time.process_time()
    roadmap = rapp.Roadmap(arm, obstacles, seed=seed)
    build = time.process_time() - t0
    times, certified = [], []
    for a, b in zip(ends[:-1], ends[1:]):
        before = roadmap.certified
        t0 = time.process_time()
        res = roadmap.query(a, b)
        times.append(time.process_time() - t0)
        certified.append(roadmap.certified - before)
        assert res.success and rapp.path_collision_free(arm, res.path, obstacles), seed
    t0 = time.process_time()
    one = rapp.prm(arm, ends[0], ends[1], obstacles, seed=seed)
    prm_s = time.process_time() - t0
    assert one.success
    return build, times, certified, prm_s


def main() -> None:
    arm, obstacles = rapp.Arm(LINKS3), list(OBSTACLES3)
    ends = query_ends(arm, obstacles, QUERIES)
    run(arm, obstacles, ends, 0)  # the compiled loops loaded (numba's disk cache)
    load_before = os.getloadavg()
    runs = [run(arm, obstacles, ends, seed) for seed in range(SEEDS)]
    build = np.array([r[0] for r in runs])
    times = np.array([r[1] for r in runs])          # (SEEDS, QUERIES)
    certified = np.array([r[2] for r in runs])
    ratio = build[:, None] / times                  # each query against its own roadmap's build
    result = {
        "date": date.today().isoformat(),
        "timing": "CPU time (time.process_time) of the build and of each query, per seed",
        "machine": {"cpus": os.cpu_count(), "load_before": load_before,
                    "load_after": os.getloadavg(), "platform": platform.platform(),
                    "python": platform.python_version()},
        "problem": {"links": LINKS3, "seeds": SEEDS, "queries": QUERIES, "samples": 500,
                    "neighbours": 10, "query_ends_seed": 5},
        "build_cpu_s": build.tolist(),
        "query_cpu_s": times.tolist(),
        "certified_per_query": certified.tolist(),
        "one_query_prm_cpu_s": [r[3] for r in runs],
        "median_build_cpu_s": float(np.median(build)),
        "median_query_cpu_s": float(np.median(times)),
        "median_query_cpu_s_by_position": np.median(times, axis=0).tolist(),
        "build_over_query_median": float(np.median(ratio)),
        "build_over_query_min": float(ratio.min()),
        "queries_at_least_10x_cheaper": int((ratio >= 10).sum()),
        "queries_total": int(ratio.size),
        "all_certified": True,
    }
    print(f"load {load_before[0]:.1f}; {SEEDS} roadmaps x {QUERIES} queries")
    print(f"build median {1e3 * np.median(build):.2f} ms; query median "
          f"{1e3 * np.median(times):.3f} ms (first {1e3 * np.median(times[:, 0]):.3f} ms, last "
          f"{1e3 * np.median(times[:, -1]):.3f} ms); one-query prm median "
          f"{1e3 * np.median(result['one_query_prm_cpu_s']):.2f} ms")
    print(f"build / query: median {np.median(ratio):.1f}x, least {ratio.min():.1f}x; "
          f"{(ratio >= 10).sum()} of {ratio.size} queries at least 10x cheaper than the build; "
          f"edges certified per query (median by position): "
          f"{np.median(certified, axis=0).astype(int).tolist()}")
    target = Path(__file__).resolve().parent.parent / "rapp" / "recorded" / "roadmap.json"
    target.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
