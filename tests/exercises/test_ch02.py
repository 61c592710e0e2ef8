"""Chapter 2's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check

LENGTHS = (1.0, 0.8, 0.5)
Q = (np.pi / 2, -np.pi / 2, np.pi / 2)


def _tip_along(lengths, angles):
    """The end effector with link i along ``angles[i]`` from +x (the MIS formula)."""
    angles = np.asarray(angles, dtype=float)
    return (float(np.sum(np.multiply(lengths, np.cos(angles)))),
            float(np.sum(np.multiply(lengths, np.sin(angles)))))


def test_2_1_reach(book_exercises):
    assert check("2.1", (0, 2.5))
    assert not check("2.1", (0, 2.3))  # the reach of (1, 0.8, 0.5), which the chapter prints, is not 2.1's
    assert "(0, 2.5)" in book_exercises["2.1"]["solution"]
    assert "never negative" in check("2.1", (-0.1, 2.5)).message
    assert "two-link formula" in check("2.1", (0.5, 2.5)).message
    assert "close a triangle" in check("2.1", (0.1, 2.5)).message
    assert "order" in check("2.1", (2.5, 0)).message
    assert "2 numbers" in check("2.1", 2.3).message


def test_2_2_end_effector(book_exercises):
    assert check("2.2", (0.8, 1.5))
    assert "(0.8, 1.5)" in book_exercises["2.2"]["solution"]
    mis = check("2.2", (0, 0.7))
    assert not mis and "relative angles" in mis.message
    degree_mode = rapp.Arm(LENGTHS).end_effector(np.deg2rad(Q))
    assert "degree" in check("2.2", degree_mode).message
    assert "(y, x)" in check("2.2", (1.5, 0.8)).message
    assert "link 3" in check("2.2", (0.8, 1.0)).message


def test_2_3_model_function_passes_and_slips_fail(solution):
    assert check("2.3", solution("2.3")["fk"])
    assert check("2.3", lambda lengths, q: rapp.Arm(lengths).end_effector(q))  # an array is fine

    relative = check("2.3", _tip_along)
    assert not relative and "relative angles" in relative.message and "lengths=(1, 1)" in relative.message

    def in_degrees(lengths, q):  # reads q as degrees
        return _tip_along(lengths, np.cumsum(np.deg2rad(q)))

    deg = check("2.3", in_degrees)
    assert not deg and "degrees" in deg.message and "lengths=(2,)" in deg.message

    def own_angle_left_out(lengths, q):
        return _tip_along(lengths, np.concatenate(([0.0], np.cumsum(q)[:-1])))

    assert "its own joint angle" in check("2.3", own_angle_left_out).message
    every_joint = check("2.3", lambda lengths, q: rapp.Arm(lengths).joint_positions(q))
    assert not every_joint and "every joint position" in every_joint.message
    assert "missing return" in check("2.3", lambda lengths, q: None).message
    assert "fk(lengths, q)" in check("2.3", lambda q: (0.0, 0.0)).message


def test_2_4_reaches_base(solution):
    assert check("2.4", solution("2.4")["reaches_base"])
    # Other correct forms of the triangle inequality agree on every case, boundary included.
    assert check("2.4", lambda L: all(L[i] <= L[(i + 1) % 3] + L[(i + 2) % 3] for i in range(3)))
    assert check("2.4", lambda L: bool(np.max(L) <= np.sum(L) - np.max(L)))

    strict = check("2.4", lambda L: 2 * max(L) < sum(L))
    assert not strict and "boundary" in strict.message
    first_only = check("2.4", lambda L: L[0] <= L[1] + L[2])
    assert not first_only and "wherever it is" in first_only.message
    assert "True or False" in check("2.4", lambda L: int(2 * max(L) <= sum(L))).message
    assert not check("2.4", lambda L: 2 * max(L) >= sum(L))
