"""Chapter 4's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import math

import numpy as np

import rapp
from rapp.exercises import check


def test_4_1_cell_of_two_angles(book_exercises):
    assert check("4.1", [9, 0])
    assert "[9, 0]" in book_exercises["4.1"]["solution"]
    assert "seam" in check("4.1", [9, 12]).message
    assert "floor" in check("4.1", [9, 11]).message
    assert "numbered from 0" in check("4.1", [10, 1]).message
    assert "degrees" in check("4.1", [9, 6]).message
    assert "whole number" in check("4.1", [9, 0.5]).message
    assert "shape" in check("4.1", 9).message


def test_4_2_model_function_passes_and_slips_fail(solution):
    assert check("4.2", solution("4.2")["cell_of"])
    assert check("4.2", lambda a, m: int(rapp.JointGrid(rapp.Arm([1.0]), m).index([a])[0]))

    def no_wrap(angle, m):
        return int(round((angle + math.pi) / (2 * math.pi / m)))

    v = check("4.2", no_wrap)
    assert not v and "one past the last cell" in v.message and "angle=3" in v.message

    def no_seam(angle, m):
        return int(round(((angle + math.pi) % (2 * math.pi)) / (2 * math.pi / m)))

    v = check("4.2", no_seam)
    assert not v and "seam" in v.message

    def floor(angle, m):
        return int(math.floor(((angle + math.pi) % (2 * math.pi)) / (2 * math.pi / m))) % m

    v = check("4.2", floor)
    assert not v and "(floor)" in v.message and "nearest" in v.message

    def one_based(angle, m):
        return int(round(((angle + math.pi) % (2 * math.pi)) / (2 * math.pi / m))) % m + 1

    v = check("4.2", one_based)
    assert not v and "numbered from 0" in v.message

    def degrees(angle, m):
        return int(round(((angle + 180.0) % 360.0) / (360.0 / m))) % m

    v = check("4.2", degrees)
    assert not v and "radians" in v.message

    v = check("4.2", lambda angle, m: ((angle + math.pi) % (2 * math.pi)) / (2 * math.pi / m))
    assert not v and "whole number" in v.message
    assert "takes" in check("4.2", lambda angle: 0).message


def test_4_3_interval_width(book_exercises):
    assert check("4.3", 0.659) and check("4.3", 2 * np.arccos(3.69 / 3.9))
    assert "0.659" in book_exercises["4.3"]["solution"]
    assert "half-width" in check("4.3", 0.3297).message
    assert "tangent" in check("4.3", 2 * np.arcsin(0.5 / 1.5)).message
    assert "degrees" in check("4.3", np.degrees(0.659)).message
    assert "not it" in check("4.3", 0.7).message


def test_4_4_full_columns(solution, book_exercises):
    assert check("4.4", solution("4.4")["answer"])
    assert "**9** columns" in book_exercises["4.4"]["solution"]
    assert "at least one occupied" in check("4.4", 101).message
    assert "small disc touches" in check("4.4", 51).message
    assert "full rows" in check("4.4", 0).message
    assert "one too many" in check("4.4", 10).message
    assert "whole number" in check("4.4", 9.65).message


def test_4_5_collision_between_samples(solution):
    lengths, obstacles, cells, q = solution("4.5")["answer"]
    verdict = check("4.5", (lengths, obstacles, cells, q))
    assert verdict and "(4, 4)" in verdict.message
    tip = tuple(rapp.Arm([1.0, 1.0]).end_effector(q))
    big = check("4.5", (lengths, [rapp.Circle(tip, 1.0)], cells, q))
    assert not big and "so does the sample" in big.message
    misses = check("4.5", (lengths, [rapp.Circle((5.0, 5.0), 0.5)], cells, q))
    assert not misses and "does not collide" in misses.message
    assert "at least one" in check("4.5", (lengths, [], cells, q)).message
    assert "shape" in check("4.5", (lengths, obstacles, cells, [0.1])).message
    assert "grid" in check("4.5", (lengths, obstacles, 1, q)).message
    assert "tuple" in check("4.5", q).message
    assert "Circle" in check("4.5", (lengths, ["disc"], cells, q)).message
    limited = rapp.Arm([1.0, 1.0], [None, (-0.2, 0.2)])
    assert "joint limit" in check("4.5", (limited, obstacles, cells, q)).message


def test_4_6_the_reach_of_link_1(book_exercises):
    assert check("4.6", 1.25) and check("4.6", 1.27)  # read off the explorer's status line
    assert "1.25" in book_exercises["4.6"]["solution"]
    assert "near edge" in check("4.6", 1.0).message
    assert "link 2" in check("4.6", 2.25).message.lower() or "only link" in check("4.6", 2.25).message
    assert not check("4.6", 1.4)


def test_4_7_the_interval_of_a_thick_link(book_exercises):
    grown_tip = 2 * np.arccos((1.3**2 + 1.5**2 - 0.6**2) / (2 * 1.3 * 1.5))  # disc grown to 0.6
    assert check("4.7", grown_tip) and check("4.7", 0.816)
    assert "0.816" in book_exercises["4.7"]["solution"]
    assert "zero-width" in check("4.7", 0.659).message
    assert "width (0.2 m)" in check("4.7", 2 * np.arccos((1.3**2 + 1.5**2 - 0.7**2) / 3.9)).message
    assert "half-width" in check("4.7", grown_tip / 2).message
    assert "degrees" in check("4.7", np.degrees(grown_tip)).message
    assert not check("4.7", 0.9)
