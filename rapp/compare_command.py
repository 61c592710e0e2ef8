"""``python -m rapp compare``: every planner of the table on scenarios, seeds times, resumable.

The runs are :mod:`rapp.compare`'s; this is their command line. Each finished run is appended
at once to the ``--out`` journal (:mod:`rapp.journal`, JSON Lines), so Ctrl-C, SIGTERM or
even a kill loses no finished run, and a rerun with the same ``--out`` (and the same
scenarios and settings) runs only what is missing. The runs go to a local process pool
(``--workers``) or to Dask (``--scheduler local`` for a ``LocalCluster``, or a scheduler's
address; the ``dask`` extra); every worker compiles the kernels before its first timed run.
At the end the summary (success rates with Wilson intervals, means with Student-t intervals)
is printed, and written with every record to ``--summary`` when given (the format of
:func:`rapp.compare.recorded_results`).
"""

from __future__ import annotations

import json
import os
import time
from importlib import resources
from contextlib import contextmanager
from dataclasses import asdict

from rapp import compare, planners as planner_table, progress, scenario
from rapp.errors import InvalidValue
from rapp.files import atomic_output
from rapp.journal import Journal, read_journal

__all__ = ["add_parser", "run", "DEFAULT_OUT"]

#: The journal's default name, in the current folder (never inside the package).
DEFAULT_OUT = "rapp-compare.jsonl"


def add_parser(sub) -> None:
    """The ``compare`` subcommand of ``python -m rapp``."""
    names = ", ".join(planner_table.PLANNERS)
    pc = sub.add_parser(
        "compare", help="compare the planners on scenarios and seeds (resumable, parallel)",
        description="Run every planner of rapp's table (grid planners at three resolutions) on "
        "SCENARIO files or embedded names, or on --random seeded random scenarios, --seeds "
        "times for a sampling planner. Each finished run is appended to --out at once: "
        "rerun with the same --out to finish an interrupted comparison (only the missing "
        "runs are run). Prints per planner the success rate (Wilson 95 %% interval) and the "
        "mean time and lengths (Student-t 95 %% intervals).")
    pc.add_argument("scenarios", nargs="*", metavar="SCENARIO",
                    help="scenario files or embedded names (default: --random 30)")
    pc.add_argument("--random", type=int, metavar="N", default=None,
                    help="N seeded random scenarios (2-4 links, open and narrow), when no "
                    "SCENARIO is given (default 30)")
    pc.add_argument("--scenario-seed", type=int, default=2026, metavar="S",
                    help="the seed of the random scenarios (default 2026)")
    pc.add_argument("--seeds", type=int, default=20, metavar="K",
                    help="runs per scenario of each sampling planner, seeds 0..K-1 (default 20)")
    pc.add_argument("--planners", metavar="NAMES", default=None,
                    help=f"comma-separated planners to run ({names}, or a grid resolution "
                    "such as astar_24); default all")
    pc.add_argument("--workers", metavar="N", default=None,
                    help="worker processes (default: every core); 1 runs here, without a pool")
    pc.add_argument("--scheduler", metavar="local|ADDRESS", default=None,
                    help="run on Dask: 'local' starts a LocalCluster of --workers processes, "
                    "an address (tcp://host:8786) uses that scheduler (pip install 'rapp[dask]')")
    pc.add_argument("--out", metavar="RUNS.jsonl", default=DEFAULT_OUT,
                    help=f"the journal of runs, appended run by run (default {DEFAULT_OUT} here)")
    pc.add_argument("--summary", metavar="RESULT.json", default=None,
                    help="also write the summary and every record, as one JSON file (atomically)")
    pc.add_argument("--quiet", "-q", action="store_true", help="no progress line")


def _positive(text, field: str, *, zero: bool = False) -> int:
    try:
        value = int(text)
    except (TypeError, ValueError):
        raise InvalidValue(f"must be a whole number, got {text!r}", field=field) from None
    if value < (0 if zero else 1):
        raise InvalidValue(f"must be at least {0 if zero else 1}, got {value}", field=field)
    return value


def _planners(text, extra=()) -> list | None:
    """The chosen run names' prefixes, each checked against the table."""
    if text is None:
        return None
    chosen = [name.strip() for name in text.split(",") if name.strip()]
    if not chosen:
        raise InvalidValue("names no planner", field="--planners")
    every = {p for n in compare.ASTAR_CELLS for p in compare.planners_for(n)}
    for name in chosen:
        if name not in planner_table.PLANNERS and name not in every and name not in extra:
            raise InvalidValue(f"unknown planner {name!r} (the table's: "
                               f"{', '.join(planner_table.PLANNERS)})", field="--planners")
    return chosen


def _scenarios(args) -> tuple[list[dict], object]:
    """The scenario dicts, and what the header records as their seed (None for files)."""
    if args.scenarios and args.random is not None:
        raise InvalidValue("give SCENARIO files or --random, not both", field="--random")
    if not args.scenarios:
        count = _positive(30 if args.random is None else args.random, "--random")
        return compare.make_scenarios(count, args.scenario_seed), args.scenario_seed
    out = []
    for source in args.scenarios:
        s = scenario.load_scenario(source)  # validated: one line naming the field if not
        if os.path.exists(source):
            with open(source, "rb") as f:
                data = json.loads(f.read())
        else:  # an embedded name (load_scenario found it)
            data = json.loads(resources.files("rapp").joinpath(
                f"scenarios/{source}.json").read_bytes())
        data.setdefault("name", s.name)
        data.setdefault("description", s.description)
        out.append(data)
    return out, None


def _inside_package(path: str) -> bool:
    package = os.path.dirname(os.path.abspath(compare.__file__))
    return os.path.commonpath([package, os.path.abspath(path)]) == package


