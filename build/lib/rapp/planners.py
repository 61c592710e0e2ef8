"""The planner table: every planner's name, function, settings and description, in one place.

Every planner follows one contract::

    function(arm, start, goal, obstacles=(), *, <its settings>, raise_on_failure=True)
        -> rapp.paths.PlannerResult      # .path .success .cost, and its own .details

``start`` is one configuration (n,), ``goal`` one or several (g, n) (every free IK
solution of a Cartesian goal), ``obstacles`` circles and polygons; the path runs from the
exact start to one of the goals, unwrapped, every straight segment certified free.

:data:`PLANNERS` is read by the scenario loader (which keys ``planner`` accepts, their
defaults and ranges, which ones an algorithm reads, how the echo shows them), by
:func:`rapp.plan` (which function to call with which settings) and by the test of the
book's "Scenario files" page (the page documents every planner and every setting of this
table). Planners never read a scenario: :func:`run` hands them plain values.

Adding a planner is its module (a function of the contract) and one :class:`Planner` entry
in :data:`PLANNERS`; a setting no planner had before is one more :class:`Setting` in its
entry. Then document it on the "Scenario files" page, whose test says what is missing.

Examples
--------
>>> sorted(PLANNERS)
['astar', 'prm', 'rrt', 'rrt_connect', 'rrt_star']
>>> PLANNERS["rrt_connect"].keys
('step', 'max_iterations', 'seed', 'time_budget')
>>> PLANNERS["rrt_star"].default("max_iterations"), STEP.accepts(4.0), STEP.range_text
(3000, False, '[1e-06, pi] rad')
>>> from rapp import Arm
>>> r = run("rrt_connect", Arm([1.0, 1.0]), [0.0, 0.0], [[1.0, 0.5]], [], seed=2)
>>> r.success, r.path[0].tolist(), round(r.cost, 4)
(True, [0.0, 0.0], 1.118)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any, Callable, Mapping

from rapp.grid_route import grid_route
from rapp.paths import PlannerResult
from rapp.prm import prm
from rapp.rrt import MAX_STEP, MIN_STEP, check_reachable, rrt
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

__all__ = ["Setting", "Planner", "PLANNERS", "SETTINGS", "names", "entry", "all_settings", "run",
           "MAX_HEURISTIC_WEIGHT", "MAX_GOAL_THRESHOLD", "MAX_TIME_BUDGET"]

#: Largest ``heuristic_weight``: weighted A* returns a path at most this factor longer than
#: the optimum on the grid, so larger weights only hide a bad setting.
MAX_HEURISTIC_WEIGHT = 100.0
#: Largest ``goal_threshold`` (rad, joint space): a goal region wider than this is no goal.
MAX_GOAL_THRESHOLD = 1.0
#: Longest ``time_budget`` (s).
MAX_TIME_BUDGET = 3600.0


@dataclass(frozen=True)
class Setting:
    """One key of a scenario's ``planner`` object.

    Attributes
    ----------
    key : str
    kind : {"number", "integer", "cells"}
        ``"cells"`` is an integer or one per joint (its default and limit depend on the arm;
        the loader handles it).
    default
        Value when the file does not set it; ``None`` means "no limit" where ``nullable``
        (``radius``: the step).
    low, high : float
        The accepted range; ``low_open`` makes it ``(low, high]``.
    range_text : str
        The range as error messages say it (``"(0, pi] rad"``).
    unit : str
        Appended to the value in the echo (``"rad"``, ``"s"``), or ``""``.
    label : str
        The echo's row label.
    nullable : bool
        ``null`` is accepted (and means no limit).
    null_text : str
        What the echo shows for ``null`` (``"none"``: no limit).
    warns_when_ignored : bool
        Given to a planner that does not read it, the loader warns (A*'s own settings and
        ``seed`` do not: a file that switches algorithm keeps them harmlessly).
    description : str
    """

    key: str
    kind: str
    default: Any
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    range_text: str = ""
    unit: str = ""
    label: str = ""
    nullable: bool = False
    null_text: str = "none"
    warns_when_ignored: bool = True
    description: str = ""

    def accepts(self, value) -> bool:
        """Whether a number of the right kind is within the range.

        Examples
        --------
        >>> GOAL_BIAS.accepts(0.0), GOAL_BIAS.accepts(1.5), TIME_BUDGET.accepts(None)
        (True, False, True)
        """
        if value is None:
            return self.nullable
        above = value > self.low if self.low_open else value >= self.low
        return bool(above and value <= self.high)


@dataclass(frozen=True)
class Planner:
    """One entry of the table: ``function`` of the contract and the ``settings`` it reads
    (passed to it by keyword, under the same names)."""

    name: str
    function: Callable[..., PlannerResult]
    settings: tuple
    description: str = ""
    #: The A* family plans on a grid: the loader checks ``cells`` against the memory limit.
    grid: bool = False
    #: Settings checked against the problem before a run, ``check(arm, start, goal, **settings)``,
    #: raising :class:`rapp.errors.InvalidSetting` (e.g. a step too small to reach the goal).
    check: Callable[..., None] | None = None

    @property
    def keys(self) -> tuple:
        """The names of the settings it reads, in table order."""
        return tuple(s.key for s in self.settings)

    def default(self, key: str):
        """This planner's default for ``key``."""
        return next(s.default for s in self.settings if s.key == key)


