"""Checks for the exercises of chapter 6, "Inverse kinematics".

The damped least-squares step of Exercise 6.5 is checked against :func:`_dls_ref`, eq.
``ch06-dls`` written out. It is the package's step with the damping held fixed: with
``sigma_floor`` so large that the damping is always on and ``lambda_max = lam`` (and an error
of at least ``lam**2``, the cap of line 7), ``rapp.ik.dls_step`` takes the same step, and with
``lam = 0`` it is the pseudo-inverse (Newton) step.

Examples
--------
>>> [ex.id for ex in EXERCISES]
['6.1', '6.2', '6.3', '6.4', '6.5', '6.6']
>>> from rapp.ik import dls_step
>>> J = jacobian(Arm([0.5, 0.3, 0.2]), [0.3, 1.1, -0.4])
>>> e = np.array([0.3, -0.2])
>>> pkg = dls_step(J[0][:, None], J[1][:, None], e[:1], e[1:], 1e100, 0.2)[:, 0]
>>> bool(np.allclose(_dls_ref(J, e, 0.2), pkg, rtol=1e-12, atol=1e-15))
True
>>> bool(np.allclose(_dls_ref(J, e, 0.0), np.linalg.pinv(J) @ e))
True
"""

from __future__ import annotations

import functools

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.exercises.core import Exercise, Judgement, as_number_array, describe, implement, numeric
from rapp.ik import ik_2link, jacobian

__all__ = ["EXERCISES"]

_SINGULAR_TOL = 1e-9  # a configuration is singular when sigma_min(J) <= this times the arm's length


# --- 6.1: both solutions by hand ---------------------------------------------------------------

def _two_solutions() -> np.ndarray:
    """The rows elbow-down, elbow-up, flattened: (theta1, theta2, theta1, theta2)."""
    return ik_2link([1.0, 1.0], [1.0, 1.0]).reshape(4)


def _plus_instead_of_minus() -> np.ndarray:
    q = _two_solutions().reshape(2, 2)
    q[:, 0] = np.arctan2(1.0, 1.0) + np.arctan2(np.sin(q[:, 1]), 1.0 + np.cos(q[:, 1]))
    return q.reshape(4)


def _judge_two_solutions():
    """The numeric judge on the flattened answer: a 2 x 2 array or the four angles in a row."""
    judge = numeric(_two_solutions, angles=True,
                    mistakes=[(lambda: _two_solutions().reshape(2, 2)[::-1].reshape(4),
                               "the rows are swapped: elbow-down (theta_2 > 0) comes first."),
                              (lambda: np.degrees(_two_solutions()), "those are degrees; give radians."),
                              (_plus_instead_of_minus, "theta_1 has the wrong sign of the second atan2 "
                                                       "(eq. ch06-q1 subtracts it); put your angles back "
                                                       "into the forward kinematics.")],
                    hint="cos theta_2 from eq. ch06-cos, then theta_1 from eq. ch06-q1 for each sign of "
                         "theta_2; put them back into the forward kinematics to check.")

    def flat(answer):
        got = as_number_array(answer)
        if isinstance(got, np.ndarray) and got.shape in ((2, 2), (4,)):
            return judge(got.reshape(4))
        if isinstance(got, np.ndarray):
            return Judgement(False, f"expected a 2 x 2 array (one row per elbow), got shape {got.shape}.")
        return judge(answer)

    flat.expected = _two_solutions
    flat.tolerance = judge.tolerance
    return flat


# --- 6.2: det J --------------------------------------------------------------------------------

_ARM_62, _Q_62 = (1.0, 0.8), (0.4, 2.0)


def _det_j() -> float:
    return float(np.linalg.det(jacobian(Arm(_ARM_62), _Q_62)))


def _l1l2(f) -> float:
    return _ARM_62[0] * _ARM_62[1] * f


# --- 6.3 and 6.4: singular configurations ------------------------------------------------------

def _singular_ref(lengths, q) -> bool:
    """The package's verdict: the smallest singular value of ``rapp.jacobian`` is (nearly) zero."""
    lengths = np.asarray(lengths, dtype=float)
    sigma = np.linalg.svd(jacobian(Arm(lengths), q), compute_uv=False)
    return bool(sigma[-1] <= _SINGULAR_TOL * lengths.sum())


def _singular2_ref(L1, L2, q) -> bool:
    return _singular_ref([L1, L2], q)