def _check_out(path: str, field: str, *, package_ok: bool = False) -> None:
    if not package_ok and _inside_package(path):
        raise InvalidValue(f"{path!r} is inside the rapp package; write elsewhere", field=field)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidValue(f"folder {folder!r} does not exist", field=field)
    if os.path.isdir(path):
        raise InvalidValue(f"{path!r} is a folder", field=field)


def _dask():
    """Dask's ``Client`` and ``LocalCluster``, imported only for ``--scheduler``."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise InvalidValue("needs Dask's distributed scheduler: pip install 'rapp[dask]'",
                           field="--scheduler") from None
    return Client, LocalCluster


@contextmanager
def _executor(args, workers: int):
    """None (run here), a warmed process pool, or a warmed Dask client's executor."""
    if args.scheduler is None:
        if workers == 1:
            yield None
            return
        from concurrent.futures import ProcessPoolExecutor  # multiprocessing: only when used

        pool = ProcessPoolExecutor(max_workers=workers, initializer=compare.start_worker)
        try:
            yield pool
        except BaseException:
            # An interrupt or an error: stop the workers at once (their unfinished runs are
            # not in the journal; a rerun does them).
            for process in list((getattr(pool, "_processes", None) or {}).values()):
                process.terminate()
            raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
        return
    Client, LocalCluster = _dask()
    cluster = None
    try:
        if args.scheduler == "local":
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
        else:
            client = Client(args.scheduler, timeout="10s")
    except OSError as e:
        raise InvalidValue(f"cannot reach the scheduler: {e}", field="--scheduler") from None
    try:
        client.run(compare.warm)  # every worker compiles before its first timed run
        yield client.get_executor()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _progress(args, err, total: int):
    """A :class:`rapp.progress.TerminalLine` on a terminal; else a plain line every 10 %."""
    try:
        terminal = err.isatty()
    except (AttributeError, ValueError, OSError):
        terminal = False
    if args.quiet:
        return None, lambda done: None
    if terminal:
        line = progress.TerminalLine(err)
        return line, lambda done: line("compare", done, total)
    t0, shown = time.monotonic(), [-1]

    def plain(done):
        tenth = 10 * done // max(total, 1)
        if tenth > shown[0] or done == total:
            shown[0] = tenth
            print(f"compare: {done}/{total} runs ({100 * done / max(total, 1):.0f}%), "
                  f"{time.monotonic() - t0:.0f} s", file=err, flush=True)
    return None, plain


def run(args, out, err, *, say, runner=None, extra=()) -> int:
    """The ``compare`` command; ``say(stream, text)`` prints a line (the command line's, which
    escapes what a terminal must not see); ``runner`` and ``extra`` as in
    :func:`rapp.compare.run` (a benchmark adds its own planners with them). The summary's
    ``wall_s`` is this session's wall-clock time (a resumed run's covers only what it ran)."""
    workers = _positive(os.cpu_count() or 1 if args.workers is None else args.workers, "--workers")
    seeds = _positive(args.seeds, "--seeds")
    chosen = _planners(args.planners, extra)
    _check_out(args.out, "--out")
    if args.summary:
        # The recorded comparison the book reads is a summary written into the package.
        _check_out(args.summary, "--summary", package_ok=True)
        if os.path.abspath(args.summary) == os.path.abspath(args.out):
            raise InvalidValue("is the same file as --out", field="--summary")
    if args.scheduler is not None:
        _dask()  # before any file is touched
    scenarios, seed = _scenarios(args)
    settings = compare.settings_record(scenarios, seeds, seed, chosen)
    if extra:
        settings["extra"] = list(extra)
    header = {"rapp_compare": 1, "settings": settings, "scenarios": scenarios}
    todo = compare.tasks(scenarios, seeds, chosen, extra)
    wanted = {compare.task_key(t) for t in todo}
    t0 = time.perf_counter()
    with Journal(args.out, header, field="--out") as journal:
        _, old = read_journal(args.out)
        done = {compare.task_key(r): r for r in old if compare.task_key(r) in wanted}
        left = [t for t in todo if compare.task_key(t) not in done]
        line, show = _progress(args, err, len(todo))
        with (line if line is not None else _nothing()):
            show(len(done))
            if left:
                with _executor(args, workers) as executor:
                    records = compare.run_tasks(left, executor, runner)
                    try:
                        for record in records:
                            journal.append(asdict(record))
                            done[compare.task_key(record)] = asdict(record)
                            show(len(done))
                    finally:
                        records.close()
    wall = time.perf_counter() - t0
    result = compare.result(scenarios, settings, done.values(), wall)
    if args.summary:
        with atomic_output(args.summary, ".json") as tmp, open(tmp, "w", encoding="utf-8") as f:
            f.write(json.dumps(result, indent=1, allow_nan=True) + "\n")
    plural = "" if len(scenarios) == 1 else "s"
    say(out, f"{len(done)} runs ({len(left)} new) on {len(scenarios)} scenario{plural}, "
             f"journal {args.out}")
    for planner, by_class in result["summary"].items():
        a = by_class["all"]
        lo, hi = a["success_interval"]
        t, length = a["time_s"], a["length_rad"]
        say(out, f"{planner:18s} success {a['success_rate']:6.1%} [{lo:.2f}, {hi:.2f}]  "
                 f"time {t['mean']:.3f} s [{t['low']:.3f}, {t['high']:.3f}]  length "
                 f"{length['mean']:.2f} -> {a['shortcut_length_rad']['mean']:.2f} rad")
    return 0


@contextmanager
def _nothing():
    yield

