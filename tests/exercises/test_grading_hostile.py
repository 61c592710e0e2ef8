"""A class with hostile submissions and hostile grader inputs (issue 32).

Each hostile submission tries to reach what isolation must keep from it: the key, classmates'
files, earlier feedback, the rapp package, the grader's process and the network. It reports
success the only way it can, by answering 1.1 right when an attack worked and wrong when
every attempt failed (1.1 has no per-student numbers, so the key changes nothing there); the test then checks the files themselves too.
"""

import csv
import hashlib
import io
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

import rapp
from rapp import cli
from rapp.grading import GradeLimits, grade_submission, isolation_available

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = Path(rapp.__file__).resolve().parent

needs_bwrap = pytest.mark.skipif(isolation_available() is None, reason="bubblewrap cannot isolate here")

GD1 = """
def h(a, b, shape):
    return sum(min(abs(x - y), m - abs(x - y)) for x, y, m in zip(a, b, shape))
"""
HONEST = GD1 + 'answers = {"1.1": [1.5708, 0, 0], "5.2": h}\n'

# Every attack sets ok = True when it worked; the answer to 1.1 says so.
ATTACKS = {
    "reads_key": """
import os, glob
ok = False
for path in [KEY] + glob.glob("/proc/*/cwd/key.txt"):
    try:
        open(path).read(); ok = True
    except OSError:
        pass
for pid in os.listdir("/proc"):
    if pid.isdigit():
        try:
            if b"--key" in open(f"/proc/{pid}/cmdline", "rb").read():
                ok = True
        except OSError:
            pass
""",
    "reads_grader_memory": """
import os, re
ok = False
for pid in {os.getppid(), *[int(p) for p in os.listdir("/proc") if p.isdigit()]} - {os.getpid()}:
    try:  # every process in sight but itself (its own source holds KEY_TEXT, for the test's sake)
        maps = open(f"/proc/{pid}/maps").read()
        with open(f"/proc/{pid}/mem", "rb") as mem:
            for line in maps.splitlines():
                if "[heap]" in line:
                    lo, hi = (int(x, 16) for x in line.split()[0].split("-"))
                    mem.seek(lo)
                    if KEY_TEXT.encode() in mem.read(hi - lo):
                        ok = True
    except (OSError, ValueError, OverflowError):
        pass
""",
    "overwrites_classmate": """
ok = False
for path in (VICTIM, FEEDBACK_OF_FIRST, ROSTER):
    try:
        with open(path, "a") as f:
            f.write("\\nanswers = {}\\n")
        ok = True
    except OSError:
        pass
""",
    "plants_in_package": """
import os, rapp
ok = False
for folder in {os.path.dirname(rapp.__file__), PACKAGE}:
    try:
        open(os.path.join(folder, "planted.py"), "w").write("x = 1")
        ok = True
    except OSError:
        pass
    try:
        with open(os.path.join(folder, "grading.py"), "a") as f:
            f.write("\\n# planted\\n")
        ok = True
    except OSError:
        pass
""",
    "cripples_grader": """
import os, resource, signal
ok = False
for pid in {os.getppid(), 1, *[int(p) for p in os.listdir("/proc") if p.isdigit()]}:
    if pid == os.getpid():
        continue
    try:
        resource.prlimit(pid, resource.RLIMIT_NOFILE, (8, 8))
        ok = ok or pid == os.getppid() and pid != 1
    except (OSError, ValueError):
        pass
try:
    os.kill(-1, signal.SIGSTOP)
except OSError:
    pass
""",
    "uses_network": """
import socket
ok = False
for host in (("1.1.1.1", 53), ("127.0.0.1", 22)):
    try:
        socket.create_connection(host, timeout=1).close(); ok = True
    except OSError:
        pass
""",
    "runs_as_root": """
import os
ok = os.getuid() == 0 or os.geteuid() == 0
""",
}


def _attack(kind: str, paths: dict) -> str:
    consts = "".join(f"{k} = {v!r}\n" for k, v in paths.items())
    return consts + ATTACKS[kind] + GD1 + 'answers = {"1.1": [1.5708 if ok else 0, 0, 0], "5.2": h}\n'


