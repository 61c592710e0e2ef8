"""Per-student numbers for the numeric exercises of chapters 1–8, from an instructor's secret key.

The exercises with variants: 1.3, 1.4, 2.1, 2.2, 3.1, 3.5, 4.1, 4.3, 5.1, 5.3, 6.1, 6.2, 6.6, 8.1, 8.3.

Without a key nothing changes: the book's numbers, which the book prints anyway. With a key, each
student gets a *code*, ``code(key, student)`` (an HMAC of the student id), and each exercise that
has a variant draws its numbers from that code: ``python -m rapp assign`` writes every student's
sheet (their numbers and their code), ``python -m rapp grade --key`` computes each student's
expected answers from the same key. The expected values are never stored; they are computed
from a code, and a code is derived from the secret key, so the package cannot hand a
student's answers to anyone who has neither the key nor that student's sheet. A student checks
their own answers with their code: ``rapp.exercises.check("1.3", 0.42, variant=CODE)``.

Chapter 7 has no variant: its numbers come from planning runs on the chapter's scenarios (7.1,
7.3) or are an exit code (7.5); 1.1 has a single answer, 4.4 is the chapter's benchmark grid,
and 4.6 and 5.6 are read off the chapter's live explorer, which shows the book's scenario.

Examples
--------
>>> c = code("instructor secret", "alice")
>>> len(c), c == code("instructor secret", "alice"), c == code("instructor secret", "bob")
(16, True, False)
>>> p = params("1.3", c)
>>> judge("1.3", c)(abs(p["L1"] - p["L2"])).correct
True
"""

from __future__ import annotations

import hashlib
import hmac
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.collision import motion_bounds, segment_point_distance
from rapp.exercises.core import Judgement, numeric
from rapp.ik import ik_2link, jacobian
from rapp import search, trajectory

__all__ = ["Variant", "VARIANTS", "code", "params", "judge", "statement", "has_variant"]


@dataclass(frozen=True)
class Variant:
    """How one exercise's numbers vary: draw them, state them, compute the answer."""

    draw: Callable[[np.random.Generator], dict]
    text: Callable[[dict], str]
    expected: Callable[[dict], Any]
    exact_integer: bool = False
    angles: bool = False
    mistakes: Callable[[dict], list] = lambda p: []


def code(key: str, student: str) -> str:
    """The student's code: 16 hex digits of HMAC-SHA256(key, student id)."""
    return hmac.new(str(key).encode(), str(student).strip().encode(), hashlib.sha256).hexdigest()[:16]


def _rng(variant_code: str, ex_id: str) -> np.random.Generator:
    digest = hashlib.sha256(f"{variant_code}|{ex_id}".encode()).digest()
    return np.random.default_rng(int.from_bytes(digest[:8], "little"))


def has_variant(ex_id: str) -> bool:
    return ex_id in VARIANTS


def params(ex_id: str, variant_code: str) -> dict:
    """The numbers of exercise ``ex_id`` for the student whose code is ``variant_code``."""
    return VARIANTS[ex_id].draw(_rng(str(variant_code), ex_id))


def statement(ex_id: str, variant_code: str) -> str:
    """The exercise as the student's sheet states it, with their numbers."""
    return VARIANTS[ex_id].text(params(ex_id, variant_code))


def judge(ex_id: str, variant_code: str) -> Callable[[Any], Judgement]:
    """The judge of ``ex_id`` with the numbers of ``variant_code`` (same tolerance policy as the book)."""
    v = VARIANTS[ex_id]
    p = params(ex_id, variant_code)
    base = numeric(lambda: v.expected(p), exact_integer=v.exact_integer, angles=v.angles,
                   mistakes=[(lambda w=w: w, why) for w, why in v.mistakes(p)],
                   hint="work it with the numbers of your sheet.")
    if ex_id != "6.1":
        return base

    def flat(answer):  # 6.1 takes a 2 x 2 array or the four angles in a row
        arr = np.asarray(answer, dtype=float) if isinstance(answer, (list, tuple, np.ndarray)) else None
        if arr is not None and arr.shape == (2, 2):
            return base(arr.reshape(4))
        return base(answer)

    flat.tolerance = base.tolerance
    return flat


# --- the variants -----------------------------------------------------------------------------

def _u(rng, lo, hi, digits=2) -> float:
    return round(float(rng.uniform(lo, hi)), digits)


def _peak(coeffs, order: int, tf: float) -> float:
    """Largest |d^order q / dt^order| of a polynomial (ascending coefficients) on [0, tf]."""
    poly = np.polynomial.Polynomial(coeffs).deriv(order)
    points = [0.0, tf] + [float(r.real) for r in poly.deriv().roots() if abs(r.imag) < 1e-12 and 0 < r.real < tf]
    return float(max(abs(poly(t)) for t in points))


def _ring_cost(p) -> int:
    return int(search.astar_search(np.zeros(p["n"], bool), [p["s"]], [p["g"]], heuristic_wraps=False).cost)


