"""Static obstacles: circles (A5) and convex polygons (LC2; seed 003's rectangles).

Obstacles are values: frozen dataclasses validated on construction. Collision
tests live in :mod:`rapp.collision`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Circle", "Polygon"]


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

    def __post_init__(self):
        c = np.asarray(self.center, dtype=float)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise ValueError(f"circle center must be two finite numbers, got {self.center!r}")
        r = float(self.radius)
        if not np.isfinite(r) or r <= 0:
            raise ValueError(f"circle radius must be finite and > 0, got {self.radius!r}")
        object.__setattr__(self, "center", (float(c[0]), float(c[1])))
        object.__setattr__(self, "radius", r)

    def contains(self, points) -> np.ndarray:
        """True where a point of shape ``(..., 2)`` lies in the closed disc.

        Examples
        --------
        >>> Circle((0, 0), 1.0).contains([[1.0, 0.0], [1.0, 0.1]]).tolist()
        [True, False]
        """
        d = np.asarray(points, dtype=float) - np.array(self.center)
        return np.einsum("...i,...i->...", d, d) <= self.radius**2


@dataclass(frozen=True)
class Polygon:
    """A convex polygon, vertices stored counter-clockwise.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        At least three finite points in order (either orientation) forming a
        strictly convex polygon of positive area.

    Examples
    --------
    >>> square = Polygon.rectangle((0, 0), 2, 1)
    >>> square.vertices
    ((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0))
    >>> bool(square.contains((1.0, 0.5)))
    True
    """

    vertices: tuple

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
            raise ValueError(f"polygon needs at least 3 vertices of 2 numbers, got shape {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError("polygon vertices must be finite numbers")
        edges = np.roll(v, -1, axis=0) - v
        nxt = np.roll(edges, -1, axis=0)
        cross = edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0]
        scale = np.abs(edges).max() ** 2
        if np.all(cross < -1e-12 * scale):
            v = v[::-1]
        elif not np.all(cross > 1e-12 * scale):
            raise ValueError("polygon must be strictly convex with vertices in order")
        object.__setattr__(self, "vertices", tuple((float(x), float(y)) for x, y in v))

    @classmethod
    def rectangle(cls, corner, width: float, height: float, angle: float = 0.0) -> "Polygon":
        """A rectangle from its corner, rotated by ``angle`` (radians, CCW) about that corner.

        This is how seed 003 places its obstacles: corner, width, height and
        orientation.

        Examples
        --------
        >>> np.round(Polygon.rectangle((1, 1), 2, 1, np.pi / 2).array, 12).tolist()
        [[1.0, 1.0], [1.0, 3.0], [0.0, 3.0], [0.0, 1.0]]
        """
        w, h, a = float(width), float(height), float(angle)
        if not (np.isfinite(w) and w > 0 and np.isfinite(h) and h > 0):
            raise ValueError(f"rectangle width and height must be finite and > 0, got {width}, {height}")
        if not np.isfinite(a):
            raise ValueError(f"rectangle angle must be finite, got {angle}")
        local = np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        return cls(np.asarray(corner, dtype=float) + local @ rot.T)

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
        p = np.asarray(points, dtype=float)[..., None, :] - v
        cross = e[:, 0] * p[..., 1] - e[:, 1] * p[..., 0]
        return np.all(cross >= 0, axis=-1)
