"""Batch numerical IK vs the classic per-target loop; batched analytic 2-link IK vs a loop.

Times ``rapp.ik_numeric`` on 10,000 random reachable targets of the 3-link arm
[1.0, 0.8, 0.5] against the baseline of classic demos: a Python loop over
targets, each solved by plain Newton-Raphson with ``np.linalg.pinv`` from a
random start (restarted from a new random start when it fails). Both run in
this one process on the same targets; the ratio is the number to quote, since
absolute times depend on the machine and its load.

The second comparison: ``rapp.ik_2link(arm, targets)`` on 10,000 targets of the 2-link arm
[1.0, 0.8] at once, against a loop of ``rapp.ik(arm, target)`` over them (what a user without
the batched call writes); every solution must put the tip within 1e-9 m of its target. Beside
it the fair peers of the same run: a loop of ``ik_2link`` itself (the batching alone, without
``ik``'s joint limits and checks), and the textbook closed form in plain numpy (``arccos`` of
the law of cosines, both elbows), which skips the input checks and the boundary care.

Run: ``python benchmarks/bench_ik.py`` -> prints a table, writes
``rapp/recorded/ik.json``; ``--only-2link`` re-measures the 2-link comparison alone and
replaces that part of the file (with its own date and load).
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from rapp import Arm, ik, ik_2link, ik_numeric

N_TARGETS = 10_000
TOL = 1e-10


def naive_ik(arm: Arm, target, rng, tol=TOL, max_iter=100, restarts=8):
    """Plain Newton-Raphson with the pseudo-inverse, one target at a time."""
    lengths = arm.lengths
    for _ in range(restarts + 1):
        q = rng.uniform(-np.pi, np.pi, arm.n)
        for _ in range(max_iter):
            phi = np.cumsum(q)
            tip = np.array([np.sum(lengths * np.cos(phi)), np.sum(lengths * np.sin(phi))])
            err = target - tip
            if np.linalg.norm(err) <= tol:
                return q, True
            J = np.zeros((2, arm.n))
            for j in range(arm.n):
                J[0, j] = -np.sum(lengths[j:] * np.sin(phi[j:]))
                J[1, j] = np.sum(lengths[j:] * np.cos(phi[j:]))
            q = q + np.linalg.pinv(J) @ err
    return q, False


def best_of(fn, repeat):
    times = []
    out = None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def numpy_2link(l1, l2, targets):
    """The textbook closed form, both elbows, in plain numpy: no checks, arccos near the rim."""
    x, y = targets[..., 0], targets[..., 1]
    q2 = np.arccos(np.clip((x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0))
    q2 = np.stack((q2, -q2), axis=-1)
    q1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    return np.stack((q1, q2), axis=-1)


def analytic_2link() -> dict:
    """``ik_2link`` on a batch against loops of ``rapp.ik`` and ``ik_2link`` and a numpy
    one-liner, same targets, same run."""
    arm = Arm([1.0, 0.8])
    rng = np.random.default_rng(7)
    targets = arm.end_effector(rng.uniform(-np.pi, np.pi, (N_TARGETS, 2)))
    ik_2link(arm, targets[:10])  # warm-up
    t_batch, q = best_of(lambda: ik_2link(arm, targets), repeat=7)
    t_loop, sols = best_of(lambda: [ik(arm, tt) for tt in targets], repeat=1)
    t_loop2, _ = best_of(lambda: [ik_2link(arm, tt) for tt in targets], repeat=3)
    t_np, q_np = best_of(lambda: numpy_2link(1.0, 0.8, targets), repeat=7)
    err_batch = np.linalg.norm(arm.end_effector(q) - targets[:, None, :], axis=-1)
    err_np = np.linalg.norm(arm.end_effector(q_np) - targets[:, None, :], axis=-1)
    err_loop = max(float(np.linalg.norm(arm.end_effector(s) - tt, axis=-1).max())
                   for s, tt in zip(sols, targets))
    out = {"arm": list(arm.link_lengths), "targets": N_TARGETS,
           "batch_us_per_target": 1e6 * t_batch / N_TARGETS,
           "loop_us_per_target": 1e6 * t_loop / N_TARGETS,
           "speedup": t_loop / t_batch,
           "batch_max_error_m": float(err_batch.max()), "loop_max_error_m": err_loop,
           "goal": "speedup >= 100 and batch_max_error_m <= 1e-9",
           "loop_ik_2link_us_per_target": 1e6 * t_loop2 / N_TARGETS,
           "speedup_over_loop_ik_2link": t_loop2 / t_batch,
           "numpy_us_per_target": 1e6 * t_np / N_TARGETS,
           "numpy_max_error_m": float(err_np.max()),
           "ratio_batch_over_numpy": t_batch / t_np,
           "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None}
    out["goal_met"] = bool(out["speedup"] >= 100 and out["batch_max_error_m"] <= 1e-9)
    print(f"2-link analytic IK, {N_TARGETS} targets: batch {out['batch_us_per_target']:.3f} us/target, "
          f"loop of rapp.ik {out['loop_us_per_target']:.1f} us/target, speed-up {out['speedup']:.0f}x, "
          f"max error {out['batch_max_error_m']:.1e} m")
    print(f"  loop of ik_2link {out['loop_ik_2link_us_per_target']:.1f} us/target "
          f"({out['speedup_over_loop_ik_2link']:.0f}x the batch); numpy one-liner "
          f"{out['numpy_us_per_target']:.3f} us/target (the batch takes {out['ratio_batch_over_numpy']:.1f}x "
          f"its time), max error {out['numpy_max_error_m']:.1e} m")
    return out


OUT = Path(__file__).resolve().parent.parent / "rapp" / "recorded" / "ik.json"


def main():
    if "--only-2link" in sys.argv[1:]:
        result = json.loads(OUT.read_text())
        result["analytic_2link"] = analytic_2link()
        OUT.write_text(json.dumps(result, indent=2) + "\n")
        print(f"wrote {OUT} (2-link part only)")
        return
    arm = Arm([1.0, 0.8, 0.5])
    rng = np.random.default_rng(2024)
    targets = arm.end_effector(rng.uniform(-np.pi, np.pi, (N_TARGETS, arm.n)))

    ik_numeric(arm, targets[:100])  # warm-up
    t_fast, (q, ok) = best_of(lambda: ik_numeric(arm, targets, tol=TOL), repeat=7)
    err = np.linalg.norm(arm.end_effector(q) - targets, axis=-1)

    def run_naive():
        r = np.random.default_rng(0)
        return [naive_ik(arm, tt, r) for tt in targets]

    t_naive, res = best_of(run_naive, repeat=1)
    qn = np.array([r[0] for r in res])
    okn = np.array([r[1] for r in res])
    errn = np.linalg.norm(arm.end_effector(qn) - targets, axis=-1)

    us_fast = 1e6 * t_fast / N_TARGETS
    us_naive = 1e6 * t_naive / N_TARGETS
    rows = [
        ("rapp.ik_numeric (batched NR + DLS)", us_fast, ok.mean(), err.max(), err[ok].max()),
        ("naive loop (NR + np.linalg.pinv)", us_naive, okn.mean(), errn.max(),
         errn[okn].max()),
    ]
    print(f"3-link arm {arm.link_lengths}, {N_TARGETS} reachable targets, tol {TOL:g} m")
    print(f"{'method':38s} {'us/target':>10s} {'success':>8s} {'max err':>10s} {'max err ok':>11s}")
    for name, us, succ, emax, eok in rows:
        print(f"{name:38s} {us:10.2f} {succ:8.4f} {emax:10.2e} {eok:11.2e}")
    print(f"speed-up: {us_naive / us_fast:.1f}x")

    result = {
        "benchmark": "ik_numeric vs per-target Newton-Raphson with pinv",
        "arm": list(arm.link_lengths),
        "targets": N_TARGETS,
        "tol_m": TOL,
        "batched": {"us_per_target": us_fast, "success_rate": float(ok.mean()),
                    "max_error_m": float(err.max()), "max_error_ok_m": float(err[ok].max())},
        "naive": {"us_per_target": us_naive, "success_rate": float(okn.mean()),
                  "max_error_m": float(errn.max()), "max_error_ok_m": float(errn[okn].max())},
        "speedup": us_naive / us_fast,
        "machine": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "cpus": os.cpu_count(),
            "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        },
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    result["analytic_2link"] = analytic_2link()
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
