"""Collision geometry: links are segments, obstacles are discs and convex polygons.

The segment–circle test is TM:SegmentCircleCollision of the SRS (seed 000):
project the centre on the segment, clip the projection parameter to ``[0, 1]``,
and compare the distance to the closest point with the radius. Touching counts
as collision (``<=``).

The MIS (seed 001, ``checkCollision``) measures the distance from the centre to
the infinite *line* through the link instead. That distance is never larger
than the distance to the segment, so the MIS reports collisions that do not
happen (an obstacle beyond the end of a link, on the line's extension). It is
kept here as :func:`line_distance_mis` so that the book can show one such false
collision; the package never uses it.

Every function works on batches: points have shape ``(..., 2)`` and
configurations ``(..., n)``. Loops run over links and obstacles, never over
configurations.
"""

from __future__ import annotations


import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm

from rapp.arm import MAX_ANGLE
from rapp.checks import finite_number, positive_integer
from rapp import collision_kernel
from rapp.collision_kernel import pack
from rapp.obstacles import Circle, Polygon

__all__ = [
    "closest_point_on_segment",
    "segment_point_distance",
    "segment_circle_distance",
    "segment_hits_circle",
    "line_distance_mis",
    "segment_hits_polygon",
    "segment_polygon_distance",
    "check_obstacle",
    "link_clearances",
    "segment_clearances",
    "collides",
    "clearance",
    "motion_bounds",
    "reach_matrix",
    "segment_collision_free",
    "check_segments",
    "path_collision_free",
    "MAX_PENDING_INTERVALS",
]

#: Most sub-intervals :func:`segment_collision_free` keeps pending at once in one
#: call (a few MB in all); one segment needing more raises
#: :class:`~rapp.errors.CertificationLimit`. Planning the bundled scenarios keeps
#: at most about a thousand pending; only an arm huge relative to its clearance
#: (links of 1e20 beside an obstacle 1 away) comes near the limit.
MAX_PENDING_INTERVALS = 1 << 14


#: The answers of the one-configuration kernel (0 free, 1 collides) as numpy's own booleans.
_ANSWER = (np.False_, np.True_)

#: Multiplying a row vector (x, y) by this gives (-y, x): a quarter turn, exactly.
_QUARTER_TURN = np.array([[0.0, 1.0], [-1.0, 0.0]])
_QUARTER_TURN.setflags(write=False)


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


