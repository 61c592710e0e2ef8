"""Figures of inverse kinematics: solutions on the workspace, singular arms, iterations converging.

Chapter 6's figures. Each function takes an arm and configurations (or the iterations'
records) and returns the :class:`matplotlib.figure.Figure` it drew; nothing here solves IK,
nothing calls ``plt.show()``.

Examples
--------
>>> import numpy as np
>>> from rapp import Arm
>>> fig = plot_arm_choices(Arm([1.0, 0.8]), [([0.5, 0.0], "stretched")], "one arm")
>>> fig.axes[0].get_title()
'one arm'
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt

from rapp.palette import COLORS
from rapp.plotting import plot_arm, plot_workspace, style_axes

__all__ = ["ELBOW_COLORS", "plot_target", "plot_arm_choices", "plot_solution_family",
           "plot_singular_arms", "plot_convergence", "plot_tip_errors", "plot_redundancy"]

#: Colours of the elbow-down and the elbow-up solution.
ELBOW_COLORS = (COLORS["blue"], COLORS["orange"])


def plot_target(ax, target, *, color="k", ms=12, label="target"):
    """A target for the tip: a cross at ``target`` (m). Returns the line."""
    return ax.plot(*target, "x", color=color, ms=ms, mew=2, label=label)[0]


def _finish(ax, title):
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title(title)
    style_axes(ax)


def plot_arm_choices(arm, arms, title, ax=None, *, targets=(), target_size=10):
    """The workspace of ``arm`` with configurations ``arms``, ``(q, label)`` pairs, and targets.

    The configurations are drawn blue, orange, green in turn; ``targets`` holds
    ``(point, colour, label)`` triples drawn as crosses of ``target_size`` points. Returns the figure.

    Examples
    --------
    >>> from rapp import Arm
    >>> fig = plot_arm_choices(Arm([1.0, 0.8]), [([0.3, 1.0], "down"), ([1.0, -1.0], "up")], "two",
    ...                        targets=[([1.0, 0.6], "k", "target")])
    >>> [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    ['workspace', 'down', 'up', 'target']
    >>> plt.close(fig)
    """
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
    plot_workspace(arm, ax)
    colors = (*ELBOW_COLORS, COLORS["green"])
    for (q, label), color in zip(arms, colors):
        plot_arm(arm, q, ax, color=color, label=label)
    for point, color, label in targets:
        plot_target(ax, point, color=color, ms=target_size, label=label)
    _finish(ax, title)
    return ax.figure


def plot_solution_family(arm, solutions, target, title, ax=None, *, shown=8):
    """``shown`` of the ``solutions`` reaching ``target`` (ordered by the first joint) as ghosts.

    ``shown=None`` draws them all, in the order given.

    Examples
    --------
    >>> from rapp import Arm
    >>> q = np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6], [0.0, 0.1, 0.2]])
    >>> fig = plot_solution_family(Arm([1.0, 0.8, 0.5]), q, [1.0, 0.9], "three", shown=2)
    >>> len(fig.axes[0].collections[-2].get_segments())          # two ghosts
    2
    >>> plt.close(fig)
    """
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
    solutions = np.asarray(solutions, float)
    if shown is None:
        pick = np.arange(len(solutions))
    else:
        order = np.argsort(solutions[:, 0])
        pick = order[np.linspace(0, len(order) - 1, shown).round().astype(int)]
    plot_workspace(arm, ax)
    plot_arm(arm, solutions[pick], ax, ghost_alpha=(0.35, 0.9))
    plot_target(ax, target)
    _finish(ax, title)
    return ax.figure


def plot_singular_arms(arms):
    """Each arm stretched (theta_2 = 0) and folded (theta_2 = pi) on its workspace, side by side.

    Examples
    --------
    >>> from rapp import Arm
    >>> fig = plot_singular_arms([Arm([1.0, 0.6]), Arm([1.0, 1.0])])
    >>> [ax.get_title() for ax in fig.axes]
    ['links (1, 0.6) m', 'links (1, 1) m']
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, len(arms), figsize=(10, 4.8), layout="constrained")
    for ax, a in zip(axs, arms):
        plot_arm_choices(a, [([0.5, 0.0], r"stretched, $\theta_2 = 0$"), ([2.0, np.pi], r"folded, $\theta_2 = \pi$")],
                         f"links ({a.link_lengths[0]:g}, {a.link_lengths[1]:g}) m", ax)
    return fig


