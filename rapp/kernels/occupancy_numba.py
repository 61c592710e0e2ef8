"""The compiled occupancy kernel: hit intervals computed and painted per prefix cell.

:func:`rapp.cspace.occupancy` works link by link on prefix grids: on the grid of joints
``0..i-1`` (one *row* per prefix cell) link ``i`` touches each obstacle for one interval
of its own joint angle, and the intervals are painted onto joint ``i``'s axis. The numpy
version (:func:`rapp.cspace.occupancy_numpy`) computes every interval of a link into arrays,
paints them into a difference array, sums it up and ORs the result, broadcast, into the
grid. Here each level (link) takes four steps, :func:`run`:

* :func:`_collect`, compiled, one parent cell's rows at a time: a row whose prefix already
  collides (an earlier link hits there) is filled with True and nothing is computed for
  it; any other row is cleared. Then, obstacle by obstacle, only the rows on the arc of
  base points that can reach it are visited (:func:`_arc`: the base points of a parent
  cell's rows lie on a circle about its point, and those within an obstacle's reach form
  one arc, taken wider by margins far above rounding); for each, the base point and angle
  are computed (by the operations of :func:`rapp.cspace.prefix_grid`), the exact test of
  reach is made (a polygon's by its bounding box as well), and the closed form of
  ``rapp.kernels.occupancy_numpy``'s ``_circle_hits`` or ``_polygon_hits`` is evaluated, operation by
  operation, up to its trigonometry (:func:`_circle_args`, :func:`_polygon_args`); the
  arguments of the ``atan2`` and ``atan`` it needs are appended to buffers;
* numpy: all of them at once, one vectorized ``np.arctan2`` and one ``np.arctan`` (the
  same numpy functions the numpy version calls, so the two agree to the bit; numpy's are
  vectorized and several times faster than the C library's, which compiled code calls);
* :func:`_found`, compiled: each interval's start and width from its angles;
* :func:`_paint`, compiled: each interval cut into cell ranges and set in its row (the
  very function the benchmark's floor times).

Level ``i`` writes the array of shape ``cells[:i + 1]`` once, and level ``i + 1`` reads it as
its rows' "already collides" flags, so the last level writes the result once and the
only other arrays are the shorter levels (``M**2`` bytes for a 3-link ``M**3`` grid), the
parent level's geometry (cached per grid), the obstacles' arrays (tolerances and reaches,
computed by compiled code too, :func:`_polygons` and :func:`_reaches`; the levels are
cached per grid and scene: :func:`levels`) and the buffers (at most :data:`BATCH`
intervals, kept between calls).

The grids agree cell for cell with the numpy version's (tested on random scenes); a
difference could only come from the one step done differently, the choice of a polygon's
extreme candidates by cross products instead of angles, which decides differently only
between directions equal to rounding, i.e. at a configuration touching an obstacle.

:func:`kernels` compiles the loops on first use (cached on disk, ``cache=True``) and
returns None when numba cannot be imported; :mod:`rapp.kernels.occupancy` then runs
:mod:`rapp.kernels.occupancy_numpy`. Importing this module does not import numba.

Examples
--------
>>> from rapp import Circle, Polygon
>>> circles, polys = pack([Circle((1.0, 0.0), 0.5), Polygon.rectangle((0, 1), 1, 1)])
>>> circles.tolist(), polys.offsets.tolist()
([[1.0, 0.0, 0.5]], [0, 4])
"""

from __future__ import annotations

import functools
import math
import threading
from collections import namedtuple

import numpy as np

from rapp.kernels.collision_numba import by_identity
from rapp.kernels.occupancy_numpy import prefix_step
from rapp.jit import jit, numba_available
from rapp.obstacles import Circle, Polygon

__all__ = ["pack", "levels", "run", "paint", "one_per_cell", "kernels", "Kernels", "Batch",
           "Polygons", "Level", "BATCH", "NONE", "TANGENT", "TIP", "IN_DISC", "POLYGON",
           "IN_POLYGON"]

#: The compiled functions (see :func:`kernels`): :func:`_collect`, :func:`_found`,
#: :func:`_paint`, :func:`_rows`, and the scene's set-up, :func:`_polygons` and
#: :func:`_reaches`.
Kernels = namedtuple("Kernels", "collect found paint rows polygons reaches")

#: Convex polygons as arrays: polygon ``p`` owns rows ``offsets[p]:offsets[p + 1]`` of
#: ``v`` (vertices, counter-clockwise), ``e`` (edge vectors ``v[j+1] - v[j]``), ``ee``
#: (their squared lengths) and ``norm`` (their lengths); ``centre``, ``radius`` (a disc
#: holding the polygon), ``extent`` (its largest ``|coordinate|``) and ``box`` (its bounding
#: box, ``xmin, xmax, ymin, ymax``) are one per polygon.
Polygons = namedtuple("Polygons", "v e ee norm offsets centre radius extent box")


def pack(obstacles) -> tuple:
    """Obstacles as the kernel's arrays: ``circles`` ``(c, 3)`` (centre, radius), :data:`Polygons`.

    The derived quantities are computed by numpy exactly as
    :func:`rapp.cspace.occupancy_numpy` computes them, so both versions start from the same
    numbers. ``obstacles`` must already be checked (Circle or Polygon). The arrays are
    cached for the last few obstacle lists (by the identity of their obstacles, which are
    immutable), so a grid recomputed for the same scene does not pack it again.

    Examples
    --------
    >>> from rapp import Polygon
    >>> _, p = pack([Polygon.rectangle((0, 0), 2, 1)])
    >>> p.ee.tolist(), p.centre.tolist(), p.extent.tolist()
    ([4.0, 1.0, 4.0, 1.0], [[1.0, 0.5]], [2.0])
    """
    return by_identity(_PACKED, obstacles, _pack)


