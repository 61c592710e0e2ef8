"""Checks for the exercises of chapter 12, "Case study: a 3-link arm with RRT".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['12.1', '12.2', '12.3', '12.4', '12.5', '12.6', '12.7']
>>> _steer_ref(np.array([3.0, 0.0, 0.0]), np.array([-3.0, 0.0, 0.0]), 0.1).round(4).tolist()
[3.1, 0.0, 0.0]
>>> _steer_ref(np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.4, 0.0]), 1.0).round(4).tolist()
[0.3, 0.4, 0.0]
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm
from rapp.collision import collides, segment_collision_free
from rapp.cases import rrt_report as s3
from rapp.exercises.core import Exercise, Judgement, as_number_array, describe, implement, numeric
from rapp.ik import jacobian
from rapp.obstacles import Circle, Polygon
from rapp.rrt import Grower, rrt

__all__ = ["EXERCISES"]


# --- 12.1: the Jacobian at the upright arm ---------------------------------------------------

_UPRIGHT_REP = (0.0, 0.0, 0.0)  # the report's angles: the arm straight up along +y


def _report_jacobian() -> np.ndarray:
    """dx/d theta_rep (the x row): minus rapp's Jacobian at the converted angles (chain rule, -I)."""
    return -jacobian(s3.seed_arm(), s3.report_to_rapp(_UPRIGHT_REP))[0]


def _printed_jacobian() -> np.ndarray:
    J, l, t = s3.printed_jacobian()
    at = {**dict(zip(l, s3.LINK_LENGTHS)), **dict(zip(t, _UPRIGHT_REP))}
    return np.array(J.subs(at), dtype=float)[0]


# --- 12.2: the separating gap on the rectangle's first edge direction -------------------------

_ANGLE = 0.3
_LINK = np.array([[1.2, 0.6], [1.6, 1.4]])


def _gap_on(axis_angle: float, rect_angle: float = _ANGLE, axis=None) -> float:
    """Nearest link end minus the rectangle's far end, projected on the axis."""
    u = np.array([np.cos(axis_angle), np.sin(axis_angle)]) if axis is None else np.asarray(axis)
    rect = Polygon.rectangle((0.0, 0.0), 1.0, 1.0, rect_angle).array @ u
    return float((_LINK @ u).min() - rect.max())


def _sat_gap() -> float:
    return _gap_on(_ANGLE)


def _far_end_gap() -> float:
    u = np.array([np.cos(_ANGLE), np.sin(_ANGLE)])
    return float((_LINK @ u).max() - (Polygon.rectangle((0.0, 0.0), 1.0, 1.0, _ANGLE).array @ u).max())


# --- 12.3: the wrap-aware distance -----------------------------------------------------------

_ARM3 = Arm([0.5, 0.5, 0.5], [None, None, (-3.2, 3.2)])  # joints 1, 2 free; joint 3 limited
_QA = np.array([2.9, -3.0, 3.0])
_QB = np.array([-2.8, 2.7, -3.1])


def _wrap_distance() -> float:
    return float(np.linalg.norm(_ARM3.joint_delta(_QA, _QB)))


def _all_wrapped() -> float:
    return float(np.linalg.norm(Arm([0.5, 0.5, 0.5]).joint_delta(_QA, _QB)))


# --- 12.4: one RRT extend step ---------------------------------------------------------------

_FREE3 = Arm([0.5, 0.5, 0.5])  # three free joints: every joint wraps


def _steer_ref(q_near, q_rand, step):
    """The package's steer: ``rapp.rrt``'s own rule (``steer="step"``) from one node."""
    grower = Grower(_FREE3, [], None, None, None, float(step), "step", 0.0)
    _, q_new, _ = grower.steer_from(np.asarray(q_near, float)[None], np.asarray(q_rand, float)[None])
    return q_new[0]