def _tree_digest(folder: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(folder.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(folder)).encode() + path.read_bytes())
        elif path.is_dir() and "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(folder)).encode())
    return digest.hexdigest()


def _sandboxes_left() -> list[int]:
    """Processes still running a submission as user 65534 (a forked child of one included), after
    a few seconds for the kernel to end what a closed sandbox held."""
    for _ in range(50):
        left = []
        for pid in filter(str.isdigit, os.listdir("/proc")):
            try:
                if os.stat(f"/proc/{pid}").st_uid == 65534 and \
                        b"serve_submission" in Path(f"/proc/{pid}/cmdline").read_bytes():
                    left.append(int(pid))
            except OSError:
                pass
        if not left:
            return left
        time.sleep(0.1)
    return left


def _grade(*args) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    old = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = out, err
    try:
        code = cli.main(["grade", *map(str, args)])
    finally:
        sys.stdout, sys.stderr = old
    return code, out.getvalue(), err.getvalue()


@needs_bwrap
@pytest.mark.slow
def test_hostile_submissions_leave_the_key_classmates_package_and_later_students_untouched(tmp_path):
    subs, fb = tmp_path / "subs", tmp_path / "fb"
    subs.mkdir()
    key = tmp_path / "key.txt"
    key.write_text("k" * 8 + "0123456789abcdef0123456789abcdef\n")
    key.chmod(0o600)
    roster = tmp_path / "roster.txt"
    paths = {"KEY": str(key), "KEY_TEXT": key.read_text().strip(), "VICTIM": str(subs / "zz_victim.py"),
             "FEEDBACK_OF_FIRST": str(fb / "a_honest.txt"), "ROSTER": str(roster), "PACKAGE": str(PACKAGE)}
    (subs / "a_honest.py").write_text(HONEST)
    for kind in ATTACKS:
        (subs / f"m_{kind}.py").write_text(_attack(kind, paths))
    (subs / "m_shouts.py").write_text(GD1 + "def bad(*a):\n    raise ValueError('SECRET-MARKER ' * 50)\n"
                                      'answers = {"1.1": "SECRET-MARKER", "5.2": bad}\nraise KeyError("SECRET-MARKER")\n')
    (subs / "m_delegates.py").write_text('import rapp\nfrom rapp.search import toroidal_manhattan as t\n'
                                         'answers = {"1.1": [1.5708, 0, 0], "5.2": t}\n')
    (subs / "m_delegates_wrapped.py").write_text('from rapp import search\nseen = []\n'
                                                 'def h(a, b, shape):\n    seen.append((a, b, shape))\n'
                                                 '    return search.toroidal_manhattan(a, b, shape)\n'
                                                 'answers = {"1.1": [1.5708, 0, 0], "5.2": h}\n')
    (subs / "m_forks.py").write_text("import os, time\nfor _ in range(10000):\n    try:\n"
                                     "        if os.fork() == 0:\n            time.sleep(10**6)\n"
                                     "    except OSError:\n        break\n" + HONEST)
    (subs / "m_fills_disk.py").write_text("for i in range(8):\n    try:\n"
                                          "        open(f'/tmp/big{i}', 'wb').write(b'0' * 2**27)\n"
                                          "    except OSError:\n        pass\n" + HONEST)
    (subs / "zz_victim.py").write_text(HONEST)
    victim_before = (subs / "zz_victim.py").read_bytes()
    students = sorted(p.stem for p in subs.iterdir())
    roster.write_text("\n".join(students) + "\n")
    roster_before, package_before = roster.read_bytes(), _tree_digest(PACKAGE)

    code, out, err = _grade(subs, "--exercises", "1.1,5.2:2", "--roster", roster, "--key", key,
                            "--out", tmp_path / "grades.csv", "--feedback", fb, "--time", "20")
    assert code == 0, err
    assert not _sandboxes_left(), "a submission's processes outlived its grading"
    rows = list(csv.DictReader((tmp_path / "grades.csv").open()))
    verdicts = {(r["student"], r["exercise"]): r["verdict"] for r in rows}
    assert {r["student"] for r in rows} == set(students)
    for kind in ATTACKS:  # every attack failed, and the honest function that follows it still counts
        assert verdicts[(f"m_{kind}", "1.1")] == "wrong", kind
        assert verdicts[(f"m_{kind}", "5.2")] == "correct", kind
    for student in ("a_honest", "zz_victim", "m_forks", "m_fills_disk"):
        assert verdicts[(student, "1.1")] == verdicts[(student, "5.2")] == "correct", student
    assert verdicts[("m_delegates", "5.2")] == verdicts[("m_delegates_wrapped", "5.2")] == "wrong"
    assert "delegates to rapp" in (fb / "m_delegates_wrapped.txt").read_text()
    # untouched: the key, a classmate's file, earlier feedback, the roster, the package
    assert key.read_text().strip() == paths["KEY_TEXT"] and stat.S_IMODE(key.stat().st_mode) == 0o600
    assert (subs / "zz_victim.py").read_bytes() == victim_before and roster.read_bytes() == roster_before
    assert "answers = {}" not in (fb / "a_honest.txt").read_text()
    assert _tree_digest(PACKAGE) == package_before
    # no text a submission wrote reaches the feedback; the outputs have the usual mode
    texts = "".join(p.read_text() for p in fb.iterdir())
    assert "SECRET-MARKER" not in texts and paths["KEY_TEXT"] not in texts
    assert "KeyError" in (fb / "m_shouts.txt").read_text()
    umask = os.umask(0)
    os.umask(umask)
    for path in [tmp_path / "grades.csv", *fb.iterdir()]:
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask, path


