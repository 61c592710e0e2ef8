"""rapp.student_t against mpmath at 50 digits: the distribution function and the quantile.

The oracle for a quantile q is one Newton step of mpmath's own t distribution function from
q, at 50 digits: the exact root to far better than the tolerance, with no root finder to trust.
"""

import math

import mpmath
import pytest
from hypothesis import given, settings, strategies as st

from rapp.errors import InvalidValue
from rapp.student_t import incomplete_beta, t_cdf, t_quantile

mpmath.mp.dps = 50


def exact_cdf(t, df):
    t, df = mpmath.mpf(t), mpmath.mpf(df)
    tail = mpmath.betainc(df / 2, mpmath.mpf(1) / 2, 0, df / (df + t * t), regularized=True) / 2
    return 1 - tail if t > 0 else tail


def exact_pdf(t, df):
    t, df = mpmath.mpf(t), mpmath.mpf(df)
    return (mpmath.gamma((df + 1) / 2) / (mpmath.sqrt(df * mpmath.pi) * mpmath.gamma(df / 2))
            * (1 + t * t / df) ** (-(df + 1) / 2))


def exact_quantile(q, p, df):
    """The root of cdf(t) = p next to ``q``: one Newton step at 50 digits."""
    return mpmath.mpf(q) - (exact_cdf(q, df) - mpmath.mpf(p)) / exact_pdf(q, df)


def relative_error(q, p, df):
    exact = exact_quantile(q, p, df)
    return float(abs(mpmath.mpf(q) - exact) / max(1, abs(exact)))


@pytest.mark.parametrize("df", [1, 2, 3, 4, 5, 11, 13, 29, 30, 31, 99, 100, 101, 1000, 10**6, 10**9])
def test_the_95_percent_quantile_of_every_sample_size_the_comparison_meets(df):
    assert relative_error(t_quantile(0.975, df), 0.975, df) < (1e-7 if df > 10**6 else 1e-10)


def test_closed_forms_df_1_and_2():
    for p in (0.6, 0.9, 0.975, 0.999):
        assert t_quantile(p, 1) == pytest.approx(math.tan(math.pi * (p - 0.5)), rel=1e-12)
        a = 4 * p * (1 - p)
        assert t_quantile(p, 2) == pytest.approx(2 * (p - 0.5) * math.sqrt(2 / a), rel=1e-12)


@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(df=st.one_of(st.integers(1, 60), st.floats(0.5, 1e9)),
       p=st.floats(1e-8, 1 - 1e-8).filter(lambda p: p != 0.5))
def test_quantiles_equal_mpmaths(df, p):
    q = t_quantile(p, df)
    # The continued fraction's rounding grows with df: 1e-10 up to a million, 1e-7 beyond.
    assert relative_error(q, p, df) < (1e-7 if df > 1e6 else 1e-10), (p, df, q)


@pytest.mark.slow
@settings(max_examples=100, deadline=None)
@given(df=st.floats(0.5, 1e6), t=st.floats(-50, 50))
def test_the_distribution_function_equals_mpmaths(df, t):
    assert abs(t_cdf(t, df) - float(exact_cdf(t, df))) < 1e-12


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(a=st.floats(0.1, 500), b=st.floats(0.1, 500), x=st.floats(0, 1))
def test_incomplete_beta_equals_mpmaths(a, b, x):
    assert abs(incomplete_beta(a, b, x) - float(mpmath.betainc(a, b, 0, x, regularized=True))) < 1e-12


@pytest.mark.parametrize("t, df", [(0.3, 1), (-2.0, 2), (4.5, 3.5), (1.96, 40), (-0.7, 5000)])
def test_the_distribution_function_at_a_few_points(t, df):  # the fast sibling of the above
    assert abs(t_cdf(t, df) - float(exact_cdf(t, df))) < 1e-13


def test_symmetry_and_bad_input():
    assert t_quantile(0.3, 7) == pytest.approx(-t_quantile(0.7, 7), rel=1e-14) and t_quantile(0.5, 3) == 0.0
    with pytest.raises(InvalidValue, match="p:"):
        t_quantile(1.0, 3)
    with pytest.raises(InvalidValue, match="df:"):
        t_quantile(0.9, 0)
