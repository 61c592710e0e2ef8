"""trapezoidal_moves: many trapezoids as plain arrays, the durations of trapezoidal exactly."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp.time_scaling import trapezoidal, trapezoidal_moves


@st.composite
def moves(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 6))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    scale = draw(st.sampled_from([1e-3, 1.0, 10.0]))
    p0 = rng.uniform(-3, 3, (m, n))
    pf = p0 + scale * rng.uniform(-2, 2, (m, n))
    vmax = rng.uniform(0.1, 3.0, n)
    amax = rng.uniform(0.1, 5.0, n)
    return p0, pf, vmax, amax


@settings(max_examples=80, deadline=None, derandomize=True)
@given(moves())
def test_the_durations_and_pieces_are_those_of_trapezoidal(case):
    p0, pf, vmax, amax = case
    fast = trapezoidal_moves(p0, pf, vmax, amax)
    for i in range(len(p0)):
        pp = trapezoidal(p0[i], pf[i], vmax, amax)
        assert fast.duration[i] == pp.duration  # equal floats, not close ones
        one = trapezoidal_moves(p0[i], pf[i], vmax, amax)  # one move: the Python-float path
        assert one.ends[0].tolist() == fast.ends[i].tolist()
        assert one.velocity[0].tolist() == fast.velocity[i].tolist()
        assert trapezoidal_moves(p0[i].tolist(), pf[i].tolist(), vmax.tolist(),
                                 amax.tolist()).duration[0] == pp.duration
        assert np.unique(fast.ends[i]).tolist() == pp.breakpoints[1:].tolist()
        t = np.linspace(0.0, pp.duration, 23)
        for got, want in zip(fast.sample(np.broadcast_to(t, (len(p0), 23)))[:2], pp.sample(t)[:2]):
            np.testing.assert_allclose(got[i], want, rtol=1e-9, atol=1e-9 * (1 + np.abs(want).max()))


def test_one_move_may_be_given_as_vectors():
    one = trapezoidal_moves([0.0, 0.0], [2.0, -1.0], 1.0, 1.0)
    assert one.duration.tolist() == [3.0]
    q, qd, qdd = one.sample([1.5])
    assert qd.tolist() == [[1.0, -0.5]] and qdd.tolist() == [[0.0, 0.0]]


@pytest.mark.parametrize("p0, pf, vmax, match", [
    ([[0.0, 1.0]], [[0.0, 1.0]], 1.0, "move 0 does not move"),
    ([[0.0, np.nan]], [[1.0, 1.0]], 1.0, "^p0 must be finite"),
    ([[0.0, 1.0]], [[1.0]], 1.0, "^p0 and pf must be"),
    ([[0.0, 1.0]], [[1.0, 1.0]], -1.0, "^vmax must be > 0"),
])
def test_bad_moves_are_refused_naming_the_field(p0, pf, vmax, match):
    with pytest.raises(ValueError, match=match):
        trapezoidal_moves(p0, pf, vmax, 1.0)


@settings(max_examples=150, deadline=None, derandomize=True)
@given(moves(), st.sampled_from(["array", "list", "scalar limits", "zero joint", "signed zeros"]))
def test_one_trapezoid_is_the_numpy_construction_bit_for_bit(case, form):
    """trapezoidal's one-move path (Python floats) against the numpy construction it replaced,
    which trapezoidal_path runs for a path of two waypoints: the same bytes in every array."""
    from rapp.time_scaling import trapezoidal_path
    p0, pf, vmax, amax = (x[0] if x.ndim == 2 else x for x in case)
    p0, pf = p0.copy(), pf.copy()
    if form == "zero joint" and p0.size > 1:
        pf[0] = p0[0]  # a joint that does not move: zero velocity, zero coefficients
    if form == "signed zeros" and p0.size > 1:
        p0[-1], pf[-1] = 0.0, -0.0
    args = (p0, pf, vmax, amax)
    if form == "list":
        args = tuple(x.tolist() for x in args)
    if form == "scalar limits":
        args = (p0, pf, float(vmax[0]), float(amax[0]))
    fast, slow = trapezoidal(*args), trapezoidal_path([args[0], args[1]], args[2], args[3])
    for name in ("breakpoints", "coefficients", "local"):
        a, b = getattr(fast, name), getattr(slow, name)
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), name
        assert not a.flags.writeable
    assert fast.local.flags.c_contiguous


def test_one_trapezoid_refuses_bad_input_with_the_numpy_messages():
    for args, message in [((0.0, 0.0, 1.0, 1.0), "pf must differ from p0"),
                          (([0.0, 1.0], [1.0], 1.0, 1.0), "p0 and pf must be"),
                          ((0.0, 1.0, -1.0, 1.0), "vmax must be > 0"),
                          ((0.0, float("nan"), 1.0, 1.0), "pf must be finite"),
                          ((0.0, 1e308, 1e-308, 1.0), "overflows float64"),
                          ((0.0, 1.0, [1.0, 2.0], 1.0), "vmax must be a number or one number per joint")]:
        with pytest.raises(ValueError, match=message):
            trapezoidal(*args)