@needs_bwrap
def test_show_errors_gives_the_full_message_and_none_is_no_answer(tmp_path):
    path = tmp_path / "sam.py"
    path.write_text('answers = {"5.1": None, "5.3": 15}\nraise KeyError("the-message")\n')
    hidden = grade_submission(path, {"5.1": 1.0, "5.3": 1.0}, GradeLimits(run=20))
    shown = grade_submission(path, {"5.1": 1.0, "5.3": 1.0}, GradeLimits(run=20, show_errors=True))
    assert "the-message" in str(shown.notes) and "the-message" not in str(hidden.notes)
    assert "KeyError" in str(hidden.notes)
    assert [r[3] for r in hidden.rows] == ["unanswered", "correct"]  # None is no answer, as check says


def test_grade_submission_never_raises_on_bad_input(tmp_path):
    for path, weights in ((tmp_path / "none.py", {"5.1": 1.0}), (tmp_path, {"5.1": 1.0}),
                          (tmp_path / "x.py", {"99.9": 1.0}), (tmp_path / "x.py", None),
                          ("\x00", {"5.1": 1.0}), (tmp_path / "x.py", {"5.1": "heavy"})):
        (tmp_path / "x.py").write_text("answers = {}")
        r = grade_submission(path, weights, GradeLimits(isolate=False))
        assert all(row[3] in ("error", "unanswered") for row in r.rows), (path, weights, r)
    r = grade_submission(tmp_path / "x.py", {"5.1": 1.0}, GradeLimits(run=1e308, isolate=False))
    assert [row[3] for row in r.rows] == ["error"]


@pytest.mark.parametrize("line", ["../notes", "/etc/passwd", "a/b", "..", ".hidden", "x" * 10**6,
                                  "nul\x00here", "tab\tname"])
def test_a_bad_roster_line_is_one_line_naming_it_and_nothing_is_written(tmp_path, line):
    (tmp_path / "subs").mkdir()
    roster = tmp_path / "roster.txt"
    roster.write_text("alice\n" + line + "\n")
    code, out, err = _grade(tmp_path / "subs", "--exercises", "5.1", "--roster", roster,
                            "--out", tmp_path / "g.csv", "--feedback", tmp_path / "fb", "--no-isolation")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--roster line 2" in err, err
    assert not (tmp_path / "g.csv").exists() and not (tmp_path / "fb").exists()
    code = cli.main(["assign", "--key", str(tmp_path / "k"), "--roster", str(roster), "--exercises", "1.3",
                     "--out", str(tmp_path / "sheets")])
    assert code == 2 and not (tmp_path / "sheets").exists() and not (tmp_path / "k").exists()


