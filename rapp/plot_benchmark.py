"""Figures of planner benchmarks: success against budget, cost against budget, the recorded comparison.

Chapter 14's figures. Each function takes values a planner or :mod:`rapp.compare` returned and
returns the :class:`matplotlib.figure.Figure` it drew; nothing here runs a planner, nothing calls
``plt.show()``.

Examples
--------
>>> import numpy as np
>>> fig = plot_success_by_budget({"RRT": np.array([1, 4])}, [10, 100], 5)
>>> fig.axes[0].get_xscale()
'log'
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.colors import ListedColormap

from rapp.collision import collides
from rapp.compare import mean_interval, wilson
from rapp.cspace import JointGrid, occupancy as occupancy_grid
from rapp.palette import COLORS, GOAL, START, TEXT
from rapp.paths import split_at_seam
from rapp.plotting import plot_arm, plot_cspace, plot_light_cspace, plot_obstacles, style_axes
from rapp.search import bfs_distances

__all__ = ["FAMILY_STYLE", "plot_grid_gap", "plot_success_by_budget", "plot_shortcuts",
           "plot_cost_by_budget", "plot_narrow_gap", "plot_success_rates", "plot_time_and_length"]

#: Colour and marker of each planner family in the recorded comparison's figures.
FAMILY_STYLE = {"A* coarse": ("#bbbbbb", "s"), "A* medium": (COLORS["grey"], "s"),
                "A* fine": (COLORS["black"], "s"), "RRT": (COLORS["blue"], "o"),
                "RRT-Connect": (COLORS["orange"], "o"), "RRT*": (COLORS["green"], "o"),
                "PRM": (COLORS["purple"], "o"), "OMPL RRT-Connect": (COLORS["vermillion"], "^"),
                "OMPL RRT*": (COLORS["sky"], "^")}
_GRID = "#e6e6e6"
_WRAP = ([-np.pi] * 2, [2 * np.pi] * 2, [True, True])


def plot_grid_gap(arm, discs, q_start, q_goal, fine, cells=60):
    """The workspace with a gap, a coarse grid's C-space that misses it, a finer plan through it.

    Returns ``(fig, grid, occupancy, reachable)``: the coarse grid, its occupancy and the cells
    reachable from the start's cell (shaded in the middle panel).

    Examples
    --------
    >>> import rapp
    >>> arm = rapp.Arm([1.0, 1.0])
    >>> p = rapp.plan({"arm": {"link_lengths": [1, 1]}, "start": [0, 0], "goal": {"joints": [1, 1]},
    ...                "planner": {"cells": 24}})
    >>> fig, grid, occ, reach = plot_grid_gap(arm, [], [0, 0], [1, 1], p, cells=12)
    >>> len(fig.axes), occ.shape, bool(reach.all())
    (3, (12, 12), True)
    >>> plt.close(fig)
    """
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.4), layout="constrained")
    plot_obstacles(discs, axes[0])
    plot_arm(arm, q_start, axes[0], color=START, label="start")
    plot_arm(arm, q_goal, axes[0], color=GOAL, label="goal")
    axes[0].set_xlim(-0.6, 2.2)
    axes[0].set_ylim(-0.8, 2.1)
    axes[0].set_title("two discs, a 0.2 m gap", fontsize="medium")
    axes[0].legend(loc="lower left", fontsize="small")
    grid = JointGrid(arm, cells)
    occ = occupancy_grid(arm, discs, grid)
    reach = bfs_distances(occ, tuple(grid.index(q_start).tolist())) >= 0
    plot_cspace(occ, grid, axes[1], start=q_start, goal=q_goal,
                title=f"{cells} cells: NoPathFound, with δ ≤ ρ")
    axes[1].imshow(np.ma.masked_where(~reach.T, reach.T), origin="lower",
                   extent=axes[1].images[0].get_extent(), cmap=ListedColormap([COLORS["sky"]]),
                   alpha=0.35, interpolation="nearest", zorder=1)
    plot_cspace(fine.occupancy, fine.grid, axes[2], path=fine.waypoints, start=q_start,
                goal=q_goal, title=f"{fine.grid.shape[0]} cells: a verified plan")
    return fig, grid, occ, reach


def plot_success_by_budget(found, budgets, seeds):
    """Fraction of ``seeds`` runs with a path within each budget, with Wilson 95 % intervals.

    ``found[name]`` counts, per budget, the runs that had a path within it.

    Examples
    --------
    >>> fig = plot_success_by_budget({"RRT": np.array([2, 5])}, [10, 100], 5)
    >>> [round(float(v), 1) for v in fig.axes[0].lines[0].get_ydata()]
    [0.4, 1.0]
    >>> plt.close(fig)
    """
    fig, ax = plt.subplots(figsize=(10, 4), layout="constrained")
    for (name, k), colour, shift in zip(found.items(), (COLORS["blue"], COLORS["orange"]), (0.97, 1.03)):
        rate = k / seeds
        lo, hi = np.array([wilson(int(c), seeds) for c in k]).T
        ax.errorbar(np.array(budgets) * shift, rate, yerr=[rate - lo, hi - rate], fmt="o-", capsize=4,
                    color=colour, label=f"{name} ({seeds} seeds)")
    ax.set_xscale("log")
    ax.set_xticks(budgets, [str(b) for b in budgets])
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel("iteration budget K (iterations)")
    ax.set_ylabel("fraction of runs with a path")
    ax.set_title("three-disc benchmark, step 0.2 rad: success within the budget, Wilson 95 % intervals",
                 fontsize="medium")
    ax.legend(loc="lower right", fontsize="small")
    ax.grid(True, color=_GRID, linewidth=0.6)
    style_axes(ax)
    return fig


def plot_shortcuts(plans, titles):
    """Each plan's C-space with its grid path and, dashed, its shortcut path; one panel a plan.

    Examples
    --------
    >>> import rapp
    >>> p = rapp.plan({"arm": {"link_lengths": [1, 1]}, "start": [-1, -1], "goal": {"joints": [1, 1]},
    ...                "planner": {"cells": 24}})
    >>> fig = plot_shortcuts([p, p], ["a", "b"])
    >>> fig.axes[0].get_title().startswith("a: ")
    True
    >>> plt.close(fig)
    """
    fig, axes = plt.subplots(1, len(plans), figsize=(10, 4.4), layout="constrained")
    for ax, p, title in zip(np.atleast_1d(axes), plans, titles):
        m = p.metrics
        plot_cspace(p.occupancy, p.grid, ax, path=p.waypoints, start=p.q[0], goal=p.q[-1],
                    title=f"{title}: {m['path_cells']} steps, "
                          f"{m['waypoint_length_rad']:.2f} → {m['shortcut_length_rad']:.2f} rad")
        s = split_at_seam(p.shortcut, *_WRAP)
        ax.plot(s[:, 0], s[:, 1], "--", color=COLORS["blue"], lw=2, label="shortcut", zorder=2)
        ax.legend(loc="upper right", fontsize="small")
    return fig


def plot_cost_by_budget(costs, budgets, means, reference, baseline):
    """RRT*'s path cost against its budget (each seed thin, the mean with its interval).

    ``costs`` is (seeds, budgets), ``means`` a :func:`rapp.compare.mean_interval` per budget,
    ``reference`` RRT's first-path :func:`~rapp.compare.mean_interval` (a band) and ``baseline``
    the shortcut A* path's cost (a dashed line).

    Examples
    --------
    >>> c = np.array([[3.0, 2.5], [3.2, 2.6]])
    >>> fig = plot_cost_by_budget(c, [100, 200], [mean_interval(v) for v in c.T],
    ...                           mean_interval([4.0, 4.4]), 2.4)
    >>> len(fig.axes[0].lines) >= 3, fig.axes[0].get_xscale()
    (True, 'log')
    >>> plt.close(fig)
    """
    fig, ax = plt.subplots(figsize=(10, 4), layout="constrained")
    for c in costs:
        ax.plot(budgets, c, "-", color=COLORS["sky"], lw=0.8, zorder=1)
    m = np.array([[d["mean"], d["low"], d["high"]] for d in means])
    ax.errorbar(budgets, m[:, 0], yerr=[m[:, 0] - m[:, 1], m[:, 2] - m[:, 0]], fmt="o-", capsize=4,
                color=COLORS["blue"], label="RRT*: mean and 95 % interval (thin: each seed)", zorder=3)
    ax.axhspan(reference["low"], reference["high"], color=COLORS["orange"], alpha=0.25,
               label="RRT's first path: 95 % interval of the mean")
    ax.axhline(baseline, color=TEXT, ls="--", lw=1, label="A* (96 cells) + shortcutting")
    ax.set_xscale("log")
    ax.set_xticks(budgets, [str(k) for k in budgets])
    ax.set_xlabel("iteration budget K (iterations)")
    ax.set_ylabel("path cost (rad, joint space)")
    ax.set_title(f"three-disc benchmark, step 0.5 rad, {len(costs)} seeds", fontsize="medium")
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(True, color=_GRID, linewidth=0.6)
    style_axes(ax)
    return fig


def _gap_cspace(ax, arm, discs, q_start, q_goal, samples, path):
    g180 = JointGrid(arm, 180)
    plot_light_cspace(occupancy_grid(arm, discs, g180), g180, ax)
    shown = samples[:3000]
    free = ~collides(arm, shown, discs)
    ax.plot(*shown[free].T, ".", ms=1.5, color=COLORS["sky"], label="free samples (3000 drawn)")
    s = split_at_seam(path, *_WRAP)
    ax.plot(s[:, 0], s[:, 1], "-", color=COLORS["orange"], lw=2, label="RRT-Connect path, seed 0")
    ax.plot(*q_start, "o", color=START, ms=8, label="start")
    ax.plot(*q_goal, "*", color=GOAL, ms=12, label="goal")
    ax.set_xlim(-np.pi, np.pi)
    ax.set_ylim(-np.pi, np.pi)
    ax.set_xlabel("θ1 (rad)")
    ax.set_ylabel("θ2 (rad)")
    ax.set_title("gap of 0.2 m: C-space (grey: collision)", fontsize="medium")
    ax.legend(loc="upper right", fontsize="small")


def plot_narrow_gap(arm, discs, q_start, q_goal, samples, path, iterations, share):
    """A gap's C-space with free samples and a path; iterations against the gap's width.

    ``iterations[h]`` lists RRT-Connect's iterations (one a seed) for the half gap ``h`` (m),
    ``share[h]`` the fraction of samples that put the forearm in it.

    Examples
    --------
    >>> import rapp
    >>> arm = rapp.Arm([1.0, 1.0])
    >>> q = np.zeros((3, 2))
    >>> fig = plot_narrow_gap(arm, [], q[0], q[1], q, q, {0.1: [5, 7], 0.05: [9, 12]},
    ...                       {0.1: 0.02, 0.05: 0.01})
    >>> [float(x) for x in fig.axes[1].get_xticks()]
    [0.2, 0.1]
    >>> plt.close(fig)
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    _gap_cspace(ax1, arm, discs, q_start, q_goal, samples, path)
    half_gaps = list(iterations)
    widths = [2 * h for h in half_gaps]
    for w, h in zip(widths, half_gaps):
        ax2.plot([w] * len(iterations[h]), iterations[h], "o", color=COLORS["orange"], alpha=0.6)
    it = {h: mean_interval(v) for h, v in iterations.items()}
    m = np.array([[it[h]["mean"], it[h]["low"], it[h]["high"]] for h in half_gaps])
    ax2.errorbar(widths, m[:, 0], yerr=[m[:, 0] - m[:, 1], m[:, 2] - m[:, 0]], fmt="s-", capsize=4,
                 color=COLORS["blue"], label="mean, 95 % interval")
    for w, h in zip(widths, half_gaps):
        ax2.annotate(f"{100 * share[h]:.2f} % of samples\nin the gap", (w, 0), textcoords="offset points",
                     xytext=(0, 6), ha="center", va="bottom", fontsize="small")
    ax2.set_xlabel("gap between the discs (m)")
    ax2.set_ylabel("RRT-Connect iterations to a path")
    ax2.set_xticks(widths)
    ax2.set_ylim(0, 1.35 * m[:, 2].max())
    ax2.set_title("narrower gap, fewer samples in it, more iterations", fontsize="medium")
    ax2.legend(loc="upper right", fontsize="small")
    ax2.grid(True, color=_GRID, linewidth=0.6)
    style_axes(ax2)
    return fig


