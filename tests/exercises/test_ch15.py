"""Chapter 15's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check


def test_15_1_quintic_minimum_duration(book_exercises, solution):
    want = max(15 * 0.5 / 8, np.sqrt(10 * 0.5 / (np.sqrt(3) * 2.0)))
    assert check("15.1", want) and check("15.1", solution("15.1")["T"])
    assert "1.2014" in book_exercises["15.1"]["solution"]
    assert "acceleration limit asks for more time" in check("15.1", 15 * 0.5 / 8).message
    assert "cubic's" in check("15.1", np.sqrt(6 * 0.5 / 2.0)).message
    assert "trapezoid's" in check("15.1", 1.0).message
    assert "10/√3, not 10" in check("15.1", np.sqrt(10 * 0.5 / 2.0)).message
    assert "not it" in check("15.1", 2.0).message


def test_15_2_model_function_passes_and_slips_fail(solution):
    assert check("15.2", solution("15.2")["lspb"])

    def always_cruise(delta, vmax, amax):
        d = abs(delta)
        return d / vmax + vmax / amax, vmax / amax

    wrong = check("15.2", always_cruise)
    assert not wrong and "triangle" in wrong.message and "delta=0.3" in wrong.message

    def always_triangle(delta, vmax, amax):
        tb = np.sqrt(abs(delta) / amax)
        return 2 * tb, tb

    wrong = check("15.2", always_triangle)
    assert not wrong and "long enough to cruise" in wrong.message and "delta=1.2" in wrong.message

    def no_abs(delta, vmax, amax):
        if delta >= vmax**2 / amax:
            return delta / vmax + vmax / amax, vmax / amax
        tb = np.sqrt(delta / amax) if delta > 0 else -1.0
        return 2 * tb, tb

    wrong = check("15.2", no_abs)
    assert not wrong and "positive" in wrong.message and "delta=-1.2" in wrong.message

    def swapped(delta, vmax, amax):
        T, tb = solution("15.2")["lspb"](delta, vmax, amax)
        return tb, T

    assert "order (T, tb)" in check("15.2", swapped).message

    def wrong_blend(delta, vmax, amax):
        T, tb = solution("15.2")["lspb"](delta, vmax, amax)
        return T, 2 * tb

    assert "right duration T, but not the right blend" in check("15.2", wrong_blend).message

    def too_fast(delta, vmax, amax):
        T, tb = solution("15.2")["lspb"](delta, vmax, amax)
        return 0.9 * T, 0.9 * tb

    assert "shorter than any motion" in check("15.2", too_fast).message
    assert "pair (T, tb)" in check("15.2", lambda d, v, a: 1.0).message
    assert "missing return" in check("15.2", lambda d, v, a: None).message


def test_15_3_counterexample(solution):
    verdict = check("15.3", solution("15.3")["counterexample"])
    assert verdict and "0.294" in verdict.message
    assert "same amount" in check("15.3", ([0.0, 0.0], [1.0, -1.0])).message
    assert "only one joint moves" in check("15.3", ([0.0, 0.0], [2.0, 0.0])).message
    assert "same configuration" in check("15.3", ([1.0, 2.0], [1.0, 2.0])).message
    small = check("15.3", ([0.0, 0.0], [2.0, 1.9]))
    assert not small and "only" in small.message and "0.1 rad" in small.message
    assert "pair (p0, pf)" in check("15.3", [0.0, 1.0, 2.0]).message
    assert "finite" in check("15.3", ([0.0, np.nan], [1.0, 2.0])).message
    assert "no answer yet" in check("15.3", None).message


def test_15_4_condition_number(book_exercises, solution):
    assert check("15.4", solution("15.4")["kappa"])
    assert "4.391" in book_exercises["15.4"]["solution"]
    kappa = float(solution("15.4")["kappa"])
    assert "manipulability" in check("15.4", 0.5 * np.sqrt(3) / 2).message
    assert "at least 1" in check("15.4", 1 / kappa).message
    assert "eigenvalues" in check("15.4", kappa**2).message
    assert "degrees" in check("15.4", _degrees()).message
    assert "not it" in check("15.4", 2.0).message


def _degrees():
    """The condition number with theta2 = 60 taken as radians (the degrees slip)."""
    return float(rapp.condition_number(rapp.Arm([1.0, 0.5]), [0.3, 60.0]))


def test_15_5_stopping_costs_time(solution):
    verdict = check("15.5", solution("15.5")["waypoints"])
    assert verdict and "6.000" in verdict.message
    assert check("15.5", [0.0, 2.0, 4.0, 6.0, 8.0])
    two = check("15.5", [0.0, 3.0])
    assert not two and "fastest of all" in two.message
    back = check("15.5", [0.0, 2.0, 0.0])           # a real stop: the trapezoid wins
    assert not back and "not slower" in back.message
    assert "do not move" in check("15.5", [1.0, 1.0, 1.0]).message
    assert "list of joint angles" in check("15.5", [[0.0, 1.0], [1.0, 2.0]]).message
    assert "no answer yet" in check("15.5", None).message
