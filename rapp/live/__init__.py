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

__all__ = ["core_js"]

HERE = Path(__file__).resolve().parent


@cache
def _read(name: str) -> str:
    return (HERE / name).read_text(encoding="utf-8")


def core_js() -> str:
    """The JavaScript of ``window.rappLive`` (occupancy, A*), as a classic script's text."""
    return _read("core.js")
