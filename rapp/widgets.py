"""Interactive explorers for the book, built on :mod:`rapp.plotting` and :mod:`rapp.view_stack`.

Every explorer is a view stack: each combination of its sliders' values is drawn when the
explorer is built, and the browser switches between the drawings itself. So an explorer works
the same in JupyterLab and in the static HTML book, where no kernel runs: moving a slider
changes the figure at once, offline. A slider steps through a fixed set of values (fine enough
to follow a motion; the status line prints the exact numbers); to explore other values, build
the explorer again with other ranges.

Examples
--------
>>> from rapp import Arm, Circle
>>> w = arm_explorer(Arm([1.0, 1.0]), [Circle((1.2, 0.8), 0.3)], steps=5)
>>> list(sliders_of(w)), "end effector" in selected(w)[1]
(['θ1 (rad)', 'θ2 (rad)'], True)
"""

from __future__ import annotations

import dataclasses
import functools
import html

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from rapp import plotting
from rapp.collision import clearance, collides, line_distance_mis, segment_circle_distance
from rapp.cspace import JointGrid, occupancy
from rapp.errors import RappError
from rapp.planner import plan as run_plan
from rapp.search import bfs_distances
from rapp.plotting import subplots
from rapp.trajectory import cubic, quintic
from rapp.view_stack import Control, selected, values_of, view_stack
from rapp.view_stack import sliders_of as stack_sliders  # widgets.sliders_of names them

__all__ = [
    "arm_explorer",
    "collision_explorer",
    "planner_playground",
    "trajectory_explorer",
    "astar_explorer",
    "rrt_explorer",
    "planner_comparison",
    "ik_explorer",
    "line_ride_explorer",
    "sliders_of",
    "selected",
    "values_of",
]


def _book_style(explorer):
    """Build ``explorer`` in the book's figure style, whatever the session's matplotlib defaults.

    Type sizes are fixed when text is created, and an explorer's views are all drawn while it
    is built, so the style must hold for the whole call: the figure is drawn at 72 dpi, a point
    is a pixel, and the smallest text (10 pt) stays about 10 CSS px in the book's column.
    """
    @functools.wraps(explorer)
    def styled(*args, **kwargs):
        with matplotlib.rc_context(plotting.BOOK_STYLE):
            return explorer(*args, **kwargs)
    return styled


def _figure(w, h):
    fig = Figure(figsize=(w, h), layout="constrained")
    fig.patch.set_facecolor("white")
    return fig


def _badge(ok, yes, no):
    color = plotting.COLORS["green"] if ok else plotting.COLORS["vermillion"]
    return f'<span style="color:{color};font-weight:bold">{yes if ok else no}</span>'


def _steps(lo, hi, n):
    """``n`` values from ``lo`` to ``hi``, rounded so the slider prints them exactly."""
    return [float(v) for v in np.round(np.linspace(lo, hi, n), 4)]


def sliders_of(widget):
    """The sliders of an explorer, by description, in order.

    Examples
    --------
    >>> list(sliders_of(collision_explorer(steps=3)))
    ['centre x (m)', 'centre y (m)']
    """
    return {s.description: s for s in stack_sliders(widget)}


