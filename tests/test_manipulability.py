"""Manipulability, condition number and velocity ellipse (rapp.manipulability).

Properties: the 2-link closed form L1 L2 |sin q2| that sympy derives; agreement with
np.linalg.svd of the Jacobian on random arms and batches; zero / infinite exactly at the
stretched and folded configurations; invariance under a turn of the base; the ellipse's
semi-axes and major axis are the singular values and top left singular vector of J; the
scaling with the arm's size (no overflow for the largest accepted arms); bad input refused
with a ValueError naming the argument.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import rapp
from rapp.arm import Arm
from rapp.ik import jacobian
from rapp.manipulability import condition_number, manipulability, manipulability_ellipse
from rapp.symbolic import jacobian_symbolic, manipulability_symbolic

FUNCTIONS = [manipulability, condition_number, manipulability_ellipse]
SEEDS = st.integers(0, 2**31 - 1)


def random_arm(rng, n):
    return Arm(rng.uniform(0.1, 2.0, n))


def svd_values(arm, q):
    """Reference: singular values (..., 2) of J by LAPACK, a zero appended for one link."""
    s = np.linalg.svd(jacobian(arm, q), compute_uv=False)
    if s.shape[-1] == 1:
        s = np.concatenate((s, np.zeros_like(s)), axis=-1)
    return s


# ----------------------------------------------------------------- the sympy derivation


def test_sympy_derives_two_link_manipulability():
    """det(J J^T) of the symbolic Jacobian simplifies to (L1 L2 sin q2)^2."""
    J, (q1, q2), (l1, l2) = jacobian_symbolic(2)
    det = sp.simplify(sp.expand_trig((J * J.T).det()))
    assert sp.simplify(det - (l1 * l2 * sp.sin(q2)) ** 2) == 0
    w, q, L = manipulability_symbolic(2)
    assert w == l1 * l2 * sp.Abs(sp.sin(q2))
    assert manipulability_symbolic(1)[0] == 0


@pytest.fixture(scope="module")
def symbolic_w():
    """Lambdified w(q, L) from rapp.symbolic for 2 and 3 links (sympy takes a few seconds)."""
    out = {}
    for n in (2, 3):
        w, q, L = manipulability_symbolic(n)
        # Cross-check the Cauchy-Binet sum against the plain determinant once, symbolically
        # at a rational point (the full simplification of det(J J^T) for 3 links is slow).
        J, _, _ = jacobian_symbolic(n)
        point = {s: v for s, v in zip(q + L, [sp.Rational(k + 1, 7) for k in range(2 * n)])}
        assert abs(sp.N((J * J.T).det().subs(point) - (w**2).subs(point), 30)) < 1e-25
        out[n] = sp.lambdify(q + L, w, modules="numpy")
    return out


@pytest.mark.parametrize("n", [2, 3])
def test_manipulability_equals_the_symbolic_formula_at_random_points(symbolic_w, n):
    rng = np.random.default_rng(n)
    for _ in range(20):
        arm = random_arm(rng, n)
        q = rng.uniform(-4.0, 4.0, (50, n))
        expected = symbolic_w[n](*q.T, *arm.lengths)
        np.testing.assert_allclose(manipulability(arm, q), expected, rtol=1e-11, atol=1e-13)


@settings(max_examples=100, deadline=None)
@given(st.floats(0.01, 10.0), st.floats(0.01, 10.0), st.floats(-10.0, 10.0), st.floats(-10.0, 10.0))
def test_two_link_closed_form(l1, l2, q1, q2):
    w = manipulability(Arm([l1, l2]), [q1, q2])
    assert w.shape == ()
    assert w >= 0.0
    assert abs(w - l1 * l2 * abs(np.sin(q2))) <= 1e-14 * (l1 + l2) ** 2


@pytest.mark.parametrize("q2", [1e-6, 1e-9, 1e-12, np.pi - 1e-9])
def test_near_singular_accuracy_is_round_off_in_w_not_its_square(q2):
    """The sum of squared minors keeps absolute accuracy ~eps |J|^2 in w. The textbook
    a c - b^2 cancels to ~eps |J|^4 in w^2, an error of ~1e-8 in w: larger than these w."""
    arm = Arm([1.0, 0.7])
    q = np.array([[a, q2] for a in np.linspace(-3.0, 3.0, 25)])
    np.testing.assert_allclose(manipulability(arm, q), 0.7 * np.sin(q2), rtol=0, atol=1e-15)


# ----------------------------------------------------------------- singularities


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 6), SEEDS)
def test_collinear_arm_is_singular(n, seed):
    """Every link on one line (q_j in {0, pi} for j >= 2): w = 0 up to round-off, cond inf or huge."""
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n)
    q = np.zeros((32, n))
    q[:, 0] = rng.uniform(-np.pi, np.pi, 32)
    q[:, 1:] = rng.choice([0.0, np.pi, -np.pi], (32, n - 1))
    total = arm.lengths.sum()
    assert np.all(manipulability(arm, q) <= 1e-14 * total**2)
    assert np.all(condition_number(arm, q) >= 1e12)
    axes, _ = manipulability_ellipse(arm, q)
    assert np.all(axes[..., 1] <= 1e-14 * total)


@pytest.mark.parametrize("lengths", [[1.0], [1.0, 1.0], [0.3, 2.0, 0.5], [1.0, 0.5, 0.25, 0.125]])
def test_stretched_arm_exactly_zero(lengths):
    """Stretched with the first joint on an axis: J has a zero row, w and sigma2 are exactly 0."""
    arm = Arm(lengths)
    q = np.zeros((4, arm.n))
    q[:, 0] = [0.0, np.pi / 2, -np.pi / 2, np.pi]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # inf without a divide-by-zero warning
        w = manipulability(arm, q)
        cond = condition_number(arm, q)
        axes, angle = manipulability_ellipse(arm, q)
    assert w[0] == 0.0
    assert cond[0] == np.inf
    assert np.all(w <= 1e-15)
    assert np.all((cond == np.inf) | (cond > 1e15))
    # The only direction left is across the arm: sigma1 = |J|_F = sqrt(sum of squared suffix sums).
    np.testing.assert_allclose(axes[:, 0], np.sqrt((np.cumsum(lengths[::-1]) ** 2).sum()))
    # Across the arm: vertical for the arm along the x axis, horizontal along y.
    np.testing.assert_allclose(np.abs(angle), [np.pi / 2, 0.0, 0.0, np.pi / 2], atol=1e-15)


def test_one_link_is_always_singular():
    arm = Arm([1.5])
    q = np.linspace(-3.0, 3.0, 7)[:, None]
    assert np.all(manipulability(arm, q) == 0.0)
    assert np.all(condition_number(arm, q) == np.inf)
    axes, angle = manipulability_ellipse(arm, q)
    np.testing.assert_allclose(axes, np.column_stack((np.full(7, 1.5), np.zeros(7))))
    # The tip of one link moves perpendicular to it.
    np.testing.assert_allclose(np.cos(angle - q[:, 0]), 0.0, atol=1e-12)


def test_isotropic_two_link_arm():
    """L1 = sqrt(2) L2 and q2 = +-3 pi/4: a round ellipse, condition number 1 (a classic result)."""
    arm = Arm([np.sqrt(2.0), 1.0])
    q = np.array([[0.4, 3 * np.pi / 4], [-2.0, -3 * np.pi / 4]])
    np.testing.assert_allclose(condition_number(arm, q), 1.0, rtol=1e-7)
    axes, _ = manipulability_ellipse(arm, q)
    np.testing.assert_allclose(axes, 1.0, rtol=1e-7)
    assert np.all(condition_number(arm, q) >= 1.0)


# ----------------------------------------------------------------- agreement with the SVD


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 6), SEEDS)
def test_agrees_with_numpy_svd_on_batches(n, seed):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n)
    q = rng.uniform(-2 * np.pi, 2 * np.pi, (3, 4, n))
    s = svd_values(arm, q)
    scale = arm.lengths.sum()
    w = manipulability(arm, q)
    cond = condition_number(arm, q)
    axes, angle = manipulability_ellipse(arm, q)
    assert w.shape == (3, 4) and cond.shape == (3, 4)
    assert axes.shape == (3, 4, 2) and angle.shape == (3, 4)
    np.testing.assert_allclose(w, s[..., 0] * s[..., 1], rtol=1e-12, atol=1e-14 * scale**2)
    np.testing.assert_allclose(axes, s, rtol=1e-12, atol=1e-14 * scale)
    assert np.all(w >= 0.0)
    assert np.all(axes[..., 0] >= axes[..., 1])
    assert np.all(cond >= 1.0 - 1e-12)
    if n == 1:
        assert np.all(cond == np.inf)
    else:
        # sigma2 carries an absolute error ~eps sigma1, so the ratio one ~eps cond^2.
        ref = s[..., 0] / s[..., 1]
        assert np.all(np.abs(cond - ref) <= 1e-12 * ref + 1e-14 * ref**2)
        np.testing.assert_allclose(axes[..., 0] * axes[..., 1], w, rtol=1e-12, atol=1e-14 * scale**2)


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 6), SEEDS)
def test_major_axis_is_the_top_left_singular_vector(n, seed):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n)
    q = rng.uniform(-np.pi, np.pi, (20, n))
    J = jacobian(arm, q)
    U, s, _ = np.linalg.svd(J)
    axes, angle = manipulability_ellipse(arm, q)
    assert np.all((angle > -np.pi / 2) & (angle <= np.pi / 2))
    u = np.stack((np.cos(angle), np.sin(angle)), axis=-1)
    # Defined only where the ellipse is not (nearly) round: a well separated sigma1 > sigma2.
    sep = s[:, 0] - (s[:, 1] if n > 1 else 0.0)
    ok = sep > 1e-6 * s[:, 0]
    dot = np.abs(np.einsum("ki,ki->k", u, U[:, :, 0]))
    assert np.all(np.abs(dot[ok] - 1.0) <= 1e-9)
    # And it is an eigenvector of J J^T for sigma1^2, stretched by J^T to length sigma1.
    jt_u = np.einsum("kij,ki->kj", J, u)
    np.testing.assert_allclose(np.linalg.norm(jt_u, axis=-1), axes[:, 0], rtol=1e-9)


# ----------------------------------------------------------------- invariances and scaling


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 6), SEEDS, st.floats(-10.0, 10.0))
def test_invariant_under_turning_the_base(n, seed, turn):
    """q1 only rotates the whole arm: w, cond and the semi-axes stay, the ellipse turns with it."""
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n)
    q = rng.uniform(-np.pi, np.pi, (10, n))
    turned = q.copy()
    turned[:, 0] += turn
    scale = arm.lengths.sum()
    np.testing.assert_allclose(manipulability(arm, turned), manipulability(arm, q),
                               rtol=1e-12, atol=1e-13 * scale**2)
    axes, angle = manipulability_ellipse(arm, q)
    axes_t, angle_t = manipulability_ellipse(arm, turned)
    np.testing.assert_allclose(axes_t, axes, rtol=1e-12, atol=1e-13 * scale)
    if n > 1:
        well = axes[:, 1] > 1e-3 * axes[:, 0]
        np.testing.assert_allclose(condition_number(arm, turned)[well],
                                   condition_number(arm, q)[well], rtol=1e-9)
    # Axis directions agree modulo pi where the ellipse has a clear major axis.
    clear = axes[:, 0] - axes[:, 1] > 1e-6 * axes[:, 0]
    np.testing.assert_allclose(np.sin(angle_t - angle - turn)[clear], 0.0, atol=1e-8)


@pytest.mark.parametrize("k", [1e-150, 1e-3, 7.0, 1e90])
def test_scales_with_the_arm_and_never_overflows(k):
    """w is length^2, the axes length, cond has no unit; det(J J^T) ~ k^4 would overflow
    float64 for k = 1e90 if it were formed directly."""
    unit = Arm([0.5, 0.3, 0.2])
    arm = Arm(k * unit.lengths)
    q = np.random.default_rng(3).uniform(-np.pi, np.pi, (40, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w = manipulability(arm, q)
        cond = condition_number(arm, q)
        axes, angle = manipulability_ellipse(arm, q)
    np.testing.assert_allclose(w, k**2 * manipulability(unit, q), rtol=1e-12)
    np.testing.assert_allclose(cond, condition_number(unit, q), rtol=1e-9)
    axes_u, angle_u = manipulability_ellipse(unit, q)
    np.testing.assert_allclose(axes, k * axes_u, rtol=1e-12)
    np.testing.assert_allclose(angle, angle_u, atol=1e-12)


def test_batch_entries_equal_single_calls():
    arm = Arm([1.0, 0.8, 0.5, 0.3])
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (3, 4, 4))
    w = manipulability(arm, q)
    cond = condition_number(arm, q)
    axes, angle = manipulability_ellipse(arm, q)
    for idx in np.ndindex(3, 4):
        assert manipulability(arm, q[idx]) == w[idx]
        assert condition_number(arm, q[idx]) == cond[idx]
        a, t = manipulability_ellipse(arm, q[idx].tolist())
        assert a.shape == (2,) and t.shape == ()
        assert np.array_equal(a, axes[idx]) and t == angle[idx]


def test_exported_from_the_package():
    assert rapp.manipulability is manipulability
    assert rapp.condition_number is condition_number
    assert rapp.manipulability_ellipse is manipulability_ellipse
    for name in ("manipulability", "condition_number", "manipulability_ellipse"):
        assert name in rapp.__all__


# ----------------------------------------------------------------- bad input

ARM = Arm([1.0, 1.0])


@pytest.mark.parametrize("f", FUNCTIONS)
@pytest.mark.parametrize("arm", [[1.0, 1.0], None, "arm", np.array([1.0, 1.0])])
def test_refuses_what_is_not_an_arm(f, arm):
    with pytest.raises(ValueError, match=r"^arm must be a rapp.Arm"):
        f(arm, [0.0, 0.0])


@pytest.mark.parametrize("f", FUNCTIONS)
@pytest.mark.parametrize("q, message", [
    ([0.0, float("nan")], r"^q must be finite joint angles"),
    ([[0.0, 0.0], [float("inf"), 0.0]], r"^q must be finite joint angles"),
    ([0.0, 0.0, 0.0], r"^q must have shape \(\.\.\., 2\), got \(3,\)"),
    (np.zeros((4, 3)), r"^q must have shape \(\.\.\., 2\), got \(4, 3\)"),
    (0.5, r"^q must have shape \(\.\.\., 2\), got \(\)"),
    ([], r"^q must have shape \(\.\.\., 2\), got \(0,\)"),
    (["a", "b"], r"^q must be an array of joint angles"),
    ([1e101, 0.0], r"^q must be joint angles of magnitude at most"),
])
def test_refuses_bad_q_naming_it(f, q, message):
    with pytest.raises(ValueError, match=message):
        f(ARM, q)


@pytest.mark.parametrize("f", FUNCTIONS)
def test_empty_batch(f):
    out = f(ARM, np.zeros((0, 2)))
    shapes = [o.shape for o in out] if isinstance(out, tuple) else [out.shape]
    assert shapes[0][0] == 0
