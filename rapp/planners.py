"""The planner table: every planner's name, function, settings and description, in one place.

Every planner follows one contract::

    function(arm, start, goal, obstacles=(), *, <its settings>, raise_on_failure=True,
             margin=0.0) -> rapp.paths.PlannerResult      # .path .success .cost, .details

``margin`` (metres) is kept by every link beyond its radius (``arm.link_radius``): the
planner turns both into zero-width links among grown obstacles (:func:`rapp.collision.scene`).

``start`` is one configuration (n,), ``goal`` one or several (g, n) (every free IK
solution of a Cartesian goal), ``obstacles`` circles and polygons; the path runs from the
exact start to one of the goals, unwrapped, every straight segment certified free.

:data:`PLANNERS` is read by the scenario loader (which keys ``planner`` accepts, their
defaults and ranges, which ones an algorithm reads, how the echo shows them), by
:func:`rapp.plan` (which function to call with which settings) and by the test of the
book's "Scenario files" page (the page documents every planner and every setting of this
table). Planners never read a scenario: :func:`run` hands them plain values.

The defaults are the planner functions' own: an entry reads each setting's default from its
function's signature, so ``rapp.rrt_star(...)`` and a scenario naming ``rrt_star`` run the same
settings. An entry also says what its planner guarantees (:attr:`Planner.complete`,
:attr:`Planner.optimizing`, ...), which the contract tests and the book's planner table read.

Adding a planner is its module (a function of the contract) and one :class:`Planner` entry
in :data:`PLANNERS`; a setting no planner had before is one more :class:`Setting` in its
entry. Then give it its row on the "Scenario files" page, whose test says what is missing.

Examples
--------
>>> sorted(PLANNERS)
['astar', 'prm', 'rrt', 'rrt_connect', 'rrt_star']
>>> PLANNERS["rrt_connect"].keys
('step', 'max_iterations', 'seed', 'time_budget')
>>> PLANNERS["rrt_star"].default("max_iterations"), STEP.accepts(4.0), STEP.range_text
(3000, False, '[1e-06, pi] rad')
>>> PLANNERS["astar"].complete, PLANNERS["rrt_star"].optimizing
('resolution', 'asymptotically')
>>> from rapp import Arm
>>> r = run("rrt_connect", Arm([1.0, 1.0]), [0.0, 0.0], [[1.0, 0.5]], [], seed=2)
>>> r.success, r.path[0].tolist(), round(r.cost, 4)
(True, [0.0, 0.0], 1.118)
"""

from __future__ import annotations

import inspect
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
from rapp.validity import MAX_RESOLUTION, MIN_RESOLUTION