@_book_style
def arm_explorer(arm, obstacles=(), grid=None, *, q=None, cells=90, steps=None):
    """A slider per joint; the arm in the workspace and, for 2 joints, its point in C-space.

    Parameters
    ----------
    arm : rapp.Arm
    obstacles : sequence of Circle / Polygon
    grid : rapp.JointGrid, optional
        The C-space grid (2-joint arms); ``JointGrid(arm, cells)`` when None.
    q : array_like, shape (n,), optional
        The configuration shown first, exactly: each angle inside its joint's limits is added to
        its slider's values (an angle outside them opens at the nearest value). All zeros when
        None.
    steps : int, optional
        Evenly spaced values per slider, from each joint's lower to upper limit. Default: 19 for
        two joints (20 degrees apart on a free joint), fewer for more joints so that the views
        (one per combination of values, ``q``'s included) stay under about 400 (the page stays
        light and becomes interactive quickly).

    Returns
    -------
    ipywidgets.VBox
        The status line says ``collision`` or ``free``, with the clearance and the end effector.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> w = arm_explorer(Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)], cells=16, steps=5)
    >>> list(sliders_of(w)), "collision" in selected(w)[1]
    (['θ1 (rad)', 'θ2 (rad)'], True)
    >>> values_of(arm_explorer(Arm([1.0, 1.0]), q=[0.123, -1.5], steps=5))
    {'q0': 0.123, 'q1': -1.5}
    """
    obstacles = tuple(obstacles)
    n = arm.n
    if steps is None:
        steps = max(3, int(np.floor(361 ** (1.0 / n) + 1e-9)))
        if q is not None and (steps + 1) ** n > 400:
            steps -= 1  # room for q's own values
    q0 = np.zeros(n) if q is None else np.asarray(q, dtype=float)

    def values(i):
        even = _steps(arm.lower[i], arm.upper[i], int(steps))
        if q is None or not arm.lower[i] <= q0[i] <= arm.upper[i]:
            return even
        return sorted(set(even) | {round(float(q0[i]), 4)})

    controls = {f"q{i}": Control(f"θ{i + 1} (rad)", values(i), default=float(q0[i]))
                for i in range(n)}
    fig = _figure(10.0 if n == 2 else 5.0, 5.0)
    axs = subplots(fig, 1, 2 if n == 2 else 1)
    ax_w = axs[-1] if n == 2 else axs
    if n == 2:
        grid = JointGrid(arm, cells) if grid is None else grid
        plotting.plot_cspace(occupancy(arm, obstacles, grid), grid, axs[0])
    plotting.plot_workspace(arm, ax_w)
    plotting.plot_obstacles(obstacles, ax_w)

    framed = []

    def view(**values):
        q = np.array([values[f"q{i}"] for i in range(n)])
        if n == 2:
            axs[0].plot(*q, "o", color=plotting.START, ms=10, mec="white", mew=1.5, zorder=5)
        # The view stack freezes the limits its first view leaves: framing once is enough, and
        # re-framing every view was a third of the explorer's build time.
        plotting.plot_arm(arm, q, ax_w, frame=not framed)
        framed.append(True)
        hit = bool(collides(arm, q, obstacles)) if obstacles else False
        ax_w.set_title("collision" if hit else "free", fontsize="medium",
                       color=plotting.COLORS["vermillion"] if hit else plotting.TEXT)
        text = _badge(not hit, "free", "collision")
        if obstacles:
            text += f" &nbsp; clearance {float(clearance(arm, q, obstacles)):.3f} m"
        ee = arm.end_effector(q)
        return text + f" &nbsp; end effector ({ee[0]:.3f}, {ee[1]:.3f}) m"

    return view_stack(fig, controls, view, title="Arm explorer")


@_book_style
def collision_explorer(a=(0.0, 0.0), b=(1.0, 0.0), center=(1.6, 0.1), radius=0.3, *,
                       extent=2.0, steps=17):
    """Segment against disc: move the disc and watch the closest point of the segment follow.

    Two sliders move the disc's centre over ``[-extent, extent]``; the segment ``ab`` and the
    radius stay. The figure shows the clipped projection (the true closest point) and the
    foot on the infinite line (the MIS's formula); the status compares
    ``segment_circle_distance`` (the true clearance) with ``line_distance_mis - r`` and flags a
    *false collision* when the MIS's formula reports a hit the segment does not make. The
    default view is such a case: the disc lies beyond the segment's end, on its line.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> w = collision_explorer(steps=5)
    >>> "false collision" in selected(w)[1]
    True
    """
    values = _steps(-extent, extent, steps)
    controls = {"cx": Control("centre x (m)", values, default=float(center[0])),
                "cy": Control("centre y (m)", values, default=float(center[1]))}
    A, B, r = tuple(map(float, a)), tuple(map(float, b)), float(radius)
    fig = _figure(5.5, 5.5)
    ax = subplots(fig)
    ax.set_xlim(-extent - r, extent + r)
    ax.set_ylim(-extent - r, extent + r)

    def view(cx, cy):
        C = (cx, cy)
        seg = float(segment_circle_distance(A, B, C, r))
        line = float(line_distance_mis(A, B, C)) - r
        plotting.plot_segment_circle(A, B, C, r, ax)
        hit, mis_hit = seg <= 0, line <= 0
        false = mis_hit and not hit
        ax.set_title("FALSE COLLISION (MIS formula)" if false else
                     ("collision" if hit else "free"), fontsize="medium",
                     color=plotting.COLORS["vermillion"] if (false or hit) else plotting.TEXT)
        text = (f"segment clearance {seg:.3f} m: {_badge(not hit, 'free', 'collision')}"
                f" &nbsp;|&nbsp; MIS line clearance {line:.3f} m: "
                f"{_badge(not mis_hit, 'free', 'collision')}")
        if false:
            text += (" &nbsp; <b>disagree: a false collision</b>: the obstacle is near the"
                     " line's extension, not the segment")
        return text

    return view_stack(fig, controls, view, title="Segment–circle collision")


