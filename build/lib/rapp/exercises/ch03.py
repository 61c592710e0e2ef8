"""Checks for the exercises of chapter 3, "Segment–circle collision".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['3.1', '3.2', '3.3', '3.4', '3.5']
>>> bool(_seed003_hits([0.0, 0.0], [1.0, 0.0], _SQUARE)), bool(_seed003_hits([0.0, 0.0], [1.5, 0.0], _SQUARE))
(False, True)
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm
from rapp.collision import (line_distance_mis, motion_bounds, segment_hits_circle, segment_hits_polygon,
                            segment_point_distance, segment_polygon_distance)
from rapp.exercises.core import Exercise, Judgement, describe, implement, numeric
from rapp.obstacles import Polygon

__all__ = ["EXERCISES"]


# --- 3.1: the distance from a point to a segment ---------------------------------------------

_A1, _B1, _C1, _R1 = (0.0, 0.0), (2.0, 0.0), (3.0, 1.0), 1.2


def _distance_31() -> float:
    return float(segment_point_distance(_A1, _B1, _C1))


# --- 3.2: the clipped segment–circle test -----------------------------------------------------

def _hits_ref(a, b, center, radius) -> bool:
    return bool(segment_hits_circle(a, b, center, radius))


def _circle_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (touching, beyond either end on the line, a point segment), then random ones.

    The touching cases use numbers that are exact in floating point, so that ``<=`` and ``<``
    really differ on them.
    """
    f = lambda *xs: np.array(xs, dtype=float)  # noqa: E731
    cases: list[tuple] = [
        (f(0, 0), f(2, 0), f(1, 3), 1.0),        # clearly free, beside the middle
        (f(0, 0), f(2, 0), f(1, 0.5), 1.0),      # clearly hit, through the middle
        (f(0, 0), f(2, 0), f(3, 0.25), 0.5),     # beyond the end b, near the line: free
        (f(0, 0), f(2, 0), f(-1, 0.3), 0.5),     # before the start a, near the line: free
        (f(0, 0), f(2, 0), f(1, 0.5), 0.5),      # tangent to the middle: touching counts
        (f(0, 0), f(2, 0), f(2.5, 0), 0.5),      # touching the end b
        (f(1, 1), f(1, 1), f(3, 1), 1.0),        # a point segment, free
        (f(1, 1), f(1, 1), f(2, 1), 1.0),        # a point segment, touching
        (f(2, 0), f(0, 0), f(3, 0.25), 0.5),     # the same segment backwards, beyond a
    ]
    for _ in range(50):
        a, b = rng.uniform(-2.0, 2.0, (2, 2))
        c = rng.uniform(-3.0, 3.0, 2)
        cases.append((a, b, c, float(rng.uniform(0.05, 1.5))))
    return cases


def _compare_hit(got, want, args) -> str | None:
    if got is None:
        return "returned None (a missing return?)."
    if not isinstance(got, (bool, np.bool_)) and not (isinstance(got, np.ndarray) and got.shape == ()
                                                      and got.dtype == bool):
        return f"returned {describe(got)}; expected True or False."
    if bool(got) == want:
        return None
    a, b, center, radius = args
    if not np.any(a != b):
        if bool(got):
            return "returned True, but this segment is a single point outside the disc."
        return ("returned False, but this segment is a single point on the disc (when b = a there is "
                "no direction to project on: the closest point is a itself).")
    if bool(got):
        if line_distance_mis(a, b, center) <= radius:
            return ("returned True, but the disc lies beyond an end of the segment: it is close to the "
                    "infinite line, not to the link. Clip the projection parameter t to [0, 1].")
        return "returned True, but the segment passes clear of the disc."
    if segment_point_distance(a, b, center) == radius:
        return ("returned False, but the segment touches the disc here, and touching counts as a "
                "collision (distance <= radius).")
    return ("returned False, but the segment meets the disc (compare the distance from the centre to "
            "the closest point of the segment with the radius).")


# --- 3.3: a false collision of the MIS --------------------------------------------------------

def _judge_mis_counterexample(answer) -> Judgement:
    """``(a, b, center, radius)``: the MIS's line test reports a hit, the segment is clear."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (a, b, center, radius).")
    try:
        a, b, center, radius = answer
        a, b, center = (np.asarray(p, dtype=float) for p in (a, b, center))
        radius = float(radius)
    except Exception:
        return Judgement(False, f"expected a tuple (a, b, center, radius) of three points and a number; "
                                f"got {describe(answer)}.")
    if any(p.shape != (2,) for p in (a, b, center)):
        return Judgement(False, "a, b and center must each be a point (x, y).")
    if not (np.all(np.isfinite([*a, *b, *center])) and np.isfinite(radius)) or radius <= 0:
        return Judgement(False, "use finite coordinates and a positive radius.")
    if not np.any(a != b):
        return Judgement(False, "a and b are the same point: the MIS's formula divides by the link's "
                                "length, which is 0; a link has a length.")
    line = float(line_distance_mis(a, b, center))
    seg = float(segment_point_distance(a, b, center))
    if line > radius:
        return Judgement(False, f"the line through a and b passes {line:.4g} from the centre, more than the "
                                "radius: the MIS reports no collision here. Put the centre near the line.")
    if segment_hits_circle(a, b, center, radius):
        return Judgement(False, "the segment really meets the disc (rapp.collision.segment_hits_circle "
                                "says so): the MIS is right here. Move the disc beyond an end of the link.")
    return Judgement(True, f"the MIS's line distance is {line:.4g} <= r = {radius:.4g}, a collision, but "
                           f"the link's closest point is {seg:.4g} from the centre: free. A false collision.")


# --- 3.4: a touch that the seed's strict test misses ------------------------------------------

_SQUARE = Polygon.rectangle((1.0, -1.0), 2.0, 2.0)


def _seed003_hits(a, b, polygon: Polygon) -> bool:
    """Seed 003's overlap test on the axes of alg-ch03-sat: strict inequalities on every axis."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    v = polygon.array
    e = np.roll(v, -1, axis=0) - v
    axes = [np.array([e[i, 1], -e[i, 0]]) for i in range(len(v))]
    axes.append(np.array([-(b - a)[1], (b - a)[0]]))
    for n in axes:
        s = (a @ n, b @ n)
        p = v @ n
        if not (min(s) < p.max() and max(s) > p.min()):
            return False
    return True