def test_a_duplicated_or_fifo_roster_is_refused(tmp_path):
    (tmp_path / "subs").mkdir()
    roster = tmp_path / "roster.txt"
    roster.write_text("alice\nbob\nalice\n")
    code, _, err = _grade(tmp_path / "subs", "--exercises", "5.1", "--roster", roster, "--no-isolation",
                          "--out", tmp_path / "g.csv")
    assert code == 2 and "line 3" in err and "line 1" in err
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    code, _, err = _grade(tmp_path / "subs", "--exercises", "5.1", "--roster", fifo, "--no-isolation",
                          "--out", tmp_path / "g.csv")
    assert code == 2 and "not a regular file" in err and time.monotonic() - t0 < 30


def test_outputs_that_are_inputs_fifos_or_devices_are_refused_before_grading(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "alice.py").write_text("answers = {}")
    roster, key, fifo = tmp_path / "roster.txt", tmp_path / "key.txt", tmp_path / "fifo"
    roster.write_text("alice\n")
    key.write_text("0123456789abcdef0123\n")
    os.mkfifo(fifo)
    before = {p: p.read_bytes() for p in (roster, key, subs / "alice.py")}
    for out in (roster, key, subs / "alice.py", fifo, "/dev/full", "/dev/null", tmp_path, subs / "new.py"):
        code, _, err = _grade(subs, "--exercises", "5.1", "--roster", roster, "--key", key, "--out", out,
                              "--feedback", tmp_path / "fb", "--no-isolation")
        assert code == 2 and len(err.strip().splitlines()) == 1 and "--out" in err, (out, err)
    for feedback in (subs, key, fifo):
        code, _, err = _grade(subs, "--exercises", "5.1", "--roster", roster, "--out", tmp_path / "g.csv",
                              "--feedback", feedback, "--no-isolation")
        assert code == 2 and "--feedback" in err, (feedback, err)
    assert {p: p.read_bytes() for p in before} == before
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode) and not (tmp_path / "g.csv").exists()


@pytest.mark.parametrize("option", [["--time", "1e308"], ["--time", "nan"], ["--time", "0"], ["--time", "-1"],
                                    ["--memory", "0"], ["--memory", "10000000"]])
def test_limits_out_of_range_are_refused(tmp_path, option):
    code, _, err = _grade(tmp_path, "--exercises", "5.1", *option, "--no-isolation")
    assert code == 2 and option[0] in err and len(err.strip().splitlines()) == 1


@needs_bwrap
@pytest.mark.slow
def test_odd_file_names_are_graded_or_reported_per_student(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    good = 'answers = {"5.1": 71}\n'
    (subs / "bom.py").write_bytes(b"\xef\xbb\xbf" + good.encode())
    (subs / "UPPER.PY").write_text(good)
    (subs / ".hidden.py").write_text(good)
    (subs / "both.py").write_text('answers = {"5.1": 70}\n')
    (subs / "both.ipynb").write_text('{"cells": [{"cell_type": "code", "source": "answers = {\\"5.1\\": 71}"}]}')
    os.symlink("/etc/passwd", subs / "passwd.py")
    os.mkfifo(subs / "pipe.py")
    with open(os.path.join(os.fsencode(subs), b"caf\xe9.py"), "w") as f:
        f.write(good)
    (subs / "zz_last.py").write_text(good)
    code, out, err = _grade(subs, "--exercises", "5.1", "--out", tmp_path / "g.csv", "--feedback", tmp_path / "fb")
    assert code == 0, err
    verdicts = {r["student"]: r["verdict"] for r in csv.DictReader((tmp_path / "g.csv").open(encoding="utf-8"))}
    assert verdicts == {"bom": "correct", "UPPER": "correct", "both": "correct", "passwd": "error",
                        "pipe": "error", "caf%E9": "correct", "zz_last": "correct"}, verdicts
    assert "outside the submissions folder" in (tmp_path / "fb" / "passwd.txt").read_text()
    assert "skipped .hidden.py" in out and "skipped both.py" in out


def test_without_bubblewrap_grade_refuses_unless_told(tmp_path, monkeypatch):
    from rapp import grading
    monkeypatch.setitem(grading._ISOLATION, "bwrap", None)
    code, _, err = _grade(tmp_path, "--exercises", "5.1")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "bwrap" in err and "--no-isolation" in err
    code, _, err = _grade(tmp_path, "--exercises", "5.1", "--no-isolation", "--out", tmp_path / "g.csv",
                          "--feedback", tmp_path / "fb")
    assert code == 0 and "can read and write your files" in err


def _busy(seconds: float) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", f"import time\nend = time.time() + {seconds}\n"
                             "while time.time() < end:\n    pass\n"])