def _two_link_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (stretched, folded, equal links, 2 pi multiples, nearly singular) then random."""
    pi = np.pi
    cases: list[tuple] = [
        (1.0, 0.8, np.array([0.3, 1.2])),          # regular
        (1.0, 0.8, np.array([0.0, 1.0])),          # regular, theta_1 = 0
        (1.0, 0.8, np.array([0.3, 0.0])),          # stretched
        (1.0, 0.8, np.array([0.3, pi])),           # folded
        (1.0, 1.0, np.array([1.0, pi])),           # folded, equal links: the tip at the base
        (0.6, 1.5, np.array([2.0, -pi])),          # folded, the other way round
        (1.0, 0.8, np.array([-2.5, 2 * pi])),      # stretched, written as 2 pi
        (0.5, 1.5, np.array([-1.0, 3 * pi])),      # folded, written as 3 pi
        (1.0, 0.8, np.array([0.3, 1e-4])),         # nearly stretched: regular
        (1.0, 0.8, np.array([0.0, pi - 1e-4])),    # nearly folded: regular
        (1.0, 0.8, np.array([pi, 0.5])),           # theta_1 = pi: regular
    ]
    for k in range(50):
        L1, L2 = (float(v) for v in rng.uniform(0.2, 2.0, 2))
        q = rng.uniform(-pi, pi, 2)
        if k % 2:
            q[1] = int(rng.integers(-3, 4)) * pi
        cases.append((L1, L2, q))
    return cases


def _bool_problem(got) -> str | None:
    if got is None:
        return "returned None (a missing return?)."
    if not isinstance(got, (bool, np.bool_)):
        return f"returned {describe(got)}; expected True or False."
    return None


def _compare_singular2(got, want, args) -> str | None:
    problem = _bool_problem(got)
    if problem or bool(got) == want:
        return problem
    L1, L2, q = args
    t2 = float(wrap_angle(q[1]))
    if want:
        if abs(abs(t2) - np.pi) < 1e-6:
            where = (" The tip is at the base here, inside the workspace: singular all the same."
                     if L1 == L2 else "")
            return ("said False for the folded arm, which is singular (its links lie on one line)."
                    + where + " Note that np.sin(np.pi) is not exactly 0: compare with a tolerance.")
        return ("said False for a stretched arm, which is singular; angles repeat every 2 pi, so "
                "compare sin(theta_2), or the wrapped angle, with a tolerance.")
    if abs(np.sin(t2)) < 1e-2:
        return ("said True for a configuration that is close to a singular one but not on it; use a "
                "tolerance near 1e-9, not a loose one.")
    return ("said True for a regular configuration: its Jacobian has rank 2. Which joint angle does "
            "det J depend on?")


def _n_link_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (all flat, partly flat, equal links, nearly flat) then random arms of 2-5 links."""
    pi = np.pi
    arm3 = np.array([1.0, 0.8, 0.5])
    cases: list[tuple] = [
        (arm3, np.array([0.3, 0.7, -1.1])),        # regular
        (arm3, np.array([0.3, 0.0, 0.0])),         # stretched
        (arm3, np.array([0.3, 0.0, 1.0])),         # first two links in line, the third bent: regular
        (arm3, np.array([0.3, 1.0, 0.0])),         # last two links in line: regular
        (arm3, np.array([-1.0, pi, 0.0])),         # folded at joint 2
        (arm3, np.array([0.3, 0.0, -pi])),         # folded at joint 3
        (arm3, np.array([1.0, -pi, pi])),          # folded twice
        (arm3, np.array([0.3, pi, 1.0])),          # folded at joint 2, bent at 3: regular
        (np.array([1.0, 0.5, 0.5]), np.array([0.2, 0.7, pi])),   # L2 = L3 folded, joint 2 bent: regular
        (np.array([1.0, 0.5, 0.5]), np.array([0.2, pi, pi])),    # all in line
        (np.array([1.0, 0.8]), np.array([0.3, pi])),              # two links
        (np.array([0.4, 0.4, 0.4, 0.4]), np.array([2.0, 0.0, 2 * pi, -pi])),
        (np.array([0.4, 0.4, 0.4, 0.4]), np.array([2.0, 0.0, 1e-4, -pi])),   # nearly flat: regular
        (np.array([0.5, 0.3, 0.2, 0.4, 0.6]), np.array([0.1, pi, 0.0, 3 * pi, 0.0])),
    ]
    for k in range(50):
        n = int(rng.integers(2, 6))
        lengths = rng.uniform(0.2, 2.0, n)
        q = rng.uniform(-pi, pi, n)
        if k % 3:
            q[1:] = rng.integers(-3, 4, n - 1) * pi
            if k % 3 == 2 and n > 2:
                q[int(rng.integers(1, n))] = rng.uniform(0.2, pi - 0.2) * rng.choice([-1.0, 1.0])
        cases.append((lengths, q))
    return cases


