"""``python -m rapp compare``: resumable after any interruption, parallel, exact intervals.

The slow tests run the command as a user would (a subprocess), interrupt it with Ctrl-C
(SIGINT) and with SIGKILL in the middle of its runs, rerun it with the same ``--out`` and
check that every (scenario, seed, planner) is then in the journal exactly once; the fast
ones check the journal's torn-line handling and the one-line refusals of bad input.
"""

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import mpmath
import pytest

from rapp import compare, compare_command
from rapp.errors import InvalidFormat, InvalidValue
from rapp.journal import Journal, read_journal

from tests.helpers import ROOT, one_line, run

# Two scenarios (2 and 3 links); RRT* spends its 1 s budget on each run, which leaves time to
# interrupt; RRT-Connect and A* are deterministic per seed, so their records must be equal.
SMALL = ["--random", "2", "--seeds", "3", "--planners", "astar_24,rrt_connect,rrt_star"]


def keys(records):
    return [compare.task_key(r) for r in records]


def expected_keys():
    todo = compare.tasks(compare.make_scenarios(2), 3, ["astar_24", "rrt_connect", "rrt_star"])
    return sorted(compare.task_key(t) for t in todo)


# --------------------------------------------------------------------------- the journal


def test_a_torn_last_line_is_dropped_and_cut_before_appending(tmp_path):
    path = tmp_path / "j.jsonl"
    with Journal(path, {"h": 1}) as j:
        j.append({"k": 1})
        j.append({"k": 2})
    whole = path.read_bytes()
    for cut in range(len(whole) - 8, len(whole)):  # a kill at every byte of the last record
        path.write_bytes(whole[:cut])
        assert read_journal(path) == ({"h": 1}, [{"k": 1}])
        with Journal(path, {"h": 1}) as j:
            j.append({"k": 3})
        assert read_journal(path) == ({"h": 1}, [{"k": 1}, {"k": 3}])
        assert path.read_bytes().count(b"\n") == 3


def test_a_damaged_line_inside_or_another_header_is_refused(tmp_path):
    path = tmp_path / "j.jsonl"
    path.write_bytes(b'{"h": 1}\n{"k": \n{"k": 2}\n')
    with pytest.raises(InvalidFormat, match="line 2"):
        read_journal(path)
    path.write_bytes(b'{"h": 1}\n')
    with pytest.raises(InvalidValue, match="--out: .*another run"):
        with Journal(path, {"h": 2}, field="--out"):
            pass


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("argv, field", [
    (["no/such/file.json"], "scenario"),
    (["--planners", "astar,dijkstra"], "--planners"),
    (["--workers", "0"], "--workers"),
    (["--workers", "two"], "--workers"),
    (["--seeds", "0"], "--seeds"),
    (["--random", "3", "default"], "--random"),
    (["--out", str(ROOT / "rapp" / "recorded" / "x.jsonl")], "--out"),
    (["--out", "/no/such/folder/x.jsonl"], "--out"),
])
def test_bad_input_is_one_line_naming_the_field(capsys, tmp_path, argv, field):
    if "--out" not in argv:
        argv = argv + ["--out", str(tmp_path / "r.jsonl")]
    code, out, err = run(capsys, "compare", *argv)
    assert code == 2 and field in one_line(err), err
    assert not (tmp_path / "r.jsonl").exists()