def _failure_cspace(scenario, cells, ax):
    """What a failed plan's grid shows: its C-space, the start's free region, the joint limits.

    A failure view teaches only if it shows why: the cells reachable from the start (shaded
    blue) and whether the goal is among them. Returns that sentence (empty for arms of more than
    two joints or a Cartesian goal, where the grid has no single goal cell to show).
    """
    arm = scenario.arm
    if arm.n != 2:
        return ""
    grid = JointGrid(arm, cells)
    occ = occupancy(arm, scenario.obstacles, grid)
    start = grid.index(np.asarray(scenario.start, dtype=float))
    reach = bfs_distances(occ, tuple(int(i) for i in start), wraps=grid.wraps) >= 0
    goal = None if scenario.goal_q is None else np.asarray(scenario.goal_q, dtype=float)
    plotting.plot_cspace(occ, grid, ax, start=np.asarray(scenario.start, dtype=float), goal=goal,
                         expanded=reach, title="C-space: blue = reachable from the start")
    lo, hi = ax.get_xlim()
    for i, axis in enumerate("xy"):
        if not grid.wraps[i]:  # the angles the joint may not take, outside its limits
            span = ax.axvspan if axis == "x" else ax.axhspan
            for a, b in ((-np.pi, arm.lower[i]), (arm.upper[i], np.pi)):
                if b > a:
                    span(a, b, facecolor="none", edgecolor=plotting.TEXT, hatch="///", lw=0.0,
                         alpha=0.5, zorder=1)
    free = int((~occ).sum())
    if goal is None:
        return f"The start reaches {int(reach.sum())} of the grid's {free} free cells."
    inside = bool(reach[tuple(int(i) for i in grid.index(goal))])
    where = "and the goal is among them" if inside else "and the goal is not among them"
    limits = "; hatched: beyond the joint limits" if not all(grid.wraps) else ""
    return (f"The start reaches {int(reach.sum())} of the grid's {free} free cells (blue), "
            f"{where}{limits}.")


def playground_status(metrics, report, *, weight=1.0, shaded=True):
    """What a plan did, in two sentences a student reads: the search, then the motion.

    Parameters
    ----------
    metrics : dict
        A plan's ``metrics`` (:func:`rapp.plan`): ``expansions``, ``expansions_total``,
        ``grid_cells``, ``path_cells``, ``bfs_optimum_cells``, ``certification_repairs``,
        ``shortcut_waypoints``, ``waypoint_length_rad`` and ``shortcut_length_rad``.
    report : rapp.verify.Report
        The plan's verification report.
    weight : float
        The heuristic weight the search ran with; above 1 a longer path is put down to it.
    shaded : bool
        Whether the figure shades the expanded cells (2-joint grids).

    Returns
    -------
    str
        Plain text (no markup): how many of the grid's cells A* expanded and how long its path
        is against the fewest steps possible, the repairs when a move between two free cells
        could not be certified, then the shortcut and the verification's verdict.

    Examples
    --------
    >>> m = {"expansions": 779, "expansions_total": 779, "grid_cells": 10000, "path_cells": 92,
    ...      "bfs_optimum_cells": 92, "certification_repairs": 0, "shortcut_waypoints": 4,
    ...      "waypoint_length_rad": 5.817, "shortcut_length_rad": 4.442}
    >>> class Passed:
    ...     ok, failed = True, ()
    >>> print(playground_status(m, Passed()))
    A* expanded 779 of the grid's 10,000 cells (shaded blue) and found a path of 92 steps, the fewest possible on this grid. Shortcutting leaves 4 waypoints, 4.44 rad of joint motion instead of 5.82 rad, and the verification passed.
    """
    m = metrics
    steps, fewest = int(m["path_cells"]), int(m["bfs_optimum_cells"])
    search = (f"A* expanded {int(m['expansions']):,} of the grid's {int(m['grid_cells']):,} cells"
              + (" (shaded blue)" if shaded else ""))
    repairs = int(m.get("certification_repairs", 0))
    if repairs:
        search += (f" in its last search ({int(m['expansions_total']):,} in all: {repairs} "
                   f"{'move' if repairs == 1 else 'moves'} between free cells could not be certified, "
                   f"so A* blocked {'its cell' if repairs == 1 else 'their cells'} and searched again)")
    if steps == fewest:
        length = f"a path of {steps} steps, the fewest possible on this grid"
    else:
        length = (f"a path of {steps} steps, {steps - fewest} more than the fewest possible "
                  f"({fewest})" + (f": the heuristic weight {weight:g} trades length for fewer "
                                   "expansions" if weight > 1 else ""))
    verdict = ("the verification passed" if report.ok else "the verification failed ("
               + ", ".join(c.name for c in report.failed) + ")")
    short, grid_path = f"{m['shortcut_length_rad']:.2f}", f"{m['waypoint_length_rad']:.2f}"
    motion = (f"Shortcutting leaves {int(m['shortcut_waypoints'])} waypoints, "
              + (f"{short} rad of joint motion instead of {grid_path} rad" if short != grid_path
                 else f"the same {short} rad of joint motion") + f", and {verdict}.")
    return f"{search} and found {length}. {motion}"


