"""Joint-space polylines: unwrapping, repeats, length, shortcutting, and what a planner returns.

A path is an array ``(k, n)`` of configurations joined by straight joint-space
segments. On a free joint the angle is *unwrapped* along a path (it may leave
``[-pi, pi)``) so that the straight segment between two waypoints is the short
way round, the motion the collision check certified. To be drawn, it is wrapped back
into the plot's range and broken where it crosses a seam (:func:`split_at_seam`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.obstacles import Circle, Polygon

from rapp.checks import sorted_unique

from rapp.arm import Arm
from rapp.collision import segment_collision_free

__all__ = ["PlannerResult", "tree_result", "STATUSES", "SOLVED", "TIME_BUDGET_SPENT", "ITERATION_CAP",
           "NODE_CAP", "NO_PATH", "GRID_TOO_COARSE", "unwrap_near", "unwrap_path", "drop_repeats", "path_length", "shortcut",
           "split_at_seam", "even_indices"]


#: Why a planner stopped (:attr:`PlannerResult.status`): it found a path; its ``time_budget`` was
#: spent; its ``max_iterations`` (or ``max_expansions``) were all run; its tree or roadmap
#: reached the most nodes it may hold; it proved that no path exists (on its grid, or because
#: the start or every goal collides); the grid holds a path that cannot be certified at its
#: resolution.
SOLVED, TIME_BUDGET_SPENT, ITERATION_CAP, NODE_CAP, NO_PATH, GRID_TOO_COARSE = STATUSES = (
    "solved", "time budget spent", "iteration cap", "node cap", "proved no path", "grid too coarse")


@dataclass(frozen=True, eq=False)
class PlannerResult:
    """What every planner returns (the contract of :mod:`rapp.planners`).

    Attributes
    ----------
    path : ndarray (k, n)
        From the exact start to a goal configuration, unwrapped: every straight segment
        between consecutive rows is certified collision-free. ``(0, n)`` on failure.
    success : bool
    cost : float
        Joint-space length of ``path`` (radians); ``inf`` on failure.
    details : mapping
        The planner's own: ``nodes``, ``parent``, ``iterations`` for trees and roadmaps;
        ``grid``, ``occupancy``, ``expanded``, ``metrics``, ``times`` for the grid search.
        Each is also read as an attribute (``result.nodes``), as before the contract.
    status : str
        Why the planner stopped, one of :data:`STATUSES`: ``"solved"`` exactly when
        ``success``; a failure says which limit stopped it (``"time budget spent"``,
        ``"iteration cap"``, ``"node cap"``) or that there is no path (``"proved no path"``).
        Given as ``""`` it is ``"solved"`` on success (a failure must say why).

    Examples
    --------
    >>> r = PlannerResult(np.array([[0.0, 0.0], [0.3, 0.4]]), True, 0.5, {"iterations": 7})
    >>> r.iterations, r.goal_q.tolist(), r.waypoints is r.path, r.status
    (7, [0.3, 0.4], True, 'solved')
    """

    path: np.ndarray
    success: bool
    cost: float
    details: Mapping = field(default_factory=dict)
    status: str = ""

    def __post_init__(self):
        status = self.status or (SOLVED if self.success else "")
        if status not in STATUSES or (status == SOLVED) != bool(self.success):
            raise ValueError(f"status must be one of {STATUSES}, 'solved' exactly on success; "
                             f"got {self.status!r} with success={self.success}")
        object.__setattr__(self, "status", status)

    def __getattr__(self, name):
        # Only called when normal lookup fails: the planner's own details read as attributes.
        if name.startswith("__") or name == "details":
            raise AttributeError(name)
        try:
            return self.details[name]
        except KeyError:
            raise AttributeError(f"this planner's result has no {name!r} (its details: "
                                 f"{', '.join(self.details) or 'none'})") from None

    @property
    def waypoints(self) -> np.ndarray:
        """``path``, by the name the pipeline uses."""
        return self.path

    @property
    def certified(self) -> bool:
        """False when the path relied on a user's ``validity`` checker (:mod:`rapp.validity`),
        which is sampled, not certified (``details["checked_by"]`` says at which step); True
        when every segment is proved free of rapp's obstacles alone."""
        return bool(self.details.get("certified", True))

    @property
    def goal_q(self) -> np.ndarray:
        """The goal configuration reached: the last waypoint."""
        return self.path[-1]


def tree_result(arm: Arm, path, nodes, parent, iterations: int, status: str = "") -> PlannerResult:
    """A tree or roadmap planner's result: success when ``path`` is given (else None, and
    ``status`` says why it stopped, one of :data:`STATUSES`).

    Examples
    --------
    >>> r = tree_result(Arm([1.0]), None, np.zeros((1, 1)), np.array([-1]), 5, ITERATION_CAP)
    >>> r.success, r.cost, r.path.shape, r.iterations, r.status
    (False, inf, (0, 1), 5, 'iteration cap')
    """
    details = {"nodes": nodes, "parent": parent, "iterations": int(iterations)}
    if path is None:
        return PlannerResult(np.empty((0, arm.n)), False, float("inf"), details, status)
    return PlannerResult(path, True, path_length(path), details)


