"""Fair verdicts: the stated tolerance, rounded answers, whole turns, ids, hints that name no false cause.

Each case the instructors' trial found (issue 25, first list) is a test here.
"""

import math

import numpy as np
import pytest

from rapp.exercises import catalog, check, grade, normalize_id
from rapp.exercises.core import CLOSE_FACTOR, TOLERANCE, TOLERANCE_ANGLES, TOLERANCE_COUNT, close

CATALOG = catalog()
VALUED = [ex for ex in CATALOG if hasattr(ex.judge, "expected")]


def _round_sig(x: np.ndarray, digits: int) -> np.ndarray:
    """Every entry rounded to ``digits`` significant figures, as a book prints it."""
    out = np.array(x, dtype=float)
    for i, v in np.ndenumerate(out):
        if v != 0 and math.isfinite(v):
            out[i] = round(v, digits - 1 - int(math.floor(math.log10(abs(v)))))
    return out


def test_the_issues_honest_answers_are_right():
    assert check("1.4", 0.283)
    assert check("1.2", [1.179, -1.0])
    assert check("6.2", 0.727) and check("3.1", 1.41) and check("12.3", 6.16)
    q = np.array([[0.0, np.pi / 2], [np.pi / 2, -np.pi / 2]])  # 6.1, a whole turn added
    assert check("6.1", q + [[2 * np.pi, 0.0], [0.0, -2 * np.pi]])
    assert check("5.1", 71.0000001) and check("Exercise 5.1", 71)
    assert check("5.4", lambda a, b, shape: 0)  # admissible and consistent, as the statement asks


def test_ids_are_normalised_in_check_and_grade():
    h = lambda a, b, s: sum(min(abs(x - y), m - abs(x - y)) for x, y, m in zip(a, b, s))  # noqa: E731
    verdicts = grade({"Exercise 5.2": h, " 5.1 ": 71}, ["5.2", "Exercise 5.1"])
    assert [bool(v) for v in verdicts] == [True, True]
    assert [v.exercise_id for v in verdicts] == ["5.2", "5.1"]
    assert [bool(v) for v in grade({"Exercise 5.2": h})] == [True]
    assert normalize_id("exercise 5.2:") == normalize_id("  5.2") == "5.2"


@pytest.mark.parametrize("ex", VALUED, ids=lambda e: e.id)
def test_the_value_rounded_as_the_book_prints_it_is_right(ex):
    want = np.asarray(ex.judge.expected(), dtype=float)
    # Three figures, unless the statement asks for more (11.3: within 0.0005, the book prints 1.5024).
    first = 3 if ex.tolerance in (TOLERANCE, TOLERANCE_ANGLES, TOLERANCE_COUNT) else 5
    for digits in range(first, 9):
        assert check(ex.id, _round_sig(want, digits)), (ex.id, digits)


@pytest.mark.parametrize("ex", [e for e in VALUED if e.tolerance != TOLERANCE_COUNT], ids=lambda e: e.id)
def test_a_right_value_rounded_too_far_is_told_close_never_a_mistake(ex):
    """Two significant figures (or a value just outside the tolerance): 'close', no cause named."""
    want = np.asarray(ex.judge.expected(), dtype=float)
    scale = np.maximum(5e-3 * np.abs(want), 5e-4)
    candidates = [_round_sig(want, 2), want + 1.5 * scale, want - 3 * scale]
    for got in candidates:
        verdict = check(ex.id, got)
        if verdict:
            continue
        assert "close" in verdict.message or "if you rounded" in verdict.message, (ex.id, got, verdict.message)


@pytest.mark.parametrize("ex", [e for e in CATALOG if e.tolerance == TOLERANCE_ANGLES], ids=lambda e: e.id)
def test_whole_turns_are_accepted_wherever_angles_are_asked(ex):
    known = {"1.1": [np.pi / 2, 0.0, 0.0], "1.2": [1.17880, -1.0]}
    answer = np.asarray(known[ex.id] if ex.id in known else ex.judge.expected(), dtype=float)
    assert check(ex.id, answer)
    turns = np.resize([1, -2, 3, 0], answer.size).reshape(answer.shape)
    assert check(ex.id, answer + 2 * np.pi * turns), ex.id


def test_every_exercise_with_a_value_states_its_tolerance_in_the_book(book_exercises):
    stated = [ex for ex in CATALOG if ex.tolerance]
    assert {ex.id for ex in CATALOG if ex.kind == "numeric"} <= {ex.id for ex in stated}
    for ex in stated:
        assert ex.tolerance in book_exercises[ex.id]["text"], ex.id
    assert {ex.tolerance for ex in stated} >= {TOLERANCE, TOLERANCE_ANGLES, TOLERANCE_COUNT}


def test_the_policy_and_its_close_band():
    assert close(1.41, math.sqrt(2)) and not close(1.40, math.sqrt(2))
    assert close(1.40, math.sqrt(2), CLOSE_FACTOR) and not close(1.2, math.sqrt(2), CLOSE_FACTOR)
    assert close(0.0004, 0.0) and not close(0.001, 0.0)
    assert "close" in check("1.4", 0.28).message and "long way" in check("1.4", 6.0).message


def test_15_5_the_book_states_the_tie_it_checks(book_exercises):
    from rapp.exercises.ch15 import minimum_duration

    six = np.arange(6.0)
    assert minimum_duration(six, "trapezoidal", 1.0, 1.0) == pytest.approx(10.0)
    assert minimum_duration(six, "cubic", 1.0, 1.0) == pytest.approx(10.0)
    assert not check("15.5", six.tolist())
    assert "10.000 s both" in book_exercises["15.5"]["solution"]
    ten = np.arange(0.0, 21.0, 2.0)
    assert round(minimum_duration(ten, "trapezoidal", 1.0, 1.0)) == 30
    assert round(minimum_duration(ten, "cubic", 1.0, 1.0), 1) == 28.3
    assert check("15.5", ten.tolist())
