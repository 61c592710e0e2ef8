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

The third comparison, the fair peer of the 3-link case: robotics-toolbox-python's C++
Gauss-Newton solver ``ik_GN`` (the version pinned in ``benchmarks/requirements.txt``) on the
same arm built as an ETS robot of three revolute joints in the plane, position-only mask (the
2-D tip), called once per target on every 5th of the 10,000 targets (2,000 targets: a stable
per-target time), best of 3 passes, both with its normal-matrix inverse and with
``pinv=True`` (the option its documentation gives for redundant robots), each called on the
Robot (as a user does, and as issue 27 measured) and on the Robot's ETS (the same C++ without
the Robot's per-call Python set-up, about 35 % less time); the fastest of the four is the
peer. Its tolerance is on ``E = e^T e / 2``, set so that ``|e| <= 1e-10`` m like rapp's; every
solution it reports is checked with ``rapp``'s forward kinematics to within 1e-9 m. CPU time
(``time.process_time``) and wall time (``time.perf_counter``) per target, beside rapp's on the
whole batch; the ratio is rtb's time over rapp's. rapp's default start is exact for these
targets (two links by the law of cosines, the third held straight), so its Newton-Raphson has
nothing left to do; the row "rapp from random starts" gives ``ik_numeric`` the kind of start
``ik_GN`` gets (a random configuration per target) and times the iteration itself, and "rapp,
numpy path" the batch without numba.

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
from rapp.kernels import ik as ik_kernel

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


def best_cpu_wall(fn, repeat):
    """Best CPU time (``time.process_time``) and best wall time of ``repeat`` calls, and the
    last result."""
    cpu, wall = [], []
    out = None
    for _ in range(repeat):
        c, w = time.process_time(), time.perf_counter()
        out = fn()
        wall.append(time.perf_counter() - w)
        cpu.append(time.process_time() - c)
    return min(cpu), min(wall), out


RTB_EVERY = 5      # rtb solves every 5th target: 2,000 of the 10,000
RTB_REPEAT = 3


def planar_robot(lengths):
    """The arm as a robotics-toolbox ETS robot: Rz(q1) tx(L1) Rz(q2) tx(L2) ... in the plane."""
    import roboticstoolbox as rtb
    from roboticstoolbox import ET

    ets = ET.Rz()
    for k, length in enumerate(lengths):
        ets = ets * ET.tx(float(length))
        if k + 1 < len(lengths):
            ets = ets * ET.Rz()
    return rtb.Robot(ets)


