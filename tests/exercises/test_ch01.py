"""Chapter 1's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

from rapp.exercises import check


def test_1_1_straight_up(book_exercises):
    assert check("1.1", [np.pi / 2, 0.0, 0.0])
    assert check("1.1", [np.pi / 2 + 2 * np.pi, 0.0, -2 * np.pi])  # whole turns are the same pose
    assert "(pi/2, 0, 0)" in book_exercises["1.1"]["solution"].replace("\\pi", "pi").replace("$", "")
    assert "degrees" in check("1.1", [90, 0, 0]).message
    assert "relative" in check("1.1", [np.pi / 2] * 3).message
    assert "3 joint angles" in check("1.1", [np.pi / 2, 0.0]).message


def test_1_2_second_configuration(solution):
    assert check("1.2", solution("1.2")["answer"])
    assert "shoulder must turn" in check("1.2", [0.3, -1.0]).message
    for shoulder in (1.0, -0.5, 2.0):   # the shoulder turned, by a wrong angle: no "elbow alone"
        wrong = check("1.2", [shoulder, -1.0])
        assert not wrong and "elbow alone" not in wrong.message and "shoulder turned" in wrong.message
    assert "same configuration on the torus" in check("1.2", [0.3 + 2 * np.pi, 1.0]).message
    assert "degrees" in check("1.2", np.degrees(solution("1.2")["answer"])).message


def test_1_3_hole_radius(book_exercises):
    assert check("1.3", 0.7) and "0.7" in book_exercises["1.3"]["solution"]
    assert "outer radius" in check("1.3", 1.3).message
    assert "second link" in check("1.3", 0.3).message


def test_1_4_short_way_round(book_exercises):
    assert check("1.4", 2 * np.pi - 6) and "0.283" in book_exercises["1.4"]["solution"]
    assert "long way" in check("1.4", 6.0).message


def test_1_5_wrap(solution):
    assert check("1.5", solution("1.5")["wrap"])
    at_pi = check("1.5", lambda a: float(np.arctan2(np.sin(a), np.cos(a))))
    assert not at_pi and "pi itself wraps" in at_pi.message
    shifted = check("1.5", lambda a: a % (2 * np.pi) - np.pi)
    assert not shifted and "not the same angle" in shifted.message
    no_wrap_below = check("1.5", lambda a: -np.pi if a == np.pi else a)
    assert not no_wrap_below and "outside [-pi, pi)" in no_wrap_below.message
    degrees = check("1.5", lambda a: (a + 180.0) % 360.0 - 180.0)
    assert not degrees
