"""Peak memory per grid cell of the whole planning pipeline, the number behind the grid limit.

Each case runs ``rapp.plan`` in a fresh Python process (so one case's peak cannot hide in
another's) on an arm of n equal links reaching round a disc, with the grid limit lifted, and
reads the process's peak resident memory (``ru_maxrss``). The cost of a cell is the peak above
the process's size after importing rapp and loading the scenario, divided by the number of
cells. ``rapp.scenario`` accepts a grid only when ``cells * bytes_per_cell(n)`` fits ``MEMORY_BUDGET``; this script checks that the model is
above every measurement and writes ``rapp/recorded/memory.json``.

Run from the repository root: ``python benchmarks/bench_memory.py`` (about two minutes).
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from datetime import date
from pathlib import Path

import numpy as np

import rapp.scenario as sc

CASES = [(2, 1000), (2, 2000), (3, 120), (4, 40), (5, 18), (6, 11), (7, 8), (8, 6)]

CHILD = r"""
import json, resource, sys
import rapp, rapp.scenario as sc
n, cells = int(sys.argv[1]), int(sys.argv[2])
sc.MEMORY_BUDGET = 1e15                      # measure beyond the limit
d = {"arm": {"link_lengths": [2.0 / n] * n}, "start": [0.0] * n,
     "goal": {"joints": [2.0] + [0.0] * (n - 1)},
     "obstacles": [{"type": "circle", "center": [0.3, 1.2], "radius": 0.2}],
     "planner": {"algorithm": "astar", "cells": cells}}
s = rapp.load_scenario(d)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
try:
    rapp.plan(s)
    outcome = "planned"
except rapp.NoPathFound as e:
    outcome = type(e).__name__
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"base_kib": base, "peak_kib": peak, "outcome": outcome}))
"""


def measure(n: int, cells: int) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(n), str(cells)], check=True,
                         capture_output=True, text=True).stdout
    r = json.loads(out.strip().splitlines()[-1])
    total = cells ** n
    per_cell = (r["peak_kib"] - r["base_kib"]) * 1024 / total
    model = sc.bytes_per_cell(n)
    return {"joints": n, "cells_per_joint": cells, "cells": total, "outcome": r["outcome"],
            "process_base_mb": r["base_kib"] / 1024, "peak_mb": r["peak_kib"] / 1024,
            "bytes_per_cell": per_cell, "model_bytes_per_cell": model,
            "model_over_measured": model / per_cell}


def main() -> None:
    rows = [measure(n, c) for n, c in CASES]
    print(f"{'n':>2} {'cells':>10} {'peak MB':>8} {'B/cell':>7} {'model':>6} {'model/meas':>10}")
    for r in rows:
        print(f"{r['joints']:>2} {r['cells']:>10} {r['peak_mb']:>8.0f} {r['bytes_per_cell']:>7.0f} "
              f"{r['model_bytes_per_cell']:>6} {r['model_over_measured']:>10.2f}")
    worst = min(r["model_over_measured"] for r in rows)
    largest = [{"joints": n, "max_cells": sc.max_cells(n),
                "predicted_peak_gb": sc.max_cells(n) * sc.bytes_per_cell(n) / 1e9}
               for n in range(1, 9)]
    result = {
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "load_1min": os.getloadavg()[0],
                    "platform": platform.platform(), "python": platform.python_version(),
                    "numpy": np.__version__},
        "memory_budget_bytes": sc.MEMORY_BUDGET,
        "cases": rows,
        "model_over_measured_min": worst,
        "limits": largest,
    }
    path = Path(__file__).resolve().parent.parent / "rapp" / "recorded" / "memory.json"
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(f"model / measured >= {worst:.2f} (must be >= 1); written {path}")
    if worst < 1:
        sys.exit("the memory model is below a measurement: raise BYTES_PER_CELL_*")


if __name__ == "__main__":
    main()
