"""The collision tests in numpy: the backend without numba, and the geometry both backends share.

:mod:`rapp.kernels.collision` runs these where the compiled kernel
(:mod:`rapp.kernels.collision_numba`) is not loaded: without numba, and for the first checks of a
process (see :data:`rapp.kernels.collision_numba.LOAD_FROM`). Both start from the same checked
arguments (:func:`check_segments`, :func:`check_obstacle`) and give the same answers; the public
names here are re-exported by :mod:`rapp.collision`, where the book meets them.

Examples
--------
>>> from rapp import Arm, Circle
>>> collides(Arm([1.0, 1.0]), [[0.0, 0.0], [1.5, 0.0]], [Circle((1.5, 0.0), 0.2)]).tolist()
[True, False]
"""

from __future__ import annotations

import numpy as np

from rapp.checks import finite_number, positive_integer
from rapp.errors import CertificationLimit
from rapp.obstacles import Circle, Polygon
from rapp.kernels.collision_numba import unpack_scene

__all__ = ["closest_point_on_segment", "segment_point_distance", "segment_hits_polygon",
           "segment_polygon_distance", "check_obstacle", "segment_clearances", "reach_matrix",
           "check_segments", "collides", "link_clearances", "segment_collision_free",
           "MAX_PENDING_INTERVALS", "collides_scene"]

#: Most sub-intervals :func:`segment_collision_free` keeps pending at once in one
#: call (a few MB in all); one segment needing more raises
#: :class:`~rapp.errors.CertificationLimit`. Planning the bundled scenarios keeps
#: at most about a thousand pending; only an arm huge relative to its clearance
#: (links of 1e20 beside an obstacle 1 away) comes near the limit.
MAX_PENDING_INTERVALS = 1 << 14


#: Multiplying a row vector (x, y) by this gives (-y, x): a quarter turn, exactly.
_QUARTER_TURN = np.array([[0.0, 1.0], [-1.0, 0.0]])
_QUARTER_TURN.setflags(write=False)


def segment_circle_distance(a, b, center, radius) -> np.ndarray:
    """Signed clearance of segment ``ab`` from a disc: distance to the centre minus ``radius``.

    Positive: free by that margin; ``<= 0``: the segment touches or enters the disc.

    Examples
    --------
    >>> float(segment_circle_distance([0, 0], [2, 0], (1, 1), 0.5))
    0.5
    """
    return segment_point_distance(a, b, center) - np.asarray(radius, dtype=float)


def segment_hits_circle(a, b, center, radius) -> np.ndarray:
    """TM:SegmentCircleCollision: True where the segment meets the closed disc.

    Examples
    --------
    >>> bool(segment_hits_circle([0, 0], [1, 0], (2, 0), 1.0))   # touching counts
    True
    >>> bool(segment_hits_circle([0, 0], [0, 0], (2, 0), 1.0))   # degenerate segment
    False
    """
    return segment_point_distance(a, b, center) <= np.asarray(radius, dtype=float)