@_book_style
def planner_playground(scenarios, *, cells=(30, 60, 90), weights=(1.0, 1.5, 2.0, 3.0, 5.0)):
    """Plan scenarios at several grid sizes and heuristic weights, and compare.

    Every combination is planned with :func:`rapp.plan` when the playground is built and drawn
    with :func:`rapp.plotting.plot_plan`, the cells A* expanded shaded: a larger weight
    visibly expands fewer, a coarser grid plans faster and may find no path. A planning
    failure (no path, no IK solution) is shown as such.

    Parameters
    ----------
    scenarios : Scenario or mapping of str to Scenario
        One scenario, or several by name (a slider picks one).
    cells : sequence of int
        Cells per joint to offer.
    weights : sequence of float
        Heuristic weights ``w >= 1`` to offer.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> from rapp import load_scenario
    >>> w = planner_playground(load_scenario("default"), cells=(40,), weights=(1.0, 3.0))
    >>> list(sliders_of(w)), "A* expanded" in selected(w)[1]
    (['cells / joint', 'heuristic w'], True)
    """
    named = dict(scenarios) if hasattr(scenarios, "items") else {"scenario": scenarios}
    first = next(iter(named.values()))
    controls = {}
    if len(named) > 1:
        controls["name"] = Control("scenario", list(named), default=next(iter(named)), fmt="{}")
    controls["cells"] = Control("cells / joint", [int(c) for c in cells],
                                default=int(np.max(first.planner.cells)), fmt="{}")
    controls["weight"] = Control("heuristic w", [float(w) for w in weights],
                                 default=float(first.planner.heuristic_weight), fmt="{:g}")
    fig = _figure(10.5, 5.0)
    ax_c, ax_w = subplots(fig, 1, 2)
    reach = max(s.arm.reach[1] for s in named.values())
    lim = 1.1 * reach
    ax_w.set_xlim(-lim, lim)
    ax_w.set_ylim(-lim, lim)
    ax_c.set_xlim(-np.pi, np.pi)
    ax_c.set_ylim(-np.pi, np.pi)

    def view(cells, weight, name=next(iter(named))):
        scenario = named[name]
        planner = dataclasses.replace(scenario.planner, cells=(int(cells),) * scenario.arm.n,
                                      heuristic_weight=float(weight))
        s = dataclasses.replace(scenario, planner=planner)
        try:
            p = run_plan(s)
        except RappError as exc:
            plotting.plot_workspace(s.arm, ax_w)
            plotting.plot_obstacles(s.obstacles, ax_w)
            plotting.plot_arm(s.arm, np.asarray(s.start, dtype=float), ax_w, color=plotting.START)
            if s.goal_xy is not None:
                ax_w.plot(*s.goal_xy, "*", color=plotting.GOAL, ms=14)
            ax_w.set_title(f"{type(exc).__name__}", fontsize="medium",
                           color=plotting.COLORS["vermillion"])
            told = _failure_cspace(s, int(cells), ax_c)
            return (_badge(False, "", type(exc).__name__) + " " + html.escape(str(exc))
                    + ("<br>" + told if told else ""))
        closed = p.expanded if np.ndim(p.occupancy) == 2 else None
        plotting.plot_plan(p, s, expanded=closed, axes=(ax_c, ax_w))
        return _badge(True, "planned", "") + " &nbsp; " + html.escape(
            playground_status(p.metrics, p.report, weight=weight, shaded=closed is not None),
            quote=False)

    return view_stack(fig, controls, view, title="Planner playground")