CELLS = Setting("cells", "cells", None, low=3, label="cells", warns_when_ignored=False,
                description="cells per joint of the joint grid")
HEURISTIC_WEIGHT = Setting("heuristic_weight", "number", 1.0, 1.0, MAX_HEURISTIC_WEIGHT,
                           range_text=f"[1, {MAX_HEURISTIC_WEIGHT:g}]", label="weight",
                           warns_when_ignored=False,
                           description="1 is optimal A*; above 1 weighted A*")
MAX_EXPANSIONS = Setting("max_expansions", "integer", None, 1, math.inf, label="max expand",
                         nullable=True, warns_when_ignored=False,
                         description="expansions at most; null: no limit")
STEP = Setting("step", "number", 0.1, MIN_STEP, MAX_STEP, range_text=f"[{MIN_STEP:g}, pi] rad",
               unit="rad", label="step", description="joint-space step of each extension")
RADIUS = Setting("radius", "number", None, MIN_STEP, MAX_STEP,
                 range_text=f"[{MIN_STEP:g}, pi] rad", unit="rad", label="radius", nullable=True,
                 null_text="the step", description="largest rewiring radius; null: the step")
GOAL_BIAS = Setting("goal_bias", "number", 0.1, 0.0, 1.0, range_text="[0, 1]", label="goal bias",
                    description="probability of sampling the goal")
GOAL_THRESHOLD = Setting(
    "goal_threshold", "number", 0.01, 0.0, MAX_GOAL_THRESHOLD, low_open=True,
    range_text=f"(0, {MAX_GOAL_THRESHOLD:g}] rad (a joint-space distance to a goal configuration)",
    unit="rad", label="goal thresh", description="a node this close to a goal has reached it")
SAMPLES = Setting("samples", "integer", 500, 10, 100_000, label="samples",
                  description="free configurations added each time the roadmap holds no path")
NEIGHBOURS = Setting("neighbours", "integer", 10, 1, 100, label="neighbours",
                     description="candidate edges from each node to its nearest nodes")
MAX_ITERATIONS = Setting("max_iterations", "integer", 20000, 1, 10_000_000, label="iterations",
                         description="iterations at most")
TIME_BUDGET = Setting("time_budget", "number", None, 0.0, MAX_TIME_BUDGET, low_open=True,
                      range_text=f"(0, {MAX_TIME_BUDGET:g}] s", unit="s", label="time budget",
                      nullable=True, description="seconds at most; null: no limit")