def _dot(u, v):
    return np.einsum("...i,...i->...", u, v)


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def closest_point_on_segment(a, b, p) -> np.ndarray:
    """Closest point to ``p`` on the segment ``ab`` (the clipped projection).

    ``t = (p - a)·(b - a) / |b - a|^2`` is clipped to ``[0, 1]``; a degenerate
    segment (``a == b``) gives ``a``.

    Parameters
    ----------
    a, b, p : array_like, shape (..., 2)
        Broadcast against each other.

    Returns
    -------
    ndarray, shape (..., 2)

    Examples
    --------
    >>> closest_point_on_segment([0, 0], [2, 0], [3, 1]).tolist()
    [2.0, 0.0]
    >>> closest_point_on_segment([0, 0], [2, 0], [[1, 5], [-1, 0]]).tolist()
    [[1.0, 0.0], [0.0, 0.0]]
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    p = np.asarray(p, dtype=float)
    ab = b - a
    den = _dot(ab, ab)
    num = _dot(p - a, ab)
    # clip(num / den, 0, 1) computed as clip(num, 0, den) / den: the same numbers, but a very
    # short segment far from p can no longer overflow, and a point segment (den = 0) gives a.
    t = np.minimum(np.maximum(num, 0.0), den)  # np.clip's wrapper costs more than the work
    t = np.divide(t, den, out=np.zeros(t.shape), where=den > 0)
    return a + t[..., None] * ab


def segment_point_distance(a, b, p) -> np.ndarray:
    """Euclidean distance from points ``p`` to the segments ``ab``, shape ``(...)``.

    Examples
    --------
    >>> float(segment_point_distance([0, 0], [2, 0], [3, 4]))
    4.123105625617661
    """
    p = np.asarray(p, dtype=float)
    return np.linalg.norm(closest_point_on_segment(a, b, p) - p, axis=-1)


def _polygon_arrays(vertices):
    v = vertices.array if isinstance(vertices, Polygon) else np.asarray(vertices, dtype=float)
    return v, np.roll(v, -1, axis=0) - v


def segment_hits_polygon(a, b, vertices) -> np.ndarray:
    """Separating-axis test of segments against one convex polygon; touching counts.

    The candidate axes are the polygon's edge normals and the segment's normal.
    The two convex sets are disjoint exactly when their projections on one of
    these axes are disjoint (strictly: a shared endpoint is a touch).

    Parameters
    ----------
    a, b : array_like, shape (..., 2)
    vertices : Polygon or array_like, shape (k, 2)
        A convex polygon (either orientation for a raw array).

    Returns
    -------
    ndarray of bool, shape (...)

    Examples
    --------
    >>> sq = Polygon.rectangle((1, -1), 2, 2)
    >>> segment_hits_polygon([0, 0], [[1.5, 0], [0.5, 0], [1, 0]], sq).tolist()
    [True, False, True]
    """
    if isinstance(vertices, Polygon):
        v, normals, pmin, pmax = vertices.separating_axes
    else:
        v, e = _polygon_arrays(vertices)
        normals = np.stack((e[:, 1], -e[:, 0]), axis=-1)  # (k, 2)
        # Polygon normals: (k axes) projections of the polygon are fixed numbers.
        pv = v @ normals.T  # (k vertices, k axes)
        pmin, pmax = pv.min(axis=0), pv.max(axis=0)
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape != b.shape:
        a, b = np.broadcast_arrays(a, b)
    sa, sb = a @ normals.T, b @ normals.T  # (..., k)
    sep = ((np.maximum(sa, sb) < pmin) | (np.minimum(sa, sb) > pmax)).any(axis=-1)
    # Segment normal (-ab_y, ab_x): the segment projects to one number.
    n = (b - a) @ _QUARTER_TURN
    s = _dot(a, n)
    proj = n @ v.T
    sep |= (proj.max(axis=-1) < s) | (proj.min(axis=-1) > s)
    return ~sep


def segment_polygon_distance(a, b, vertices) -> np.ndarray:
    """Distance from segments to a convex polygon, 0 where they intersect.

    For disjoint convex polygons (a segment is a degenerate one) the distance is
    attained between a vertex of one and an edge of the other, so it is the
    minimum over: segment endpoints to polygon edges, polygon vertices to the segment.

    Examples
    --------
    >>> sq = Polygon.rectangle((1, -1), 2, 2)
    >>> segment_polygon_distance([0, 0], [[0.25, 0], [2, 0], [0, 3]], sq).tolist()
    [0.75, 0.0, 1.0]
    """
    if isinstance(vertices, Polygon):
        v, v2 = vertices.edge_ends
    else:
        v, e = _polygon_arrays(vertices)
        v2 = v + e
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a, b = np.broadcast_arrays(a, b)
    da = segment_point_distance(v, v2, a[..., None, :]).min(axis=-1)
    db = segment_point_distance(v, v2, b[..., None, :]).min(axis=-1)
    dv = segment_point_distance(a[..., None, :], b[..., None, :], v).min(axis=-1)
    d = np.minimum(np.minimum(da, db), dv)
    return np.where(segment_hits_polygon(a, b, vertices if isinstance(vertices, Polygon) else v),
                    0.0, d)


def check_obstacle(ob):
    """``ob`` itself when it is a Circle or a Polygon, else a ValueError.

    Examples
    --------
    >>> check_obstacle((1.0, 2.0))
    Traceback (most recent call last):
    ...
    ValueError: obstacles must be rapp.Circle or rapp.Polygon, got tuple
    """
    if not isinstance(ob, (Circle, Polygon)):
        raise ValueError(f"obstacles must be rapp.Circle or rapp.Polygon, got {type(ob).__name__}")
    return ob


def segment_clearances(a, b, obstacles, *, link=None) -> np.ndarray:
    """Clearance of segments ``ab`` (..., 2) from the nearest obstacle, shape ``(...)``.

    The link-level work of :func:`link_clearances`, for callers that already
    hold the segment end points (e.g. one link on a whole grid). An obstacle that
    applies to some links only (:attr:`rapp.Circle.links`) counts for the segments
    that are those links: with ``link=None`` the segments are the links ``0..n-1``
    along axis -2 (as :func:`link_clearances` lays them out), with ``link=j`` they
    are all link ``j``.

    Examples
    --------
    >>> from rapp import Circle
    >>> float(segment_clearances(np.array([0.0, 0.0]), np.array([2.0, 0.0]), [Circle((1.0, 1.0), 0.5)]))
    0.5
    >>> a, b = np.zeros((2, 2)), np.array([[2.0, 0.0], [2.0, 0.0]])   # two links, side by side
    >>> segment_clearances(a, b, [Circle((1.0, 1.0), 0.5, links=(1,))]).tolist()
    [inf, 0.5]
    """
    out = np.full(np.broadcast_shapes(a.shape, b.shape)[:-1], np.inf)
    circles = [ob for ob in obstacles if isinstance(check_obstacle(ob), Circle) and ob.links is None]
    if circles:
        # Every disc in one broadcast (discs on a new last axis): the arithmetic of one disc at
        # a time with a fixed number of numpy calls.
        centers = np.array([c.center for c in circles])
        radii = np.array([c.radius for c in circles])
        d = segment_point_distance(a[..., None, :], b[..., None, :], centers) - radii
        np.minimum(out, d.min(axis=-1), out=out)
    for ob in obstacles:
        if ob.links is None:
            if not isinstance(ob, Circle):
                np.minimum(out, segment_polygon_distance(a, b, ob), out=out)
            continue
        mine = _link_mask(ob, link, out.shape[-1] if out.ndim else 0)
        if mine is False:
            continue
        d = (segment_circle_distance(a, b, ob.center, ob.radius) if isinstance(ob, Circle)
             else segment_polygon_distance(a, b, ob))
        np.minimum(out, np.where(mine, d, np.inf), out=out)
    return out


def _link_mask(ob, link, n):
    """Where obstacle ``ob`` applies: True/False for segments that are all link ``link``, or a
    bool ``(n,)`` over links laid out on the last axis (``link`` None)."""
    if link is not None:
        return link in ob.links
    return np.isin(np.arange(n), ob.links)


def reach_matrix(arm) -> np.ndarray:
    """``R[i, j] = L_i + ... + L_j`` for ``i <= j``, else 0 (see :func:`motion_bounds`)."""
    n = arm.n
    c = np.concatenate(([0.0], np.cumsum(arm.lengths)))
    R = c[None, 1:] - c[:-1, None]
    return np.where(np.arange(n)[:, None] <= np.arange(n)[None, :], R, 0.0)


def check_segments(arm, q0, q1, min_interval, max_intervals) -> tuple:
    """The arguments of :func:`segment_collision_free`, checked and flattened.

    Returns ``(q0, q1, dq, bounds, shape, min_interval, cap)``: the endpoints as
    C-contiguous ``(m, n)`` copies, ``dq = q1 - q0``, the per-link motion bounds of
    each segment (``|dq| @`` :func:`reach_matrix`), the broadcast batch shape, and the
    two limits as validated numbers. Both the compiled and the numpy certificate
    (:func:`rapp.reference.segment_collision_free`) start here, so they refuse the
    same inputs with the same one-line errors.

    Examples
    --------
    >>> from rapp import Arm
    >>> q0, q1, dq, bounds, shape, h, cap = check_segments(Arm([1.0, 1.0]), [0.0, 0.0],
    ...                                                    [[0.5, 0.0], [0.0, 1.0]], 1e-9, 64)
    >>> shape, dq.tolist(), bounds.tolist()
    ((2,), [[0.5, 0.0], [0.0, 1.0]], [[0.5, 1.0], [0.0, 1.0]])
    >>> check_segments(Arm([1.0, 1.0]), [0.0, 0.0], [0.0, 0.0], 0.0, 64)
    Traceback (most recent call last):
    ...
    ValueError: min_interval must be a finite number > 0, got 0.0
    """
    q0, q1 = arm.check_q(q0, "q0"), arm.check_q(q1, "q1")
    try:
        q0, q1 = np.broadcast_arrays(q0, q1)
    except ValueError:
        raise ValueError(f"q0 and q1 must broadcast together, got shapes {q0.shape} and {q1.shape}") from None
    min_interval = finite_number(min_interval, "min_interval", above=0.0)
    cap = positive_integer(max_intervals, "max_intervals", lo=2)
    shape = q0.shape[:-1]
    # Copies where broadcast (numba wants real arrays).
    q0, q1 = np.ascontiguousarray(q0.reshape(-1, arm.n)), np.ascontiguousarray(q1.reshape(-1, arm.n))
    dq = q1 - q0
    bounds = np.abs(dq) @ reach_matrix(arm)  # (m, n); finite: angles and lengths are bounded
    return q0, q1, dq, bounds, shape, min_interval, cap


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
        else:  # for some links only (rapp.collision.scene): their own test, the others left alone
            own = (segment_hits_circle(a, b, ob.center, ob.radius) if isinstance(ob, Circle)
                   else segment_hits_polygon(a, b, ob))
            hit |= own & _link_mask(ob, None, arm.n)
    return hit.any(axis=-1)


def collides_scene(scene, q) -> int:
    """The compiled ``collides_scene`` of :mod:`rapp.kernels.collision_numba` in numpy: one
    configuration ``q`` ``(n,)`` against a :func:`~rapp.kernels.collision_numba.pack_scene`
    array; 1 collides, 0 free, -1 an angle not finite or beyond the scene's bound, -2 not
    one angle per link.

    Examples
    --------
    >>> from rapp import Circle
    >>> from rapp.kernels.collision_numba import pack_scene
    >>> scene = pack_scene([1.0, 1.0], [Circle((1.5, 0.0), 0.2)], 1e100)
    >>> collides_scene(scene, np.array([0.0, 0.0])), collides_scene(scene, np.array([1.5, 0.0]))
    (1, 0)
    """
    lengths, circles, pv, _, pr, offsets, max_abs = unpack_scene(scene)
    q = np.asarray(q, dtype=float)
    if q.shape != lengths.shape:
        return -2
    if not (np.abs(q) <= max_abs).all():
        return -1
    phi = np.cumsum(q)
    pts = np.concatenate([np.zeros((1, 2)), np.cumsum(np.stack((np.cos(phi), np.sin(phi)), -1)
                                                      * lengths[:, None], axis=0)])
    for j in range(lengths.size):  # links, and below obstacles: never configurations
        own = lambda mask: mask < 0 or (int(mask) >> j) & 1 == 1  # noqa: E731  link_mask's bits
        c = circles[[own(m) for m in circles[:, 3]]] if circles.size else circles
        if (segment_point_distance(pts[j], pts[j + 1], c[:, :2]) <= c[:, 2]).any():
            return 1
        for s, e in zip(offsets[:-1], offsets[1:]):
            if own(pr[s, 2]) and segment_hits_polygon(pts[j], pts[j + 1], pv[s:e]):
                return 1
    return 0


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
        # Likewise a clearance only pieces shorter than min_interval could cover: a link
        # grazing a vertex whose clearance grows quadratically would otherwise double its
        # pending pieces every two levels and reach the interval limit first.
        hit = ((d <= touch) | (d < bounds[owner] * (0.5 * min_interval))).any(axis=-1)
        # Certified with room for touching: every point of the piece keeps a clearance over
        # ``touch``, so no piece next to an end within touching distance is ever certified.
        need = bounds[owner] * half[:, None] + touch
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
