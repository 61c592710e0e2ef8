"""rapp: 2D robot-arm path planning, the package behind the rapp book.

The names below are the contract (see the book's pages and ``DESIGN.md``).
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
from rapp.arm import Arm, wrap_angle
from rapp.obstacles import Circle, Polygon
from rapp.collision import clearance, collides, path_collision_free, segment_collision_free
from rapp.cspace import JointGrid, occupancy
from rapp.search import astar, bfs_distances
from rapp.ik import ik, ik_2link, ik_numeric, jacobian
from rapp.manipulability import condition_number, manipulability, manipulability_ellipse
from rapp.trajectory import PiecewisePolynomial, cubic, quintic, time_path, via_points
from rapp.scenario import Scenario, echo, list_scenarios, load_scenario
from rapp.verify import Report, verify
from rapp.results import Plan, load_result, save_result
from rapp.rrt import RRTResult, rrt
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star
from rapp.prm import prm
from rapp.planner import plan

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
    # the application
    "Scenario", "load_scenario", "list_scenarios", "echo",
    "plan", "Plan", "verify", "Report", "save_result", "load_result",
    "rrt", "rrt_connect", "rrt_star", "prm", "RRTResult",
]

__version__ = "0.1.0"



def __getattr__(name):
    """``rapp.exercises`` (the readers' answer checks) is imported on first use.

    Its chapter modules import the case studies, and those import sympy: loading them with
    ``import rapp`` would cost every user, the command line included, about half a second.
    """
    if name == "exercises":
        import importlib

        return importlib.import_module("rapp.exercises")
    raise AttributeError(f"module 'rapp' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | {"exercises"})
