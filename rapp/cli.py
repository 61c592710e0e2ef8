"""Command line: ``python -m rapp plan|check|list|schema|compare`` (and ``grade``, ``assign``, ``--version``).

Exit codes: 0 done; 1 a planning answer (no path, no IK solution, a straight
line the end effector cannot follow), said in one line; 2 bad input, one line on stderr naming the field or option and what is
wrong; 3 a failed verification or an unexpected internal error (still one
line, never a traceback); 130 interrupted (Ctrl-C, wherever it lands, start-up
included: see :mod:`rapp.interrupts`); 143 terminated (SIGTERM, handled as Ctrl-C is).

Every output path is checked before any planning work: its folder exists and
is writable, its format can be written, and it is neither the input scenario
nor another output. The outputs of a run are written to temporary files and renamed
into place together at the end (:class:`rapp.files.OutputBatch`), so an error, Ctrl-C or
SIGTERM never leaves a half-written file, destroys a previous one, or mixes the files of two
runs.

Everything printed passes through :func:`printable`, so a scenario's name or a
file name cannot inject terminal escape sequences or make printing fail.
Warnings (numpy's RuntimeWarning included) never reach the terminal: they are
counted and mentioned in one ``note:`` line of the normal output.

Examples
--------
>>> main(["list"])  # doctest: +ELLIPSIS
default ...
0
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import os
import re
import shutil
import sys
import warnings
from contextlib import contextmanager, nullcontext
from typing import Any

import numpy as np

from rapp.errors import (InvalidValue, NoIKSolution, NoPathFound, PathNotFollowable, RappError,
                         ScenarioError)
from rapp.files import OutputBatch
from rapp import compare_command, interrupts, planner, progress, results, scenario

# matplotlib and rapp.plotting (about 1 s to import, twice a whole plan) are imported only when
# --plot or --animate is given: `check`, `list` and a plan without a figure start fast. A figure
# costs that import on top of the plan; benchmarks/bench_cli.py records how much.

__all__ = ["main", "build_parser", "printable", "COMMANDS", "OUT_FORMATS", "command"]

#: What ``plan --out`` can write (``--format``); without it, ``.csv`` names a CSV, anything
#: else a result file.
OUT_FORMATS = ("result", "csv", "joint-trajectory")

EXIT_OK, EXIT_NO_PLAN, EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
#: 128 + SIGTERM: ended by ``kill`` (handled as Ctrl-C is: temporary files removed, one line).
EXIT_TERMINATED = interrupts.EXIT_SIGTERM
#: 128 + SIGPIPE: the exit status of a program whose output pipe was closed by its reader.
EXIT_BROKEN_PIPE = 141

#: Frames per second of a saved animation (GIF and MP4 alike).
ANIMATION_FPS = 15

# Besides the C0 controls: DEL and C1 controls, lone surrogates, the line and paragraph
# separators (a terminal may break the line there) and the bidirectional embeddings,
# overrides and isolates (they reorder what is shown).
_MORE_UNSAFE = r"\x7f-\x9f\ud800-\udfff\u2028\u2029\u202a-\u202e\u2066-\u2069"
_UNSAFE_RE = re.compile(rf"[\x00-\x1f{_MORE_UNSAFE}]")
_UNSAFE_BUT_NEWLINE_RE = re.compile(rf"[\x00-\x09\x0b-\x1f{_MORE_UNSAFE}]")


def _escape(match) -> str:
    c = ord(match.group())
    return f"\\x{c:02x}" if c <= 0xFF else f"\\u{c:04x}"


def printable(text, *, newline: bool = False) -> str:
    """``text`` with every character that is unsafe on a terminal written as an escape.

    C0 controls (tab and newline included), DEL and C1 controls become
    ``\\xNN``; lone surrogates (from a JSON ``"\\ud800"`` or an undecodable
    file name) become ``\\udNNN``; the Unicode line and paragraph separators
    and the bidirectional controls become ``\\uNNNN``. Everything else,
    backslashes included, is kept, so ordinary text reads as it is.

    Parameters
    ----------
    text : object
        Converted with ``str`` first.
    newline : bool, default False
        Keep ``"\\n"`` (for text of several lines, such as the scenario echo).

    Returns
    -------
    str
        Text that encodes to UTF-8 without error and holds no control characters
        (other than ``"\\n"`` when ``newline`` is true).

    Examples
    --------
    >>> printable("\\x1b[31mred\\x1b[0m")
    '\\\\x1b[31mred\\\\x1b[0m'
    >>> print(printable("bad \\ud800 name\\x85"))
    bad \\ud800 name\\x85
    >>> printable("two\\nlines"), printable("two\\nlines", newline=True)
    ('two\\\\x0alines', 'two\\nlines')
    >>> printable("café → ok")
    'café → ok'
    """
    pattern = _UNSAFE_BUT_NEWLINE_RE if newline else _UNSAFE_RE
    return pattern.sub(_escape, str(text))


class _UsageError(Exception):
    """argparse's complaint, turned into one line and exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse would print usage and call sys.exit
        raise _UsageError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``python -m rapp`` (each subcommand has ``--help``).

    Examples
    --------
    >>> args = build_parser().parse_args(["plan", "--out", "r.json"])
    >>> args.command, args.scenario, args.out, args.timings
    ('plan', 'default', 'r.json', False)
    """
    import rapp

    p = _Parser(prog="rapp", description="2D robot-arm path planning (2D-RAPP).")
    p.add_argument("--version", action="version", version=f"rapp {rapp.__version__}")
    sub = p.add_subparsers(dest="command", metavar="{plan,check,list,schema,compare,grade,assign}", parser_class=_Parser)
    sub.required = True
    pp = sub.add_parser("plan", help="plan, time and verify a trajectory",
                        description="Plan a collision-free trajectory for SCENARIO (a JSON file "
                        "or an embedded scenario name; default: the embedded default), echo the "
                        "inputs, verify the result and print the report. Output paths are "
                        "checked before planning; none may be the scenario file or another "
                        "output. The result file is the same byte for byte for the same "
                        "scenario unless --timings is given.")
    pp.add_argument("scenario", nargs="?", default="default",
                    help="scenario file or embedded name (see 'rapp list')")
    pp.add_argument("--out", metavar="RESULT.json",
                    help="write the result (atomically): rapp's result JSON, or a CSV of t and "
                    "each joint's q, qd, qdd when the name ends in .csv (see --format)")
    pp.add_argument("--format", choices=OUT_FORMATS, default=None,
                    help="what --out holds: 'result' (rapp's JSON, the default), 'csv' (the "
                    "default for .csv) or 'joint-trajectory' (JSON: joint_names and points "
                    "with positions, velocities, accelerations, time_from_start, as ROS's "
                    "JointTrajectory)")
    pp.add_argument("--plot", metavar="FIG.png",
                    help="save a figure of the plan (atomically), drawn with matplotlib; the "
                    "extension picks the format: .png, .svg, .pdf, ...")
    pp.add_argument("--animate", metavar="ANIM.gif",
                    help="save an animation of the arm (atomically): .gif, or .mp4 when "
                    "ffmpeg is installed")
    pp.add_argument("--timings", action="store_true",
                    help="print the wall-clock time per stage and, apart, numba's compilation "
                    "(also with --quiet); store them in the --out result, which then differs "
                    "from run to run")
    pp.add_argument("--quiet", "-q", action="store_true",
                    help="print only the one-line summary (and the stage times with --timings); "
                    "no progress line (shown on stderr when it is a terminal and work takes "
                    "more than a moment)")
    pc = sub.add_parser("check", help="validate a scenario and echo it; plan nothing",
                        description="Validate SCENARIO and echo every input with units (R2).")
    pc.add_argument("scenario", help="scenario file or embedded name")
    sub.add_parser("list", help="list the embedded scenarios",
                   description="List the embedded scenarios with their descriptions.")
    ps = sub.add_parser("schema", help="print the JSON Schema of scenario or result files",
                        description="Print the JSON Schema (draft 2020-12) of a scenario file "
                        "or of a result file, as the package ships it (rapp/schemas/).")
    ps.add_argument("which", choices=("scenario", "result"), help="which file's schema")
    compare_command.add_parser(sub)
    _grading().add_parser(sub)  # the instructors' subcommands live with their logic
    return p


def _one_line(text) -> str:
    return " ".join(printable(text, newline=True).split())


def _say(stream, text="", *, lines: bool = False) -> None:
    """Print ``text`` made :func:`printable`; never fails on the stream's encoding."""
    text = printable(text, newline=lines)
    encoding = getattr(stream, "encoding", None)
    if encoding:
        try:
            text.encode(encoding)
        except UnicodeEncodeError:  # e.g. an ASCII terminal and an accented name
            text = text.encode(encoding, "backslashreplace").decode(encoding)
        except LookupError:
            pass
    print(text, file=stream)


