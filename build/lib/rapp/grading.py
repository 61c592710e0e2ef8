"""Grade a class: a folder of submissions in, a CSV of points and one feedback file per student out.

``python -m rapp grade SUBMISSIONS --exercises 5.1,5.2:2 --out grades.csv``

A submission is a notebook (``.ipynb``) or a Python file (``.py``) named after the student
(``alice.ipynb`` is student ``alice``). Each runs in its own sandbox: a fresh Python process in
its own process group and a temporary folder, with CPU-time, memory and wall-clock limits
and, on Linux x86-64, a seccomp filter that refuses signals to other processes (see
:mod:`rapp.exercises.sandbox`). A notebook's code cells run in order; a cell that fails is
noted in the feedback and the next one runs, as "Run All" would not stop a grader.

Where the answers are read (documented in the book's "For instructors" page):

1. a dict named ``answers`` at the top level, ``{"5.2": h, "Exercise 5.1": 71}``; otherwise
2. the last answer passed to ``rapp.exercises.check(id, answer)`` for each id, so a notebook
   whose check cells were filled in, as the book's chapters have them, needs nothing else.

Only plain data and function calls on copies of the hidden cases cross from the sandbox to the
grader; every verdict is computed in the grader (:func:`rapp.exercises.check`'s judges).

Examples
--------
>>> parse_weights("5.1, 5.2:2,Exercise 6.1")
{'5.1': 1.0, '5.2': 2.0, '6.1': 1.0}
"""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["GradeLimits", "StudentResult", "parse_weights", "read_roster", "read_key", "grade_submission",
           "grade_class", "write_csv", "write_feedback", "write_sheets", "add_parser", "run", "run_assign",
           "serve_submission"]

SUFFIXES = (".ipynb", ".py")


@dataclass(frozen=True)
class GradeLimits:
    """What one submission may use.

    Attributes
    ----------
    run : float
        Wall-clock seconds to execute the submission (its cells or its module).
    memory : int
        Bytes of address space beyond the interpreter's start.
    restarts : int
        Times a submission is started again after one answer hung or crashed it.
    """

    run: float = 60.0
    memory: int = 1 << 30
    restarts: int = 2


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
    for row in csv.reader(Path(path).read_text(encoding="utf-8").splitlines()):
        if not row or row[0].strip().lower() in ("exercise", "") or row[0].lstrip().startswith("#"):
            continue
        items.append(f"{row[0]}:{row[1]}" if len(row) > 1 and row[1].strip() else row[0])
    return parse_weights(",".join(items))


def read_roster(path: Path) -> list[str]:
    """Student ids, one per line (the first CSV column; a header ``student`` and ``#`` lines skipped)."""
    out = []
    for row in csv.reader(Path(path).read_text(encoding="utf-8").splitlines()):
        if row and row[0].strip() and not row[0].lstrip().startswith("#") and row[0].strip().lower() != "student":
            out.append(row[0].strip())
    return out


# --- the sandboxed side: execute a submission, then serve its answers -------------------------

_SERVE = "import sys; from rapp.grading import serve_submission; serve_submission(sys.argv[1:])"


def serve_submission(argv: list[str]) -> None:
    """Entry point of the sandbox process that :func:`grade_submission` starts (public: it is
    named in that process's command line): ``SUBMISSION RFD WFD RUN_SECONDS CPU_SECONDS MEMORY``.

    It confines itself to the limits, executes the submission and answers the grader's
    questions on the two pipes; it is not meant to be called in a process of one's own.
    """
    from rapp.exercises.sandbox import Limits, confine, send_message, serve, to_plain

    path, rfd, wfd = argv[0], int(argv[1]), int(argv[2])
    limits = Limits(wall=float(argv[3]), cpu=float(argv[4]), memory=int(argv[5]))
    confine(limits)
    devnull = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(devnull, fd)
    sys.stdout = sys.stderr = io.StringIO()
    try:
        namespace, notes = _execute(Path(path))
        answers = _answers_of(namespace)
        reply = {"ok": to_plain({"keys": sorted(answers), "notes": notes})}
    except BaseException as exc:  # the submission could not be read: say why, in one line
        answers = {}
        reply = {"raised": _one_line(exc)}
    try:
        sys.stdout = sys.stderr = io.StringIO()
        send_message(wfd, json.dumps(reply).encode())
    except BaseException:
        os._exit(0)
    serve(answers, rfd, wfd)
    os._exit(0)


def _one_line(exc: BaseException) -> str:
    try:
        text = " ".join(str(exc).split())
    except BaseException:
        text = ""
    where = f" (line {exc.lineno})" if isinstance(exc, SyntaxError) and exc.lineno else ""
    return f"{type(exc).__name__}{where}: {text[:300]}" if text else type(exc).__name__


