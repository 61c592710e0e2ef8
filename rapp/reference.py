"""Reference implementations: slow, obviously correct, kept to check and time the fast ones.

Each function here computes what a function of the package computes, the plain way: the
previous, straightforward version that the faster one replaced. Tests compare the two on
random inputs (the reference is the oracle) and the benchmarks time them side by side
(``benchmarks/bench_core.py``, ``benchmarks/bench_cli.py``). Nothing in the pipeline calls
them; a new fast path keeps its predecessor here, documented, instead of as a private copy
next to it.

=====================  ==========================================================
reference              the fast function it checks
=====================  ==========================================================
:func:`occupancy`      :func:`rapp.cspace.occupancy` (every link against every
                       obstacle on every cell of its prefix grid)
:func:`certified_free` :func:`rapp.cspace.certified_free` (link clearances on
                       every prefix cell)
=====================  ==========================================================

Examples
--------
>>> from rapp import Arm, Circle, JointGrid
>>> import rapp.cspace
>>> arm, discs = Arm([1.0, 1.0]), [Circle((1.75, 0.75), 0.6)]
>>> grid = JointGrid(arm, 24)
>>> bool((occupancy(arm, discs, grid) == rapp.cspace.occupancy(arm, discs, grid)).all())
True
"""

from __future__ import annotations

import math

import numpy as np

from rapp.checks import positive_integer
from rapp.collision import check_obstacle, motion_bounds, segment_clearances
from rapp.cspace import check_grid, prefix_grid
from rapp.obstacles import Circle

__all__ = ["occupancy", "certified_free", "circle_hits", "polygon_hits"]


def circle_hits(P, cos_phi, sin_phi, L, center, r):
    """Closed-form hit of a link from ``P`` (prefix grid) at angle ``phi`` with a disc.

    With ``d = |c - P|`` and ``delta`` the angle between the link and ``c - P``:
    inside (``d <= r``) always hits; if the link reaches the tangent point
    (``L >= sqrt(d^2 - r^2)``) it hits iff ``delta <= asin(r / d)``; else it
    hits iff its tip is in the disc, ``cos delta >= (L^2 + d^2 - r^2) / (2 L d)``
    (never when ``L < d - r``). Since ``delta`` is in ``[0, pi]`` these are
    ``d cos delta >= T`` with ``T = sqrt(d^2 - r^2)`` or ``(L^2 + d^2 - r^2) / (2L)``,
    and ``d cos delta = (c - P) . u(phi)``: no trigonometry on the full grid.
    """
    v = np.asarray(center) - P
    d2 = v[..., 0] ** 2 + v[..., 1] ** 2
    t2 = d2 - r * r
    tangent = np.sqrt(np.maximum(t2, 0.0))
    # For a short link far from the disc the tip distance overflows; inf means "never hits".
    with np.errstate(over="ignore"):
        T = np.where(L >= tangent, tangent, (L * L + t2) / (2 * L))
    T = np.where(L < np.sqrt(d2) - r, np.inf, T)
    T = np.where(t2 <= 0, -np.inf, T)
    dot = v[..., 0, None] * cos_phi
    dot += v[..., 1, None] * sin_phi
    return dot >= T[..., None]


def polygon_hits(P, cos_phi, sin_phi, L, poly):
    """Separating-axis test of every link on the prefix grid against one convex polygon.

    The link runs from ``P`` (shape ``S + (2,)``) to ``P + L u(phi)``
    (``cos_phi``, ``sin_phi`` of shape ``S + (M,)``). Projections of ``P`` are
    computed once on the prefix grid; only the terms in ``phi`` span the full
    grid. Touching counts (separation needs a strict gap).
    """
    v = poly.array
    e = np.roll(v, -1, axis=0) - v
    normals = np.stack((e[:, 1], -e[:, 0]), axis=-1)
    proj = v @ normals.T
    pmin, pmax = proj.min(axis=0), proj.max(axis=0)
    sep = np.zeros(cos_phi.shape, dtype=bool)
    for k in range(len(v)):
        nx, ny = normals[k]
        sa = (P @ normals[k])[..., None]
        sb = sa + L * (cos_phi * nx + sin_phi * ny)
        sep |= (np.maximum(sa, sb) < pmin[k]) | (np.minimum(sa, sb) > pmax[k])
    # The link's own normal m = (-sin, cos): separated when every vertex is strictly on one side.
    above = np.ones(cos_phi.shape, dtype=bool)
    below = np.ones(cos_phi.shape, dtype=bool)
    for vx, vy in v:
        w = (vy - P[..., 1])[..., None] * cos_phi - (vx - P[..., 0])[..., None] * sin_phi
        above &= w > 0
        below &= w < 0
    return ~(sep | above | below)


