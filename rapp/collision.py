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
from rapp.checks import finite_number
from rapp.errors import CertificationLimit
from rapp.kernels import collision as collision_backend
from rapp.kernels.collision_numba import MASK_LINKS
from rapp.kernels.collision_numpy import (
    MAX_PENDING_INTERVALS,
    check_obstacle,
    check_segments,
    closest_point_on_segment,
    reach_matrix,
    segment_circle_distance,
    segment_clearances,
    segment_hits_circle,
    segment_hits_polygon,
    segment_point_distance,
    segment_polygon_distance,
)
from rapp.obstacles import Circle, Polygon, grown  # noqa: F401  (Circle, Polygon: doctests)

__all__ = [
    "closest_point_on_segment",
    "segment_point_distance",
    "segment_circle_distance",
    "segment_hits_circle",
    "line_distance_mis",
    "segment_hits_polygon",
    "segment_polygon_distance",
    "check_obstacle",
    "scene",
    "required_distances",
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
    "segment_distance",
    "self_pairs",
    "self_gaps",
    "self_clearance",
    "pair_bounds",
    "self_segment_free",
]


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
        return np.abs(ab[..., 0] * (a - c)[..., 1] - ab[..., 1] * (a - c)[..., 0]) / np.linalg.norm(ab, axis=-1)


def segment_distance(a, b, c, d) -> np.ndarray:
    """Distance between the segments ``a b`` and ``c d`` (points ``(..., 2)``), shape ``(...)``.

    Closed form: 0 when they cross (each segment's ends lie strictly on opposite sides of
    the other's line), otherwise the smallest of the four end-to-segment distances (two
    disjoint segments are closest at an end of one of them; segments that touch or overlap
    collinearly have an end on the other, distance 0).

    Examples
    --------
    >>> float(segment_distance([0, 0], [2, 0], [1, -1], [1, 1]))    # crossing
    0.0
    >>> float(segment_distance([0, 0], [1, 0], [2, 1], [3, 1]))     # end to end
    1.4142135623730951
    """
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))

    def cross(o, p, r):
        return (p - o)[..., 0] * (r - o)[..., 1] - (p - o)[..., 1] * (r - o)[..., 0]

    crossing = ((cross(a, b, c) * cross(a, b, d) < 0) & (cross(c, d, a) * cross(c, d, b) < 0))
    ends = np.minimum(np.minimum(segment_point_distance(a, b, c), segment_point_distance(a, b, d)),
                      np.minimum(segment_point_distance(c, d, a), segment_point_distance(c, d, b)))
    return np.where(crossing, 0.0, ends)


def self_pairs(n: int) -> tuple:
    """``(i, j)``: index arrays of the non-adjacent link pairs ``i < j - 1`` of an ``n``-link arm.

    Adjacent links share a joint (their distance is always 0), so only these pairs are tested.

    Examples
    --------
    >>> [p.tolist() for p in self_pairs(4)]
    [[0, 0, 1], [2, 3, 3]]
    """
    i, j = np.triu_indices(n, k=2)
    return i, j


def self_gaps(arm, q, *, margin=0.0) -> np.ndarray:
    """Gap of every non-adjacent link pair beyond the one required, ``(..., P)`` (:func:`self_pairs`).

    Pair ``(i, j)``'s value is the distance between the two links' centre segments
    (:func:`segment_distance`) minus ``pair_radius[i] + pair_radius[j] + margin``
    (:attr:`rapp.Arm.pair_radius`: the links' radii); ``<= 0`` is a self-collision.
    Computed whatever ``arm.self_collision`` says.

    Examples
    --------
    >>> from rapp import Arm
    >>> arm = Arm([1.0, 1.0, 1.0], link_radius=0.1)
    >>> self_gaps(arm, [0.0, 0.0, 0.0]).round(12).tolist()            # stretched: 1 m apart
    [0.8]
    >>> self_gaps(arm, [0.0, 2.5, 2.5]).round(6).tolist()             # folded back across link 0
    [-0.2]
    """
    q = arm.check_q(q)
    i, j = self_pairs(arm.n)
    p = arm.joint_positions_unchecked(q)
    r = np.asarray(arm.pair_radius, dtype=float)
    m = finite_number(margin, "margin")
    if m < 0:
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    dist = segment_distance(p[..., i, :], p[..., i + 1, :], p[..., j, :], p[..., j + 1, :])
    return dist - (r[i] + r[j] + m)