__all__ = ["Setting", "Planner", "PLANNERS", "SETTINGS", "USER_CHECK", "names", "entry", "all_settings", "run",
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
        (``radius``: the step). In an entry of :data:`PLANNERS` it is the planner function's
        own default (the shared settings below leave it ``None`` until then).
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
    in_files : bool
        A scenario file may hold it. ``validity`` (a Python callable) and its
        ``validity_resolution`` are keywords of the planner functions only: a file cannot carry
        a callable, so the loader, the schema and the echo leave them out (:func:`all_settings`,
        :attr:`Planner.keys`).
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
    in_files: bool = True

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
    (passed to it by keyword, under the same names), with what the planner guarantees.

    Each setting's default is ``function``'s own keyword default (read from its signature
    when the entry is made): the table and a direct call agree by construction.

    Examples
    --------
    >>> def hop(arm, start, goal, obstacles=(), *, seed=7, raise_on_failure=True): ...
    >>> Planner("hop", hop, (SEED,)).default("seed")
    7
    """

    name: str
    function: Callable[..., PlannerResult]
    settings: tuple
    description: str = ""
    #: The A* family plans on a grid: the loader checks ``cells`` against the memory limit.
    grid: bool = False
    #: Settings checked against the problem before a run, ``check(arm, start, goal, **settings)``,
    #: raising :class:`rapp.errors.InvalidSetting` (e.g. a step too small to reach the goal).
    check: Callable[..., None] | None = None
    #: Which completeness it has: ``"resolution"`` (finds a path whenever its grid holds one and
    #: proves there is none otherwise), ``"probabilistic"`` (finds one with probability tending
    #: to 1 as it runs longer, proves nothing), or ``""`` (none: it may miss a path).
    complete: str = ""
    #: Which optimality: ``"resolution"`` (shortest on its grid, with ``heuristic_weight`` 1),
    #: ``"asymptotically"`` (its path tends to the shortest as it runs longer), or ``""``.
    optimizing: str = ""
    #: It runs every iteration it is given, improving its answer (an anytime planner), rather
    #: than stopping at its first path.
    anytime: bool = False
    #: It can answer "no path" as a proof (``status`` ``"proved no path"``).
    proves_no_path: bool = False
    #: What one of its ``max_iterations`` counts (``"samples"``, ``"path searches"``), or ``""``.
    iteration: str = ""

    def __post_init__(self):
        own = inspect.signature(self.function).parameters
        missing = [s.key for s in self.settings if s.key not in own]
        if missing:
            raise ValueError(f"planner {self.name!r}: its function has no keyword {missing}")
        object.__setattr__(self, "settings", tuple(
            replace(s, default=None if own[s.key].default is inspect.Parameter.empty
                    else own[s.key].default) for s in self.settings))

    @property
    def keys(self) -> tuple:
        """The names of the settings it reads that a scenario file may hold, in table order."""
        return tuple(s.key for s in self.settings if s.in_files)

    @property
    def code_keys(self) -> tuple:
        """The names of its settings only a Python call can give (``validity``, ...)."""
        return tuple(s.key for s in self.settings if not s.in_files)

    def default(self, key: str):
        """This planner's default for ``key``."""
        return next(s.default for s in self.settings if s.key == key)


CELLS = Setting("cells", "cells", None, low=3, label="cells", warns_when_ignored=False,
                description="cells per joint of the joint grid")
HEURISTIC_WEIGHT = Setting("heuristic_weight", "number", None, 1.0, MAX_HEURISTIC_WEIGHT,
                           range_text=f"[1, {MAX_HEURISTIC_WEIGHT:g}]", label="weight",
                           warns_when_ignored=False,
                           description="1 is optimal A*; above 1 weighted A*")
MAX_EXPANSIONS = Setting("max_expansions", "integer", None, 1, math.inf, label="max expand",
                         nullable=True, warns_when_ignored=False,
                         description="expansions at most; null: no limit")
STEP = Setting("step", "number", None, MIN_STEP, MAX_STEP, range_text=f"[{MIN_STEP:g}, pi] rad",
               unit="rad", label="step", description="joint-space step of each extension")
RADIUS = Setting("radius", "number", None, MIN_STEP, MAX_STEP,
                 range_text=f"[{MIN_STEP:g}, pi] rad", unit="rad", label="radius", nullable=True,
                 null_text="the step", description="largest rewiring radius; null: the step")
GOAL_BIAS = Setting("goal_bias", "number", None, 0.0, 1.0, range_text="[0, 1]", label="goal bias",
                    description="probability of sampling the goal")
GOAL_THRESHOLD = Setting(
    "goal_threshold", "number", None, 0.0, MAX_GOAL_THRESHOLD, low_open=True,
    range_text=f"(0, {MAX_GOAL_THRESHOLD:g}] rad (a joint-space distance to a goal configuration)",
    unit="rad", label="goal thresh", description="a node this close to a goal has reached it")
SAMPLES = Setting("samples", "integer", None, 10, 100_000, label="samples",
                  description="free configurations of the roadmap's first batch; each later "
                              "batch doubles the roadmap")
NEIGHBOURS = Setting("neighbours", "integer", None, 1, 100, label="neighbours",
                     description="candidate edges from each node to its nearest nodes")
MAX_ITERATIONS = Setting("max_iterations", "integer", None, 1, 10_000_000, label="iterations",
                         description="iterations at most")
TIME_BUDGET = Setting("time_budget", "number", None, 0.0, MAX_TIME_BUDGET, low_open=True,
                      range_text=f"(0, {MAX_TIME_BUDGET:g}] s", unit="s", label="time budget",
                      nullable=True, description="seconds at most; null: no limit")
SEED = Setting("seed", "integer", None, 0, 2**63 - 1, label="seed", warns_when_ignored=False,
               description="seeds the random generator")
VALIDITY = Setting("validity", "callable", None, label="validity", nullable=True,
                   null_text="rapp's obstacles only", in_files=False,
                   description="a user's checker, (m, n) configurations -> m booleans, sampled "
                               "along each motion (rapp.validity); Python calls only")
VALIDITY_RESOLUTION = Setting("validity_resolution", "number", None, MIN_RESOLUTION,
                              MAX_RESOLUTION, range_text=f"[{MIN_RESOLUTION:g}, pi] rad",
                              unit="rad", label="validity step", in_files=False,
                              description="largest joint-space step between two samples of a "
                                          "motion for validity")
#: What every planner takes besides its own settings: a user's checker and its step.
USER_CHECK = (VALIDITY, VALIDITY_RESOLUTION)


#: The settings shared by the planners below, in the order the loader checks them and the echo
#: shows them. Their defaults are each planner function's own (see :class:`Planner`).
SETTINGS = (CELLS, HEURISTIC_WEIGHT, MAX_EXPANSIONS, STEP, RADIUS, GOAL_BIAS, GOAL_THRESHOLD,
            SAMPLES, NEIGHBOURS, MAX_ITERATIONS, TIME_BUDGET, SEED)


#: Planner name -> :class:`Planner`. Read-only: a planner is added here, in code.
PLANNERS: Mapping[str, Planner] = MappingProxyType({
    "astar": Planner("astar", grid_route, (CELLS, HEURISTIC_WEIGHT, MAX_EXPANSIONS, *USER_CHECK),
                     "A* on the joint grid, every move certified", grid=True,
                     complete="resolution", optimizing="resolution", proves_no_path=True),
    "rrt": Planner("rrt", rrt, (STEP, GOAL_BIAS, GOAL_THRESHOLD, MAX_ITERATIONS, SEED, TIME_BUDGET,
                                *USER_CHECK),
                   "a rapidly-exploring random tree from the start", check=check_reachable,
                   complete="probabilistic", iteration="samples"),
    "rrt_connect": Planner("rrt_connect", rrt_connect, (STEP, MAX_ITERATIONS, SEED, TIME_BUDGET,
                                                        *USER_CHECK),
                           "two trees, from the start and the goals, grown toward each other",
                           complete="probabilistic", iteration="samples"),
    "rrt_star": Planner("rrt_star", rrt_star, (STEP, RADIUS, GOAL_BIAS, GOAL_THRESHOLD,
                                               MAX_ITERATIONS, SEED, TIME_BUDGET, *USER_CHECK),
                        "RRT with rewiring: runs its whole budget, shortening the path",
                        complete="probabilistic", optimizing="asymptotically", anytime=True,
                        iteration="samples"),
    "prm": Planner("prm", prm, (SAMPLES, NEIGHBOURS, MAX_ITERATIONS, SEED, TIME_BUDGET,
                                *USER_CHECK),
                   "a lazy probabilistic roadmap; its iterations are path searches",
                   complete="probabilistic", iteration="path searches"),
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
    """Every setting of any planner that a scenario file may hold (:attr:`Setting.in_files`),
    key -> :class:`Setting`: :data:`SETTINGS`' order first, then any a planner brings of its own. A key's range is the same in every planner that reads it;
    its default here is that of the first planner reading it (``max_iterations`` differs by
    planner: :meth:`Planner.default`)."""
    read: dict = {}
    for p in PLANNERS.values():
        for s in p.settings:
            if s.in_files:   # a scenario file's keys (validity is for Python calls only)
                read.setdefault(s.key, s)
    return {**{s.key: read[s.key] for s in SETTINGS if s.key in read}, **read}


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
    if settings.get("margin"):  # passed when there is one: a planner written before margins runs
        kw["margin"] = settings["margin"]
    if p.check is not None:
        p.check(arm, start, goal, **kw)
    return p.function(arm, start, goal, obstacles, **kw)
