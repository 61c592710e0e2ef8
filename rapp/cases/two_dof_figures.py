"""Case study, seed 004: the figures and the animation of chapter 13 (the 2-link workspace).

Each function draws one of chapter 13's figures from values the chapter computes
(:mod:`rapp.cases.two_dof_workspace` and :func:`rapp.ik_2link` compute; this module only
draws). A function that makes its own figure returns it; one given an ``ax`` draws into it.
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt

from rapp.ik import ik_2link
from rapp.plotting import COLORS, animate, plot_arm, plot_workspace, style_axes

__all__ = [
    "plot_targets",
    "plot_all_solutions",
    "plot_target_map",
    "plot_fan",
    "plot_elbow_pairs",
    "plot_joint_interpolation",
    "targets_animation",
]

LIMITS = (-3.8, 3.8)


def plot_targets(ax, targets, flags, *, numbers=True):
    """Reachable targets as green dots, unreachable ones as red crosses, numbered from 0.

    Examples
    --------
    >>> ax = plot_targets(plt.figure().add_subplot(), np.array([[0, 1], [5, 0]]), np.array([True, False]))
    >>> [t.get_text() for t in ax.texts], [c.get_label() for c in ax.collections]
    (['0', '1'], ['reachable', 'unreachable'])
    >>> plt.close("all")
    """
    targets, flags = np.asarray(targets, dtype=float), np.asarray(flags, dtype=bool)
    ax.scatter(*targets[flags].T, s=40, color=COLORS["green"], zorder=6, label="reachable")
    ax.scatter(*targets[~flags].T, s=70, marker="x", color=COLORS["vermillion"], linewidths=2,
               zorder=6, label="unreachable")
    if numbers:
        for i, p in enumerate(targets):
            ax.annotate(str(i), p, xytext=(5, 4), textcoords="offset points", fontsize="small")
    return ax


def plot_all_solutions(arm, targets, flags, solutions):
    """Both elbows' solutions (``(k, 2, 2)``, :func:`rapp.ik_2link`) of the reachable targets.

    Examples
    --------
    >>> from rapp import Arm
    >>> arm, t = Arm([2.0, 1.25]), np.array([[2.0, 1.0], [5.0, 0.0]])
    >>> ax = plot_all_solutions(arm, t, np.array([True, False]), ik_2link(arm, t))
    >>> [c.get_offsets().shape[0] for c in ax.collections[-2:]]
    [1, 1]
    >>> plt.close("all")
    """
    flags = np.asarray(flags, dtype=bool)
    fig, ax = plt.subplots(figsize=(6.6, 6.2), layout="constrained")
    plot_workspace(arm, ax)
    plot_arm(arm, solutions[flags, 0], ax, color=COLORS["blue"], ghost_alpha=(0.8, 0.8), frame=False,
             label=r"elbow-down, $\theta_2 \geq 0$")
    plot_arm(arm, solutions[flags, 1], ax, color=COLORS["orange"], ghost_alpha=(0.8, 0.8), frame=False,
             label=r"elbow-up, $\theta_2 \leq 0$")
    ax.scatter(*targets[flags].T, s=45, color=COLORS["green"], zorder=6, label="reachable target")
    ax.scatter(*targets[~flags].T, s=70, marker="x", color=COLORS["vermillion"], linewidths=2,
               zorder=6, label="unreachable target")
    ax.set_xlim(-4.2, 3.9)
    ax.set_ylim(-4.2, 3.9)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"every solution of {_count(len(targets))} targets, arm L = ({arm.lengths[0]:g}, "
                 f"{arm.lengths[1]:g}) m", fontsize="medium")
    ax.legend(loc="lower left", fontsize="small")
    style_axes(ax)
    return ax


def plot_target_map(arm, targets, flags):
    """The numbered targets in the arm's workspace annulus.

    Examples
    --------
    >>> from rapp import Arm
    >>> ax = plot_target_map(Arm([2.0, 1.25]), np.array([[2.0, 1.0]]), np.array([True]))
    >>> ax.get_title()
    'targets 0-0 in the workspace of L = (2, 1.25) m'
    >>> plt.close("all")
    """
    fig, ax = plt.subplots(figsize=(6.2, 6.2), layout="constrained")
    plot_workspace(arm, ax)
    plot_targets(ax, targets, flags)
    ax.set_xlim(*LIMITS)
    ax.set_ylim(*LIMITS)
    ax.set_title(f"targets 0-{len(targets) - 1} in the workspace of L = ({arm.lengths[0]:g}, "
                 f"{arm.lengths[1]:g}) m", fontsize="medium")
    ax.legend(loc="lower left", fontsize="small")
    style_axes(ax)
    return ax


def plot_fan(arm, fan):
    """Folded postures ``fan`` (``(k, 2)``) of an arm with ``L1 = L2``, their elbows marked.

    Examples
    --------
    >>> from rapp import Arm
    >>> fan = np.stack((np.linspace(-3, 3, 4), np.full(4, np.pi)), axis=-1)
    >>> plot_fan(Arm([1.0, 1.0]), fan).collections[-1].get_offsets().shape
    (4, 2)
    >>> plt.close("all")
    """
    fig, ax = plt.subplots(figsize=(6.0, 6.0), layout="constrained")
    plot_workspace(arm, ax)
    plot_arm(arm, fan, ax, ghost_alpha=(0.5, 0.9), label=rf"$\theta_2 = \pi$, {_count(len(fan))} $\theta_1$")
    elbows = arm.joint_positions(fan)[:, 1]
    ax.scatter(*elbows.T, s=25, color=COLORS["blue"], zorder=4, label="elbows")
    ax.set_title("L1 = L2: infinitely many solutions at the base", fontsize="medium")
    ax.legend(loc="lower left", fontsize="small")
    style_axes(ax)
    return ax


def _count(n):
    words = "zero one two three four five six seven eight nine ten".split()
    return words[n] if n < len(words) else str(n)


def plot_elbow_pairs(arm, points):
    """Both elbow solutions of each target of ``points``, one panel per target, with the
    line from the base through the target (rapp's names against seed 004's).

    Examples
    --------
    >>> from rapp import Arm
    >>> fig = plot_elbow_pairs(Arm([2.0, 1.25]), [np.array([2.5, 0.0])])
    >>> fig.axes[0].get_title()
    'target (2.5, 0) m'
    >>> plt.close("all")
    """
    fig, axs = plt.subplots(1, len(points), figsize=(5.25 * len(points), 5.4), layout="constrained",
                            squeeze=False)
    for ax, p in zip(axs[0], points):
        down, up = ik_2link(arm, p)
        plot_workspace(arm, ax)
        ax.plot([0, 1.3 * p[0]], [0, 1.3 * p[1]], ":", color=COLORS["grey"], label="base to target")
        plot_arm(arm, down, ax, color=COLORS["blue"], label=r"$\theta_2>0$: rapp elbow-down, seed 004 'up'")
        plot_arm(arm, up, ax, color=COLORS["orange"], label=r"$\theta_2<0$: rapp elbow-up, seed 004 'down'")
        ax.set_title(f"target ({p[0]:g}, {p[1]:g}) m", fontsize="medium")
        ax.legend(loc="lower left", fontsize="small")
        style_axes(ax)
    return fig


def plot_joint_interpolation(short, long):
    """Joint angles (deg) over a move: theta_1 the short way and the long way, and theta_2.

    Examples
    --------
    >>> a = np.linspace([0.0, 0.0], [1.0, 1.0], 5)
    >>> ax = plot_joint_interpolation(a, a)
    >>> [round(float(line.get_ydata()[-1]), 2) for line in ax.lines[:3]]
    [57.3, 57.3, 57.3]
    >>> plt.close("all")
    """
    u = np.linspace(0.0, 1.0, len(short))
    fig, ax = plt.subplots(figsize=(7.5, 3.8), layout="constrained")
    ax.plot(u, np.degrees(short[:, 0]), color=COLORS["blue"], label=r"$\theta_1$, wrapped $\Delta\theta_1$ (short way)")
    ax.plot(u, np.degrees(long[:, 0]), "--", color=COLORS["vermillion"], label=r"$\theta_1$, plain $\Delta\theta_1$")
    ax.plot(u, np.degrees(short[:, 1]), color=COLORS["orange"], label=r"$\theta_2$")
    ax.axhline(-180, color=COLORS["grey"], lw=0.8)
    ax.set_xlabel("u, fraction of the move (dimensionless)")
    ax.set_ylabel("joint angle (deg)")
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.02, 0.5))
    style_axes(ax)
    return ax


def targets_animation(arm, motion, targets, flags, *, interval=150):
    """The arm along ``motion`` (one frame a sample) over the numbered targets.

    Returns
    -------
    matplotlib.animation.FuncAnimation

    Examples
    --------
    >>> from rapp import Arm
    >>> anim = targets_animation(Arm([2.0, 1.25]), np.linspace([0, 0], [1, 1], 4), [[2.0, 1.0]], [True])
    >>> len(list(anim.new_frame_seq()))
    4
    >>> plt.close("all")
    """
    _, ax = plt.subplots(figsize=(6.6, 6.6), dpi=75)  # the book's constrained layout
    plot_targets(ax, targets, flags)
    anim = animate(arm, motion, ax=ax, max_frames=len(motion), interval=interval)
    ax.set_xlim(*LIMITS)
    ax.set_ylim(*LIMITS)
    ax.legend(loc="lower left", fontsize="small")
    return anim