def _code_of(path: Path) -> list[str]:
    """The code to run: a .py file whole, or a notebook's code cells (magics and ! lines left out)."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".py":
        return [text]
    try:
        nb = json.loads(text)
        cells = nb["cells"]
    except (ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"not a notebook ({_one_line(exc)})") from None
    code = []
    for cell in cells:
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        source = cell.get("source", "")
        source = "".join(source) if isinstance(source, list) else str(source)
        lines = [("pass  # " + line) if line.lstrip().startswith(("%", "!")) else line
                 for line in source.split("\n")]
        code.append("\n".join(lines))
    return code


def _execute(path: Path) -> tuple[dict, list[str]]:
    """Run the submission's code in one namespace, recording every rapp.exercises.check call."""
    import rapp
    import rapp.exercises as exercises

    recorded: dict = {}
    real_check = exercises.check

    def recording_check(exercise_id, answer):
        key = exercises.normalize_id(exercise_id)
        if key is not None:
            recorded[key] = answer
        return exercises.Verdict(key or "?", False, "recorded for grading; the verdict comes later.")

    exercises.check = recording_check
    namespace: dict = {"__name__": "__main__", "rapp": rapp}
    notes = []
    try:
        for i, source in enumerate(_code_of(path)):
            try:
                exec(compile(source, f"<{path.name} cell {i + 1}>", "exec"), namespace)
            except SyntaxError as exc:
                notes.append(f"cell {i + 1}: {_one_line(exc)}")
                if path.suffix == ".py":
                    raise
            except Exception as exc:
                notes.append(f"cell {i + 1}: {_one_line(exc)}")
    finally:
        exercises.check = real_check
    namespace["__recorded__"] = recorded
    return namespace, notes[:20]


def _answers_of(namespace: dict) -> dict:
    from rapp.exercises import normalize_id

    given = namespace.get("answers")
    if type(given) is dict:
        return {normalize_id(k): v for k, v in given.items() if normalize_id(k)}
    return dict(namespace.get("__recorded__", {}))


# --- the grader's side ------------------------------------------------------------------------