def plot_convergence(runs, k):
    """Tip error (log) and distance travelled in joint space, per iteration, of start ``k``.

    ``runs`` maps a label to ``(errors, travel, colour)``, both ``(iterations, starts)`` arrays
    (:func:`rapp.ik.iterate_ik` returns them).

    Examples
    --------
    >>> e = np.array([[1.0], [0.1], [0.0]])
    >>> fig = plot_convergence({"Newton": (e, np.zeros((3, 1)), "k")}, 0)
    >>> fig.axes[0].get_yscale(), [float(v) for v in fig.axes[0].lines[0].get_ydata()][-1]
    ('log', 1e-17)
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    for name, (e, s, c) in runs.items():
        it = np.arange(e.shape[0])
        axs[0].semilogy(it, np.maximum(e[:, k], 1e-17), "-o", ms=3, color=c, label=name)
        axs[1].plot(it, s[:, k], "-o", ms=3, color=c, label=name)
    axs[0].set(xlabel="iteration", ylabel="tip error (m)", title="error")
    axs[1].set(xlabel="iteration", ylabel=r"$|\mathbf{q}_k - \mathbf{q}_0|$ (rad)", title="distance from the start")
    for a in axs:
        a.legend(fontsize="small")
        a.grid(True, alpha=0.3)
        style_axes(a)
    return fig


def plot_tip_errors(tip_error, tolerance, title):
    """A histogram of log10 tip errors (exact zeros at -18) against the ``tolerance`` (m).

    Examples
    --------
    >>> fig = plot_tip_errors(np.array([0.0, 1e-16, 1e-15]), 1e-9, "three")
    >>> fig.axes[0].get_legend().get_texts()[0].get_text(), float(fig.axes[0].lines[0].get_xdata()[0])
    ('tolerance $10^{-9}$ m', -9.0)
    >>> plt.close(fig)
    """
    fig, ax = plt.subplots(figsize=(7, 3.6), layout="constrained")
    ax.hist(np.log10(np.maximum(tip_error, 1e-18)), bins=40, color=COLORS["blue"])
    ax.axvline(np.log10(tolerance), color=COLORS["vermillion"], ls="--",
               label=f"tolerance $10^{{{np.log10(tolerance):.0f}}}$ m")
    ax.set(xlabel="$\\log_{10}$ tip error (m)  (exact zeros at $-18$)", ylabel="targets", title=title)
    ax.legend(fontsize="small")
    style_axes(ax)
    return fig


def plot_redundancy(arm2, q2, target2, arm3, q3, target3):
    """Two links reach a target two ways (``q2``), three links in a family (every 4th of ``q3``).

    ``q2`` holds the elbow-down and elbow-up solutions for ``target2``; ``q3`` solutions of the
    3-link arm for ``target3``, drawn as ghosts in the order of their first joint.

    Examples
    --------
    >>> from rapp import Arm, ik, ik_2link
    >>> arm2, arm3 = Arm([1.0, 0.8]), Arm([1.0, 0.8, 0.5])
    >>> q3 = ik(arm3, [1.0, 0.9], q0=[0.3, 0.5, 0.5])
    >>> fig = plot_redundancy(arm2, ik_2link(arm2, [1.0, 0.6]), [1.0, 0.6], arm3, q3, [1.0, 0.9])
    >>> [ax.get_title() for ax in fig.axes] == ["2 links: two solutions", f"3 links: {len(q3)} of infinitely many"]
    True
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.8), layout="constrained")
    plot_arm_choices(arm2, [(q2[0], "elbow-down"), (q2[1], "elbow-up")], "2 links: two solutions", axs[0],
                     targets=[(target2, "k", "target")], target_size=12)
    plot_solution_family(arm3, q3[np.argsort(q3[:, 0])][::4], target3,
                         f"3 links: {len(q3)} of infinitely many", axs[1], shown=None)
    return fig