@_book_style
def trajectory_explorer(t0=0.0, tf=2.0, p0=0.0, pf=1.0, v0=0.0, vf=0.0, a0=0.0, af=0.0, *,
                        accelerations=None):
    """Cubic against quintic for the same boundary values; sliders set the end accelerations.

    The cubic (``rapp.cubic``) meets positions and velocities only, so it ignores the
    accelerations asked for; the quintic (``rapp.quintic``) meets them too. The sliders choose
    the accelerations at the start and the end; the status shows what each polynomial actually
    has there.

    Parameters
    ----------
    accelerations : sequence of float, optional
        The values each slider offers (rad/s²); default -5 to 5 in steps of 1.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> w = trajectory_explorer(a0=1.0, accelerations=[0.0, 1.0])
    >>> "quintic 1.000, 0.000 (set: 1.000, 0.000)" in selected(w)[1]
    True
    """
    values = [float(v) for v in (np.arange(-5.0, 5.5, 1.0) if accelerations is None else accelerations)]
    controls = {"a0": Control("a0 (rad/s²)", values, default=float(a0), fmt="{:g}"),
                "af": Control("af (rad/s²)", values, default=float(af), fmt="{:g}")}
    P = np.polynomial.polynomial
    c3 = np.asarray(cubic(t0, tf, p0, pf, v0, vf), dtype=float)
    fig = _figure(6.5, 6.0)
    axs = subplots(fig, 3, 1, sharex=True)
    # Limits that hold every view: the curves of the extreme accelerations bound the rest.
    t = np.linspace(t0, tf, 200)
    curves = [c3] + [np.asarray(quintic(t0, tf, p0, pf, v0, vf, x, y), dtype=float)
                     for x in (min(values), max(values)) for y in (min(values), max(values))]
    for d, ax in enumerate(axs):
        ys = np.concatenate([P.polyval(t, P.polyder(c, d) if d else c) for c in curves])
        pad = 0.08 * max(float(np.ptp(ys)), 1e-6)
        ax.set_ylim(float(ys.min()) - pad, float(ys.max()) + pad)
        ax.set_xlim(t0, tf)

    def view(a0, af):
        c5 = np.asarray(quintic(t0, tf, p0, pf, v0, vf, a0, af), dtype=float)
        plotting.plot_polynomials({"cubic": c3, "quintic": c5}, t0, tf, axes=axs)
        ends = np.array([t0, tf])
        acc3 = P.polyval(ends, P.polyder(c3, 2))
        acc5 = P.polyval(ends, P.polyder(c5, 2))
        return (f"end accelerations (rad/s²): cubic {acc3[0]:.3f}, {acc3[1]:.3f} (not chosen)"
                f" &nbsp;|&nbsp; quintic {acc5[0]:.3f}, {acc5[1]:.3f} (set: {a0:.3f}, {af:.3f})")

    return view_stack(fig, controls, view, title="Cubic vs quintic")


@_book_style
def astar_explorer(occupied, start, goal, *, weights=(1.0,), wraps=True, step=None):
    """Step through A* one expansion at a time, for one or several heuristic weights.

    One trace (:func:`rapp.search.astar_steps`) per weight; the step slider runs over the
    longest, and a search that ended earlier shows its final state with its path. Drawn with
    :func:`rapp.plotting.plot_astar_step`: closed set, open list, the cell being expanded, and
    the path at the end.

    Parameters
    ----------
    occupied : bool array, 2-D
    start, goal : pair of int
    weights : sequence of float
        Heuristic weights ``w >= 1`` to compare (a slider when more than one).
    step : int, optional
        The step shown first (1-based); the last when None.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> grid = np.zeros((6, 6), bool); grid[1:5, 3] = True
    >>> w = astar_explorer(grid, (2, 1), (2, 5), weights=(1.0, 3.0), step=1)
    >>> list(sliders_of(w)), "step 1 of" in selected(w)[1]
    (['heuristic w', 'step'], True)
    """
    from rapp.search import astar_steps

    traces = {float(w): astar_steps(occupied, start, goal, wraps=wraps, heuristic_weight=float(w))
              for w in weights}
    last = max(t.expansions for t in traces.values()) + 1
    controls = {}
    if len(traces) > 1:
        controls["weight"] = Control("heuristic w", list(traces), default=min(traces), fmt="{:g}")
    controls["step"] = Control("step", list(range(1, last + 1)), default=last if step is None else step,
                               fmt="{}")
    fig = _figure(8.4, 5.6)
    ax = subplots(fig)

    def view(step, weight=min(traces)):
        trace = traces[weight]
        k = min(step - 1, trace.expansions)
        plotting.plot_astar_step(trace, k, ax)
        if k == trace.expansions:
            return (f"w = {weight:g}: step {step} of {last}: done after {trace.expansions} "
                    f"expansions, path of {trace.cost} steps")
        cell = tuple(int(i) for i in trace.current[k])
        g = int(trace.g[k][cell])
        return (f"w = {weight:g}: step {step} of {last}: expand {cell}, g = {g}, "
                f"f = g + w h = {g + float(trace.h[cell]):g}; {int(trace.closed[k].sum())} closed, "
                f"{int(trace.frontier[k].sum())} open")

    return view_stack(fig, controls, view, title="A*, one expansion at a time")


