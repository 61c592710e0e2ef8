"""Bring your own checker: a user's validity function, sampled along joint-space motions.

rapp certifies its own obstacles (discs and polygons): a straight joint-space edge is *proved*
free (:func:`rapp.collision.segment_collision_free`). A constraint rapp does not model (a
keep-out zone for the tool, a cable's reach, a rule about the elbow) can be given to every
planner of the table as ``validity=``: a Python callable taking an ``(m, n)`` array of
configurations and returning ``m`` booleans, True where the configuration is allowed. rapp then
checks a motion as OMPL's ``DiscreteMotionValidator`` does: at points at most
``validity_resolution`` rad apart along each edge (joint-space Euclidean distance, the short way
round on a free joint), both ends included. Both tests must pass: rapp's certificate for its
obstacles and the user's checker at every sample.

A sampled check is not a proof. Between two samples the constraint may be broken where it is
thinner than the motion of one step, so a path found with a user checker says so: its result
carries ``certified=False`` and ``checked_by`` ("sampled at r rad, not certified"), and
:func:`rapp.verify` with the same checker reports it that way, never as certified. What the
samples do prove for a keep-out disc of the end effector: no sample is in the disc, and along a
step of at most ``r`` rad the end effector moves at most ``r * sqrt(sum_j R_j^2)``, ``R_j`` the
distance from joint ``j`` to the tip when the arm is straight (the sum of the lengths from link
``j`` on); so every point of the path keeps out of the disc shrunk by half that.

The user's function is called in batches (one call for all the samples of a batch of edges,
up to :data:`MAX_BATCH` configurations), never once per sample. The configurations it receives
are wrapped into the arm's joint bounds (free joints in ``[-pi, pi)``) when the planner passes
its arm. Its answer must be ``m`` booleans (dtype bool); anything else, or an exception it
raises, is one line naming ``validity`` (:class:`rapp.errors.InvalidSetting`).

Only Python code can pass a callable: a scenario file cannot carry one, so ``rapp plan`` and
:func:`rapp.plan` plan with rapp's obstacles only. The compiled (numba) loops cannot call
Python, so a planner given ``validity`` runs its numpy loop.

Examples
--------
>>> import numpy as np
>>> keep_right = lambda q: q[:, 0] > -0.5                  # joint 0 never below -0.5 rad
>>> edges_valid(keep_right, [[0.0, 0.0], [0.0, 0.0]], [[1.0, 0.0], [-1.0, 0.0]], 0.1).tolist()
[True, False]
>>> pts, counts = motion_samples([[0.0, 0.0]], [[0.25, 0.0]], 0.1)
>>> pts[:, 0].tolist(), counts.tolist()                      # 3 steps of 0.083 rad, ends included
([0.0, 0.08333333333333333, 0.16666666666666666, 0.25], [4])

References
----------
Sucan, Moll and Kavraki (2012), The Open Motion Planning Library: ``StateValidityChecker``,
``DiscreteMotionValidator``, ``setLongestValidSegmentFraction``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from rapp.errors import InvalidSetting

__all__ = ["ValidityFunction", "DEFAULT_RESOLUTION", "MIN_RESOLUTION", "MAX_RESOLUTION", "MAX_BATCH", "UserValidity",
           "user_validity", "check_configurations", "motion_samples", "edges_valid",
           "sampled_text", "mark_sampled", "end_effector_travel"]

#: A user's checker: an ``(m, n)`` array of configurations -> ``m`` booleans (True: allowed).
ValidityFunction = Callable[[np.ndarray], Any]

#: The default ``validity_resolution`` (rad): 0.01 rad, the joint accuracy the SRS asks of a
#: plan (NFR1). OMPL's default is a fraction (1 %) of its space's extent; here it is a step.
DEFAULT_RESOLUTION = 0.01
#: ``validity_resolution`` lies in ``[MIN_RESOLUTION, MAX_RESOLUTION]`` rad (the bounds of a
#: planner's ``step``: below 1e-6 rad no joint can be told apart).
MIN_RESOLUTION, MAX_RESOLUTION = 1e-6, float(np.pi)
#: Configurations handed to the user's function in one call at most.
MAX_BATCH = 1 << 16


def sampled_text(resolution: float) -> str:
    """How a path checked by a user's function was checked: the words results and reports use.

    Examples
    --------
    >>> sampled_text(0.01)
    'sampled at 0.01 rad, not certified'
    """
    return f"sampled at {resolution:g} rad, not certified"


def _one_line(err: BaseException) -> str:
    text = str(err).strip().splitlines()
    return type(err).__name__ + (f": {text[0]}" if text else "")


def check_configurations(validity: Callable, q) -> np.ndarray:
    """The user's answer for every configuration of ``q`` ``(m, n)``: bool ``(m,)``, checked.

    ``validity`` is called on a copy of ``q`` (in batches of at most :data:`MAX_BATCH` rows);
    an answer that is not ``m`` booleans, or an exception, is an
    :class:`~rapp.errors.InvalidSetting` naming ``validity`` in one line.

    Examples
    --------
    >>> check_configurations(lambda q: q[:, 0] > 0, [[1.0, 0.0], [-1.0, 0.0]]).tolist()
    [True, False]
    >>> check_configurations(lambda q: q[:, 0], [[1.0, 0.0]])
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidSetting: validity must return booleans (dtype bool), got float64
    """
    q = np.array(q, dtype=float, ndmin=2)
    m = q.shape[0]
    out = np.empty(m, dtype=bool)
    for lo in range(0, m, MAX_BATCH):
        block = q[lo:lo + MAX_BATCH].copy()
        k = block.shape[0]
        try:
            answer = validity(block)
        except Exception as err:  # the user's code: its failure is a bad setting, said in a line
            raise InvalidSetting(f"validity raised {_one_line(err)}", "validity") from None
        answer = np.asarray(answer)
        if answer.shape != (k,):
            raise InvalidSetting(f"validity must return {k} booleans for a {block.shape} array of "
                                 f"configurations, got shape {answer.shape}", "validity")
        if answer.dtype != np.bool_:
            raise InvalidSetting(f"validity must return booleans (dtype bool), got {answer.dtype}",
                                 "validity")
        out[lo:lo + k] = answer
    return out


def motion_samples(qa, qb, resolution: float, arm=None) -> tuple:
    """The points at which each straight edge ``qa -> qb`` is checked, and how many per edge.

    Edge ``i`` is cut into ``max(1, ceil(|d_i| / resolution))`` equal steps (``d_i = qb_i - qa_i``,
    the short way round on a free joint when ``arm`` is given, as the planners step), so no
    step exceeds ``resolution`` (joint-space Euclidean distance); its samples are both ends
    (exactly ``qa_i`` and ``qb_i``) and the points between.

    Returns
    -------
    points : ndarray (sum(counts), n)
        The samples of edge 0, then of edge 1, ...
    counts : ndarray (m,) of int
        Samples per edge (at least 2).

    Examples
    --------
    >>> from rapp import Arm
    >>> pts, counts = motion_samples([[3.0]], [[-3.0]], 0.2, Arm([1.0]))   # across the seam
    >>> counts.tolist(), pts[:, 0].round(3).tolist()
    ([3], [3.0, 3.142, -3.0])
    """
    qa = np.array(qa, dtype=float, ndmin=2)
    qb = np.array(qb, dtype=float, ndmin=2)
    d = qb - qa if arm is None else arm.joint_delta(qa, qb)
    length = np.sqrt((d * d).sum(axis=-1))
    steps = np.maximum(1, np.ceil(length / resolution)).astype(np.int64)
    counts = steps + 1
    edge = np.repeat(np.arange(len(qa)), counts)
    first = np.cumsum(counts) - counts
    j = np.arange(len(edge)) - first[edge]
    points = qa[edge] + (j / steps[edge])[:, None] * d[edge]
    last = j == steps[edge]
    points[last] = qb[edge[last]]   # the end itself, not qa + d rounded
    return points, counts


def edges_valid(validity: Callable, qa, qb, resolution: float, arm=None) -> np.ndarray:
    """Whether the user's checker allows every sample of each edge ``qa -> qb``: bool ``(m,)``.

    The samples are :func:`motion_samples`' (wrapped into the arm's bounds when ``arm`` is
    given), all of them in one call of ``validity`` per :data:`MAX_BATCH`.

    Examples
    --------
    >>> edges_valid(lambda q: q[:, 1] < 0.3, [[0.0, 0.0]], [[0.0, 0.35]], 0.1).tolist()
    [False]
    """
    qa = np.array(qa, dtype=float, ndmin=2)
    if len(qa) == 0:
        return np.zeros(0, dtype=bool)
    points, counts = motion_samples(qa, qb, resolution, arm)
    ok = check_configurations(validity, points if arm is None else arm.wrap(points))
    return np.logical_and.reduceat(ok, np.cumsum(counts) - counts)


@dataclass(frozen=True)
class UserValidity:
    """A user's checker and the step it is sampled at (:func:`user_validity` makes one).

    Examples
    --------
    >>> v = UserValidity(lambda q: q[:, 0] < 1.0, 0.1)
    >>> v.points([[0.5, 0.0], [1.5, 0.0]]).tolist(), v.edges([[0.0, 0.0]], [[2.0, 0.0]]).tolist()
    ([True, False], [False])
    >>> v.text
    'sampled at 0.1 rad, not certified'
    """

    function: Callable
    resolution: float = DEFAULT_RESOLUTION

    def points(self, q, arm=None) -> np.ndarray:
        """The checker's answer for each configuration ``(m, n) -> (m,)``."""
        q = np.array(q, dtype=float, ndmin=2)
        return check_configurations(self.function, q if arm is None else arm.wrap(q))

    def edges(self, qa, qb, arm=None) -> np.ndarray:
        """:func:`edges_valid` at this resolution."""
        return edges_valid(self.function, qa, qb, self.resolution, arm)

    @property
    def text(self) -> str:
        """:func:`sampled_text` of this resolution."""
        return sampled_text(self.resolution)


