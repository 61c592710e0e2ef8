"""Symbolic derivations with sympy, and their lambdified numeric versions.

The book derives the formulas the package uses rather than quoting them:
forward kinematics and the Jacobian of an n-link planar arm (seed 003 gives
the 3-link Jacobian), the law-of-cosines inverse kinematics of a 2-link arm
(seeds 002 and 004), and the cubic and quintic boundary-value polynomials of
seed 002 in absolute time. Every function here is pure: it builds fresh
symbols and expressions on each call (no caches, no module state).

The ``*_function`` helpers return numpy callables made by ``sympy.lambdify``;
tests compare them with the hand-written numeric code of :mod:`rapp.arm`,
:mod:`rapp.ik` and :mod:`rapp.trajectory`.
"""

from __future__ import annotations

import functools

import numpy as np
import sympy as sp

__all__ = [
    "fk_symbolic",
    "joint_positions_symbolic",
    "jacobian_symbolic",
    "manipulability_symbolic",
    "ik_2link_symbolic",
    "cubic_coefficients_symbolic",
    "quintic_coefficients_symbolic",
    "fk_function",
    "jacobian_function",
    "ik_2link_function",
    "cubic_function",
    "quintic_function",
    "check_fk",
    "check_ik_2link",
    "check_jacobian",
]


def _arm_symbols(n: int):
    if int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n}")
    q = sp.symbols(f"q1:{n + 1}", real=True)
    lengths = sp.symbols(f"L1:{n + 1}", positive=True)
    return q, lengths


def joint_positions_symbolic(n: int):
    """Positions of base, joints and tip of an n-link arm, as a sympy Matrix.

    Returns
    -------
    P : sympy.Matrix, shape (n + 1, 2)
    q, L : tuples of sympy symbols ``q1..qn`` and ``L1..Ln``

    Examples
    --------
    >>> P, q, L = joint_positions_symbolic(2)
    >>> P[2, 0]
    L1*cos(q1) + L2*cos(q1 + q2)
    """
    q, lengths = _arm_symbols(n)
    rows = [[sp.Integer(0), sp.Integer(0)]]
    phi = sp.Integer(0)
    x = y = sp.Integer(0)
    for qi, li in zip(q, lengths):
        phi = phi + qi
        x = x + li * sp.cos(phi)
        y = y + li * sp.sin(phi)
        rows.append([x, y])
    return sp.Matrix(rows), q, lengths


def fk_symbolic(n: int):
    """End effector ``(x, y)`` of an n-link arm (TM:FWDKinematics), a 2 x 1 Matrix.

    Examples
    --------
    >>> f, q, L = fk_symbolic(2)
    >>> f[1]
    L1*sin(q1) + L2*sin(q1 + q2)
    """
    P, q, lengths = joint_positions_symbolic(n)
    return P[n, :].T, q, lengths


def jacobian_symbolic(n: int):
    """Jacobian ``d(x, y)/dq`` of an n-link arm, a 2 x n Matrix.

    Examples
    --------
    >>> J, q, L = jacobian_symbolic(2)
    >>> J[0, 1]
    -L2*sin(q1 + q2)
    """
    f, q, lengths = fk_symbolic(n)
    return f.jacobian(sp.Matrix(q)), q, lengths


def manipulability_symbolic(n: int):
    """Yoshikawa's manipulability ``w = sqrt(det(J J^T))`` of an n-link arm, simplified.

    By the Cauchy-Binet formula ``det(J J^T)`` is the sum of the squares of
    the 2 x 2 minors of ``J`` (pairs of columns ``i < j``); each minor
    simplifies to a sum of ``L_a L_b sin(q_{a+1} + ... + q_b)`` terms, which
    is how :mod:`rapp.manipulability` computes ``w`` numerically too. For two
    links the single minor is ``L1 L2 sin q2``.

    Returns
    -------
    w : sympy expression
        ``0`` for one link (``J`` has rank one).
    q, L : tuples of sympy symbols ``q1..qn`` and ``L1..Ln``

    Examples
    --------
    >>> w, q, L = manipulability_symbolic(2)
    >>> w
    L1*L2*Abs(sin(q2))
    """
    J, q, lengths = jacobian_symbolic(n)
    minors = [
        sp.simplify(sp.expand_trig(J[0, i] * J[1, j] - J[0, j] * J[1, i]))
        for i in range(n) for j in range(i + 1, n)
    ]
    return sp.sqrt(sum((m**2 for m in minors), sp.Integer(0))), q, lengths