def unwrap_near(arm: Arm, q, ref) -> np.ndarray:
    """``q`` moved by whole turns on free joints to lie within pi of ``ref``.

    Examples
    --------
    >>> unwrap_near(Arm([1.0, 1.0]), [-3.0, 0.0], [3.0, 0.0]).round(4).tolist()
    [3.2832, 0.0]
    """
    q = np.asarray(q, float)
    return np.where(arm.limited, q, np.asarray(ref, float) + arm.joint_delta(ref, q))


def unwrap_path(arm: Arm, path) -> np.ndarray:
    """Unwrap free-joint columns so consecutive configurations differ by the short way.

    Examples
    --------
    >>> unwrap_path(Arm([1.0]), [[3.0], [-3.0]]).round(4).tolist()
    [[3.0], [3.2832]]
    """
    path = np.asarray(path, float).copy()
    free = ~arm.limited
    if free.any() and len(path) > 1:
        path[:, free] = np.unwrap(path[:, free], axis=0)
    return path


def drop_repeats(path, eps: float = 1e-12) -> np.ndarray:
    """Drop consecutive repeats (zero-length segments); the last waypoint is always kept.

    Examples
    --------
    >>> drop_repeats([[0.0], [0.0], [1.0], [1.0]]).tolist()
    [[0.0], [1.0]]
    """
    path = np.asarray(path, float)
    if len(path) < 2:
        return path
    keep = np.concatenate(([True], np.linalg.norm(np.diff(path, axis=0), axis=1) > eps))
    keep[-1] = True
    out = path[keep]
    if len(out) >= 2 and np.linalg.norm(out[-1] - out[-2]) <= eps:
        out = np.delete(out, -2, axis=0)
    return out


def path_length(path) -> float:
    """Joint-space length of a polyline: the sum of its segments' Euclidean lengths (rad).

    Examples
    --------
    >>> path_length([[0.0, 0.0], [0.3, 0.4], [0.3, 1.4]])
    1.5
    """
    p = np.asarray(path, dtype=float)
    if p.shape[0] < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(p, axis=0), axis=-1).sum())


def shortcut(arm: Arm, path: ArrayLike, obstacles: Iterable[Circle | Polygon]) -> np.ndarray:
    """Greedy shortcutting: from each kept waypoint, jump to the farthest certified-free one.

    ``path`` (m, n) must be unwrapped with every consecutive segment certified
    free; the result keeps the first and last waypoints and every segment of it
    is certified free too. Each step tests all later waypoints in one batch.

    Examples
    --------
    >>> from rapp import Circle
    >>> arm = Arm([1.0, 1.0])
    >>> shortcut(arm, [[0, 0], [0.1, 0], [0.2, 0], [0.3, 0]], [Circle((0, 1.5), 0.3)]).tolist()
    [[0.0, 0.0], [0.3, 0.0]]
    """
    path = np.asarray(path, float)
    if len(path) <= 2:
        return path.copy()
    keep = [0]
    i = 0
    while i < len(path) - 1:
        free = segment_collision_free(arm, path[i], path[i + 1:], obstacles)
        ahead = np.flatnonzero(free)
        i = i + 1 + (int(ahead[-1]) if ahead.size else 0)
        keep.append(i)
    return path[keep]


def split_at_seam(path, lo, span, wraps):
    """Polyline of joint angles, broken with a NaN row where a wrapping joint crosses the seam.

    Angles of wrapping joints are wrapped into ``[lo, lo + span)``. At a
    crossing the line runs on past the border to where the unwrapped step
    ends, stops (NaN), and resumes from the matching point beyond the opposite
    border, so no drawn segment jumps across the plot.
    :mod:`rapp.plotting` draws joint paths with it.

    Parameters
    ----------
    path : array_like, shape (k, m)
    lo, span : array_like, shape (m,)
        Lower plot bound and period of each axis.
    wraps : array_like of bool, shape (m,)

    Examples
    --------
    >>> p = split_at_seam([[3.0, 0.0], [-3.0, 0.0]], [-np.pi] * 2, [2 * np.pi] * 2, [True, True])
    >>> np.round(p, 3).tolist()
    [[3.0, 0.0], [3.283, 0.0], [nan, nan], [-3.283, 0.0], [-3.0, 0.0]]
    """
    p = np.array(path, dtype=float, ndmin=2)
    lo = np.asarray(lo, dtype=float)
    span = np.asarray(span, dtype=float)
    wraps = np.asarray(wraps, dtype=bool)
    p = np.where(wraps, (p - lo) % span + lo, p)
    if len(p) < 2:
        return p
    step = np.diff(p, axis=0)
    short = np.where(wraps, (step + span / 2) % span - span / 2, step)
    jump = np.flatnonzero(np.any(np.abs(short - step) > 1e-9, axis=1))
    if jump.size == 0:
        return p
    nan = np.full((jump.size, p.shape[1]), np.nan)
    extra = np.stack((p[jump] + short[jump], nan, p[jump + 1] - short[jump]), axis=1)
    return np.insert(p, np.repeat(jump + 1, 3), extra.reshape(-1, p.shape[1]), axis=0)


def even_indices(k: int, most: int) -> np.ndarray:
    """At most ``most`` indices from ``0 .. k-1``, evenly spread, first and last included.

    The samples of a path a figure shows (ghost arms, animation frames).

    Examples
    --------
    >>> even_indices(10, 4).tolist()
    [0, 3, 6, 9]
    >>> even_indices(3, 8).tolist()
    [0, 1, 2]
    """
    return sorted_unique(np.linspace(0, k - 1, min(k, most)).round().astype(int))