VARIANTS: dict[str, Variant] = {
    "1.3": Variant(
        lambda r: {"L1": _u(r, 0.8, 1.5), "L2": _u(r, 0.2, 0.7)},
        lambda p: f"The arm ({p['L1']}, {p['L2']}) cannot reach the points near its base. What is the "
                  "radius, in metres, of the disc around the base that its end effector never enters?",
        lambda p: Arm([p["L1"], p["L2"]]).reach[0],
        mistakes=lambda p: [(p["L1"] + p["L2"], "that is the outer radius, the arm stretched out."),
                            (p["L2"], "that is the second link alone; fold the elbow back.")]),
    "1.4": Variant(
        lambda r: {"a": _u(r, 2.6, 3.1), "b": _u(r, -1.0, 1.0)},
        lambda p: f"Two configurations of a two-link arm are q_a = ({p['a']}, {p['b']}) and "
                  f"q_b = ({-p['a']}, {p['b']}). How long (Euclidean length, in radians) is the shortest "
                  "straight move in the joint space from one to the other, on the torus?",
        lambda p: float(np.linalg.norm(wrap_angle(np.array([-p["a"], p["b"]]) - [p["a"], p["b"]]))),
        mistakes=lambda p: [(2 * p["a"], "that is the long way round; on the torus the two are close.")]),
    "2.1": Variant(
        lambda r: {"L": [_u(r, 0.3, 1.2) for _ in range(3)]},
        lambda p: f"What is the reach (r_min, r_max) of the arm with links {tuple(p['L'])} m? "
                  "Pass the pair (r_min, r_max) in metres.",
        lambda p: Arm(p["L"]).reach),
    "2.2": Variant(
        lambda r: {"L": [_u(r, 0.4, 1.2, 1) for _ in range(3)], "q": [_u(r, -1.6, 1.6) for _ in range(3)]},
        lambda p: f"Where is the end effector of the arm with links {tuple(p['L'])} m at q = "
                  f"{tuple(p['q'])} rad? Pass the pair (x, y) in metres.",
        lambda p: Arm(p["L"]).end_effector(p["q"])),
    "3.1": Variant(
        lambda r: {"bx": _u(r, 1.5, 3.0, 1), "cx": _u(r, 0.5, 4.0, 1), "cy": _u(r, 0.4, 1.5, 1),
                   "r": _u(r, 0.5, 1.5, 1)},
        lambda p: f"The link runs from a = (0, 0) to b = ({p['bx']}, 0), and a disc of radius {p['r']} has "
                  f"its centre at c = ({p['cx']}, {p['cy']}) (metres). What is the distance from c to the "
                  "link? Pass it in metres.",
        lambda p: float(segment_point_distance((0.0, 0.0), (p["bx"], 0.0), (p["cx"], p["cy"]))),
        mistakes=lambda p: [(p["cy"], "that is the distance to the infinite line; the link ends at a and b.")]
        if not 0 <= p["cx"] <= p["bx"] else []),
    "3.5": Variant(
        lambda r: {"L": [_u(r, 0.5, 1.5, 1) for _ in range(2)], "dq": [_u(r, 0.05, 0.3) for _ in range(2)]},
        lambda p: f"For the arm with links {tuple(p['L'])} m and the joint step dq = {tuple(p['dq'])} rad, "
                  "compute the motion bounds B1, B2. Pass the array [B1, B2] in metres.",
        lambda p: motion_bounds(Arm(p["L"]), p["dq"])),
    "4.1": Variant(
        lambda r: {"M": int(r.choice([8, 10, 12, 16, 20, 24])), "a": _u(r, -3.1, 3.1), "b": _u(r, -3.1, 3.1)},
        lambda p: f"On a grid of M = {p['M']} cells per freely turning joint, which cell index holds "
                  f"theta = {p['a']} rad, and which holds theta = {p['b']} rad? The cell of an angle is the "
                  "one whose grid angle is nearest, as JointGrid.index does it. Pass [k1, k2].",
        lambda p: [int(_cell(p["a"], p["M"])), int(_cell(p["b"], p["M"]))], exact_integer=True),
    "4.3": Variant(
        lambda r: (lambda d, rad: {"d": d, "r": rad, "L": _u(r, d - rad + 0.1, d + 0.2, 1)})(_u(r, 1.2, 2.0, 1), _u(r, 0.3, 0.6, 1)),
        lambda p: f"A link of length L = {p['L']} m starts at a point at distance d = {p['d']} m from the centre "
                  f"of a disc of radius r = {p['r']} m. Over what angle, the full width of the interval of "
                  "link directions, does the link hit the disc? Answer in radians.",
        lambda p: 2 * _half_width(p["L"], p["d"], p["r"]),
        mistakes=lambda p: [(_half_width(p["L"], p["d"], p["r"]), "that is the half-width; the question asks "
                                                                   "for the full width.")]),
    "5.1": Variant(
        lambda r: {"M": int(r.integers(60, 121)), "a": [int(v) for v in r.integers(0, 60, 2)],
                   "b": [int(v) for v in r.integers(0, 60, 2)]},
        lambda p: f"On a {p['M']} x {p['M']} torus, what is GD1 between cells {tuple(p['a'])} and "
                  f"{tuple(p['b'])}?",
        lambda p: int(search.toroidal_manhattan(p["a"], p["b"], (p["M"], p["M"]))), exact_integer=True,
        mistakes=lambda p: [(sum(abs(x - y) for x, y in zip(p["a"], p["b"])),
                             "that is the wrap-blind distance; on each axis take the shorter way round.")]),
    "5.3": Variant(
        lambda r: (lambda n: {"n": n, "s": int(r.integers(1, 4)), "g": n - int(r.integers(2, 5))})(int(r.integers(16, 31))),
        lambda p: f"A 1-D ring of {p['n']} free cells, start {p['s']}, goal {p['g']}. How many steps long is "
                  f"the path A* returns with the wrap-blind heuristic h(c) = |c - {p['g']}|?",
        _ring_cost, exact_integer=True),
    "6.1": Variant(
        lambda r: {"L": [_u(r, 0.7, 1.3, 1) for _ in range(2)], "rad": _u(r, 0.3, 0.95), "phi": _u(r, -3.0, 3.0)},
        lambda p: f"The arm {tuple(p['L'])} and the target ({_target(p)[0]:.4f}, {_target(p)[1]:.4f}): find both "
                  "solutions. Pass them as a 2 x 2 array, elbow-down (theta2 > 0) first, in radians.",
        lambda p: ik_2link(p["L"], _target(p)).reshape(4), angles=True),
    "6.2": Variant(
        lambda r: {"L": [_u(r, 0.5, 1.5, 1) for _ in range(2)], "q": [_u(r, -1.5, 1.5), _u(r, 0.3, 2.8)]},
        lambda p: f"The 2-link arm (L1, L2) = {tuple(p['L'])} m is at q = {tuple(p['q'])} rad. Compute det J "
                  "(in square metres).",
        lambda p: float(np.linalg.det(jacobian(Arm(p["L"]), p["q"])))),
    "6.6": Variant(
        lambda r: {"lam": _u(r, 0.03, 0.3), "e": _u(r, 0.05, 0.5)},
        lambda p: f"With lambda = {p['lam']}, what is the longest step |dq| (in radians) that DLS can take "
                  f"for an error of |e| = {p['e']} m, whatever the configuration?",
        lambda p: _longest_dls(p["lam"], p["e"])),
    "8.1": Variant(
        lambda r: {"d": _u(r, 0.5, 2.0, 1), "T": float(r.choice([1.0, 1.5, 2.0, 2.5, 3.0, 4.0]))},
        lambda p: f"A joint moves from rest at 0 rad to rest at {p['d']} rad in T = {p['T']:g} s along the "
                  "cubic (t0 = 0). What is its peak velocity? Pass it in rad/s.",
        lambda p: _peak(trajectory.cubic(0.0, p["T"], 0.0, p["d"]), 1, p["T"]),
        mistakes=lambda p: [(p["d"] / p["T"], "that is the mean velocity; the cubic peaks in the middle.")]),
    "8.3": Variant(
        lambda r: {"d": _u(r, 0.5, 2.0, 1), "T": float(r.choice([1.0, 1.5, 2.0, 2.5, 3.0, 4.0]))},
        lambda p: f"A joint moves from rest at 0 rad to rest at {p['d']} rad in T = {p['T']:g} s along the "
                  "rest-to-rest quintic. What is its peak |acceleration|? Pass it in rad/s^2.",
        lambda p: _peak(trajectory.quintic(0.0, p["T"], 0.0, p["d"]), 2, p["T"])),
}


