"""The compiled collision kernel: forward kinematics, link clearances and edge certificates.

The geometry of :mod:`rapp.collision` (the clipped projection for discs, the separating
axes for convex polygons, the bisection certificate of
:func:`rapp.collision.segment_collision_free`) written as plain loops over scalars for
numba, one configuration or one edge at a time: a planner calling
:func:`rapp.collides` for a single configuration pays microseconds, not the fixed cost
of a dozen numpy calls on tiny arrays. The arithmetic is the numpy version's, operation
by operation, so both give the same answers (up to the last bits of ``cos``/``sin``,
which only matter for a configuration that touches an obstacle within about 1e-15).

Obstacles are packed once into arrays (:func:`pack`, cached per obstacle list): discs as
rows ``(cx, cy, r)``, polygons as their vertices, edge normals and projections with
offsets. :func:`kernels` compiles the loops on first use (cached on disk,
``cache=True``) and returns None when numba cannot be imported; the dispatcher
(:mod:`rapp.kernels.collision`) then runs :mod:`rapp.kernels.collision_numpy`. Importing this
module does not import numba.

Examples
--------
>>> from rapp import Arm, Circle
>>> k = kernels()
>>> packed = pack([Circle((1.5, 0.0), 0.2)])
>>> k is None or k.collides(np.array([1.0, 1.0]), np.zeros((1, 2)), *packed, 1e100)[0].tolist() == [True]
True
"""

from __future__ import annotations

import functools
import math
import sys
from collections import namedtuple

import numpy as np

from rapp.obstacles import Circle, Polygon
from rapp.jit import jit, numba_available

__all__ = ["pack", "by_identity", "kernels", "loaded", "Kernels", "LOAD_FROM", "link_mask", "MASK_LINKS",
           "pack_scene", "unpack_scene", "SCENE_HEADER"]

#: The compiled functions (see :func:`kernels`).
Kernels = namedtuple("Kernels", "collides collides_one clearances certify collides_scene clearances_one")


def pack(obstacles) -> tuple:
    """Obstacles as the kernel's arrays ``(circles, pv, pn, pr, offsets)``.

    ``circles`` is ``(c, 4)``: centre, radius and :func:`link_mask`. Polygon ``p`` owns rows
    ``offsets[p]:offsets[p + 1]`` of ``pv`` (vertices), ``pn`` (edge normals) and ``pr``
    (the polygon's own projection on each normal, min and max, as
    :attr:`rapp.Polygon.separating_axes` gives them, and its :func:`link_mask`). Obstacles other than Circle and
    Polygon raise the ValueError of :func:`rapp.collision.check_obstacle`.

    Examples
    --------
    >>> from rapp import Circle, Polygon
    >>> c, pv, pn, pr, off = pack([Circle((0, 1), 0.5), Polygon.rectangle((0, 0), 1, 1)])
    >>> c.tolist(), pv.shape, off.tolist()
    ([[0.0, 1.0, 0.5, -1.0]], (4, 2), [0, 4])
    """
    return by_identity(_PACKED, obstacles, _pack)


def by_identity(cache: dict, obstacles, build):
    """``build(obstacles)`` (a tuple), kept in ``cache`` for the same obstacles, by identity.

    Obstacles are immutable, and the cache holds them, so while an entry lives no other
    object can take one of their ids: equal ids are the same obstacles. The cache keeps
    the last 64 lists.

    Examples
    --------
    >>> from rapp import Circle
    >>> obs, cache = [Circle((0, 1), 0.5)], {}
    >>> by_identity(cache, obs, len), by_identity(cache, obs, lambda o: 1 / 0)
    (1, 1)
    """
    if not isinstance(obstacles, (list, tuple)):  # an iterator is read once, here
        obstacles = tuple(obstacles)
    key = tuple(map(id, obstacles))
    hit = cache.get(key)
    if hit is not None:
        return hit[1]
    obstacles = tuple(obstacles)
    out = build(obstacles)
    if len(cache) >= 64:
        cache.clear()
    cache[key] = (obstacles, out)
    return out


