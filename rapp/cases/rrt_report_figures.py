"""Case study, seed 003: the figures and the explorer of chapter 12 (the 3-link RRT report).

Each function draws one of chapter 12's figures from values the chapter computes
(:mod:`rapp.cases.rrt_report` and :func:`rapp.rrt` compute; this module only draws). A function
that makes its own figure returns it; one given an ``ax`` draws into it and returns it.
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from rapp.plotting import COLORS, TEXT, plot_arm, plot_obstacles, plot_value_grid, plot_workspace, style_axes
from rapp.rrt import rrt
from rapp.view_stack import Control, view_stack
from rapp.cases.rrt_report import mean_interval, wilson_interval

__all__ = [
    "plot_straight_vs_rrt",
    "plot_axis_projections",
    "plot_tree_projection",
    "plot_goal_run",
    "plot_alpha_beta",
    "plot_cost_heatmaps",
    "plot_cost_and_time",
    "plot_plans",
    "tree_explorer",
]


def _legend(ax, loc="lower left"):
    ax.legend(loc=loc, fontsize="small")
    style_axes(ax)


def plot_straight_vs_rrt(arm, obstacles, start, goal, straight, path):
    """The arm along a straight joint-space motion (left) and along an RRT path (right).

    Examples
    --------
    >>> from rapp.cases.rrt_report import seed_arm, seed_square
    >>> arm, q = seed_arm(), np.array([[1.6, 0.0, 0.0], [1.5, 0.1, 0.0]])
    >>> fig = plot_straight_vs_rrt(arm, [seed_square()], q[0], q[1], q, q)
    >>> [t.get_text() for t in fig.axes[1].get_legend().get_texts()][-3:]
    ['RRT path (2 nodes)', 'start', 'goal']
    >>> plt.close("all")
    """
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.9), layout="constrained")
    panels = ((straight, COLORS["vermillion"], "straight joint-space motion"),
              (path, COLORS["blue"], f"RRT path ({len(path)} nodes)"))
    for ax, (motion, colour, name) in zip(axes, panels):
        plot_workspace(arm, ax)
        plot_obstacles(obstacles, ax, label="square (0.2 m)")
        plot_arm(arm, motion, ax, color=colour, frame=False, label=name)
        plot_arm(arm, start, ax, color=COLORS["green"], label="start", frame=False)
        plot_arm(arm, goal, ax, color=COLORS["purple"], label="goal", frame=True)
        _legend(ax)
    axes[0].set_title("moving every joint at once hits the square", fontsize="medium")
    axes[1].set_title("RRT goes round it: every edge certified free", fontsize="medium")
    return fig


def _interval(points, axis):
    p = np.asarray(points, dtype=float) @ axis
    return float(p.min()), float(p.max())


def plot_axis_projections(polygon, a, b):
    """A link ``ab`` and a polygon, with their projections on y (left) and x (below).

    Examples
    --------
    >>> from rapp import Polygon
    >>> ax = plot_axis_projections(Polygon.rectangle((0, 0), 1, 1), np.array([1.5, -1.0]), np.array([2.5, 0.5]))
    >>> [float(v) for v in ax.lines[1].get_ydata()]    # the square projected on y
    [0.0, 1.0]
    >>> plt.close("all")
    """
    sq_y, seg_y = _interval(polygon.array, [0, 1]), _interval([a, b], [0, 1])
    sq_x, seg_x = _interval(polygon.array, [1, 0]), _interval([a, b], [1, 0])
    fig, ax = plt.subplots(figsize=(6.4, 4.6), layout="constrained")
    plot_obstacles([polygon], ax, label="square")
    ax.plot(*np.stack((a, b)).T, "-o", color=COLORS["blue"], lw=3, label="link")
    ax.plot([-0.6, -0.6], sq_y, color=COLORS["grey"], lw=6, alpha=0.7, label="square projected")
    ax.plot([-0.4, -0.4], seg_y, color=COLORS["sky"], lw=6, label="link projected")
    ax.plot(sq_x, [-1.5, -1.5], color=COLORS["grey"], lw=6, alpha=0.7)
    ax.plot(seg_x, [-1.5, -1.5], color=COLORS["sky"], lw=6)
    ax.annotate("gap on x", ((sq_x[1] + seg_x[0]) / 2, -1.5), (1.0, -1.15), ha="center",
                arrowprops=dict(arrowstyle="->"))
    ax.annotate("overlap on y", (-0.5, 0.25), (-0.25, 1.25), arrowprops=dict(arrowstyle="->"))
    ax.set_xlim(-0.9, 4.3)
    ax.set_ylim(-1.8, 1.6)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("overlap on one axis, yet no collision", fontsize="medium")
    _legend(ax, "upper right")
    return ax


def plot_tree_projection(result, arm, start, goal, ax, title=""):
    """An RRT's tree (and path, if any) projected on ``(theta_1, theta_2)``, in the arm's limits.

    Examples
    --------
    >>> from rapp import Arm
    >>> from rapp.rrt import rrt
    >>> arm = Arm([1.0, 1.0], joint_limits=[(-3, 3), (-3, 3)])
    >>> res = rrt(arm, [0.0, 0.0], [1.0, 1.0], [], step=0.5, seed=0)
    >>> ax = plot_tree_projection(res, arm, [0.0, 0.0], [1.0, 1.0], plt.figure().add_subplot())
    >>> len(ax.collections[0].get_segments()) == len(res.nodes) - 1
    True
    >>> plt.close("all")
    """
    e = np.stack((result.nodes[result.parent[1:]], result.nodes[1:]), 1)[:, :, :2]
    ax.add_collection(LineCollection(e, colors=COLORS["sky"], linewidths=0.8, label="tree"))
    ax.plot(*result.nodes[:, :2].T, ".", color=COLORS["sky"], ms=2)
    if result.success:
        ax.plot(*result.path[:, :2].T, "-", color=COLORS["orange"], lw=2.5, label="path")
    ax.plot(*np.asarray(start)[:2], "o", color=COLORS["green"], ms=8, label="start")
    ax.plot(*np.asarray(goal)[:2], "*", color=COLORS["vermillion"], ms=12, label="goal (one IK)")
    ax.set_xlim(arm.lower[0], arm.upper[0])
    ax.set_ylim(arm.lower[1], arm.upper[1])
    ax.set_xlabel(r"$\theta_1$ (rad)")
    ax.set_ylabel(r"$\theta_2$ (rad)")
    ax.set_title(title, fontsize="medium")
    ax.legend(loc="lower left", fontsize="small")
    return style_axes(ax)


def plot_goal_run(arm, result, obstacles, start, goal, goal_xy, *, radius=0.05):
    """A goal-circle RRT run: its tree in joint space (left), the arm along its path (right).

    Examples
    --------
    >>> from rapp.cases.rrt_report import seed_arm
    >>> arm = seed_arm()
    >>> res = rrt(arm, arm.wrap([1.5, 0, 0]), [1.6, 0.1, 0.0], [], step=0.2, seed=0)
    >>> fig = plot_goal_run(arm, res, [], res.path[0], res.path[-1], arm.end_effector(res.path[-1]))
    >>> fig.axes[1].patches[-1].get_radius()
    0.05
    >>> plt.close("all")
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5), layout="constrained")
    plot_tree_projection(result, arm, start, goal, ax1,
                         rf"tree of {len(result.nodes)} nodes, projected on $(\theta_1, \theta_2)$")
    plot_workspace(arm, ax2)
    plot_obstacles(obstacles, ax2, label="square")
    plot_arm(arm, result.path, ax2, frame=False, label="arm along the path")
    plot_arm(arm, result.path[-1], ax2, color=COLORS["green"], frame=True, label="final")
    ax2.add_patch(plt.Circle(goal_xy, radius, fill=False, color=COLORS["vermillion"], lw=1.5,
                             label=f"goal circle ({radius * 100:g} cm)"))
    ax2.plot(*arm.end_effector(result.path).T, "-", color=COLORS["orange"], lw=1.5, label="tip")
    ax2.set_title("the arm along the path", fontsize="medium")
    _legend(ax2)
    return fig


