"""Case study, seed 002: the figures, the animation and the explorer of chapter 11.

Each function draws one of chapter 11's figures from the values the chapter computes
(:mod:`rapp.cases.via_point_detour` computes; this module only draws). A function that makes
its own figure returns it; one given an ``ax`` draws into it and returns it. The arm poses come
from the seed's printed inverse kinematics (:func:`rapp.cases.via_point_detour.printed_ik`,
elbow down), as in the chapter.
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.animation import FuncAnimation
from matplotlib.figure import Figure

from rapp.arm import Arm
from rapp.collision import clearance
from rapp.ik import ik_2link
from rapp.plotting import COLORS, plot_arm, plot_obstacles, style_axes
from rapp.trajectory import via_points
from rapp.view_stack import Control, view_stack
from rapp.cases.via_point_detour import path_clearance, printed_ik

__all__ = [
    "SCENE_LIMITS",
    "plot_arm_along",
    "plot_xy_profiles",
    "plot_via_choices",
    "plot_formula_vs_atan2",
    "plot_postures",
    "closest_approach_animation",
    "plot_spline_vs_cubic",
    "via_point_explorer",
]

#: The x and y limits (m) of the chapter's whole-scene figures: the 18 m arm's reach around C.
SCENE_LIMITS = ((-2.0, 19.0), (-9.0, 12.0))


def _scene(ax):
    ax.set_xlim(*SCENE_LIMITS[0])
    ax.set_ylim(*SCENE_LIMITS[1])


def plot_arm_along(arm, traj, points, obstacles, ax=None, *, ghosts=17):
    """The arm (elbow down) at ``ghosts`` instants of ``traj``, the tip's path and named points.

    Parameters
    ----------
    arm : rapp.Arm
    traj : rapp.trajectory.PiecewisePolynomial
        The tip's trajectory.
    points : mapping of str to (2,) array
        Points to mark and name (``{"A": A, ...}``).
    obstacles : sequence of rapp.Circle
    ax : matplotlib Axes, optional
        A new 7 x 6 in figure when omitted.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> tr = via_points([0.0, 1.0], [[9.0, 1.0], [9.0, 3.0]], velocities=[[0, 0], [0, 0]])
    >>> ax = plot_arm_along(Arm([9.0, 9.0]), tr, {"A": [9.0, 1.0]}, [Circle((5, 5), 1)])
    >>> [t.get_text() for t in ax.texts], [float(x) for x in ax.get_xlim()]
    (['A'], [-2.0, 19.0])
    >>> plt.close("all")
    """
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    t = np.linspace(traj.t0, traj.tf, ghosts)
    q = ik_2link(arm, traj.evaluate(t))[:, 0]
    plot_arm(arm, q, ax, label=f"arm every {(traj.tf - traj.t0) / (ghosts - 1):g} s (elbow down)")
    plot_obstacles(obstacles, ax)
    ax.plot(*traj.evaluate(np.linspace(traj.t0, traj.tf, 801)).T, color=COLORS["orange"], lw=2,
            label="tip path")
    for name, P in points.items():
        ax.plot(*P, "ko", ms=4)
        ax.annotate(name, P, textcoords="offset points", xytext=(5, 5))
    _scene(ax)
    ax.legend(loc="upper left", fontsize="small")
    style_axes(ax)
    return ax


def plot_xy_profiles(traj, title, knots):
    """x, y and their velocities against time (2 x 2 panels), the knots dotted.

    Examples
    --------
    >>> tr = via_points([0.0, 1.0, 2.0], [[0, 0], [1, 1], [2, 0]], velocities=[[0, 0], [1, 0], [0, 0]])
    >>> fig = plot_xy_profiles(tr, "t", [0.0, 1.0, 2.0])
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['x (m)', 'y (m)', 'ẋ (m/s)', 'ẏ (m/s)']
    >>> plt.close("all")
    """
    t = np.linspace(traj.t0, traj.tf, 801)
    p, v = traj.evaluate(t), traj.evaluate(t, 1)
    fig, axs = plt.subplots(2, 2, figsize=(9, 5), sharex=True, layout="constrained")
    for ax, data, lab in zip(axs.T.ravel(), (p[:, 0], v[:, 0], p[:, 1], v[:, 1]),
                             ("x (m)", "ẋ (m/s)", "y (m)", "ẏ (m/s)")):
        ax.plot(t, data, color=COLORS["blue"], lw=2)
        for tk in knots:
            ax.axvline(tk, color="#999999", lw=0.8, ls=":")
        ax.set_ylabel(lab)
        ax.grid(True, color="#e6e6e6")
        style_axes(ax)
    for ax in axs[1]:
        ax.set_xlabel("t (s)")
    fig.suptitle(title)
    return fig


def _draw_via_paths(ax, ends, vias, obstacle, times, velocities, title):
    start, via_start, goal = ends
    t = np.linspace(times[0], times[-1], 801)
    plot_obstacles([obstacle], ax)
    for (name, D), col in zip(vias, (COLORS["blue"], COLORS["green"], COLORS["vermillion"])):
        traj = via_points(times, [start, via_start, D, goal], velocities=velocities)
        ax.plot(*traj.evaluate(t).T, color=col, lw=2, label=f"cubic path, {name}")
        ax.plot(*np.array([via_start, D, goal]).T, "--", color=col, lw=1)
        ax.plot(*D, "o", color=col)
    for n, P in zip("ABC", ends):
        ax.annotate(n, P, textcoords="offset points", xytext=(4, 4))
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)
    ax.grid(True, color="#e6e6e6")


def plot_via_choices(ends, vias, obstacle, times, velocities, *, zoom):
    """Cubic paths ``A -> B -> D -> C`` for several D, with the straight segments, and a zoom.

    Parameters
    ----------
    ends : (A, B, C)
        The start, the first via point and the goal, each ``(2,)``.
    vias : sequence of (str, (2,) array)
        The candidate D's, named (three at most: one colour each).
    obstacle : rapp.Circle
    times, velocities
        The four knot times and velocities, as :func:`rapp.trajectory.via_points` takes them.
    zoom : ((x0, x1), (y0, y1))
        The right panel's limits.

    Examples
    --------
    >>> from rapp import Circle
    >>> ends, z = ([0, 0], [1, 1], [4, 0]), np.zeros(2)
    >>> fig = plot_via_choices(ends, [("D", [2, 2])], Circle((2, 0), 0.5), [0, 1, 2, 3], [z] * 4,
    ...                        zoom=((1, 3), (1, 3)))
    >>> len(fig.axes), [float(x) for x in fig.axes[1].get_xlim()]
    (2, [1.0, 3.0])
    >>> plt.close("all")
    """
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    _draw_via_paths(axs[0], ends, vias, obstacle, times, velocities,
                    "Task 2: paths (solid), straight segments (dashed)")
    _draw_via_paths(axs[1], ends, vias, obstacle, times, velocities, "zoom near D")
    axs[1].set_xlim(*zoom[0])
    axs[1].set_ylim(*zoom[1])
    fig.legend(*axs[0].get_legend_handles_labels(), loc="outside lower center", ncol=3, fontsize="small")
    for ax in axs:
        style_axes(ax)
    return fig


def plot_formula_vs_atan2(cases):
    """For each ``name -> (links, target)``: the atan2 solution and the printed eqs. 36-37's.

    Examples
    --------
    >>> fig = plot_formula_vs_atan2({"x < 0": ((1.0, 1.0), np.array([-1.0, 0.5]))})
    >>> [len(ax.get_legend().get_texts()) for ax in fig.axes]
    [3]
    >>> plt.close("all")
    """
    fig, axs = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4.6), layout="constrained",
                            squeeze=False)
    for ax, (name, (links, target)) in zip(axs[0], cases.items()):
        arm = Arm(links)
        plot_arm(arm, ik_2link(links, target)[0], ax, label="atan2 form (rapp.ik_2link)")
        plot_arm(arm, printed_ik(target, +1, lengths=links, strict=False), ax,
                 color=COLORS["vermillion"], label="eqs. 36–37 (arctan, arcsin)")
        ax.plot(*target, "*", color="k", ms=14, label="target", zorder=6)
        ax.set_title(f"links ({links[0]:g}, {links[1]:g}) m, target ({target[0]:g}, {target[1]:g}) m:\n{name}",
                     fontsize="medium")
        ax.legend(loc="lower left", fontsize="small")
        style_axes(ax)
    return fig


def plot_postures(arm, postures, obstacles, *, marks=None, path=None, title=None):
    """Two (or more) postures of ``arm`` among ``obstacles`` on the chapter's whole scene.

    Parameters
    ----------
    postures : sequence of (q, label)
        The first in the arm's colour, the next in vermillion, then orange.
    marks : (points, label), optional
        Points drawn as black triangles, one legend entry.
    path : (k, 2) array, optional
        The tip's path (orange).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> ax = plot_postures(Arm([9.0, 9.0]), [([0, 0], "a"), ([1, 1], "b")], [Circle((5, 5), 1)],
    ...                    path=np.zeros((3, 2)), title="t")
    >>> [t.get_text() for t in ax.get_legend().get_texts()][:2], ax.get_title()
    (['a', 'b'], 't')
    >>> plt.close("all")
    """
    colours = (None, COLORS["vermillion"], COLORS["orange"])
    ax = None
    for (q, label), colour in zip(postures, colours):
        kw = {} if colour is None else {"color": colour}
        ax = plot_arm(arm, q, ax, label=label, **kw)
    plot_obstacles(obstacles, ax)
    if marks is not None:
        ax.plot(*np.asarray(marks[0]).T, "k^", ms=7, label=marks[1])
    if path is not None:
        ax.plot(*np.asarray(path).T, color=COLORS["orange"], lw=1.5, label="path")
    _scene(ax)
    ax.legend(loc="lower left", fontsize="small")
    if title is not None:
        ax.set_title(title)
    return ax


def _zoom_panel(az, obstacle, tip, window):
    """The disc's edge near ``tip`` filled, limits a square ``window`` wide; returns the edge point."""
    centre = np.asarray(obstacle.center, dtype=float)
    toward = (tip - centre) / np.linalg.norm(tip - centre)
    edge = centre + obstacle.radius * toward  # the nearest point of the disc
    ang = np.arctan2(toward[1], toward[0]) + np.linspace(-0.2, 0.2, 2001)
    arc = centre + obstacle.radius * np.stack([np.cos(ang), np.sin(ang)], -1)
    az.fill(*np.vstack([arc, centre]).T, color="#8c8c8c", zorder=1)
    half = window / 2
    az.set_xlim(tip[0] - half, tip[0] + half)
    az.set_ylim(tip[1] - half, tip[1] + half)
    az.annotate("", xy=edge, xytext=tip, arrowprops=dict(arrowstyle="<->", color="k", lw=1.2,
                                                         shrinkA=0, shrinkB=0))
    return edge