def ik_2link_symbolic():
    """Derive the analytic 2-link IK by the law of cosines.

    Squaring and adding the two FK equations eliminates ``q1``:
    ``x^2 + y^2 = L1^2 + L2^2 + 2 L1 L2 cos q2`` (sympy checks this identity),
    which is solved for ``cos q2``. Then the tip is the vector sum of a link
    of length ``L1 + L2 cos q2`` along ``q1`` and one of ``L2 sin q2``
    perpendicular to it, so
    ``q1 = atan2(y, x) - atan2(L2 sin q2, L1 + L2 cos q2)``.

    Returns
    -------
    dict
        ``"cos_q2"``: the expression for ``cos q2``; ``"elbow_down"`` and
        ``"elbow_up"``: ``(q1, q2)`` expressions with ``q2 = +acos`` and
        ``q2 = -acos`` respectively (the names of seed 002; seed 004 calls
        ``+acos`` elbow-up); ``"symbols"``: ``(x, y, L1, L2)``.

    Examples
    --------
    >>> sol = ik_2link_symbolic()
    >>> sol["cos_q2"]
    (-L1**2 - L2**2 + x**2 + y**2)/(2*L1*L2)
    """
    f, (q1, q2), (l1, l2) = fk_symbolic(2)
    x, y = sp.symbols("x y", real=True)
    c = sp.Symbol("c", real=True)
    r2 = sp.expand(sp.trigsimp(sp.expand_trig(f[0] ** 2 + f[1] ** 2)))
    # r2 == L1^2 + L2^2 + 2 L1 L2 cos(q2): solve for the cosine.
    (cos_q2,) = sp.solve(sp.Eq(r2.subs(sp.cos(q2), c), x**2 + y**2), c)
    cos_q2 = sp.together(cos_q2)
    out = {"cos_q2": cos_q2, "symbols": (x, y, l1, l2)}
    for name, sign in (("elbow_down", 1), ("elbow_up", -1)):
        q2e = sign * sp.acos(cos_q2)
        q1e = sp.atan2(y, x) - sp.atan2(l2 * sp.sin(q2e), l1 + l2 * sp.cos(q2e))
        out[name] = (q1e, q2e)
    return out


