"""Figures of one arm: a first look, its plan, its joint angles, its elbow sweeping, its sampled workspace.

Chapters 1 and 2's figures. Each function takes an arm and configurations and returns the
:class:`matplotlib.figure.Figure` it drew (an animation for the sweep); nothing calls
``plt.show()``.

Examples
--------
>>> from rapp import Arm
>>> fig = plot_joint_angles(Arm([1.0, 0.8, 0.5]), [0.4, 1.0, -0.6])
>>> [t.get_text() for t in fig.axes[0].texts][:2]
['$\\\\theta_1$', '$L_1$']
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.animation import FuncAnimation

from rapp.plotting import plot_arm, plot_plan, plot_workspace, style_axes

__all__ = ["plot_first_arm", "animate_elbow_sweep", "plot_joint_angles", "plot_sampled_workspaces", "plot_plan_wide"]

_BLUE, _ORANGE, _GREEN = "#0072B2", "#E69F00", "#009E73"


def _metre_axes(ax, lo, hi, title):
    ax.set_aspect("equal")
    ax.set_xlim(*lo)
    ax.set_ylim(*hi)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)


def plot_first_arm(arm, q, obstacle, title):
    """The arm at ``q`` beside a disc ``obstacle``: links, joints, end effector and base, plainly.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> fig = plot_first_arm(Arm([1.0, 0.8]), [0.0, 0.0], Circle([1.2, 1.2], 0.3), "flat")
    >>> fig.axes[0].lines[0].get_xydata().tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.8, 0.0]]
    >>> plt.close(fig)
    """
    points = arm.joint_positions(np.asarray(q, float))
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    fig.patch.set_facecolor("white")
    ax.add_patch(plt.Circle(obstacle.center, obstacle.radius, color="tab:red", alpha=0.4, label="obstacle"))
    ax.plot(points[:, 0], points[:, 1], "-o", color="tab:blue", lw=3, label="links and joints")
    ax.plot(*points[-1], "s", color="black", label="end effector")
    ax.plot(0, 0, "k^", ms=10, label="base")
    _metre_axes(ax, (-0.5, 2.0), (-0.5, 2.0), title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right")
    return fig


def animate_elbow_sweep(arm, shoulder=0.8, frames=24):
    """The elbow turning a full circle in ``frames`` steps, the shoulder held at ``shoulder`` (rad).

    Returns the :class:`~matplotlib.animation.FuncAnimation`; its end effector leaves a dotted trace.

    Examples
    --------
    >>> from rapp import Arm
    >>> anim = animate_elbow_sweep(Arm([1.0, 0.8]), frames=4)
    >>> line, trace = anim._func(3)
    >>> len(trace.get_xdata())
    4
    >>> plt.close(anim._fig)
    """
    angles = np.linspace(0.0, 2 * np.pi, frames, endpoint=False)
    sweep_points = arm.joint_positions(np.stack([np.full_like(angles, shoulder), angles], axis=-1))
    fig, ax = plt.subplots(figsize=(6.0, 6.0), dpi=80)
    fig.patch.set_facecolor("white")
    (line,) = ax.plot([], [], "-o", color="tab:blue", lw=3)
    (trace,) = ax.plot([], [], ":", color="gray")
    _metre_axes(ax, (-2, 2), (-2, 2), f"elbow turning a full circle, shoulder at {shoulder:g} rad")

    def show(k):
        line.set_data(sweep_points[k, :, 0], sweep_points[k, :, 1])
        trace.set_data(sweep_points[: k + 1, -1, 0], sweep_points[: k + 1, -1, 1])
        return line, trace

    return FuncAnimation(fig, show, frames=frames, interval=100, blit=True)


def _angle_labels(ax, p, phi, i, last):
    before = 0.0 if i == 0 else phi[i - 1]
    ax.plot(*np.array([p[i], p[i] + 0.5 * np.array([np.cos(before), np.sin(before)])]).T, ":", color="#555555")
    arc = np.linspace(before, phi[i], 40)
    ax.plot(p[i, 0] + 0.32 * np.cos(arc), p[i, 1] + 0.32 * np.sin(arc), color=_ORANGE, lw=2)
    mid = (before + phi[i]) / 2
    ax.text(p[i, 0] + 0.42 * np.cos(mid), p[i, 1] + 0.42 * np.sin(mid), rf"$\theta_{i + 1}$",
            color="#B06F00", fontsize=15, ha="center", va="center")
    side = -1.0 if last else 1.0
    ax.text(*(0.5 * (p[i] + p[i + 1]) + side * 0.12 * np.array([-np.sin(phi[i]), np.cos(phi[i])])),
            rf"$L_{i + 1}$", color=_BLUE, fontsize=14, ha="center", va="center")
    ax.text(*(p[i] + np.array([-0.13, -0.09]) if i else p[i] + np.array([-0.12, -0.12])),
            rf"$\mathbf{{p}}_{i}$", fontsize=13)


def plot_joint_angles(arm, q):
    """The arm at ``q`` with its relative joint angles (orange) and its last link's absolute angle (green).

    Drawn for a 3-link arm in the first quadrant (the limits are fixed, 2.3 m wide).
    """
    p, phi = arm.joint_positions(np.asarray(q, float)), arm.absolute_angles(np.asarray(q, float))
    fig, ax = plt.subplots(figsize=(6.5, 6.2))
    fig.patch.set_facecolor("white")
    ax.plot(p[:, 0], p[:, 1], "-o", color=_BLUE, lw=3, ms=7, mfc="white", mew=1.5, zorder=3)
    ax.plot(0, 0, "s", color="#222222", ms=10, zorder=4)
    for i in range(arm.n):
        _angle_labels(ax, p, phi, i, i == arm.n - 1)
    ax.text(*(p[-1] + np.array([0.06, 0.05])), rf"$\mathbf{{p}}_{arm.n}$", fontsize=13)
    k = arm.n - 1                  # the absolute angle of the last link, measured from +x at its joint
    ax.plot(*np.array([p[k], p[k] + [0.75, 0.0]]).T, "--", color=_GREEN)
    arc = np.linspace(0.0, phi[k], 40)
    ax.plot(p[k, 0] + 0.6 * np.cos(arc), p[k, 1] + 0.6 * np.sin(arc), color=_GREEN, lw=2)
    ax.text(p[k, 0] + 0.72 * np.cos(phi[k] / 2), p[k, 1] + 0.72 * np.sin(phi[k] / 2), rf"$\varphi_{arm.n}$",
            color="#007A5A", fontsize=15, ha="center", va="center")
    _metre_axes(ax, (-0.3, 2.0), (-0.3, 2.1), "")
    ax.grid(True, alpha=0.3)
    ax.set_title(rf"relative joint angles $\theta_i$ (orange) and an absolute angle $\varphi_{arm.n}$ (green)",
                 fontsize="medium")
    return fig


def plot_sampled_workspaces(samples, shown=3000):
    """Per arm, its workspace with sampled end effectors and a configuration attaining ``r_min``.

    ``samples[name]`` is ``(arm, end_effectors, q_inner)``; one panel per entry.

    Examples
    --------
    >>> from rapp import Arm
    >>> arm = Arm([1.0, 0.8])
    >>> fig = plot_sampled_workspaces({"(1, 0.8)": (arm, arm.end_effector(np.zeros((5, 2))), [0, np.pi])})
    >>> fig.axes[0].get_title()
    'links (1, 0.8) m: reach 0.2 to 1.8 m'
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, len(samples), figsize=(11, 5.5), layout="constrained")
    for ax, (name, (arm, ee, q_in)) in zip(np.atleast_1d(axs), samples.items()):
        plot_workspace(arm, ax)
        ax.scatter(ee[:shown, 0], ee[:shown, 1], s=2, color=_ORANGE, alpha=0.5, label="sampled end effectors")
        plot_arm(arm, q_in, ax, label=r"attains $r_{\min}$")
        ax.set_title(f"links {name} m: reach {arm.reach[0]:.1f} to {arm.reach[1]:.1f} m")
        ax.legend(loc="lower left", fontsize="small")
        style_axes(ax)
    return fig


def plot_plan_wide(plan, scenario):
    """:func:`rapp.plotting.plot_plan` across the page (12.5 x 5 in), the workspace's legend outside it.

    Examples
    --------
    >>> import rapp
    >>> scenario = rapp.load_scenario("default")
    >>> fig = plot_plan_wide(rapp.plan(scenario), scenario)
    >>> [round(float(v), 1) for v in fig.get_size_inches()], fig.axes[1].get_legend().get_bbox_to_anchor() is not None
    ([12.5, 5.0], True)
    >>> plt.close(fig)
    """
    fig = plot_plan(plan, scenario)
    fig.set_size_inches(12.5, 5.0)
    workspace_ax = fig.axes[1]
    workspace_ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    style_axes(workspace_ax)
    return fig