def _compare_singular_n(got, want, args) -> str | None:
    problem = _bool_problem(got)
    if problem or bool(got) == want:
        return problem
    lengths, q = args
    s = np.abs(np.sin(np.asarray(q[1:], dtype=float)))
    if want:
        return ("said False for a singular configuration: all of its links lie on one line "
                "(compare angles with a tolerance, and remember they repeat every 2 pi).")
    if s.max() < 1e-2:
        return ("said True for a configuration that is close to a singular one but not on it; use a "
                "tolerance near 1e-9, not a loose one.")
    if s.min() < 1e-6:
        return ("said True, but this configuration's Jacobian has rank 2: some links lie in line, "
                "not all of them. What must hold at every joint for the rank to drop?")
    return "said True for a regular configuration: its Jacobian has rank 2."


# --- 6.5: one damped least-squares step --------------------------------------------------------

def _dls_ref(J, e, lam) -> np.ndarray:
    """Eq. ch06-dls: ``J^T (J J^T + lam^2 I)^{-1} e``."""
    J = np.asarray(J, dtype=float)
    return J.T @ np.linalg.solve(J @ J.T + lam**2 * np.eye(2), np.asarray(e, dtype=float))


def _dls_cases(rng: np.random.Generator) -> list[tuple]:
    """Newton (lam = 0) on a square and a wide J, damping on a regular and on singular Js, then random."""
    arm2, arm3 = Arm([1.0, 0.8]), Arm([1.0, 0.8, 0.5])
    cases: list[tuple] = [
        (jacobian(arm2, [0.3, 1.2]), np.array([0.05, -0.02]), 0.0),
        (jacobian(arm3, [0.3, 1.2, -0.7]), np.array([0.05, -0.02]), 0.0),
        (jacobian(arm2, [0.3, 1.2]), np.array([0.05, -0.02]), 0.3),
        (jacobian(arm2, [0.5, 0.0]), np.array([0.1, 0.05]), 0.05),     # stretched: singular
        (jacobian(arm3, [0.5, np.pi, 0.0]), np.array([-0.1, 0.2]), 0.1),  # flat: singular
        (jacobian(arm3, [0.5, 0.7, 1e-3]), np.array([0.2, 0.1]), 0.0),
    ]
    for _ in range(50):
        n = int(rng.integers(2, 6))
        arm = Arm(rng.uniform(0.2, 1.5, n))
        q = rng.uniform(-np.pi, np.pi, n)
        if rng.random() < 0.3:
            q[1:] = rng.integers(-1, 2, n - 1) * np.pi + rng.normal(0.0, 1e-3, n - 1)
        lam = float(rng.uniform(0.01, 0.5)) if rng.random() < 0.8 else 0.0
        cases.append((jacobian(arm, q), rng.normal(0.0, 0.2, 2), lam))
    return cases