def _pack(obstacles) -> tuple:
    """:func:`pack`, uncached."""
    circles, pv, pn, pr, offsets = [], [], [], [], [0]
    for ob in obstacles:
        if isinstance(ob, Circle):
            circles.append((ob.center[0], ob.center[1], ob.radius, link_mask(ob)))
        elif isinstance(ob, Polygon):
            v, normals, lo, hi = ob.separating_axes
            pv.append(v)
            pn.append(normals)
            pr.append(np.stack((lo, hi, np.full(len(v), link_mask(ob))), axis=-1))
            offsets.append(offsets[-1] + len(v))
        else:
            raise ValueError(f"obstacles must be rapp.Circle or rapp.Polygon, got {type(ob).__name__}")
    out = (
        np.array(circles, dtype=float).reshape(-1, 4),
        np.concatenate(pv) if pv else np.zeros((0, 2)),
        np.concatenate(pn) if pn else np.zeros((0, 2)),
        np.concatenate(pr) if pr else np.zeros((0, 3)),
        np.array(offsets, dtype=np.int64),
    )
    for arr in out:
        arr.setflags(write=False)
    return out


_PACKED: dict = {}

#: Entries before the arrays of a :func:`pack_scene` array: links, discs, polygons, polygon
#: rows, and the largest angle accepted.
SCENE_HEADER = 5


def pack_scene(lengths, obstacles, max_abs: float) -> np.ndarray:
    """An arm's link lengths, its obstacles and the angle bound as ONE float array.

    The question "does this one configuration collide?" then crosses from Python into
    compiled code with two arrays, the scene and ``q``: each array argument costs a call
    about 0.05 µs, and :func:`pack`'s five arrays plus the lengths and the bound were most
    of a single check's cost. Layout: ``n, c, p, v, max_abs`` (:data:`SCENE_HEADER`), then
    the ``n`` lengths, the ``(c, 4)`` discs, the ``p + 1`` polygon offsets and the ``(v, 2)``
    vertices, ``(v, 2)`` normals and ``(v, 3)`` projections of :func:`pack`, row by row.
    :func:`unpack_scene` reads it back.

    Examples
    --------
    >>> from rapp import Circle
    >>> pack_scene(np.array([1.0, 1.0]), [Circle((0, 1), 0.5)], 1e100).tolist()
    [2.0, 1.0, 0.0, 0.0, 1e+100, 1.0, 1.0, 0.0, 1.0, 0.5, -1.0, 0.0]
    """
    circles, pv, pn, pr, offsets = pack(obstacles)
    lengths = np.asarray(lengths, dtype=float)
    head = [lengths.size, circles.shape[0], offsets.size - 1, pv.shape[0], max_abs]
    # Writable, as the compiled check is declared for (the scene never leaves rapp).
    return np.concatenate([np.array(head, dtype=float), lengths, circles.ravel(), offsets.astype(float),
                           pv.ravel(), pn.ravel(), pr.ravel()])


def unpack_scene(scene):
    """:func:`pack_scene`'s arrays back: ``lengths, circles, pv, pn, pr, offsets, max_abs``
    (views of ``scene``, but ``offsets``: int64).

    Examples
    --------
    >>> from rapp import Polygon
    >>> parts = unpack_scene(pack_scene(np.array([1.0]), [Polygon.rectangle((0, 0), 1, 1)], 7.0))
    >>> [np.shape(x) for x in parts], parts[5].tolist()
    ([(1,), (0, 4), (4, 2), (4, 2), (4, 3), (2,), ()], [0, 4])
    """
    n, c, p, v = (int(x) for x in scene[:4])
    i = SCENE_HEADER
    offsets = scene[i + n + 4 * c:i + n + 4 * c + p + 1].astype(np.int64)
    i += n + 4 * c + p + 1
    return (scene[SCENE_HEADER:SCENE_HEADER + n], scene[SCENE_HEADER + n:SCENE_HEADER + n + 4 * c].reshape(c, 4),
            scene[i:i + 2 * v].reshape(v, 2), scene[i + 2 * v:i + 4 * v].reshape(v, 2),
            scene[i + 4 * v:i + 7 * v].reshape(v, 3), offsets, float(scene[4]))


#: Link masks are bits of a float64 (exact below 2**53): obstacles for some links only
#: (:func:`rapp.collision.scene`) name links 0 .. MASK_LINKS - 1.
MASK_LINKS = 52


def link_mask(ob) -> float:
    """The links obstacle ``ob`` applies to as the kernel reads them: -1 for every link, else
    the sum of ``2**j`` over its links (:attr:`rapp.Circle.links`).

    Examples
    --------
    >>> from rapp import Circle
    >>> link_mask(Circle((0, 0), 1.0)), link_mask(Circle((0, 0), 1.0, links=(0, 2)))
    (-1.0, 5.0)
    """
    if ob.links is None:
        return -1.0
    if ob.links[-1] >= MASK_LINKS:
        raise ValueError(f"an obstacle for some links only may name links below {MASK_LINKS}, "
                         f"got {ob.links}")
    return float(sum(1 << j for j in ob.links))