def plot_alpha_beta(blocked, free, trials):
    """Seed 003's experiment: success rates with Wilson intervals (with the square, left) and
    mean iterations with 1.96 standard errors (no obstacle, right), one line per beta.

    ``blocked`` and ``free`` are :func:`rapp.cases.rrt_report.alpha_beta_experiment`'s results.

    Examples
    --------
    >>> from rapp import Arm
    >>> from rapp.cases.rrt_report import alpha_beta_experiment
    >>> out = alpha_beta_experiment(Arm([1.0, 1.0]), [0.0, 0.0], [0.0, 2.0], [], [0.5, 1.0], [1.0], 3)
    >>> fig = plot_alpha_beta(out, out, 3)
    >>> fig.axes[0].get_ylabel(), fig.axes[1].get_yscale()
    ('success rate (3 trials)', 'log')
    >>> plt.close("all")
    """
    alphas, betas = blocked["alpha"], blocked["beta"]
    lo, hi = wilson_interval(blocked["successes"], trials)
    it_mean, it_half = mean_interval(free["trial_iterations"])
    colours = [COLORS[c] for c in ("blue", "orange", "green", "purple")]
    shift = 0.016 * (np.arange(len(betas)) - (len(betas) - 1) / 2)  # side by side: bars apart
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
    for j, b in enumerate(betas):
        rate = blocked["success_rate"][:, j]
        ax1.errorbar(alphas + shift[j], rate, yerr=[rate - lo[:, j], hi[:, j] - rate],
                     fmt="o-", color=colours[j % 4], capsize=4, label=f"β = {b:g}")
        ax2.errorbar(alphas + shift[j], it_mean[:, j], yerr=it_half[:, j], fmt="o-",
                     color=colours[j % 4], capsize=4, label=f"β = {b:g}")
    ax1.set_ylim(-0.03, 1.03)
    ax1.set_ylabel(f"success rate ({trials} trials)")
    ax1.set_title("with the square: success rate, Wilson 95 % intervals", fontsize="medium")
    ax1.legend(loc="upper left", fontsize="small")
    ax2.set_yscale("log")
    ax2.set_ylabel("iterations to the goal (mean)")
    ax2.set_title("no obstacle: iterations, mean ± 1.96 standard errors", fontsize="medium")
    ax2.legend(loc="upper right", fontsize="small")
    for ax in (ax1, ax2):
        ax.set_xlabel("α (fraction of the distance)")
        ax.set_xticks(alphas)
        ax.grid(True, color="#e6e6e6", linewidth=0.6)
        style_axes(ax)
    return fig


