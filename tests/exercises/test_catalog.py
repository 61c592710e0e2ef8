"""The exercises as a whole: the book's rules, the book agrees with the catalog, check() is robust.

Every teaching chapter has at least four exercises and, from chapter 2 on, an implement one;
the book has at least eight argue exercises. The notebooks print exactly the catalog's
exercises, in order (so the number the book prints is the id ``check`` takes), each with a
folded solution and a check cell. ``check`` returns a verdict for anything it is given and no
message contains the expected value.
"""

import math
import os
import re
import time
from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import exercises
from rapp.exercises import KINDS, Verdict, catalog, check, grade

TEACHING = (1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 13, 14, 15)
CATALOG = catalog()
IDS = [ex.id for ex in CATALOG]


def test_every_teaching_chapter_has_four_exercises_and_the_kinds_the_issue_asks_for():
    by_chapter = Counter(ex.chapter for ex in CATALOG)
    assert {c: by_chapter[c] for c in TEACHING if by_chapter[c] < 4} == {}
    implement = {ex.chapter for ex in CATALOG if ex.kind == "implement"}
    assert [c for c in TEACHING if c >= 2 and c not in implement] == []
    assert sum(ex.kind == "argue" for ex in CATALOG) >= 8
    assert {ex.kind for ex in CATALOG} <= set(KINDS)


def test_ids_number_the_exercises_of_each_chapter_in_order():
    assert len(set(IDS)) == len(IDS)
    for chapter in {ex.chapter for ex in CATALOG}:
        mine = [ex.id for ex in CATALOG if ex.chapter == chapter]
        assert mine == [f"{chapter}.{i}" for i in range(1, len(mine) + 1)]
    assert all(ex.difficulty in (1, 2, 3) and ex.title and ex.expects for ex in CATALOG)


def test_the_notebooks_print_exactly_the_catalog(book_exercises):
    assert list(book_exercises) == IDS  # same exercises, same order: "Exercise 5.2" is check("5.2")
    assert IDS, "no exercise in the catalog"
    for ex in CATALOG:
        printed = book_exercises[ex.id]
        assert (printed["chapter"], printed["title"], printed["kind"], printed["difficulty"]) == \
            (ex.chapter, ex.title, ex.kind, ex.difficulty), ex.id
        assert printed["solution"] is not None, f"Exercise {ex.id} has no solution"
        cell = printed["check_cell"] or ""
        assert re.match(rf"answer = None  # Exercise {re.escape(ex.id)}: .+\n"
                        rf"rapp\.exercises\.check\(\"{re.escape(ex.id)}\", answer\)$", cell), ex.id


def test_solutions_are_folded_and_no_notebook_hides_an_answer(book_exercises):
    import json
    from pathlib import Path

    for ex_id, printed in book_exercises.items():
        assert ":class: dropdown" in printed["solution"], ex_id
    # A hidden cell would show its answer in JupyterLab: the exercise sections hold none.
    for path in sorted(Path(__file__).resolve().parents[2].glob("notebooks/[0-9][0-9]_*.ipynb")):
        cells = json.loads(path.read_text())["cells"]
        start = [i for i, c in enumerate(cells) if "".join(c["source"]).startswith("## Exercises")]
        if not start or int(path.name[:2]) not in {ex.chapter for ex in CATALOG}:
            continue  # a chapter still in the old format has no check cells yet
        end = next((i for i in range(start[0] + 1, len(cells)) if cells[i]["cell_type"] == "markdown"
                    and "".join(cells[i]["source"]).startswith("## ")), len(cells))
        for c in cells[start[0]:end]:
            if c["cell_type"] == "code":
                assert "".join(c["source"]).startswith("answer = None"), path.name
                assert not set(c["metadata"].get("tags", [])) & {"remove-cell", "remove-input",
                                                                  "hide-input", "hide-cell"}


ODD_VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20), st.binary(max_size=8), st.lists(st.integers(), max_size=5),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=3),
    st.tuples(st.integers(), st.floats()), st.just(np.zeros((3, 3))), st.just(object()),
    st.just(np.array([np.nan, 1.0])), st.just(Ellipsis), st.just({1, 2}),
)


