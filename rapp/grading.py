"""Grade a class: a folder of submissions in, a CSV of points and one feedback file per student out.

``python -m rapp grade SUBMISSIONS --exercises 5.1,5.2:2 --out grades.csv``

A submission is a notebook (``.ipynb``) or a Python file (``.py``) named after the student
(``alice.ipynb`` is student ``alice``). Each runs in its own sandbox, isolated by the operating
system with bubblewrap (``bwrap``): its own process, IPC, network, UTS and mount namespaces, as
the unprivileged user 65534 (a user namespace maps it, or, where the grader is root, ``setpriv``
becomes it with no capabilities), its own ``/proc``, a read-only view of the Python
environment and of the rapp package, private ``/tmp`` and home folders, and of the class only
its own file (a copy). Inside, the limits of :mod:`rapp.exercises.sandbox` apply as a second
layer: CPU time (so a loaded machine never fails a correct answer; a generous wall-clock
backstop stops a sleeper), address space, open files, processes, file size, and a seccomp
filter. Without bwrap, ``grade`` refuses to run unless told ``--no-isolation``.

A notebook's code cells run in order; a cell that fails is noted in the feedback and the next
one runs, as "Run All" would not stop a grader.

Where the answers are read (documented in the book's "For instructors" page):

1. a dict named ``answers`` at the top level, ``{"5.2": h, "Exercise 5.1": 71}``; otherwise
2. the last answer passed to ``rapp.exercises.check(id, answer)`` for each id, so a notebook
   whose check cells were filled in, as the book's chapters have them, needs nothing else.

An answer ``None`` is "no answer" (``unanswered``). Only plain data and function calls on copies
of the hidden cases cross from the sandbox to the grader; every verdict is computed in the
grader. The feedback carries no text a submission wrote beyond an exception's class name
(``show_errors`` gives the full messages). The instructor's key (``assign``) never enters a
sandbox: each student's numbers are derived before any student code runs, and only the grader
judges with them.

Examples
--------
>>> parse_weights("5.1, 5.2:2,Exercise 6.1")
{'5.1': 1.0, '5.2': 2.0, '6.1': 1.0}
>>> check_student_id("alice_01", "--roster line 2")
'alice_01'
"""

from __future__ import annotations

import csv
import functools
import io
import json
import math
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["GradeLimits", "StudentResult", "parse_weights", "read_roster", "read_key", "grade_submission",
           "grade_class", "write_csv", "write_feedback", "write_sheets", "write_gradescope", "write_canvas",
           "add_parser", "run", "run_assign", "serve_submission", "check_student_id", "find_submissions",
           "isolation_available", "SOLVED_BY", "DelegatesToRapp", "wall_backstop"]

SUFFIXES = (".ipynb", ".py")

MAX_ID = 100
"""Characters: the longest student id (a roster line or a file name)."""

MAX_SUBMISSION = 20 * 2**20
"""Bytes: the largest submission file graded; a larger one is reported, not run."""

MAX_INPUT = 10 * 2**20
"""Bytes: the largest roster, key or weights file read."""

TIME_RANGE = (0.1, 3600.0)
"""Seconds of CPU time ``--time`` may give one submission to run."""

MEMORY_RANGE = (64, 65536)
"""Megabytes ``--memory`` may give one submission."""

SOLVED_BY: dict[str, tuple[str, ...]] = {
    "1.5": ("rapp.arm.wrap_angle", "rapp.arm.Arm.wrap"),
    "2.3": ("rapp.arm.Arm.end_effector", "rapp.arm.Arm.joint_positions", "rapp.arm.Arm.joint_positions_unchecked"),
    "3.2": ("rapp.collision.segment_hits_circle",),
    "4.2": ("rapp.cspace.JointGrid.index",),
    "5.2": ("rapp.search.toroidal_manhattan",),
    "6.5": ("rapp.ik.dls_step",),
    "7.2": ("rapp.paths.unwrap_path",),
    "8.2": ("rapp.trajectory.cubic_local",),
    "11.5": ("rapp.trajectory.heuristic_velocities",),
    "12.4": ("rapp.rrt.Grower.steer_from",),
    "13.3": ("rapp.ik.ik_2link",),
    "14.2": ("rapp.rrt_star.choose_parent_and_add",),
    "15.2": ("rapp.time_scaling.trapezoidal", "rapp.time_scaling.trapezoidal_moves"),
}
"""The rapp functions that solve each implement exercise: while the grader calls a student's
function for that exercise, calling one of them (under any name rapp gives it) ends the call
with :class:`DelegatesToRapp`, and the answer scores nothing."""


class DelegatesToRapp(Exception):
    """Raised in the sandbox when a student's function calls the rapp function it was to write."""


def wall_backstop(cpu_seconds: float) -> float:
    """Wall-clock seconds after which a child that has used less than ``cpu_seconds`` of CPU
    (it sleeps, or the machine is loaded to a crawl) is stopped anyway: 4x + 30 s.

    >>> wall_backstop(5.0)
    50.0
    """
    return 4.0 * float(cpu_seconds) + 30.0


@dataclass(frozen=True)
class GradeLimits:
    """What one submission may use.

    Attributes
    ----------
    run : float
        CPU seconds to execute the submission (its cells or its module); each exercise then has
        its own CPU time (``Exercise.time_limit``). Wall-clock time is only a backstop
        (:func:`wall_backstop`), so a loaded machine never fails a correct answer.
    memory : int
        Bytes of address space beyond the interpreter's start.
    restarts : int
        Times a submission is started again after one answer hung or crashed it.
    isolate : bool
        Run each submission under bubblewrap (:func:`isolation_available`); False runs it with
        the lighter sandbox alone, which sees the grader's files.
    show_errors : bool
        Put the full text of a submission's exceptions in its feedback (off: the class only).
    """

    run: float = 60.0
    memory: int = 1 << 30
    restarts: int = 2
    isolate: bool = True
    show_errors: bool = False


@dataclass
class StudentResult:
    """The verdicts of one student, in the order of the assignment."""

    student: str
    rows: list = field(default_factory=list)  # (exercise, points, max_points, verdict, message)
    notes: list = field(default_factory=list)

    @property
    def points(self) -> float:
        return sum(r[1] for r in self.rows)

    @property
    def max_points(self) -> float:
        return sum(r[2] for r in self.rows)


