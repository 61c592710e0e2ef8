"""Verification of a planned trajectory: every check with its measured value and its limit.

Every check reports what it measured next to the limit it was held to, so a
passing report is evidence and a failing one says by how much:

* ``collision-free``: the motion itself, every piece of the plan's ``motion``
  over its whole time span, between samples too, is certified free
  (:func:`rapp.motion.certify_motion`, a proof, not a test of the samples); a plan
  without its ``motion`` has each straight joint-space chord between consecutive
  samples certified instead (:func:`rapp.collision.segment_collision_free`);
* ``samples on the motion`` (with a ``motion``): the samples ``q`` are the motion
  at the times ``t``, to 1e-9 rad, so that what is certified is what is reported;
* ``min clearance``: the smallest link-obstacle distance over the whole motion,
  measured to 0.1 % (the certificate proves the motion never comes closer than
  that less 0.1 %); without a ``motion``, over the samples; with thick links
  (``arm.link_radius``) or a ``safety_margin``, the smallest gap beyond the one
  required (``link_radius + safety_margin``): the checks test the zero-width links
  against the obstacles grown by it (:func:`rapp.collision.scene`);
* ``joint limits``: the largest violation of a limit at the samples; with a
  ``motion``, every limited joint is also proved within its limits between them;
* ``starts at start`` and ``goal reached``: the first sample is the start, and
  the last one is the joint goal within 0.01 rad or puts the end effector
  within 1 mm of the Cartesian goal;
* ``continuity``: no jump between samples larger than the motion the sampled
  velocity and acceleration allow, and finite derivatives;
* ``time``: the sample times increase from 0 to the duration;
* ``FK consistency``: the reported Cartesian path is ``FK(q)`` to 1e-9 m;
* ``peak velocity`` and ``peak acceleration`` (only when ``trajectory.max_velocity``
  or ``trajectory.max_acceleration`` is given): the largest ``|q'|`` and ``|q''|``
  of each joint against its limit, exact when the plan carries its motion
  (:func:`rapp.time_scaling.peak_rates` over every piece), else over the samples;
  the joint nearest its limit is reported, and a peak above its limit by more
  than the relative rounding ``RATE_TOL`` fails;
* ``on the line`` (only for a goal with ``"path": "line"``): the end effector's
  distance from the segment from its start position to the goal, bounded over
  the whole straight joint-space chord between consecutive samples (the largest
  distance at 17 even points of the chord plus the curvature term ``K / 2048``,
  the bound of :func:`rapp.cartesian.edge_deviation_bound` on 16 intervals
  instead of 4), at most 1 mm. The bound covers the motion itself when the arm
  moves along each chord between samples, as a plan of a line goal does;
* ``validity (sampled at r rad, not certified)`` (only when :func:`verify` is given a user's
  ``validity`` checker, :mod:`rapp.validity`): the checker at points at most
  ``validity_resolution`` rad apart along each chord between samples, both ends included. A
  sampled check, not a proof: the check's very name says so, never "certified".

References
----------
SRS of 2D-RAPP (seed 000): R4 (verify the output), NFR1 (accuracy: 0.01 rad, 0.1 cm).
MIS of 2D-RAPP (seed 001): ``verifyOutput``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from typing import TYPE_CHECKING, Iterable, Protocol, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.scenario import Scenario

from rapp.collision import (clearance, collides, scene, segment_collision_free, segment_point_distance,
                            self_clearance)
from rapp.motion import certify_motion
from rapp.time_scaling import peak_rates
from rapp.trajectory import PiecewisePolynomial
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, user_validity


__all__ = ["Check", "Report", "verify", "JOINT_TOL", "POSITION_TOL", "FK_TOL", "RATE_TOL",
           "MOTION_TOL", "CLEARANCE_RTOL"]

#: NFR1: joint angles within 0.01 rad, Cartesian positions within 0.1 cm.
JOINT_TOL = 0.01
POSITION_TOL = 0.001
#: Reported Cartesian samples must be FK of the joint samples to rounding.
FK_TOL = 1e-9
START_TOL = 1e-9
LIMIT_TOL = 1e-9
#: A peak speed or acceleration may exceed its limit by this relative amount (rounding).
RATE_TOL = 1e-9
#: The samples must be the plan's motion at their times to this (rad).
MOTION_TOL = 1e-9
#: The motion's smallest clearance is measured to this relative precision.
CLEARANCE_RTOL = 1e-3


def _num(v):
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


@dataclass(frozen=True)
class Check:
    """One verification: measured ``value`` against ``limit`` (in ``unit``)."""

    name: str
    ok: bool
    value: float | None
    limit: float | None
    unit: str
    detail: str = ""

    def to_dict(self) -> dict:
        """A JSON-ready mapping; non-finite numbers become ``None``.

        Examples
        --------
        >>> Check("time", True, float("nan"), 1e-9, "s").to_dict()["value"] is None
        True
        """
        return {"name": self.name, "ok": bool(self.ok), "value": _num(self.value),
                "limit": _num(self.limit), "unit": self.unit, "detail": self.detail}

    @classmethod
    def from_dict(cls, d) -> "Check":
        """Inverse of :meth:`to_dict`.

        Examples
        --------
        >>> c = Check("joint limits", True, 0.0, 1e-9, "rad", "no limited joint")
        >>> Check.from_dict(c.to_dict()) == c
        True
        """
        return cls(str(d["name"]), bool(d["ok"]), d.get("value"), d.get("limit"),
                   str(d.get("unit", "")), str(d.get("detail", "")))


@dataclass(frozen=True)
class Report:
    """The outcome of :func:`verify`: ``ok`` when every check passed.

    Examples
    --------
    >>> r = Report.from_checks([Check("goal reached", True, 2e-12, 0.001, "m")])
    >>> r.ok, r["goal reached"].value
    (True, 2e-12)
    >>> Report.from_dict(r.to_dict()) == r
    True
    """

    ok: bool
    checks: tuple

    @classmethod
    def from_checks(cls, checks) -> "Report":
        """A report whose ``ok`` is the conjunction of the checks.

        Examples
        --------
        >>> Report.from_checks([Check("a", True, 0, 1, ""), Check("b", False, 2, 1, "")]).ok
        False
        """
        checks = tuple(checks)
        return cls(all(c.ok for c in checks), checks)

    def __getitem__(self, name: str) -> Check:
        for c in self.checks:
            if c.name == name:
                return c
        raise KeyError(name)

    @property
    def failed(self) -> tuple:
        """The checks that did not pass.

        Examples
        --------
        >>> r = Report.from_checks([Check("a", True, 0, 1, ""), Check("b", False, 2, 1, "")])
        >>> [c.name for c in r.failed]
        ['b']
        """
        return tuple(c for c in self.checks if not c.ok)

    def to_dict(self) -> dict:
        """A JSON-ready mapping: ``ok`` and one entry per check (see :meth:`Check.to_dict`).

        Examples
        --------
        >>> Report.from_checks([Check("a", True, 0.5, 1.0, "m")]).to_dict()["checks"][0]["value"]
        0.5
        """
        return {"ok": bool(self.ok), "checks": [c.to_dict() for c in self.checks]}

    @classmethod
    def from_dict(cls, d) -> "Report":
        """Inverse of :meth:`to_dict` (see the class example)."""
        return cls(bool(d["ok"]), tuple(Check.from_dict(c) for c in d["checks"]))

    def __str__(self) -> str:
        def fmt(v):
            return "-" if v is None else f"{v:.3g}"

        rows = [("check", "ok", "measured", "limit", "unit")]
        rows += [(c.name, "yes" if c.ok else "NO", fmt(c.value), fmt(c.limit), c.unit)
                 for c in self.checks]
        w = [max(len(r[i]) for r in rows) for i in range(5)]
        lines = ["  ".join(f"{r[i]:<{w[i]}}" for i in range(5)).rstrip() for r in rows]
        lines.insert(1, "  ".join("-" * x for x in w))
        lines.append(f"verification: {'passed' if self.ok else 'FAILED'}")
        return "\n".join(lines)


def _joint_error(arm, q, target) -> np.ndarray:
    """|q - target| per joint, measured the short way round on a free joint."""
    return np.abs(arm.joint_delta(target, q))


def _check_collision(arm, obs, q) -> list:
    """A certified continuous check of each chord between samples; one sample is a point."""
    k = len(q)
    if k >= 2:
        n_bad = int((~segment_collision_free(arm, q[:-1], q[1:], obs)).sum())
    else:
        n_bad = int((bool(obs) or arm.self_collision) and bool(collides(arm, q, obs).any()))
    checks = [Check("collision-free", n_bad == 0, n_bad, 0, "segments",
                    f"{max(k - 1, 1)} chords between samples, each certified over its whole "
                    "length (the plan carries no motion)")]
    if obs:
        c = float(clearance(arm, q, obs).min())
        checks.append(Check("min clearance", c > 0, c, 0.0, "m",
                            "smallest link-obstacle distance over the samples; must be > 0"))
    return checks


def _check_motion(arm, obs, motion, t, q) -> tuple:
    """The motion certified over its whole time span: ``(checks, certificate)``."""
    cert = certify_motion(arm, motion, obs, rtol=CLEARANCE_RTOL)
    with np.errstate(all="ignore"):
        gap = float(np.abs(motion.evaluate(t) - q).max())
    on = (bool(gap <= MOTION_TOL) and float(t[0]) == motion.t0 and float(t[-1]) == motion.tf)
    n_bad = int((~cert.pieces).sum())
    pieces = len(cert.pieces)
    checks = [Check("collision-free", cert.free, n_bad, 0, "pieces",
                    f"the motion q(t), {pieces} polynomial piece{'s' * (pieces != 1)}, certified "
                    "over its whole time span, between samples too"),
              Check("samples on the motion", on, gap, MOTION_TOL, "rad",
                    "samples against the motion at their times, which spans them exactly")]
    if obs:
        checks.append(Check("min clearance", cert.free and cert.lower > 0, cert.clearance, 0.0,
                            "m", "smallest link-obstacle distance over the whole motion, between "
                            f"samples too (proved at least {cert.lower:.6g} m); must be > 0"))
    return checks, cert


def _check_required(arm, obs, q, margin) -> list:
    """:func:`_check_collision` of thick links with a margin: zero-width links, grown obstacles."""
    thin, grown = scene(arm, obs, margin)
    checks = _check_collision(thin, list(grown), q)
    if arm.self_collision and arm.n >= 3:
        checks.append(_self_gap_check(arm, thin, q, margin, "certified along each segment "
                                      "(counted in collision-free)"))
    if thin is arm and not margin:
        return checks
    detail = _required_detail(arm, margin, "the samples")
    return [replace(c, detail=detail) if c.name == "min clearance" else c for c in checks]


def _self_gap_check(arm, thin, q, margin, how) -> Check:
    """The smallest gap between non-adjacent links over the samples (``arm.self_collision``)."""
    gap = float(self_clearance(thin, q).min())
    radii = ", ".join(f"{r:g}" for r in arm.link_radius)
    return Check("min self-gap", gap > 0, gap, 0.0, "m",
                 f"self-collision checked: every non-adjacent link pair {how}; the smallest pair "
                 f"distance over the samples beyond the one required (r_i + r_j + margin; "
                 f"r = [{radii}] m, margin {margin:g} m); must be > 0")


def _required_detail(arm, margin, over) -> str:
    need = ", ".join(f"{r + margin:g}" for r in arm.link_radius)
    return (f"smallest gap over {over} beyond the distance each link must keep "
            f"(link radius + safety margin: [{need}] m); must be > 0")


def _check_motion_required(arm, obs, motion, t, q, margin) -> tuple:
    """:func:`_check_motion` of thick links with a margin: zero-width links, grown obstacles."""
    thin, grown = scene(arm, obs, margin)
    checks, cert = _check_motion(thin, list(grown), motion, t, q)
    if arm.self_collision and arm.n >= 3:
        checks.append(_self_gap_check(arm, thin, q, margin, "certified over the whole motion, "
                                      "between samples too (counted in collision-free)"))
    if thin is arm and not margin:
        return checks, cert
    detail = _required_detail(arm, margin, "the whole motion, between samples too")
    return [replace(c, detail=detail) if c.name == "min clearance" else c for c in checks], cert


def _check_limits(arm, q, cert=None) -> Check:
    lo, hi, lim = arm.lower, arm.upper, arm.limited
    viol = np.where(lim, np.maximum(lo - q, q - hi), -np.inf).max() if lim.any() else -np.inf
    viol = max(float(viol), 0.0)
    if not lim.any():
        return Check("joint limits", True, viol, LIMIT_TOL, "rad", "no limited joint")
    if cert is None:
        return Check("joint limits", viol <= LIMIT_TOL, viol, LIMIT_TOL, "rad",
                     "largest excess beyond a joint limit at the samples")
    return Check("joint limits", viol <= LIMIT_TOL and cert.within_limits and cert.free, viol,
                 LIMIT_TOL, "rad", "largest excess beyond a joint limit at the samples; "
                 + ("proved within the limits between samples too" if cert.within_limits
                    and cert.free else "NOT proved within the limits between samples"))


def _check_ends(arm, q, scenario) -> list:
    e0 = float(_joint_error(arm, q[0], scenario.start).max())
    checks = [Check("starts at start", e0 <= START_TOL, e0, START_TOL, "rad",
                    "first sample against the scenario's start")]
    if scenario.goal_q is not None:
        eg = float(_joint_error(arm, q[-1], scenario.goal_q).max())
        checks.append(Check("goal reached", eg <= JOINT_TOL, eg, JOINT_TOL, "rad",
                            "last sample against the joint goal (NFR1: 0.01 rad)"))
    else:
        eg = float(np.hypot(*(arm.end_effector(q[-1]) - np.asarray(scenario.goal_xy))))
        checks.append(Check("goal reached", eg <= POSITION_TOL, eg, POSITION_TOL, "m",
                            "FK of the last sample against the Cartesian goal (NFR1: 0.1 cm)"))
    return checks


def _check_continuity(t, q, qd, qdd) -> Check:
    """By Taylor, |q(t+h) - q(t)| <= |q'(t)| h + max|q''| h^2 / 2 per joint; a jump beyond
    1.5 times that (plus rounding) is not a continuous motion."""
    h = np.diff(t)[:, None]
    amax = np.abs(qdd).max(axis=0)
    vmax = np.maximum(np.abs(qd[:-1]), np.abs(qd[1:]))
    bound = 1.5 * (vmax * h + 0.5 * amax * h**2) + 1e-9
    jump = np.abs(np.diff(q, axis=0))
    ratio = float((jump / bound).max())
    return Check("continuity", ratio <= 1.0, ratio, 1.0, "ratio",
                 f"largest step {float(jump.max()):.3g} rad between samples over its "
                 "bound 1.5 (|q'| dt + max|q''| dt^2 / 2)")


def _check_time(t, duration) -> Check:
    k = len(t)
    dt_ok = bool(np.all(np.diff(t) > 0)) if k >= 2 else True
    terr = abs(float(t[0])) + abs(float(t[-1] - t[0]) - duration) if k >= 2 else 0.0
    tlim = 1e-9 * max(duration, 1.0)  # relative to the duration: times are sums of float steps
    return Check("time", dt_ok and terr <= tlim, terr, tlim, "s",
                 f"times increase from 0 to the duration {duration:g} s")


def _check_rates(plan, qd, qdd, trajectory) -> list:
    """Peak speed and acceleration of every joint against its limit (where one is given)."""
    motion = getattr(plan, "motion", None)
    if isinstance(motion, PiecewisePolynomial):
        v, a = peak_rates(motion)
        how = "exact peak over the whole motion"
    else:
        v, a = np.abs(qd).max(axis=0), np.abs(qdd).max(axis=0)
        how = "largest value at the samples"
    checks = []
    for name, peak, limit, unit in (("peak velocity", v, trajectory.max_velocity, "rad/s"),
                                    ("peak acceleration", a, trajectory.max_acceleration,
                                     "rad/s^2")):
        if limit is None:
            continue
        limit = np.asarray(limit, float)
        ratio = peak / limit
        j = int(np.argmax(ratio))
        checks.append(Check(name, bool(np.all(ratio <= 1.0 + RATE_TOL)), float(peak[j]),
                            float(limit[j]), unit, f"joint {j}, the nearest its limit "
                            f"({ratio[j]:.10g} of it); {how}"))
    return checks


#: The points of a chord at which ``on the line`` measures the distance: 16 intervals.
_CHORD_T = np.linspace(0.0, 1.0, 17)


def _check_line(arm, q, xy, scenario) -> Check:
    """Distance of the end effector from the segment start -> goal, over the chords between
    samples: 17 points of each chord plus ``K h^2 / 8 = K / 2048`` (``h = 1/16``),
    ``K = sum_i L_i Phi_i^2``: the bound of :func:`rapp.cartesian.edge_deviation_bound`,
    proved in :mod:`rapp.cartesian`, on a finer partition."""
    a = arm.end_effector(np.asarray(scenario.start, float))
    b = np.asarray(scenario.goal_xy, float)
    sampled = float(segment_point_distance(a, b, xy).max())
    if len(q) >= 2:
        dq = np.diff(q, axis=0)
        phi = np.cumsum(dq, axis=1)
        curve = (phi * phi) @ arm.lengths / 2048.0
        pts = arm.end_effector(q[:-1, None, :] + _CHORD_T[None, :, None] * dq[:, None, :])
        bound = float((segment_point_distance(a, b, pts).max(axis=1) + curve).max())
    else:
        bound = sampled
    return Check("on the line", bound <= POSITION_TOL, bound, POSITION_TOL, "m",
                 f"end effector's distance from the straight segment to the goal, bounded "
                 f"between samples along each joint-space chord ({sampled:.3g} m at the samples)")


def _check_validity(arm, q, checker) -> Check:
    """The user's checker along every chord between samples, at its resolution (sampled)."""
    chords = max(len(q) - 1, 1)
    ok = (checker.edges(q[:-1], q[1:], arm) if len(q) >= 2 else checker.points(q, arm))
    bad = int((~ok).sum())
    return Check(f"validity ({checker.text})", bad == 0, bad, 0, "chords",
                 f"the user's validity checker at points at most {checker.resolution:g} rad apart "
                 f"along each of the {chords} chords between samples, ends included: "
                 f"{checker.text}")