def occupancy(arm, obstacles, grid) -> np.ndarray:
    """:func:`rapp.cspace.occupancy` the straightforward way: every link against every obstacle on
    every cell of its prefix grid, by closed-form hit tests (:func:`circle_hits`,
    :func:`polygon_hits`). The arguments are those of :func:`rapp.cspace.occupancy`.

    Examples
    --------
    >>> from rapp import Arm, Circle, Polygon, collides
    >>> from rapp.cspace import JointGrid, grid_q
    >>> arm, grid = Arm([1.0, 0.8]), JointGrid(Arm([1.0, 0.8]), 12)
    >>> scene = [Circle((1.2, 0.9), 0.4), Polygon.rectangle((-1.5, -0.6), 0.5, 0.4, 0.3)]
    >>> occ = occupancy(arm, scene, grid)
    >>> bool(occ.any()), bool((occ == collides(arm, grid_q(grid), scene)).all())
    (True, True)
    """
    check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    shape, n = grid.shape, arm.n
    occ = np.zeros(shape, dtype=bool)
    circles = [ob for ob in obstacles if isinstance(ob, Circle)]
    polys = [ob for ob in obstacles if not isinstance(ob, Circle)]
    axes = grid.axes
    for i in range(n):
        P, phi_prev = prefix_grid(grid, i)
        L = arm.link_lengths[i]
        hit = np.zeros(shape[: i + 1], dtype=bool)
        # cos/sin of phi_prev + theta by the addition formulas: outer products, no trig on the grid.
        cp, sp = np.cos(phi_prev)[..., None], np.sin(phi_prev)[..., None]
        ct, st = np.cos(axes[i]), np.sin(axes[i])
        cos_phi = cp * ct - sp * st
        sin_phi = sp * ct + cp * st
        for ob in circles:
            hit |= circle_hits(P, cos_phi, sin_phi, L, ob.center, ob.radius)
        for ob in polys:
            hit |= polygon_hits(P, cos_phi, sin_phi, L, ob)
        occ |= hit.reshape(hit.shape + (1,) * (n - i - 1))
    return occ


def certified_free(arm, obstacles, grid, *, chunk: int = 200_000) -> np.ndarray:
    """:func:`rapp.cspace.certified_free` the straightforward way: the clearance of each link,
    computed on every cell of its prefix grid, against half the largest motion of that link in
    one grid step (chunks of ``chunk`` configurations bound the memory).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> from rapp.cspace import JointGrid, certified_free as fast
    >>> arm, discs = Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)]
    >>> grid = JointGrid(arm, 24)
    >>> bool((certified_free(arm, discs, grid, chunk=100) == fast(arm, discs, grid)).all())
    True
    """
    check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    chunk = positive_integer(chunk, "chunk")
    n = arm.n
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)  # (n,) per link
    axes = grid.axes
    out = np.ones(grid.shape, bool)
    for j in range(n):
        # Link j depends on joints 0..j only: test it on that prefix grid and broadcast.
        prefix = grid.shape[: j + 1]
        size = math.prod(prefix)
        ok = np.empty(size, bool)
        for lo in range(0, size, chunk):  # chunks bound the memory, not a loop over cells
            idx = np.unravel_index(np.arange(lo, min(lo + chunk, size)), prefix)
            q = np.zeros((idx[0].size, n))
            for k in range(j + 1):
                q[:, k] = axes[k][idx[k]]
            pts = arm.joint_positions(q)
            d = segment_clearances(pts[:, j, :], pts[:, j + 1, :], obstacles)
            ok[lo:lo + chunk] = d > need[j]
        out &= ok.reshape(prefix + (1,) * (n - j - 1))
    return out
