"""Command line: ``python -m rapp plan|check|list``.

Exit codes: 0 done; 1 a planning answer (no path, no IK solution), said in one
line; 2 bad input, one line on stderr naming the field and what is wrong; 130
interrupted. Never a traceback: an unexpected internal error is one line and
exit code 3.

Examples
--------
>>> main(["list"])  # doctest: +ELLIPSIS
default ...
0
"""

from __future__ import annotations

import argparse
import os
import sys

from rapp.errors import NoIKSolution, NoPathFound, RappError, ScenarioError

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_NO_PLAN, EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


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
    >>> args.command, args.scenario, args.out
    ('plan', 'default', 'r.json')
    """
    p = _Parser(prog="rapp", description="2D robot-arm path planning (2D-RAPP).")
    sub = p.add_subparsers(dest="command", metavar="{plan,check,list}", parser_class=_Parser)
    sub.required = True
    pp = sub.add_parser("plan", help="plan, time and verify a trajectory",
                        description="Plan a collision-free trajectory for SCENARIO (a JSON file "
                        "or an embedded scenario name; default: the embedded default), echo the "
                        "inputs, verify the result and print the report.")
    pp.add_argument("scenario", nargs="?", default="default",
                    help="scenario file or embedded name (see 'rapp list')")
    pp.add_argument("--out", metavar="RESULT.json", help="write the result as JSON (atomically)")
    pp.add_argument("--plot", metavar="FIG.png", help="save a figure of the plan")
    pp.add_argument("--animate", metavar="ANIM.gif", help="save an animation of the arm")
    pp.add_argument("--quiet", "-q", action="store_true", help="print only the one-line summary")
    pc = sub.add_parser("check", help="validate a scenario and echo it; plan nothing",
                        description="Validate SCENARIO and echo every input with units (R2).")
    pc.add_argument("scenario", help="scenario file or embedded name")
    sub.add_parser("list", help="list the embedded scenarios",
                   description="List the embedded scenarios with their descriptions.")
    return p


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _check_writable(path: str, option: str) -> None:
    """Refuse an output path before any work, naming the option."""
    from rapp.errors import InvalidValue

    if os.path.isdir(path):
        raise InvalidValue(f"{path!r} is a directory, not a file name", field=option)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidValue(f"folder {folder!r} does not exist", field=option)
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise InvalidValue(f"cannot write {path!r} (permission denied)", field=option)


def _cmd_list(out) -> int:
    from rapp.scenario import list_scenarios, load_scenario

    for name in list_scenarios():
        s = load_scenario(name, check=False)
        print(f"{name:<14}{s.description}", file=out)
    return EXIT_OK


def _cmd_check(args, out) -> int:
    from rapp.scenario import echo, load_scenario

    s = load_scenario(args.scenario)
    print(echo(s), file=out)
    print("scenario is valid", file=out)
    return EXIT_OK


def _cmd_plan(args, out, err) -> int:
    from rapp.planner import plan
    from rapp.results import save_result
    from rapp.scenario import echo, load_scenario

    for path, option in ((args.out, "--out"), (args.plot, "--plot"), (args.animate, "--animate")):
        if path:
            _check_writable(path, option)
    s = load_scenario(args.scenario)
    if not args.quiet:
        print(echo(s), file=out)
        print(file=out)
    p = plan(s)
    if not args.quiet:
        print(p.report, file=out)
        times = p.timings
        print("time per stage: " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in times.items()),
              file=out)
    if args.out:
        save_result(p, args.out)
    if args.plot or args.animate:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from rapp import plotting

        if args.plot:
            fig = plotting.plot_plan(p, s)
            fig.savefig(args.plot, dpi=100)
            plt.close(fig)
        if args.animate:
            anim = plotting.animate(s.arm, p.q, s.obstacles, t=p.t)
            plotting.save_gif(anim, args.animate)
            plt.close(anim._fig)
    m = p.metrics
    status = "verified" if p.report.ok else "VERIFICATION FAILED"
    print(f"planned {len(p.t)} samples over {s.trajectory.duration:g} s, "
          f"joint path {m.get('joint_length_rad', 0):.3f} rad, end effector "
          f"{m.get('ee_length_m', 0):.3f} m: {status}", file=out)
    if not p.report.ok:
        print("rapp: error: the trajectory failed verification: "
              + ", ".join(c.name for c in p.report.failed), file=err)
        return EXIT_INTERNAL
    return EXIT_OK


def main(argv=None) -> int:
    """Run the command line; returns the exit code (see the module notes).

    Examples
    --------
    >>> main(["check", "no/such/file.json"])
    2
    """
    out, err = sys.stdout, sys.stderr
    try:
        try:
            args = build_parser().parse_args(argv)
        except SystemExit as e:  # --help, --version
            return int(e.code or 0) if not isinstance(e.code, str) else EXIT_BAD_INPUT
        if args.command == "list":
            return _cmd_list(out)
        if args.command == "check":
            return _cmd_check(args, out)
        return _cmd_plan(args, out, err)
    except _UsageError as e:
        print(f"{_one_line(e)} (see --help)", file=err)
        return EXIT_BAD_INPUT
    except ScenarioError as e:
        print(f"rapp: error: {_one_line(e)}", file=err)
        return EXIT_BAD_INPUT
    except NoIKSolution as e:
        print(f"rapp: no IK solution ({e.reason}): {_one_line(e)}", file=err)
        return EXIT_NO_PLAN
    except NoPathFound as e:
        print(f"rapp: no path: {_one_line(e)}", file=err)
        return EXIT_NO_PLAN
    except KeyboardInterrupt:
        print("rapp: interrupted", file=err)
        return EXIT_INTERRUPTED
    except RappError as e:
        print(f"rapp: error: {_one_line(e)}", file=err)
        return EXIT_BAD_INPUT
    except OSError as e:
        name = getattr(e, "filename", None)
        print(f"rapp: error: {name or 'output'}: {_one_line(e.strerror or e)}", file=err)
        return EXIT_BAD_INPUT
    except MemoryError:
        print("rapp: error: out of memory; try a smaller planner.cells", file=err)
        return EXIT_BAD_INPUT
    except Exception as e:  # a bug: still one line, never a traceback
        print(f"rapp: internal error: {type(e).__name__}: {_one_line(e)}", file=err)
        return EXIT_INTERNAL
