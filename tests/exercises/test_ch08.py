"""Chapter 8's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check


def test_8_1_cubic_peak_velocity(book_exercises):
    assert check("8.1", 0.75)
    assert "0.75" in book_exercises["8.1"]["solution"]
    assert "average velocity" in check("8.1", 0.5).message          # Δ/T
    assert "quintic's peak" in check("8.1", 15 / 16).message        # the other profile
    assert "factor is off" in check("8.1", 1.5).message            # 3Δ/T, the 1/2 forgotten
    assert "not it" in check("8.1", 0.6).message


def test_8_2_model_function_passes_and_slips_fail(solution):
    assert check("8.2", solution("8.2")["cubic_coeffs"])

    def sign_a3(h, p0, pf, v0, vf):
        d = pf - p0
        return [p0, v0, (3 * d - (2 * v0 + vf) * h) / h**2, (2 * d - (v0 + vf) * h) / h**3]

    wrong = check("8.2", sign_a3)
    assert not wrong and "p(h) = pf" in wrong.message and "p'(0) = v0" not in wrong.message
    assert "h=2" in wrong.message                                   # the first (rest-to-rest) case

    def swapped(h, p0, pf, v0, vf):
        d = pf - p0
        return [p0, vf, (3 * d - (2 * vf + v0) * h) / h**2, (-2 * d + (vf + v0) * h) / h**3]

    wrong = check("8.2", swapped)
    assert not wrong and "swapped" in wrong.message

    descending = check("8.2", lambda *a: rapp.trajectory.cubic_local(*a)[::-1])
    assert not descending and "descending" in descending.message
    assert "4 coefficients" in check("8.2", lambda *a: rapp.trajectory.cubic_local(*a)[1:]).message
    assert "missing return" in check("8.2", lambda *a: None).message


def test_8_3_quintic_peak_acceleration(book_exercises, solution):
    want = 10 * np.sqrt(3) / 3 / 4
    assert check("8.3", want) and check("8.3", solution("8.3")["peak"])
    assert "1.443" in book_exercises["8.3"]["solution"]
    assert "cubic's peak acceleration" in check("8.3", 1.5).message
    assert "peak velocity" in check("8.3", 15 / 16).message
    assert "T = 1 s" in check("8.3", want * 4).message
    assert "not Δ/T" in check("8.3", want * 2).message
    assert "mid-time" in check("8.3", 0.0).message


def test_8_4_shortest_duration(solution):
    verdict = check("8.4", solution("8.4")["shortest"])
    assert verdict
    average = check("8.4", lambda delta, vmax: abs(delta) / vmax)
    assert not average and "too short" in average.message
    quintic = check("8.4", lambda delta, vmax: 15 * abs(delta) / (8 * vmax))
    assert not quintic and "longer than needed" in quintic.message
    no_abs = check("8.4", lambda delta, vmax: 3 * delta / (2 * vmax))
    assert not no_abs and "positive" in no_abs.message and "delta=-1" in no_abs.message
    assert "one duration" in check("8.4", lambda delta, vmax: np.array([1.0, 2.0])).message