# --------------------------------------------------------------------------- output paths


def _plot_formats() -> dict:
    """Extension (no dot) -> "" when ``--plot`` can write it, else why it cannot."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    formats = {ext: "" for ext in FigureCanvasAgg.get_supported_filetypes()}
    tex = matplotlib.rcParams["pgf.texsystem"]
    if "pgf" in formats and not shutil.which(tex):
        # The pgf backend measures text with LaTeX; without it savefig fails after planning.
        formats["pgf"] = f"needs {tex}, which is not installed"
    features: Any
    try:
        from PIL import features
    except ImportError:  # pragma: no cover - Pillow is a dependency of matplotlib
        features = None
    for ext in ("webp", "avif"):
        if ext in formats:
            try:
                ok = features is not None and features.check_module(ext)
            except ValueError:  # a Pillow too old to know the format
                ok = False
            if not ok:
                formats[ext] = f"needs Pillow built with {ext} support"
    return formats


def _check_format(path: str, option: str) -> None:
    ext = os.path.splitext(path)[1].lower()
    if option == "--plot":
        formats = _plot_formats()
        usable = ", ".join("." + e for e, why in sorted(formats.items()) if not why)
        if not ext:
            raise InvalidValue(f"{path!r} has no extension to pick the format (one of {usable})",
                               field=option)
        why = formats.get(ext[1:])
        if why is None:
            raise InvalidValue(f"unsupported extension {ext!r} (one of {usable})", field=option)
        if why:
            raise InvalidValue(f"cannot write {ext!r}: {why}", field=option)
    elif option == "--animate":
        from matplotlib import animation

        writer = {".gif": "pillow", ".mp4": "ffmpeg"}.get(ext)
        if writer is None:
            raise InvalidValue(f"unsupported extension {ext!r} (use .gif, or .mp4 with ffmpeg)",
                               field=option)
        if not animation.writers.is_available(writer):
            raise InvalidValue(f"cannot write {ext!r}: matplotlib's {writer} writer is not "
                               "available" + (" (install ffmpeg, or use .gif)"
                                              if writer == "ffmpeg" else ""), field=option)


def _check_writable(path: str, option: str) -> None:
    """Refuse an output path before any work, naming the option."""
    if not path:
        raise InvalidValue("empty file name", field=option)
    if os.path.isdir(path):
        raise InvalidValue(f"{path!r} is a directory, not a file name", field=option)
    if os.path.exists(path) and not os.path.isfile(path):
        # os.replace would put a regular file in place of a device or a pipe (/dev/null!).
        raise InvalidValue(f"{path!r} is not a regular file", field=option)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidValue(f"folder {folder!r} does not exist", field=option)
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise InvalidValue(f"cannot write {path!r} (permission denied)", field=option)


def _same_file(a: str, b: str) -> bool:
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)  # hard links too
    except OSError:
        pass
    return os.path.normcase(os.path.realpath(a)) == os.path.normcase(os.path.realpath(b))


def _check_outputs(args) -> None:
    """Refuse, before any planning, every output that could not be written or would clobber
    the scenario or another output."""
    outputs = [(path, option) for path, option in
               ((args.out, "--out"), (args.plot, "--plot"), (args.animate, "--animate"))
               if path is not None]
    # The loader reads a file whenever one exists under that name, embedded name or not.
    source = args.scenario if os.path.exists(args.scenario) else None
    for i, (path, option) in enumerate(outputs):
        if path and source is not None and _same_file(path, source):
            raise InvalidValue(f"{path!r} is the scenario file {source!r}; refusing to "
                               "overwrite it", field=option)
        for other, other_option in outputs[:i]:
            if path and other and _same_file(path, other):
                raise InvalidValue(f"{path!r} is the same file as {other_option} {other!r}",
                                   field=option)
    for path, option in outputs:
        _check_writable(path, option)
        _check_format(path, option)


@contextmanager
def _writing(option: str):
    """Report a failed write (disk full, ...) under the option's name, not a temporary one."""
    try:
        yield
    except OSError as e:
        if _interrupted(e):
            raise
        raise InvalidValue(f"cannot write: {e.strerror or e}", field=option) from e


