"""Views of the C-space: beside the workspace, with an interval's closed-form edges, tiled, on the torus.

Chapter 4's figures. Each function takes occupancy grids (:func:`rapp.occupancy`) and returns
the :class:`matplotlib.figure.Figure` it drew; nothing calls ``plt.show()``.

Examples
--------
>>> import numpy as np
>>> from rapp import Arm, JointGrid
>>> grid = JointGrid(Arm([1.0, 1.0]), 8)
>>> fig = plot_tiled(np.eye(8, dtype=bool), grid)
>>> fig.axes[1].images[0].get_array().shape
(16, 16)
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.colors import ListedColormap

from rapp.arm import wrap_angle
from rapp.palette import COLORS, OCCUPIED
from rapp.plotting import plot_arm, plot_cspace, plot_obstacles, plot_torus, plot_workspace, style_axes

__all__ = ["plot_side_by_side", "plot_interval_edges", "plot_tiled", "plot_torus_and_square"]


def plot_side_by_side(arm, obstacles, occupancy, grid, configurations, title):
    """The workspace with the arm at each configuration, and the C-space with each as a dot.

    The configurations are coloured blue, vermillion, green in turn, the same in both panels.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> arm = Arm([1.0, 1.0])
    >>> fig = plot_side_by_side(arm, [], np.zeros((8, 8), bool), JointGrid(arm, 8), [[0.0, 0.0]], "C")
    >>> [ax.get_title() for ax in fig.axes], fig.axes[1].lines[-1].get_xydata().tolist()
    (['workspace', 'C'], [[0.0, 0.0]])
    >>> plt.close(fig)
    """
    colors = [COLORS["blue"], COLORS["vermillion"], COLORS["green"]]
    fig, (ax_w, ax_c) = plt.subplots(1, 2, figsize=(10, 4.8), layout="constrained")
    plot_workspace(arm, ax_w)
    plot_obstacles(obstacles, ax_w)
    plot_cspace(occupancy, grid, ax_c, title=title)
    for q, c in zip(configurations, colors):
        plot_arm(arm, q, ax_w, color=c)
        ax_c.plot(*q, "o", color=c, ms=9, mec="white")
    ax_w.set_title("workspace")
    return fig


def plot_interval_edges(occupancy, grid, t1, half_width, direction, title):
    """A one-obstacle C-space with the closed-form edges of link 2's interval drawn over it.

    At each shoulder angle ``t1`` link 2 touches the obstacle for absolute directions
    ``direction`` +- ``half_width`` (no contact where ``half_width < 0``); the edges are drawn
    relative to ``t1``, broken where they cross the seam.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> grid = JointGrid(Arm([1.0, 1.0]), 8)
    >>> t1 = np.linspace(-np.pi, np.pi, 9)
    >>> fig = plot_interval_edges(np.zeros((8, 8), bool), grid, t1, np.full(9, 0.2), np.zeros(9), "one disc")
    >>> len(fig.axes[0].get_legend().get_texts())
    1
    >>> plt.close(fig)
    """
    fig, ax = plt.subplots(figsize=(7.5, 5.0), layout="constrained")
    plot_cspace(occupancy, grid, ax, title=title)
    for sign in (-1, 1):
        edge = np.where(half_width >= 0, wrap_angle(direction + sign * half_width - t1), np.nan)
        edge[np.abs(np.diff(edge, append=edge[-1])) > np.pi] = np.nan  # do not draw across the seam
        ax.plot(t1, edge, color=COLORS["orange"], lw=1.5, label="interval edges (closed form)")
    handles, labels = ax.get_legend_handles_labels()
    ax.legend(handles[:1], labels[:1], loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    style_axes(ax)
    return fig


def plot_tiled(occupancy, grid):
    """A C-space cut open at +-pi, and four copies of it side by side: its pieces join across the seam."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.8), layout="constrained")
    plot_cspace(occupancy, grid, ax1, title="one disc behind the base,\ncut open at ±π")
    tiled = np.tile(occupancy.T.astype(float), (2, 2))
    x0, x1, y0, y1 = ax1.images[0].get_extent()  # pixel edges: a sample at each pixel centre
    ax2.imshow(tiled, origin="lower", extent=[x0, 2 * x1 - x0, y0, 2 * y1 - y0],
               cmap=ListedColormap(["white", OCCUPIED]), interpolation="nearest")
    ax2.axvline(np.pi, color=COLORS["vermillion"], ls="--", lw=1, label="seam θ = ±π")
    ax2.axhline(np.pi, color=COLORS["vermillion"], ls="--", lw=1)
    ax2.set_title("four copies side by side:\nthe pieces join", fontsize="medium")
    ticks = np.arange(-1, 4) * np.pi
    ax2.set_xticks(ticks, ["−π", "0", "π", "2π", "3π"])
    ax2.set_yticks(ticks, ["−π", "0", "π", "2π", "3π"])
    ax2.set_xlabel("θ1 (rad)")
    ax2.set_ylabel("θ2 (rad)")
    ax2.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    style_axes(ax2)
    return fig


def plot_torus_and_square(occupancy, grid, path):
    """The C-space on the torus (seen from below) with a path, and the square it unrolls to.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> grid = JointGrid(Arm([1.0, 1.0]), 8)
    >>> fig = plot_torus_and_square(np.zeros((8, 8), bool), grid, np.array([[0.0, 0.0], [1.0, 1.0]]))
    >>> fig.axes[0].name, fig.axes[1].get_title()
    ('3d', 'the square it unrolls to')
    >>> plt.close(fig)
    """
    fig = plt.figure(figsize=(10, 4.6), layout="constrained")
    ax3d = fig.add_subplot(1, 2, 1, projection="3d")
    plot_torus(occupancy, grid, ax3d, path=path, start=path[0], goal=path[-1], title="the torus (seen from below)")
    plot_cspace(occupancy, grid, fig.add_subplot(1, 2, 2), path=path, start=path[0], goal=path[-1],
                title="the square it unrolls to")
    return fig