@_book_style
def rrt_explorer(arm, result, trace, *, occupancy=None, grid=None, goal=None, step=None):
    """Step through the growth of an RRT, one iteration at a time.

    Parameters
    ----------
    arm : rapp.Arm
    result : rapp.RRTResult
        What :func:`rapp.rrt` returned ...
    trace : list of rapp.rrt.RRTStep
        ... with this ``trace``; each step is drawn with :func:`rapp.plotting.plot_rrt_step`.
    occupancy, grid, goal : optional
        As for :func:`rapp.plotting.plot_rrt_step`.
    step : int, optional
        The iteration shown first (1-based); the end when None.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> from rapp import Arm, rrt
    >>> arm = Arm([1.0, 1.0]); steps = []
    >>> r = rrt(arm, [0.0, 0.0], [1.0, 1.0], [], step=0.5, seed=1, trace=steps)
    >>> w = rrt_explorer(arm, r, steps, step=1)
    >>> "iteration 1 of" in selected(w)[1]
    True
    """
    last = len(trace) + 1
    controls = {"step": Control("iteration", list(range(1, last + 1)),
                                default=last if step is None else step, fmt="{}")}
    fig = _figure(8.4, 5.6)
    ax = subplots(fig)
    if occupancy is not None:  # the same in every view: drawn once, in the background
        plotting.plot_light_cspace(occupancy, grid, ax)

    def view(step):
        k = step - 1
        plotting.plot_rrt_step(arm, result, trace, k, ax, occupancy=occupancy, grid=grid, goal=goal)
        if k == len(trace):
            return (f"iteration {step} of {last}: the end, {len(result.nodes)} nodes"
                    + (f", path cost {result.cost:.3f} rad" if result.success else ", no path"))
        record = trace[k]
        toward = "the goal (goal bias)" if record.goal_biased else "a random sample"
        what = {"added": "the new edge is free: added", "blocked": "the new edge is blocked",
                "no move": "the target is the nearest node: no move"}.get(record.status, record.status)
        return f"iteration {step} of {last}: extend toward {toward}; {what}"

    return view_stack(fig, controls, view, title="RRT, one iteration at a time")


#: The names the comparison explorer shows for the planners of :data:`rapp.planners.PLANNERS`.
PLANNER_LABELS = {"astar": "A*", "rrt": "RRT", "rrt_connect": "RRT-Connect", "rrt_star": "RRT*",
                  "prm": "PRM"}


def comparison_run(arm, start, goal, obstacles, planner, settings, seed):
    """One planner of rapp's planner table on one problem: ``(its result, a status line)``.

    ``settings`` are the planner's own (:func:`rapp.planners.run` hands it those it reads); the
    status line says what a student needs: the path's cost, or that there is none, and the work.

    Examples
    --------
    >>> from rapp import Arm
    >>> r, status = comparison_run(Arm([1.0, 1.0]), [0.0, 0.0], [1.0, 1.0], [], "rrt_connect",
    ...                            {"step": 0.2}, 0)
    >>> r.success, status.startswith("RRT-Connect, seed 0: a path of")
    (True, True)
    """
    from rapp import planners

    r = planners.run(planner, arm, start, goal, obstacles, seed=seed, raise_on_failure=False,
                     **settings)
    if planner == "astar":
        cells = settings.get("cells", "?")
        return r, (f"A* on {cells} × {cells} cells (every seed the same): "
                   f"{r.metrics['path_cells']} steps, {r.cost:.2f} rad")
    what = "searches" if planner == "prm" else "iterations"
    outcome = f"a path of {r.cost:.2f} rad" if r.success else "no path"
    return r, (f"{PLANNER_LABELS.get(planner, planner)}, seed {seed}: {outcome} after "
               f"{r.iterations} {what}, {len(r.nodes)} nodes")