# Solved once per degree: sympy expressions are immutable, so every caller may share them.
@functools.lru_cache(maxsize=None)
def _boundary_value(degree: int):
    t, t0, tf = sp.symbols("t t0 tf", real=True)
    names = ["p0", "pf", "v0", "vf", "a0", "af"][: degree + 1]
    vals = sp.symbols(" ".join(names), real=True)
    # Unknowns named c_k: "a0" is also the start acceleration of the quintic.
    a = sp.symbols(f"c0:{degree + 1}", real=True)
    p = sum(ai * t**i for i, ai in enumerate(a))
    derivs = [p, sp.diff(p, t), sp.diff(p, t, 2)]
    eqs = []
    for k in range((degree + 1) // 2):
        eqs.append(sp.Eq(derivs[k].subs(t, t0), vals[2 * k]))
        eqs.append(sp.Eq(derivs[k].subs(t, tf), vals[2 * k + 1]))
    sol = sp.solve(eqs, a, dict=True)[0]
    coeffs = [sp.factor(sol[ai]) for ai in a]
    return tuple(coeffs), (t0, tf) + tuple(vals)


def cubic_coefficients_symbolic():
    """Solve seed 002's 4 x 4 boundary-value system in absolute time.

    ``p(t) = a0 + a1 t + a2 t^2 + a3 t^3`` with ``p(t0) = p0``, ``p'(t0) = v0``,
    ``p(tf) = pf``, ``p'(tf) = vf``.

    Returns
    -------
    coeffs : list of 4 sympy expressions ``a0..a3``
    symbols : tuple ``(t0, tf, p0, pf, v0, vf)``

    Examples
    --------
    >>> a, s = cubic_coefficients_symbolic()
    >>> t0, tf, p0, pf, v0, vf = s
    >>> [sp.simplify(c.subs({t0: 0, v0: 0, vf: 0})) for c in a]
    [p0, 0, 3*(-p0 + pf)/tf**2, 2*(p0 - pf)/tf**3]
    """
    coeffs, symbols = _boundary_value(3)
    return list(coeffs), symbols  # a fresh list: the cached solution stays as solved


def quintic_coefficients_symbolic():
    """Solve the 6 x 6 boundary-value system (position, velocity, acceleration).

    Returns
    -------
    coeffs : list of 6 sympy expressions ``a0..a5``
    symbols : tuple ``(t0, tf, p0, pf, v0, vf, a0, af)``

    Examples
    --------
    >>> a, s = quintic_coefficients_symbolic()
    >>> len(a), [str(v) for v in s]
    (6, ['t0', 'tf', 'p0', 'pf', 'v0', 'vf', 'a0', 'af'])
    """
    coeffs, symbols = _boundary_value(5)
    return list(coeffs), symbols


# --------------------------------------------------------------------------- numeric


def _stack_lambdified(exprs, args):
    """Lambdify each entry and broadcast the results (constants included)."""
    funcs = [sp.lambdify(args, e, modules="numpy") for e in exprs]

    def call(*values):
        outs = [np.asarray(f(*values), dtype=float) for f in funcs]
        outs = np.broadcast_arrays(*outs)
        return np.stack(outs, axis=0)

    return call


def fk_function(n: int):
    """Numeric FK from the symbolic one: ``f(q, lengths) -> (..., 2)``.

    Examples
    --------
    >>> f = fk_function(2)
    >>> f([0.0, np.pi / 2], [1.0, 1.0]).round(12).tolist()
    [1.0, 1.0]
    """
    expr, q, lengths = fk_symbolic(n)
    call = _stack_lambdified(list(expr), q + lengths)

    def fk(qv, lv):
        qv = np.asarray(qv, dtype=float)
        lv = np.asarray(lv, dtype=float)
        out = call(*np.moveaxis(qv, -1, 0), *lv)
        return np.moveaxis(out, 0, -1)

    return fk


def jacobian_function(n: int):
    """Numeric Jacobian from the symbolic one: ``J(q, lengths) -> (..., 2, n)``.

    Examples
    --------
    >>> J = jacobian_function(2)
    >>> J([0.0, 0.0], [1.0, 1.0]).tolist()
    [[-0.0, -0.0], [2.0, 1.0]]
    """
    expr, q, lengths = jacobian_symbolic(n)
    call = _stack_lambdified(list(expr), q + lengths)

    def jac(qv, lv):
        qv = np.asarray(qv, dtype=float)
        lv = np.asarray(lv, dtype=float)
        out = call(*np.moveaxis(qv, -1, 0), *lv)  # (2n, ...), row-major entries
        out = np.moveaxis(out, 0, -1)
        return out.reshape(out.shape[:-1] + (2, n))

    return jac


def ik_2link_function():
    """Numeric 2-link IK from the symbolic derivation.

    Returns a callable ``ik(target, lengths) -> (2, 2)`` whose rows are the
    elbow-down and elbow-up solutions (unwrapped). It uses ``acos`` exactly as
    derived, so it is less accurate than :func:`rapp.ik.ik_2link` next to the
    workspace boundary; it is the reference the tests compare against.

    Examples
    --------
    >>> ik = ik_2link_function()
    >>> ik([1.0, 1.0], [1.0, 1.0]).round(6).tolist()
    [[0.0, 1.570796], [1.570796, -1.570796]]
    """
    sol = ik_2link_symbolic()
    args = sol["symbols"]
    call = _stack_lambdified([*sol["elbow_down"], *sol["elbow_up"]], args)

    def ik(target, lengths):
        x, y = np.asarray(target, dtype=float)
        l1, l2 = np.asarray(lengths, dtype=float)
        return call(x, y, l1, l2).reshape(2, 2)

    return ik


def _coefficient_function(coeffs, symbols):
    call = _stack_lambdified(coeffs, symbols)

    def f(*values):
        return call(*(np.asarray(v, dtype=float) for v in values))

    return f


def cubic_function():
    """Numeric cubic coefficients from the symbolic solution.

    Returns ``f(t0, tf, p0, pf, v0, vf) -> (4, ...)``, ascending powers of
    absolute time.

    Examples
    --------
    >>> cubic_function()(0.0, 3.0, 2.0, 5.0, 0.0, 0.25).round(4).tolist()
    [2.0, 0.0, 0.9167, -0.1944]
    """
    return _coefficient_function(*cubic_coefficients_symbolic())


def quintic_function():
    """Numeric quintic coefficients: ``f(t0, tf, p0, pf, v0, vf, a0, af) -> (6, ...)``.

    Examples
    --------
    >>> quintic_function()(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0).round(9).tolist()
    [0.0, 0.0, 0.0, 10.0, -15.0, 6.0]
    """
    return _coefficient_function(*quintic_coefficients_symbolic())


# --- the package against the derivations (chapter 6's checks) ----------------------------------

def check_ik_2link(rng, arms: int = 400) -> dict:
    """:func:`rapp.ik.ik_2link` against :func:`ik_2link_function` on ``arms`` random arms and targets.

    Each arm's link lengths are uniform in [0.3, 2] m; its target is uniform over the area of
    its workspace annulus (1 mm inside both circles). Returns the largest angle difference
    (rad, wrapped) ``worst_angle``, the largest tip error of FK(IK) ``worst_tip`` (m) and, per
    arm, whether row 0 is the ``+arccos`` elbow and row 1 the ``-arccos`` one (``elbow_order``).

    Examples
    --------
    >>> c = check_ik_2link(np.random.default_rng(0), arms=20)
    >>> all(c["elbow_order"]), c["worst_angle"] < 1e-12, c["worst_tip"] < 1e-12
    (True, True, True)
    """
    from rapp.arm import Arm, wrap_angle
    from rapp.ik import ik_2link

    ik_sym = ik_2link_function()
    worst_angle = worst_tip = 0.0
    elbow_order = []
    for lengths in rng.uniform(0.3, 2.0, size=(arms, 2)):
        arm = Arm(lengths)
        r_in, r_out = arm.reach
        r = np.sqrt(rng.uniform((r_in + 1e-3) ** 2, (r_out - 1e-3) ** 2))
        th = rng.uniform(-np.pi, np.pi)
        target = r * np.array([np.cos(th), np.sin(th)])
        q_pkg, q_ref = ik_2link(arm, target), ik_sym(target, lengths)
        elbow_order.append(q_pkg.shape == (2, 2) and q_pkg[0, 1] > 0 > q_pkg[1, 1])
        worst_angle = max(worst_angle, np.abs(wrap_angle(q_pkg - q_ref)).max())
        worst_tip = max(worst_tip, np.abs(arm.end_effector(q_pkg) - target).max())
    return {"worst_angle": float(worst_angle), "worst_tip": float(worst_tip), "elbow_order": elbow_order}


def check_jacobian(rng, links: int = 5, samples: int = 200, h: float = 1e-6) -> dict:
    """:func:`rapp.ik.jacobian` against :func:`jacobian_function` and central differences.

    For 1 to ``links`` links (lengths uniform in [0.3, 1.5] m) at ``samples`` random
    configurations each, returns per arm whether the batch shape is ``(samples, 2, n)``
    (``shapes``), the largest difference from sympy (``sympy``) and from central differences
    of step ``h`` (``central``).

    Examples
    --------
    >>> c = check_jacobian(np.random.default_rng(0), links=3, samples=20)
    >>> all(c["shapes"]), max(c["sympy"]) < 1e-12, max(c["central"]) < 1e-8
    (True, True, True)
    """
    from rapp.arm import Arm
    from rapp.ik import jacobian

    out: dict = {"shapes": [], "sympy": [], "central": []}
    for n in range(1, links + 1):
        lengths = rng.uniform(0.3, 1.5, size=n)
        arm = Arm(lengths)
        qs = rng.uniform(-np.pi, np.pi, size=(samples, n))
        J_pkg = jacobian(arm, qs)
        J_fd = np.stack([(arm.end_effector(qs + s) - arm.end_effector(qs - s)) / (2 * h)
                         for s in h * np.eye(n)], axis=-1)
        out["shapes"].append(J_pkg.shape == (samples, 2, n))
        out["sympy"].append(float(np.abs(J_pkg - jacobian_function(n)(qs, lengths)).max()))
        out["central"].append(float(np.abs(J_pkg - J_fd).max()))
    return out


def check_fk(rng, links: int = 6, samples: int = 2000, joints_checked: int = 20) -> dict:
    """:meth:`rapp.Arm.end_effector` and :meth:`~rapp.Arm.joint_positions` against the derivation.

    For 1 to ``links`` links (lengths uniform in [0.1, 2] m) at ``samples`` random configurations:
    ``fk[n]``, the largest difference of the tip from :func:`fk_function`; ``joints[n]``, that of
    every joint from :func:`joint_positions_symbolic` (on the first ``joints_checked``
    configurations, one sympy call each); ``shapes``, whether sympy's batch had shape ``(samples, 2)``.

    Examples
    --------
    >>> c = check_fk(np.random.default_rng(0), links=3, samples=50, joints_checked=5)
    >>> all(c["shapes"]), max(c["fk"].values()) < 1e-12, max(c["joints"].values()) < 1e-12
    (True, True, True)
    """
    from rapp.arm import Arm

    out: dict = {"fk": {}, "joints": {}, "shapes": []}
    for n in range(1, links + 1):
        lengths = rng.uniform(0.1, 2.0, size=n)
        arm = Arm(lengths)
        qs = rng.uniform(-np.pi, np.pi, size=(samples, n))
        by_sympy = fk_function(n)(qs, lengths)
        out["shapes"].append(by_sympy.shape == (samples, 2))
        out["fk"][n] = float(np.abs(arm.end_effector(qs) - by_sympy).max())
        P_n, qsym, Lsym = joint_positions_symbolic(n)
        joints = sp.lambdify(qsym + Lsym, P_n[1:, :], "numpy")
        expected = np.stack([np.array(joints(*qk, *lengths), dtype=float) for qk in qs[:joints_checked]])
        out["joints"][n] = float(np.abs(arm.joint_positions(qs[:joints_checked])[:, 1:] - expected).max())
    return out
