"""Reference implementations: slow, obviously correct, kept to check and time the fast ones.

Each function here computes what a function of the package computes, the plain way: the
previous, straightforward version that the faster one replaced. Tests compare the two on
random inputs (the reference is the oracle) and the benchmarks time them side by side
(``benchmarks/bench_core.py``, ``benchmarks/bench_cli.py``). Nothing in the pipeline calls
them; a new fast path keeps its predecessor here, documented, instead of as a private copy
next to it.

================================  ==========================================================
reference                         the fast function it checks
================================  ==========================================================
:func:`occupancy`                 :func:`rapp.cspace.occupancy` (every link against every
                                  obstacle on every cell of its prefix grid)
:func:`certified_free`            :func:`rapp.cspace.certified_free` (link clearances on
                                  every prefix cell)
:func:`collides`                  :func:`rapp.collision.collides` (numpy over a batch; the
                                  compiled kernel of :mod:`rapp._kernels.collision_numba`
                                  replaced it)
:func:`link_clearances`           :func:`rapp.collision.link_clearances`
:func:`segment_collision_free`    :func:`rapp.collision.segment_collision_free` (the
                                  bisection as numpy arrays, level by level)
:func:`link_gaps`                 :func:`rapp.collision.link_clearances` of thick links
                                  (a capsule's distance from each obstacle, one at a time,
                                  with no grown shapes: :func:`capsule_distance`)
================================  ==========================================================

The package never calls them: its numpy backend without numba is :mod:`rapp._kernels`'
``collision_numpy`` and ``occupancy_numpy``, which the tests compare with these.

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
from rapp.collision import (
    MAX_PENDING_INTERVALS,
    check_obstacle,
    check_segments,
    motion_bounds,
    scene,
    segment_clearances,
    segment_hits_circle,
    segment_hits_polygon,
    segment_point_distance,
)
from rapp.errors import CertificationLimit
from rapp.cspace import check_grid, prefix_grid
from rapp.obstacles import Circle, applies

__all__ = ["occupancy", "certified_free", "circle_hits", "polygon_hits", "collides", "link_clearances",
           "segment_collision_free", "capsule_distance", "link_gaps"]


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


def occupancy(arm, obstacles, grid, *, margin=0.0) -> np.ndarray:
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
    arm, obstacles = scene(arm, [check_obstacle(ob) for ob in obstacles], margin)
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
            if applies(ob, i):
                hit |= circle_hits(P, cos_phi, sin_phi, L, ob.center, ob.radius)
        for ob in polys:
            if applies(ob, i):
                hit |= polygon_hits(P, cos_phi, sin_phi, L, ob)
        occ |= hit.reshape(hit.shape + (1,) * (n - i - 1))
    return occ


def certified_free(arm, obstacles, grid, *, chunk: int = 200_000, margin=0.0) -> np.ndarray:
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
    arm, obstacles = scene(arm, [check_obstacle(ob) for ob in obstacles], margin)
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
            d = segment_clearances(pts[:, j, :], pts[:, j + 1, :], obstacles, link=j)
            ok[lo:lo + chunk] = d > need[j]
        out &= ok.reshape(prefix + (1,) * (n - j - 1))
    return out


# Segments bisected together, and configurations per clearance evaluation: they
# bound the temporaries (about n * k * 16 bytes per configuration for a k-gon).
_GROUP = 256
_CHUNK = 4096


def collides(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.collides` in numpy: every link against every obstacle, batched.

    Examples
    --------
    >>> from rapp import Arm, Circle, Polygon
    >>> import rapp.collision
    >>> arm = Arm([1.0, 1.0])
    >>> obs = [Circle((1.75, 0.75), 0.6), Polygon.rectangle((-2, -2), 1, 1)]
    >>> q = [[0.4, 0.0], [np.pi / 2, 0.0], [-2.4, 0.0]]
    >>> collides(arm, q, obs).tolist() == rapp.collision.collides(arm, q, obs).tolist()
    True
    """
    pts = arm.joint_positions(q)
    a, b = pts[..., :-1, :], pts[..., 1:, :]
    circles, polygons = [], []
    for ob in obstacles:
        (circles if isinstance(check_obstacle(ob), Circle) and ob.links is None else polygons).append(ob)
    hit = np.zeros(a.shape[:-1], dtype=bool)
    if circles:
        # Every link against every disc in one broadcast (links on axis -2, discs on -1): the
        # same arithmetic as one disc at a time, with a fixed number of numpy calls, which is
        # what a sampling planner calling this for one configuration at a time pays for.
        centers = np.array([c.center for c in circles])
        radii = np.array([c.radius for c in circles])
        d = segment_point_distance(a[..., None, :], b[..., None, :], centers)
        hit |= (d <= radii).any(axis=-1)
    for ob in polygons:
        if ob.links is None:
            hit |= segment_hits_polygon(a, b, ob)
        else:  # applies to some links only: their own test, the others left alone
            own = (segment_hits_circle(a, b, ob.center, ob.radius) if isinstance(ob, Circle)
                   else segment_hits_polygon(a, b, ob))
            hit |= own & np.isin(np.arange(arm.n), ob.links)
    return hit.any(axis=-1)


