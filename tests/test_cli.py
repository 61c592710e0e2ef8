"""The command line: exit codes 0 / 1 / 2 / 130, exactly one stderr line naming the field
for bad input, never a traceback; results round-trip. Most tests call main(argv) in
process; a few run ``python -m rapp`` to check the real entry point."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from tests.helpers import one_line, run, write
from rapp.results import load_result
from rapp.scenario import list_scenarios, load_scenario

GOOD = {"arm": {"link_lengths": [1.0, 1.0]},
        "obstacles": [{"type": "circle", "center": [1.75, 0.75], "radius": 0.4}],
        "start": [0.0, 0.0], "goal": {"joints": [2.0, 0.5]},
        "planner": {"cells": 40}, "trajectory": {"samples": 40}}


def test_list_and_check_every_embedded(capsys):
    code, listing, err = run(capsys, "list")
    assert code == 0 and err == ""
    for name in list_scenarios():
        assert name in listing
        code, out, err = run(capsys, "check", name)
        assert code == 0 and out.rstrip().endswith("scenario is valid") and err == ""


@pytest.mark.parametrize("name", [n for n in list_scenarios() if n != "no_solution"])
def test_plan_every_embedded_scenario(capsys, name):
    code, out, err = run(capsys, "plan", name)
    assert code == 0, err
    assert "verification: passed" in out and out.rstrip().endswith("verified")


def test_no_solution_is_exit_1_in_one_plain_line(capsys):
    code, out, err = run(capsys, "plan", "no_solution")
    assert code == 1
    assert one_line(err).startswith("rapp: no path:")


def test_no_ik_solution_is_exit_1(capsys, tmp_path):
    # Reachable by the free arm, but not within these joint limits.
    bad = {**GOOD, "arm": {"link_lengths": [1.0, 1.0], "joint_limits": [[-0.1, 0.1], [-0.1, 0.1]]},
           "start": [0.0, 0.0], "goal": {"position": [0.0, 1.5]}, "obstacles": []}
    code, out, err = run(capsys, "plan", write(tmp_path, bad))
    assert code == 1 and one_line(err).startswith("rapp: no IK solution (joint limits)")


BAD = [
    # (file content, field named in the message)
    ("", "scenario"),
    (b"\x89PNG\r\n\x1a\n\x00\x00garbage\xff", "scenario"),
    (json.dumps(GOOD)[:40], "scenario"),
    ("[" * 100_000 + "]" * 100_000, "scenario"),
    (json.dumps(GOOD).replace("0.4", "NaN"), "obstacles[0].radius"),
    (json.dumps(GOOD).replace("0.4", "Infinity"), "obstacles[0].radius"),
    ({**GOOD, "arm": {"link_lengths": [1.0, -1.0]}}, "arm.link_lengths[1]"),
    ({**GOOD, "arm": {"link_lengths": [1.0, 0]}}, "arm.link_lengths[1]"),
    ({**GOOD, "arm": {"link_lengths": [1.0, "1"]}}, "arm.link_lengths[1]"),
    ({**GOOD, "arm": {"link_lengths": [1.0, 1.0, 1.0]}}, "start"),
    ({**GOOD, "obstacles": [{"type": "circle", "center": [2, 2], "radius": 0}]},
     "obstacles[0].radius"),
    ({**GOOD, "start": [0.0]}, "start"),
    ({**GOOD, "goal": {"joints": [0.0, 0.0, 1.0]}}, "goal.joints"),
    ({**GOOD, "goal": {"position": [5.0, 0.0]}}, "goal.position"),
    ({**GOOD, "planner": {"cells": 100_000}}, "planner.cells"),
    ({**GOOD, "planner": {"cels": 10}}, "planner.cels"),
    ({**GOOD, "trajectory": {"duration": -1}}, "trajectory.duration"),
    ({k: v for k, v in GOOD.items() if k != "goal"}, "goal"),
    ({**GOOD, "start": [0.405, 0.0]}, "start"),  # in collision with the disc
]


@pytest.mark.parametrize("content,field", BAD, ids=[f"{i}-{b[1]}" for i, b in enumerate(BAD)])
@pytest.mark.parametrize("command", ["plan", "check"])
def test_bad_input_is_exit_2_with_one_line_naming_the_field(capsys, tmp_path, content, field,
                                                             command):
    code, out, err = run(capsys, command, write(tmp_path, content))
    assert code == 2
    line = one_line(err)
    assert line.startswith(f"rapp: error: {field}:"), line


@pytest.mark.parametrize("argv,needle", [
    (["plan", "--bogus"], "unrecognized arguments"),
    ([], "required"),
    (["fly"], "invalid choice"),
    (["check"], "required"),
    (["plan", "does_not_exist.json"], "scenario: no such file"),
    (["plan", "."], "directory"),
    (["plan", "default", "--out", "/no/such/folder/r.json"], "--out"),
    (["plan", "default", "--out", "."], "--out"),
    (["plan", "default", "--plot", "/no/such/folder/f.png"], "--plot"),
])
def test_usage_errors_are_exit_2_in_one_line(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert needle in one_line(err)


def test_help_is_exit_0(capsys):
    for argv in (["--help"], ["plan", "--help"], ["check", "--help"], ["list", "--help"]):
        code, out, err = run(capsys, *argv)
        assert code == 0 and "usage:" in out


def test_keyboard_interrupt_is_130(capsys, monkeypatch):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr("rapp.planner.plan", interrupted)
    code, out, err = run(capsys, "plan", "default")
    assert code == 130 and one_line(err) == "rapp: interrupted"


def test_out_round_trips_and_keeps_the_old_result_on_a_crash(capsys, tmp_path, monkeypatch):
    out_path = tmp_path / "r.json"
    code, out, err = run(capsys, "plan", "srs_typical", "--out", str(out_path), "-q")
    assert code == 0
    back = load_result(out_path)
    assert back.report.ok and back.scenario.name == "srs_typical"
    d = json.loads(out_path.read_text())
    assert {"t", "q", "xy", "report", "metrics", "echo", "scenario"} <= set(d)
    assert np.allclose(np.array(d["xy"]), back.scenario.arm.end_effector(np.array(d["q"])),
                       atol=1e-12)
    before = out_path.read_bytes()

    def crash(*a, **k):
        raise RuntimeError("simulated crash while writing")

    monkeypatch.setattr("rapp.results.json.dumps", crash)
    code, out, err = run(capsys, "plan", "default", "--out", str(out_path), "-q")
    assert code == 3 and "internal error" in one_line(err)
    assert out_path.read_bytes() == before


@pytest.mark.slow
def test_plot_and_animate(capsys, tmp_path, monkeypatch):
    import rapp.plotting as plotting

    full = plotting.animate  # a GIF of every frame takes long; the wiring is what is tested here
    monkeypatch.setattr(plotting, "animate", lambda *a, **k: full(*a, **{**k, "max_frames": 3}))
    fig, gif = tmp_path / "f.png", tmp_path / "a.gif"
    code, out, err = run(capsys, "plan", "srs_typical", "--plot", str(fig), "--animate",
                         str(gif), "-q")
    assert code == 0, err
    assert fig.read_bytes()[:4] == b"\x89PNG" and gif.read_bytes()[:6] == b"GIF89a"


def subprocess_run(*argv, cwd):
    return subprocess.run([sys.executable, "-m", "rapp", *argv], capture_output=True, text=True,
                          timeout=120, cwd=cwd, env={**os.environ, "MPLBACKEND": "Agg"})


def test_real_entry_point(tmp_path):
    r = subprocess_run("plan", "-q", cwd=tmp_path)  # no file: the embedded default
    assert r.returncode == 0 and r.stdout.rstrip().endswith("verified") and r.stderr == ""
    r = subprocess_run("plan", "no_solution", "-q", cwd=tmp_path)
    assert r.returncode == 1 and len(r.stderr.splitlines()) == 1
    deep = tmp_path / "deep.json"
    deep.write_text("{" * 50_000)
    r = subprocess_run("check", str(deep), cwd=tmp_path)
    assert r.returncode == 2 and len(r.stderr.splitlines()) == 1 and "Traceback" not in r.stderr


def test_a_stop_by_the_time_budget_says_so_and_names_it(capsys, tmp_path):
    # Issue 31: a run its budget stopped said "joined no goal in 0 iterations".
    s = load_scenario("no_solution").to_dict()
    s["planner"] = {"algorithm": "rrt_connect", "time_budget": 0.05, "max_iterations": 10**7}
    code, _, err = run(capsys, "plan", write(tmp_path, s), "-q")
    line = one_line(err)
    assert code == 1 and "RRT-Connect stopped: time_budget 0.05 s spent after" in line, line
    assert line.endswith("no goal joined")
