"""Static obstacles: circles (A5) and convex polygons (LC2; seed 003's rectangles).

Obstacles are values: frozen dataclasses validated on construction. Collision
tests live in :mod:`rapp.collision`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from rapp.arm import MAX_COORDINATE

__all__ = ["Circle", "Polygon", "grown", "applies", "check_links"]

#: A rectangle's width and height must each be at least this fraction of its
#: largest dimension (the other side, or the corner's distance from the axes).
#: float64 keeps about 16 digits, so below this ratio the corner's rounding
#: would visibly distort the rectangle or merge its vertices.
RECTANGLE_MIN_RATIO = 1e-9

# Turns of consecutive edges must exceed this fraction of the largest squared
# edge: a smaller turn is a straight angle blurred by rounding.
_STRICT = 1e-12


@dataclass(frozen=True)
class Circle:
    """A disc of centre ``center`` and radius ``radius`` (touching counts as collision).

    Examples
    --------
    >>> Circle((1.75, 0.75), 0.6)
    Circle(center=(1.75, 0.75), radius=0.6)
    """

    center: tuple
    radius: float
    #: The links (0-based) this obstacle applies to, or None for every link. Set on the
    #: pieces :func:`grown` makes for one link's distance; a scenario's obstacles keep None.
    links: tuple | None = field(default=None, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "links", check_links(self.links))
        try:
            c = np.asarray(self.center, dtype=float)
        except (TypeError, ValueError):
            c = np.full(1, np.nan)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise ValueError(f"circle center must be two finite numbers, got {self.center!r}")
        try:
            r = float(self.radius)
        except (TypeError, ValueError):
            r = np.nan
        if not np.isfinite(r) or r <= 0:
            raise ValueError(f"circle radius must be finite and > 0, got {self.radius!r}")
        # The disc reaches |center| + radius from the axes.
        for value, name in ((r, "radius"), (np.abs(c).max() + r, "center")):
            if value > MAX_COORDINATE:
                raise ValueError(
                    f"circle {name} puts the disc beyond {MAX_COORDINATE:g} of the axes "
                    f"(rapp.arm.MAX_COORDINATE), got center {self.center!r}, radius {self.radius!r}"
                )
        object.__setattr__(self, "center", (float(c[0]), float(c[1])))
        object.__setattr__(self, "radius", r)

    def contains(self, points) -> np.ndarray:
        """True where a point of shape ``(..., 2)`` lies in the closed disc.

        Examples
        --------
        >>> Circle((0, 0), 1.0).contains([[1.0, 0.0], [1.0, 0.1]]).tolist()
        [True, False]
        """
        d = _points(points) - np.array(self.center)
        # A point so far away that |d|^2 overflows is outside: inf <= r^2 is False.
        with np.errstate(over="ignore"):
            return np.einsum("...i,...i->...", d, d) <= self.radius**2


def check_links(links):
    """``links`` as a sorted tuple of distinct link indices (ints >= 0), or None (every link).

    Examples
    --------
    >>> check_links([2, 0]), check_links(None)
    ((0, 2), None)
    >>> check_links([-1])
    Traceback (most recent call last):
    ...
    ValueError: links must be None or a non-empty list of link indices >= 0, got [-1]
    """
    if links is None:
        return None
    bad = ValueError(f"links must be None or a non-empty list of link indices >= 0, got {links!r}")
    try:
        out = tuple(sorted({int(i) for i in links}))
    except (TypeError, ValueError):
        raise bad from None
    if not out or out[0] < 0 or any(int(i) != i for i in links):
        raise bad
    return out


def applies(ob, link: int) -> bool:
    """True when obstacle ``ob`` applies to link ``link`` (its :attr:`~Circle.links` hold it).

    Examples
    --------
    >>> applies(Circle((0, 0), 1.0), 3), applies(Circle((0, 0), 1.0, links=(0,)), 3)
    (True, False)
    """
    return ob.links is None or link in ob.links


def grown(ob, distance: float, links=None) -> tuple:
    """Exact convex pieces whose union is ``ob`` grown by ``distance`` (its Minkowski sum with a disc).

    Every point within ``distance`` of the obstacle, and no other, lies in one of the
    pieces. A disc of radius ``r`` grows into the disc of radius ``r + distance``. A
    convex polygon grows into itself, a rectangle of depth ``distance`` outside each
    edge, and a disc of radius ``distance`` at each vertex: the nearest point of the
    polygon to a point outside it lies inside an edge (the point is in that edge's
    rectangle) or at a vertex (the point is in that vertex's disc). These are the shapes
    rapp already tests and paints in closed form, so a segment is within ``distance`` of
    ``ob`` exactly when it touches a piece: a link of radius ``r`` (a capsule) keeps a
    margin ``m`` from ``ob`` exactly when its centre segment misses ``grown(ob, r + m)``.

    Parameters
    ----------
    ob : Circle or Polygon
    distance : float
        Finite and ``>= 0``; 0 gives ``ob`` itself. An edge's rectangle thinner than
        float64 can store (below about 4e-12 of the edge, or 4e-15 of the vertices'
        coordinates) is widened to that thickness: the pieces then hold points up to
        that rounding distance farther, never fewer.
    links : sequence of int, optional
        The :attr:`Circle.links` of every piece (default: those of ``ob``).

    Raises
    ------
    ValueError
        Naming ``distance``.

    Examples
    --------
    >>> grown(Circle((0, 0), 1.0), 0.5)
    (Circle(center=(0.0, 0.0), radius=1.5),)
    >>> pieces = grown(Polygon.rectangle((0, 0), 2, 1), 0.1)
    >>> len(pieces), sum(isinstance(p, Circle) for p in pieces)    # itself, 4 rectangles, 4 discs
    (9, 4)
    >>> any(bool(p.contains((2.05, 1.05))) for p in pieces), any(bool(p.contains((2.08, 1.08))) for p in pieces)
    (True, False)
    """
    d = _number(distance, "distance")
    if not (np.isfinite(d) and d >= 0):
        raise ValueError(f"distance must be a finite number >= 0, got {distance!r}")
    links = ob.links if links is None else check_links(links)
    if d == 0:
        return (ob if links == ob.links else replace(ob, links=links),)
    if isinstance(ob, Circle):
        return (Circle(ob.center, ob.radius + d, links=links),)
    v = ob.array
    e = np.roll(v, -1, axis=0) - v
    # Outward normals of a polygon stored counter-clockwise: the edge turned a quarter clockwise.
    nrm = np.stack((e[:, 1], -e[:, 0]), axis=-1) / np.hypot(e[:, 0], e[:, 1])[:, None]
    pieces = [ob if links == ob.links else replace(ob, links=links)]
    for k in range(len(v)):
        a, b = v[k], v[(k + 1) % len(v)]
        # A rectangle thinner than float64 resolves beside its edge and corners (about 1e-12 of
        # them) cannot be stored: it is widened to the thinnest that can, which only adds
        # points at rounding distance (a test stays conservative: it never misses a hit).
        depth = max(d, 4e-12 * float(np.abs(e[k]).max()), 16 * np.finfo(float).eps * float(np.abs(v).max()))
        try:
            pieces.append(Polygon((a, b, b + depth * nrm[k], a + depth * nrm[k]), links=links))
        except ValueError:
            raise ValueError(
                f"distance {d:g} is too small beside an edge of length {np.hypot(*e[k]):g} at "
                f"{tuple(a.tolist())}: float64 cannot tell the grown edge's rectangle from a line"
            ) from None
        pieces.append(Circle(a, d, links=links))
    return tuple(pieces)


def _points(points) -> np.ndarray:
    """``points`` as a float array ``(..., 2)``, or a ValueError naming ``points``."""
    try:
        p = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"points must be an array of shape (..., 2), got {points!r}") from None
    if p.ndim == 0 or p.shape[-1] != 2:
        raise ValueError(f"points must have shape (..., 2), got {p.shape}")
    if np.isnan(p).any():
        raise ValueError("points must not be NaN")
    return p


def _number(value, name: str) -> float:
    """``value`` as a float, or a ValueError naming ``name``."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None


def _turns(edges):
    """Cross products of consecutive edges (the turn at each vertex) and the next edges."""
    nxt = np.roll(edges, -1, axis=0)
    return edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0], nxt


