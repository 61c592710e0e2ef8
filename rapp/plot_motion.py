"""Figures of timed motions: profiles against limits, synchronized joints, the tip along a line.

Chapter 15's figures. Each function takes timed paths (:mod:`rapp.trajectory`,
:mod:`rapp.time_scaling`) or waypoints and returns the :class:`matplotlib.figure.Figure` it drew;
nothing here plans, nothing calls ``plt.show()``.

Examples
--------
>>> import numpy as np
>>> fig, peaks = plot_duration_scaling([[0.0, 0.0], [1.0, 0.5]], np.linspace(0, 4, 41), (2.0, 4.0))
>>> [ax.get_title() for ax in fig.axes]
['angle', 'velocity', 'acceleration']
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.patches import Ellipse

from rapp.cartesian import line_fraction, tip_along_edges
from rapp.collision import segment_point_distance
from rapp.manipulability import condition_number, manipulability, manipulability_ellipse
from rapp.palette import COLORS
from rapp.plotting import plot_arm, plot_cspace, plot_workspace, style_axes
from rapp.time_scaling import peak_rates, time_path

__all__ = ["PROFILE_STYLE", "plot_duration_scaling", "plot_limited_moves", "plot_synchronization",
           "plot_joint_velocities", "plot_line_following", "plot_velocity_ellipse",
           "plot_manipulability_along", "plot_timed_path", "plot_conditioning", "plot_derivatives"]

#: Colour and line style of each time-scaling profile in chapter 15's figures.
PROFILE_STYLE = {"trapezoidal": (COLORS["blue"], "-"), "cubic": (COLORS["orange"], "--"),
                 "quintic": (COLORS["purple"], "-."), "spline": (COLORS["green"], ":")}


def _finish(axs, labels, titles):
    for ax, label, title in zip(axs, labels, titles):
        ax.set(xlabel="t (s)", ylabel=label, title=title)
        ax.grid(True, alpha=0.3)
        style_axes(ax)


def plot_duration_scaling(waypoints, ts, durations=(2.0, 4.0)):
    """Joint 1's angle, velocity and acceleration of quintic timings of ``waypoints`` over ``durations``.

    Returns ``(fig, peaks)``, ``peaks[T]`` the :func:`rapp.time_scaling.peak_rates` of duration T.

    Examples
    --------
    >>> fig, peaks = plot_duration_scaling([[0.0], [1.0]], np.linspace(0, 4, 41), (2.0, 4.0))
    >>> bool(np.allclose(peaks[4.0][0], peaks[2.0][0] / 2)), len(fig.axes[0].lines)
    (True, 2)
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, 3, figsize=(10, 3.6), layout="constrained")
    peaks = {}
    for T, color, ls in zip(durations, (COLORS["orange"], COLORS["blue"]), ("--", "-")):
        timed = time_path(np.asarray(waypoints, float), T, "quintic")
        for ax, y in zip(axs, timed.sample(ts)):
            ax.plot(ts, y[:, 0], ls, color=color, lw=2, label=f"T = {T:g} s")
        peaks[T] = peak_rates(timed)
    _finish(axs, (r"$\theta_1$ (rad)", r"$\dot\theta_1$ (rad/s)", r"$\ddot\theta_1$ (rad/s²)"),
            ("angle", "velocity", "acceleration"))
    axs[0].legend(fontsize="small", loc="lower right")
    return fig, peaks