def _steer_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (far, near, across the seam, equal, exactly one step, both), then random ones."""
    cases: list[tuple] = [
        (np.array([0.1, 0.2, -0.3]), np.array([1.5, -0.8, 0.9]), 0.3),     # far, no seam
        (np.array([0.5, -0.5, 1.0]), np.array([0.6, -0.45, 1.05]), 0.5),   # closer than step
        (np.array([3.0, 0.0, -3.0]), np.array([-2.9, 0.3, 2.9]), 0.2),     # across the seam
        (np.array([1.0, -2.0, 3.0]), np.array([1.0, -2.0, 3.0]), 0.1),     # q_rand is q_near
        (np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.4, 0.0]), 0.5),       # exactly one step away
        (np.array([-3.1, 0.0, 0.0]), np.array([3.1, 0.0, 0.0]), 0.5),      # seam, closer than step
    ]
    for k in range(50):
        q_near = rng.uniform(-np.pi, np.pi, 3)
        step = float(rng.uniform(0.05, 1.0))
        if k % 5 == 0:
            q_rand = _FREE3.wrap(q_near + rng.uniform(-0.3, 0.3, 3) * step)
        else:
            q_rand = rng.uniform(-np.pi, np.pi, 3)
        cases.append((q_near, q_rand, step))
    return cases


def _same_angles(a, b) -> bool:
    """Equal up to whole turns on every joint."""
    return bool(np.allclose(_FREE3.joint_delta(a, b), 0.0, atol=1e-9))


def _compare_steer(got, want, args) -> str | None:
    q_near, q_rand, step = args
    g = as_number_array(got)
    if isinstance(g, str):
        if got is None:
            return "returned None (a missing return?)."
        if np.array_equal(q_near, q_rand):
            return (f"returned {describe(got)}. Here q_rand is q_near: there is no direction to "
                    "divide by, and the answer is q_near itself (its distance is below step).")
        return f"returned {describe(got)}, not a configuration."
    if g.shape != (3,):
        return f"returned shape {g.shape}; expected a configuration of 3 joint angles."
    if _same_angles(g, want):
        return None
    d = _FREE3.joint_delta(q_near, q_rand)
    dist = float(np.linalg.norm(d))
    plain = q_rand - q_near
    plain_dist = float(np.linalg.norm(plain))
    if plain_dist > 0 and _same_angles(g, q_near + min(1.0, step / plain_dist) * plain):
        return (f"returned {describe(got)}: it went the long way across the ±π seam. Take each "
                "joint's difference the short way round (wrapped into [-π, π)) before measuring "
                "and before stepping.")
    if dist > 0 and dist < step and _same_angles(g, q_near + step / dist * d):
        return (f"returned {describe(got)}: it overshoots q_rand. When q_rand is closer than step, "
                "the new configuration is q_rand itself (clip the step).")
    if dist > step and _same_angles(g, q_rand):
        return (f"returned {describe(got)}: it jumped all the way to q_rand, which is further than "
                "step away; move at most step.")
    if _same_angles(g, q_near + step * d) or _same_angles(g, q_near + min(1.0, step) * d):
        return (f"returned {describe(got)}: it moved step × d. Divide d by its length first, so "
                "that the move is step long, in the direction of q_rand.")
    move = _FREE3.joint_delta(q_near, g)
    length = float(np.linalg.norm(move))
    if length > min(step, dist) + 1e-9:
        return (f"returned {describe(got)}, which is further from q_near (wrap-aware) than both step "
                "and q_rand.")
    if dist > 0 and np.linalg.norm(np.cross(move, d)) > 1e-9 * max(1.0, length * dist):
        return (f"returned {describe(got)}, which does not lie on the way from q_near towards "
                "q_rand along the wrap-aware difference.")
    return (f"returned {describe(got)}, on the way to q_rand but not as far as it should go "
            "(min(step, distance) along the wrap-aware difference).")


# --- 12.5: a step the node test lets through -------------------------------------------------

_MAX_APART = 0.5  # one RRT step of alpha = 0.5 rad


def _judge_node_test_counterexample(answer) -> Judgement:
    """``(q_a, q_b)`` of the report's arm: both free, at most 0.5 rad apart, the edge not free."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (q_a, q_b), two configurations of the report's arm.")
    try:
        q_a, q_b = (np.asarray(q, dtype=float) for q in answer)
    except Exception:
        return Judgement(False, f"expected a pair (q_a, q_b) of configurations; got {describe(answer)}.")
    if q_a.shape != (3,) or q_b.shape != (3,) or not (np.isfinite(q_a).all() and np.isfinite(q_b).all()):
        return Judgement(False, "q_a and q_b must each be 3 finite joint angles (radians, the book's "
                                "convention).")
    arm, square = s3.seed_arm(), [s3.seed_square()]
    inside = arm.within_limits(np.stack((q_a, q_b)))
    if not inside.all():
        which = "q_a" if not inside[0] else "q_b"
        return Judgement(False, f"{which} lies outside the arm's joint limits (the report's ±1.5 rad "
                                "box in the book's angles: convert with s3.report_to_rapp).")
    apart = float(np.linalg.norm(q_b - q_a))
    if apart > _MAX_APART + 1e-12:
        return Judgement(False, f"q_a and q_b are {apart:.3g} rad apart; one step may be at most "
                                f"{_MAX_APART:g} rad.")
    hit = collides(arm, np.stack((q_a, q_b)), square)
    if hit.any():
        which = " and ".join(n for n, h in zip(("q_a", "q_b"), hit) if h)
        return Judgement(False, f"{which} collides with the square, so the report's node test rejects "
                                "the step too; both ends must be free.")
    if segment_collision_free(arm, q_a, q_b, square):
        return Judgement(False, "both ends are free, and so is the edge between them: no "
                                "counterexample. Let one link sweep across the square during the step.")
    return Judgement(True, "both ends are free and the edge between them hits the square: the "
                           "report's node test accepts a step that rapp.rrt rejects.")


