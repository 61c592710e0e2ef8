"""A checker that cannot be fooled or hung: each hostile submission of issue 25 is a test.

The reader's object runs in a child process (own process group, CPU, memory and wall limits,
seccomp on Linux x86-64); only plain data comes back, and the verdict is computed here.
"""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from rapp.exercises import check, grade
from rapp.exercises.sandbox import Limits, Opaque, Sandbox, from_plain, to_plain

ROOT = Path(__file__).resolve().parents[2]


def _gd1(a, b, shape):
    return sum(min(abs(x - y), m - abs(x - y)) for x, y, m in zip(a, b, shape))


def test_plain_data_round_trips_and_nothing_else_does():
    import rapp

    value = (1, [2.5, np.int64(3), None, "s"], np.arange(4.0).reshape(2, 2), {"k": (True,)},
             rapp.Circle((1, 2), 0.5), rapp.Arm([1.0, 1.0], [None, (-1, 1)]), float("inf"))
    back = from_plain(to_plain(value))
    assert back[0] == 1 and back[1][:2] == [2.5, 3] and type(back[1][1]) is np.int64
    assert np.array_equal(back[2], value[2]) and back[3] == {"k": (True,)} and back[4] == value[4]
    assert back[5].link_lengths == value[5].link_lengths and back[6] == float("inf")
    assert isinstance(from_plain(to_plain(object())), Opaque)
    scenario = rapp.load_scenario("default")
    assert from_plain(to_plain(scenario)).to_dict() == scenario.to_dict()
    with pytest.raises(ValueError):
        from_plain({"$": "pickle", "v": "..."})


def test_reading_the_reference_from_the_callers_frame_is_refused():
    def peeks(a, b, shape):
        import sys as _sys

        frame = _sys._getframe(1)
        while frame is not None:
            for name in ("reference", "want", "expected"):
                if name in frame.f_locals and callable(frame.f_locals[name]):
                    return frame.f_locals[name](a, b, shape)
            frame = frame.f_back
        raise LookupError("no reference in reach")

    verdict = check("5.2", peeks)
    assert not verdict and "LookupError" in verdict.message
    assert not check("13.3", lambda L1, L2, x, y: _getframe_reference(L1, L2, x, y))


def _getframe_reference(*args):
    frame = sys._getframe(2)
    return frame.f_locals["reference"](*args)


def test_forging_the_report_and_exiting_is_refused():
    def forges(a, b, shape):
        import json
        import struct

        frame = sys._getframe(1)
        while frame is not None and "wfd" not in frame.f_locals:
            frame = frame.f_back
        if frame is not None:  # a reply claiming every answer is right, then quietly gone
            payload = json.dumps({"ok": "correct"}).encode()
            os.write(frame.f_locals["wfd"], struct.pack("<Q", len(payload)) + payload)
        report = sys._getframe(1).f_locals.get("report")
        if report:
            report(("ok",))
        os._exit(0)

    verdict = check("5.2", forges)
    assert not verdict
    assert not check("5.4", forges)


def test_patching_numpy_or_rapp_in_the_child_changes_nothing_here():
    def patches(a, b, shape):
        import numpy
        import rapp.search

        numpy.isclose = numpy.allclose = lambda *args, **kw: True
        numpy.array_equal = lambda *args, **kw: True
        numpy.abs = lambda x: 0 * x
        rapp.search.toroidal_manhattan = lambda *args: -1
        return -1

    assert not check("5.2", patches)
    assert not check("3.2", patches)

    class PatchesOnConversion:
        def __array__(self, dtype=None, copy=None):
            np.abs = lambda x: 0 * x
            np.isclose = lambda *args, **kw: True
            return np.array(5.0)

    assert not check("1.4", PatchesOnConversion())
    assert np.abs(-2.0) == 2.0 and not np.isclose(1.0, 2.0)
    assert not check("1.4", 5.0) and check("1.4", 0.2832)  # later answers are judged as before