def self_clearance(arm, q, *, margin=0.0) -> np.ndarray:
    """Smallest :func:`self_gaps` over the pairs, shape ``(...)``; ``inf`` for fewer than 3 links.

    Examples
    --------
    >>> from rapp import Arm
    >>> float(self_clearance(Arm([1.0, 1.0]), [0.0, 3.0]))
    inf
    """
    g = self_gaps(arm, q, margin=margin)
    return g.min(axis=-1) if g.shape[-1] else np.full(g.shape[:-1], np.inf)


def pair_bounds(arm, dq) -> np.ndarray:
    """Bound on how much each non-adjacent pair's distance changes along a joint-space step ``dq``.

    Returns ``(..., P)`` (pairs of :func:`self_pairs`): for ``i < j``,
    ``C_ij = sum_{i < k <= j} |dq_k| R_kj``, ``R_kj = L_k + ... + L_j`` (:func:`reach_matrix`).

    Proof. Joints ``0..i`` turn links ``i`` and ``j`` together, rigidly, which leaves their
    distance unchanged. Seen from link ``i``'s frame, link ``i`` stands still and a point
    ``x`` of link ``j`` moves at speed at most ``sum_{i < k <= j} |dq_k| |x - p_k|`` with
    ``|x - p_k| <= R_kj`` (as in :func:`motion_bounds`), and the distance between the two
    links changes no faster than that. It never exceeds ``B_i + B_j`` of
    :func:`motion_bounds`, the bound with every joint counted for both links.

    Examples
    --------
    >>> from rapp import Arm
    >>> pair_bounds(Arm([1.0, 1.0, 1.0]), [5.0, 0.0, 0.1]).tolist()   # joint 0 moves both links
    [0.1]
    """
    dq = np.abs(np.asarray(dq, dtype=float))
    i, j = self_pairs(arm.n)
    reach = reach_matrix(arm)                       # (n, n): R[k, j]
    k = np.arange(arm.n)
    w = (k[:, None] > i) & (k[:, None] <= j)        # (n, P): joints that move j relative to i
    with np.errstate(over="ignore", invalid="ignore"):
        return dq @ np.where(w, reach[:, j], 0.0)


def self_segment_free(arm, q0, q1, *, margin=0.0, min_interval: float = 1e-9,
                      max_intervals: int = MAX_PENDING_INTERVALS) -> np.ndarray:
    """Certify that no non-adjacent link pair comes within its distance along ``q0 → q1``.

    The same proof as :func:`segment_collision_free` with pairs in place of obstacles: on a
    parameter interval of length ``h`` around ``t_m``, points of link ``j`` stay within
    ``B_j h / 2`` of where they are at ``t_m`` (:func:`motion_bounds`); sharper, pair
    ``(i, j)``'s gap changes by at most ``C_ij h / 2`` (:func:`pair_bounds`: the joints below
    both links turn them together and do not count); an interval is
    certified when every pair's gap at ``t_m`` exceeds that. Uncertified intervals are
    bisected; a sample with a gap ``<= 0``, or an interval shorter than ``min_interval``
    still uncertified, makes the segment not free. Computed in numpy (a loop over bisection
    levels, all segments and intervals as arrays), whatever ``arm.self_collision`` says.

    Returns
    -------
    ndarray of bool, shape (...)

    Examples
    --------
    >>> from rapp import Arm
    >>> arm = Arm([1.0, 1.0, 1.0], link_radius=0.05)
    >>> self_segment_free(arm, [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], [[0.0, 1.0, 1.0], [0.0, 2.6, 2.6]]).tolist()
    [True, False]
    """
    a = arm.check_q(q0, "q0")
    b = arm.check_q(q1, "q1")
    a, b = np.broadcast_arrays(a, b)
    shape = a.shape[:-1]
    a = a.reshape(-1, arm.n)
    dq = b.reshape(-1, arm.n) - a
    ok = np.ones(a.shape[0], bool)
    if arm.n < 3 or not a.shape[0]:
        return ok.reshape(shape)
    pb = pair_bounds(arm, dq)  # (segments, P)
    seg = np.arange(a.shape[0])
    lo = np.zeros(a.shape[0])
    h = np.ones(a.shape[0])
    while seg.size:
        mid = lo + h / 2
        gaps = self_gaps(arm, a[seg] + mid[:, None] * dq[seg], margin=margin)
        bad = (gaps <= 0).any(axis=-1)
        done = (gaps > pb[seg] * (h / 2)[:, None]).all(axis=-1)
        bad |= ~done & (h < min_interval)
        ok[seg[bad]] = False
        keep = ~done & ok[seg]
        seg, lo, h = seg[keep], lo[keep], h[keep]
        if seg.size * 2 > max_intervals:
            raise CertificationLimit(
                f"self-collision: a segment needs more than {max_intervals} pending sub-intervals "
                f"(links of total length {float(arm.lengths.sum()):g} m, smallest pair gap "
                f"{float(gaps.min()):g} m)")
        h = h / 2
        seg = np.concatenate([seg, seg])
        lo = np.concatenate([lo, lo + h])
        h = np.concatenate([h, h])
    return ok.reshape(shape)


