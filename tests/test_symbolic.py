"""The sympy derivations agree with the numeric code, and find the seed errors."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp.arm import Arm
from rapp.symbolic import (
    cubic_coefficients_symbolic,
    fk_function,
    fk_symbolic,
    ik_2link_symbolic,
    jacobian_symbolic,
    joint_positions_symbolic,
    quintic_coefficients_symbolic,
)

FK = {n: fk_function(n) for n in range(1, 6)}


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 5), st.integers(0, 2**31 - 1))
def test_symbolic_fk_equals_arm_end_effector(n, seed):
    rng = np.random.default_rng(seed)
    arm = Arm(rng.uniform(0.1, 2.0, n))
    q = rng.uniform(-4, 4, (7, n))
    assert np.abs(FK[n](q, arm.lengths) - arm.end_effector(q)).max() < 1e-12


def test_symbolic_joint_positions_equal_arm():
    P, q, L = joint_positions_symbolic(3)
    f = sp.lambdify(q + L, P, modules="numpy")
    arm = Arm([1.0, 0.8, 0.5])
    qv = [0.3, -1.2, 2.0]
    assert np.allclose(np.array(f(*qv, *arm.lengths), dtype=float), arm.joint_positions(qv),
                       atol=1e-14)


def test_jacobian_is_the_derivative_of_fk():
    J, q, L = jacobian_symbolic(3)
    f, _, _ = fk_symbolic(3)
    for i in range(2):
        for j in range(3):
            assert sp.simplify(J[i, j] - sp.diff(f[i], q[j])) == 0
    # Column j is the sum over the links beyond joint j (rapp.ik.jacobian).
    assert sp.simplify(J[0, 2] + L[2] * sp.sin(q[0] + q[1] + q[2])) == 0


def test_seed003_printed_jacobian_has_sign_errors():
    # Seed 003 measures angles from +y: x = sum L sin(phi), y = sum L cos(phi).
    t1, t2, t3 = sp.symbols("theta1:4", real=True)
    l1, l2, l3 = sp.symbols("l1:4", positive=True)
    x = l1 * sp.sin(t1) + l2 * sp.sin(t1 + t2) + l3 * sp.sin(t1 + t2 + t3)
    y = l1 * sp.cos(t1) + l2 * sp.cos(t1 + t2) + l3 * sp.cos(t1 + t2 + t3)
    printed_dx_dt1 = -l1 * sp.cos(t1) - l2 * sp.cos(t1 + t2) - l3 * sp.cos(t1 + t2 + t3)
    printed_dy_dt2 = l2 * sp.sin(t1 + t2) - l3 * sp.sin(t1 + t2 + t3)
    assert sp.simplify(sp.diff(x, t1) + printed_dx_dt1) == 0      # printed with the wrong sign
    assert sp.simplify(sp.diff(y, t2) - printed_dy_dt2) != 0
    assert sp.simplify(sp.diff(y, t2) + l2 * sp.sin(t1 + t2) + l3 * sp.sin(t1 + t2 + t3)) == 0


@pytest.mark.slow
def test_ik_2link_symbolic_law_of_cosines_and_back_substitution():
    sol = ik_2link_symbolic()
    x, y, l1, l2 = sol["symbols"]
    f, (q1, q2), (L1, L2) = fk_symbolic(2)
    assert sp.simplify(sp.trigsimp(sp.expand(f[0] ** 2 + f[1] ** 2))
                       - (L1**2 + L2**2 + 2 * L1 * L2 * sp.cos(q2))) == 0
    rng = np.random.default_rng(1)
    for _ in range(20):
        lv = rng.uniform(0.3, 1.5, 2)
        r = rng.uniform(abs(lv[0] - lv[1]) + 1e-3, lv.sum() - 1e-3)
        a = rng.uniform(-np.pi, np.pi)
        sub = {x: r * np.cos(a), y: r * np.sin(a), l1: lv[0], l2: lv[1]}
        for name in ("elbow_down", "elbow_up"):
            qv = [float(e.subs(sub)) for e in sol[name]]
            tip = [float(c.subs({q1: qv[0], q2: qv[1], L1: lv[0], L2: lv[1]})) for c in f]
            assert np.allclose(tip, [sub[x], sub[y]], atol=1e-12)
        assert float(sol["elbow_down"][1].subs(sub)) >= 0


@pytest.mark.slow
@pytest.mark.parametrize("make, order", [(cubic_coefficients_symbolic, 3),
                                         (quintic_coefficients_symbolic, 5)])
def test_boundary_value_solutions_satisfy_their_system(make, order):
    a, syms = make()
    assert all(e.free_symbols <= set(syms) for e in a)
    t0, tf = syms[:2]
    vals = syms[2:]
    t = sp.Symbol("t", real=True)
    p = sum(c * t**k for k, c in enumerate(a))
    rng = np.random.default_rng(7)
    for _ in range(3):
        # exact rational values: the check is exact arithmetic, not a tolerance
        num = [sp.Rational(int(v), 7) for v in rng.integers(-50, 50, len(syms))]
        num[1] = num[0] + sp.Rational(int(rng.integers(1, 30)), 11)
        sub = dict(zip(syms, num))
        for k in range((order + 1) // 2):
            dk = sp.diff(p, t, k)
            assert (dk.subs(t, t0).subs(sub) - sub[vals[2 * k]]) == 0
            assert (dk.subs(t, tf).subs(sub) - sub[vals[2 * k + 1]]) == 0
