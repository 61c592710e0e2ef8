"""Check your own answers to the book's exercises.

Every exercise of the book has a number, "Exercise 5.2", and that number is its id here.
Call :func:`check` with the id and your answer: a number for a *numeric* exercise, your
function for an *implement* exercise, the artefact your argument produces (a counterexample, a
heuristic, a bound) for an *argue* exercise. The verdict is truthy when the answer is right, and
its message says what is right, or what is wrong with a hint; it never gives the answer away.
:func:`catalog` lists the exercises; :func:`grade` checks many answers at once, for an
instructor grading a class.

Examples
--------
>>> from rapp import exercises
>>> verdict = exercises.check("5.1", 70)
>>> bool(verdict)
False
>>> exercises.check("5.1", None).message
'no answer yet: expected an integer: the number of steps.'
>>> exercises.check("99.9", 1).correct
False
>>> [e.kind for e in exercises.catalog() if e.chapter == 5][:2]
['numeric', 'implement']
"""

from __future__ import annotations

from typing import Any

import importlib
import pkgutil

from rapp.exercises.core import KINDS, Exercise, Verdict

__all__ = ["check", "grade", "catalog", "Verdict", "Exercise", "KINDS"]

# One module per chapter, ``chNN``, each with a tuple EXERCISES in book order.
_CHAPTERS = tuple(
    importlib.import_module(f"{__name__}.{name}")
    for name in sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name.startswith("ch"))
)


def catalog() -> tuple[Exercise, ...]:
    """Every exercise of the book, in book order.

    Returns
    -------
    tuple of Exercise
        Each with ``id``, ``chapter``, ``kind``, ``title``, ``difficulty`` and ``expects``.

    Examples
    --------
    >>> first = catalog()[0]
    >>> first.id.count("."), first.kind in KINDS
    (1, True)
    """
    return tuple(ex for module in _CHAPTERS for ex in module.EXERCISES)


def check(exercise_id: Any, answer: Any) -> Verdict:
    """Check your answer to one exercise.

    Parameters
    ----------
    exercise_id : str
        The exercise's number as the book prints it, e.g. ``"5.2"``.
    answer : object
        Your answer: what the exercise's ``expects`` says (a number, an array, a function...).

    Returns
    -------
    Verdict
        Truthy when correct; ``.message`` says what is right or what is wrong, with a hint.
        ``check`` never raises: a wrong type, a function that raises or never returns, are all
        verdicts.

    Examples
    --------
    >>> print(check("5.1", 71.5))
    Exercise 5.1: not yet. 71.5 is not a whole number; this is a count.
    """
    if not isinstance(exercise_id, str):
        return Verdict(str(exercise_id), False,
                       f"the exercise id is a string such as \"5.2\", got {type(exercise_id).__name__} "
                       f"{exercise_id!r}.")
    key = exercise_id.strip()
    if key.lower().startswith("exercise"):
        key = key[len("exercise"):].strip()
    found = {ex.id: ex for ex in catalog()}
    if key not in found:
        chapter = key.split(".")[0]
        near = [i for i in found if i.split(".")[0] == chapter]
        known = f"chapter {chapter} has {', '.join(near)}" if near else \
            "see rapp.exercises.catalog() for the ids"
        return Verdict(key, False, f"there is no exercise {key!r}; {known}.")
    ex = found[key]
    try:
        judgement = ex.judge(answer)
    except Exception as exc:  # a judge bug must still not cost the reader their session
        return Verdict(key, False, f"the check itself failed ({type(exc).__name__}); expected {ex.expects}.")
    message = judgement.message
    if message == "no answer yet.":
        message = f"no answer yet: expected {ex.expects}."
    return Verdict(key, judgement.correct, message)


def grade(answers: Any, exercises: Any = None) -> tuple[Verdict, ...]:
    """Check many answers at once: what an instructor runs over each student's submission.

    Parameters
    ----------
    answers : mapping of str to object
        Exercise id to answer, e.g. a dict a student's module defines.
    exercises : iterable of str, optional
        The exercises assigned. A missing answer is checked as ``None`` (not yet answered).
        Default: the ids in ``answers``.

    Returns
    -------
    tuple of Verdict
        In the order of ``exercises`` (or of ``answers``); ``sum(map(bool, verdicts))`` is the score.
        Never raises: a malformed ``answers`` gives one verdict that says what is wrong with it.

    Examples
    --------
    >>> verdicts = grade({"5.1": 71, "5.3": 5}, exercises=["5.1", "5.3", "5.4"])
    >>> [bool(v) for v in verdicts], sum(map(bool, verdicts))
    ([True, False, False], 1)
    >>> print(grade([71])[0])
    Exercise ?: not yet. answers must be a mapping of exercise id to answer, such as {"5.1": 71}; got list.
    """
    if not hasattr(answers, "get") or not hasattr(answers, "keys"):
        return (Verdict("?", False, "answers must be a mapping of exercise id to answer, such as "
                                    f'{{"5.1": 71}}; got {type(answers).__name__}.'),)
    try:
        ids = list(answers.keys() if exercises is None else exercises)
    except TypeError:
        return (Verdict("?", False, "exercises must be an iterable of exercise ids such as \"5.2\"."),)
    return tuple(check(ex_id, _lookup(answers, ex_id)) for ex_id in ids)


def _lookup(answers: Any, ex_id: Any) -> Any:
    try:
        return answers.get(ex_id)
    except Exception:  # an unhashable id, or a mapping whose get raises: no answer
        return None