# --- 12.6: the fraction rule's iterations ----------------------------------------------------

def _fraction_iterations() -> int:
    free = Arm([1.0, 1.0], [(-4.0, 4.0)] * 2)
    return rrt(free, [0.0, 0.0], [2.0, 0.0], [], step=0.5, goal_bias=1.0, steer="fraction",
               goal_threshold=0.01).iterations


# --- 12.7: a scene where full goal bias fails ------------------------------------------------

_ARM2 = Arm([1.0, 1.0])
_START2 = np.array([0.0, 0.0])
_GOAL2 = np.array([2.0, 0.0])
_SETTINGS = dict(step=0.2, goal_threshold=0.05, raise_on_failure=False, seed=0)


def _judge_goal_bias_scene(answer) -> Judgement:
    """A list of obstacles on which beta = 1 never reaches the goal but beta = 0.1 does."""
    if answer is None:
        return Judgement(False, "no answer yet: pass a list of obstacles (rapp.Circle, rapp.Polygon).")
    if isinstance(answer, (Circle, Polygon)):
        answer = [answer]
    try:
        obstacles = list(answer)
    except TypeError:
        return Judgement(False, f"expected a list of obstacles; got {describe(answer)}.")
    if not obstacles or len(obstacles) > 6 or not all(isinstance(o, (Circle, Polygon)) for o in obstacles):
        return Judgement(False, "pass a list of 1 to 6 obstacles, each a rapp.Circle or a rapp.Polygon.")
    ends = collides(_ARM2, np.stack((_START2, _GOAL2)), obstacles)
    if ends.any():
        which = " and ".join(n for n, h in zip(("the start", "the goal"), ends) if h)
        return Judgement(False, f"{which} collides with your obstacles; both must be free.")
    greedy = rrt(_ARM2, _START2, _GOAL2, obstacles, goal_bias=1.0, max_iterations=300, **_SETTINGS)
    if greedy.success:
        return Judgement(False, f"with β = 1 the tree reaches the goal ({greedy.iterations} iterations): "
                                "the straight joint-space segment from start to goal is free. Block it.")
    mixed = rrt(_ARM2, _START2, _GOAL2, obstacles, goal_bias=0.1, max_iterations=3000, **_SETTINGS)
    if not mixed.success:
        return Judgement(False, "β = 1 fails, but β = 0.1 finds no path within 3000 iterations either: "
                                "leave a way round, so that only the greedy tree is stuck.")
    return Judgement(True, f"β = 1 is stuck on the straight segment, while β = 0.1 goes round in "
                           f"{mixed.iterations} iterations: without random samples RRT is not "
                           "probabilistically complete.")