def plot_limited_moves(moves, ts, v_lim, a_lim):
    """Angle, velocity and acceleration of one-joint moves ``moves[profile]``, limits dotted.

    Examples
    --------
    >>> from rapp.time_scaling import trapezoidal
    >>> fig = plot_limited_moves({"trapezoidal": trapezoidal(0.0, 1.2, 1.0, 2.0)},
    ...                          np.linspace(0, 2.4, 25), 1.0, 2.0)
    >>> fig.legends[0].get_texts()[0].get_text()
    'trapezoidal, T = 1.700 s'
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, 3, figsize=(10, 3.8), layout="constrained")
    for profile, pp in moves.items():
        color, ls = PROFILE_STYLE[profile]
        for ax, y in zip(axs, pp.sample(ts)):
            ax.plot(ts, y[:, 0], ls, color=color, lw=2, label=f"{profile}, T = {pp.duration:.3f} s")
    for ax, limit in ((axs[1], v_lim), (axs[2], a_lim)):
        for sign in (1, -1):
            ax.axhline(sign * limit, color=COLORS["vermillion"], lw=1, ls=":")
    _finish(axs, (r"$q$ (rad)", r"$\dot q$ (rad/s)", r"$\ddot q$ (rad/s²)"),
            ("angle", "velocity (limit dotted)", "acceleration (limit dotted)"))
    fig.legend(*axs[0].get_legend_handles_labels(), fontsize="small", loc="outside lower center", ncols=3)
    return fig


def plot_synchronization(plan, ts, q_sync, q_alone, hits):
    """A segment of ``plan`` timed with the joints synchronized and each joint alone.

    Left: the plan's C-space with the unsynchronized joint-space trace (``hits`` marks its
    configurations in collision); right: both timings, joint by joint, against ``ts``.

    Examples
    --------
    >>> import rapp
    >>> plan = rapp.plan("default")
    >>> q = np.linspace(plan.shortcut[2], plan.shortcut[3], 5)
    >>> fig = plot_synchronization(plan, np.linspace(0, 1, 5), q, q, np.zeros(5, bool))
    >>> fig.axes[0].get_title(), len(fig.axes[1].lines)
    ('joint space, segment 3', 4)
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    plot_cspace(plan.occupancy, plan.grid, axs[0], path=plan.shortcut, start=plan.shortcut[0],
                goal=plan.shortcut[-1])
    axs[0].plot(*q_alone.T, "--", color=COLORS["vermillion"], lw=2, label="each joint alone")
    axs[0].plot(*q_alone[hits].T, "x", color=COLORS["yellow"], ms=6, mew=1.5, label="in collision")
    ticks = np.arange(0.0, 2.01, 0.5)
    axs[0].set(xlim=(-0.1, 2.0), ylim=(1.0, 2.4), xticks=ticks, xticklabels=[f"{x:g}" for x in ticks],
               yticks=ticks[2:], yticklabels=[f"{x:g}" for x in ticks[2:]])
    axs[0].set_title("joint space, segment 3", fontsize="medium")
    for j, color in enumerate((COLORS["blue"], COLORS["green"])):
        axs[1].plot(ts, q_sync[:, j], "-", color=color, lw=2, label=fr"$\theta_{j + 1}$ synchronized")
        axs[1].plot(ts, q_alone[:, j], "--", color=color, lw=2, label=fr"$\theta_{j + 1}$ alone")
    axs[1].set(xlabel="t (s)", ylabel="joint angle (rad)", title="the two timings")
    axs[1].grid(True, alpha=0.3)
    axs[0].get_legend().remove()
    handles, labels = (sum(pair, []) for pair in zip(*(ax.get_legend_handles_labels() for ax in axs)))
    fig.legend(handles, labels, fontsize="small", loc="outside lower center", ncols=5)
    for ax in axs:
        style_axes(ax)
    return fig


