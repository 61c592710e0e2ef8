"""Chapter 5's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

from rapp.exercises import check


def test_5_1_gd1_value(book_exercises):
    assert check("5.1", 71)
    assert "71" in book_exercises["5.1"]["solution"]
    assert "long way round" in check("5.1", 129).message
    assert "one axis" in check("5.1", 47).message
    assert "whole number" in check("5.1", 71.5).message


def test_5_2_model_function_passes_and_slips_fail(solution):
    assert check("5.2", solution("5.2")["h"])
    blind = check("5.2", lambda a, b, shape: sum(abs(x - y) for x, y in zip(a, b)))
    assert not blind and "seam" in blind.message and "b=(9, 0)" in blind.message
    off_by_one = check("5.2", lambda a, b, shape: sum(min(abs(x - y), m - abs(x - y) - 1)
                                                       for x, y, m in zip(a, b, shape)))
    assert not off_by_one and "fewer steps" in off_by_one.message
    two_d_only = check("5.2", lambda a, b, shape: min(abs(a[0] - b[0]), shape[0] - abs(a[0] - b[0]))
                       + min(abs(a[1] - b[1]), shape[1] - abs(a[1] - b[1])))
    assert not two_d_only and "IndexError" in two_d_only.message


def test_5_3_ring(book_exercises):
    assert check("5.3", 15)
    assert "15 steps" in book_exercises["5.3"]["solution"]
    assert "seam" in check("5.3", 5).message


def test_5_4_king_heuristic(solution):
    verdict = check("5.4", solution("5.4")["h"])
    assert verdict and "exact" in verdict.message
    gd1 = check("5.4", solution("5.2")["h"])
    assert not gd1 and "not admissible" in gd1.message
    assert "tells the search nothing" in check("5.4", lambda a, b, s: 0).message
    half = check("5.4", lambda a, b, s: max(min(abs(x - y), m - abs(x - y)) for x, y, m in zip(a, b, s)) / 2)
    assert half and "larger admissible" in half.message


def test_5_5_greedy_counterexample(solution):
    assert check("5.5", solution("5.5")["answer"])
    empty = check("5.5", (np.zeros((5, 5), bool), (0, 0), (2, 2)))
    assert not empty and "shortest path" in empty.message
    walled = np.ones((3, 3), bool)
    walled[0, 0] = walled[2, 2] = False
    assert "no path" in check("5.5", (walled, (0, 0), (2, 2))).message


def test_5_6_the_first_weight_that_lengthens_the_path(book_exercises):
    assert check("5.6", 1.5)
    assert "1.5" in book_exercises["5.6"]["solution"]
    assert "smaller weight" in check("5.6", 2.0).message
    assert "optimal length" in check("5.6", 1.25).message
    assert not check("5.6", 3.0)