def _rates(stats, family, groups):
    x, rate, err = [], [], [[], []]
    for i, g in enumerate(groups):
        if (family, g) not in stats:
            continue
        st = stats[family, g]
        p = st["successes"] / st["runs"]
        x.append(i)
        rate.append(p)
        err[0].append(p - st["interval"][0])
        err[1].append(st["interval"][1] - p)
    return np.array(x, float), rate, err


def plot_success_rates(groups):
    """Each family's success rate with its Wilson 95 % interval, overall and per scenario class.

    ``groups`` is a :class:`rapp.compare.RunGroups`.

    Examples
    --------
    >>> from rapp.compare import group_runs, recorded_results
    >>> fig = plot_success_rates(group_runs(recorded_results()))
    >>> fig.axes[0].get_xticklabels()[0].get_text()
    'all\\n(30)'
    >>> plt.close(fig)
    """
    columns = ["all"] + groups.classes
    fig, ax = plt.subplots(figsize=(10, 4.6), layout="constrained")
    offsets = np.linspace(-0.36, 0.36, len(groups.families))
    for f, dx in zip(groups.families, offsets):
        colour, marker = FAMILY_STYLE[f]
        x, rate, err = _rates(groups.stats, f, columns)
        ax.errorbar(list(x + dx), rate, yerr=err, fmt=marker, color=colour, capsize=2, ms=5, lw=1, label=f)
    for i in range(1, len(columns)):
        ax.axvline(i - 0.5, color="#dddddd", lw=0.8, zorder=0)
    ax.set_xticks(range(len(columns)), [f"all\n({sum(groups.size.values())})"] +
                  [f"{c.replace(', ', chr(10))}\n({groups.size[c]})" for c in groups.classes])
    ax.set_xlim(-0.5, len(columns) - 0.5)
    ax.set_ylim(-0.03, 1.03)
    ax.set_ylabel("success rate (verified plans)")
    ax.set_xlabel("scenario class (number of scenarios)")
    ax.set_title("success rate with Wilson 95 % intervals", fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside right center", fontsize="small")
    style_axes(ax)
    return fig


def _interval(t):
    # An interval that may be NaN (a single success) shrinks to its mean; a log axis needs > 0.
    low = max(t["low"], 1e-4) if np.isfinite(t["low"]) else t["mean"]
    high = t["high"] if np.isfinite(t["high"]) else t["mean"]
    return [[t["mean"] - low], [high - t["mean"]]]


def plot_time_and_length(groups):
    """Each family's mean time to a path and mean path length (returned, shortcut), 95 % intervals.

    Examples
    --------
    >>> from rapp.compare import group_runs, recorded_results
    >>> groups = group_runs(recorded_results())
    >>> fig = plot_time_and_length(groups)
    >>> labels = {t.get_text() for t in fig.axes[0].get_yticklabels()}
    >>> fig.axes[0].get_xscale(), labels == set(groups.families)
    ('log', True)
    >>> plt.close(fig)
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained", sharey=True)
    ypos = np.arange(len(groups.families))[::-1]
    for y, f in zip(ypos, groups.families):
        colour, marker = FAMILY_STYLE[f]
        t = groups.stats[f, "all"]["time_s"]
        ax1.errorbar(t["mean"], y, xerr=_interval(t), fmt=marker, color=colour, capsize=3, ms=6)
        for q, filled, dy in (("length_rad", False, 0.15), ("shortcut_length_rad", True, -0.15)):
            L = groups.stats[f, "all"][q]
            ax2.errorbar(L["mean"], y + dy, xerr=[[L["mean"] - L["low"]], [L["high"] - L["mean"]]],
                         fmt=marker, color=colour, mfc=colour if filled else "white", capsize=3, ms=6)
    ax1.set_xscale("log")
    ax1.xaxis.set_major_formatter(plt.FuncFormatter(lambda v, _: f"{v:g}"))
    ax1.xaxis.set_minor_formatter(plt.NullFormatter())
    ax1.set_yticks(ypos, groups.families)
    ax1.set_xlabel("time to a path (s), log scale")
    ax1.set_title("mean time to a path, 95 % interval", fontsize="medium")
    ax2.set_xlabel("joint-space path length (rad)")
    ax2.set_title("path length: returned (open), shortcut (filled)", fontsize="medium")
    for ax in (ax1, ax2):
        ax.grid(True, axis="x", color=_GRID, linewidth=0.6)
        style_axes(ax)
    return fig