@settings(max_examples=60 if os.environ.get("CI") else 30, deadline=None)
@given(ex_index=st.integers(0, len(CATALOG) - 1), answer=ODD_VALUES)
def test_check_returns_a_verdict_for_any_value(ex_index, answer):
    verdict = check(IDS[ex_index], answer)
    assert isinstance(verdict, Verdict) and isinstance(verdict.message, str) and verdict.message
    assert isinstance(repr(verdict), str)


def _raises(*args):
    raise RuntimeError("boom")


def _returns_junk(*args):
    return "junk"


def _exits(*args):
    os._exit(3)


@pytest.mark.parametrize("answer", [None, "x", 3, lambda: 0, _raises, _returns_junk, _exits],
                         ids=["none", "string", "int", "no-args", "raises", "junk", "exits"])
def test_implement_exercises_turn_bad_functions_into_verdicts(answer):
    for ex in CATALOG:
        if ex.kind != "implement":
            continue
        verdict = check(ex.id, answer)
        assert not verdict, ex.id
        assert verdict.message and "check itself failed" not in verdict.message, (ex.id, verdict.message)


@pytest.mark.slow  # waits out the 5 s wall limit
def test_a_function_that_never_returns_is_stopped():
    def spins(*args):
        while True:
            pass

    first = next(ex for ex in CATALOG if ex.kind == "implement")
    t0 = time.monotonic()
    verdict = check(first.id, spins)
    assert not verdict and "did not finish" in verdict.message
    assert time.monotonic() - t0 < 15  # the time limit, not forever


def _shown(value: float) -> set[str]:
    """Ways a message could print ``value``."""
    forms = {f"{value:.{k}f}" for k in (2, 3, 4)} | {f"{value:.{k}g}" for k in (3, 4, 5, 6)}
    if float(value).is_integer():
        forms.add(str(int(value)))
    return {f for f in forms if len(f.lstrip("-").replace(".", "").lstrip("0")) >= 2}


@pytest.mark.parametrize("ex", [ex for ex in CATALOG if hasattr(ex.judge, "expected")], ids=lambda e: e.id)
def test_no_message_gives_a_numeric_answer_away(ex):
    want = np.atleast_1d(np.asarray(ex.judge.expected(), dtype=float))
    assert check(ex.id, ex.judge.expected())  # the package's own value is right
    wrongs = [None, "x", np.asarray(ex.judge.expected(), float) * 1.37 + 0.51, -np.asarray(
        ex.judge.expected(), float) - 3.0, np.zeros(np.shape(ex.judge.expected()))]
    for wrong in wrongs:
        verdict = check(ex.id, wrong)
        assert not verdict
        for v in want:
            if math.isfinite(v) and abs(v) >= 0.01:
                leaked = {f for f in _shown(v) if re.search(rf"(?<![\d.]){re.escape(f)}(?![\d])",
                                                            verdict.message)}
                shown_answer = {f for f in _shown(float(np.ravel(wrong)[0]))} if isinstance(
                    wrong, np.ndarray) and wrong.size else set()
                assert not (leaked - shown_answer), (ex.id, verdict.message)


def test_check_names_a_wrong_id_and_accepts_the_printed_form():
    assert "no exercise" in check("5.99", 1).message
    assert "string" in check(5.1, 71).message
    assert check("Exercise 5.1", 71) and check(" 5.1 ", 71)


def test_grade_checks_a_submission():
    verdicts = grade({"5.1": 71, "5.3": 15}, ["5.1", "5.2", "5.3"])
    assert [v.exercise_id for v in verdicts] == ["5.1", "5.2", "5.3"]
    assert [bool(v) for v in verdicts] == [True, False, True]
    assert "no answer yet" in verdicts[1].message
    assert not grade(None)[0] and not grade({"5.1": 71}, exercises=5)[0]
    assert exercises.grade({}, [["unhashable"]])[0].correct is False