def _agg() -> None:
    """matplotlib's file-only backend, chosen before pyplot is imported: no display is opened."""
    import matplotlib

    matplotlib.use("Agg")


def _save_plot(p, s, path: str, ext: str) -> None:
    """The plan figure of :func:`rapp.plotting.plot_plan` in the format ``ext`` (PNG, SVG, PDF, ...),
    on a figure of its own (no pyplot), written to ``path`` (a temporary file of the batch)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from rapp import plotting

    fig = Figure(figsize=plotting.PLAN_FIGSIZE, layout="constrained")
    FigureCanvasAgg(fig)  # the canvas that writes every format _plot_formats lists
    plotting.plot_plan(p, s, fig=fig)
    # The target's name decides the format, whatever the temporary file is called.
    fig.savefig(path, dpi=100, format=ext[1:].lower())


def _save_animation(p, s, path: str, ext: str) -> None:
    _agg()
    from matplotlib import animation

    from rapp import plotting

    anim = plotting.animate(s.arm, p.q, s.obstacles, t=p.t)
    try:
        if ext.lower() == ".mp4":
            anim.save(path, writer=animation.FFMpegWriter(fps=ANIMATION_FPS), dpi=80)
        else:
            plotting.save_gif(anim, path, fps=ANIMATION_FPS)
    finally:
        plotting.close_animation(anim)


def _write_outputs(args, p, s) -> None:
    """Every output of the run, each to a temporary file, then all renamed into place at once:
    an error or an interrupt on the way leaves every previous file as it was."""
    options = {}
    try:
        with OutputBatch() as batch:
            if args.out:
                options[args.out] = "--out"
                kind = _out_format(args)
                with _writing("--out"):
                    if kind == "csv":
                        results.save_csv(p, batch.stage(args.out, ".csv"))
                    elif kind == "joint-trajectory":
                        results.save_joint_trajectory(p, batch.stage(args.out, ".json"))
                    else:
                        results.save_result(p, batch.stage(args.out, ".json"), timings=args.timings)
            if args.plot:
                options[args.plot] = "--plot"
                ext = os.path.splitext(args.plot)[1]
                with _writing("--plot"):
                    tmp = batch.stage(args.plot, ext)
                    _save_plot(p, s, tmp, ext)
            if args.animate:
                options[args.animate] = "--animate"
                ext = os.path.splitext(args.animate)[1]
                with _writing("--animate"):
                    _save_animation(p, s, batch.stage(args.animate, ext), ext)
    except OSError as e:  # renaming into place failed (the folder changed under the run)
        if _interrupted(e):
            raise
        option = options.get(getattr(e, "filename2", None), "--out")
        raise InvalidValue(f"cannot write: {e.strerror or e}", field=option) from e


# --------------------------------------------------------------------------- commands


def _shown(s):
    """The scenario with its free-text fields escaped one by one, so that a newline in a
    name cannot forge a line of the echo."""
    return dataclasses.replace(s, name=printable(s.name), description=printable(s.description),
                               source=printable(s.source))


def _say_notes(out, caught) -> None:
    if caught:
        first = caught[0]
        n = len(caught)
        _say(out, f"note: {n} warning{'s' if n > 1 else ''} silenced while running "
                  f"(first: {_one_line(first.message)})")


def _out_format(args) -> str:
    """What ``--out`` holds: ``--format``, else CSV for a ``.csv`` name, else the result file."""
    if getattr(args, "format", None):
        return args.format
    return "csv" if os.path.splitext(args.out or "")[1].lower() == ".csv" else "result"


def _cmd_schema(args, out) -> int:
    import json

    from rapp import schema

    _say(out, json.dumps(schema.shipped_schema(args.which), indent=2), lines=True)
    return EXIT_OK


def _cmd_list(out) -> int:

    for name in scenario.list_scenarios():
        s = scenario.load_scenario(name, check=False)
        _say(out, f"{name:<14}{s.description}")
    return EXIT_OK


def _cmd_check(args, out, caught) -> int:

    s = scenario.load_scenario(args.scenario)
    _say(out, scenario.echo(_shown(s)), lines=True)
    # The refusals plan would make of a setting (judged against this start and goal), too.
    planner.preflight(s)
    _say_notes(out, caught)
    _say(out, "scenario is valid")
    return EXIT_OK


def _progress(args, err, stage: str):
    """One updating line on stderr for long work, when stderr is a terminal and not --quiet.

    Erased when the work ends (normally or not), before anything else is printed.
    """
    try:
        terminal = err.isatty()
    except (AttributeError, ValueError, OSError):
        terminal = False
    if args.quiet or not terminal:
        return nullcontext()
    line = progress.TerminalLine(err)
    line(stage)
    return line


def _cmd_plan(args, out, err, caught) -> int:

    _check_outputs(args)
    s = scenario.load_scenario(args.scenario)
    if not args.quiet:
        _say(out, scenario.echo(_shown(s)), lines=True)
        _say(out)
    with _progress(args, err, "planning"):
        p = planner.plan(s)
    if not args.quiet:
        _say(out, str(p.report), lines=True)
    if args.timings:
        _say(out, "time per stage: " + ", ".join(f"{k} {v * 1e3:.1f} ms"
                                                 for k, v in p.timings.items() if k != "compile"))
        _say(out, f"compilation: {p.timings.get('compile', 0.0) * 1e3:.1f} ms (numba, before the "
                  "planner's clock; not counted in its time_budget)")
    with _progress(args, err, "writing " + ", ".join(
            o for o in (args.out, args.plot, args.animate) if o)):
        _write_outputs(args, p, s)
    if not args.quiet:
        _say_notes(out, caught)
    m = p.metrics
    assert p.report is not None  # rapp.plan always verifies
    status = "verified" if p.report.ok else "VERIFICATION FAILED"
    _say(out, f"planned {len(p.t)} samples over {float(p.t[-1]):g} s, "
              f"joint path {m.get('joint_length_rad', 0):.3f} rad, end effector "
              f"{m.get('ee_length_m', 0):.3f} m: {status}")
    if not p.report.ok:
        _say(err, "rapp: error: the trajectory failed verification: "
                  + ", ".join(c.name for c in p.report.failed))
        return EXIT_INTERNAL
    return EXIT_OK


#: Sub-command -> ``function(args, out, err, caught) -> exit code`` (``caught``: the warnings
#: collected so far). A new sub-command is its sub-parser in :func:`build_parser` and one
#: entry here; it gets the same handling of bad input, interrupts and warnings as the others.
COMMANDS = {
    "plan": _cmd_plan,
    "check": lambda args, out, err, caught: _cmd_check(args, out, caught),
    "list": lambda args, out, err, caught: _cmd_list(out),
    "schema": lambda args, out, err, caught: _cmd_schema(args, out),
    "compare": lambda args, out, err, caught: compare_command.run(args, out, err, say=_say),
    "grade": lambda args, out, err, caught: _grading().run(args, out, err),
    "assign": lambda args, out, err, caught: _grading().run_assign(args, out, err),
}


#: The teaching layer's module that adds the ``grade`` and ``assign`` subcommands, named rather
#: than imported: the interface does not import the teaching code (ARCHITECTURE.md, the layers);
#: it is loaded when the parser is built.
TEACHING_COMMANDS = "rapp.grading"


def _grading():
    """The module of :data:`TEACHING_COMMANDS` (``add_parser``, ``run``, ``run_assign``)."""
    return importlib.import_module(TEACHING_COMMANDS)


# --------------------------------------------------------------------------- main


def _interrupted(e: BaseException | None) -> bool:
    """Whether ``e`` is a Ctrl-C, or was raised while one was being handled.

    A KeyboardInterrupt inside ``Animation.save`` surfaces as an IndexError from the
    writer's cleanup; the interrupt is still there in the exception's context.
    """
    seen = set()
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def _signal_exit(e: BaseException | None) -> tuple:
    """Exit code and line for an interrupt found in ``e``'s chain (SIGTERM or Ctrl-C)."""
    seen = set()
    while e is not None and id(e) not in seen:
        if isinstance(e, interrupts.Terminated):
            return EXIT_TERMINATED, "rapp: terminated"
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return EXIT_INTERRUPTED, "rapp: interrupted"