def test_mutating_the_inputs_cannot_change_what_the_reference_sees():
    from rapp.exercises.ch14 import _choose_parent_ref

    def clears(arm, near, costs, q_new, obstacles):
        obstacles.clear()  # the old checker passed the same list to the reference next
        return _choose_parent_ref(arm, near, costs, q_new, [])

    verdict = check("14.2", clears)
    assert not verdict, verdict.message


@pytest.mark.slow
@pytest.mark.parametrize("method", ["__array__", "__float__"])
def test_a_numeric_answer_that_loops_is_stopped(method):
    def spin(self, *args, **kw):
        while True:
            pass

    answer = type("Loops", (), {method: spin})()
    t0 = time.monotonic()
    verdict = check("1.4", answer)
    assert not verdict and "did not finish" in verdict.message
    assert time.monotonic() - t0 < 15


def test_messages_are_bounded():
    def shouts(*args):
        raise ValueError("x" * 50_000_000)

    for ex_id in ("5.2", "5.4"):
        verdict = check(ex_id, shouts)
        assert not verdict and "ValueError" in verdict.message and len(verdict.message) <= 2000

    class LongRepr:
        def __repr__(self):
            return "y" * 10_000_000

    assert len(check("1.4", LongRepr()).message) <= 2000


def test_memory_hogs_and_exits_are_verdicts():
    def hog(*args):
        return bytearray(64 * 2**30)

    def exits(*args):
        raise SystemExit(0)

    assert "MemoryError" in check("5.2", hog).message
    assert not check("5.2", exits) and not check("5.4", exits)


@pytest.mark.slow
def test_the_5_4_second_pass_runs_in_the_sandbox_too():
    calls = {"n": 0}

    def changes_its_mind(a, b, shape):
        calls["n"] += 1  # the child's copy counts; the first pass makes 108 calls
        if calls["n"] > 108:
            while True:
                pass
        return 0

    t0 = time.monotonic()
    verdict = check("5.4", changes_its_mind)
    assert not verdict and "did not finish" in verdict.message
    assert time.monotonic() - t0 < 20
    assert calls["n"] == 0  # the reader's function never ran in this process


@pytest.mark.slow
def test_grandchildren_die_with_the_child(tmp_path):
    marker = tmp_path / "pids"

    def forks(a, b, shape):
        pid = os.fork()
        if pid == 0:
            try:
                os.setsid()  # refused: it stays in the group that is killed
            except OSError:
                pass
            with open(marker, "a") as f:
                f.write(f"{os.getpid()}\n")
            time.sleep(60)
            os._exit(0)
        while True:
            pass

    verdict = check("5.2", forks)
    assert not verdict
    time.sleep(0.5)
    pids = [int(p) for p in marker.read_text().split()] if marker.exists() else []
    assert pids, "the grandchild never ran"
    for pid in pids:
        assert not _alive(pid), f"grandchild {pid} outlived check()"


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def test_a_submission_cannot_kill_the_grader():
    script = textwrap.dedent("""
        import os, signal
        from rapp.exercises import check, grade

        def kills(*args):
            for target in (os.getppid(), -os.getpgid(os.getppid())):
                try:
                    os.kill(target, signal.SIGKILL)
                except OSError:
                    pass
            return 0

        print(bool(check("5.2", kills)), "|", check("5.2", kills).message[:60])
        print(len(grade({"5.1": 71, "5.2": kills}, ["5.1", "5.2"])))
        print("grader alive")
    """)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().endswith("grader alive") and out.stdout.startswith("False")


def test_check_and_grade_never_raise_on_hostile_mappings():
    class Hostile(dict):
        def items(self):
            raise KeyboardInterrupt

        def keys(self):
            raise SystemExit

    assert not grade(Hostile())[0]
    assert len(grade(Hostile(), ["5.1"])) == 1


def test_the_sandbox_limits_a_direct_call():
    with Sandbox.of({"f": lambda: [1] * 10}, Limits(wall=5)) as box:
        assert box.call("f", ()) == [1] * 10
    with Sandbox.of({"f": lambda: os.kill(os.getppid(), signal.SIGTERM)}, Limits(wall=5)) as box:
        with pytest.raises(Exception, match="PermissionError"):
            box.call("f", ())
