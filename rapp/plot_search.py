"""Figures of grid searches on the C-space: paths, expanded or reachable cells, resolution studies.

Chapter 5's figures. Each function takes occupancy grids and the cells a search returned and
returns the :class:`matplotlib.figure.Figure` it drew; nothing here searches, nothing calls
``plt.show()``.

Examples
--------
>>> import numpy as np
>>> from rapp import Arm, JointGrid
>>> grid = JointGrid(Arm([1.0, 1.0]), 8)
>>> occ = np.zeros((8, 8), bool)
>>> fig = plot_searches([dict(occupancy=occ, grid=grid, start=(0, 0), goal=(3, 3), path=[(0, 0), (3, 3)])],
...                     (5, 4))
>>> len(fig.axes), fig.axes[0].get_legend() is not None
(1, True)
>>> plt.close(fig)
"""

from __future__ import annotations

import numpy as np
import matplotlib.pyplot as plt
from matplotlib import patches
from matplotlib.colors import ListedColormap

from rapp.palette import COLORS, GOAL, START
from rapp.plotting import legend_outside, plot_arm, plot_cspace, plot_obstacles, style_axes

__all__ = ["plot_search_panel", "plot_searches", "plot_arm_ends", "plot_resolution_study"]


def plot_search_panel(ax, occupancy, grid, start, goal, path=None, title=None, shaded=None, alpha=0.45):
    """One C-space panel: a search's ``path`` (cells) from ``start`` to ``goal`` (cells), ``shaded`` cells in sky blue.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> grid = JointGrid(Arm([1.0, 1.0]), 4)
    >>> ax = plot_search_panel(plt.figure().add_subplot(), np.zeros((4, 4), bool), grid, (0, 0), (2, 2),
    ...                        shaded=np.eye(4, dtype=bool))
    >>> len(ax.images)                                 # the C-space and the shaded cells
    2
    >>> plt.close(ax.figure)
    """
    plot_cspace(occupancy, grid, ax, path=None if path is None else grid.angles(np.asarray(path)),
                start=grid.angles(np.array(start)), goal=grid.angles(np.array(goal)), title=title)
    if shaded is not None:
        ax.imshow(np.ma.masked_where(~shaded.T, shaded.T), origin="lower", extent=ax.images[0].get_extent(),
                  cmap=ListedColormap([COLORS["sky"]]), alpha=alpha, interpolation="nearest", zorder=1)
    return ax


def plot_searches(panels, figsize, *, shade_label=None, alpha=0.45, axes=None):
    """One :func:`plot_search_panel` per entry of ``panels`` (its keyword arguments), one legend outside.

    The panels fill the last ``len(panels)`` of ``axes`` (a new row of axes when ``None``); the
    legend, right of the last, adds a patch named ``shade_label`` for the shaded cells.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> grid = JointGrid(Arm([1.0, 1.0]), 8)
    >>> occ = np.zeros((8, 8), bool)
    >>> fig = plot_searches([dict(occupancy=occ, grid=grid, start=(0, 0), goal=(3, 3), title=t) for t in "ab"],
    ...                     (8, 4), shade_label="expanded")
    >>> [ax.get_legend() is None for ax in fig.axes], fig.axes[1].get_legend().get_texts()[-1].get_text()
    ([True, False], 'expanded')
    >>> plt.close(fig)
    """
    if axes is None:
        _, axes = plt.subplots(1, len(panels), figsize=figsize, layout="constrained")
    axes = np.atleast_1d(axes)
    for ax, panel in zip(axes[len(axes) - len(panels):], panels):
        plot_search_panel(ax, **panel, alpha=alpha)
        ax.get_legend().remove()
    extra = [] if shade_label is None else [patches.Patch(facecolor=COLORS["sky"], alpha=alpha, label=shade_label)]
    legend_outside(axes[-1], extra)
    return axes[0].figure


def plot_arm_ends(ax, arm, obstacles, q_start, q_goal, title):
    """The workspace with ``obstacles`` and the arm at its start and goal configurations.

    Examples
    --------
    >>> from rapp import Arm
    >>> ax = plot_arm_ends(plt.figure().add_subplot(), Arm([1.0, 1.0]), [], [0, 0], [1, 1], "ends")
    >>> [t.get_text() for t in ax.get_legend().get_texts()]
    ['start', 'goal']
    >>> plt.close(ax.figure)
    """
    plot_obstacles(obstacles, ax)
    plot_arm(arm, q_start, ax, color=START, label="start")
    plot_arm(arm, q_goal, ax, color=GOAL, label="goal")
    ax.set_title(title, fontsize="medium")
    ax.legend(loc="lower left", fontsize="small")
    return ax


def plot_resolution_study(cells, lengths, expansions):
    """Path length and A* expansions against the cells per joint: length settles, effort grows.

    Examples
    --------
    >>> fig = plot_resolution_study([24, 48], [6.0, 5.9], [100, 400])
    >>> fig.axes[1].get_xscale(), fig.axes[0].get_title()
    ('log', 'length settles')
    >>> plt.close(fig)
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    ax1.plot(cells, lengths, "o-", color=COLORS["blue"])
    ax1.set_xlabel("cells per joint M")
    ax1.set_ylabel("path length (rad, L1)")
    ax1.set_title("length settles", fontsize="medium")
    ax2.loglog(cells, expansions, "o-", color=COLORS["vermillion"])
    ax2.set_xlabel("cells per joint M")
    ax2.set_ylabel("A* expansions (cells)")
    ax2.set_title("effort grows", fontsize="medium")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        style_axes(ax)
    return fig