def _compare_dls(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not numbers."
    J, e, lam = args
    n = J.shape[1]
    if g.shape != (n,):
        return f"returned shape {g.shape}; Δq has one entry per joint, shape ({n},)."

    def same(a) -> bool:
        return bool(np.allclose(g, a, rtol=1e-7, atol=1e-10))

    if same(want):
        return None
    shown = f"returned {describe(got)}"
    alternatives = []
    try:
        alternatives.append((lambda: J.T @ np.linalg.solve(J @ J.T + lam * np.eye(2), e),
                             "damped with λ instead of λ²: the term added to J Jᵀ is λ² I."))
        alternatives.append((lambda: np.linalg.pinv(J) @ e,
                             "the undamped (pseudo-inverse) step; with λ > 0 add λ² I to J Jᵀ "
                             "before inverting."))
        if n == 2:
            alternatives.append((lambda: J @ np.linalg.solve(J @ J.T + lam**2 * np.eye(2), e),
                                 "J where eq. ch06-dls has Jᵀ in front."))
    except Exception:
        pass
    for alt, why in alternatives:
        try:
            if same(alt()):
                return f"{shown}: {why}"
        except Exception:
            continue
    if not np.all(np.isfinite(g)):
        return f"{shown}, not finite: with λ > 0, J Jᵀ + λ² I is invertible even at a singular J."
    return f"{shown}: that is not Jᵀ (J Jᵀ + λ² I)⁻¹ e."


# --- 6.6: the longest DLS step -----------------------------------------------------------------

_LAM, _ERR = 0.05, 0.1


@functools.cache  # 20 002 small solves, and a judge asks for the value at every check
def _longest_dls_step() -> float:
    """Largest |step| over sigma for an error along the singular direction of J = diag(1, sigma)."""
    sigmas = np.concatenate((np.linspace(0.0, 1.0, 20001), [_LAM]))
    return max(float(np.linalg.norm(_dls_ref(np.diag([1.0, s]), [0.0, _ERR], _LAM))) for s in sigmas)


EXERCISES = (
    Exercise(
        "6.1", 6, "numeric", "Both solutions by hand", 1,
        "a 2 x 2 array [[theta1, theta2] elbow-down, [theta1, theta2] elbow-up], in radians",
        _judge_two_solutions(),
    ),
    Exercise(
        "6.2", 6, "numeric", "The determinant of the Jacobian", 1,
        "a number: det J (in square metres)",
        numeric(_det_j,
                mistakes=[(lambda: -_det_j(), "the sign is off: J is [[dx/dθ1, dx/dθ2], [dy/dθ1, "
                                              "dy/dθ2]], and det = J11 J22 - J12 J21."),
                          (lambda: _l1l2(np.sin(np.radians(_Q_62[1]))), "that takes θ2 in degrees; "
                                                                       "it is in radians."),
                          (lambda: _l1l2(np.sin(sum(_Q_62))), "that uses the absolute angle "
                                                              "θ1 + θ2; det J depends on the "
                                                              "relative angle θ2 alone."),
                          (lambda: _det_j() ** 2, "that is det(J Jᵀ) = (det J)²; this asks for "
                                                  "det J."),
                          (lambda: _l1l2(np.cos(_Q_62[1])), "that has a cosine where eq. ch06-det "
                                                            "has a sine.")],
                hint="build J from eq. ch06-jac (or rapp.jacobian) and take its determinant."),
    ),
    Exercise(
        "6.3", 6, "argue", "When the 2-link arm is singular", 2,
        "a function singular(L1, L2, q) returning True or False",
        implement(_singular2_ref, _two_link_cases, call="singular(L1, L2, q)", names=("L1", "L2", "q"),
                  compare=_compare_singular2, seed=63),
    ),
    Exercise(
        "6.4", 6, "argue", "Singular configurations of an n-link arm", 2,
        "a function singular(lengths, q) returning True or False, for any number of links",
        implement(_singular_ref, _n_link_cases, call="singular(lengths, q)", names=("lengths", "q"),
                  compare=_compare_singular_n, seed=64),
    ),
    Exercise(
        "6.5", 6, "implement", "One damped least-squares step", 2,
        "a function dls_step(J, e, lam) returning the step Δq, shape (n,)",
        implement(_dls_ref, _dls_cases, call="dls_step(J, e, lam)", names=("J", "e", "lam"),
                  compare=_compare_dls, seed=65),
    ),
    Exercise(
        "6.6", 6, "numeric", "The longest damped step", 1,
        "a number: the largest |Δq| in radians",
        numeric(_longest_dls_step,
                mistakes=[(lambda: _ERR / _LAM, "that is |e| / λ; the factor σ / (σ² + λ²) is "
                                                "largest at σ = λ, where it is 1 / (2λ)."),
                          (lambda: _ERR / _LAM**2, "that divides by λ²; at its largest the factor "
                                                   "σ / (σ² + λ²) is 1 / (2λ)."),
                          (lambda: _ERR / (2 * _LAM**2), "that divides by 2λ²; maximise σ / (σ² + λ²) "
                                                         "over σ and put σ back in."),
                          (lambda: _ERR / (2 * _LAM) ** 2, "maximise σ / (σ² + λ²) over σ and put "
                                                           "the maximiser back in.")],
                hint="in the singular-value basis each component of e is multiplied by "
                     "σ / (σ² + λ²); maximise that over σ ≥ 0."),
    ),
)