def closest_approach_animation(arm, traj, obstacle, frames_t, *, window=0.05):
    """The arm along ``traj`` (printed IK, elbow down), with a zoom on its closest frame.

    Left: the whole scene. Right: a square ``window`` (m) wide centred on the tip at the frame of
    smallest clearance, where the disc's edge and the gap are drawn to scale. The title gives
    each frame's time and clearance.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Its figure's zoom axes carry the gap arrow from the tip to the disc's nearest point.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> tr = via_points([0.0, 1.0], [[9.0, 3.0], [12.0, 3.0]], velocities=[[0, 0], [0, 0]])
    >>> anim = closest_approach_animation(Arm([9.0, 9.0]), tr, Circle((10.5, 5.0), 1.9), [0.0, 0.5, 1.0])
    >>> plt.gcf().axes[1].get_title()
    'zoom: closest approach at t = 0.50 s'
    >>> plt.close("all")
    """
    frames_t = np.asarray(frames_t, dtype=float)
    q_frames = printed_ik(traj.evaluate(frames_t), +1, lengths=tuple(arm.lengths))
    joints = arm.joint_positions(q_frames)  # (frames, 3, 2)
    gaps = clearance(arm, q_frames, [obstacle])
    k = int(np.argmin(gaps))
    tip, gap = joints[k, -1], float(gaps[k])
    path = traj.evaluate(np.linspace(traj.t0, traj.tf, 2001))

    fig, (ax, az) = plt.subplots(1, 2, figsize=(9, 4.8), dpi=100, layout="constrained")
    plot_obstacles([obstacle], ax)
    edge = _zoom_panel(az, obstacle, tip, window)
    for a in (ax, az):
        a.plot(*path.T, color=COLORS["orange"], lw=1.5, zorder=2)
        a.set_aspect("equal")
        a.set_xlabel("x (m)")
        a.set_ylabel("y (m)")
    _scene(ax)
    ax.plot([0.0], [0.0], "s", color="k", ms=8, zorder=4)
    ax.annotate("zoom window", tip, xytext=(15, -5), ha="center", color=COLORS["vermillion"],
                arrowprops=dict(arrowstyle="->", color=COLORS["vermillion"]))
    az.annotate(f"{gap * 1000:.1f} mm", (tip + edge) / 2, xytext=(12, 0),
                textcoords="offset points", va="center")
    az.set_title(f"zoom: closest approach at t = {frames_t[k]:.2f} s", fontsize="medium")
    (arm_l,) = ax.plot([], [], "-o", color=COLORS["blue"], lw=3, ms=6, mfc="white", zorder=3)
    (tip_l,) = ax.plot([], [], "o", color=COLORS["vermillion"], ms=7, zorder=5)
    (arm_z,) = az.plot([], [], "-", color=COLORS["blue"], lw=2, zorder=3)
    (tip_z,) = az.plot([], [], "o", color=COLORS["vermillion"], ms=4, zorder=5)
    title = ax.set_title("", fontsize="medium")
    for a in (ax, az):
        style_axes(a)

    def update(i):
        arm_l.set_data(joints[i, :, 0], joints[i, :, 1])
        tip_l.set_data(joints[i, -1:, 0], joints[i, -1:, 1])
        arm_z.set_data(joints[i, 1:, 0], joints[i, 1:, 1])
        tip_z.set_data(joints[i, -1:, 0], joints[i, -1:, 1])
        g = gaps[i]
        title.set_text(f"t = {frames_t[i]:.2f} s, clearance " + (f"{g * 1000:.1f} mm" if g < 0.1 else f"{g:.2f} m"))
        return arm_l, tip_l, arm_z, tip_z, title

    update(0)
    return FuncAnimation(fig, update, frames=len(frames_t), interval=320, blit=False)