def _failure(e: BaseException) -> tuple:
    """The exit code and the one stderr line for an exception that ended a command."""
    if _interrupted(e):
        return _signal_exit(e)
    if isinstance(e, _UsageError):
        return EXIT_BAD_INPUT, f"{_one_line(e)} (see --help)"
    if isinstance(e, ScenarioError):
        return EXIT_BAD_INPUT, f"rapp: error: {_one_line(e)}"
    if isinstance(e, NoIKSolution):
        return EXIT_NO_PLAN, f"rapp: no IK solution ({_one_line(e.reason)}): {_one_line(e)}"
    if isinstance(e, NoPathFound):
        return EXIT_NO_PLAN, f"rapp: no path: {_one_line(e)}"
    if isinstance(e, PathNotFollowable):
        return EXIT_NO_PLAN, f"rapp: no straight line: {_one_line(e)}"
    if isinstance(e, RappError):
        return EXIT_BAD_INPUT, f"rapp: error: {_one_line(e)}"
    if isinstance(e, OSError):
        name = _one_line(getattr(e, "filename", None) or "output")
        return EXIT_BAD_INPUT, f"rapp: error: {name}: {_one_line(e.strerror or e)}"
    if isinstance(e, MemoryError):
        # Every planner estimates its memory up front (grid cells, roadmap, tree nodes), so this
        # is a machine with less than their budget free: no one field is at fault.
        return EXIT_BAD_INPUT, ("rapp: error: out of memory (this machine has less free than "
                                "the planners' 1.5 GB budget; lower planner.cells for astar or "
                                "planner.samples for prm)")
    return EXIT_INTERNAL, f"rapp: internal error: {type(e).__name__}: {_one_line(e)}"


