"""Chapter 11's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

from rapp.exercises import check


def test_11_1_constraint_1_literally(book_exercises, solution):
    assert check("11.1", [-2 / 9, 1.0, 0.0, 5.0]) and check("11.1", solution("11.1")["answer"])
    assert "-2/9" in book_exercises["11.1"]["solution"]
    assert "printed tables" in check("11.1", [-7 / 36, 11 / 12, 0.0, 5.0]).message   # ẏ_B = 0.25
    assert "ascending" in check("11.1", [5.0, 0.0, 1.0, -2 / 9]).message
    assert "not x_A" in check("11.1", [-2 / 9, 1.0, 0.0, 2.0]).message
    assert "4 numbers" in check("11.1", 1.0).message


def test_11_2_fastest_on_dc(book_exercises, solution):
    assert check("11.2", 6.75) and check("11.2", solution("11.2")["answer"])
    assert "6.75" in book_exercises["11.2"]["solution"]
    assert "local time" in check("11.2", 1.25).message
    assert "at rest at D" in check("11.2", 5.5).message
    assert "at rest at C" in check("11.2", 8.0).message
    assert "close" in check("11.2", 7.0).message  # 6.75 rounded to one figure: close, no cause named
    assert "acceleration is zero" in check("11.2", 7.5).message


def test_11_3_reach_d_later(book_exercises, solution):
    assert check("11.3", 1.5024) and check("11.3", solution("11.3")["answer"])
    assert "1.5024" in book_exercises["11.3"]["solution"]
    assert "surface" in check("11.3", 0.0024).message
    assert "radius" in check("11.3", 1.5).message
    assert "straight segment BD" in check("11.3", 1.5111).message
    assert "does not change" in check("11.3", 0).message


def test_11_4_heuristic_velocity_at_b(book_exercises, solution):
    assert check("11.4", [1.4, 0.0]) and check("11.4", solution("11.4")["answer"])
    assert "(1.4, 0)" in book_exercises["11.4"]["solution"]
    assert "opposite signs" in check("11.4", [1.4, 0.4]).message          # sign rule forgotten
    assert "time step" in check("11.4", [6.0, 0.0]).message               # slopes not divided
    assert "time step" in check("11.4", [6.0, 1.0]).message
    assert "prescribed" in check("11.4", [0.25, 0.25]).message            # the seed's velocity


def _slopes(t, p):
    return np.diff(p) / np.diff(t)


def test_11_5_model_function_passes_and_slips_fail(solution):
    assert check("11.5", solution("11.5")["via_velocities"])

    def no_sign_rule(times, positions):
        s = _slopes(times, positions)
        return np.concatenate(([0.0], (s[:-1] + s[1:]) / 2, [0.0]))

    wrong = check("11.5", no_sign_rule)
    assert not wrong and "opposite signs" in wrong.message and "index 2" in wrong.message

    def ends_not_zero(times, positions):
        s = _slopes(times, positions)
        inner = np.where(s[:-1] * s[1:] > 0, (s[:-1] + s[1:]) / 2, 0.0)
        return np.concatenate(([s[0]], inner, [s[-1]]))

    wrong = check("11.5", ends_not_zero)
    assert not wrong and "at rest" in wrong.message and "index 0" in wrong.message

    def not_divided(times, positions):
        s = np.diff(positions)
        return np.concatenate(([0.0], np.where(s[:-1] * s[1:] > 0, (s[:-1] + s[1:]) / 2, 0.0), [0.0]))

    wrong = check("11.5", not_divided)
    assert not wrong and "divided by its time step" in wrong.message and "times=[0, 2, 3, 7]" in wrong.message

    def flat_kept(times, positions):
        s = _slopes(times, positions)
        return np.concatenate(([0.0], np.where(s[:-1] * s[1:] >= 0, (s[:-1] + s[1:]) / 2, 0.0), [0.0]))

    wrong = check("11.5", flat_kept)
    assert not wrong and "flat segment" in wrong.message

    def interior_only(times, positions):
        return solution("11.5")["via_velocities"](times, positions)[1:-1]

    assert "one velocity per via point" in check("11.5", interior_only).message
    assert "missing return" in check("11.5", lambda t, p: None).message
    column = check("11.5", lambda t, p: solution("11.5")["via_velocities"](t, p)[:, None])
    assert column                                                         # a (k, 1) column is fine


def test_11_6_heuristic_counterexample(solution):
    verdict = check("11.6", solution("11.6")["answer"])
    assert verdict and "t = 1.5" in verdict.message
    even = check("11.6", (np.arange(4.0), np.arange(4.0)))
    assert not even and "stays monotone" in even.message
    assert "strictly monotone" in check("11.6", ([0, 1, 2, 3], [0, 10, 5, 21])).message
    assert "strictly increasing" in check("11.6", ([0, 1, 1, 3], [0, 10, 11, 21])).message
    assert "tuple" in check("11.6", 3.0).message
    # the ratio of slopes 5 is still monotone (alpha = beta = 3), a little more is not
    assert not check("11.6", ([0, 1, 2, 3], [0, 5, 6, 11]))
    assert check("11.6", ([0, 1, 2, 3], [0, 5.5, 6.5, 12]))


def test_11_7_spline_overshoots(solution):
    verdict = check("11.7", solution("11.7")["answer"])
    assert verdict and "overshoots" in verdict.message
    seed = check("11.7", (3.0, 5.5))
    assert not seed and "never goes backwards" in seed.message
    both = check("11.7", (4.0, 4.5))
    assert not both and "so does the heuristic" in both.message
    assert "t_B < t_D" in check("11.7", (5.0, 2.0)).message
    assert "two times" in check("11.7", (1.0, 2.0, 3.0)).message