def link_clearances(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.link_clearances` in numpy, ``(..., n)``.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> link_clearances(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)]).tolist()
    [0.6180339887498949, 0.5]
    """
    pts = arm.joint_positions(q)
    return segment_clearances(pts[..., :-1, :], pts[..., 1:, :], obstacles)


def segment_collision_free(arm, q0, q1, obstacles, *, min_interval: float = 1e-9,
                           max_intervals: int = MAX_PENDING_INTERVALS) -> np.ndarray:
    """:func:`rapp.collision.segment_collision_free` in numpy: groups of segments bisected level by level.

    Examples
    --------
    The compiled certificate's answers, from the same checked arguments:

    >>> from rapp import Arm, Circle, collision
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((0.0, 1.5), 0.3)]
    >>> q1 = [[0.5, 0.0], [3.0, 0.0], [1.2, 0.3]]
    >>> free = segment_collision_free(arm, [0.0, 0.0], q1, obs)
    >>> free.tolist(), bool((free == collision.segment_collision_free(arm, [0.0, 0.0], q1, obs)).all())
    ([True, False, True], True)
    """
    obstacles = [check_obstacle(ob) for ob in obstacles]
    q0, q1, dq, bounds, shape, min_interval, cap = check_segments(arm, q0, q1, min_interval,
                                                                  max_intervals)
    free = np.ones(q0.shape[0], dtype=bool)
    if not obstacles:
        return free.reshape(shape)
    for g in range(0, q0.shape[0], _GROUP):
        sl = slice(g, g + _GROUP)
        try:
            free[sl] = _bisect(arm, q0[sl], q1[sl], dq[sl], bounds[sl], obstacles, min_interval, cap)
        except _GroupTooLarge:
            for i in range(g, min(g + _GROUP, q0.shape[0])):
                one = slice(i, i + 1)
                free[i] = _bisect(arm, q0[one], q1[one], dq[one], bounds[one], obstacles,
                                  min_interval, cap)[0]
    return free.reshape(shape)


class _GroupTooLarge(Exception):
    """Several segments together exceed the pending limit; retry them one by one."""


def _bisect(arm, q0, q1, dq, bounds, obstacles, min_interval, cap):
    """Certification of the segments ``q0 + t dq`` by bisection: bool ``(m,)``.

    Raises :class:`_GroupTooLarge` when more than ``cap`` intervals of several
    segments are pending, :class:`CertificationLimit` when one segment alone needs more.
    """
    m = q0.shape[0]
    free = np.ones(m, dtype=bool)
    owner = np.arange(m)
    lo = np.zeros(m)
    hi = np.ones(m)
    worst = np.full(m, np.inf)  # per segment: smallest clearance that failed to certify
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    while owner.size:
        if owner.size > cap:
            if owner[0] != owner[-1]:  # owners stay sorted: several segments pending
                raise _GroupTooLarge
            i = owner[0]
            raise CertificationLimit(_limit_message(arm, q0[i], q1[i], bounds[i], worst[i], cap))
        mid = 0.5 * (lo + hi)
        half = 0.5 * (hi - lo)
        q = q0[owner] + mid[:, None] * dq[owner]
        d = np.empty(q.shape)
        for s in range(0, len(q), _CHUNK):
            pts = arm.joint_positions(q[s:s + _CHUNK])
            d[s:s + _CHUNK] = segment_clearances(pts[..., :-1, :], pts[..., 1:, :], obstacles)
        # Touching counts as collision, and a clearance below the rounding of the arm's own
        # coordinates cannot be told from touching: without this, a link grazing a vertex
        # along a whole stretch would be bisected until the interval limit.
        hit = (d <= touch).any(axis=-1)
        need = bounds[owner] * half[:, None]
        certified = (need < d).all(axis=-1)
        stuck = ~certified & ~hit & (hi - lo < min_interval)
        free[owner[hit | stuck]] = False
        keep = ~certified & free[owner]
        if not keep.any():  # the common case for a short edge: settled at the first level
            break
        failed = np.where(need >= d, d, np.inf).min(axis=-1)
        np.minimum.at(worst, owner[keep], failed[keep])
        owner, lo, mid, hi = owner[keep], lo[keep], mid[keep], hi[keep]
        # Children interleaved so that owners stay sorted.
        owner = np.repeat(owner, 2)
        lo, hi = np.stack((lo, mid), axis=1).ravel(), np.stack((mid, hi), axis=1).ravel()
    return free


def _limit_message(arm, q0, q1, bounds, clearance, cap):
    scale = float(np.sum(arm.lengths))
    sweep = float(bounds.max())
    return (
        f"the segment q0={q0.tolist()} -> q1={q1.tolist()} could not be certified "
        f"collision-free within {cap} sub-intervals (rapp.collision.MAX_PENDING_INTERVALS): "
        f"the arm is too large relative to its clearance. Its links add up to {scale:.3g} "
        f"and sweep up to {sweep:.3g} along the segment, but the clearance where "
        f"certification failed is only {clearance:.3g}, so the pieces would have to be "
        f"shorter than {2 * clearance / sweep:.3g} of the segment. Use units in which the arm "
        "and its clearances are of comparable size, or shorter segments"
    )


def capsule_distance(a, b, radius, ob) -> float:
    """Distance from the capsule of segment ``ab`` and ``radius`` to one obstacle; <= 0 is a hit.

    One segment, plain Python floats, no grown shapes: for a disc, the distance from its
    centre to the segment (the clipped projection) minus both radii; for a convex
    polygon, 0 when the segment has a point inside it (an end inside, or a crossing with
    an edge found by orientation signs), else the smallest of the four end-to-edge and
    vertex-to-segment distances (disjoint convex sets are nearest at a vertex of one),
    minus the radius.

    Examples
    --------
    >>> from rapp import Circle, Polygon
    >>> capsule_distance((0, 0), (2, 0), 0.1, Circle((1, 1), 0.5))
    0.4
    >>> capsule_distance((0, 0), (2, 0), 0.1, Polygon.rectangle((3, -1), 1, 2))
    0.9
    """
    def point_segment(p, u, v):
        (px, py), (ux, uy), (vx, vy) = p, u, v
        ex, ey = vx - ux, vy - uy
        den = ex * ex + ey * ey
        t = 0.0 if den == 0 else min(1.0, max(0.0, ((px - ux) * ex + (py - uy) * ey) / den))
        return math.hypot(ux + t * ex - px, uy + t * ey - py)

    def orient(p, u, v):
        return (u[0] - p[0]) * (v[1] - p[1]) - (u[1] - p[1]) * (v[0] - p[0])

    def on_segment(p, u, v):  # p is collinear with u, v: is it between them?
        return min(u[0], v[0]) <= p[0] <= max(u[0], v[0]) and min(u[1], v[1]) <= p[1] <= max(u[1], v[1])

    def cross(u, w):  # do segments ab and uw share a point? (the textbook orientation test)
        o1, o2, o3, o4 = orient(a, b, u), orient(a, b, w), orient(u, w, a), orient(u, w, b)
        if o1 * o2 < 0 and o3 * o4 < 0:
            return True
        return ((o1 == 0 and on_segment(u, a, b)) or (o2 == 0 and on_segment(w, a, b))
                or (o3 == 0 and on_segment(a, u, w)) or (o4 == 0 and on_segment(b, u, w)))

    a, b = tuple(map(float, a)), tuple(map(float, b))
    if isinstance(ob, Circle):
        return point_segment(ob.center, a, b) - ob.radius - radius
    v = ob.vertices  # counter-clockwise
    k = len(v)
    edges = [(v[i], v[(i + 1) % k]) for i in range(k)]
    inside = any(all(orient(u, w, p) >= 0 for u, w in edges) for p in (a, b))
    crossing = any(cross(u, w) for u, w in edges)
    if inside or crossing:
        return -radius
    d = min(min(point_segment(p, u, w) for u, w in edges) for p in (a, b))
    d = min(d, min(point_segment(p, a, b) for p in v))
    return d - radius


def link_gaps(arm, q, obstacles) -> np.ndarray:
    """Each link's gap to the nearest obstacle, as capsules (:func:`capsule_distance`): ``(n,)``.

    One configuration ``q`` ``(n,)``, a loop over links and obstacles. Link ``j`` keeps a
    margin ``m`` exactly when its gap is greater than ``m``, which is what
    :func:`rapp.collision.link_clearances` with ``margin=m`` measures beyond ``m``.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> link_gaps(Arm([1.0, 1.0], link_radius=0.1), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)]).round(6).tolist()
    [0.518034, 0.4]
    """
    pts = arm.joint_positions(q)
    out = np.full(arm.n, np.inf)
    for j in range(arm.n):
        for ob in obstacles:
            out[j] = min(out[j], capsule_distance(pts[j], pts[j + 1], arm.link_radius[j], ob))
    return out