@contextmanager
def _warning_policy():
    """Collect every warning instead of printing it (the caller mentions them in a note).

    numpy's floating-point errors are pinned to "warn" so that they are collected too,
    whatever state imported code left numpy in; underflow stays ignored, as in numpy.
    A plan is judged by its verification, not by a warning on the way, so a warning is
    not an error; ``python -W error`` still makes it one (an internal error, one line).
    """

    with warnings.catch_warnings(record=True) as caught, \
            np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):
        yield caught


def _run(argv, out, err) -> int:
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as e:  # --help, --version
        return int(e.code or 0) if not isinstance(e.code, str) else EXIT_BAD_INPUT
    with _warning_policy() as caught:
        return COMMANDS[args.command](args, out, err, caught)


def _silence(stream) -> None:
    """Point a closed standard stream at /dev/null so that Python's exit flush cannot fail."""
    try:
        if stream is sys.stdout:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # not a real file (a test's StringIO)
        pass


def command() -> None:
    """The ``rapp`` command and ``python -m rapp``: :func:`main`, then the process ends at once.

    The interpreter's own shut-down would give Ctrl-C back its default action (death by
    SIGINT, no line) after the run has answered; instead the streams are flushed with the
    signals held back and the process exits with :func:`main`'s code, so a Ctrl-C that
    comes after the answer changes nothing.
    """
    code = main()
    with interrupts.deferred():
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed pipe: nothing more can be said on it
                pass
        os._exit(code)