def rtb_comparison(arm: Arm, targets, us_rapp_cpu, us_rapp_wall) -> dict | None:
    """robotics-toolbox's ``ik_GN``, one call per target, on every RTB_EVERY-th target."""
    try:
        import roboticstoolbox
    except ImportError:
        print("robotics-toolbox-python not installed (pip install -r benchmarks/requirements.txt): "
              "no ik_GN comparison")
        return None
    robot = planar_robot(arm.link_lengths)
    sample = targets[::RTB_EVERY]
    poses = []
    for x, y in sample:
        pose = np.eye(4)
        pose[0, 3], pose[1, 3] = x, y
        poses.append(pose)
    mask = np.array([1.0, 1.0, 0.0, 0.0, 0.0, 0.0])   # x and y of the tip only
    e_tol = 0.5 * TOL**2                              # E = e^T e / 2 <= this  <=>  |e| <= TOL
    variants = {}
    # Robot.ik_GN, as a user calls it, and the same solver on the robot's ETS, which skips
    # the Robot's per-call Python set-up (the stricter peer).
    for api, pinv in (("robot", False), ("robot", True), ("ets", False), ("ets", True)):
        solve = robot.ik_GN if api == "robot" else robot.ets().ik_GN

        def run():
            # q0 None: ik_GN's C++ draws a random start per search (its own generator).
            return [solve(p, mask=mask, tol=e_tol, joint_limits=False, pinv=pinv) for p in poses]
        run()  # warm-up
        cpu, wall, sols = best_cpu_wall(run, RTB_REPEAT)
        q = np.array([s.q for s in sols])
        ok = np.array([bool(s.success) for s in sols])
        err = np.linalg.norm(arm.end_effector(q) - sample, axis=-1)
        variants[f"{api}, {'pinv' if pinv else 'inverse'}"] = {
            "cpu_us_per_target": 1e6 * cpu / len(sample),
            "wall_us_per_target": 1e6 * wall / len(sample),
            "success_rate": float(ok.mean()),
            "max_error_m": float(err.max()),
            "max_error_ok_m": float(err[ok].max(initial=0.0)),
            "all_ok_within_1e-9_m": bool(np.all(err[ok] <= 1e-9)),
            "mean_iterations": float(np.mean([s.iterations for s in sols])),
            "mean_searches": float(np.mean([s.searches for s in sols])),
        }
    best = min(variants, key=lambda k: variants[k]["cpu_us_per_target"])
    best_wall = min(v["wall_us_per_target"] for v in variants.values())
    robot_cpu = min(v["cpu_us_per_target"] for k, v in variants.items() if k.startswith("robot"))
    return {
        "peer": f"roboticstoolbox-python {roboticstoolbox.__version__} ik_GN (C++) of the Robot "
                "and of its ETS, one call per target, mask [1, 1, 0, 0, 0, 0], "
                "joint_limits=False, random start; the fastest variant is the peer",
        "targets_sampled": len(sample),
        "sample": f"every {RTB_EVERY}th of the {len(targets)} targets",
        "repeats": RTB_REPEAT,
        "tol_E": e_tol,
        "variants": variants,
        "fastest_variant": best,
        "rapp_cpu_us_per_target": us_rapp_cpu,
        "rapp_wall_us_per_target": us_rapp_wall,
        # Each against rtb's faster variant in that measure.
        "ratio_cpu_rtb_over_rapp": variants[best]["cpu_us_per_target"] / us_rapp_cpu,
        "ratio_wall_rtb_over_rapp": best_wall / us_rapp_wall,
        # Robot.ik_GN alone, the call issue 27 measured (its faster variant).
        "ratio_cpu_rtb_robot_over_rapp": robot_cpu / us_rapp_cpu,
        "goal": "ratio_cpu_rtb_over_rapp >= 150 and every rapp target within 1e-9 m",
    }


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


def measure(fn, arm, targets, repeat):
    """Best CPU and wall time per target (us) of ``fn() -> (q, ok)``, its success rate and
    tip errors."""
    cpu, wall, (q, ok) = best_cpu_wall(fn, repeat)
    err = np.linalg.norm(arm.end_effector(q) - targets, axis=-1)
    return {"cpu_us_per_target": 1e6 * cpu / len(targets),
            "us_per_target": 1e6 * wall / len(targets), "ok": ok, "err": err,
            "success_rate": float(ok.mean()), "max_error_m": float(err.max()),
            "max_error_ok_m": float(err[ok].max(initial=0.0))}


def rapp_runs(arm, targets) -> dict:
    """``ik_numeric`` on the batch: by default (compiled where numba is), from a random
    start per target (the iteration itself, the start ik_GN gets) and by the numpy path."""
    ik_numeric(arm, targets[:100])  # warm-up
    runs = {"default": measure(lambda: ik_numeric(arm, targets, tol=TOL), arm, targets, 7)}
    starts = np.random.default_rng(1).uniform(-np.pi, np.pi, targets.shape[:1] + (arm.n,))
    runs["random_starts"] = measure(lambda: ik_numeric(arm, targets, starts, tol=TOL),
                                    arm, targets, 5)
    loaded = ik_kernel.loaded
    ik_kernel.loaded = lambda m: None   # the numpy path, as without numba
    try:
        runs["numpy_path"] = measure(lambda: ik_numeric(arm, targets, tol=TOL), arm, targets, 5)
    finally:
        ik_kernel.loaded = loaded
    runs["numpy_path"]["same_success_set"] = bool(np.array_equal(runs["default"]["ok"],
                                                                 runs["numpy_path"]["ok"]))
    return runs


