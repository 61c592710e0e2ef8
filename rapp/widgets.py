"""Interactive explorers for the book, built on :mod:`rapp.plotting` (ipywidgets).

Every explorer returns one widget (a ``VBox``: controls, a status line, and an
``Output`` holding the figure). The figure of the default values is drawn at
construction, so the saved widget state — all a static HTML page has, with no
kernel behind it — shows a meaningful view.

Each figure is rendered to PNG and placed in the ``Output`` widget's
``outputs`` directly rather than captured with ``with out:``: capture needs a
running kernel, and this way the default view exists in plain Python too
(where the tests check it) and is stored in the widget state the book saves.
The figures are pyplot-free ``Figure`` objects, so nothing is shown twice and
no figure is left open.

Examples
--------
>>> from rapp import Arm, Circle
>>> w = arm_explorer(Arm([1.0, 1.0]), [Circle((1.2, 0.8), 0.3)])
>>> output_of(w).outputs[0]["data"]["image/png"][:8]  # base64 of the PNG signature
'iVBORw0K'
"""

from __future__ import annotations

import base64
import dataclasses
import io
import html

import numpy as np
import ipywidgets as widgets
from matplotlib.figure import Figure

from rapp import plotting
from rapp.collision import clearance, collides, line_distance_mis, segment_circle_distance
from rapp.cspace import JointGrid, occupancy
from rapp.errors import RappError
from rapp.planner import plan as run_plan
from rapp.plotting import subplots
from rapp.trajectory import cubic, quintic

__all__ = [
    "arm_explorer",
    "collision_explorer",
    "planner_playground",
    "trajectory_explorer",
    "output_of",
    "sliders_of",
]

# Plain values, not widgets: a Layout made here would be one shared, mutable model
# created at import time.
_SLIDER_WIDTH = "420px"
_DESCRIPTION_WIDTH = "110px"


def _figure(w, h):
    fig = Figure(figsize=(w, h), layout="constrained")
    fig.patch.set_facecolor("white")
    return fig


def _png_output(fig, dpi=80):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, facecolor="white")
    w, h = fig.get_size_inches() * dpi
    return {
        "output_type": "display_data",
        "data": {
            "image/png": base64.b64encode(buf.getvalue()).decode("ascii"),
            "text/plain": f"<Figure size {w:.0f}x{h:.0f} with {len(fig.axes)} Axes>",
        },
        "metadata": {},
    }


def _live(controls, render, *, title=""):
    """Wire ``render(**values) -> (Figure, status_html)`` to the controls; draw once now."""
    out = widgets.Output()
    status = widgets.HTML()

    def update(change=None):
        values = {name: c.value for name, c in controls.items()}
        fig, text = render(**values)
        out.outputs = (_png_output(fig),)
        status.value = text

    for c in controls.values():
        c.observe(update, names="value")
    update()
    head = [widgets.HTML(f"<b>{html.escape(title)}</b>")] if title else []
    box = widgets.Box(list(controls.values()),
                      layout=widgets.Layout(display="flex", flex_flow="row wrap"))
    return widgets.VBox(head + [box, status, out])


def _on_grid(value, lo, hi, step):
    """``(value, lo, hi)`` moved onto the multiples of ``step`` inside ``[lo, hi]``.

    A browser slider snaps its value to ``min + k * step``; a default off that grid is
    snapped on first display and sends a second value change, whose redraw races the
    first (chapter 1's figure came back blank after Run All in 6 of 11 runs). On the
    grid, the browser has nothing to change.

    Examples
    --------
    >>> _on_grid(0.8, -np.pi, np.pi, 0.05)
    (0.8, -3.1, 3.1)
    """
    k_lo, k_hi = int(np.ceil(lo / step - 1e-9)), int(np.floor(hi / step + 1e-9))
    k = min(max(int(round(value / step)), k_lo), k_hi)
    digits = max(0, -int(np.floor(np.log10(step))) + 1)
    return round(k * step, digits), round(k_lo * step, digits), round(k_hi * step, digits)