def user_validity(validity, resolution=DEFAULT_RESOLUTION) -> UserValidity | None:
    """A planner's ``validity`` and ``validity_resolution`` checked: a :class:`UserValidity`,
    or None without a checker (the resolution is checked all the same).

    Examples
    --------
    >>> user_validity(None) is None, user_validity(abs, 0.05).resolution
    (True, 0.05)
    >>> user_validity("no")
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidSetting: validity must be a callable (an (m, n) array of configurations -> m booleans), got str
    """
    try:
        r = float(resolution)
    except (TypeError, ValueError):
        r = math.nan
    if not (math.isfinite(r) and MIN_RESOLUTION <= r <= MAX_RESOLUTION):
        raise InvalidSetting(f"validity_resolution must lie in [{MIN_RESOLUTION:g}, pi] rad, "
                             f"got {resolution!r}", "validity_resolution")
    if validity is None:
        return None
    if not callable(validity):
        raise InvalidSetting("validity must be a callable (an (m, n) array of configurations -> "
                             f"m booleans), got {type(validity).__name__}", "validity")
    return UserValidity(validity, r)


def mark_sampled(result, checker: UserValidity | None):
    """``result`` (a :class:`rapp.paths.PlannerResult`) saying its path relied on ``checker``:
    details ``certified`` False, ``checked_by`` the checker's :attr:`UserValidity.text` and
    ``validity_resolution``; unchanged without a checker.

    Examples
    --------
    >>> from rapp.paths import PlannerResult
    >>> r = mark_sampled(PlannerResult(np.zeros((1, 2)), True, 0.0), UserValidity(abs, 0.02))
    >>> r.certified, r.checked_by
    (False, 'sampled at 0.02 rad, not certified')
    """
    if checker is None:
        return result
    return replace(result, details={**result.details, "certified": False,
                                    "checked_by": checker.text,
                                    "validity_resolution": checker.resolution})


def end_effector_travel(lengths, step: float) -> float:
    """The farthest the end effector can move over a joint-space step of length ``step``:
    ``step * sqrt(sum_j R_j^2)``, ``R_j`` the sum of the lengths from link ``j`` on.

    Joint ``j`` turning by ``dq_j`` moves the tip at most ``R_j |dq_j|`` (it lies within
    ``R_j`` of that joint), so by Cauchy-Schwarz the tip moves at most
    ``sum_j R_j |dq_j| <= |R| |dq|``. Half of this is how far a path sampled at ``step`` can
    reach into a keep-out disc of the end effector between two allowed samples.

    Examples
    --------
    >>> round(end_effector_travel([1.0, 1.0], 0.01), 6)   # sqrt(2^2 + 1^2) * 0.01
    0.022361
    """
    reach = np.cumsum(np.asarray(lengths, float)[::-1])[::-1]
    return float(step * np.sqrt((reach * reach).sum()))