@needs_bwrap
@pytest.mark.slow
def test_a_class_graded_under_a_cpu_hog_judges_every_honest_answer_right(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    honest = GD1 + ('import numpy as np\n'
                    'def wrap(a):\n    return float((a + np.pi) % (2 * np.pi) - np.pi)\n'
                    'answers = {"5.1": 71, "5.2": h, "5.3": 15, "1.5": wrap}\n')
    for i in range(5):
        (subs / f"s{i}.py").write_text(honest)
    hogs = [_busy(600) for _ in range(4)]
    try:
        code, out, err = _grade(subs, "--exercises", "5.1,5.2,5.3,1.5", "--out", tmp_path / "g.csv",
                                "--feedback", tmp_path / "fb", "--time", "10")
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    assert code == 0, err
    rows = list(csv.DictReader((tmp_path / "g.csv").open()))
    assert len(rows) == 20 and {r["verdict"] for r in rows} == {"correct"}, \
        [(r["student"], r["exercise"], (tmp_path / "fb" / f"{r['student']}.txt").read_text())
         for r in rows if r["verdict"] != "correct"][:2]


def test_gradescope_and_canvas_formats(tmp_path):
    import json
    from rapp.grading import StudentResult, write_canvas, write_gradescope
    r = StudentResult("ann", [("5.1", 1.0, 1.0, "correct", "71 is right."), ("5.2", 0.0, 2.0, "wrong", "no.")])
    data = json.loads(write_gradescope(r, tmp_path / "gs").read_text())
    assert data["score"] == 1.0 and [t["max_score"] for t in data["tests"]] == [1.0, 2.0]
    assert data["tests"][0]["name"] == "Exercise 5.1" and data["tests"][1]["status"] == "failed"
    write_canvas([r], tmp_path / "canvas.csv", "Homework 3")
    rows = list(csv.reader((tmp_path / "canvas.csv").open()))
    assert rows[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Homework 3"]
    assert rows[1][0].strip() == "Points Possible" and rows[1][-1] == "3" and rows[2] == ["ann", "", "", "ann", "", "1"]


def test_every_function_said_to_solve_an_exercise_exists_and_the_exercise_is_implement():
    from rapp.exercises import catalog
    from rapp.grading import SOLVED_BY, _resolve  # noqa: the test reads the table as the child does

    kinds = {ex.id: ex.kind for ex in catalog()}
    assert set(SOLVED_BY) == {i for i, k in kinds.items() if k == "implement"}
    for ex_id, names in SOLVED_BY.items():
        for dotted in names:
            owner, attr, obj = _resolve(dotted)
            assert callable(getattr(owner, attr)), dotted


@needs_bwrap
@pytest.mark.slow
def test_an_answer_that_is_rapps_own_function_scores_nothing(tmp_path):
    path = tmp_path / "lazy.py"
    path.write_text("import rapp\nanswers = {'1.5': rapp.wrap_angle, '5.2': lambda a, b, s: "
                    "rapp.exercises.ch05.search.toroidal_manhattan(a, b, s)}\n")
    r = grade_submission(path, {"1.5": 1.0, "5.2": 1.0}, GradeLimits(run=20))
    assert [row[3] for row in r.rows] == ["wrong", "wrong"]
    assert all("delegates to rapp" in row[4] for row in r.rows), r.rows


def test_a_python_environment_under_tmp_is_not_hidden_by_the_private_tmp():
    """bwrap mounts in order: the private /tmp comes before the environment's read-only views,
    so a checkout under /tmp (as a CI clone may be) is still seen inside the sandbox."""
    from rapp.grading import _bwrap_argv
    argv = _bwrap_argv("bwrap", None, "submission.py")
    tmp = argv.index("/tmp", argv.index("--tmpfs"))
    binds = [i for i, a in enumerate(argv) if a == "--ro-bind"]
    assert binds and tmp < min(binds)
    prefix = os.path.realpath(sys.prefix)
    assert any(argv[i + 1] == prefix or argv[i + 1] == sys.prefix for i in binds)