def _applies(mask, j):
    """The kernel's :func:`rapp.obstacles.applies`: mask -1 is every link, else bit ``j``."""
    return mask < 0 or (int(mask) >> j) & 1 == 1


# ---------------------------------------------------------------- the loops, compiled by kernels()

def _fk(lengths, q, pts):
    """Joint positions of one configuration into ``pts`` ``(n + 1, 2)``, as Arm does it."""
    phi = 0.0
    x = 0.0
    y = 0.0
    pts[0, 0] = 0.0
    pts[0, 1] = 0.0
    for j in range(lengths.shape[0]):
        phi += q[j]
        x += math.cos(phi) * lengths[j]
        y += math.sin(phi) * lengths[j]
        pts[j + 1, 0] = x
        pts[j + 1, 1] = y


def _point_distance(ax, ay, bx, by, px, py):
    """rapp.collision.segment_point_distance, the same operations."""
    abx = bx - ax
    aby = by - ay
    den = abx * abx + aby * aby
    num = (px - ax) * abx + (py - ay) * aby
    t = min(max(num, 0.0), den)
    t = t / den if den > 0 else 0.0
    dx = ax + t * abx - px
    dy = ay + t * aby - py
    return math.sqrt(dx * dx + dy * dy)


def _hits_polygon(ax, ay, bx, by, pv, pn, pr, s, e):
    """rapp.collision.segment_hits_polygon for polygon rows s:e (touching counts)."""
    for k in range(s, e):
        sa = ax * pn[k, 0] + ay * pn[k, 1]
        sb = bx * pn[k, 0] + by * pn[k, 1]
        if max(sa, sb) < pr[k, 0] or min(sa, sb) > pr[k, 1]:
            return False
    nx = -(by - ay)
    ny = bx - ax
    sv = ax * nx + ay * ny
    lo = np.inf
    hi = -np.inf
    for k in range(s, e):
        p = nx * pv[k, 0] + ny * pv[k, 1]
        lo = min(lo, p)
        hi = max(hi, p)
    return not (hi < sv or lo > sv)


def _polygon_distance(ax, ay, bx, by, pv, pn, pr, s, e):
    """rapp.collision.segment_polygon_distance for polygon rows s:e."""
    if _hits_polygon(ax, ay, bx, by, pv, pn, pr, s, e):
        return 0.0
    d = np.inf
    for k in range(s, e):
        k2 = k + 1 if k + 1 < e else s
        d = min(d, _point_distance(pv[k, 0], pv[k, 1], pv[k2, 0], pv[k2, 1], ax, ay))
    for k in range(s, e):
        k2 = k + 1 if k + 1 < e else s
        d = min(d, _point_distance(pv[k, 0], pv[k, 1], pv[k2, 0], pv[k2, 1], bx, by))
    for k in range(s, e):
        d = min(d, _point_distance(ax, ay, bx, by, pv[k, 0], pv[k, 1]))
    return d


def _link_hits(pts, j, circles, pv, pn, pr, offsets):
    """Link ``j`` (from ``pts[j]`` to ``pts[j + 1]``) touches an obstacle that applies to it."""
    ax, ay, bx, by = pts[j, 0], pts[j, 1], pts[j + 1, 0], pts[j + 1, 1]
    for c in range(circles.shape[0]):
        if _applies(circles[c, 3], j) and \
                _point_distance(ax, ay, bx, by, circles[c, 0], circles[c, 1]) <= circles[c, 2]:
            return True
    for p in range(offsets.shape[0] - 1):
        if _applies(pr[offsets[p], 2], j) and \
                _hits_polygon(ax, ay, bx, by, pv, pn, pr, offsets[p], offsets[p + 1]):
            return True
    return False


def _link_clearance(pts, j, circles, pv, pn, pr, offsets):
    """Clearance of link ``j`` from the obstacles that apply to it."""
    ax, ay, bx, by = pts[j, 0], pts[j, 1], pts[j + 1, 0], pts[j + 1, 1]
    d = np.inf
    for c in range(circles.shape[0]):
        if _applies(circles[c, 3], j):
            d = min(d, _point_distance(ax, ay, bx, by, circles[c, 0], circles[c, 1]) - circles[c, 2])
    for p in range(offsets.shape[0] - 1):
        if _applies(pr[offsets[p], 2], j):
            d = min(d, _polygon_distance(ax, ay, bx, by, pv, pn, pr, offsets[p], offsets[p + 1]))
    return d


