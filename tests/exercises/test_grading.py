"""``python -m rapp grade``: a fake class with honest, wrong, hostile and broken submissions."""

import csv
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rapp.grading import GradeLimits, grade_submission, parse_weights, read_roster

ROOT = Path(__file__).resolve().parents[2]

GD1 = """
def h(a, b, shape):
    return sum(min(abs(x - y), m - abs(x - y)) for x, y, m in zip(a, b, shape))
"""

# What each kind of student submits, and the verdicts of 5.1, 5.2 and 5.3 it must get.
KINDS = {
    "honest": (GD1 + 'answers = {"5.1": 71, "Exercise 5.2": h, " 5.3 ": 15}\n',
               ["correct", "correct", "correct"]),
    "wrong": ('answers = {"5.1": 70, "5.2": lambda a, b, s: 0, "5.3": 5}\n', ["wrong", "wrong", "wrong"]),
    "partial": ('answers = {"5.1": 71.0}\n', ["correct", "unanswered", "unanswered"]),
    "hangs_running": ("while True:\n    pass\n", ["error", "error", "error"]),
    "hangs_in_h": ('def h(a, b, s):\n    while True:\n        pass\nanswers = {"5.1": 71, "5.2": h, "5.3": 15}\n',
                   ["correct", "wrong", "correct"]),
    "crashes": ('import os\ndef h(a, b, s):\n    os._exit(1)\nanswers = {"5.2": h, "5.3": 15}\n',
                ["unanswered", "wrong", "correct"]),
    "forges": ('import sys, os, json, struct\n'
               'def h(a, b, s):\n'
               '    f = sys._getframe(1)\n'
               '    os.write(f.f_locals["wfd"], struct.pack("<Q", 12) + b\'{"ok": true}\')\n'
               '    os._exit(0)\n'
               'answers = {"5.2": h, "5.1": 71}\n', ["correct", "wrong", "unanswered"]),
    "kills_grader": ('import os, signal\n'
                     'for pid in (os.getppid(), -os.getpgid(os.getppid()), 1):\n'
                     '    try:\n        os.kill(pid, signal.SIGKILL)\n    except OSError:\n        pass\n'
                     'answers = {"5.1": 71}\n', ["correct", "unanswered", "unanswered"]),
    "syntax": ("answers = {\n", ["error", "error", "error"]),
    "exits": ("raise SystemExit(3)\n", ["error", "error", "error"]),
}


def _notebook(source: str) -> str:
    """The same code as a notebook whose check cells were filled in (no dict needed)."""
    cells = [{"cell_type": "markdown", "metadata": {}, "source": ["# Homework"]},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": ["%matplotlib inline\n", "import rapp\n"]},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": [GD1]},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": ['answer = h  # Exercise 5.2\nrapp.exercises.check("5.2", answer)']},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": ['answer = 70\nrapp.exercises.check("5.1", answer)\n1 / 0']},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": ['answer = 71  # fixed\nrapp.exercises.check("Exercise 5.1", answer)']}]
    return json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5})


def _make_class(folder: Path) -> dict[str, list[str]]:
    """30 students: every kind three times, as .py files, plus notebooks and a broken one."""
    expected = {}
    names = list(KINDS)
    for i in range(27):
        kind = names[i % len(names)]
        student = f"s{i:02d}_{kind}"
        (folder / f"{student}.py").write_text(KINDS[kind][0])
        expected[student] = KINDS[kind][1]
    (folder / "s27_notebook.ipynb").write_text(_notebook(""))
    expected["s27_notebook"] = ["correct", "correct", "unanswered"]
    (folder / "s28_not_json.ipynb").write_text("{ not a notebook")
    expected["s28_not_json"] = ["error", "error", "error"]
    (folder / "s29_latin1.py").write_bytes("x = 'caf\xe9'\n".encode("latin-1"))
    expected["s29_latin1"] = ["error", "error", "error"]
    return expected


@pytest.mark.slow
def test_a_class_of_30_is_graded_in_bounded_time(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    expected = _make_class(subs)
    assert len(expected) == 30
    roster = tmp_path / "roster.txt"
    roster.write_text("student\n" + "\n".join(sorted(expected)) + "\nzz_absent\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-m", "rapp", "grade", str(subs), "--exercises", "5.1,5.2:2,5.3",
                          "--roster", str(roster), "--out", str(tmp_path / "grades.csv"),
                          "--feedback", str(tmp_path / "fb"), "--time", "8"],
                         capture_output=True, text=True, timeout=600, env=env, cwd=tmp_path)
    elapsed = time.monotonic() - t0
    assert out.returncode == 0, out.stderr[-2000:]
    rows = list(csv.DictReader((tmp_path / "grades.csv").open()))
    got: dict[str, list[str]] = {}
    for row in rows:
        got.setdefault(row["student"], []).append(row["verdict"])
    assert got.pop("zz_absent") == ["missing"] * 3
    assert got == expected
    points = {r["student"]: sum(float(x["points"]) for x in rows if x["student"] == r["student"]) for r in rows}
    assert points["s00_honest"] == 4 and points["s01_wrong"] == 0
    assert {r["max_points"] for r in rows if r["exercise"] == "5.2"} == {"2"}
    feedback = (tmp_path / "fb" / "s05_crashes.txt").read_text()
    assert "ended" in feedback and "Exercise 5.3 (1/1, correct)" in feedback
    assert "SyntaxError" in (tmp_path / "fb" / "s08_syntax.txt").read_text()
    assert "not a notebook" in (tmp_path / "fb" / "s28_not_json.txt").read_text()
    assert "while running: cell" in (tmp_path / "fb" / "s27_notebook.txt").read_text()
    assert all(len(line) <= 2200 for f in (tmp_path / "fb").iterdir() for line in f.read_text().splitlines())
    print(f"30 students in {elapsed:.1f} s ({elapsed / 30:.2f} s per student)")
    # The limits are CPU time, so a loaded machine stretches the wall clock (about 250 s at a load
    # of 25 on two cores); a hang would hold on to its wall-clock backstops far longer.
    assert elapsed < 600


def test_one_submission_and_the_inputs():
    assert parse_weights("5.1,Exercise 5.2:2") == {"5.1": 1.0, "5.2": 2.0}
    for bad in ("9.9", "5.1:x", "5.1:-1", ""):
        with pytest.raises(ValueError, match="--exercises"):
            parse_weights(bad)


def test_grade_submission_reads_answers_and_is_sandboxed(tmp_path):
    path = tmp_path / "eve.py"
    path.write_text(GD1 + 'import numpy\nnumpy.isclose = lambda *a, **k: True\nanswers = {"5.2": h, "1.4": 5.0}\n')
    r = grade_submission(path, {"5.2": 1.0, "1.4": 1.0}, GradeLimits(run=20))
    assert [(row[0], row[3]) for row in r.rows] == [("5.2", "correct"), ("1.4", "wrong")]


def test_the_cli_names_bad_input_in_one_line(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for args in (["grade", str(tmp_path / "nowhere"), "--exercises", "5.1"],
                 ["grade", str(tmp_path), "--exercises", "77.1"],
                 ["grade", str(tmp_path)]):
        out = subprocess.run([sys.executable, "-m", "rapp", *args], capture_output=True, text=True, env=env)
        assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr
    roster = tmp_path / "r.txt"
    roster.write_text("# class A\nstudent\nann\nben,extra\n")
    assert read_roster(roster) == ["ann", "ben"]