def plot_spline_vs_cubic(trajs, points, obstacle):
    """Path, speed and acceleration magnitude of each named trajectory, side by side.

    Examples
    --------
    >>> from rapp import Circle
    >>> tr = via_points([0.0, 1.0], [[0, 0], [1, 0]], velocities=[[0, 0], [0, 0]])
    >>> fig = plot_spline_vs_cubic({"a": tr}, [[0, 0], [1, 0]], Circle((0.5, 1), 0.2))
    >>> [ax.get_title() for ax in fig.axes]
    ['path', 'speed', 'acceleration']
    >>> plt.close("all")
    """
    fig, axs = plt.subplots(1, 3, figsize=(12, 3.8), layout="constrained")
    plot_obstacles([obstacle], axs[0])
    for (name, tr), col in zip(trajs.items(), (COLORS["blue"], COLORS["orange"])):
        tt = np.linspace(tr.t0, tr.tf, 1601)
        axs[0].plot(*tr.evaluate(tt).T, color=col, lw=2, label=name)
        axs[1].plot(tt, np.linalg.norm(tr.evaluate(tt, 1), axis=-1), color=col, lw=2, label=name)
        axs[2].plot(tt, np.linalg.norm(tr.evaluate(tt, 2), axis=-1), color=col, lw=2, label=name)
    axs[0].plot(*np.array(points).T, "ko", ms=4)
    axs[0].set_aspect("equal")
    axs[0].set_xlabel("x (m)")
    axs[0].set_ylabel("y (m)")
    for ax, lab in zip(axs, ("path", "speed", "acceleration")):
        ax.set_title(lab)
        ax.grid(True, color="#e6e6e6")
        style_axes(ax)
    axs[1].set_ylabel("speed (m/s)")
    axs[2].set_ylabel("|acceleration| (m/s²)")
    for ax in axs[1:]:
        ax.set_xlabel("t (s)")
    fig.legend(*axs[0].get_legend_handles_labels(), loc="outside lower center", ncol=3, fontsize="small")
    return fig