class _Submission:
    """The sandbox process of one submission, started again (up to a limit) after a crash."""

    def __init__(self, path: Path, limits: GradeLimits, budget: float):
        self.path, self.limits, self.budget = path, limits, budget
        self.starts, self.box, self.keys, self.notes, self.error = 0, None, set(), [], None
        self._tmp = None

    def start(self) -> bool:
        from rapp.exercises.sandbox import Limits, Sandbox, SandboxError

        self.close()
        self.starts += 1
        self._tmp = tempfile.mkdtemp(prefix="rapp-grade-")
        copy = Path(self._tmp) / self.path.name
        shutil.copyfile(self.path, copy)
        p_read, c_write = os.pipe()
        c_read, p_write = os.pipe()
        env = {k: v for k, v in os.environ.items() if k in ("PATH", "PYTHONPATH", "HOME", "LANG", "LC_ALL")}
        env.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", MPLBACKEND="Agg",
                   PYTHONDONTWRITEBYTECODE="1", PYTHONHASHSEED="0")
        cpu = self.limits.run + self.budget + 5
        limits = Limits(wall=self.limits.run, cpu=cpu, memory=self.limits.memory)
        popen = subprocess.Popen(
            [sys.executable, "-c", _SERVE, str(copy), str(c_read), str(c_write), str(limits.wall),
             str(cpu), str(limits.memory)],
            cwd=self._tmp, env=env, pass_fds=(c_read, c_write), start_new_session=True,
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(c_read), os.close(c_write)
        self.box = Sandbox.attach(popen, p_read, p_write, limits)
        try:
            ready = self.box.receive()
        except SandboxError as exc:
            self.error = f"did not finish running within {self.limits.run:g} s" if "no answer within" in str(exc) \
                else f"stopped while running: {exc}"
            self.close()
            return False
        if "raised" in ready:
            self.error = f"could not be run: {str(ready['raised'])[:300]}"
            self.close()
            return False
        from rapp.exercises.sandbox import from_plain
        try:
            info = from_plain(ready.get("ok"))
            self.keys, self.notes = set(info["keys"]), list(info["notes"])
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


def grade_submission(path: Path, weights: dict[str, float], limits: GradeLimits = GradeLimits(),
                     variant_code: str | None = None) -> StudentResult:
    """Every assigned exercise of one submission, judged; never raises.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "bob.py").write_text('answers = {"5.1": 71, "Exercise 5.3": 14}')
    >>> r = grade_submission(d / "bob.py", {"5.1": 1.0, "5.3": 2.0})
    >>> [(row[0], row[1], row[3]) for row in r.rows], r.points
    ([('5.1', 1.0, 'correct'), ('5.3', 0.0, 'wrong')], 1.0)

    With ``variant_code`` (from :func:`rapp.exercises.variants.code`), the exercises that have
    per-student numbers are judged with that student's numbers.
    """
    from rapp.exercises import variants
    from rapp.exercises import catalog, verdict_in_sandbox
    from rapp.exercises import check

    exercises = {ex.id: ex for ex in catalog()}
    result = StudentResult(Path(path).stem)
    budget = sum(exercises[e].time_limit for e in weights)
    sub = _Submission(Path(path), limits, budget)
    try:
        running = sub.start()
        result.notes += [f"while running: {n}" for n in sub.notes]
        for ex_id, weight in weights.items():
            ex = exercises[ex_id]
            if not running:
                result.rows.append((ex_id, 0.0, weight, "error", f"the submission {sub.error}."))
                continue
            if ex_id not in sub.keys:
                verdict = check(ex_id, None)
                result.rows.append((ex_id, 0.0, weight, "unanswered", verdict.message))
                continue
            sub.box.deadline = time.monotonic() + ex.time_limit
            own = variants.judge(ex_id, variant_code) if variant_code and variants.has_variant(ex_id) else None
            verdict = verdict_in_sandbox(ex, sub.box, ex_id, own)
            result.rows.append((ex_id, weight if verdict else 0.0, weight,
                                "correct" if verdict else "wrong", verdict.message))
            if sub.box.dead:  # the answer hung or ended the process: start it again for the next one
                running = sub.starts <= limits.restarts and sub.start()
                if not running and not sub.error:
                    sub.error = "kept stopping (hung or crashed more than the restarts allowed)"
    except BaseException as exc:  # never lose the class for one student
        done = {r[0] for r in result.rows}
        for ex_id, weight in weights.items():
            if ex_id not in done:
                result.rows.append((ex_id, 0.0, weight, "error", f"the grader failed on it ({type(exc).__name__})."))
        if isinstance(exc, KeyboardInterrupt):
            raise
    finally:
        sub.close()
    if sub.error and not any(r[3] != "error" for r in result.rows):
        result.notes.insert(0, f"the submission {sub.error}")
    return result


def find_submissions(folder: Path) -> dict[str, Path]:
    """Student id → submission file (``.ipynb`` preferred over ``.py`` when both exist)."""
    found: dict[str, Path] = {}
    for path in sorted(Path(folder).iterdir()):
        if path.is_file() and path.suffix in SUFFIXES and not path.name.startswith("."):
            if path.stem not in found or path.suffix == ".ipynb":
                found[path.stem] = path
    return found


def grade_class(folder: Path, weights: dict[str, float], roster: list[str] | None = None,
                limits: GradeLimits = GradeLimits(), progress=None, key: str | None = None) -> list[StudentResult]:
    """Grade every submission in ``folder`` (and list the roster's students who sent none).

    With the instructor's ``key``, each student is judged on their own numbers (``assign``).
    """
    from rapp.exercises import variants

    subs = find_submissions(folder)
    students = list(roster) if roster is not None else sorted(subs)
    if roster is not None:
        students += sorted(s for s in subs if s not in set(roster))
    results = []
    for student in students:
        if student not in subs:
            r = StudentResult(student, [(e, 0.0, w, "missing", "no submission.") for e, w in weights.items()])
            r.notes.append("no submission found")
        else:
            r = grade_submission(subs[student], weights, limits,
                                 variants.code(key, student) if key is not None else None)
            if roster is not None and student not in roster:
                r.notes.append("not on the roster")
        results.append(r)
        if progress:
            progress(r)
    return results


def write_csv(results: list[StudentResult], path: Path) -> None:
    """One row per student and exercise: student, exercise, points, max_points, verdict (atomic)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["student", "exercise", "points", "max_points", "verdict"])
    for r in results:
        for ex_id, points, max_points, verdict, _ in r.rows:
            w.writerow([r.student, ex_id, f"{points:g}", f"{max_points:g}", verdict])
    _atomic_write(Path(path), buf.getvalue())


def write_feedback(result: StudentResult, folder: Path) -> Path:
    """``folder/STUDENT.txt``: the total, then each exercise's verdict and hint (atomic)."""
    lines = [f"Feedback for {result.student}: {result.points:g} of {result.max_points:g} points", ""]
    lines += [f"Note: {n}" for n in result.notes]
    if result.notes:
        lines.append("")
    for ex_id, points, max_points, verdict, message in result.rows:
        lines.append(f"Exercise {ex_id} ({points:g}/{max_points:g}, {verdict}): {message}")
    path = Path(folder) / f"{result.student}.txt"
    _atomic_write(path, "\n".join(lines) + "\n")
    return path


def _atomic_write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


# --- the command line -------------------------------------------------------------------------

def add_parser(sub) -> None:
    """The ``grade`` subcommand of ``python -m rapp``."""
    pg = sub.add_parser("grade", help="grade a folder of student submissions (sandboxed)",
                        description="Run every submission (STUDENT.ipynb or STUDENT.py) in SUBMISSIONS "
                        "in its own sandbox, judge its answers (a dict 'answers', or the last "
                        "rapp.exercises.check call per exercise) and write a CSV (student, exercise, "
                        "points, max_points, verdict) and one feedback file per student.")
    pg.add_argument("submissions", help="folder of STUDENT.ipynb / STUDENT.py files")
    pg.add_argument("--exercises", metavar="IDS",
                    help="the assignment, ids with optional weights: 5.1,5.2:2,6.1")
    pg.add_argument("--weights", metavar="FILE.csv", help="the assignment as a CSV: exercise,weight")
    pg.add_argument("--roster", metavar="FILE", help="student ids, one per line (missing ones get 0)")
    pg.add_argument("--out", metavar="GRADES.csv", default="grades.csv", help="the CSV (default grades.csv)")
    pg.add_argument("--feedback", metavar="DIR", default="feedback", help="feedback folder (default feedback)")
    pg.add_argument("--time", metavar="SECONDS", type=float, default=60.0,
                    help="wall-clock seconds to run one submission (default 60)")
    pg.add_argument("--memory", metavar="MB", type=int, default=1024,
                    help="memory a submission may add, in MB (default 1024)")
    pg.add_argument("--key", metavar="KEYFILE", help="the instructor's key file of 'assign': judge each "
                    "student on their own numbers")
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


def read_key(path: Path, create: bool = False) -> str:
    """The key in ``path`` (stripped); a new random one is written (mode 600) when ``create``."""
    path = Path(path)
    if create and not path.exists():
        import secrets
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(secrets.token_hex(32) + "\n")
    key = path.read_text(encoding="utf-8").strip()
    if len(key) < 16:
        raise ValueError(f"--key: {path} holds fewer than 16 characters; use a longer secret")
    return key


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
        path = Path(folder) / f"{student}.md"
        _atomic_write(path, "\n".join(lines))
        paths.append(path)
    return paths


def _input_error(exc: Exception, err) -> int:
    """One line naming what was wrong with the instructor's input; exit status 2.

    A file that cannot be read (OSError, or bytes that are not UTF-8) is named by its path; a
    ValueError says itself which option is wrong.
    """
    if isinstance(exc, (OSError, UnicodeDecodeError)):
        print(f"rapp: error: {getattr(exc, 'filename', '') or 'input'}: {exc.__class__.__name__}", file=err)
    else:
        print(f"rapp: error: {exc}", file=err)
    return 2


def run_assign(args, out, err) -> int:
    """``python -m rapp assign``: 0 done, 2 bad input (one line naming it)."""
    try:
        key = read_key(Path(args.key), create=True)
        students = read_roster(Path(args.roster))
        ids = list(parse_weights(args.exercises))
        if not students:
            raise ValueError(f"--roster: {args.roster} names no student")
    except (OSError, ValueError) as exc:
        return _input_error(exc, err)
    from rapp.exercises import variants
    paths = write_sheets(key, students, ids, Path(args.out))
    own = [i for i in ids if variants.has_variant(i)]
    print(f"wrote {len(paths)} sheets to {args.out}/; own numbers for {', '.join(own) or 'none'}", file=out)
    return 0


def run(args, out, err) -> int:
    """``python -m rapp grade``: 0 done, 2 bad input (one line naming it)."""
    folder = Path(args.submissions)
    if not folder.is_dir():
        print(f"rapp: error: submissions: {folder} is not a folder", file=err)
        return 2
    try:
        if args.weights:
            weights = read_weights_file(Path(args.weights))
        elif args.exercises:
            weights = parse_weights(args.exercises)
        else:
            raise ValueError("--exercises: name the assignment, e.g. --exercises 5.1,5.2:2")
        roster = read_roster(Path(args.roster)) if args.roster else None
        key = read_key(Path(args.key)) if args.key else None
    except (OSError, ValueError) as exc:
        return _input_error(exc, err)
    if not (args.time > 0 and args.memory > 0):
        print("rapp: error: --time and --memory must be > 0", file=err)
        return 2
    limits = GradeLimits(run=args.time, memory=args.memory * 2**20)

    def progress(r: StudentResult) -> None:
        write_feedback(r, Path(args.feedback))
        bad = [n for n in r.notes if n.startswith("the submission") or n == "no submission found"]
        line = f"{r.student}: {r.points:g}/{r.max_points:g}" + (f"  ({bad[0]})" if bad else "")
        print(line, file=out, flush=True)

    results = grade_class(folder, weights, roster, limits, progress, key)
    write_csv(results, Path(args.out))
    print(f"graded {len(results)} students; wrote {args.out} and {args.feedback}/", file=out)
    return 0


if __name__ == "__main__":  # pragma: no cover
    serve_submission(sys.argv[1:])