def _pack(obstacles) -> tuple:
    """:func:`pack`, uncached: the obstacles gathered into two arrays, the rest by
    :func:`_polygons` (compiled when numba is, one call for every polygon)."""
    circles = [(ob.center[0], ob.center[1], ob.radius)
               for ob in obstacles if isinstance(ob, Circle)]
    verts = [ob.array for ob in obstacles if isinstance(ob, Polygon)]
    off = [0]
    for v in verts:
        off.append(off[-1] + len(v))
    v = np.concatenate(verts) if verts else np.zeros((0, 2))
    offsets = np.array(off, dtype=np.int64)
    k = kernels()
    e, ee, norm, centre, radius, extent, box = (k.polygons if k else _polygons)(v, offsets)
    return (np.array(circles, dtype=float).reshape(-1, 3),
            Polygons(v, e, ee, norm, offsets, centre, radius, extent, box))


def _polygons(v, offsets):
    """Each edge's vector ``e``, squared length ``ee`` and length ``norm``, and each polygon's
    ``centre``, ``radius``, ``extent`` and ``box`` (see :data:`Polygons`), polygon ``p`` being
    rows ``offsets[p]:offsets[p + 1]`` of ``v``.

    By the operations of ``rapp.kernels.occupancy_numpy``'s ``_polygon_hits``, one element at a time, so
    the numbers are numpy's to the bit: ``e = np.roll(v, -1, axis=0) - v``, ``ee`` its
    ``einsum("ij,ij->i", e, e)`` (``ex * ex + ey * ey``), ``norm = sqrt(ee)``, the centre
    ``v.mean(axis=0)`` (a sum row after row, divided by the count) and the radius
    ``sqrt(((v - c) ** 2).sum(axis=1).max())``.
    """
    nv = v.shape[0]
    npoly = offsets.shape[0] - 1
    e = np.empty((nv, 2))
    ee = np.empty(nv)
    norm = np.empty(nv)
    centre = np.empty((npoly, 2))
    radius = np.empty(npoly)
    extent = np.empty(npoly)
    box = np.empty((npoly, 4))
    for p in range(npoly):
        s0 = offsets[p]
        s1 = offsets[p + 1]
        sx = v[s0, 0]
        sy = v[s0, 1]
        ext = max(abs(v[s0, 0]), abs(v[s0, 1]))
        lox = hix = v[s0, 0]
        loy = hiy = v[s0, 1]
        for j in range(s0, s1):
            nxt = j + 1 if j + 1 < s1 else s0
            ex = v[nxt, 0] - v[j, 0]
            ey = v[nxt, 1] - v[j, 1]
            e[j, 0] = ex
            e[j, 1] = ey
            ee[j] = ex * ex + ey * ey
            norm[j] = math.sqrt(ee[j])
            if j > s0:
                sx += v[j, 0]
                sy += v[j, 1]
                ext = max(ext, abs(v[j, 0]), abs(v[j, 1]))
                lox = min(lox, v[j, 0])
                hix = max(hix, v[j, 0])
                loy = min(loy, v[j, 1])
                hiy = max(hiy, v[j, 1])
        cx = sx / (s1 - s0)
        cy = sy / (s1 - s0)
        far = 0.0
        for j in range(s0, s1):
            dx = v[j, 0] - cx
            dy = v[j, 1] - cy
            far = max(far, dx * dx + dy * dy)
        centre[p, 0] = cx
        centre[p, 1] = cy
        radius[p] = math.sqrt(far)
        extent[p] = ext
        box[p, 0] = lox
        box[p, 1] = hix
        box[p, 2] = loy
        box[p, 3] = hiy
    return e, ee, norm, centre, radius, extent, box


_PACKED: dict = {}


#: The geometry of one level (link ``i`` on the grid of joints ``0..i-1``): the rows (the
#: parent level's prefix cells ``Pp``, ``phip``, ``cp``, ``sp`` times joint ``i - 1``'s cells
#: ``axp``, ``cap``, ``sap``, ``stepp``, ``periodsp``, link ``Lp``), the link ``L`` and its
#: obstacles (:func:`pack`; ``slack`` and ``etol`` per polygon edge and ``tol`` per polygon
#: are ``rapp.kernels.occupancy_numpy``'s ``_polygon_hits`` tolerances: ``tol / |edge|``, ``-tol * |edge|``,
#: ``tol``; ``box``, each polygon's bounding box ``xmin, xmax, ymin, ymax``), each
#: obstacle's centre ``ox``, ``oy`` and reach ``rho`` (beyond which a base point cannot
#: touch it), and joint ``i``'s axis ``ax`` (``step``, and the number of ``2 pi`` pieces an
#: interval is cut into, ``periods``).
Level = namedtuple("Level", "Pp phip cp sp axp cap sap stepp periodsp Lp L circles v e ee "
                            "offsets slack etol tol box ox oy rho ax step periods")

#: The buffers of one batch of intervals (:func:`_collect`): each interval's row ``rowof``,
#: ``meta`` (its kind, where its ``atan2`` and ``atan`` arguments start), prefix angle ``phis``;
#: the ``atan2`` arguments ``Y``, ``X`` and the ``atan`` arguments ``Z``.
Batch = namedtuple("Batch", "rowof meta phis Y X Z")


