"""Chapter 7's exercises: the model solutions pass, plausible wrong answers fail usefully."""

import numpy as np

import rapp
from rapp.exercises import check


def test_7_1_other_elbow(book_exercises, solution):
    answer = solution("7.1")["answer"]
    assert check("7.1", answer)
    assert check("7.1", (50, 200, 4.967))
    text = book_exercises["7.1"]["solution"]
    assert "50 and 200 steps" in text and "4.967 rad" in text
    staircase = check("7.1", (50, 200, 2 * np.pi))
    assert not staircase and "staircase" in staircase.message
    through = check("7.1", (50, 200, np.hypot(np.pi / 2, np.pi / 2)))
    assert not through and "through the disc" in through.message
    waypoints = check("7.1", (53, 203, 4.967))
    assert not waypoints and "count waypoints" in waypoints.message
    assert "expected 3 numbers" in check("7.1", 4.967).message


def test_7_2_model_unwrap_passes_and_slips_fail(solution):
    assert check("7.2", solution("7.2")["unwrap"])
    assert check("7.2", lambda arm, path: rapp.paths.unwrap_path(arm, path))
    every_column = check("7.2", lambda arm, path: np.unwrap(np.asarray(path, float), axis=0))
    assert not every_column and "limited joint" in every_column.message
    wrong_axis = check("7.2", lambda arm, path: np.unwrap(np.asarray(path, float), axis=1))
    assert not wrong_axis and "long way round" in wrong_axis.message
    forgotten = check("7.2", lambda arm, path: np.asarray(path, float))
    assert not forgotten and "long way round" in forgotten.message and "path=[[3], [-3]]" in forgotten.message
    dropped = check("7.2", lambda arm, path: rapp.paths.unwrap_path(arm, path)[1:])
    assert not dropped and "shape" in dropped.message
    shifted = check("7.2", lambda arm, path: rapp.paths.unwrap_path(arm, path) + np.where(arm.limited, 0, 2 * np.pi))
    assert not shifted and "first configuration" in shifted.message
    half = check("7.2", lambda arm, path: np.where(arm.limited, path, np.unwrap(np.asarray(path, float), axis=0) + 0.1))
    assert not half and "first configuration" in half.message


def test_7_3_trusted_cells(book_exercises, solution):
    answer = solution("7.3")["answer"]
    assert check("7.3", answer)
    assert "M = 33" in book_exercises["7.3"]["solution"]
    # The claim behind the number: rapp.plan answers GridTooCoarse just below it, plain NoPathFound at it.
    sn = rapp.load_scenario("no_solution")
    kinds = []
    for cells in (answer - 1, answer):
        d = sn.to_dict()
        d["planner"]["cells"] = cells
        try:
            rapp.plan(d)
        except rapp.NoPathFound as exc:
            kinds.append(type(exc))
    assert kinds == [rapp.GridTooCoarse, rapp.NoPathFound]
    below = check("7.3", answer - 1)
    assert not below and "cell at each limit" in below.message
    assert "whole turn" in check("7.3", 63).message
    assert "delta(M)" in check("7.3", 20).message
    assert "whole number" in check("7.3", 32.5).message


def test_7_4_coarse_miss(solution):
    answer = solution("7.4")["answer"]
    verdict = check("7.4", answer)
    assert verdict and "GridTooCoarse" in verdict.message
    scenario, coarse, fine = answer
    assert "finds no path either" in check("7.4", ("no_solution", 20, 100)).message
    assert "finds a path" in check("7.4", ("srs_typical", 12, 100)).message
    assert "fewer than" in check("7.4", (scenario, fine, coarse)).message
    assert "at most 200" in check("7.4", (scenario, coarse, 400)).message
    assert "does not load" in check("7.4", ({"arm": {"link_lengths": [1.0, 0.0]}}, 12, 60)).message
    assert "expected a tuple" in check("7.4", scenario).message
    assert "integer" in check("7.4", (scenario, 12.5, 60)).message


def test_7_5_exit_code(book_exercises, solution):
    assert check("7.5", solution("7.5")["answer"])
    assert check("7.5", 2) and "Exit code 2" in book_exercises["7.5"]["solution"]
    assert "planning answer" in check("7.5", 1).message
    assert "loaded at all" in check("7.5", 0).message