class SampledTrajectory(Protocol):
    """What :func:`verify` reads of a plan: a :class:`rapp.results.Plan`, or any object with
    these arrays (and, optionally, the ``motion`` it certified)."""

    @property
    def t(self) -> np.ndarray:
        """(k,) times."""

    @property
    def q(self) -> np.ndarray:
        """(k, n) joint angles."""

    @property
    def qd(self) -> np.ndarray:
        """(k, n) joint velocities."""

    @property
    def qdd(self) -> np.ndarray:
        """(k, n) joint accelerations."""

    @property
    def xy(self) -> np.ndarray:
        """(k, 2) end-effector positions."""


def verify(plan: SampledTrajectory, scenario: Scenario, *, validity: ValidityFunction | None = None,
           validity_resolution: float = DEFAULT_RESOLUTION) -> Report:
    """Check a plan's timed trajectory against the scenario.

    Parameters
    ----------
    plan : rapp.results.Plan, or any object with ``t`` (k,), ``q``, ``qd``, ``qdd`` (k, n) and ``xy`` (k, 2)
    scenario : Scenario
    validity : callable, optional
        A user's checker (:mod:`rapp.validity`), ``(m, n)`` configurations -> ``m`` booleans;
        a scenario cannot carry one, so it is given here. Adds the check
        ``validity (sampled at r rad, not certified)``: the checker at points at most
        ``validity_resolution`` rad apart along each chord between samples.
    validity_resolution : float
        That step (rad).

    Returns
    -------
    Report

    Examples
    --------
    >>> from rapp import load_scenario, plan
    >>> s = load_scenario("default")
    >>> r = verify(plan(s), s)
    >>> r.ok, r["goal reached"].unit
    (True, 'm')
    >>> away = lambda q: np.hypot(*s.arm.end_effector(q).T) > 0.1   # the tip keeps off the base
    >>> verify(plan(s), s, validity=away, validity_resolution=0.05).checks[-1].name
    'validity (sampled at 0.05 rad, not certified)'
    """
    checker = user_validity(validity, validity_resolution)
    arm, obs = scenario.arm, scenario.obstacles
    t = np.asarray(plan.t, dtype=float)
    q = np.asarray(plan.q, dtype=float)
    qd = np.asarray(plan.qd, dtype=float)
    qdd = np.asarray(plan.qdd, dtype=float)
    xy = np.asarray(plan.xy, dtype=float)
    k = t.shape[0] if t.ndim == 1 else -1
    shapes_ok = (t.ndim == 1 and k >= 1 and q.shape == (k, arm.n) and qd.shape == q.shape
                 and qdd.shape == q.shape and xy.shape == (k, 2))
    shape_check = Check("shapes", shapes_ok, None, None, "",
                        f"t {t.shape}, q {q.shape}, qd {qd.shape}, qdd {qdd.shape}, xy {xy.shape}")
    if not shapes_ok:
        return Report.from_checks([shape_check])
    finite = bool(np.isfinite(q).all() and np.isfinite(qd).all() and np.isfinite(qdd).all()
                  and np.isfinite(t).all() and np.isfinite(xy).all())
    if not finite:
        return Report.from_checks([shape_check, Check(
            "finite", False, None, None, "", "t, q, q', q'' or xy holds NaN or infinity")])
    margin = getattr(scenario, "safety_margin", 0.0)
    motion = getattr(plan, "motion", None)
    if isinstance(motion, PiecewisePolynomial) and motion.dim == arm.n:
        found, cert = _check_motion_required(arm, obs, motion, t, q, margin)
    else:
        found, cert = _check_required(arm, obs, q, margin), None
    checks = [shape_check, *found, _check_limits(arm, q, cert), *_check_ends(arm, q, scenario)]
    if k >= 2:
        checks.append(_check_continuity(t, q, qd, qdd))
    tr = scenario.trajectory
    # Without a duration the plan took the shortest within the limits: its own last time.
    checks.append(_check_time(t, tr.duration if tr.duration is not None else float(t[-1])))
    fk = float(np.abs(arm.end_effector(q) - xy).max())
    checks.append(Check("FK consistency", fk <= FK_TOL, fk, FK_TOL, "m",
                        "reported Cartesian path against FK of the joint samples"))
    if getattr(scenario, "goal_path", None) == "line":
        checks.append(_check_line(arm, q, xy, scenario))
    checks.extend(_check_rates(plan, qd, qdd, tr))
    if checker is not None:
        checks.append(_check_validity(arm, q, checker))
    return Report.from_checks(checks)
