"""The compiled collision kernel and the lazy start-up, each side by side with what it replaced.

In one run, on the 3-link benchmark problem of ``bench_core.py`` (links 1.0, 0.8, 0.5; four
discs and a rectangle):

* ``rapp.collides`` for one configuration: the compiled kernel (``rapp.kernels.collision_numba``)
  against the numpy backend that runs without numba (``rapp.kernels.collision_numpy``, not the
  per-configuration oracle ``rapp.reference``, which only checks the answers), alternately;
  also a batch of 10,000 configurations, and ``segment_collision_free`` for one short edge.
* ``rrt_connect``, ``prm`` and ``rrt_star`` over 20 seeds: compiled (the collision kernel,
  the planners' compiled loops of ``rapp.kernels.sampling_numba`` and PRM's compiled Dijkstra) and
  with the numpy versions and PRM's Python Dijkstra (switched off as when numba is missing),
  the same seeds growing the same trees (checked node by node); ratio of the summed times.
* Start-up: ``python -m rapp plan`` (the default scenario) against ``python -c "import
  numpy"``, alternately, CPU seconds (user + sys) of each finished process, median of 7, with
  bytecode caches written (as an installed package has them; ``PYTHONDONTWRITEBYTECODE``
  is dropped for these runs).

Every figure is a ratio of CPU times (``time.process_time``) measured in the same run; the machine's load (``os.getloadavg``) is
recorded before and after. Run from the repository root:
``PYTHONPATH=$PWD python benchmarks/bench_kernel.py``; writes ``rapp/recorded/kernel.json``.
"""

from __future__ import annotations

import datetime
import importlib
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
from rapp import reference
from rapp.kernels import collision_numba as collision_kernel
from rapp.kernels import collision_numpy
from rapp.collision import segment_collision_free
from rapp.prm import prm
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import LINKS3, OBSTACLES3, START3, GOAL3  # noqa: E402  the problem, defined once

HERE = Path(__file__).resolve().parent
PRM = importlib.import_module("rapp.prm")  # the module (rapp.prm is the function)
SEEDS = 20


def alternately(fns, k):
    """Per-call CPU seconds of several functions: the best of 5 rounds of ``k`` calls each, the
    functions in turn within every round so that the machine's load hits them alike."""
    best = [np.inf] * len(fns)
    for _ in range(5):
        for j, fn in enumerate(fns):
            best[j] = min(best[j], _mean(fn, k))
    return best


def _mean(fn, k):
    t0 = time.process_time()
    for _ in range(k):
        fn()
    return (time.process_time() - t0) / k


class numpy_only:
    """Within ``with numpy_only():`` rapp runs the numpy versions, as when numba is missing."""

    def __enter__(self):
        self.saved = collision_kernel.kernels, PRM._compiled_dijkstra
        collision_kernel.kernels = PRM._compiled_dijkstra = lambda: None

    def __exit__(self, *exc):
        collision_kernel.kernels, PRM._compiled_dijkstra = self.saved


def single_checks(arm, obstacles):
    q = np.array([0.3, -0.4, 0.9])
    qs = np.random.default_rng(0).uniform(-np.pi, np.pi, (10_000, 3))
    q1 = q + 0.1
    rapp.collides(arm, q, obstacles)
    segment_collision_free(arm, q, q1, obstacles)
    one = alternately([lambda: rapp.collides(arm, q, obstacles),
                       lambda: collision_numpy.collides(arm, q, obstacles)], 2000)
    batch = alternately([lambda: rapp.collides(arm, qs, obstacles),
                         lambda: collision_numpy.collides(arm, qs, obstacles)], 5)
    edge = alternately([lambda: segment_collision_free(arm, q, q1, obstacles),
                        lambda: collision_numpy.segment_collision_free(arm, q, q1, obstacles)], 500)
    assert (rapp.collides(arm, qs, obstacles) == collision_numpy.collides(arm, qs, obstacles)).all()
    assert (rapp.collides(arm, qs[:500], obstacles) == reference.collides(arm, qs[:500], obstacles)).all()
    return {
        "collides_one_us": {"kernel": one[0] * 1e6, "numpy": one[1] * 1e6, "ratio": one[1] / one[0]},
        "collides_10k_ms": {"kernel": batch[0] * 1e3, "numpy": batch[1] * 1e3,
                            "ratio": batch[1] / batch[0]},
        "segment_collision_free_one_us": {"kernel": edge[0] * 1e6, "numpy": edge[1] * 1e6,
                                          "ratio": edge[1] / edge[0]},
    }