def via_point_explorer(arm, ends, obstacle, times, velocities, xs, ys, default):
    """An explorer of the via point D: path, straight segments, the arm at its closest approach.

    The path is ``A -> B -> D -> C`` (``ends = (A, B, C)``) at ``times`` with ``velocities``; the
    arm (printed IK, elbow down) is drawn at the instant of its least clearance among 401 from
    B's time on. The status line gives ``|BD| + |DC|``, the path's exact clearance
    (:func:`rapp.cases.via_point_detour.path_clearance`) and the arm's least clearance, in m.

    Parameters
    ----------
    xs, ys : sequence of float
        The slider stops of D's coordinates.
    default : (float, float)
        The view shown first.

    Returns
    -------
    ipywidgets.VBox
        :func:`rapp.view_stack.view_stack`'s explorer.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> from rapp.view_stack import selected
    >>> z = np.zeros(2)
    >>> w = via_point_explorer(Arm([9.0, 9.0]), ([2, 5], [5, 8], [14, 7]), Circle((10, 7), 1.5),
    ...                        [0.0, 3.0, 5.5, 8.0], [z, [0.25, 0.25], z, z], [9.86], [5.32], (9.86, 5.32))
    >>> selected(w)[1].split(";")[0]
    '|BD| + |DC| = 10.018 m'
    """
    start, via_start, goal = (np.asarray(p, dtype=float) for p in ends)
    fig = Figure(figsize=(6.4, 6.4), layout="constrained")
    ax = fig.add_subplot()
    plot_obstacles([obstacle], ax)
    ax.set_xlim(-1, 16)
    ax.set_ylim(-7, 12)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")

    def view(Dx, Dy):
        D = np.array([Dx, Dy])
        tr = via_points(times, [start, via_start, D, goal], velocities=velocities)
        q = printed_ik(tr.evaluate(np.linspace(times[1], times[-1], 401)), +1, lengths=tuple(arm.lengths))
        arm_gap = clearance(arm, q, [obstacle])
        plot_arm(arm, q[np.argmin(arm_gap)], ax, label="arm at closest approach", frame=False)
        ax.plot(*tr.evaluate(np.linspace(times[0], times[-1], 400)).T, color=COLORS["orange"], lw=2,
                label="path")
        ax.plot(*np.array([via_start, D, goal]).T, "--", color="#777777", lw=1)
        ax.legend(loc="upper left", fontsize="small")
        pc = float(path_clearance(D, via_start, goal, obstacle.center, v_start=velocities[1],
                                  times=tuple(times[1:]))) - obstacle.radius
        ax.set_title(f"D = ({Dx:.2f}, {Dy:.2f}) m", fontsize="medium")
        length = np.linalg.norm(D - via_start) + np.linalg.norm(goal - D)
        return (f"|BD| + |DC| = {length:.3f} m; path clearance {pc:+.3f} m; "
                f"arm clearance {arm_gap.min():+.3f} m")

    return view_stack(fig, {"Dx": Control("D x (m)", xs, default=default[0]),
                            "Dy": Control("D y (m)", ys, default=default[1])}, view,
                      title="Move the via point D")