def levels(grid, per_link) -> list:
    """The :data:`Level` of every link of ``grid.arm``, link ``i`` against ``per_link[i]``.

    Each level's rows are its parent's prefix cells times joint ``i - 1``'s cells;
    the parent's geometry is built as :func:`rapp.cspace.prefix_grid` builds it
    (:func:`rapp.cspace.prefix_step`), on the grid of joints ``0..i-2``: ``M**(i-1)``
    cells, the last level's own ``M**i`` are never kept. The levels depend only on the
    grid and the obstacles (all immutable): they are cached for the last few of them, so
    a grid recomputed for the same scene starts at once.

    Examples
    --------
    >>> from rapp import Arm, Circle, JointGrid
    >>> lv = levels(JointGrid(Arm([1.0, 0.5]), 8), [[Circle((1.0, 1.0), 0.2)]] * 2)
    >>> [(x.Pp.shape[0] * x.axp.size, x.ax.size) for x in lv]   # rows x cells per level
    [(1, 8), (8, 8)]
    """
    per_link = tuple(tuple(obs) for obs in per_link)
    key = (grid, tuple(tuple(map(id, obs)) for obs in per_link))
    # Grids (their arm and cells) compare by value, obstacles by identity: both immutable.
    # A few entries: a fine grid's parent geometry takes megabytes.
    hit = _LEVELS.get(key)
    if hit is None:
        if len(_LEVELS) >= 8:
            _LEVELS.clear()
        # The entry holds the obstacles, so no other object can take one of their ids.
        hit = _LEVELS[key] = (per_link, _levels(grid, per_link))
    return hit[1]


_LEVELS: dict = {}


def _levels(grid, per_link) -> list:
    """:func:`levels`, uncached (but for the grid's part, :func:`_rows_geometry`, and the
    packed obstacles, :func:`pack`). The levels sharing a list of obstacles (all of them,
    for :func:`rapp.cspace.occupancy`) get their obstacle arrays from one call of
    :func:`_reaches`."""
    k = kernels()
    reaches = k.reaches if k else _reaches
    geometry = _rows_geometry(grid)
    groups: dict = {}
    for i, obs in enumerate(per_link):
        groups.setdefault(tuple(map(id, obs)), []).append(i)
    out = [None] * len(geometry)
    for which in groups.values():
        circles, polys = pack(per_link[which[0]])
        low = float(polys.extent.min()) if polys.extent.size else math.inf
        tol, slack, etol, ox, oy, rho = reaches(
            circles, polys.centre, polys.radius, polys.extent, polys.norm, polys.offsets,
            np.array([geometry[i][7] for i in which]),
            np.array([_pmax(low, grid, i, geometry[i]) for i in which]))
        for row, i in enumerate(which):
            parent, axp, cap, sap, stepp, periodsp, Lp, L, ax, step, periods, _ = geometry[i]
            out[i] = Level(*parent, axp, cap, sap, stepp, periodsp, Lp, L, circles, polys.v,
                           polys.e, polys.ee, polys.offsets, slack[row], etol[row], tol[row],
                           polys.box, ox, oy, rho[row], ax, step, periods)
    return out


def _rows_geometry(grid) -> list:
    """The part of each :data:`Level` that depends on the grid alone: ``parent`` (``Pp``,
    ``phip``, ``cp``, ``sp``, flat), ``axp, cap, sap, stepp, periodsp, Lp, L, ax, step,
    periods``, and a bound on the base points' coordinates (:func:`_pmax`); cached for the
    last few grids (a new scene on the same grid reuses it)."""
    hit = _GRIDS.get(grid)
    if hit is not None:
        return hit
    arm, axes, steps = grid.arm, grid.axes, grid.step
    trig = [(np.cos(ax), np.sin(ax)) for ax in axes]
    # The prefix grid of joints 0..i-2 (level i's parent), starting from the base alone.
    base = pre = (np.zeros(2), np.zeros(()), np.ones(()), np.zeros(()))
    out = []
    for i in range(arm.n):
        if i == 0:
            # Level 0's parent: the base, on a one-cell axis at angle 0 with no link.
            parent, axp, cap, sap, Lp = base, np.zeros(1), np.ones(1), np.zeros(1), 0.0
            stepp = 2 * np.pi
        else:
            if i >= 2:
                pre = prefix_step(*pre, axes[i - 2], *trig[i - 2], arm.link_lengths[i - 2])
            parent, axp, (cap, sap), Lp = pre, axes[i - 1], trig[i - 1], arm.link_lengths[i - 1]
            stepp = steps[i - 1]
        P, phi, c, s = parent
        out.append(((np.ascontiguousarray(P.reshape(-1, 2)), phi.reshape(-1), c.reshape(-1),
                     s.reshape(-1)), axp, cap, sap, float(stepp), _periods(axp), float(Lp),
                    float(arm.link_lengths[i]), axes[i], float(steps[i]), _periods(axes[i]),
                    float(sum(arm.link_lengths[:i])) * (1 + 1e-9)))
    if len(_GRIDS) >= 8:
        _GRIDS.clear()
    _GRIDS[grid] = out
    return out


_GRIDS: dict = {}