def parse_weights(text: str) -> dict[str, float]:
    """``"5.1,5.2:2"`` → ``{"5.1": 1.0, "5.2": 2.0}``; ids as the book prints them.

    Raises ``ValueError`` naming the item that is not an id or a weight.
    """
    from rapp.exercises import catalog, normalize_id

    known = {ex.id for ex in catalog()}
    weights: dict[str, float] = {}
    for item in str(text).split(","):
        if not item.strip():
            continue
        name, _, weight = item.partition(":")
        ex_id = normalize_id(name)
        if ex_id not in known:
            raise ValueError(f"--exercises: no exercise {name.strip()!r} (see rapp.exercises.catalog())")
        try:
            w = float(weight) if weight.strip() else 1.0
        except ValueError:
            raise ValueError(f"--exercises: the weight of {ex_id} must be a number, got {weight.strip()!r}") from None
        if not (w >= 0 and w < float("inf")):
            raise ValueError(f"--exercises: the weight of {ex_id} must be finite and >= 0, got {weight.strip()!r}")
        weights[ex_id] = w
    if not weights:
        raise ValueError("--exercises: name at least one exercise, e.g. 5.1,5.2:2")
    return weights


def read_weights_file(path: Path) -> dict[str, float]:
    """A CSV with columns ``exercise,weight`` (a header row is allowed)."""
    items = []
    for row in csv.reader(_read_input(Path(path), "--weights").splitlines()):
        if not row or row[0].strip().lower() in ("exercise", "") or row[0].lstrip().startswith("#"):
            continue
        items.append(f"{row[0]}:{row[1]}" if len(row) > 1 and row[1].strip() else row[0])
    return parse_weights(",".join(items))


# --- the instructor's inputs ------------------------------------------------------------------