def test_without_dask_the_scheduler_option_names_the_extra(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails as if absent
    code, out, err = run(capsys, "compare", *SMALL, "--scheduler", "local",
                         "--out", str(tmp_path / "r.jsonl"))
    assert code == 2 and "--scheduler" in one_line(err) and "rapp[dask]" in err


def test_the_default_output_is_outside_the_package():
    assert not os.path.isabs(compare_command.DEFAULT_OUT)
    assert compare_command.DEFAULT_OUT.endswith(".jsonl")


# --------------------------------------------------------------------------- whole runs


def command(*argv, cwd):
    return [sys.executable, "-m", "rapp", "compare", *argv]


def records_in(path):
    return read_journal(path)[1] if Path(path).exists() else []


def interrupt_then_finish(tmp_path, how, workers):
    out = tmp_path / f"{how}.jsonl"
    argv = command(*SMALL, "--workers", str(workers), "--out", str(out), cwd=tmp_path)
    proc = subprocess.Popen(argv, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    deadline = time.monotonic() + 240
    while len(records_in(out)) < 5 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert proc.poll() is None, "finished before it could be interrupted"
    if how == "SIGINT":
        proc.send_signal(signal.SIGINT)
    else:
        os.killpg(proc.pid, signal.SIGKILL)  # the process and its workers, mid-run
    _, err = proc.communicate(timeout=60)
    if how == "SIGINT":
        assert proc.returncode == 130 and err.strip().splitlines()[-1] == "rapp: interrupted", err
        assert "Traceback" not in err
    part = records_in(out)
    assert 5 <= len(part) < len(expected_keys())
    again = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    assert f"({len(expected_keys()) - len(part)} new)" in again.stdout
    return read_journal(out)[1], part


@pytest.mark.slow
@pytest.mark.parametrize("how, workers", [("SIGINT", 1), ("SIGKILL", 1), ("SIGINT", 2)])
def test_an_interrupted_run_rerun_has_every_run_exactly_once(tmp_path, how, workers):
    records, part = interrupt_then_finish(tmp_path, how, workers)
    assert sorted(keys(records)) == expected_keys()  # every run, none twice
    assert records[:len(part)] == part                # what was done is kept as it was
    # The deterministic planners give what an uninterrupted run gives, record for record.
    whole = tmp_path / "whole.jsonl"
    subprocess.run(command(*SMALL, "--workers", "1", "--out", str(whole), cwd=tmp_path),
                   cwd=tmp_path, check=True, capture_output=True, timeout=600)
    same = {"scenario_index", "planner", "seed", "success", "length_rad", "shortcut_length_rad"}
    pick = lambda rs: sorted((tuple(r[k] for k in sorted(same)) for r in rs  # noqa: E731
                              if r["planner"] != "rrt_star"), key=str)
    assert pick(records) == pick(records_in(whole))


@pytest.mark.slow
def test_it_runs_on_a_local_dask_cluster_and_its_intervals_are_students(tmp_path):
    pytest.importorskip("dask.distributed")
    summary = tmp_path / "summary.json"
    r = subprocess.run(command(*SMALL, "--scheduler", "local", "--workers", "2",
                               "--out", str(tmp_path / "r.jsonl"), "--summary", str(summary),
                               cwd=tmp_path), cwd=tmp_path, capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    result = json.loads(summary.read_text())
    assert sorted(keys(result["records"])) == expected_keys()
    checked = 0
    for planner, by_class in result["summary"].items():
        times = [x["time_s"] for x in result["records"] if x["planner"] == planner and x["success"]]
        m = by_class["all"]["time_s"]
        if len(times) < 2:
            continue
        # Student's t from mpmath at 50 digits, not from rapp.
        mpmath.mp.dps = 50
        df = len(times) - 1
        t = mpmath.findroot(lambda x: mpmath.betainc(df / mpmath.mpf(2), 0.5, 0, df / (df + x * x),
                                                     regularized=True) / 2 - mpmath.mpf("0.025"), 2.5)
        mean = sum(times) / len(times)
        sd = math.sqrt(sum((x - mean) ** 2 for x in times) / df)
        half = float(t) * sd / math.sqrt(len(times))
        assert m["low"] == pytest.approx(mean - half, abs=1e-6) and m["high"] == pytest.approx(
            mean + half, abs=1e-6)
        checked += 1
    assert checked >= 2


def test_intervals_use_the_exact_t_quantile_for_every_size():
    for n in (2, 3, 11, 14, 22, 34, 300):
        values = [math.sin(k) for k in range(n)]
        m = compare.mean_interval(values)
        mpmath.mp.dps = 50
        df = n - 1
        t = mpmath.findroot(lambda x: mpmath.betainc(df / mpmath.mpf(2), 0.5, 0, df / (df + x * x),
                                                     regularized=True) / 2 - mpmath.mpf("0.025"),
                            2.0 if n > 3 else 5.0)
        mean = sum(values) / n
        sd = math.sqrt(sum((x - mean) ** 2 for x in values) / df)
        assert m["high"] - m["mean"] == pytest.approx(float(t) * sd / math.sqrt(n), rel=1e-9)


@pytest.mark.slow
def test_the_users_scenario_files_and_embedded_names(capsys, tmp_path):
    mine = tmp_path / "mine.json"
    mine.write_text(json.dumps({"arm": {"link_lengths": [1, 1]}, "start": [0, 0],
                                "goal": {"joints": [90, 45]}, "units": {"angle": "deg"}}))
    out = tmp_path / "r.jsonl"
    code, text, err = run(capsys, "compare", str(mine), "rectangles", "--planners", "astar_24,rrt_connect",
                          "--seeds", "2", "--workers", "1", "--out", str(out), "-q")
    assert code == 0, err
    header, records = read_journal(out)
    assert [s.get("units", {}).get("angle") for s in header["scenarios"]][0] == "deg"  # as written
    # Both are 2-link arms: A* at 24 cells once, RRT-Connect with seeds 0 and 1.
    assert sorted(keys(records)) == [(i, p, k) for i in (0, 1) for p, k in
                                     (("astar_24", 0), ("rrt_connect", 0), ("rrt_connect", 1))]
    assert all(r["success"] for r in records if r["scenario_index"] == 0)
    assert "6 runs (6 new) on 2 scenarios" in text