def line_distance_mis(a, b, c) -> np.ndarray:
    """Distance from ``c`` to the infinite LINE through ``a`` and ``b`` — the MIS's formula.

    ``d = |(x2 - x1)(y1 - yk) - (y2 - y1)(x1 - xk)| / |b - a|`` (seed 001,
    checkCollision). It ignores where the segment ends, so ``d <= r`` can hold
    for an obstacle that lies on the line's extension, far from the link: a
    false collision. Kept to show that error; the package uses
    :func:`segment_point_distance`. A degenerate segment gives ``nan``.

    Examples
    --------
    >>> a, b, c = [0, 0], [1, 0], (3, 0)         # circle of radius 0.5 beyond the link's end
    >>> float(line_distance_mis(a, b, c)) <= 0.5  # the MIS says: collision
    True
    >>> bool(segment_hits_circle(a, b, c, 0.5))   # the clipped projection says: free
    False
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    c = np.asarray(c, dtype=float)
    ab = b - a
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs(_cross(ab, a - c)) / np.linalg.norm(ab, axis=-1)


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


def link_clearances(arm, q, obstacles) -> np.ndarray:
    """Clearance of every link from the nearest obstacle, shape ``(..., n)``.

    A circle's clearance is the segment-to-centre distance minus the radius; a
    polygon's is the segment-to-polygon distance (0 when they intersect). With
    no obstacles every clearance is ``inf``. A value ``<= 0`` is a collision.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> link_clearances(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)]).tolist()
    [0.6180339887498949, 0.5]
    """
    k = collision_kernel.loaded(np.size(q) // arm.n)
    if k is None:
        from rapp import reference

        return reference.link_clearances(arm, q, obstacles)
    packed = pack(obstacles)
    q = _checked(arm, q)
    return k.clearances(arm.lengths, q.reshape(-1, arm.n), *packed).reshape(q.shape)


def segment_clearances(a, b, obstacles) -> np.ndarray:
    """Clearance of segments ``ab`` (..., 2) from the nearest obstacle, shape ``(...)``.

    The link-level work of :func:`link_clearances`, for callers that already
    hold the segment end points (e.g. one link on a whole grid).

    Examples
    --------
    >>> from rapp import Circle
    >>> float(segment_clearances(np.array([0.0, 0.0]), np.array([2.0, 0.0]), [Circle((1.0, 1.0), 0.5)]))
    0.5
    """
    out = np.full(np.broadcast_shapes(a.shape, b.shape)[:-1], np.inf)
    circles = [ob for ob in obstacles if isinstance(check_obstacle(ob), Circle)]
    if circles:
        # Every disc in one broadcast (discs on a new last axis): the arithmetic of one disc at
        # a time with a fixed number of numpy calls.
        centers = np.array([c.center for c in circles])
        radii = np.array([c.radius for c in circles])
        d = segment_point_distance(a[..., None, :], b[..., None, :], centers) - radii
        np.minimum(out, d.min(axis=-1), out=out)
    for ob in obstacles:
        if not isinstance(ob, Circle):
            np.minimum(out, segment_polygon_distance(a, b, ob), out=out)
    return out


def collides(arm: Arm, q: ArrayLike, obstacles: Iterable[Circle | Polygon]) -> np.ndarray:
    """True where a configuration puts any link on any obstacle (touching counts).

    Parameters
    ----------
    arm : Arm
    q : array_like, shape (..., n)
    obstacles : iterable of Circle and Polygon

    Returns
    -------
    ndarray of bool, shape ``q.shape[:-1]``

    Examples
    --------
    >>> from rapp import Arm, Circle, Polygon
    >>> arm = Arm([1.0, 1.0])
    >>> obs = [Circle((1.75, 0.75), 0.6), Polygon.rectangle((-2, -2), 1, 1)]
    >>> collides(arm, [[0.4, 0.0], [np.pi / 2, 0.0], [-2.4, 0.0]], obs).tolist()
    [True, False, True]
    """
    n = arm.n
    if type(q) is np.ndarray and q.shape == (n,) and q.dtype == np.float64:
        # One configuration, as the sampling planners ask: the shortest way to the kernel.
        k = collision_kernel.loaded(1)
        if k is not None:
            hit = k.collides_one(arm.lengths, q, *pack(obstacles), MAX_ANGLE)
            if hit < 0:  # the kernel checks the angles' range; the message is check_q's
                arm.check_q(q)
            return _ANSWER[hit]
    k = collision_kernel.loaded(np.size(q) // n)
    if k is None:
        from rapp import reference

        return reference.collides(arm, q, obstacles)
    packed = pack(obstacles)
    if type(q) is not np.ndarray or q.dtype != np.float64 or not q.ndim or q.shape[-1] != n:
        q = arm.check_q(q)
    hit, ok = k.collides(arm.lengths, q.reshape(-1, n), *packed, MAX_ANGLE)
    if not ok:  # the kernel checks the angles' range; the message is check_q's
        arm.check_q(q)
    return hit[0] if q.ndim == 1 else hit.reshape(q.shape[:-1])


def _checked(arm, q):
    """``arm.check_q(q)``, with the common case (a float array in range) in two numpy calls."""
    if type(q) is np.ndarray and q.dtype == np.float64 and q.ndim and q.shape[-1] == arm.n \
            and q.size and np.abs(q).max() <= MAX_ANGLE:
        return q
    return arm.check_q(q)


def clearance(arm: Arm, q: ArrayLike, obstacles: Iterable[Circle | Polygon]) -> np.ndarray:
    """Smallest distance from any link to any obstacle, shape ``(...)``; ``<= 0`` is a collision.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> float(clearance(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.0, 1.0), 0.5)]))
    0.5
    """
    return link_clearances(arm, q, obstacles).min(axis=-1)


def motion_bounds(arm, dq) -> np.ndarray:
    """Bound on how far any point of each link moves along a straight joint-space step ``dq``.

    Returns ``B`` of shape ``(..., n)`` with

    ``B_j = sum_{i <= j} |dq_i| R_ij``,  ``R_ij = L_i + ... + L_j``.

    Proof. Along ``q(t) = q0 + t dq`` (``0 <= t <= 1``) take a point ``x`` of
    link ``j``. Turning joint ``i`` (relative angles) rotates everything beyond
    it rigidly about joint ``i``'s position ``p_i``, so
    ``dx/dt = sum_{i <= j} dq_i J(x - p_i)`` with ``J`` the 90° rotation, and
    ``|x - p_i| <= L_i + ... + L_j = R_ij`` by the triangle inequality along the
    chain. Hence ``|dx/dt| <= B_j`` and over a parameter interval of length
    ``h`` the point moves at most ``B_j h``. ``R_ij`` never exceeds the
    whole-arm bound ``R_i = sum_{k >= i} L_k``.

    Examples
    --------
    >>> from rapp import Arm
    >>> motion_bounds(Arm([1.0, 1.0]), [0.1, 0.0]).tolist()   # rotating the base by 0.1
    [0.1, 0.2]
    """
    dq = np.abs(arm.check_q(dq, "dq", max_abs=np.inf))
    # Finite steps times finite lengths can still exceed float64; inf is then the true bound.
    with np.errstate(over="ignore"):
        return dq @ reach_matrix(arm)


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


def segment_collision_free(arm: Arm, q0: ArrayLike, q1: ArrayLike, obstacles: Iterable[Circle | Polygon], *,
                           min_interval: float = 1e-9,
                           max_intervals: int = MAX_PENDING_INTERVALS) -> np.ndarray:
    """Certify that every configuration on the joint-space segments ``q0 → q1`` is free.

    The straight segment ``q(t) = q0 + t (q1 - q0)``, ``t in [0, 1]``, is
    covered by intervals. For an interval of length ``h`` around a sample
    ``t_m`` where link ``j`` has clearance ``d_j > 0``, every point of link
    ``j`` stays within ``B_j h / 2`` of where it is at ``t_m``
    (:func:`motion_bounds`), and the distance to an obstacle changes by no more
    than the points move, so the interval is free when ``B_j h / 2 < d_j`` for
    every link. This is a proof, not a sampling resolution. Intervals not
    certified are bisected; a sample that collides makes the segment not free;
    an interval shorter than ``min_interval`` still uncertified (the arm
    grazes an obstacle, clearance about 0) also counts as not free, which is
    conservative and agrees with "touching counts".

    Segments are processed together as arrays, in groups of up to 256 with
    all their pending intervals; the loop runs over bisection levels. At most
    ``max_intervals`` intervals are pending at once, which bounds the memory
    (about 50 bytes per interval) and the work. A segment that would need more
    raises :class:`~rapp.errors.CertificationLimit` instead of running for
    minutes: that happens only when the arm is huge relative to its clearance
    (e.g. links of 1e20 beside an obstacle at distance 1), and the message
    gives both numbers.

    Angles are taken as given: for a wrapping joint, pass unwrapped values
    (e.g. ``q1 = q0 + step`` across the ``±pi`` seam), otherwise the segment
    goes the long way round.

    Parameters
    ----------
    arm : Arm
    q0, q1 : array_like, shape (..., n)
    obstacles : iterable of Circle and Polygon
    min_interval : float
        Shortest parameter interval examined before giving up (conservatively).
    max_intervals : int
        Most sub-intervals pending at once (:data:`MAX_PENDING_INTERVALS`).

    Returns
    -------
    ndarray of bool, shape (...)

    Raises
    ------
    ValueError
        ``q0`` or ``q1`` is not a finite configuration of the arm, or an
        obstacle or a keyword argument is invalid.
    CertificationLimit
        (a ValueError) A segment needs more than ``max_intervals`` pending
        sub-intervals.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((0.0, 1.5), 0.3)]
    >>> segment_collision_free(arm, [[0.0, 0.0], [0.0, 0.0]], [[0.5, 0.0], [3.0, 0.0]], obs).tolist()
    [True, False]
    """
    k = collision_kernel.loaded(max(np.size(q0), np.size(q1)) // arm.n)
    if k is None:
        from rapp import reference

        return reference.segment_collision_free(arm, q0, q1, obstacles, min_interval=min_interval,
                                                max_intervals=max_intervals)
    packed = pack(obstacles)
    q0, q1, dq, bounds, shape, min_interval, cap = check_segments(arm, q0, q1, min_interval,
                                                                  max_intervals)
    if not len(obstacles):
        return np.ones(shape, dtype=bool)
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    code = k.certify(arm.lengths, q0, dq, bounds, *packed, min_interval, cap, touch)
    if (code < 0).any():  # more intervals than allowed: the numpy version raises the message
        from rapp import reference

        i = int(np.argmax(code < 0))
        reference.segment_collision_free(arm, q0[i], q1[i], obstacles, min_interval=min_interval,
                                         max_intervals=cap)
    return (code > 0).reshape(shape)


def path_collision_free(arm: Arm, path_q: ArrayLike, obstacles: Iterable[Circle | Polygon], *,
                        min_interval: float = 1e-9,
                        max_intervals: int = MAX_PENDING_INTERVALS) -> np.ndarray:
    """True where every straight joint-space segment of a polyline is certified free.

    Parameters
    ----------
    path_q : array_like, shape (..., k, n)
        ``k >= 1`` configurations; wrapping joints must be unwrapped by the
        caller (``np.unwrap`` along the path) so that consecutive angles differ
        by the intended short step.
    min_interval, max_intervals
        Passed to :func:`segment_collision_free`.

    Returns
    -------
    bool, or ndarray of bool of shape ``(...)``

    Raises
    ------
    ValueError
        ``path_q`` is not an array of finite configurations of the arm.
    CertificationLimit
        See :func:`segment_collision_free`.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((0.0, 1.5), 0.3)]
    >>> bool(path_collision_free(arm, [[0.0, 0.0], [0.5, 0.0], [0.5, -1.0]], obs))
    True
    """
    p = arm.check_q(path_q, "path_q")
    if p.ndim < 2 or p.shape[-2] < 1:
        raise ValueError(f"path_q must have shape (..., k, {arm.n}) with k >= 1, got {p.shape}")
    if p.shape[-2] == 1:
        ok = ~collides(arm, p[..., 0, :], obstacles)
    else:
        ok = segment_collision_free(
            arm, p[..., :-1, :], p[..., 1:, :], obstacles, min_interval=min_interval,
            max_intervals=max_intervals,
        ).all(axis=-1)
    return ok if ok.ndim else bool(ok)