def _collides(lengths, q, circles, pv, pn, pr, offsets, max_abs):
    """Collision of every configuration of ``q`` ``(m, n)``: bool ``(m,)``, and whether every
    angle is finite and at most ``max_abs`` in magnitude (else the answer means nothing)."""
    m, n = q.shape
    out = np.zeros(m, dtype=np.bool_)
    pts = np.empty((n + 1, 2))
    for i in range(m):
        hit = _hits(lengths, q[i], pts, circles, pv, pn, pr, offsets, max_abs)
        if hit < 0:
            return out, False
        out[i] = hit == 1
    return out, True


def _hits(lengths, q, pts, circles, pv, pn, pr, offsets, max_abs):
    """One configuration ``q`` ``(n,)``, its joints written into ``pts``: 1 collides, 0 free,
    -1 an angle is not finite or beyond ``max_abs``."""
    n = q.shape[0]
    for j in range(n):
        if not abs(q[j]) <= max_abs:  # also False for NaN
            return -1
    _fk(lengths, q, pts)
    for j in range(n):
        if _link_hits(pts, j, circles, pv, pn, pr, offsets):
            return 1
    return 0


def _collides_one(lengths, q, circles, pv, pn, pr, offsets, max_abs):
    """:func:`_hits` for one configuration, with its own joint buffer. A number, not arrays:
    the call of a planner's inner loop then costs no allocation on the way back."""
    return _hits(lengths, q, np.empty((q.shape[0] + 1, 2)), circles, pv, pn, pr, offsets, max_abs)


def _collides_scene(scene, q):
    """One configuration against a :func:`pack_scene` array: 1 collides, 0 free, -1 an angle
    is not finite or beyond the scene's bound, -2 ``q`` has not one angle per link.

    :func:`_hits` and :func:`_link_hits`, the same operations, but reading the scene in place
    (no views made) and walking the links without a joint buffer (no allocation): those were
    half of a single check's cost.
    """
    n, c, p, v = int(scene[0]), int(scene[1]), int(scene[2]), int(scene[3])
    if q.shape[0] != n:
        return -2
    for j in range(n):
        if not abs(q[j]) <= scene[4]:  # also False for NaN
            return -1
    start = SCENE_HEADER + n + 4 * c  # the polygon offsets, then the vertices, normals, projections
    rows = (start + p + 1, start + p + 1 + 2 * v, start + p + 1 + 4 * v)
    phi = x = y = 0.0
    for j in range(n):
        phi += q[j]
        ax, ay = x, y
        x += math.cos(phi) * scene[SCENE_HEADER + j]
        y += math.sin(phi) * scene[SCENE_HEADER + j]
        for k in range(SCENE_HEADER + n, start, 4):
            if _applies(scene[k + 3], j) and _point_distance(ax, ay, x, y, scene[k], scene[k + 1]) <= scene[k + 2]:
                return 1
        for k in range(p):
            s, e = int(scene[start + k]), int(scene[start + k + 1])
            if _applies(scene[rows[2] + 3 * s + 2], j) and _hits_polygon_flat(ax, ay, x, y, scene, rows, s, e):
                return 1
    return 0


def _hits_polygon_flat(ax, ay, bx, by, scene, rows, s, e):
    """:func:`_hits_polygon` on a :func:`pack_scene` array: its vertices, normals and
    projections start at ``rows``; polygon rows ``s:e``."""
    vs, ns, rs = rows
    for k in range(s, e):
        sa = ax * scene[ns + 2 * k] + ay * scene[ns + 2 * k + 1]
        sb = bx * scene[ns + 2 * k] + by * scene[ns + 2 * k + 1]
        if max(sa, sb) < scene[rs + 3 * k] or min(sa, sb) > scene[rs + 3 * k + 1]:
            return False
    nx = -(by - ay)
    ny = bx - ax
    sv = ax * nx + ay * ny
    lo = np.inf
    hi = -np.inf
    for k in range(s, e):
        pk = nx * scene[vs + 2 * k] + ny * scene[vs + 2 * k + 1]
        lo = min(lo, pk)
        hi = max(hi, pk)
    return not (hi < sv or lo > sv)


def _clearances(lengths, q, circles, pv, pn, pr, offsets):
    """Link clearances of every configuration of ``q`` ``(m, n)``: ``(m, n)``."""
    m, n = q.shape
    out = np.empty((m, n))
    pts = np.empty((n + 1, 2))
    for i in range(m):
        _fk(lengths, q[i], pts)
        for j in range(n):
            out[i, j] = _link_clearance(pts, j, circles, pv, pn, pr, offsets)
    return out