@dataclass(frozen=True)
class Polygon:
    """A convex polygon, vertices stored counter-clockwise.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        At least three distinct finite points in order (either orientation)
        forming a strictly convex polygon of positive area that goes round
        once (a star such as a pentagram turns the same way at every vertex
        but is refused), within :data:`rapp.arm.MAX_COORDINATE` of the axes.

    Raises
    ------
    ValueError
        Naming ``vertices`` and what is wrong with them.

    Examples
    --------
    >>> square = Polygon.rectangle((0, 0), 2, 1)
    >>> square.vertices
    ((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0))
    >>> bool(square.contains((1.0, 0.5)))
    True
    >>> t = 2 * np.pi * np.arange(5) / 5
    >>> Polygon(np.c_[np.cos(2 * t), np.sin(2 * t)])       # a pentagram
    Traceback (most recent call last):
    ...
    ValueError: vertices wind 2 times around: the edges cross (a star such as a pentagram), ...
    """

    vertices: tuple
    #: As :attr:`Circle.links`: the links this obstacle applies to, None for every link.
    links: tuple | None = field(default=None, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "links", check_links(self.links))
        try:
            v = np.asarray(self.vertices, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"vertices must be a (k, 2) array of numbers, got {self.vertices!r}") from None
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
            raise ValueError(f"vertices must be at least 3 points of 2 numbers, got shape {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"vertices must be finite numbers, got {v.tolist()}")
        if np.abs(v).max() > MAX_COORDINATE:
            raise ValueError(
                f"vertices must lie within {MAX_COORDINATE:g} of the axes "
                f"(rapp.arm.MAX_COORDINATE), got {v.tolist()}"
            )
        edges = np.roll(v, -1, axis=0) - v
        same = np.flatnonzero(np.all(edges == 0, axis=1))
        if same.size:
            i = int(same[0])
            raise ValueError(
                f"vertices must be distinct: vertices[{(i + 1) % len(v)}] repeats "
                f"vertices[{i}] = {tuple(v[i].tolist())}"
            )
        cross, nxt = _turns(edges)
        tol = _STRICT * np.abs(edges).max() ** 2
        if np.all(np.abs(cross) <= tol):
            raise ValueError(f"vertices are collinear: the polygon has no area, got {v.tolist()}")
        given = v
        if cross.sum() < 0:
            v = v[::-1]
            edges = np.roll(v, -1, axis=0) - v
            cross, nxt = _turns(edges)
        if np.any(cross <= tol):
            raise ValueError(
                "vertices must form a strictly convex polygon, in order: at some vertex the "
                f"boundary runs straight on or turns the other way, got {given.tolist()}"
            )
        # Every turn is now a left turn in (0, pi); they add up to a whole number of
        # turns, exactly one for a convex polygon. Two or more is a star such as a
        # pentagram: its edges cross, and its hull and its interior differ.
        turning = float(np.arctan2(cross, np.einsum("ij,ij->i", edges, nxt)).sum())
        if turning > 3 * np.pi:
            raise ValueError(
                f"vertices wind {turning / (2 * np.pi):.0f} times around: the edges cross (a star "
                "such as a pentagram), so they do not form a simple convex polygon"
            )
        object.__setattr__(self, "vertices", tuple((float(x), float(y)) for x, y in v))

    @classmethod
    def rectangle(cls, corner, width: float, height: float, angle: float = 0.0) -> "Polygon":
        """A rectangle from its corner, rotated by ``angle`` (radians, CCW) about that corner.

        This is how seed 003 places its obstacles: corner, width, height and
        orientation.

        Raises
        ------
        ValueError
            Naming ``corner``, ``width``, ``height`` or ``angle``. Besides
            non-finite or non-positive values, a side shorter than
            :data:`RECTANGLE_MIN_RATIO` times the other side or the corner's
            coordinates is refused: rounding would distort the rectangle.

        Examples
        --------
        >>> np.round(Polygon.rectangle((1, 1), 2, 1, np.pi / 2).array, 12).tolist()
        [[1.0, 1.0], [1.0, 3.0], [0.0, 3.0], [0.0, 1.0]]
        >>> Polygon.rectangle((1e17, 0.0), 1.0, 1.0)
        Traceback (most recent call last):
        ...
        ValueError: corner (1e+17, 0.0) is too far from the origin for a 1 x 1 rectangle: ...
        """
        try:
            c = np.asarray(corner, dtype=float)
        except (TypeError, ValueError):
            c = np.full(1, np.nan)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise ValueError(f"corner must be two finite numbers, got {corner!r}")
        w, h, a = (_number(v, name) for v, name in ((width, "width"), (height, "height"), (angle, "angle")))
        for value, name in ((w, "width"), (h, "height")):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and > 0, got {value!r}")
        if not np.isfinite(a):
            raise ValueError(f"angle must be finite, got {angle!r}")
        # The corner is the farthest point from the origin by at most w + h.
        for value, name in ((w, "width"), (h, "height"), (np.abs(c).max() + w + h, "corner")):
            if value > MAX_COORDINATE:
                raise ValueError(
                    f"{name} puts the rectangle beyond {MAX_COORDINATE:g} of the axes "
                    f"(rapp.arm.MAX_COORDINATE), got corner {tuple(c.tolist())}, width {w:g}, height {h:g}"
                )
        for side, other, name, other_name in ((w, h, "width", "height"), (h, w, "height", "width")):
            if side < RECTANGLE_MIN_RATIO * other:
                raise ValueError(
                    f"{name} {side:g} is too small beside the {other_name} {other:g}: a side must be "
                    f"at least {RECTANGLE_MIN_RATIO:g} times the other "
                    "(rapp.obstacles.RECTANGLE_MIN_RATIO), or rounding flattens the rectangle"
                )
        if min(w, h) < RECTANGLE_MIN_RATIO * np.abs(c).max():
            raise ValueError(
                f"corner {tuple(c.tolist())} is too far from the origin for a {w:g} x {h:g} "
                f"rectangle: its sides must be at least {RECTANGLE_MIN_RATIO:g} times the corner's "
                "coordinates (rapp.obstacles.RECTANGLE_MIN_RATIO), or rounding merges its vertices"
            )
        local = np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        return cls(c + local @ rot.T)

    @cached_property
    def separating_axes(self) -> tuple:
        """``(vertices, normals, lo, hi)``: the polygon's edge normals and its projection on each.

        The separating-axis test projects a segment on these axes; the polygon's own
        projections never change, so they are computed once per polygon. Read-only arrays.

        Examples
        --------
        >>> v, normals, lo, hi = Polygon.rectangle((0, 0), 2, 1).separating_axes
        >>> normals.tolist(), lo.tolist(), hi.tolist()
        ([[0.0, -2.0], [1.0, 0.0], [0.0, 2.0], [-1.0, 0.0]], [-2.0, 0.0, 0.0, -2.0], [0.0, 2.0, 2.0, 0.0])
        """
        v = self.array
        e = np.roll(v, -1, axis=0) - v
        normals = np.stack((e[:, 1], -e[:, 0]), axis=-1)
        pv = v @ normals.T
        out = (v, normals, pv.min(axis=0), pv.max(axis=0))
        for arr in out:
            arr.setflags(write=False)
        return out

    @cached_property
    def edge_ends(self) -> tuple:
        """``(starts, ends)``: each edge's two vertices, ``(k, 2)`` each, read-only.

        Examples
        --------
        >>> Polygon([(0, 0), (1, 0), (0, 1)]).edge_ends[1].tolist()
        [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]
        """
        v = self.array
        out = (v, np.roll(v, -1, axis=0))
        for arr in out:
            arr.setflags(write=False)
        return out

    @property
    def array(self) -> np.ndarray:
        """Vertices as a ``(k, 2)`` float array (counter-clockwise).

        Examples
        --------
        >>> Polygon([(0, 0), (0, 1), (1, 0)]).array.tolist()   # given clockwise
        [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]
        """
        return np.array(self.vertices)

    def contains(self, points) -> np.ndarray:
        """True where a point of shape ``(..., 2)`` lies in the closed polygon.

        Examples
        --------
        >>> Polygon.rectangle((0, 0), 2, 1).contains([[2.0, 1.0], [2.0, 1.5]]).tolist()
        [True, False]
        """
        v = self.array
        e = np.roll(v, -1, axis=0) - v
        p = _points(points)[..., None, :] - v
        # Only a point far outside (beyond 1e200) can overflow here; its true cross product
        # on some edge is negative, and -inf or nan there fails the test as it should.
        with np.errstate(over="ignore", invalid="ignore"):
            cross = e[:, 0] * p[..., 1] - e[:, 1] * p[..., 0]
            return np.all(cross >= 0, axis=-1)