def _slider(description, value, lo, hi, step=0.01, *, integer=False):
    cls = widgets.IntSlider if integer else widgets.FloatSlider
    if not integer:
        value, lo, hi = _on_grid(value, lo, hi, step)
    return cls(value=value, min=lo, max=hi, step=step, description=description,
               continuous_update=False, layout=widgets.Layout(width=_SLIDER_WIDTH),
               style={"description_width": _DESCRIPTION_WIDTH})


def _badge(ok, yes, no):
    color = plotting.COLORS["green"] if ok else plotting.COLORS["vermillion"]
    return f'<span style="color:{color};font-weight:bold">{yes if ok else no}</span>'


def output_of(widget):
    """The ``Output`` widget inside an explorer (depth-first).

    Examples
    --------
    >>> output_of(widgets.VBox([widgets.Output()])).outputs
    ()
    """
    if isinstance(widget, widgets.Output):
        return widget
    for child in getattr(widget, "children", ()):
        found = output_of(child)
        if found is not None:
            return found
    return None


def sliders_of(widget):
    """The value controls of an explorer, by description, in order.

    Examples
    --------
    >>> list(sliders_of(collision_explorer()))[:3]
    ['A x (m)', 'A y (m)', 'B x (m)']
    """
    found = {}
    if isinstance(widget, widgets.ValueWidget) and not isinstance(widget, widgets.HTML):
        found[widget.description] = widget
    for child in getattr(widget, "children", ()):
        found.update(sliders_of(child))
    return found


def arm_explorer(arm, obstacles=(), grid=None, *, q=None, cells=90):
    """A slider per joint; the arm in the workspace and, for 2 joints, its point in C-space.

    Parameters
    ----------
    arm : rapp.Arm
    obstacles : sequence of Circle / Polygon
    grid : rapp.JointGrid, optional
        The C-space grid (2-joint arms); ``JointGrid(arm, cells)`` when None.
        Its occupancy is computed once, here, not on every slider move.
    q : array_like, shape (n,), optional
        The default configuration (all zeros when None, clipped to limits).

    Returns
    -------
    ipywidgets.VBox
        The status line says ``collision`` or ``free`` with the clearance.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> w = arm_explorer(Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)], cells=16)
    >>> list(sliders_of(w)), "collision" in w.children[2].value
    (['θ1 (rad)', 'θ2 (rad)'], True)
    """

    obstacles = tuple(obstacles)
    q0 = np.clip(np.zeros(arm.n) if q is None else np.asarray(q, dtype=float), arm.lower,
                 arm.upper)
    occ = None
    if arm.n == 2:

        grid = JointGrid(arm, cells) if grid is None else grid
        occ = occupancy(arm, obstacles, grid)
    controls = {
        f"q{i}": _slider(f"θ{i + 1} (rad)", float(q0[i]), float(arm.lower[i]),
                         float(arm.upper[i]))
        for i in range(arm.n)
    }

    def render(**values):
        q = np.array([values[f"q{i}"] for i in range(arm.n)])
        fig = _figure(10.0 if occ is not None else 5.0, 5.0)
        axs = subplots(fig, 1, 2 if occ is not None else 1)
        ax_w = axs[-1] if occ is not None else axs
        if occ is not None:
            plotting.plot_cspace(occ, grid, axs[0], start=q)
            axs[0].get_legend().get_texts()[0].set_text("q")
        plotting.plot_workspace(arm, ax_w)
        plotting.plot_obstacles(obstacles, ax_w)
        plotting.plot_arm(arm, q, ax_w)
        hit = bool(collides(arm, q, obstacles)) if obstacles else False
        text = _badge(not hit, "free", "collision")
        if obstacles:
            text += f" &nbsp; clearance {float(clearance(arm, q, obstacles)):.3f} m"
        ee = arm.end_effector(q)
        text += f" &nbsp; end effector ({ee[0]:.3f}, {ee[1]:.3f}) m"
        ax_w.set_title("collision" if hit else "free", fontsize="medium",
                       color=plotting.COLORS["vermillion"] if hit else plotting.TEXT)
        return fig, text

    return _live(controls, render, title="Arm explorer")