def _clearances_one(lengths, q, pts, out, circles, pv, pn, pr, offsets):
    """:func:`_clearances` of one configuration ``q`` ``(n,)`` into ``out`` ``(n,)``, its
    joints into ``pts`` ``(n + 1, 2)``: no allocation, for a planner's inner loop."""
    _fk(lengths, q, pts)
    for j in range(q.shape[0]):
        out[j] = _link_clearance(pts, j, circles, pv, pn, pr, offsets)


def _certify(lengths, q0, dq, bounds, circles, pv, pn, pr, offsets, min_interval, cap, touch):
    """The bisection of rapp.collision.segment_collision_free, one segment at a time.

    Returns int8 ``(m,)``: 1 free, 0 not free, -1 more than ``cap`` intervals pending (the
    caller then lets the numpy implementation raise its message).
    """
    m, n = q0.shape
    out = np.ones(m, dtype=np.int8)
    pts = np.empty((n + 1, 2))
    q = np.empty(n)
    lo = np.empty(cap)
    hi = np.empty(cap)
    nlo = np.empty(2 * cap)
    nhi = np.empty(2 * cap)
    for i in range(m):
        lo[0] = 0.0
        hi[0] = 1.0
        count = 1
        while count:
            if count > cap:
                out[i] = -1
                break
            kept = 0
            for r in range(count):
                mid = 0.5 * (lo[r] + hi[r])
                half = 0.5 * (hi[r] - lo[r])
                for j in range(n):
                    q[j] = q0[i, j] + mid * dq[i, j]
                _fk(lengths, q, pts)
                certified = True
                for j in range(n):
                    d = _link_clearance(pts, j, circles, pv, pn, pr, offsets)
                    # Touching, or a clearance only pieces under min_interval could cover (a
                    # graze): not free, as an uncertified piece under min_interval would be.
                    if d <= touch or d < bounds[i, j] * 0.5 * min_interval:
                        out[i] = 0
                        break
                    if not bounds[i, j] * half + touch < d:
                        certified = False
                if out[i] == 0:
                    break
                if not certified:
                    if hi[r] - lo[r] < min_interval:
                        out[i] = 0
                        break
                    nlo[kept] = lo[r]
                    nhi[kept] = mid
                    nlo[kept + 1] = mid
                    nhi[kept + 1] = hi[r]
                    kept += 2
            if out[i] == 0:
                break
            if kept > cap:
                out[i] = -1
                break
            for r in range(kept):
                lo[r] = nlo[r]
                hi[r] = nhi[r]
            count = kept
    return out


#: Once the checks of a process add up to this many configurations (or edges), the compiled
#: kernel is loaded; before that they use it only if numba is already imported
#: (:func:`loaded`). Importing numba costs a few tenths of a second, more than a command that
#: checks a few hundred configurations spends in numpy: ``python -m rapp plan`` should not
#: pay it for a 2-link A* plan, while a loop of single checks soon does.
LOAD_FROM = 4096

_work = [0]


def loaded(work: int = 0):
    """:func:`kernels` once numba is imported or the checks so far reach ``LOAD_FROM``, else None.

    ``work`` is the number of configurations (or edges) of the call, added to the count.
    The answers are the same either way (:mod:`rapp.kernels.collision_numpy` before);
    only the time differs. The sampling planners call :func:`kernels` themselves.

    Examples
    --------
    >>> loaded(LOAD_FROM) is kernels()
    True
    """
    _work[0] += work
    if _work[0] >= LOAD_FROM or "numba" in sys.modules:
        return kernels()
    return None


@functools.cache
def kernels():
    """The compiled :class:`Kernels` (numba, cached on disk), or None without numba.

    The first call imports numba and loads the compiled code from its cache (or
    compiles it once, some seconds); :mod:`rapp.collision` calls it on its first
    check, so a command that checks nothing never pays it.
    """
    if not numba_available():
        return None
    g = globals()
    # The helpers are compiled first, so that the kernels calling them find compiled functions.
    for name in ("_fk", "_point_distance", "_applies", "_hits_polygon", "_polygon_distance", "_link_hits",
                 "_link_clearance", "_hits", "_hits_polygon_flat"):
        g[name] = jit(g[name])
    # Declared for writable C arrays only: any other q is refused (TypeError) before compiling a
    # variant, and rapp.collision.collides then takes its general path.
    one = jit(_collides_scene, signature_or_function="int64(float64[::1], float64[::1])")
    return Kernels(jit(_collides), jit(_collides_one), jit(_clearances), jit(_certify), one,
                   jit(_clearances_one))