@_book_style
def planner_comparison(arm, start, goal, obstacles, settings, *, seeds=(0, 1, 2, 3),
                       default="rrt_connect", cells=120):
    """Several planners and seeds on one 2-joint problem, in C-space: a planner menu, a seed slider.

    Each view draws the planner's tree (or PRM's roadmap and its last shortest-path tree) in
    light blue on the light C-space of ``cells`` per joint, and the path it returned in orange,
    before shortcutting; the status line is :func:`comparison_run`'s.

    Parameters
    ----------
    arm : rapp.Arm
        Two joints.
    start, goal : array_like
        The configurations joined.
    obstacles : sequence of rapp.Circle or rapp.Polygon
    settings : dict
        Planner name (of :data:`rapp.planners.PLANNERS`) to its settings; the menu lists them in
        this order.
    seeds : sequence of int
        The seed slider's values.
    default : str
        The planner shown first.
    cells : int
        Cells per joint of the drawn C-space (not the planners' grid).

    Returns
    -------
    ipywidgets.VBox
        Its ``results`` attribute maps ``(planner, seed)`` to the planner's result.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> w = planner_comparison(Arm([1.0, 1.0]), [0.0, 0.0], [1.0, 1.0], [Circle((1.5, 1.5), 0.2)],
    ...                        {"rrt_connect": {"step": 0.3}, "prm": {"samples": 30}}, seeds=(0,),
    ...                        cells=24)
    >>> sorted(w.results), selected(w)[1].startswith("RRT-Connect, seed 0: a path of")
    ([('prm', 0), ('rrt_connect', 0)], True)
    """
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    label = {key: PLANNER_LABELS.get(key, key) for key in settings}
    key_of = {text: key for key, text in label.items()}
    results = {}
    fig = _figure(6.4, 5.4)
    ax = subplots(fig)
    grid = JointGrid(arm, cells)
    plotting.plot_light_cspace(occupancy(arm, obstacles, grid), grid, ax)   # every view's background
    ax.plot(*arm.wrap(start), "o", color=plotting.START, ms=8)
    ax.plot(*arm.wrap(goal), "*", color=plotting.GOAL, ms=12)
    ax.set_xlim(-np.pi, np.pi)
    ax.set_ylim(-np.pi, np.pi)
    ax.set_xlabel("θ1 (rad)")
    ax.set_ylabel("θ2 (rad)")
    plotting.style_axes(ax)

    def view(planner, seed):
        key = key_of[planner]
        r, status = comparison_run(arm, start, goal, obstacles, key, settings[key], seed)
        results[key, seed] = r
        nodes, parent = r.details.get("nodes"), r.details.get("parent")
        if nodes is not None and len(nodes) > 1:
            plotting.plot_tree(arm, nodes, parent, ax)
        if r.success:
            s = plotting.split_at_seam(r.path, [-np.pi] * 2, [2 * np.pi] * 2, [True, True])
            ax.plot(s[:, 0], s[:, 1], "-", color=plotting.COLORS["orange"], lw=2.5)
        ax.set_title(f"{planner}, seed {seed}", fontsize="medium")
        return status

    w = view_stack(fig, {"planner": Control("planner", list(label.values()), default=label[default]
                                            if default in label else None, fmt="{}"),
                         "seed": Control("seed", list(seeds), default=seeds[0], fmt="{}")},
                   view, title=f"{len(settings)} planners on one problem")
    w.results = results
    return w


@_book_style
def ik_explorer(arm, targets, *, default=(1.2, 0.9)):
    """Drag a target over the workspace of a 2-link arm: both IK solutions, or why there is none.

    Two sliders place the target (a cross) on the grid ``targets`` x ``targets`` (metres); each
    view draws the workspace and the solutions :func:`rapp.ik` returns, elbow-down (blue) and
    elbow-up (orange), or titles the reason there is none. The status line prints both
    configurations.

    Examples
    --------
    >>> from rapp import Arm
    >>> w = ik_explorer(Arm([1.0, 0.8]), [0.0, 1.2], default=(1.2, 0.0))
    >>> selected(w)[1]
    'target (1.2, 0.0) m: elbow-down q = (-0.723, 1.696) rad; elbow-up q = (0.723, -1.696) rad'
    """
    from rapp.ik import NoIKSolution, ik

    fig = _figure(5.5, 5.5)
    ax = subplots(fig)
    plotting.plot_workspace(arm, ax)
    plotting.style_axes(ax)
    reach = float(sum(arm.link_lengths)) * 1.1
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    names = ("elbow-down", "elbow-up")

    def view(tx, ty):
        ax.plot(tx, ty, "x", color="k", ms=12, mew=2, zorder=6)
        try:
            solutions = ik(arm, [tx, ty])
        except NoIKSolution as err:
            ax.set_title(f"no solution: {err.reason}", fontsize="medium")
            return f"target ({tx:.1f}, {ty:.1f}) m: no solution, {err.reason}"
        for q, color, name in zip(solutions, (plotting.COLORS["blue"], plotting.COLORS["orange"]), names):
            plotting.plot_arm(arm, q, ax, color=color, label=name, frame=False)
        ax.legend(loc="lower left", fontsize="small")
        ax.set_title(f"{len(solutions)} solution{'s' if len(solutions) > 1 else ''}", fontsize="medium")
        shown = "; ".join(f"{name} q = ({q[0]:.3f}, {q[1]:.3f}) rad" for q, name in zip(solutions, names))
        return f"target ({tx:.1f}, {ty:.1f}) m: {shown}"

    return view_stack(fig, {"tx": Control("target x (m)", list(targets), default=default[0]),
                            "ty": Control("target y (m)", list(targets), default=default[1])},
                      view, title="IK explorer")