def _read_input(path: Path, option: str) -> str:
    """The text of an input file: a regular file (never a FIFO, which would block, or a device),
    at most :data:`MAX_INPUT` bytes, UTF-8 (a byte-order mark dropped). ValueError names ``option``."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise ValueError(f"{option}: cannot read {path} ({exc.strerror or type(exc).__name__})") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise ValueError(f"{option}: {path} is not a regular file")
        if info.st_size > MAX_INPUT:
            raise ValueError(f"{option}: {path} is larger than {MAX_INPUT // 2**20} MB")
        with os.fdopen(fd, "rb", closefd=False) as f:
            data = f.read(MAX_INPUT + 1)
    finally:
        os.close(fd)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{option}: {path} is not UTF-8 text") from None


_BAD_ID = re.compile(r"[\x00-\x1f\x7f/\\]")


def check_student_id(student: str, where: str) -> str:
    """``student`` when it is a plain name a file can carry; else ValueError naming ``where``.

    A plain name has no path separator, no control character (NUL included), is not ``.`` or
    ``..`` nor hidden (a leading dot), holds at most :data:`MAX_ID` characters, and is valid text.
    """
    if not student:
        raise ValueError(f"{where}: an empty student id")
    if len(student) > MAX_ID:
        raise ValueError(f"{where}: a student id longer than {MAX_ID} characters")
    if _BAD_ID.search(student):
        raise ValueError(f"{where}: a student id with a path separator or a control character")
    if student.startswith("."):
        raise ValueError(f"{where}: a student id may not start with '.'")
    try:
        student.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError(f"{where}: a student id that is not valid text") from None
    return student


def read_roster(path: Path) -> list[str]:
    """Student ids, one per line (the first CSV column; a header ``student`` and ``#`` lines skipped).

    Every id is checked (:func:`check_student_id`) and unique; a ValueError names ``--roster``
    and the line.
    """
    out: list[str] = []
    seen: dict[str, int] = {}
    for number, line in enumerate(_read_input(Path(path), "--roster").splitlines(), 1):
        where = f"--roster line {number}"
        if len(line) > 10 * MAX_ID:
            raise ValueError(f"{where}: the line is longer than {10 * MAX_ID} characters")
        if "\x00" in line:
            raise ValueError(f"{where}: the line holds a NUL character")
        try:
            row = next(csv.reader([line]), [])
        except csv.Error:
            raise ValueError(f"{where}: not a CSV line") from None
        if not row or not row[0].strip() or row[0].lstrip().startswith("#") or row[0].strip().lower() == "student":
            continue
        student = check_student_id(row[0].strip(), where)
        if student in seen:
            raise ValueError(f"{where}: {student!r} is already on line {seen[student]}")
        seen[student] = number
        out.append(student)
    return out


def read_key(path: Path, create: bool = False) -> str:
    """The key in ``path`` (stripped); a new random one is written (mode 600) when ``create``."""
    path = Path(path)
    if create and not os.path.lexists(path):
        import secrets
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(secrets.token_hex(32) + "\n")
    key = _read_input(path, "--key").strip()
    if len(key) < 16:
        raise ValueError(f"--key: {path} holds fewer than 16 characters; use a longer secret")
    return key


def _same_file(a, b) -> bool:
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def _check_output_file(path: Path, option: str, inputs: list) -> None:
    """Refuse, before any work, an output that is an input, not a regular file, or not writable."""
    for other, what in inputs:
        if other is not None and _same_file(path, other):
            raise ValueError(f"{option}: {path} is the {what}; refusing to overwrite it")
    if os.path.lexists(path):
        try:
            info = os.stat(path)
        except OSError:
            raise ValueError(f"{option}: {path} is a broken link") from None
        if not stat.S_ISREG(info.st_mode):
            raise ValueError(f"{option}: {path} exists and is not a regular file (a folder, FIFO or device)")
    parent = os.path.dirname(os.path.abspath(path)) or "."
    if not os.path.isdir(parent) or not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{option}: cannot write in {parent}")


def _check_output_folder(folder: Path, option: str, inputs: list, names: list[str]) -> None:
    """Refuse a folder that is or holds an input under a name it will write, or cannot be made."""
    for other, what in inputs:
        if other is not None and os.path.isdir(other) and _same_file(folder, other):
            raise ValueError(f"{option}: {folder} is the {what}; write it elsewhere")
    if os.path.lexists(folder) and not os.path.isdir(folder):
        raise ValueError(f"{option}: {folder} exists and is not a folder")
    if os.path.isdir(folder):
        if not os.access(folder, os.W_OK | os.X_OK):
            raise ValueError(f"{option}: cannot write in {folder}")
        for name in names:
            _check_output_file(Path(folder) / name, option, inputs)
    else:
        parent = os.path.dirname(os.path.abspath(folder)) or "."
        while not os.path.exists(parent) and os.path.dirname(parent) != parent:
            parent = os.path.dirname(parent)
        if not os.path.isdir(parent) or not os.access(parent, os.W_OK | os.X_OK):
            raise ValueError(f"{option}: cannot create {folder}")


@dataclass(frozen=True)
class _Found:
    """A file of the submissions folder: the student it names, and what is wrong with it, if anything."""

    student: str
    path: Path | None
    problem: str | None = None


def _shown(name: str) -> str:
    """A file name as text: bytes that are not UTF-8 written as ``%XX``.

    >>> _shown(b"caf\\xe9".decode("utf-8", "surrogateescape"))
    'caf%E9'
    """
    return "".join(f"%{ord(c) - 0xDC00:02X}" if 0xDC80 <= ord(c) <= 0xDCFF else c for c in str(name))


def find_submissions(folder: Path) -> tuple[dict[str, _Found], list[str]]:
    """Student id → submission (``.ipynb`` preferred over ``.py``), and lines about skipped files.

    Extensions are matched whatever their case; a hidden file is skipped (and said so); a name
    that is not UTF-8 is graded under its name with the bad bytes written ``%XX``; a link out of
    the folder, a FIFO, a device or a file over :data:`MAX_SUBMISSION` bytes is reported for its
    student and not run.
    """
    found: dict[str, _Found] = {}
    skipped: list[str] = []
    root = os.path.realpath(folder)
    for entry in sorted(os.scandir(folder), key=lambda e: e.name):
        name = entry.name
        base, dot, ext = name.rpartition(".")
        if not dot or "." + ext.lower() not in SUFFIXES:
            continue
        shown = _shown(name)
        if name.startswith("."):
            skipped.append(f"{shown}: a hidden file, not graded")
            continue
        student = _shown(base)
        try:
            check_student_id(student, "file name")
        except ValueError as exc:
            skipped.append(f"{shown}: {str(exc).split(': ', 1)[1]}; not graded")
            continue
        problem = None
        real = os.path.realpath(entry.path)
        if entry.is_symlink() and os.path.commonpath([root, real]) != root:
            problem = "is a link to a file outside the submissions folder; not run"
        else:
            try:
                info = os.stat(entry.path)
                if not stat.S_ISREG(info.st_mode):
                    problem = "is not a regular file; not run"
                elif info.st_size > MAX_SUBMISSION:
                    problem = f"is larger than {MAX_SUBMISSION // 2**20} MB; not run"
            except OSError as exc:
                problem = f"cannot be read ({exc.strerror or type(exc).__name__})"
        item = _Found(student, Path(entry.path), None if problem is None else f"{shown} {problem}")
        if student in found:
            keep, other = (item, found[student]) if "." + ext.lower() == ".ipynb" else (found[student], item)
            skipped.append(f"{_shown(other.path.name)}: {student} also sent {_shown(keep.path.name)}, which is graded")
            found[student] = keep
        else:
            found[student] = item
    return found, skipped


# --- isolation: bubblewrap --------------------------------------------------------------------

_ISOLATION: dict = {}


def _binds() -> list[str]:
    """bwrap arguments: read-only views of the system and of the Python environment, no more."""
    import rapp

    args = ["--ro-bind", "/usr", "/usr"]
    for top in ("/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"):
        if os.path.islink(top):
            args += ["--symlink", os.readlink(top), top]
        elif os.path.isdir(top):
            args += ["--ro-bind", top, top]
    for name in ("ld.so.cache", "ld.so.conf", "ld.so.conf.d", "localtime", "fonts", "alternatives"):
        args += ["--ro-bind-try", f"/etc/{name}", f"/etc/{name}"]
    prefixes = {os.path.realpath(p) for p in (sys.prefix, sys.base_prefix, sys.exec_prefix,
                                              sys.base_exec_prefix, os.path.dirname(os.path.realpath(sys.executable)))}
    prefixes |= {p for p in (sys.prefix, os.path.dirname(sys.executable)) if os.path.isdir(p)}
    for p in sorted(prefixes):
        if p != "/" and not p.startswith("/usr/"):
            args += ["--ro-bind", p, p]
    args += ["--ro-bind", os.path.dirname(os.path.abspath(rapp.__file__)), "/opt/rapp/rapp"]
    # The folders leading to each mount, made first and open to user 65534 (bwrap's own are 0700).
    targets = [args[i + 2] for i, a in enumerate(args) if a in ("--ro-bind", "--ro-bind-try")]
    parents = sorted({str(p) for t in targets for p in Path(t).parents if str(p) != "/"}, key=len)
    made = []
    for folder in parents:
        made += ["--perms", "0755", "--dir", folder]
    return made + args


def _bwrap_argv(bwrap: str, submission: Path | None, inner_name: str) -> list[str]:
    """The bubblewrap command line around a child (see the module docstring), ending with the
    command that drops to user 65534 where the grader is root.

    As root, bwrap makes the namespaces itself and ``setpriv`` then becomes user 65534 with no
    capabilities: a real unprivileged user, whom the kernel holds to the process limit (a user
    namespace mapped onto root would be exempt from it). Otherwise a user namespace maps the
    grader's user to 65534 inside.
    """
    if os.geteuid() == 0:
        user = ["--unshare-pid"]
        drop = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", "--inh-caps=-all",
                "--bounding-set=-all", "--nnp", "--"]
    else:
        user = ["--unshare-user", "--uid", "65534", "--gid", "65534", "--disable-userns", "--cap-drop", "ALL",
                "--unshare-pid"]
        drop = []
    argv = [bwrap, *user, "--unshare-ipc", "--unshare-net", "--unshare-uts", "--unshare-cgroup-try",
            "--hostname", "sandbox", "--die-with-parent", "--new-session",
            # The private /tmp and home first: a Python environment that lives under /tmp (a
            # checkout there) is then bound on top of the empty tmpfs, not hidden by it.
            "--perms", "1777", "--size", str(256 * 2**20), "--tmpfs", "/tmp",
            "--perms", "0777", "--size", str(256 * 2**20), "--tmpfs", "/home/student",
            *_binds(), "--proc", "/proc", "--dev", "/dev", "--dir", "/submission"]
    if submission is not None:
        argv += ["--ro-bind", str(submission), f"/submission/{inner_name}"]
    argv += ["--chdir", "/home/student", "--clearenv"]
    for k, v in _child_env(True).items():
        argv += ["--setenv", k, v]
    return argv + drop


def _child_env(isolated: bool) -> dict:
    env = dict(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", NUMBA_NUM_THREADS="1",
               MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1", PYTHONHASHSEED="0", PYTHONNOUSERSITE="1")
    if isolated:
        env.update(PATH="/usr/bin:/bin", HOME="/home/student", LANG="C.UTF-8", PYTHONPATH="/opt/rapp",
                   MPLCONFIGDIR="/tmp/matplotlib", NUMBA_CACHE_DIR="/tmp/numba")
    else:
        env.update({k: v for k, v in os.environ.items() if k in ("PATH", "PYTHONPATH", "HOME", "LANG", "LC_ALL")})
    return env


def isolation_available() -> str | None:
    """The path of a bubblewrap that can isolate a child here, or None (checked once, by running
    a trivial child under the same command line a submission gets)."""
    if "bwrap" not in _ISOLATION:
        bwrap, works = shutil.which("bwrap"), None
        if bwrap:
            try:
                done = subprocess.run(_bwrap_argv(bwrap, None, "") + [sys.executable, "-s", "-c", "import rapp"],
                                      stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL, timeout=120)
                works = bwrap if done.returncode == 0 else None
            except (OSError, subprocess.SubprocessError):
                works = None
        _ISOLATION["bwrap"] = works
    return _ISOLATION["bwrap"]


# --- the sandboxed side: execute a submission, then serve its answers -------------------------

_SERVE = "import sys; from rapp.grading import serve_submission; serve_submission(sys.argv[1:])"

_JUDGING: list = [None]  # in the child: the exercise whose answer the grader is calling


def serve_submission(argv: list[str]) -> None:
    """Entry point of the sandbox process that :func:`grade_submission` starts (public: it is
    named in that process's command line): ``SUBMISSION RFD WFD CONFIG_JSON``.

    It confines itself to the limits, hides the functions that solve the assigned implement
    exercises (:data:`SOLVED_BY`), executes the submission and answers the grader's questions on
    the two pipes; it is not meant to be called in a process of one's own.
    """
    from rapp.exercises.sandbox import Limits, start_cpu_budget, confine, send_message, serve, to_plain

    path, rfd, wfd = argv[0], int(argv[1]), int(argv[2])
    config = json.loads(argv[3])
    confine(Limits(wall=config["run"], cpu=config["cpu"], memory=config["memory"], files=config.get("files"),
                   processes=config.get("processes"), file_size=config.get("file_size")))
    devnull = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(devnull, fd)
    sys.stdout = sys.stderr = io.StringIO()
    try:
        import rapp.exercises  # noqa: F401  (loads the modules whose functions are guarded)
        _guard_solutions(config.get("solves", {}))
        start_cpu_budget(config["run"])
        namespace, notes = _execute(Path(path))
        answers = _answers_of(namespace)
        for ex_id in config.get("solves", {}):
            if ex_id in answers and callable(answers[ex_id]):
                answers[ex_id] = _judged(answers[ex_id], ex_id)
        reply = {"ok": to_plain({"keys": sorted(answers), "notes": notes})}
    except BaseException as exc:  # the submission could not be read: say why
        answers = {}
        reply = {"raised": to_plain(_error_record(exc))}
    try:
        sys.stdout = sys.stderr = io.StringIO()
        send_message(wfd, json.dumps(reply).encode())
    except BaseException:
        os._exit(0)
    serve(answers, rfd, wfd)
    os._exit(0)


def _resolve(dotted: str):
    """(owner, attribute name, the object) of a dotted rapp name, importing its module."""
    import importlib
    parts = dotted.split(".")
    for i in range(len(parts) - 1, 0, -1):
        try:
            owner = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for name in parts[i:-1]:
            owner = getattr(owner, name)
        return owner, parts[-1], (vars(owner)[parts[-1]] if isinstance(owner, type) else getattr(owner, parts[-1]))
    raise ImportError(dotted)


def _guard_solutions(solves: dict) -> None:
    """In the child: every rapp name of a function in ``solves`` (exercise → dotted names) now
    raises :class:`DelegatesToRapp` while the grader calls that exercise's answer."""
    for ex_id, names in solves.items():
        for dotted in names:
            try:
                owner, attr, original = _resolve(dotted)
            except (ImportError, AttributeError, KeyError):
                continue
            inner = original.__func__ if isinstance(original, (staticmethod, classmethod)) else original
            guarded = _guard(inner, ex_id, dotted)
            new = type(original)(guarded) if isinstance(original, (staticmethod, classmethod)) else guarded
            setattr(owner, attr, new)
            if isinstance(owner, type):
                continue
            for module in list(sys.modules.values()):  # the same function under other rapp names
                if getattr(module, "__name__", "").split(".")[0] == "rapp":
                    for key, value in list(vars(module).items()):
                        if value is original:
                            setattr(module, key, new)


def _guard(inner, ex_id: str, dotted: str):
    """``inner``, except while ``ex_id``'s answer is being judged (no ``__wrapped__``: the
    original is not handed out)."""
    def guarded(*args, **kw):
        if _JUDGING[0] == ex_id:
            raise DelegatesToRapp(dotted)
        return inner(*args, **kw)

    for name in ("__name__", "__qualname__", "__doc__"):
        try:
            setattr(guarded, name, getattr(inner, name))
        except (AttributeError, TypeError):
            pass
    return guarded


def _judged(fn, ex_id: str):
    """The student's function, marked as being judged for ``ex_id`` while it runs."""
    def call(*args, **kw):
        _JUDGING[0] = ex_id
        try:
            return fn(*args, **kw)
        finally:
            _JUDGING[0] = None

    call.__wrapped__ = fn  # inspect.signature reports the student's own signature
    return call


def _error_record(exc: BaseException) -> list:
    """[class name, line or None, message]: what the grader may report of an exception."""
    try:
        text = " ".join(str(exc).split())
    except BaseException:
        text = ""
    line = exc.lineno if isinstance(exc, SyntaxError) and isinstance(exc.lineno, int) else None
    return [type(exc).__name__, line, text[:300]]


class NotANotebook(ValueError):
    """An ``.ipynb`` submission that is not a notebook's JSON."""


def _code_of(path: Path) -> list[str]:
    """The code to run: a .py file whole, or a notebook's code cells (magics and ! lines left out)."""
    text = path.read_bytes().decode("utf-8-sig")
    if path.suffix.lower() == ".py":
        return [text]
    try:
        nb = json.loads(text)
        cells = nb["cells"]
    except (ValueError, KeyError, TypeError) as exc:
        raise NotANotebook(f"not a notebook ({type(exc).__name__})") from None
    code = []
    for cell in cells:
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        source = cell.get("source", "")
        source = "".join(map(str, source)) if isinstance(source, list) else str(source)
        lines = [("pass  # " + line) if line.lstrip().startswith(("%", "!")) else line
                 for line in source.split("\n")]
        code.append("\n".join(lines))
    return code


def _execute(path: Path) -> tuple[dict, list]:
    """Run the submission's code in one namespace, recording every rapp.exercises.check call."""
    import rapp
    import rapp.exercises as exercises

    recorded: dict = {}
    real_check = exercises.check

    def recording_check(exercise_id, answer, **kw):
        key = exercises.normalize_id(exercise_id)
        if key is not None:
            recorded[key] = answer
        return exercises.Verdict(key or "?", False, "recorded for grading; the verdict comes later.")

    exercises.check = recording_check
    namespace: dict = {"__name__": "__main__", "rapp": rapp}
    notes = []
    is_py = path.suffix.lower() == ".py"
    try:
        for i, source in enumerate(_code_of(path)):
            try:
                exec(compile(source, f"<cell {i + 1}>", "exec"), namespace)
            except SyntaxError as exc:
                notes.append([i + 1, *_error_record(exc)])
                if is_py:
                    raise
            except Exception as exc:
                notes.append([i + 1, *_error_record(exc)])
    finally:
        exercises.check = real_check
    namespace["__recorded__"] = recorded
    return namespace, notes[:20]


def _answers_of(namespace: dict) -> dict:
    """The answers, ``None`` ones left out (``None`` is "no answer", as ``check`` says)."""
    from rapp.exercises import normalize_id

    given = namespace.get("answers")
    if type(given) is dict:
        found = {normalize_id(k): v for k, v in given.items() if normalize_id(k)}
    else:
        found = dict(namespace.get("__recorded__", {}))
    return {k: v for k, v in found.items() if v is not None}


# --- the grader's side ------------------------------------------------------------------------

def _class_name(text) -> str:
    from rapp.exercises.sandbox import error_class
    return error_class(str(text))


def _describe_error(record, show: bool) -> str:
    """An error record of the child, as the feedback says it: the class (sanitised), the line,
    and the message only when ``show``."""
    from rapp.exercises.sandbox import bounded
    try:
        name, line, text = record
    except (TypeError, ValueError):
        return "an exception"
    out = _class_name(name) + (f" (line {line})" if type(line) is int else "")
    if out == "NotANotebook":
        return "the file is not a notebook (JSON with a list of cells)"
    return out + (f": {bounded(str(text), 300)}" if show and text else "")


class _Submission:
    """The sandbox process of one submission, started again (up to a limit) after a crash."""

    def __init__(self, path: Path, limits: GradeLimits, budget: float, solves: dict, bwrap: str | None):
        self.path, self.limits, self.budget, self.solves, self.bwrap = path, limits, budget, solves, bwrap
        self.starts, self.box, self.keys, self.notes, self.error = 0, None, set(), [], None
        self._tmp = None

    def start(self) -> bool:
        from rapp.exercises.sandbox import Limits, Sandbox, SandboxError, from_plain

        self.close()
        self.starts += 1
        self._tmp = tempfile.mkdtemp(prefix="rapp-grade-")
        inner = "submission" + self.path.suffix.lower()
        copy = Path(self._tmp) / inner
        with open(self.path, "rb") as src, open(copy, "wb") as dst:  # a bounded copy, never a link
            dst.write(src.read(MAX_SUBMISSION + 1)[:MAX_SUBMISSION])
        os.chmod(copy, 0o644)  # user 65534 reads it; the folder around it stays the grader's (0700)
        p_read, c_write = os.pipe()
        c_read, p_write = os.pipe()
        cpu = self.limits.run + self.budget + 10
        config = {"run": self.limits.run, "cpu": cpu, "memory": self.limits.memory, "files": 256,
                  "processes": 64 if self.bwrap else None, "file_size": 64 * 2**20, "solves": self.solves}
        if self.bwrap:
            prefix, target, cwd = _bwrap_argv(self.bwrap, copy, inner), f"/submission/{inner}", "/"
            env = None
        else:
            prefix, target, cwd, env = [], str(copy), self._tmp, _child_env(False)
        argv = prefix + [sys.executable, "-s", "-c", _SERVE, target, str(c_read), str(c_write), json.dumps(config)]
        try:
            popen = subprocess.Popen(argv, cwd=cwd, env=env, pass_fds=(c_read, c_write), start_new_session=True,
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        except OSError as exc:
            for fd in (p_read, c_write, c_read, p_write):
                os.close(fd)
            self.error = f"could not be started ({type(exc).__name__})"
            return False
        os.close(c_read), os.close(c_write)
        limits = Limits(wall=wall_backstop(self.limits.run), cpu=cpu, memory=self.limits.memory)
        self.box = Sandbox.attach(popen, p_read, p_write, limits, redact=not self.limits.show_errors,
                                  exit_codes=bool(self.bwrap))
        try:
            ready = self.box.receive()
        except SandboxError as exc:
            self.error = (f"did not finish running within {self.limits.run:g} s of CPU time (or "
                          f"{wall_backstop(self.limits.run):g} s of waiting)"
                          if "no answer within" in str(exc) or "CPU" in str(exc) or "XCPU" in str(exc)
                          else f"stopped while running: {exc}")
            self.close()
            return False
        if "raised" in ready:
            try:
                record = from_plain(ready["raised"])
            except Exception:
                record = None
            self.error = f"could not be run: {_describe_error(record, self.limits.show_errors)}"
            self.close()
            return False
        try:
            info = from_plain(ready.get("ok"))
            self.keys = {k for k in info["keys"] if type(k) is str}
            self.notes = [f"cell {int(n[0])}: {_describe_error(n[1:], self.limits.show_errors)}"
                          for n in list(info["notes"])[:20]]
        except Exception:
            self.error = "sent something that is not a list of answers"
            self.close()
            return False
        return True

    def close(self) -> None:
        if self.box is not None:
            self.box.close()
            if self.box.popen is not None:
                try:
                    self.box.popen.wait(timeout=2)
                except Exception:
                    pass
            self.box = None
        if self._tmp:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._tmp = None


def _delegation_message(ex_id: str) -> str:
    names = ", ".join(SOLVED_BY.get(ex_id, ()))
    return (f"your function calls {names}, the rapp function this exercise asks you to write: the answer "
            "delegates to rapp and scores nothing.")


def grade_submission(path: Path, weights: dict[str, float], limits: GradeLimits = GradeLimits(),
                     variant_code: str | None = None) -> StudentResult:
    """Every assigned exercise of one submission, judged; never raises (bad input included).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "bob.py").write_text('answers = {"5.1": 71, "Exercise 5.3": 14}')
    >>> r = grade_submission(d / "bob.py", {"5.1": 1.0, "5.3": 2.0}, GradeLimits(isolate=False))
    >>> [(row[0], row[1], row[3]) for row in r.rows], r.points
    ([('5.1', 1.0, 'correct'), ('5.3', 0.0, 'wrong')], 1.0)

    With ``variant_code`` (from :func:`rapp.exercises.variants.code`), the exercises that have
    per-student numbers are judged with that student's numbers. With ``limits.isolate`` and no
    working bubblewrap, every row is an error saying so.
    """
    try:
        result = StudentResult(_shown(Path(path).stem))
    except Exception:
        result = StudentResult("?")
    try:
        items = [(str(e), float(w)) for e, w in dict(weights).items()]
    except Exception:
        result.notes.append("the assignment (weights) is not a mapping of exercise id to points")
        return result
    try:
        _grade_into(result, Path(path), items, limits, variant_code)
    except KeyboardInterrupt:
        raise
    except BaseException as exc:  # never lose the class for one student
        done = {r[0] for r in result.rows}
        for ex_id, weight in items:
            if ex_id not in done:
                result.rows.append((ex_id, 0.0, weight, "error", f"the grader failed on it ({type(exc).__name__})."))
    return result


def _grade_into(result: StudentResult, path: Path, items: list, limits: GradeLimits, variant_code) -> None:
    from rapp.exercises import catalog, check, variants, verdict_in_sandbox

    exercises = {ex.id: ex for ex in catalog()}
    unknown = [e for e, _ in items if e not in exercises]
    for ex_id, weight in items:
        if ex_id in unknown:
            result.rows.append((ex_id, 0.0, weight, "error", "no such exercise in rapp.exercises.catalog()."))
    items = [(e, w) for e, w in items if e not in unknown]
    if not items:
        return
    bwrap = None
    if limits.isolate:
        bwrap = isolation_available()
        if bwrap is None:
            for ex_id, weight in items:
                result.rows.append((ex_id, 0.0, weight, "error", "not graded: bubblewrap (bwrap) cannot isolate "
                                    "submissions on this machine."))
            return
    if not (isinstance(limits.run, (int, float)) and TIME_RANGE[0] <= limits.run <= TIME_RANGE[1]):
        for ex_id, weight in items:
            result.rows.append((ex_id, 0.0, weight, "error", "not graded: the time limit is out of range."))
        return
    try:
        info = os.stat(path)
        problem = None if stat.S_ISREG(info.st_mode) else "is not a regular file"
        if problem is None and info.st_size > MAX_SUBMISSION:
            problem = f"is larger than {MAX_SUBMISSION // 2**20} MB"
    except OSError as exc:
        problem = f"cannot be read ({exc.strerror or type(exc).__name__})"
    if problem:
        result.notes.append(f"the submission {problem}")
        for ex_id, weight in items:
            result.rows.append((ex_id, 0.0, weight, "error", f"the submission {problem}."))
        return
    budget = sum(exercises[e].time_limit for e, _ in items)
    solves = {e: list(SOLVED_BY[e]) for e, _ in items if e in SOLVED_BY}
    # Each student's numbers are computed here, from the code alone, before their code runs.
    own = {e: variants.judge(e, variant_code) for e, _ in items
           if variant_code is not None and variants.has_variant(e)}
    sub = _Submission(path, limits, budget, solves, bwrap)
    try:
        running = sub.start()
        result.notes += [f"while running: {n}" for n in sub.notes]
        for ex_id, weight in items:
            ex = exercises[ex_id]
            if not running:
                result.rows.append((ex_id, 0.0, weight, "error", f"the submission {sub.error}."))
                continue
            if ex_id not in sub.keys:
                verdict = check(ex_id, None)
                result.rows.append((ex_id, 0.0, weight, "unanswered", verdict.message))
                continue
            sub.box.start_budget(ex.time_limit, wall_backstop(ex.time_limit))
            verdict = verdict_in_sandbox(ex, sub.box, ex_id, own.get(ex_id))
            message = verdict.message
            if ex_id in SOLVED_BY and "DelegatesToRapp" in message:
                verdict, message = None, _delegation_message(ex_id)
            elif "did not finish within" in message or "used up its CPU time" in message:
                message = message.replace(f"within {ex.time_limit:g} s", f"within {ex.time_limit:g} s of CPU time "
                                          f"(or {wall_backstop(ex.time_limit):g} s of waiting)")
            result.rows.append((ex_id, weight if verdict else 0.0, weight,
                                "correct" if verdict else "wrong", message))
            if sub.box.dead:  # the answer hung or ended the process: start it again for the next one
                running = sub.starts <= limits.restarts and sub.start()
                if not running and not sub.error:
                    sub.error = "kept stopping (hung or crashed more than the restarts allowed)"
    finally:
        sub.close()
    if sub.error and not any(r[3] != "error" for r in result.rows):
        result.notes.insert(0, f"the submission {sub.error}")


def grade_class(folder: Path, weights: dict[str, float], roster: list[str] | None = None,
                limits: GradeLimits = GradeLimits(), progress=None, key: str | None = None,
                skipped: list | None = None) -> list[StudentResult]:
    """Grade every submission in ``folder`` (and list the roster's students who sent none).

    With the instructor's ``key``, each student is judged on their own numbers (``assign``):
    every student's code is derived here before any submission runs, and the key is not kept.
    Files that are not graded are described in ``skipped`` (a list, filled in).
    """
    from rapp.exercises import variants

    subs, notes = find_submissions(folder)
    if skipped is not None:
        skipped.extend(notes)
    students = list(roster) if roster is not None else sorted(subs)
    if roster is not None:
        students += sorted(s for s in subs if s not in set(roster))
    codes = {s: variants.code(key, s) for s in students} if key is not None else {}
    key = None  # noqa: F841  (only the codes are needed from here on)
    results = []
    for student in students:
        found = subs.get(student)
        if found is None:
            r = StudentResult(student, [(e, 0.0, w, "missing", "no submission.") for e, w in weights.items()])
            r.notes.append("no submission found")
        elif found.problem:
            r = StudentResult(student, [(e, 0.0, w, "error", f"{found.problem}.") for e, w in weights.items()])
            r.notes.append(f"the submission {found.problem}")
        else:
            r = grade_submission(found.path, weights, limits, codes.get(student))
            r.student = student
            if roster is not None and student not in roster:
                r.notes.append("not on the roster")
        results.append(r)
        if progress:
            progress(r)
    return results


# --- the outputs ------------------------------------------------------------------------------

def _write_text(path: Path, text: str) -> None:
    """``text`` into ``path`` atomically, with the mode a plain ``open`` would give (umask)."""
    from rapp.files import atomic_output
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8", errors="backslashreplace") as f:
            f.write(text)


def write_csv(results: list[StudentResult], path: Path) -> None:
    """One row per student and exercise: student, exercise, points, max_points, verdict (atomic)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["student", "exercise", "points", "max_points", "verdict"])
    for r in results:
        for ex_id, points, max_points, verdict, _ in r.rows:
            w.writerow([r.student, ex_id, f"{points:g}", f"{max_points:g}", verdict])
    _write_text(Path(path), buf.getvalue())


def write_feedback(result: StudentResult, folder: Path) -> Path:
    """``folder/STUDENT.txt``: the total, then each exercise's verdict and hint (atomic)."""
    lines = [f"Feedback for {result.student}: {result.points:g} of {result.max_points:g} points", ""]
    lines += [f"Note: {n}" for n in result.notes]
    if result.notes:
        lines.append("")
    for ex_id, points, max_points, verdict, message in result.rows:
        lines.append(f"Exercise {ex_id} ({points:g}/{max_points:g}, {verdict}): {message}")
    path = Path(folder) / f"{check_student_id(result.student, 'student')}.txt"
    _write_text(path, "\n".join(lines) + "\n")
    return path


def write_gradescope(result: StudentResult, folder: Path) -> Path:
    """``folder/STUDENT/results.json``: the student's result in Gradescope's autograder format
    (``score``, and one test per exercise with ``score``, ``max_score``, ``status`` and ``output``)."""
    tests = [{"name": f"Exercise {ex_id}", "score": points, "max_score": max_points,
              "status": "passed" if verdict == "correct" else "failed", "output": f"{verdict}: {message}"}
             for ex_id, points, max_points, verdict, message in result.rows]
    data = {"score": result.points, "output": "\n".join(result.notes), "tests": tests,
            "visibility": "visible", "stdout_visibility": "hidden"}
    path = Path(folder) / check_student_id(result.student, "student") / "results.json"
    _write_text(path, json.dumps(data, indent=1) + "\n")
    return path


def write_canvas(results: list[StudentResult], path: Path, assignment: str = "rapp exercises") -> None:
    """A Canvas gradebook CSV: ``Student, ID, SIS User ID, SIS Login ID, Section`` and one column,
    ``assignment``, with each student's points (the student id as the SIS Login ID), after the
    "Points Possible" row Canvas reads the maximum from."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["Student", "ID", "SIS User ID", "SIS Login ID", "Section", assignment])
    w.writerow(["    Points Possible", "", "", "", "", f"{results[0].max_points:g}" if results else "0"])
    for r in results:
        w.writerow([r.student, "", "", r.student, "", f"{r.points:g}"])
    _write_text(Path(path), buf.getvalue())


# --- the command line -------------------------------------------------------------------------

def add_parser(sub) -> None:
    """The ``grade`` and ``assign`` subcommands of ``python -m rapp``."""
    pg = sub.add_parser("grade", help="grade a folder of student submissions (isolated)",
                        description="Run every submission (STUDENT.ipynb or STUDENT.py) in SUBMISSIONS "
                        "isolated by bubblewrap, judge its answers (a dict 'answers', or the last "
                        "rapp.exercises.check call per exercise) and write a CSV (student, exercise, "
                        "points, max_points, verdict) and one feedback file per student.")
    pg.add_argument("submissions", help="folder of STUDENT.ipynb / STUDENT.py files")
    pg.add_argument("--exercises", metavar="IDS",
                    help="the assignment, ids with optional weights: 5.1,5.2:2,6.1")
    pg.add_argument("--weights", metavar="FILE.csv", help="the assignment as a CSV: exercise,weight")
    pg.add_argument("--roster", metavar="FILE", help="student ids, one per line (missing ones get 0)")
    pg.add_argument("--out", metavar="PATH", default=None,
                    help="the CSV (default grades.csv); with --format gradescope, a folder (default gradescope)")
    pg.add_argument("--format", choices=("csv", "gradescope", "canvas"), default="csv",
                    help="csv (one row per student and exercise), gradescope (OUT/STUDENT/results.json) "
                    "or canvas (a gradebook CSV to import)")
    pg.add_argument("--assignment", metavar="NAME", default="rapp exercises",
                    help="the assignment's column name in a Canvas gradebook (default 'rapp exercises')")
    pg.add_argument("--feedback", metavar="DIR", default="feedback", help="feedback folder (default feedback)")
    pg.add_argument("--time", metavar="SECONDS", type=float, default=60.0,
                    help=f"CPU seconds to run one submission, {TIME_RANGE[0]:g} to {TIME_RANGE[1]:g} (default 60)")
    pg.add_argument("--memory", metavar="MB", type=int, default=1024,
                    help=f"memory a submission may add, {MEMORY_RANGE[0]} to {MEMORY_RANGE[1]} MB (default 1024)")
    pg.add_argument("--key", metavar="KEYFILE", help="the instructor's key file of 'assign': judge each "
                    "student on their own numbers")
    pg.add_argument("--show-errors", action="store_true",
                    help="put the full text of a submission's exceptions in its feedback (default: the class only)")
    pg.add_argument("--no-isolation", action="store_true",
                    help="grade without bubblewrap (a submission can then read and write what you can)")
    pa = sub.add_parser("assign", help="write per-student exercise sheets from a secret key",
                        description="Write one sheet per student of ROSTER (SHEETS/STUDENT.md) with their "
                        "own numbers for the assigned exercises that have variants (the numeric "
                        "exercises of chapters 1-8 except 7), drawn from KEYFILE and the student id; "
                        "'grade --key KEYFILE' judges each student on those numbers. A missing "
                        "KEYFILE is created with a new random key.")
    pa.add_argument("--key", metavar="KEYFILE", required=True, help="the secret key (created if missing)")
    pa.add_argument("--roster", metavar="FILE", required=True, help="student ids, one per line")
    pa.add_argument("--exercises", metavar="IDS", required=True, help="the assignment: 1.3,5.1,8.1")
    pa.add_argument("--out", metavar="SHEETS", default="sheets", help="folder for the sheets (default sheets)")


def write_sheets(key: str, students: list[str], exercise_ids: list[str], folder: Path) -> list[Path]:
    """``folder/STUDENT.md`` for each student: their code and each exercise with their numbers."""
    from rapp.exercises import catalog, variants

    found = {ex.id: ex for ex in catalog()}
    paths = []
    for student in students:
        c = variants.code(key, student)
        lines = [f"# Exercises for {student}", "",
                 f"Your code is `{c}`. Check an answer with your numbers as",
                 f'`rapp.exercises.check("ID", answer, variant="{c}")`.', ""]
        for ex_id in exercise_ids:
            ex = found[ex_id]
            lines += [f"## Exercise {ex_id}: {ex.title}", ""]
            if variants.has_variant(ex_id):
                lines += [variants.statement(ex_id, c), "", ex.tolerance or "", ""]
            else:
                lines += ["As in the book (the same numbers for everyone).", ""]
        path = Path(folder) / f"{check_student_id(student, 'student')}.md"
        _write_text(path, "\n".join(lines))
        paths.append(path)
    return paths


def _input_error(exc: Exception, err) -> int:
    """One line naming what was wrong with the instructor's input; exit status 2."""
    if isinstance(exc, (OSError, UnicodeError)):
        print(f"rapp: error: {getattr(exc, 'filename', '') or 'input'}: {exc.__class__.__name__}", file=err)
    else:
        print(f"rapp: error: {exc}", file=err)
    return 2


def run_assign(args, out, err) -> int:
    """``python -m rapp assign``: 0 done, 2 bad input (one line naming it)."""
    try:
        students = read_roster(Path(args.roster))
        ids = list(parse_weights(args.exercises))
        if not students:
            raise ValueError(f"--roster: {args.roster} names no student")
        inputs = [(args.roster, "roster"), (args.key, "key file")]
        _check_output_folder(Path(args.out), "--out", inputs, [f"{s}.md" for s in students])
        key = read_key(Path(args.key), create=True)
    except (OSError, ValueError) as exc:
        return _input_error(exc, err)
    from rapp.exercises import variants
    try:
        paths = write_sheets(key, students, ids, Path(args.out))
    except OSError as exc:
        print(f"rapp: error: --out: cannot write the sheets ({exc.strerror or type(exc).__name__})", file=err)
        return 2
    own = [i for i in ids if variants.has_variant(i)]
    print(f"wrote {len(paths)} sheets to {args.out}/; own numbers for {', '.join(own) or 'none'}", file=out)
    return 0


def _limits_of(args) -> GradeLimits:
    t, m = args.time, args.memory
    if not (isinstance(t, float) and math.isfinite(t) and TIME_RANGE[0] <= t <= TIME_RANGE[1]):
        raise ValueError(f"--time: give {TIME_RANGE[0]:g} to {TIME_RANGE[1]:g} seconds of CPU time, got {t!r}")
    if not (MEMORY_RANGE[0] <= m <= MEMORY_RANGE[1]):
        raise ValueError(f"--memory: give {MEMORY_RANGE[0]} to {MEMORY_RANGE[1]} MB, got {m}")
    return GradeLimits(run=t, memory=m * 2**20, isolate=not args.no_isolation, show_errors=args.show_errors)


_REACH = ("without isolation a submission runs as you: it can read and write your files (the key, "
          "the roster, classmates' submissions and feedback, the rapp package) and see your processes")


def run(args, out, err) -> int:
    """``python -m rapp grade``: 0 done, 2 bad input or no isolation (one line naming it)."""
    folder = Path(args.submissions)
    if not folder.is_dir():
        print(f"rapp: error: submissions: {folder} is not a folder", file=err)
        return 2
    fmt = getattr(args, "format", "csv") or "csv"
    out_path = Path(args.out if args.out is not None else ("gradescope" if fmt == "gradescope" else "grades.csv"))
    try:
        limits = _limits_of(args)
        if args.weights:
            weights = read_weights_file(Path(args.weights))
        elif args.exercises:
            weights = parse_weights(args.exercises)
        else:
            raise ValueError("--exercises: name the assignment, e.g. --exercises 5.1,5.2:2")
        roster = read_roster(Path(args.roster)) if args.roster else None
        key = read_key(Path(args.key)) if args.key else None
        subs, _ = find_submissions(folder)
        students = set(subs) | set(roster or ())
        inputs = [(args.roster, "roster"), (args.key, "key file"), (args.weights, "weights file"),
                  (str(folder), "submissions folder")] + [(str(f.path), "submission") for f in subs.values()]
        if fmt == "gradescope":
            _check_output_folder(out_path, "--out", inputs, [])
        else:
            _check_output_file(out_path, "--out", inputs)
        if os.path.abspath(out_path).startswith(os.path.abspath(folder) + os.sep) and out_path.suffix.lower() in SUFFIXES:
            raise ValueError(f"--out: {out_path} would be read as a submission")
        _check_output_folder(Path(args.feedback), "--feedback", inputs + [(str(out_path), "--out")],
                             [f"{s}.txt" for s in students])
    except (OSError, ValueError) as exc:
        return _input_error(exc, err)
    if limits.isolate and isolation_available() is None:
        print("rapp: error: bubblewrap (bwrap) is not installed or cannot isolate submissions here; install it "
              "(apt-get install bubblewrap) or pass --no-isolation", file=err)
        return 2
    if not limits.isolate:
        print(f"rapp: warning: {_REACH}.", file=err)
    failed: list[str] = []
    results: list[StudentResult] = []  # everyone graded so far: written even if the run stops

    def progress(r: StudentResult) -> None:
        results.append(r)
        try:
            write_feedback(r, Path(args.feedback))
            if fmt == "gradescope":
                write_gradescope(r, out_path)
        except (OSError, ValueError) as exc:
            failed.append(f"{r.student}: {getattr(exc, 'strerror', None) or type(exc).__name__}")
        bad = [n for n in r.notes if n.startswith("the submission") or n == "no submission found"]
        line = f"{r.student}: {r.points:g}/{r.max_points:g}" + (f"  ({bad[0]})" if bad else "")
        print(line, file=out, flush=True)

    skipped: list[str] = []
    try:
        grade_class(folder, weights, roster, limits, progress, key, skipped)
    finally:
        key = None
        if fmt == "csv":
            write_csv(results, out_path)
        elif fmt == "canvas":
            write_canvas(results, out_path, args.assignment)
    for line in skipped:
        print(f"skipped {line}", file=out)
    for line in failed:
        print(f"rapp: warning: feedback not written for {line}", file=err)
    print(f"graded {len(results)} students; wrote {out_path} and {args.feedback}/", file=out)
    return 0


if __name__ == "__main__":  # pragma: no cover
    serve_submission(sys.argv[1:])