def _half_width(L: float, d: float, r: float) -> float:
    """Largest angle between the link and the centre at which rapp.collides says the link hits."""
    from rapp.collision import collides
    from rapp.obstacles import Circle

    arm, disc = Arm([L]), [Circle((d, 0.0), r)]
    lo, hi = 0.0, np.pi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if bool(collides(arm, [mid], disc)) else (lo, mid)
    return lo


def _longest_dls(lam: float, e: float) -> float:
    """The largest |J^T (J J^T + lam^2 I)^-1 e| over J = diag(1, sigma), sigma in [0, 1] and lam itself."""
    sigmas = np.concatenate((np.linspace(0.0, 1.0, 201), [lam]))
    return max(float(np.linalg.norm(np.diag([1.0, s]) @ np.linalg.solve(
        np.diag([1.0, s]) ** 2 + lam**2 * np.eye(2), [0.0, e]))) for s in sigmas)


def _cell(angle: float, m: int) -> int:
    from rapp.cspace import JointGrid
    return int(JointGrid(Arm([1.0]), int(m)).index([float(angle)])[0])


def _target(p: dict) -> np.ndarray:
    """A reachable target: a fraction ``rad`` of the way from the inner to the outer reach."""
    lo, hi = abs(p["L"][0] - p["L"][1]), p["L"][0] + p["L"][1]
    r = lo + p["rad"] * (hi - lo)
    return np.round(np.array([r * np.cos(p["phi"]), r * np.sin(p["phi"])]), 4)