def plot_cost_heatmaps(runs, *, clim=(2.0, 7.5)):
    """Mean path cost over alpha and beta, one panel per named experiment, with half-widths.

    Examples
    --------
    >>> from rapp import Arm
    >>> from rapp.cases.rrt_report import alpha_beta_experiment
    >>> out = alpha_beta_experiment(Arm([1.0, 1.0]), [0.0, 0.0], [0.0, 2.0], [], [0.5], [1.0], 2)
    >>> [ax.get_title() for ax in plot_cost_heatmaps({"a": out}).axes[:1]]
    ['mean path cost, a']
    >>> plt.close("all")
    """
    fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 4.2), layout="constrained",
                             squeeze=False)
    for ax, (name, out) in zip(axes[0], runs.items()):
        mean, half = mean_interval(out["trial_cost"])
        im = plot_value_grid(mean, half, [f"{a:g}" for a in out["alpha"]], [f"{b:g}" for b in out["beta"]],
                             ax, cmap="Oranges", clim=clim)
        ax.set(xlabel="α (fraction of the distance)", ylabel="β (goal bias)")
        ax.set_title(f"mean path cost, {name}", fontsize="medium")
    fig.colorbar(im, ax=axes[0].tolist(), label="mean joint-space path cost (rad)")
    return fig