def plot_joint_velocities(timed, stops, v_lim):
    """Each joint's velocity under each timing ``timed[profile]``; ``stops`` the trapezoid's halts.

    Examples
    --------
    >>> from rapp.time_scaling import trapezoidal
    >>> fig = plot_joint_velocities({"trapezoidal": trapezoidal([0, 0], [1, 1], 1.0, 1.0)}, [0.0, 2.0], 1.0)
    >>> len(fig.axes), fig.axes[-1].get_xlabel()
    (2, 't (s)')
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(2, 1, figsize=(10, 5.2), sharex=True, layout="constrained")
    for profile, pp in timed.items():
        color, ls = PROFILE_STYLE[profile]
        ts = np.linspace(0.0, pp.duration, 1201)
        qd = pp.evaluate(ts, 1)
        for j, ax in enumerate(axs):
            ax.plot(ts, qd[:, j], ls, color=color, lw=2, label=f"{profile} ({pp.duration:.2f} s)")
    stops = np.asarray(stops, float)
    for j, ax in enumerate(axs):
        ax.plot(stops, np.zeros_like(stops), "o", color=COLORS["blue"], ms=6,
                label="trapezoid at a waypoint" if j == 0 else None)
        for sign in (1, -1):
            ax.axhline(sign * v_lim, color=COLORS["vermillion"], lw=1, ls=":")
        ax.set_ylabel(fr"$\dot\theta_{j + 1}$ (rad/s)")
        ax.grid(True, alpha=0.3)
        style_axes(ax)
    fig.legend(*axs[0].get_legend_handles_labels(), fontsize="small", loc="outside lower center", ncols=3)
    axs[-1].set_xlabel("t (s)")
    return fig


def plot_line_following(arm, a, b, q_line, q_edge):
    """The arm along ``q_line`` (waypoints following the line ``a``-``b``) and the tip's distance to it.

    The tip is followed densely along ``q_line``'s joint-space edges (64 points each) and along
    the single joint-space edge ``q_edge`` (4000 points, dashed, for comparison):
    :func:`rapp.cartesian.tip_along_edges`. Returns ``(fig, dist_line, dist_edge, s_line)``: both
    tips' distances to the line (m) and where ``q_line``'s tip projects onto it (a fraction).

    Examples
    --------
    >>> import rapp
    >>> from rapp.cartesian import line_path
    >>> from rapp.ik import ik_2link
    >>> arm = rapp.Arm([1.0, 1.0])
    >>> q = line_path(arm, ik_2link(arm, [1.0, 0.5])[0], [1.5, 0.5])
    >>> fig, dist_line, dist_edge, s = plot_line_following(arm, [1.0, 0.5], [1.5, 0.5], q, q[[0, -1]])
    >>> bool(dist_line.max() <= 1e-3 < dist_edge.max()), float(s[0]), round(float(s[-1]), 9)
    (True, 0.0, 1.0)
    >>> plt.close(fig)
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    tip_line, tip_edge = tip_along_edges(arm, q_line), tip_along_edges(arm, q_edge, 4000)
    dist_line, s_line = segment_point_distance(a, b, tip_line), line_fraction(tip_line, a, b)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    plot_workspace(arm, axs[0])
    plot_arm(arm, q_line[:: max(1, len(q_line) // 9)], axs[0], frame=False)
    axs[0].plot(*np.array([a, b]).T, "-", color=COLORS["black"], lw=1, label="the line")
    axs[0].plot(*tip_edge.T, "--", color=COLORS["orange"], lw=2, label="tip, one joint-space edge")
    axs[0].legend(fontsize="small", loc="lower left")
    axs[0].set_title("the arm along line_path", fontsize="medium")
    axs[1].plot(s_line, 1e3 * dist_line, color=COLORS["blue"], lw=1, label="line_path")
    axs[1].axhline(1.0, color=COLORS["vermillion"], ls=":", lw=1.5, label="tolerance 1 mm")
    axs[1].set(xlabel="s, fraction of the line (projection of the tip)", ylabel="tip's distance to the line (mm)",
               title="line_path: the tip's distance to the line", ylim=(0, 1.25))
    axs[1].grid(True, alpha=0.3)
    axs[1].legend(fontsize="small", loc="upper right")
    for ax in axs:
        style_axes(ax)
    return fig, dist_line, segment_point_distance(a, b, tip_edge), s_line


def plot_velocity_ellipse(ax, arm, q, scale, **kw):
    """The velocity ellipse at the tip: semi-axes sigma1, sigma2 (m/s per rad/s) drawn times ``scale`` (s).

    ``kw`` goes to :class:`matplotlib.patches.Ellipse`; returns the patch.

    Examples
    --------
    >>> import rapp
    >>> ax = plt.figure().add_subplot()
    >>> e = plot_velocity_ellipse(ax, rapp.Arm([1.0, 1.0]), [0.0, np.pi / 2], 1.0)
    >>> round(float(e.width * e.height) / 4, 6)              # sigma1 sigma2 = w = |sin theta2|
    1.0
    >>> plt.close(ax.figure)
    """
    (s1, s2), angle = manipulability_ellipse(arm, q)
    return ax.add_patch(Ellipse(arm.end_effector(q), 2 * scale * s1, 2 * scale * s2,
                                angle=np.degrees(angle), **kw))


def plot_manipulability_along(arm, a, b, q_line, ellipses=7):
    """Velocity ellipses along the line ``a``-``b`` and manipulability, condition number against s.

    Returns ``(fig, s_way, w, kappa)``: each waypoint of ``q_line``'s fraction of the line, its
    manipulability and its condition number.

    Examples
    --------
    >>> import rapp
    >>> from rapp.cartesian import line_path
    >>> from rapp.ik import ik_2link
    >>> arm = rapp.Arm([1.0, 1.0])
    >>> q = line_path(arm, ik_2link(arm, [1.0, 0.5])[0], [1.5, 0.5])
    >>> fig, s, w, kappa = plot_manipulability_along(arm, [1.0, 0.5], [1.5, 0.5], q)
    >>> bool(np.allclose(w, np.abs(np.sin(q[:, 1])))), len(fig.axes[0].patches) >= 7
    (True, True)
    >>> plt.close(fig)
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    w_line, kappa_line = manipulability(arm, q_line), condition_number(arm, q_line)
    s_way = line_fraction(arm.end_effector(q_line), a, b)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.4), layout="constrained")
    plot_workspace(arm, axs[0])
    axs[0].plot(*np.array([a, b]).T, "-", color=COLORS["black"], lw=1)
    for s_show in np.linspace(0.0, 1.0, ellipses):
        qq = np.array([np.interp(s_show, s_way, q_line[:, j]) for j in range(q_line.shape[1])])
        plot_arm(arm, qq, axs[0], alpha=0.35, frame=False)
        plot_velocity_ellipse(axs[0], arm, qq, 0.2, facecolor=COLORS["orange"], alpha=0.5,
                              edgecolor=COLORS["vermillion"], zorder=6)
    axs[0].set_title("velocity ellipses, drawn at 0.2 s of travel", fontsize="medium")
    axs[1].plot(s_way, w_line, color=COLORS["blue"], lw=2, label=r"manipulability $w$")
    axs[1].set(xlabel="s, fraction of the line", ylabel=r"$w$ (m²/rad²)", ylim=(0, 1.05))
    ax_k = axs[1].twinx()
    ax_k.plot(s_way, kappa_line, "--", color=COLORS["vermillion"], lw=2, label=r"condition number $\kappa$")
    ax_k.set(ylabel=r"$\kappa$ (no unit)", ylim=(0, 1.05 * kappa_line.max()))
    axs[1].grid(True, alpha=0.3)
    axs[1].set_title("along the line", fontsize="medium")
    axs[1].legend(handles=axs[1].lines + ax_k.lines, fontsize="small", loc="upper left")
    for ax in (*axs, ax_k):
        style_axes(ax)
    return fig, s_way, w_line, kappa_line


def plot_timed_path(waypoints, timed, ts):
    """A planner's waypoints and their timing: the joint-space curve, and each joint against time.

    Examples
    --------
    >>> w = np.array([[0.0, 0.0], [1.0, 0.5]])
    >>> fig = plot_timed_path(w, time_path(w, 2.0, "cubic"), np.linspace(0, 2, 21))
    >>> [ax.get_title() for ax in fig.axes]
    ['joint space', 'the same motion in time']
    >>> plt.close(fig)
    """
    waypoints = np.asarray(waypoints, float)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2), layout="constrained")
    axs[0].plot(*waypoints.T, "o--", color=COLORS["grey"], label="planner's path (waypoints)")
    axs[0].plot(*timed.evaluate(ts).T, "-", color=COLORS["blue"], lw=2, label="timed trajectory")
    axs[0].set(xlabel=r"$\theta_1$ (rad)", ylabel=r"$\theta_2$ (rad)", title="joint space")
    for j, c in enumerate((COLORS["blue"], COLORS["orange"])):
        axs[1].plot(ts, timed.evaluate(ts)[:, j], color=c, lw=2, label=fr"$\theta_{j + 1}(t)$")
        axs[1].plot(timed.breakpoints, waypoints[:, j], "o", color=c)
    axs[1].set(xlabel="t (s)", ylabel="joint angle (rad)", title="the same motion in time")
    for ax in axs:
        ax.legend(fontsize="small", loc="upper left")
        ax.grid(True, alpha=0.3)
        style_axes(ax)
    return fig


def plot_conditioning(x, kappa, rel_naive, rel_shifted):
    """Relative coefficient errors of a cubic solved in absolute and in shifted time, against ``x``.

    ``kappa`` is the absolute-time system's condition number; the dotted bound is kappa times eps.

    Examples
    --------
    >>> fig = plot_conditioning(np.array([1.0, 10.0]), np.array([10.0, 1e4]), np.array([1e-15, 1e-12]),
    ...                         np.array([0.0, 1e-16]))
    >>> fig.axes[0].get_xscale(), len(fig.axes[0].lines)
    ('log', 3)
    >>> plt.close(fig)
    """
    fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
    ax.loglog(x, kappa * np.finfo(float).eps, ":", color=COLORS["grey"], label=r"$\kappa(M)\,\varepsilon$")
    ax.loglog(x, np.maximum(rel_naive, 1e-17), "-o", color=COLORS["vermillion"], label="solve eq. 5 in absolute time")
    ax.loglog(x, np.maximum(rel_shifted, 1e-17), "-s", color=COLORS["blue"], label="rapp.cubic (shifted time)")
    ax.set(xlabel="$t_0 + 1$ (s), segment of 1 s", ylabel="relative coefficient error",
           title="conditioning of the absolute-time system")
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    style_axes(ax)
    return fig


def plot_derivatives(trajectories, ts, styles, marks, ylabels, vlines=()):
    """Joint 1's position, velocity and acceleration under each trajectory, stacked.

    ``styles`` gives a ``(colour, line style)`` per trajectory, ``marks`` is ``(t, q, label)``
    drawn as black dots on the position, ``vlines`` times marked by thin grey lines.

    Examples
    --------
    >>> from rapp.trajectory import via_points
    >>> pp = via_points([0.0, 1.0, 2.0], [0.0, 1.0, 0.0])
    >>> fig = plot_derivatives({"via": pp}, np.linspace(0, 2, 21), [("k", "-")], ([0, 1, 2], [0, 1, 0], "points"),
    ...                        ("q", "q'", "q''"), vlines=[1.0])
    >>> [ax.get_ylabel() for ax in fig.axes], fig.axes[-1].get_xlabel()
    (['q', "q'", "q''"], 't (s)')
    >>> plt.close(fig)
    """
    fig, axs = plt.subplots(3, 1, figsize=(7, 6.5), sharex=True, layout="constrained")
    for (name, pp), (c, ls) in zip(trajectories.items(), styles):
        for d, ax in enumerate(axs):
            ax.plot(ts, pp.evaluate(ts, d)[:, 0], ls, color=c, lw=2, label=name)
    axs[0].plot(marks[0], marks[1], "ko", ms=5, label=marks[2])
    for ax, lab in zip(axs, ylabels):
        ax.set_ylabel(lab)
        for tv in vlines:
            ax.axvline(tv, color="#cccccc", lw=0.8, zorder=0)
        ax.grid(True, alpha=0.3)
        style_axes(ax)
    axs[0].legend(fontsize="small", ncol=4, loc="lower right")
    axs[-1].set_xlabel("t (s)")
    return fig
