"""rapp: 2D robot-arm path planning, the package behind the rapp book.

The names below are the contract (see the book's pages and ``ARCHITECTURE.md``).
Everything else is reachable by module path: teaching counterexamples such as
``rapp.search.greedy_best_first`` and ``rapp.collision.line_distance_mis``,
helpers such as ``rapp.cspace.grid_q``, plotting (``rapp.plotting``), widgets
(``rapp.widgets``), derivations (``rapp.symbolic``, imported on demand: sympy
takes about 2 s to load) and the case studies (``rapp.cases``).

Examples
--------
>>> import rapp
>>> arm = rapp.Arm([1.0, 1.0])
>>> arm.end_effector([0.0, 0.0]).tolist()
[2.0, 0.0]
"""

import sys as _sys

if _sys.argv[:1] == ["-m"] or _sys.argv[:1] and _sys.argv[0].endswith("rapp"):
    # `python -m rapp` or the `rapp` script: Ctrl-C while the imports below run (most of a
    # short run) must end it with one line and exit 130, not a traceback (rapp.interrupts).
    from rapp import interrupts as _interrupts

    if _interrupts.running_as_command():
        _interrupts.guard_startup()

import importlib
import importlib.util
import sys
import types

from rapp.errors import (
    FileNotFound,
    GridTooCoarse,
    InvalidFormat,
    InvalidValue,
    MissingParameter,
    NoIKSolution,
    NoPathFound,
    PathNotFollowable,
    RappError,
    ScenarioError,
)

__all__ = [
    # errors
    "RappError", "ScenarioError", "FileNotFound", "InvalidFormat", "MissingParameter",
    "InvalidValue", "NoPathFound", "GridTooCoarse", "NoIKSolution", "PathNotFollowable",
    # the arm and its world
    "Arm", "wrap_angle", "Circle", "Polygon",
    "collides", "clearance", "segment_collision_free", "path_collision_free",
    # configuration space and search
    "JointGrid", "occupancy", "astar", "bfs_distances",
    # kinematics
    "ik", "ik_2link", "ik_numeric", "jacobian",
    "manipulability", "condition_number", "manipulability_ellipse",
    # trajectories
    "cubic", "quintic", "via_points", "time_path", "PiecewisePolynomial",
    # composing a motion: shorten a planner's path, then time it under joint limits
    "shortcut", "trapezoidal_path", "minimum_duration", "peak_rates",
    # the application
    "Scenario", "load_scenario", "list_scenarios", "echo",
    "plan", "Plan", "verify", "Report", "save_result", "load_result",
    "rrt", "rrt_connect", "rrt_star", "prm", "Roadmap", "RRTResult",
]

#: The package version (``rapp --version``); pyproject.toml holds the same (a test compares).
__version__ = "0.2.0"

# Where each contract name lives. They are imported on first use (module __getattr__, the
# lazy-loading pattern of scikit-image), so `import rapp` costs little more than numpy and
# `python -m rapp plan` loads only what a plan needs.
_LAZY = {
    "arm": ("Arm", "wrap_angle"),
    "obstacles": ("Circle", "Polygon"),
    "collision": ("clearance", "collides", "path_collision_free", "segment_collision_free"),
    "cspace": ("JointGrid", "occupancy"),
    "search": ("astar", "bfs_distances"),
    "ik": ("ik", "ik_2link", "ik_numeric", "jacobian"),
    "manipulability": ("condition_number", "manipulability", "manipulability_ellipse"),
    "trajectory": ("PiecewisePolynomial", "cubic", "quintic", "via_points"),
    "paths": ("shortcut",),
    "time_scaling": ("minimum_duration", "peak_rates", "time_path", "trapezoidal_path"),
    "scenario": ("Scenario", "echo", "list_scenarios", "load_scenario"),
    "verify": ("Report", "verify"),
    "results": ("Plan", "load_result", "save_result"),
    "rrt": ("RRTResult", "rrt"),
    "rrt_connect": ("rrt_connect",),
    "rrt_star": ("rrt_star",),
    "prm": ("prm",),
    "roadmap": ("Roadmap",),
    "planner": ("plan",),
}
_HOME = {name: module for module, names in _LAZY.items() for name in names}


class _Package(types.ModuleType):
    """The package module, refusing one thing: a submodule named like a contract function.

    Importing ``rapp.ik`` (or ``rapp.rrt``, ``rapp.prm``, ...) makes the import system bind
    the submodule to the package's attribute of that name; ``rapp.ik`` is the function, as
    it always was, so that binding is skipped (the submodule stays in ``sys.modules``).
    """

    def __setattr__(self, name, value):
        if name in _HOME and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


def __getattr__(name):
    """A contract name is imported from its module on first use, and a submodule by its name.

    ``rapp.exercises`` (the readers' answer checks) and ``rapp.symbolic`` (sympy) are among the
    submodules loaded only when named: importing them with rapp would cost every user, the
    command line included, about half a second or more.
    """
    module = _HOME.get(name)
    if module is not None:
        value = getattr(importlib.import_module(f"rapp.{module}"), name)
        globals()[name] = value
        return value
    if not name.startswith("_") and importlib.util.find_spec(f"rapp.{name}") is not None:
        return importlib.import_module(f"rapp.{name}")
    raise AttributeError(f"module 'rapp' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_HOME) | {"exercises"})


sys.modules[__name__].__class__ = _Package