@_book_style
def line_ride_explorer(ride, *, frames=27, default=9):
    """Ride along a line in time: the arm, its velocity ellipse and tip velocity, the joint speeds.

    ``ride`` is a :class:`rapp.cartesian.LineRide`. A slider steps through ``frames`` instants
    from rest to rest (opening at the ``default``-th); each view draws the arm, the velocity
    ellipse at 0.3 s of travel and the tip's velocity arrow, and marks the instant on the joint
    speeds' plot. The status line prints the tip speed, manipulability, condition number and
    joint speeds.

    Examples
    --------
    >>> from rapp import Arm
    >>> from rapp.cartesian import line_path, ride_line
    >>> from rapp.ik import ik_2link
    >>> arm = Arm([1.0, 1.0])
    >>> ride = ride_line(arm, [1.0, 0.5], [1.5, 0.5], line_path(arm, ik_2link(arm, [1.0, 0.5])[0], [1.5, 0.5]),
    ...                  vmax=0.5, amax=0.5)
    >>> w = line_ride_explorer(ride, frames=3, default=1)
    >>> selected(w)[1].split(":")[0]
    't = 1.00 s'
    """
    from rapp.manipulability import condition_number, manipulability
    from rapp.plot_motion import plot_velocity_ellipse

    arm, duration, colors = ride.arm, ride.timing.duration, plotting.COLORS
    t_dense = np.linspace(0.0, duration, 401)
    qdot_dense = np.array([ride.state(t)[2] for t in t_dense])
    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax_arm, ax_speed = fig.subplots(1, 2)
    plotting.plot_workspace(arm, ax_arm)
    ax_arm.plot(*np.array([ride.a, ride.b]).T, "-", color=colors["black"], lw=1)
    for j, color in enumerate((colors["blue"], colors["green"])):
        ax_speed.plot(t_dense, np.abs(qdot_dense[:, j]), color=color, lw=2, label=fr"$|\dot\theta_{j + 1}|$")
    ax_speed.set(xlabel="t (s)", ylabel="joint speed (rad/s)", xlim=(0, duration),
                 ylim=(0, 1.1 * np.abs(qdot_dense).max()))
    ax_speed.grid(True, alpha=0.3)
    ax_speed.legend(fontsize="small", loc="upper right")
    for ax in (ax_arm, ax_speed):
        plotting.style_axes(ax)

    def view(t):
        qq, xdot, qdot = ride.state(t)
        plotting.plot_arm(arm, qq, ax_arm, frame=False)
        plot_velocity_ellipse(ax_arm, arm, qq, 0.3, facecolor=colors["orange"], alpha=0.5,
                              edgecolor=colors["vermillion"], zorder=6)
        tip = arm.end_effector(qq)
        ax_arm.annotate("", tip + xdot, tip, arrowprops=dict(arrowstyle="->", color=colors["black"], lw=2),
                        zorder=7)
        ax_speed.axvline(t, color=colors["vermillion"], lw=1.5)
        ax_arm.set_title(f"t = {t:.2f} s", fontsize="medium")
        w_t, k_t = float(manipulability(arm, qq)), float(condition_number(arm, qq))
        return (f"t = {t:.2f} s: tip speed {np.linalg.norm(xdot):.2f} m/s, w = {w_t:.3f} m²/rad², "
                f"κ = {k_t:.1f}, joint speeds ({qdot[0]:+.2f}, {qdot[1]:+.2f}) rad/s")

    times = [round(float(x), 3) for x in np.linspace(0.0, duration, frames)]
    return view_stack(fig, {"t": Control("time (s)", times, default=times[default])}, view,
                      title="Ride along the line")