def collision_explorer(a=(0.0, 0.0), b=(1.0, 0.0), center=(1.6, 0.1), radius=0.3, *,
                       extent=2.0):
    """Segment against disc: the clipped projection versus the MIS's infinite line.

    Sliders move the segment's ends, the obstacle's centre and its radius.
    The status compares ``segment_circle_distance`` (the true clearance) with
    ``line_distance_mis - r`` and flags a *false collision* when the MIS's
    formula reports a hit the segment does not make. The default view is
    such a case: the disc lies beyond the segment's end, on its line.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> w = collision_explorer()
    >>> "false collision" in w.children[2].value
    True
    """

    controls = {
        "ax": _slider("A x (m)", float(a[0]), -extent, extent),
        "ay": _slider("A y (m)", float(a[1]), -extent, extent),
        "bx": _slider("B x (m)", float(b[0]), -extent, extent),
        "by": _slider("B y (m)", float(b[1]), -extent, extent),
        "cx": _slider("centre x (m)", float(center[0]), -extent, extent),
        "cy": _slider("centre y (m)", float(center[1]), -extent, extent),
        "r": _slider("radius (m)", float(radius), 0.05, extent / 2),
    }

    def render(ax, ay, bx, by, cx, cy, r):
        A, B, C = (ax, ay), (bx, by), (cx, cy)
        seg = float(segment_circle_distance(A, B, C, r))
        line = float(line_distance_mis(A, B, C)) - r
        fig = _figure(5.5, 5.5)
        axes = subplots(fig)
        plotting.plot_segment_circle(A, B, C, r, axes)
        hit, mis_hit = seg <= 0, line <= 0
        false = mis_hit and not hit
        axes.set_title("FALSE COLLISION (MIS formula)" if false else
                       ("collision" if hit else "free"), fontsize="medium",
                       color=plotting.COLORS["vermillion"] if (false or hit) else plotting.TEXT)
        text = (f"segment clearance {seg:.3f} m: {_badge(not hit, 'free', 'collision')}"
                f" &nbsp;|&nbsp; MIS line clearance {line:.3f} m: "
                f"{_badge(not mis_hit, 'free', 'collision')}")
        if false:
            text += (" &nbsp; <b>disagree: a false collision</b> — the obstacle is near the"
                     " line's extension, not the segment")
        return fig, text

    return _live(controls, render, title="Segment–circle collision")


def _plan_settings(scenario, cells, weight, goal):
    planner = dataclasses.replace(scenario.planner, cells=(int(cells),) * scenario.arm.n,
                                  heuristic_weight=float(weight))
    key = "goal_xy" if scenario.goal_xy is not None else "goal_q"
    return dataclasses.replace(scenario, planner=planner, **{key: tuple(goal)})