def main(argv=None) -> int:
    """Run the command line; returns the exit code (see the module notes).

    Examples
    --------
    >>> main(["check", "no/such/file.json"])
    2
    """
    out, err = sys.stdout, sys.stderr
    said = None  # the exit code whose line has been said
    try:
        with interrupts.catching():  # SIGTERM too unwinds as an interrupt: temporary files go
            try:
                return _run(argv, out, err)
            except BrokenPipeError:
                # The reader went away (`rapp plan | head -1`): stop quietly, as a program
                # killed by SIGPIPE would; nothing more can be said on a closed stream.
                _silence(out)
                return EXIT_BROKEN_PIPE
            except Exception as e:  # a bug too: still one line, never a traceback
                code, line = _failure(e)
            except KeyboardInterrupt as e:
                code, line = _signal_exit(e)
            if code in (EXIT_INTERRUPTED, EXIT_TERMINATED):
                interrupts.mark_reported()
            said = code
            _say(err, line)
            return code
    except KeyboardInterrupt as e:
        interrupts.mark_reported()
        if said is None:
            # The first interrupt, landing as the run ended, while catching() put the
            # handlers back: it is said like any other (the answer may be incomplete).
            code, line = _signal_exit(e)
            try:
                _say(err, line)
            except KeyboardInterrupt:  # yet another: the line is said as far as it got
                pass
            return code
        # A second Ctrl-C (or SIGTERM) while the first, or an error, was being reported.
        return said if said in (EXIT_INTERRUPTED, EXIT_TERMINATED) else _signal_exit(e)[0]
