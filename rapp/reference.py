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
:func:`collides`                  :func:`rapp.collision.collides` (one configuration at a
                                  time, by :func:`capsule_distance`)
:func:`link_clearances`           :func:`rapp.collision.link_clearances` (likewise)
:func:`segment_collision_free`    :func:`rapp.collision.segment_collision_free` (one segment
                                  at a time, plain halving with :func:`motion_bound`)
:func:`link_gaps`                 :func:`rapp.collision.link_clearances` of thick links
                                  (a capsule's distance from each obstacle, one at a time,
                                  with no grown shapes: :func:`capsule_distance`)
================================  ==========================================================

The package never calls them, and they share no code with :mod:`rapp.kernels` (the compiled and
the numpy backends, which the tests compare with these): the collision oracles are Python loops
over configurations, links and obstacles with the textbook formulas (a disc by the clipped
projection, a convex polygon by containment and edge crossings) in :func:`capsule_distance`.

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

from rapp.checks import finite_number
# Only the contract's limit and the thick-link reduction (checked against capsule_distance in
# tests/test_thick_links.py): no geometry of the kernels, which this module is the oracle of.
from rapp.collision import MAX_PENDING_INTERVALS, scene
from rapp.cspace import check_grid
from rapp.errors import CertificationLimit
from rapp.obstacles import Circle, Polygon, applies

__all__ = ["occupancy", "certified_free", "circle_hits", "polygon_hits", "collides", "link_clearances",
           "segment_collision_free", "motion_bound", "capsule_distance", "link_gaps"]


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


def _prefix(grid, i):
    """Base point ``P`` (``cells[:i] + (2,)``) and absolute angle of link ``i - 1`` on the grid of
    joints ``0..i-1``, in the arm's own frame: the forward kinematics, summed link by link."""
    mesh = np.meshgrid(*grid.axes[:i], indexing="ij")
    P, phi = np.zeros(grid.shape[:i] + (2,)), np.zeros(grid.shape[:i])
    for k in range(i):
        phi = phi + mesh[k]
        P = P + grid.arm.link_lengths[k] * np.stack((np.cos(phi), np.sin(phi)), axis=-1)
    return P, phi


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
    arm, obstacles = scene(arm, _checked_obstacles(obstacles), margin)
    shape, n = grid.shape, arm.n
    occ = np.zeros(shape, dtype=bool)
    circles = [ob for ob in obstacles if isinstance(ob, Circle)]
    polys = [ob for ob in obstacles if not isinstance(ob, Circle)]
    axes = grid.axes
    for i in range(n):
        P, phi_prev = _prefix(grid, i)
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


def certified_free(arm, obstacles, grid, *, margin=0.0) -> np.ndarray:
    """:func:`rapp.cspace.certified_free` cell by cell: link ``j`` is certified on a cell when its
    gap (:func:`capsule_distance`, its radius plus ``margin``) exceeds half the largest motion
    of that link in one grid step (:func:`motion_bound` of each axis's step). Link ``j`` depends
    on joints ``0..j`` only: it is tested once per cell of that prefix grid.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> from rapp.cspace import JointGrid, certified_free as fast
    >>> arm, discs = Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)]
    >>> grid = JointGrid(arm, 24)
    >>> bool((certified_free(arm, discs, grid) == fast(arm, discs, grid)).all())
    True
    """
    check_grid(arm, grid)
    obstacles = _checked_obstacles(obstacles)
    margin = finite_number(margin, "margin", at_least=0.0)
    n, axes = arm.n, grid.axes
    steps = [motion_bound(arm, np.eye(n)[k] * grid.step[k]) for k in range(n)]
    out = np.ones(grid.shape, bool)
    for j in range(n):
        need = 0.5 * max(step[j] for step in steps)
        radius = float(arm.link_radius[j]) + margin
        prefix = grid.shape[: j + 1]
        ok = np.empty(prefix, bool)
        for cell in np.ndindex(*prefix):
            q = np.zeros(n)
            q[: j + 1] = [axes[k][i] for k, i in enumerate(cell)]
            pts = arm.joint_positions(q)
            gaps = [capsule_distance(pts[j], pts[j + 1], radius, ob) for ob in obstacles if applies(ob, j)]
            ok[cell] = min(gaps, default=math.inf) > need
        out &= ok.reshape(prefix + (1,) * (n - j - 1))
    return out


def _checked_obstacles(obstacles) -> list:
    """The obstacles as a list, each a Circle or a Polygon, else the package's one-line error."""
    obstacles = list(obstacles)
    for ob in obstacles:
        if not isinstance(ob, (Circle, Polygon)):
            raise ValueError(f"obstacles must be rapp.Circle or rapp.Polygon, got {type(ob).__name__}")
    return obstacles


def _clearances_of(arm, q, obstacles) -> list:
    """One configuration ``q`` ``(n,)``: each link's distance from its nearest obstacle, a list.

    The links are their centre segments (zero width); an obstacle counts for the links its
    ``links`` name (all when None). No obstacle: ``inf``.
    """
    pts = arm.joint_positions(q)
    out = []
    for j in range(arm.n):
        gaps = [capsule_distance(pts[j], pts[j + 1], 0.0, ob) for ob in obstacles if applies(ob, j)]
        out.append(min(gaps, default=math.inf))
    return out