SEED = Setting("seed", "integer", 0, 0, 2**63 - 1, label="seed", warns_when_ignored=False,
               description="seeds the random generator")


#: The settings shared by the planners below, in the order the loader checks them and the echo
#: shows them.
SETTINGS = (CELLS, HEURISTIC_WEIGHT, MAX_EXPANSIONS, STEP, RADIUS, GOAL_BIAS, GOAL_THRESHOLD,
            SAMPLES, NEIGHBOURS, MAX_ITERATIONS, TIME_BUDGET, SEED)


def _iterations(default: int) -> Setting:
    return replace(MAX_ITERATIONS, default=default)


#: Planner name -> :class:`Planner`. Read-only: a planner is added here, in code.
PLANNERS: Mapping[str, Planner] = MappingProxyType({
    "astar": Planner("astar", grid_route, (CELLS, HEURISTIC_WEIGHT, MAX_EXPANSIONS),
                     "A* on the joint grid, every move certified", grid=True),
    "rrt": Planner("rrt", rrt, (STEP, GOAL_BIAS, GOAL_THRESHOLD, _iterations(20000), SEED,
                                TIME_BUDGET),
                   "a rapidly-exploring random tree from the start", check=check_reachable),
    "rrt_connect": Planner("rrt_connect", rrt_connect, (STEP, _iterations(20000), SEED, TIME_BUDGET),
                           "two trees, from the start and the goals, grown toward each other"),
    "rrt_star": Planner("rrt_star", rrt_star, (STEP, RADIUS, GOAL_BIAS, GOAL_THRESHOLD,
                                               _iterations(3000), SEED, TIME_BUDGET),
                        "RRT with rewiring: runs its whole budget, shortening the path"),
    "prm": Planner("prm", prm, (SAMPLES, NEIGHBOURS, _iterations(500), SEED, TIME_BUDGET),
                   "a lazy probabilistic roadmap; its iterations are path searches"),
})


def names() -> tuple:
    """The planners' names, in table order."""
    return tuple(PLANNERS)


def entry(name: str) -> Planner:
    """The table's entry for ``name``; a ValueError listing the names when there is none."""
    try:
        return PLANNERS[name]
    except KeyError:
        raise ValueError(f"unknown planner {name!r} (known: {', '.join(PLANNERS)})") from None


def all_settings() -> dict:
    """Every setting of any planner, key -> :class:`Setting`: :data:`SETTINGS` first, then any
    a planner brings of its own. A key's range is the same in every planner that reads it."""
    out = {s.key: s for s in SETTINGS}
    for p in PLANNERS.values():
        for s in p.settings:
            out.setdefault(s.key, s)
    return out


def run(name: str, arm, start, goal, obstacles=(), **settings) -> PlannerResult:
    """Call planner ``name`` with the settings it reads from ``settings``; the others are
    ignored, so one mapping of settings serves every planner. A setting it reads and
    ``settings`` lacks takes its default.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> r = run("astar", Arm([1.0, 1.0]), [0.0, 0.0], [2.0, 0.0], [Circle((1.5, 0.5), 0.3)],
    ...         cells=32, seed=5, step=0.3)
    >>> r.success, r.metrics["search_grid"], r.path[-1].round(4).tolist()
    (True, 'certified cells', [-4.2832, 0.0])
    """
    p = entry(name)
    if "neighbors" in settings:  # the American spelling of the setting, accepted as well
        settings = {"neighbours": settings["neighbors"],
                    **{k: v for k, v in settings.items() if k != "neighbors"}}
    kw = {s.key: settings.get(s.key, s.default) for s in p.settings}
    if "raise_on_failure" in settings:
        kw["raise_on_failure"] = settings["raise_on_failure"]
    if p.check is not None:
        p.check(arm, start, goal, **kw)
    return p.function(arm, start, goal, obstacles, **kw)
