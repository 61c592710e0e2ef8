"""Explorers computed in the page: the C-space and A* recomputed in JavaScript as a reader drags.

The JavaScript (``rapp/live/*.js``, shipped with the package) implements the book's own
definitions: ``core.js`` ports the closed-form intervals of :func:`rapp.occupancy` and the A* of
:func:`rapp.astar` (GD1, the same tie-breaking), and ``tests/test_live.py`` holds it to them in
headless Chromium. The widgets are anywidget widgets: their ES module is stored in the widget
state, so the same explorer runs in JupyterLab and, with the vendored anywidget front end, in the
static HTML book, offline.

Examples
--------
>>> "rappLive" in core_js()
True
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

__all__ = ["core_js", "explorer_js", "scenario_dict", "cspace_explorer", "astar_explorer"]

HERE = Path(__file__).resolve().parent


@cache
def _read(name: str) -> str:
    return (HERE / name).read_text(encoding="utf-8")


def core_js() -> str:
    """The JavaScript of ``window.rappLive`` (occupancy, A*), as a classic script's text."""
    return _read("core.js")


def explorer_js() -> str:
    """The explorers' ES module: :func:`core_js` followed by ``explorer.js``."""
    return _read("core.js") + "\n" + _read("explorer.js")


def scenario_dict(scenario) -> dict:
    """The arm and obstacles of a scenario (a :class:`rapp.scenario.Scenario`, a scenario file's
    mapping, or a pair ``(arm, obstacles)``) in the scenario-file format the page reads."""
    from rapp.arm import Arm
    from rapp.obstacles import Circle
    from rapp.scenario import Scenario, load_scenario

    if isinstance(scenario, tuple) and len(scenario) == 2 and isinstance(scenario[0], Arm):
        arm, obstacles = scenario
    else:
        s = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
        arm, obstacles = s.arm, s.obstacles
    if arm.n != 2 or any(arm.limited):
        raise ValueError("scenario: the live explorers need a 2-link arm whose joints turn freely")
    obs = []
    for ob in obstacles:
        if isinstance(ob, Circle):
            obs.append({"type": "circle", "center": [float(v) for v in ob.center], "radius": float(ob.radius)})
        else:
            obs.append({"type": "polygon", "vertices": [[float(x), float(y)] for x, y in ob.vertices]})
    return {"arm": {"link_lengths": [float(v) for v in arm.link_lengths], "joint_limits": None},
            "obstacles": obs}


def _widget_class():
    """The anywidget class, built on first use (importing anywidget starts no front end)."""
    global _Explorer
    if _Explorer is None:
        import anywidget
        import traitlets as t

        class Explorer(anywidget.AnyWidget):
            """A live explorer; its state is what the reader left in the page (JupyterLab)."""

            _esm = t.Unicode(explorer_js()).tag(sync=True)
            scenario = t.Dict().tag(sync=True)
            cells = t.Int(90).tag(sync=True)
            q = t.List([0.0, 0.0]).tag(sync=True)
            search = t.Bool(False).tag(sync=True)
            source = t.Unicode("cspace").tag(sync=True)
            start = t.List([0, 0]).tag(sync=True)
            goal = t.List([0, 0]).tag(sync=True)
            weight = t.Float(1.0).tag(sync=True)
            walls = t.List([]).tag(sync=True)
            paint_cells = t.Int(24).tag(sync=True)

        _Explorer = Explorer
    return _Explorer


_Explorer = None


def cspace_explorer(scenario="default", *, cells=90, q=(0.0, 0.0)):
    """The C-space explorer of chapter 4: drag obstacles, the elbow, the tip or the C-space point.

    Parameters
    ----------
    scenario : Scenario, mapping, name or ``(arm, obstacles)``
        A 2-link arm whose joints turn freely, and its obstacles (discs and convex polygons).
    cells : int
        Cells per joint of the grid the page computes (the reader can change it, 24 to 180).
    q : pair of float
        The configuration shown first, radians.

    Examples
    --------
    >>> w = cspace_explorer(cells=60)
    >>> w.cells, len(w.scenario["obstacles"]), w.search
    (60, 3, False)
    """
    cells = int(cells)
    if not 24 <= cells <= 180:
        raise ValueError(f"cells must be between 24 and 180, got {cells}")
    return _widget_class()(scenario=scenario_dict(scenario), cells=cells, q=[float(v) for v in q])


def astar_explorer(scenario="default", *, cells=60, start=(0.0, 0.0), goal=(2.2, 0.5),
                   weight=1.0, source="cspace", walls=(), paint_cells=24, paint_start=None,
                   paint_goal=None):
    """The A* explorer of chapter 5: A* on the explorer's C-space grid, or on a 24 x 24 grid of walls.

    Parameters
    ----------
    scenario : as :func:`cspace_explorer`
    cells : int
        Cells per joint of the C-space grid.
    start, goal : pair of float
        Configurations (radians); the page snaps them to their grid cells as ``rapp.JointGrid.index``.
    weight : float
        The heuristic weight ``w >= 1`` the page starts with.
    source : {"cspace", "paint"}
        Which grid the search runs on first.
    walls : iterable of (i, j)
        Blocked cells of the paintable grid.
    paint_cells : int
        Cells per axis of the paintable grid (both axes wrap), 6 to 40.
    paint_start, paint_goal : pair of int, optional
        Start and goal cells when ``source="paint"`` (then ``start`` and ``goal`` are not used).

    Examples
    --------
    >>> w = astar_explorer(cells=60, start=(0.0, 0.0), goal=(3.1, 0.0))
    >>> w.start, w.goal, w.search
    ([30, 30], [0, 30], True)
    """
    from rapp.arm import Arm
    from rapp.cspace import JointGrid

    if source not in ("cspace", "paint"):
        raise ValueError(f"source must be 'cspace' or 'paint', got {source!r}")
    if not float(weight) >= 1.0:
        raise ValueError(f"weight must be >= 1, got {weight!r}")
    if not 6 <= int(paint_cells) <= 40:
        raise ValueError(f"paint_cells must be between 6 and 40, got {paint_cells}")
    sc = scenario_dict(scenario)
    grid = JointGrid(Arm(sc["arm"]["link_lengths"]), int(cells))
    s, g = (grid.index([float(v) for v in x]).tolist() for x in (start, goal))
    if source == "paint":
        m = int(paint_cells)
        s, g = ([int(v) for v in c] if c is not None else d
                for c, d in ((paint_start, [m // 6, m // 2]), (paint_goal, [5 * m // 6, m // 2])))
    return _widget_class()(scenario=sc, cells=int(cells), search=True, source=source, start=s, goal=g,
                           weight=float(weight), walls=[[int(i), int(j)] for i, j in walls],
                           paint_cells=int(paint_cells))