EXERCISES = (
    Exercise(
        "12.1", 12, "numeric", "The Jacobian of the upright arm", 1,
        "3 numbers: the x row of J, dx/d(theta_rep_j) in metres per radian",
        numeric(_report_jacobian,
                mistakes=[(_printed_jacobian, "that is −J, the report's printed matrix (and rapp.jacobian "
                                              "in the book's angles without the chain rule): every sign "
                                              "is flipped. Which way does the tip move when θ_rep,1 grows?")],
                hint="differentiate x of eq. ch12-fk (sin gives +cos) and evaluate at θ_rep = 0."),
    ),
    Exercise(
        "12.2", 12, "numeric", "The separating gap", 1,
        "a number: the gap in metres between the two projected intervals (negative if they overlap)",
        numeric(_sat_gap,
                mistakes=[(_far_end_gap, "that is measured from the far end of the link; the gap "
                                         "starts at the link's nearer end."),
                          (lambda: _gap_on(_ANGLE + np.pi / 2), "that is the other edge direction, "
                                                                "(−sin θ, cos θ); this asks for (cos θ, sin θ)."),
                          (lambda: _gap_on(np.radians(_ANGLE), np.radians(_ANGLE)),
                           "that treats 0.3 as degrees; θ is in radians."),
                          (lambda: _gap_on(0.0), "that projects on the x axis; project on the rectangle's "
                                                 "own edge direction.")],
                hint="project both link ends and the four corners on u = (cos θ, sin θ); the gap is "
                     "the smallest link value minus the largest rectangle value."),
    ),
    Exercise(
        "12.3", 12, "numeric", "The wrap-aware distance", 1,
        "a number: the joint-space distance in radians",
        numeric(_wrap_distance,
                mistakes=[(lambda: float(np.linalg.norm(_QB - _QA)),
                           "that is the plain Euclidean distance: joints 1 and 2 are free, so their "
                           "differences go the short way round."),
                          (_all_wrapped, "that wraps joint 3 too; a limited joint lives on an interval "
                                         "and keeps its plain difference."),
                          (lambda: float(np.abs(_ARM3.joint_delta(_QA, _QB)).sum()),
                           "that adds the absolute differences; the distance is Euclidean."),
                          (lambda: _wrap_distance() ** 2, "that is the squared distance; take the root.")],
                hint="wrap each free joint's difference into [-π, π), keep the limited one, then take "
                     "the Euclidean norm."),
    ),
    Exercise(
        "12.4", 12, "implement", "One RRT extend step", 2,
        "a function steer(q_near, q_rand, step) returning the new configuration (3 angles, radians)",
        implement(_steer_ref, _steer_cases, call="steer(q_near, q_rand, step)",
                  names=("q_near", "q_rand", "step"), compare=_compare_steer, seed=124),
    ),
    Exercise(
        "12.5", 12, "argue", "A step the node test lets through", 2,
        "a pair (q_a, q_b) of the report's arm, in the book's angles: both free, at most 0.5 rad "
        "apart, the edge between them not",
        _judge_node_test_counterexample,
    ),
    Exercise(
        "12.6", 12, "numeric", "Iterations of the fraction rule", 1,
        "an integer: the number of iterations",
        numeric(_fraction_iterations, exact_integer=True,
                mistakes=[(lambda: _fraction_iterations() - 1,
                           "after that many steps the distance is still above ε; count to the first k "
                           "with (1 − α)^k d ≤ ε (round up, and start from d, not from 1)."),
                          (lambda: 4, "that is a fixed step of α = 0.5 rad; the fraction rule moves a "
                                      "fraction α of the remaining distance."),
                          (lambda: _fraction_iterations() + 1,
                           "one too many: the last edge onto the goal is not an iteration; stop at the "
                           "first k with d_k ≤ ε.")],
                hint="after k steps the distance is (1 − α)^k d."),
    ),
    Exercise(
        "12.7", 12, "argue", "A scene where full goal bias fails", 2,
        "a list of obstacles (rapp.Circle or rapp.Polygon) for the two-link arm",
        _judge_goal_bias_scene,
    ),
)