def required_distances(arm, margin=0.0) -> np.ndarray:
    """The distance each link must keep from every obstacle: ``link_radius + margin``, ``(n,)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> required_distances(Arm([1.0, 1.0], link_radius=[0.1, 0.05]), margin=0.02).tolist()
    [0.12000000000000001, 0.07]
    """
    m = finite_number(margin, "margin")
    if m < 0:
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    return np.asarray(arm.link_radius, dtype=float) + m


_SCENES: dict = {}


def scene(arm, obstacles, margin=0.0) -> tuple:
    """``(arm0, pieces)``: the same collision question with zero-width links.

    Link ``j`` of ``arm`` (a capsule of radius ``arm.link_radius[j]``) keeps ``margin``
    from an obstacle exactly when its centre segment misses the obstacle grown by
    ``d_j = link_radius[j] + margin`` (:func:`rapp.obstacles.grown`). So every test here
    asks about ``arm0`` (``arm`` with zero-width links) and ``pieces``: each obstacle
    grown by each distinct ``d_j``, the pieces marked (:attr:`rapp.Circle.links`) with the
    links that keep that distance. With zero radii and margin this is ``(arm, obstacles)``
    itself; the same question returns the same (cached) pieces, so the compiled kernels
    pack them once.

    Raises
    ------
    ValueError
        Naming ``margin`` (finite and >= 0) or an obstacle; ``distance`` when a growth is
        too small for a polygon (see :func:`rapp.obstacles.grown`).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm0, pieces = scene(Arm([1.0, 1.0], link_radius=0.1), [Circle((2, 0), 0.5)], margin=0.05)
    >>> arm0.link_radius, pieces
    ((0.0, 0.0), (Circle(center=(2.0, 0.0), radius=0.65),))
    """
    need = required_distances(arm, margin)
    if not need.any():
        return arm, obstacles
    if not isinstance(obstacles, (list, tuple)):
        obstacles = tuple(obstacles)
    for ob in obstacles:
        check_obstacle(ob)
    key = (tuple(map(id, obstacles)), tuple(need.tolist()))
    hit = _SCENES.get(key)
    if hit is None:
        values = sorted(set(need.tolist()))
        if len(values) > 1 and arm.n > MASK_LINKS:
            raise ValueError(f"link_radius: links of different radii are supported on arms of at "
                             f"most {MASK_LINKS} links, got {arm.n}; give every link one radius")
        pieces = []
        for d in values:
            links = tuple(int(j) for j in np.flatnonzero(need == d))
            for ob in obstacles:
                mine = links if ob.links is None else tuple(j for j in links if j in ob.links)
                if mine:
                    pieces.extend(grown(ob, d, None if len(values) == 1 and ob.links is None else mine))
        if len(_SCENES) >= 64:
            _SCENES.clear()
        hit = _SCENES[key] = (tuple(obstacles), tuple(pieces))  # the obstacles kept: ids stay theirs
    return arm.centre_lines(float(margin)), hit[1]