def naive_run(arm, targets) -> dict:
    def run_naive():
        r = np.random.default_rng(0)
        res = [naive_ik(arm, tt, r) for tt in targets]
        return np.array([x[0] for x in res]), np.array([x[1] for x in res])

    return measure(run_naive, arm, targets, 1)


def print_table(arm, runs, naive, rtb, compiled):
    rows = [("rapp.ik_numeric" + (" (compiled)" if compiled else " (numpy)"), runs["default"]),
            ("rapp from random starts", runs["random_starts"]),
            ("rapp, numpy path (no numba)", runs["numpy_path"])]
    if rtb is not None:
        rows += [(f"rtb ik_GN ({name}), {rtb['targets_sampled']} targets", v)
                 for name, v in rtb["variants"].items()]
    rows.append(("naive loop (NR + np.linalg.pinv)", naive))
    print(f"3-link arm {arm.link_lengths}, {N_TARGETS} reachable targets, tol {TOL:g} m, "
          f"load {os.getloadavg() if hasattr(os, 'getloadavg') else '?'}")
    print(f"{'method':42s} {'CPU us':>8s} {'wall us':>9s} {'success':>8s} {'max err ok':>11s}")
    for name, v in rows:
        wall = v.get("us_per_target", v.get("wall_us_per_target"))
        print(f"{name:42s} {v['cpu_us_per_target']:8.3f} {wall:9.3f} {v['success_rate']:8.4f} "
              f"{v['max_error_ok_m']:11.2e}")
    print(f"speed-up over the naive loop: {naive['us_per_target'] / runs['default']['us_per_target']:.1f}x")
    if rtb is not None:
        print(f"rtb ik_GN (its fastest variant) over rapp per target: "
              f"{rtb['ratio_cpu_rtb_over_rapp']:.0f}x CPU, {rtb['ratio_wall_rtb_over_rapp']:.0f}x wall; "
              f"Robot.ik_GN {rtb['ratio_cpu_rtb_robot_over_rapp']:.0f}x CPU (goal 150x CPU); "
              f"over rapp from random starts {rtb['ratio_cpu_rtb_over_rapp_random_starts']:.0f}x CPU")


def summary(run: dict) -> dict:
    return {k: v for k, v in run.items() if k not in ("ok", "err")}


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
    compiled = ik_kernel.loaded(len(targets)) is not None
    runs = rapp_runs(arm, targets)
    naive = naive_run(arm, targets)
    fast = runs["default"]
    rtb = rtb_comparison(arm, targets, fast["cpu_us_per_target"], fast["us_per_target"])
    if rtb is not None:
        rtb["goal_met"] = bool(rtb["ratio_cpu_rtb_over_rapp"] >= 150 and fast["ok"].all()
                               and fast["max_error_m"] <= 1e-9)
        # The iteration alone: rapp from a random start per target, as ik_GN starts.
        rtb["ratio_cpu_rtb_over_rapp_random_starts"] = (
            rtb["variants"][rtb["fastest_variant"]]["cpu_us_per_target"]
            / runs["random_starts"]["cpu_us_per_target"])
    print_table(arm, runs, naive, rtb, compiled)
    result = {
        "benchmark": "ik_numeric vs per-target Newton-Raphson with pinv",
        "arm": list(arm.link_lengths),
        "targets": N_TARGETS,
        "tol_m": TOL,
        "batched": {k: fast[k] for k in ("us_per_target", "success_rate", "max_error_m",
                                         "max_error_ok_m")},
        "naive": {k: naive[k] for k in ("us_per_target", "success_rate", "max_error_m",
                                        "max_error_ok_m")},
        "speedup": naive["us_per_target"] / fast["us_per_target"],
        "compiled": compiled,
        "batched_cpu_us_per_target": fast["cpu_us_per_target"],
        "random_starts": summary(runs["random_starts"]),
        "numpy_path": summary(runs["numpy_path"]),
        "machine": {
            "python": platform.python_version(),
            "numpy": np.__version__,
            "numpy_file": np.__file__,
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "cpus": os.cpu_count(),
            "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        },
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    if rtb is not None:
        result["rtb_ik_GN"] = rtb
    result["analytic_2link"] = analytic_2link()
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