def plot_cost_and_time(comparison):
    """RRT against A*: path cost (with the blocked straight line) and wall time, as bars.

    ``comparison`` is :func:`rapp.cases.rrt_report.compare_with_astar`'s result.

    Examples
    --------
    >>> fig = plot_cost_and_time({"rrt_cost": 3.0, "astar_cost": 2.5, "straight_distance": 2.0,
    ...                           "rrt_seconds": 0.1, "astar_seconds": 0.4})
    >>> [float(p.get_height()) for p in fig.axes[0].patches]
    [3.0, 2.5]
    >>> plt.close("all")
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    names = ["RRT", "A* (32 cells/joint)"]
    colors = [COLORS["orange"], COLORS["blue"]]
    ax1.bar(names, [comparison["rrt_cost"], comparison["astar_cost"]], color=colors)
    ax1.axhline(comparison["straight_distance"], color=TEXT, ls="--", lw=1, label="straight line (blocked)")
    ax1.set_ylabel("joint-space path cost (rad)")
    ax1.set_title("raw path cost", fontsize="medium")
    ax1.legend(loc="lower right", fontsize="small")
    ax2.bar(names, [comparison["rrt_seconds"], comparison["astar_seconds"]], color=colors)
    ax2.set_ylabel("wall time on this machine (s)")
    ax2.set_title("one run; A* includes building the grid", fontsize="medium")
    for ax in (ax1, ax2):
        ax.set_xlabel("planner")
        style_axes(ax)
    return fig


def plot_plans(arm, plans, obstacles):
    """Each named plan (:func:`rapp.plan`'s result): the arm along it and the tip, side by side.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from rapp import Arm
    >>> p = SimpleNamespace(q=np.zeros((3, 2)), xy=np.ones((3, 2)), metrics={"shortcut_length_rad": 1.0})
    >>> [ax.get_title() for ax in plot_plans(Arm([1.0, 1.0]), {"rrt": p}, []).axes]
    ['rrt: 1.00 rad after shortcutting']
    >>> plt.close("all")
    """
    fig, axes = plt.subplots(1, len(plans), figsize=(5 * len(plans), 4.9), layout="constrained",
                             squeeze=False)
    for ax, (name, p) in zip(axes[0], plans.items()):
        plot_workspace(arm, ax)
        plot_obstacles(obstacles, ax, label="square")
        plot_arm(arm, p.q[::20], ax, frame=False, label="arm along the path")
        plot_arm(arm, p.q[-1], ax, color=COLORS["purple"], label="goal")
        ax.plot(*p.xy.T, "-", color=COLORS["orange"], lw=1.5, label="tip")
        ax.set_title(f"{name}: {p.metrics['shortcut_length_rad']:.2f} rad after shortcutting",
                     fontsize="medium")
        _legend(ax)
    return fig


def tree_explorer(arm, start, goal, goal_xy, obstacles, controls, grown=None, *, max_iterations=2000):
    """An explorer of goal-circle RRT runs over alpha (``step``), beta (``goal_bias``) and seed.

    Parameters
    ----------
    controls : mapping with keys ``"alpha"``, ``"beta"``, ``"seed"``
        :class:`rapp.view_stack.Control` of each.
    grown : dict, optional
        Filled with ``(alpha, beta, seed) -> result`` of every view, for the caller's checks.

    Returns
    -------
    ipywidgets.VBox
        :func:`rapp.view_stack.view_stack`'s explorer, titled "Grow your own tree".

    Examples
    --------
    >>> from rapp import Arm
    >>> arm, grown = Arm([1.0, 1.0], joint_limits=[(-3, 3), (-3, 3)]), {}
    >>> c = {"alpha": Control("α", [0.5]), "beta": Control("β", [0.5]), "seed": Control("seed", [0])}
    >>> w = tree_explorer(arm, [0.0, 0.0], [1.0, 1.0], arm.end_effector([1.0, 1.0]), [], c, grown)
    >>> list(grown), grown[0.5, 0.5, 0].success
    ([(0.5, 0.5, 0)], True)
    """
    grown = {} if grown is None else grown
    fig = Figure(figsize=(6.4, 5.2), layout="constrained")
    ax = fig.add_subplot()
    ax.set_xlim(arm.lower[0], arm.upper[0])
    ax.set_ylim(arm.lower[1], arm.upper[1])

    def grow(alpha, beta, seed):
        grown[alpha, beta, seed] = r = rrt(arm, start, None, obstacles, goal_xy=goal_xy, step=alpha,
                                           goal_bias=beta, goal_threshold=0.05, seed=seed,
                                           max_iterations=max_iterations, raise_on_failure=False)
        outcome = (f"{r.iterations} iterations, cost {r.cost:.2f} rad" if r.success
                   else f"no path in {max_iterations} iterations")
        plot_tree_projection(r, arm, start, goal, ax, f"{len(r.nodes)} nodes: {outcome}")
        return f"α = {alpha:g} rad, β = {beta:g}, seed {seed}: {len(r.nodes)} nodes, {outcome}"

    return view_stack(fig, dict(controls), grow, title="Grow your own tree")