def link_clearances(arm, q, obstacles, *, margin=0.0) -> np.ndarray:
    """Clearance of every link from the nearest obstacle, beyond the distance it must keep: ``(..., n)``.

    A circle's clearance is the segment-to-centre distance minus the radius; a
    polygon's is the segment-to-polygon distance (0 when they intersect). With
    no obstacles every clearance is ``inf``. A value ``<= 0`` is a collision.
    With link radii (:class:`rapp.Arm`) or a ``margin`` (metres, >= 0), link ``j``'s
    value is its centre segment's distance from the nearest obstacle minus
    ``link_radius[j] + margin`` (the gap left beyond the one required), measured
    against the grown obstacles of :func:`scene` (0 where it enters one).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> link_clearances(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)]).tolist()
    [0.6180339887498949, 0.5]
    >>> link_clearances(Arm([1.0, 1.0], link_radius=0.1), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)],
    ...                 margin=0.1).round(12).tolist()
    [0.418033988750, 0.3]
    """
    arm, obstacles = scene(arm, obstacles, margin)
    return collision_backend.link_clearances(arm, q, obstacles)


def collides(arm: Arm, q: ArrayLike, obstacles: Iterable[Circle | Polygon], *, margin: float = 0.0) -> np.ndarray:
    """True where a configuration puts any link on any obstacle (touching counts).

    Parameters
    ----------
    arm : Arm
        Its links are capsules of radius ``arm.link_radius`` (0: segments).
    q : array_like, shape (..., n)
    obstacles : iterable of Circle and Polygon
    margin : float
        Safety margin, >= 0: a link closer than ``link_radius + margin`` to an
        obstacle (or exactly that far) collides (:func:`scene`).

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
    >>> collides(arm, [[np.pi / 2, 0.0]], [Circle((0.5, 2.0), 0.3)], margin=0.2).tolist()
    [True]
    """
    # One configuration, as a planner's loop asks: the scene packed before, one compiled call,
    # which takes a 1-D float array only (anything else raises TypeError, and goes on below).
    try:
        entry = _ONE.get((id(arm), id(obstacles), margin))
        if entry is not None and (entry[2] is obstacles or entry[2] == obstacles):
            hit = entry[0](entry[1], q)
            if hit >= 0:  # else an angle out of range or a wrong length: check_q says which
                return _ANSWER[hit]
    except (TypeError, ValueError):  # an unhashable margin, q not a 1-D float array, ...:
        pass                         # the general path checks everything and says what is wrong
    thin, pieces = scene(arm, obstacles, margin)
    hit = collision_backend.collides(thin, q, pieces)
    if arm.self_collision and arm.n >= 3:
        hit = hit | (self_clearance(arm, q, margin=margin) <= 0)
    elif type(q) is np.ndarray and q.ndim == 1 and q.dtype is _FLOAT:
        _remember(arm, obstacles, margin, thin, pieces)
    return hit


#: ``collides``' answers of the one-configuration check, numpy's own booleans.
_ANSWER = (np.False_, np.True_)
_FLOAT = np.dtype(np.float64)
#: Scenes of :func:`collides` for one configuration, packed into one array
#: (:func:`rapp.kernels.collision.pack_scene`), by the identity of the arm and of the
#: obstacles, and the margin. Each entry holds the arm and the obstacles (a tuple as given, a
#: list as a copy, compared on every use: a list may change), so that no other object takes
#: their ids while it lives. Bounded: cleared at 64 entries.
_ONE: dict = {}


def _remember(arm, obstacles, margin, thin, pieces) -> None:
    """Keep the packed scene of a one-configuration call, once the compiled kernel is loaded."""
    k = collision_backend.loaded()
    if k is None or type(obstacles) not in (tuple, list):
        return
    if len(_ONE) >= 64:
        _ONE.clear()
    held = obstacles if type(obstacles) is tuple else list(obstacles)
    packed = collision_backend.pack_scene(thin.lengths, pieces, MAX_ANGLE)
    _ONE[(id(arm), id(obstacles), margin)] = (k.collides_scene, packed, held, arm)