def _periods(ax) -> int:
    """How many ``2 pi`` pieces an interval is cut into on the axis ``ax`` (:func:`_paint_one`);
    beyond one per cell the painter tests each cell instead, so the count is capped far
    above any axis's cells (it must fit an int64)."""
    return min(int((float(ax[-1]) - float(ax[0])) // (2 * np.pi)) + 2, 1 << 40)


def _pmax(low, grid, i, geometry) -> float:
    """The largest coordinate of level ``i``'s base points where it may decide a polygon's
    tolerance (see :func:`_reaches`), else 0; ``low`` is the smallest of the polygons'
    largest coordinates (``inf`` without polygons), ``geometry`` the level's
    :func:`_rows_geometry`.

    The tolerance is ``1e-12`` of the largest of 1, ``L``, the polygon's coordinates and
    the base points'; the last are below the sum of the links before ``i`` (up to
    rounding), so they are computed, by the operations of :func:`rapp.cspace.prefix_grid`,
    once per grid, only when some polygon's own scale may be smaller."""
    parent, axp, cap, sap, _, _, Lp, L, _, _, _, bound = geometry
    if max(low, 1.0, L) >= bound:
        return 0.0
    pmax = _PMAX.get((grid, i))
    if pmax is None:
        pmax = float(np.abs(prefix_step(*parent, axp, cap, sap, Lp)[0]).max(initial=0.0))
        if len(_PMAX) >= 64:
            _PMAX.clear()
        _PMAX[(grid, i)] = pmax
    return pmax


def _reaches(circles, centre, radius, extent, norm, offsets, Ls, pmaxes):
    """The obstacle arrays of the levels with links ``Ls``, one row per level: ``rapp.kernels.occupancy_numpy``'s
    ``_polygon_hits`` tolerances, ``tol = 1e-12 * max(1, L, extent, pmax)`` per polygon
    (``pmaxes``: :func:`_pmax`), ``slack = tol / norm`` and ``etol = -tol * norm`` per edge
    (numpy's operations, one element at a time); each obstacle's centre ``ox``, ``oy``
    (one row for all) and reach ``rho``, beyond which a base point cannot touch it (a
    disc's ``L + r``, a polygon's bounding disc's grown by twice its tolerance), circles
    first."""
    nc = circles.shape[0]
    npoly = offsets.shape[0] - 1
    nl = Ls.shape[0]
    tol = np.empty((nl, npoly))
    slack = np.empty((nl, norm.shape[0]))
    etol = np.empty((nl, norm.shape[0]))
    ox = np.empty(nc + npoly)
    oy = np.empty(nc + npoly)
    rho = np.empty((nl, nc + npoly))
    for c in range(nc):
        ox[c] = circles[c, 0]
        oy[c] = circles[c, 1]
    for p in range(npoly):
        ox[nc + p] = centre[p, 0]
        oy[nc + p] = centre[p, 1]
    for i in range(nl):
        L = Ls[i]
        own = max(1.0, L)
        for c in range(nc):
            rho[i, c] = L + circles[c, 2]
        for p in range(npoly):
            t = 1e-12 * max(max(extent[p], own), pmaxes[i])
            tol[i, p] = t
            for j in range(offsets[p], offsets[p + 1]):
                slack[i, j] = t / norm[j]
                etol[i, j] = -t * norm[j]
            rho[i, nc + p] = L + radius[p] + 2 * t
    return tol, slack, etol, ox, oy, rho


_PMAX: dict = {}


#: Kinds of a collected interval (:func:`_collect`), and how many ``atan2`` each needs.
NONE, TANGENT, TIP, IN_DISC, POLYGON, IN_POLYGON = 0, 1, 2, 3, 4, 5

#: Intervals collected per batch (:func:`run`).
BATCH = 1 << 14


def _buffers(size):
    """The batch buffers of :func:`_collect`: rows, kinds and where their arguments are
    ``(size, 3)``, angles of the
    rows' prefix, the ``atan2`` arguments (up to three per interval), the ``atan`` ones
    (one per interval at most), and the outputs of both."""
    return [np.empty(size, dtype=np.int64), np.empty((size, 3), dtype=np.int64), np.empty(size),
            np.empty(3 * size),
            np.empty(3 * size), np.empty(size), np.empty(3 * size), np.empty(size),
            np.empty(size), np.empty(size)]


def run(k, lv, *, keep=False):
    """The occupancy by the compiled :data:`Kernels` ``k`` over the levels ``lv`` (:func:`levels`),
    flat over the last level's rows (reshape it to ``grid.shape``).

    Per level, in batches of at most :data:`BATCH` intervals: :func:`_collect` clears or
    fills every row and gathers the arguments of each interval's ``atan2`` and ``atan``;
    numpy computes them, in one vectorized call each (the functions
    :func:`rapp.cspace.occupancy_numpy` calls, so that both versions agree to the bit);
    :func:`_found` turns them into intervals and :func:`_paint` paints them. With
    ``keep=True`` it returns also, per level, the intervals it painted
    ``(rows, starts, widths)``, in the order of the rows (for :func:`paint`).

    Examples
    --------
    >>> from rapp import Arm, Circle, JointGrid
    >>> k, grid = kernels(), JointGrid(Arm([1.0, 0.5]), 8)
    >>> lv = levels(grid, [[Circle((1.0, 1.0), 0.2)]] * 2)
    >>> k is None or bool((paint(k, lv, run(k, lv, keep=True)[1]) == run(k, lv)).all())
    True
    """
    nobs = max([x.ox.size for x in lv] + [1])
    most = max([x.Pp.shape[0] * x.axp.size for x in lv] + [1]) * nobs
    # The buffers hold a batch (at least one row's intervals), or every interval of the
    # largest level if fewer. They are kept for the next call (fresh pages cost more to
    # touch than the kernel spends on them), unless another thread is using them.
    size = max(min(BATCH, most), nobs)
    if not _BUFFERS_LOCK.acquire(blocking=False):
        return _run(k, lv, keep, _buffers(size), size)
    try:
        if _BUFFERS[0].shape[0] < size:
            _BUFFERS[:] = _buffers(size)
        return _run(k, lv, keep, _BUFFERS, size)
    finally:
        _BUFFERS_LOCK.release()


_BUFFERS: list = [np.empty(0)]
_BUFFERS_LOCK = threading.Lock()


def _run(k, lv, keep, buffers, size):
    """:func:`run` with the batch buffers given, ``size`` intervals a batch."""
    rowof, meta, phis, Y, X, Z, A, AZ, starts, widths = buffers
    blocked = np.zeros(1, dtype=bool)
    kept = []
    batch = Batch(rowof, meta, phis, Y, X, Z)
    for x in lv:
        rows = x.Pp.shape[0] * x.axp.size
        out = np.empty((rows, x.ax.size), dtype=bool)
        r, parts = 0, []
        while r < rows:
            r, n, m, mz = k.collect(r, blocked, x, out, batch, size)
            if n == 0:
                continue
            np.arctan2(Y[:m], X[:m], out=A[:m])
            if mz:
                np.arctan(Z[:mz], out=AZ[:mz])
            found = (rowof[:n], starts[:n], widths[:n])
            k.found(n, meta, phis, A, AZ, found[1], found[2])
            k.paint(blocked, *found, x.ax, x.step, x.periods, out)
            if keep:
                parts.append(tuple(f.copy() for f in found))
        if keep:
            whole = [np.concatenate(p) if p else np.zeros(0, t) for p, t in
                     zip(zip(*parts) if parts else ((), (), ()), (np.int64, float, float))]
            order = np.argsort(whole[0], kind="stable")   # collected obstacle by obstacle
            kept.append(tuple(w[order] for w in whole))
        blocked = out.reshape(-1)
    return (blocked, kept) if keep else blocked


def paint(k, lv, given):
    """The painting of :func:`run` alone, given the intervals of every level as
    ``(rows, starts, widths)`` (those of ``run(k, lv, keep=True)[1]``, or one per prefix cell
    and obstacle, ``width < 0`` where it does not hit): every row cleared, or filled where
    an earlier level collides, and the intervals of the other rows painted. (The floor of
    ``benchmarks/bench_occupancy.py``.)"""
    blocked = np.zeros(1, dtype=bool)
    for x, found in zip(lv, given):
        out = np.empty((x.Pp.shape[0] * x.axp.size, x.ax.size), dtype=bool)
        k.rows(blocked, out)
        k.paint(blocked, *found, x.ax, x.step, x.periods, out)
        blocked = out.reshape(-1)
    return blocked


def one_per_cell(lv, kept) -> list:
    """The painted intervals ``kept`` of every level (``run(k, lv, keep=True)[1]``) as one per
    prefix cell and obstacle, in the order of the rows, ``width = -1`` where there is none
    (the link misses the obstacle, or the row was full and nothing was computed): the
    benchmark floor's input, which :func:`paint` accepts as well.

    Examples
    --------
    >>> from rapp import Arm, Circle, JointGrid
    >>> k, grid = kernels(), JointGrid(Arm([1.0, 0.5]), 8)
    >>> lv = levels(grid, [[Circle((1.0, 1.0), 0.2)]] * 2)
    >>> occ, kept = run(k, lv, keep=True) if k else (None, None)
    >>> k is None or bool((paint(k, lv, one_per_cell(lv, kept)) == occ).all())
    True
    """
    out = []
    for x, (rows, starts, widths) in zip(lv, kept):
        nobs = x.ox.size
        total = x.Pp.shape[0] * x.axp.size * nobs
        # The rows come in order: an interval's slot is its rank among its row's.
        slot = rows * nobs + (np.arange(rows.size) - np.searchsorted(rows, rows))
        s, w = np.zeros(total), np.full(total, -1.0)
        s[slot], w[slot] = starts, widths
        out.append((np.repeat(np.arange(total // nobs), nobs), s, w))
    return out


# ---------------------------------------------------------------- the loops, compiled by kernels()

def _mod(a, b):
    """``numpy.mod(a, b)``: Python's float remainder, which numpy's follows step by step
    (``fmod``, then ``+ b`` when the signs differ, ``+0.0`` for a zero)."""
    return a % b


def _circle_args(px, py, L, cx, cy, r):
    """``rapp.kernels.occupancy_numpy``'s ``_circle_hits`` for one row, up to its trigonometry:
    ``kind, ay, ax, by, bx``, the interval being ``atan2(ay, ax) -+ h`` with
    ``h = atan2(by, bx)`` (TANGENT), ``2 atan(by)`` (TIP) or ``2 pi`` (IN_DISC)."""
    vx = cx - px
    vy = cy - py
    d2 = vx * vx + vy * vy
    d = math.sqrt(d2)
    if L < d - r:
        return NONE, 0.0, 1.0, 0.0, 1.0
    if d2 <= r * r:
        return IN_DISC, vy, vx, 0.0, 1.0
    t = math.sqrt(max((d - r) * (d + r), 0.0))
    if L >= t:
        return TANGENT, vy, vx, r, t
    # d > r here, so d + L - r > 0: no guard against a zero denominator is needed.
    z = math.sqrt(max(L + r - d, 0.0) * max(d + r - L, 0.0) / ((d + L + r) * (d + L - r)))
    return TIP, vy, vx, z, 1.0


def _polygon_args(px, py, L, v, e, ee, slack, etol, s0, s1, tol):
    """``rapp.kernels.occupancy_numpy``'s ``_polygon_hits`` for one row and polygon rows ``s0:s1``, up to its
    trigonometry: ``kind, ay, ax, by, bx, cy, cx``, the interval running from
    ``atan2(ay, ax) + atan2(by, bx)`` to ``atan2(ay, ax) + atan2(cy, cx)``. ``slack`` and
    ``etol`` are numpy's ``tol / sqrt(ee)`` and ``-tol * sqrt(ee)`` per edge.

    When the base point is in the polygon every direction hits (IN_POLYGON). Otherwise
    the candidates are numpy's (vertices within reach, each edge's crossings with the
    circle of radius ``L``: its "first" and "second root"), computed by the same
    operations, one pass over the edges; the reference direction ``(ax, ay)`` is the
    first valid one in numpy's order (vertices, then first roots, then second roots).
    They all lie within an arc narrower than ``pi`` (the polygon, to rounding, is beyond
    a line missing the base point), so the sign of a cross product orders two of them:
    the two extreme candidates are found that way, and only their angles are computed
    (by numpy, from these arguments), instead of one per candidate.
    """
    inside = True
    n_seen = 0
    lox = loy = hix = hiy = 0.0
    # The first vertex, first root and second root found; which of them came first in
    # numpy's order (0: a vertex, 1: a first root, 2: a second root, 3: none yet).
    vx = vy = r1x = r1y = r2x = r2y = 0.0
    first = 3
    reach2 = (L + tol) ** 2
    for j in range(s0, s1):
        wx = v[j, 0] - px
        wy = v[j, 1] - py
        if not (e[j, 1] * wx - e[j, 0] * wy >= etol[j]):
            inside = False
        w2 = wx * wx + wy * wy
        if w2 <= reach2:
            if first > 0:
                first = 0
                vx = wx
                vy = wy
            n_seen, lox, loy, hix, hiy = _extremes(n_seen, wx, wy, lox, loy, hix, hiy)
        b = wx * e[j, 0] + wy * e[j, 1]
        disc = b * b - ee[j] * (w2 - L * L)
        if not disc >= 0:
            continue
        root = math.sqrt(disc)
        for stage in range(1, 3):
            s = (-b + (-1.0 if stage == 1 else 1.0) * root) / ee[j]
            if not (s >= -slack[j] and s <= 1 + slack[j]):
                continue
            s = min(max(s, 0.0), 1.0)
            x = wx + s * e[j, 0]
            y = wy + s * e[j, 1]
            if stage == 1 and first > 1:
                first = 1
                r1x = x
                r1y = y
            elif stage == 2 and first > 2:
                first = 2
                r2x = x
                r2y = y
            n_seen, lox, loy, hix, hiy = _extremes(n_seen, x, y, lox, loy, hix, hiy)
    if inside:
        return IN_POLYGON, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0
    if n_seen == 0:
        return NONE, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0
    rx, ry = (vx, vy) if first == 0 else ((r1x, r1y) if first == 1 else (r2x, r2y))
    return (POLYGON, ry, rx, rx * loy - ry * lox, rx * lox + ry * loy,
            rx * hiy - ry * hix, rx * hix + ry * hiy)


def _extremes(n_seen, x, y, lox, loy, hix, hiy):
    """The most clockwise and counter-clockwise of the directions seen so far and ``(x, y)``
    (all within an arc narrower than ``pi``): ``n_seen + 1, lox, loy, hix, hiy``."""
    if n_seen == 0:
        return 1, x, y, x, y
    if x * loy - y * lox > 0.0:      # clockwise of the lowest so far
        return n_seen + 1, x, y, hix, hiy
    if hix * y - hiy * x > 0.0:      # counter-clockwise of the highest so far
        return n_seen + 1, lox, loy, x, y
    return n_seen + 1, lox, loy, hix, hiy


def _collect(r0, blocked, lv, out, batch, cap_n):
    """Rows ``r0, r0 + 1, ...`` of one level ``lv`` (a :data:`Level`): each row of ``out``
    filled (an earlier link already collides at that prefix cell, ``blocked[r]``) or cleared,
    and each of its intervals appended to ``batch`` (a :data:`Batch`): its row to ``rowof``,
    its kind to ``meta``, its prefix angle to ``phis``, the arguments of its ``atan2`` (those
    of :func:`_circle_args` / :func:`_polygon_args`: one for IN_DISC and TIP, two for
    TANGENT, three for POLYGON, none for IN_POLYGON) to ``Y``, ``X`` and that of its ``atan``
    (TIP) to ``Z``.

    The rows go by parent cell, in runs that fit ``cap_n`` intervals (``nobs`` per row at
    most); it stops before a run that might not fit and returns ``(next row, intervals,
    atan2 arguments, atan arguments)``. Within a run, obstacle after obstacle, only the
    rows that may reach it are visited (:func:`_arc`); for each of them the row's base
    point and angle are computed by the operations of ``rapp.cspace.prefix_grid`` and
    the exact test of reach comes first. So the intervals of a run come obstacle by
    obstacle, not row by row.
    """
    nobs = lv.ox.shape[0]
    axp = lv.axp
    mp = axp.shape[0]
    n = m = mz = 0
    # _arc cuts at most one span per 2 pi piece, and takes every row past one piece per cell.
    spans = np.empty((max(min(lv.periodsp, mp), 1), 2), dtype=np.int64)
    turn = abs(axp[0]) + abs(axp[mp - 1])
    rp = r0 // mp
    j0 = r0 - rp * mp
    while rp < lv.Pp.shape[0]:
        room = (cap_n - n) // nobs
        if room == 0:
            return rp * mp + j0, n, m, mz
        j1 = min(mp, j0 + room)
        base = rp * mp
        for j in range(j0, j1):
            out[base + j, :] = blocked[base + j]
        for k in range(nobs):
            ns = _arc(k, rp, lv, j0, j1, spans, turn)
            if ns != 0:
                n, m, mz = _collect_obstacle(k, rp, ns, spans, blocked, lv, batch, n, m, mz)
        if j1 < mp:
            j0 = j1
        else:
            rp += 1
            j0 = 0
    return lv.Pp.shape[0] * mp, n, m, mz


def _collect_obstacle(k, rp, ns, spans, blocked, lv, batch, n, m, mz):
    """:func:`_collect`'s work for obstacle ``k`` on the rows ``spans[:ns]`` of parent cell
    ``rp``: the intervals of the rows that reach it appended to ``batch`` after the ``n``
    entries, ``m`` ``atan2`` and ``mz`` ``atan`` arguments already there; returns the new
    counts."""
    # Read once here: the compiler cannot tell that the outputs written in the loops
    # below do not alias these arrays, so it would load them again on every row.
    Px = lv.Pp[rp, 0]
    Py = lv.Pp[rp, 1]
    cpr = lv.cp[rp]
    spr = lv.sp[rp]
    phr = lv.phip[rp]
    Lp, L, cap, sap, axp = lv.Lp, lv.L, lv.cap, lv.sap, lv.axp
    v, e, ee, slack, etol = lv.v, lv.e, lv.ee, lv.slack, lv.etol
    rowof, meta, phis, Y, X, Z = batch
    base = rp * axp.shape[0]
    okx = lv.ox[k]
    oky = lv.oy[k]
    rk2 = lv.rho[k] * lv.rho[k] * (1.0 + 1e-9)
    nc = lv.circles.shape[0]
    circle = k < nc
    if circle:
        ccx = lv.circles[k, 0]
        ccy = lv.circles[k, 1]
        cr = lv.circles[k, 2]
        s0 = s1 = 0
        bx0 = bx1 = by0 = by1 = tp = lim2 = 0.0
    else:
        ccx = ccy = cr = 0.0
        p = k - nc
        s0 = lv.offsets[p]
        s1 = lv.offsets[p + 1]
        bx0 = lv.box[p, 0]
        bx1 = lv.box[p, 1]
        by0 = lv.box[p, 2]
        by1 = lv.box[p, 3]
        tp = lv.tol[p]
        lim = L + 2 * tp
        lim2 = lim * lim * (1.0 + 1e-9)
    for q in range(ns):
        for j in range(spans[q, 0], spans[q, 1]):
            r = base + j
            if blocked[r]:
                continue
            c = cpr * cap[j] - spr * sap[j]
            s = spr * cap[j] + cpr * sap[j]
            px = Px + Lp * c
            py = Py + Lp * s
            dx = okx - px
            dy = oky - py
            if dx * dx + dy * dy > rk2:
                continue
            if circle:
                kind, ay, ax, by, bx = _circle_args(px, py, L, ccx, ccy, cr)
                cy = 0.0
                cx = 1.0
            else:
                # Farther than L from the polygon's box (with a margin above its
                # tolerances): no vertex or edge within reach, and not inside.
                gx = max(bx0 - px, px - bx1, 0.0)
                gy = max(by0 - py, py - by1, 0.0)
                if gx * gx + gy * gy > lim2:
                    continue
                kind, ay, ax, by, bx, cy, cx = _polygon_args(
                    px, py, L, v, e, ee, slack, etol, s0, s1, tp)
            if kind == NONE:
                continue
            rowof[n] = r
            meta[n, 0] = kind
            meta[n, 1] = m
            meta[n, 2] = mz
            phis[n] = phr + axp[j]
            n += 1
            # Written whether used or not; the counts advance by what the kind uses.
            Y[m] = ay
            X[m] = ax
            Y[m + 1] = by
            X[m + 1] = bx
            Y[m + 2] = cy
            X[m + 2] = cx
            Z[mz] = by
            m += 0 if kind == IN_POLYGON else (
                1 if kind == IN_DISC or kind == TIP else (2 if kind == TANGENT else 3))
            mz += 1 if kind == TIP else 0
    return n, m, mz


def _arc(k, rp, lv, j0, j1, spans, turn):
    """The cells ``j0 <= j < j1`` of joint ``i - 1``'s axis (level ``lv``'s ``axp``: ``m``
    cells from ``ax0``, ``step`` apart) whose row of parent cell ``rp`` may have its base
    point within ``rho`` (``lv.rho[k]``) of obstacle ``k``, centred ``(dx, dy)`` from the
    parent point (the row's base point is ``Lp`` from it, at the parent's angle ``phi``
    plus the cell's): their ranges ``spans[q, 0] <= j < spans[q, 1]``, ``q < `` the count
    returned.

    The base point is within ``rho`` where the cosine of its angle to the centre's
    direction is at least ``kappa = (D^2 + Lp^2 - rho^2) / (2 D Lp)`` (``D`` the centre's
    distance): an arc of half-width ``acos(kappa)`` about that direction. It is taken
    wider than that, so that it holds every row the exact test of :func:`_collect`
    accepts, whatever the rounding of the rows' base points and angles:

    * ``rho^2`` grown by ``1e-9`` of the squares in play, and by what rounding may move a
      base point or the centre: ``size`` is the sum of their coordinates' magnitudes;
    * the half-width grown by one cell, ``1e-7`` radians, and ``4e-15`` of the angles in
      play (``turn``: the magnitudes of the axis's ends), which a cell's angle or the
      parent's may be off by once they are large (a joint whose limits lie at ``1e9``
      radians is rounded to ``1e-7``).

    The rows are cut from the arc as :func:`_paint_one` cuts cells from an interval. Every
    row where that is not possible (no link, the centre at the parent point, an arc of
    ``pi`` or more, an axis of more turns than cells).
    """
    two_pi = 2.0 * math.pi
    Px = lv.Pp[rp, 0]
    Py = lv.Pp[rp, 1]
    okx = lv.ox[k]
    oky = lv.oy[k]
    dx = okx - Px
    dy = oky - Py
    rho, Lp, phi, step, periods = lv.rho[k], lv.Lp, lv.phip[rp], lv.stepp, lv.periodsp
    ax0 = lv.axp[0]
    m = lv.axp.shape[0]
    size = abs(Px) + abs(Py) + abs(okx) + abs(oky) + Lp
    d2 = dx * dx + dy * dy
    reach = rho + Lp
    moved = 4e-15 * size              # how far rounding may move a point, generously
    if d2 > (reach + 2.0 * moved) * (reach + 2.0 * moved) * (1.0 + 1e-9):
        return 0
    d = math.sqrt(d2)
    half = math.pi
    if d * Lp > 0.0:
        far = rho * math.sqrt(1.0 + 1e-9) + 2.0 * moved
        grown = far * far + 1e-9 * (rho * rho + d2 + Lp * Lp)
        kappa = (d2 + Lp * Lp - grown) / (2.0 * d * Lp)
        if kappa >= 1.0:
            return 0
        if kappa > -1.0:
            half = math.acos(kappa) + step + 1e-7 + 4e-15 * (abs(phi) + turn + two_pi)
    if half >= math.pi or periods > m:
        spans[0, 0] = j0
        spans[0, 1] = j1
        return 1
    f = _mod(math.atan2(dy, dx) - phi - half - ax0, two_pi)
    ns = 0
    for piece in range(-1, periods - 1):
        first, last = _cell_range(f + piece * two_pi, 2.0 * half, step, m)
        first = max(first, j0)
        last = min(last + 1, j1)
        if first < last:
            spans[ns, 0] = first
            spans[ns, 1] = last
            ns += 1
    return ns


def _found(n, meta, phis, A, AZ, starts, widths):
    """The intervals of the ``n`` collected entries (:func:`_collect`), into ``starts``,
    ``widths``, from their angles (``A[c:]``, ``AZ[cz]``, ``c, cz = meta[i, 1:]``) by the
    formulas of ``rapp.kernels.occupancy_numpy``'s ``_circle_hits`` and ``_polygon_hits``."""
    two_pi = 2 * math.pi
    for i in range(n):
        kind = meta[i, 0]
        c = meta[i, 1]
        a = A[c]
        b = A[c + 1]
        # A disc's half-width h; the entries a kind does not use are read but not selected.
        h = 2.0 * AZ[meta[i, 2]] if kind == TIP else b
        h = two_pi if kind == IN_DISC else h
        polygon = kind == POLYGON
        start = a + b if polygon else a - min(h, math.pi)
        width = A[c + 2] - b if polygon else 2.0 * h
        start = 0.0 if kind == IN_POLYGON else start
        starts[i] = start - phis[i]
        widths[i] = two_pi if kind == IN_POLYGON else width


def _cell_range(a, width, step, m):
    """Cells ``first..last`` of an axis of ``m`` cells, ``step`` apart from angle 0, whose angle
    lies in ``[a, a + width]``; by the index arithmetic of ``rapp.kernels.occupancy_numpy``'s ``_paint``."""
    first = max(math.ceil(a / step), 0)
    last = min(math.floor((a + width) / step), m - 1)
    return first, last


def _paint_one(out, r, s, w, ax, step, periods, m):
    """Set the cells of row ``r`` of ``out`` (one joint axis of ``m`` cells, angles ``ax``) whose
    angle lies in ``[s, s + w]`` mod ``2 pi``, by the index arithmetic of ``rapp.kernels.occupancy_numpy``'s
    ``_paint``."""
    two_pi = 2.0 * math.pi
    if periods > m:
        # A limited joint spanning more turns than it has cells: each cell tested.
        for jj in range(m):
            if _mod(ax[jj] - s, two_pi) <= w:
                out[r, jj] = True
    else:
        f = _mod(s - ax[0], two_pi)
        for piece in range(-1, periods - 1):
            first, last = _cell_range(f + piece * two_pi, w, step, m)
            for jj in range(first, last + 1):
                out[r, jj] = True


def _paint(blocked, rows, starts, widths, ax, step, periods, out):
    """Set the cells of row ``rows[i]`` of ``out`` (one joint axis, angles ``ax``) whose angle
    lies in ``[starts[i], starts[i] + widths[i]]`` mod ``2 pi`` (:func:`_paint_one`);
    skipped where ``widths[i] < 0`` (no hit) or the row is ``blocked`` (already full)."""
    m = ax.shape[0]
    for i in range(rows.shape[0]):
        r = rows[i]
        if widths[i] < 0.0 or blocked[r]:
            continue
        _paint_one(out, r, starts[i], widths[i], ax, step, periods, m)


def _rows(blocked, out):
    """Each row of ``out`` filled where ``blocked``, else cleared."""
    for r in range(out.shape[0]):
        out[r, :] = blocked[r]


@functools.cache
def kernels():
    """The compiled :data:`Kernels` (numba, cached on disk), or None without numba.

    The first call imports numba and loads the compiled code from its on-disk cache
    (``cache=True``, beside this file): about half a second in a fresh process, of which
    the import of numba is most, and a few tens of milliseconds once another kernel has
    loaded numba. Without a cache (a new install, or this file changed) it compiles
    them, some seconds (``benchmarks/bench_occupancy.py`` records both).
    """
    if not numba_available():
        return None
    g = globals()
    # The helpers are compiled first, so that the kernels calling them find compiled functions.
    # They are inlined: a call passing arrays costs a reference count per array, more than
    # rejecting a far obstacle does. numpy's error model: no divisor here can be zero (see
    # _circle_args; an edge's squared length is positive), so no test for one is compiled.
    for name in ("_mod", "_circle_args", "_extremes", "_polygon_args", "_cell_range",
                 "_arc", "_collect_obstacle", "_paint_one"):
        g[name] = jit(g[name], inline="always", error_model="numpy")
    return Kernels(*(jit(g[name], error_model="numpy")
                     for name in ("_collect", "_found", "_paint", "_rows", "_polygons",
                                  "_reaches")))