def _judge_touch(answer) -> Judgement:
    """``(a, b)``: a link that touches the square with its middle, where seed 003 sees a gap."""
    if answer is None:
        return Judgement(False, "no answer yet: pass the link's ends (a, b).")
    try:
        a, b = answer
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    except Exception:
        return Judgement(False, f"expected a tuple (a, b) of two points; got {describe(answer)}.")
    if a.shape != (2,) or b.shape != (2,):
        return Judgement(False, "a and b must each be a point (x, y).")
    if not np.all(np.isfinite([*a, *b])):
        return Judgement(False, "use finite coordinates.")
    if not np.any(a != b):
        return Judgement(False, "a and b are the same point; a link has a length.")
    if not segment_hits_polygon(a, b, _SQUARE):
        gap = float(segment_polygon_distance(a, b, _SQUARE))
        return Judgement(False, f"the link misses the square (it passes {gap:.4g} away): a touch shares "
                                "at least one point with it.")
    ends = [float(segment_polygon_distance(p, p, _SQUARE)) for p in (a, b)]
    if min(ends) == 0.0:
        return Judgement(False, "an end of the link lies on the square, as in the chapter's example; "
                                "find a link that touches it with a point strictly between its ends.")
    if _seed003_hits(a, b, _SQUARE):
        return Judgement(False, "the link enters the square: even the seed's strict test sees that "
                                "overlap. A touch shares only boundary points (a corner, or part of a side).")
    return Judgement(True, "segment_hits_polygon reports the touch, and on one axis the projections "
                           "only share an end point, which the seed's strict inequalities call a gap.")


# --- 3.5: the motion bound of a joint step ----------------------------------------------------

_ARM5, _DQ5 = (1.0, 1.0), (0.1, 0.2)


def _bounds_35() -> np.ndarray:
    return motion_bounds(Arm(list(_ARM5)), list(_DQ5))


def _own_joint_only() -> np.ndarray:
    return np.abs(np.array(_DQ5)) * np.array(_ARM5)


def _own_links_summed() -> np.ndarray:
    return np.cumsum(np.abs(np.array(_DQ5)) * np.array(_ARM5))


def _whole_arm() -> np.ndarray:
    reach = np.cumsum(np.array(_ARM5)[::-1])[::-1]          # R_i = L_i + ... + L_n
    return np.cumsum(np.abs(np.array(_DQ5)) * reach)


EXERCISES = (
    Exercise(
        "3.1", 3, "numeric", "Distance from a disc's centre to a link", 1,
        "a number: the distance from the centre to the link, in metres",
        numeric(_distance_31,
                mistakes=[(lambda: float(line_distance_mis(_A1, _B1, _C1)),
                           "that is the distance to the infinite line through the link (the foot of "
                           "the perpendicular is not on the link); clip t* to [0, 1]."),
                          (lambda: float(np.hypot(*_C1)),
                           "that is the distance to the end a; which end is t* nearer to?"),
                          (lambda: _distance_31() ** 2, "that is the squared distance; take the root."),
                          (lambda: _distance_31() - _R1,
                           "that is the clearance (distance minus radius); the question asks for the "
                           "distance to the centre.")],
                hint="compute t* of eq. ch03-clip, clip it to [0, 1], and measure from that point."),
    ),
    Exercise(
        "3.2", 3, "implement", "Implement the segment–circle test", 2,
        "a function hits(a, b, center, radius) returning True or False",
        implement(_hits_ref, _circle_cases, call="hits(a, b, center, radius)",
                  names=("a", "b", "center", "radius"), compare=_compare_hit, seed=32),
    ),
    Exercise(
        "3.3", 3, "argue", "A false collision of the MIS", 1,
        "a tuple (a, b, center, radius) on which the MIS's line test reports a collision but the link is free",
        _judge_mis_counterexample,
    ),
    Exercise(
        "3.4", 3, "argue", "A touch that the seed's test misses", 2,
        "a tuple (a, b): a link that touches the square with a point between its ends",
        _judge_touch,
    ),
    Exercise(
        "3.5", 3, "numeric", "Motion bounds of a joint step", 1,
        "an array [B1, B2]: the motion bounds of the two links, in metres",
        numeric(_bounds_35,
                mistakes=[(_own_joint_only, "each link gets only its own joint here; turning joint 1 "
                                            "also swings link 2."),
                          (_own_links_summed, "turning joint 1 swings link 2 about the base, so a point "
                                              "of link 2 can be L1 + L2 from it, not L2 (see rho_ij)."),
                          (_whole_arm, "that uses the whole arm's reach for link 1; link 1 reaches only "
                                       "L1 from the base (rho_11 = L1).")],
                hint="B_j sums |dθ_i| rho_ij over the joints i <= j, with rho_ij = L_i + ... + L_j."),
    ),
)