def clearance(arm: Arm, q: ArrayLike, obstacles: Iterable[Circle | Polygon], *, margin: float = 0.0) -> np.ndarray:
    """Smallest distance from any link to any obstacle, shape ``(...)``; ``<= 0`` is a collision.

    With link radii or a ``margin``, the smallest gap beyond the one required
    (:func:`link_clearances`).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> float(clearance(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.0, 1.0), 0.5)]))
    0.5
    """
    return link_clearances(arm, q, obstacles, margin=margin).min(axis=-1)


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


def segment_collision_free(arm: Arm, q0: ArrayLike, q1: ArrayLike, obstacles: Iterable[Circle | Polygon], *,
                           min_interval: float = 1e-9,
                           max_intervals: int = MAX_PENDING_INTERVALS, margin: float = 0.0) -> np.ndarray:
    """Certify that every configuration on the joint-space segments ``q0 → q1`` is free.

    The straight segment ``q(t) = q0 + t (q1 - q0)``, ``t in [0, 1]``, is
    covered by intervals. For an interval of length ``h`` around a sample
    ``t_m`` where link ``j`` has clearance ``d_j > 0``, every point of link
    ``j`` stays within ``B_j h / 2`` of where it is at ``t_m``
    (:func:`motion_bounds`), and the distance to an obstacle changes by no more
    than the points move, so the interval is free when ``B_j h / 2 < d_j`` for
    every link. This is a proof, not a sampling resolution. It is asked with
    room for touching, ``B_j h / 2 + touch < d_j``, where ``touch`` (16 eps
    times the arm's length) is the clearance within which a link counts as
    touching: no point of a certified segment comes within it, so none leaves
    a configuration that touches. Intervals not
    certified are bisected; a sample that collides makes the segment not free;
    an interval shorter than ``min_interval`` still uncertified, or a sample
    whose clearance only intervals shorter than ``min_interval`` could cover
    (``d_j < B_j min_interval / 2``: the arm grazes an obstacle, clearance
    about 0), also counts as not free, which is conservative and agrees with
    "touching counts".

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
    margin : float
        Safety margin (>= 0) kept beyond the links' radii, as in :func:`collides`:
        the certificate runs on the obstacles grown by it (:func:`scene`), whose
        distance changes no faster than the links move.

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
    >>> [bool(segment_collision_free(arm, [0.0, 0.0], [0.5, 0.0], obs, margin=m)) for m in (1.0, 1.1)]
    [True, False]
    """
    thin, pieces = scene(arm, obstacles, margin)
    ok = collision_backend.segment_collision_free(thin, q0, q1, pieces, min_interval=min_interval,
                                                  max_intervals=max_intervals)
    if arm.self_collision and arm.n >= 3 and np.any(ok):
        # Self-collision in numpy after the compiled obstacle test, on the segments it left free.
        a, b = np.broadcast_arrays(arm.check_q(q0, "q0"), arm.check_q(q1, "q1"))
        ok = np.asarray(ok).copy()
        idx = np.flatnonzero(ok.reshape(-1))
        free = self_segment_free(arm, a.reshape(-1, arm.n)[idx], b.reshape(-1, arm.n)[idx],
                                 margin=margin, min_interval=min_interval, max_intervals=max_intervals)
        flat = ok.reshape(-1)
        flat[idx] = free
        ok = flat.reshape(ok.shape)
    return ok


def path_collision_free(arm: Arm, path_q: ArrayLike, obstacles: Iterable[Circle | Polygon], *,
                        min_interval: float = 1e-9,
                        max_intervals: int = MAX_PENDING_INTERVALS, margin: float = 0.0) -> np.ndarray:
    """True where every straight joint-space segment of a polyline is certified free.

    Parameters
    ----------
    path_q : array_like, shape (..., k, n)
        ``k >= 1`` configurations; wrapping joints must be unwrapped by the
        caller (``np.unwrap`` along the path) so that consecutive angles differ
        by the intended short step.
    min_interval, max_intervals, margin
        Passed to :func:`segment_collision_free` (``margin``: also to :func:`collides`).

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
        ok = ~collides(arm, p[..., 0, :], obstacles, margin=margin)
    else:
        ok = segment_collision_free(
            arm, p[..., :-1, :], p[..., 1:, :], obstacles, min_interval=min_interval,
            max_intervals=max_intervals, margin=margin,
        ).all(axis=-1)
    return ok if ok.ndim else bool(ok)