def planner_playground(scenario):
    """Re-plan a scenario with other grid sizes, heuristic weights and goals.

    Sliders: cells per joint, heuristic weight, and the goal (x, y for a
    Cartesian goal, else one angle per joint). Each change runs
    :func:`rapp.plan` and draws :func:`rapp.plotting.plot_plan` with the cells A*
    expanded shaded, so a larger weight visibly expands fewer; a planning
    failure (no path, no IK solution) is shown as such with the scenario.
    The default view is the plan of ``scenario`` as given.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> from rapp import load_scenario
    >>> w = planner_playground(load_scenario("default"))
    >>> list(sliders_of(w)), "planned" in w.children[2].value
    (['cells / joint', 'heuristic w', 'goal x (m)', 'goal y (m)'], True)
    """

    arm = scenario.arm
    cells0 = int(np.max(scenario.planner.cells))
    controls = {
        "cells": _slider("cells / joint", cells0, 8, max(200, cells0), 1, integer=True),
        "weight": _slider("heuristic w", float(scenario.planner.heuristic_weight), 1.0,
                          max(5.0, float(scenario.planner.heuristic_weight)), 0.1),
    }
    if scenario.goal_xy is not None:
        r = arm.reach[1]
        controls["g0"] = _slider("goal x (m)", float(scenario.goal_xy[0]), -r, r)
        controls["g1"] = _slider("goal y (m)", float(scenario.goal_xy[1]), -r, r)
    else:
        for i in range(arm.n):
            controls[f"g{i}"] = _slider(f"goal θ{i + 1} (rad)", float(scenario.goal_q[i]),
                                        float(arm.lower[i]), float(arm.upper[i]))
    ngoal = len(controls) - 2

    def render(cells, weight, **goal):
        s = _plan_settings(scenario, cells, weight, [goal[f"g{i}"] for i in range(ngoal)])
        fig = _figure(10.5, 5.0)
        try:
            p = run_plan(s)
        except RappError as exc:
            ax = subplots(fig)
            plotting.plot_workspace(arm, ax)
            plotting.plot_obstacles(s.obstacles, ax)
            plotting.plot_arm(arm, np.asarray(s.start, dtype=float), ax, color=plotting.START)
            if s.goal_xy is not None:
                ax.plot(*s.goal_xy, "*", color=plotting.GOAL, ms=14)
            ax.set_title(f"{type(exc).__name__}: {exc}", fontsize="small",
                         color=plotting.COLORS["vermillion"])
            return fig, _badge(False, "", type(exc).__name__) + " " + html.escape(str(exc))
        closed = p.expanded if np.ndim(p.occupancy) == 2 else None
        plotting.plot_plan(p, s, fig=fig, expanded=closed)
        shown = [f"{k} {v:.4g}" for k, v in p.metrics.items()
                 if isinstance(v, (int, float, np.number)) and not isinstance(v, bool)
                 and not (closed is not None and k == "expansions")][:6]
        if closed is not None:
            shown.insert(0, f"<b>{int(closed.sum())} cells expanded</b> (blue)")
        return fig, _badge(True, "planned", "") + " &nbsp; " + ", ".join(shown)

    return _live(controls, render, title="Planner playground")


def trajectory_explorer(t0=0.0, tf=2.0, p0=0.0, pf=1.0, v0=0.0, vf=0.0, a0=0.0, af=0.0):
    """Cubic against quintic for the same boundary values.

    Sliders set the duration and the boundary position, velocity and
    acceleration. The cubic (``rapp.cubic``) meets positions and velocities
    only; the quintic (``rapp.quintic``) meets the accelerations too. The
    status shows the accelerations each actually has at the ends.

    Returns
    -------
    ipywidgets.VBox

    Examples
    --------
    >>> w = trajectory_explorer(a0=1.0)
    >>> "quintic 1.000, 0.000 (set: 1.000, 0.000)" in w.children[2].value
    True
    """

    controls = {
        "tf": _slider("tf (s)", float(tf), t0 + 0.2, t0 + 10.0, 0.1),
        "p0": _slider("p0 (rad)", float(p0), -np.pi, np.pi),
        "pf": _slider("pf (rad)", float(pf), -np.pi, np.pi),
        "v0": _slider("v0 (rad/s)", float(v0), -3.0, 3.0),
        "vf": _slider("vf (rad/s)", float(vf), -3.0, 3.0),
        "a0": _slider("a0 (rad/s²)", float(a0), -5.0, 5.0),
        "af": _slider("af (rad/s²)", float(af), -5.0, 5.0),
    }
    P = np.polynomial.polynomial

    def render(tf, p0, pf, v0, vf, a0, af):
        c3 = np.asarray(cubic(t0, tf, p0, pf, v0, vf), dtype=float)
        c5 = np.asarray(quintic(t0, tf, p0, pf, v0, vf, a0, af), dtype=float)
        fig = plotting.plot_polynomials({"cubic": c3, "quintic": c5}, t0, tf,
                                        fig=_figure(6.5, 6.0))
        ends = np.array([t0, tf])
        acc3 = P.polyval(ends, P.polyder(c3, 2))
        acc5 = P.polyval(ends, P.polyder(c5, 2))
        text = (f"end accelerations (rad/s²): cubic {acc3[0]:.3f}, {acc3[1]:.3f} (not chosen)"
                f" &nbsp;|&nbsp; quintic {acc5[0]:.3f}, {acc5[1]:.3f} (set: {a0:.3f}, {af:.3f})")
        return fig, text

    return _live(controls, render, title="Cubic vs quintic")