def planners(arm, obstacles):
    out = {}
    for planner in (rrt_connect, prm, rrt_star):
        times = {"kernel": [], "numpy": []}
        solved = 0
        # Compiled once before the clock starts (numba's cache may be cold after a change).
        planner(arm, START3, GOAL3, obstacles, seed=SEEDS, raise_on_failure=False)
        for seed in range(SEEDS):
            results = {}
            for mode in ("kernel", "numpy"):  # in turn, seed by seed
                t0 = time.process_time()
                if mode == "numpy":
                    with numpy_only():
                        res = planner(arm, START3, GOAL3, obstacles, seed=seed, raise_on_failure=False)
                else:
                    res = planner(arm, START3, GOAL3, obstacles, seed=seed, raise_on_failure=False)
                times[mode].append(time.process_time() - t0)
                results[mode] = res
            a, b = results["kernel"], results["numpy"]
            assert a.success == b.success and np.array_equal(a.nodes, b.nodes) \
                and np.array_equal(a.parent, b.parent) and np.array_equal(a.path, b.path), \
                f"{planner.__name__} seed {seed}: the trees differ"
            if a.success:
                solved += 1
                assert rapp.path_collision_free(arm, a.path, obstacles)
        out[planner.__name__] = {
            "kernel_total_s": sum(times["kernel"]), "numpy_total_s": sum(times["numpy"]),
            "kernel_median_s": float(np.median(times["kernel"])),
            "numpy_median_s": float(np.median(times["numpy"])),
            "ratio_total": sum(times["numpy"]) / sum(times["kernel"]),
            "solved": solved, "seeds": SEEDS, "same_trees": True,
        }
    return out


def _cpu_seconds(cmd, env):
    """CPU seconds (user + sys) of one finished child process."""
    before = os.times()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = os.times()
    return (after.children_user - before.children_user) + (after.children_system - before.children_system)


def start_up(runs=7):
    # As an installed package runs: with bytecode caches (the warm-up run writes them).
    env = dict(os.environ, PYTHONPATH=str(HERE.parent))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    with tempfile.TemporaryDirectory() as tmp:
        plan_cmd = [sys.executable, "-m", "rapp", "plan", "--out", str(Path(tmp) / "r.json")]
        numpy_cmd = [sys.executable, "-c", "import numpy"]
        import_cmd = [sys.executable, "-c", "import rapp"]
        _cpu_seconds(plan_cmd, env)  # warm the file caches (and numba's, if used)
        t = {"plan": [], "import_numpy": [], "import_rapp": []}
        for _ in range(runs):
            t["plan"].append(_cpu_seconds(plan_cmd, env))
            t["import_numpy"].append(_cpu_seconds(numpy_cmd, env))
            t["import_rapp"].append(_cpu_seconds(import_cmd, env))
    ratios = [p / n for p, n in zip(t["plan"], t["import_numpy"])]
    return {
        "plan_cpu_s_median": float(np.median(t["plan"])),
        "import_numpy_cpu_s_median": float(np.median(t["import_numpy"])),
        "import_rapp_cpu_s_median": float(np.median(t["import_rapp"])),
        "plan_over_import_numpy_median": float(np.median(ratios)),
        "runs": runs,
        "bytecode_caches": True,
    }


def main() -> None:
    arm, obstacles = rapp.Arm(LINKS3), list(OBSTACLES3)
    if collision_kernel.kernels() is None:
        sys.exit("numba is not installed: the kernel cannot be compared with the numpy versions")
    load_before = os.getloadavg()
    result = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "load_before": load_before},
        "problem": {"links": LINKS3, "start": START3, "goal": GOAL3, "obstacles": len(obstacles)},
        "single": single_checks(arm, obstacles),
        "planners": planners(arm, obstacles),
        "start_up": start_up(),
    }
    result["machine"]["load_after"] = os.getloadavg()
    print(json.dumps(result, indent=2))
    (HERE.parent / "rapp" / "recorded" / "kernel.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