def link_clearances(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.link_clearances` one configuration at a time, ``(..., n)``.

    Each link's distance from each obstacle by :func:`capsule_distance` with radius 0 (a disc:
    the centre's distance from the segment minus the radius; a polygon: 0 when the segment
    meets it, else the nearest vertex-to-edge distance), the least per link.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> link_clearances(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.5, 1.0), 0.5)]).round(12).tolist()
    [0.618033988750, 0.5]
    """
    q = arm.check_q(q)
    obstacles = _checked_obstacles(obstacles)
    rows = q.reshape(-1, arm.n)
    out = np.array([_clearances_of(arm, row, obstacles) for row in rows], dtype=float)
    return out.reshape(q.shape)


def collides(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.collides` one configuration at a time: some link's clearance is
    not positive (:func:`link_clearances`; touching counts as collision).

    Examples
    --------
    >>> from rapp import Arm, Circle, Polygon
    >>> arm = Arm([1.0, 1.0])
    >>> obs = [Circle((1.75, 0.75), 0.6), Polygon.rectangle((-2, -2), 1, 1)]
    >>> collides(arm, [[np.pi / 2, 0.0], [0.0, 0.4], [-2.4, 0.3]], obs).tolist()
    [False, True, True]
    """
    return (link_clearances(arm, q, obstacles) <= 0.0).any(axis=-1)


def motion_bound(arm, dq) -> list:
    """How far any point of link ``j`` can move along the joint step ``dq`` ``(n,)``: a list.

    Turning joint ``i`` moves the points beyond it on circles about joint ``i``, each at most
    ``L_i + ... + L_j`` from it on link ``j``, so no point of link ``j`` moves more than
    ``B_j = sum_{i <= j} |dq_i| (L_i + ... + L_j)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> motion_bound(Arm([1.0, 1.0]), [0.1, 0.0])
    [0.1, 0.2]
    """
    lengths = [float(x) for x in arm.lengths]
    return [sum(abs(float(dq[i])) * sum(lengths[i:j + 1]) for i in range(j + 1))
            for j in range(arm.n)]


def segment_collision_free(arm, q0, q1, obstacles, *, min_interval: float = 1e-9,
                           max_intervals: int = MAX_PENDING_INTERVALS) -> np.ndarray:
    """:func:`rapp.collision.segment_collision_free` one segment at a time, by plain halving.

    A piece ``[lo, hi]`` of the segment ``q0 + t (q1 - q0)`` is free when, at its middle, every
    link's clearance exceeds how far the link can move in half the piece
    (:func:`motion_bound` times ``(hi - lo) / 2``) by more than the touching distance below. A piece not shown free is halved; the segment
    is not free when a middle touches an obstacle (a clearance within the rounding of the arm's
    own coordinates, ``16 eps`` times its length, counts as touching), when a middle's clearance
    is one only pieces shorter than ``min_interval`` could show free (a graze), or when a piece
    shorter than ``min_interval`` is still not shown free. More than ``max_intervals`` pieces to look at, at
    once, raise :class:`~rapp.errors.CertificationLimit`.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((0.0, 1.5), 0.3)]
    >>> segment_collision_free(arm, [0.0, 0.0], [[0.5, 0.0], [3.0, 0.0], [1.2, 0.3]], obs).tolist()
    [True, False, True]
    """
    q0, q1 = np.broadcast_arrays(arm.check_q(q0, "q0"), arm.check_q(q1, "q1"))
    if not (float(min_interval) > 0 and int(max_intervals) >= 2):
        raise ValueError(f"need min_interval > 0 and max_intervals >= 2, got {min_interval}, {max_intervals}")
    min_interval, cap = float(min_interval), int(max_intervals)
    obstacles = _checked_obstacles(obstacles)
    starts, ends = q0.reshape(-1, arm.n), q1.reshape(-1, arm.n)
    free = [not obstacles or _halving(arm, a, b, obstacles, min_interval, cap)
            for a, b in zip(starts, ends)]
    return np.array(free, dtype=bool).reshape(q0.shape[:-1])


def _halving(arm, q0, q1, obstacles, min_interval, cap) -> bool:
    """Is the one segment ``q0 -> q1`` free? Its pieces halved, level by level."""
    dq = q1 - q0
    bound = motion_bound(arm, dq)
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    pieces = [(0.0, 1.0)]
    while pieces:
        if len(pieces) > cap:
            raise CertificationLimit(f"the segment q0={q0.tolist()} -> q1={q1.tolist()} needs more than "
                                     f"{cap} pieces at once to be certified")
        halves = []
        for lo, hi in pieces:
            mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
            d = _clearances_of(arm, q0 + mid * dq, obstacles)
            if min(d) <= touch or any(dj < b * 0.5 * min_interval for b, dj in zip(bound, d)):
                return False
            if all(b * half + touch < dj for b, dj in zip(bound, d)):
                continue
            if hi - lo < min_interval:
                return False
            halves += [(lo, mid), (mid, hi)]
        pieces = halves
    return True


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
