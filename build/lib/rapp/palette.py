"""The colours of every rapp figure, in one place and free of matplotlib.

:mod:`rapp.plotting` draws every figure with these; they live here, free of
matplotlib, so that code which draws nothing can name a colour without paying
for matplotlib's import.

The palette is Okabe & Ito's, which stays distinguishable under the common
colour-vision deficiencies; text is dark grey on white, so that figures read
on paper and in a dark-mode notebook alike.

References
----------
Okabe & Ito (2008), Color Universal Design: the colour palette.

Examples
--------
>>> from rapp.palette import COLORS, OCCUPIED
>>> COLORS["vermillion"], OCCUPIED
('#D55E00', '#5a5a5a')
"""

from __future__ import annotations

from types import MappingProxyType

__all__ = ["COLORS", "TEXT", "ARM", "EFFECTOR", "START", "GOAL", "PATH", "OBSTACLE", "OCCUPIED",
           "JOINT_COLORS"]

# Okabe & Ito (2008), "Color Universal Design". Read-only, so no caller can recolour the book.
COLORS = MappingProxyType({
    "black": "#000000",
    "orange": "#E69F00",
    "sky": "#56B4E9",
    "green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "purple": "#CC79A7",
    "grey": "#999999",
})
TEXT = "#222222"
ARM = COLORS["blue"]
EFFECTOR = COLORS["vermillion"]
START = COLORS["green"]
GOAL = COLORS["vermillion"]
PATH = COLORS["orange"]
OBSTACLE = "#8c8c8c"
OCCUPIED = "#5a5a5a"
JOINT_COLORS = tuple(COLORS[k] for k in ("blue", "orange", "green", "purple", "sky", "vermillion",
                                          "black"))
