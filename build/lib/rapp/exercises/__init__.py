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

import numpy as np

from rapp.exercises.core import KINDS, Exercise, Verdict, describe
from rapp.exercises.sandbox import Died, Limits, Raised, Remote, Sandbox, TimedOut, bounded

__all__ = ["check", "grade", "catalog", "normalize_id", "verdict_in_sandbox", "Verdict", "Exercise", "KINDS"]

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


def normalize_id(exercise_id: Any) -> str | None:
    """The catalog id an exercise number stands for, or None when it is not a string.

    Examples
    --------
    >>> normalize_id("Exercise 5.2"), normalize_id(" 5.2 "), normalize_id("exercise\u00a05.2:")
    ('5.2', '5.2', '5.2')
    """
    if not isinstance(exercise_id, str):
        return None
    key = " ".join(str(exercise_id).split())
    if key.lower().startswith("exercise"):
        key = key[len("exercise"):].strip()
    return key.strip(" .:")[:40]


def check(exercise_id: Any, answer: Any, *, variant: str | None = None) -> Verdict:
    """Check your answer to one exercise.

    Your answer runs in a sandbox (a child process with time and memory limits), and only the
    plain data it produces comes back to be judged: see :mod:`rapp.exercises.sandbox`.

    Parameters
    ----------
    exercise_id : str
        The exercise's number as the book prints it, e.g. ``"5.2"`` (or ``"Exercise 5.2"``).
    answer : object
        Your answer: what the exercise's ``expects`` says (a number, an array, a function...).
    variant : str, optional
        The code on your exercise sheet, when your instructor gave you your own numbers
        (``python -m rapp assign``); without it, the book's numbers.

    Returns
    -------
    Verdict
        Truthy when correct; ``.message`` says what is right or what is wrong, with a hint
        (at most 2,000 characters). ``check`` never raises: a wrong type, a function that
        raises, never returns or ends its process, are all verdicts.

    Examples
    --------
    >>> print(check("5.1", 71.5))
    Exercise 5.1: not yet. 71.5 is not a whole number; this is a count.
    """
    try:
        if variant is not None:
            from rapp.exercises import variants
            key = normalize_id(exercise_id)
            if not variants.has_variant(key):
                return Verdict(_shown_id(exercise_id), False, "this exercise has no per-student numbers; "
                                                              "check it without variant=.")
            return _check(exercise_id, answer, judge=variants.judge(key, str(variant)))
        return _check(exercise_id, answer)
    except BaseException as exc:  # KeyboardInterrupt included: the reader's session survives
        return Verdict(_shown_id(exercise_id), False,
                       bounded(f"the check itself failed ({type(exc).__name__}); try again."))


def _shown_id(exercise_id: Any) -> str:
    key = normalize_id(exercise_id)
    return key if key is not None else "?"


def _check(exercise_id: Any, answer: Any, *, judge: Any = None) -> Verdict:
    key = normalize_id(exercise_id)
    if key is None:
        return Verdict("?", False,
                       f"the exercise id is a string such as \"5.2\", got {type(exercise_id).__name__} "
                       f"{describe(exercise_id, 40)}.")
    found = {ex.id: ex for ex in catalog()}
    if key not in found:
        chapter = key.split(".")[0]
        near = [i for i in found if i.split(".")[0] == chapter]
        known = f"chapter {chapter} has {', '.join(near)}" if near else \
            "see rapp.exercises.catalog() for the ids"
        return Verdict(bounded(key, 40), False, bounded(f"there is no exercise {key!r}; {known}."))
    ex = found[key]
    judge = judge or ex.judge
    if answer is None or _plain_enough(answer):
        return _verdict(ex, judge, answer, None)
    with Sandbox.of({0: answer}, Limits(wall=ex.time_limit)) as box:
        return _verdict(ex, judge, answer, box)


def verdict_in_sandbox(ex: Exercise, box: Sandbox, key: Any, judge: Any = None) -> Verdict:
    """The verdict on the answer a sandbox holds under ``key`` (what :mod:`rapp.grading` asks)."""
    try:
        return _verdict(ex, judge or ex.judge, None, box, key)
    except BaseException as exc:
        return Verdict(ex.id, False, bounded(f"the check itself failed ({type(exc).__name__})."))


def _verdict(ex: Exercise, judge: Any, answer: Any, box: Sandbox | None, key: Any = 0) -> Verdict:
    """Judge ``answer``; with a ``box``, the judge sees only what the box hands back."""
    try:
        if box is None:
            seen = answer
        elif box.is_callable(key):
            seen = Remote(box, key)
        else:
            seen = box.plain(key)
        judgement = judge(seen)
        message = judgement.message
        correct = bool(judgement.correct) and type(judgement.correct) in (bool, np.bool_)
    except TimedOut:
        correct, message = False, (f"your answer did not finish within {ex.time_limit:g} s; "
                                   "is there a loop that never ends?")
    except Raised as exc:
        correct, message = False, f"your answer raised {exc}."
    except Died as exc:
        correct, message = False, f"your answer ended its process: {exc}."
    except Exception as exc:  # a judge bug must still not cost the reader their session
        correct, message = False, f"the check itself failed ({type(exc).__name__}); expected {ex.expects}."
    if message == "no answer yet.":
        message = f"no answer yet: expected {ex.expects}."
    return Verdict(ex.id, correct, bounded(message))


_PLAIN_SCALARS = (type(None), bool, int, float, str)


def _plain_enough(value: Any, depth: int = 0) -> bool:
    """True for data no reader's code can hide in: exact builtins and numeric arrays, judged here.

    Only ``type()`` is looked at, never an attribute, so nothing of the reader's runs.
    """
    t = type(value)
    if t in _PLAIN_SCALARS:
        return True
    if t is np.ndarray:
        return value.dtype.kind in "biuf" and value.size <= 1_000_000
    if t in (np.float64, np.int64, np.bool_, np.float32, np.int32):
        return True
    if t in (list, tuple) and depth < 4 and len(value) <= 10_000:
        return all(_plain_enough(v, depth + 1) for v in value)
    return False


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
    try:
        if not hasattr(answers, "get") or not hasattr(answers, "keys"):
            return (Verdict("?", False, "answers must be a mapping of exercise id to answer, such as "
                                        f'{{"5.1": 71}}; got {type(answers).__name__}.'),)
        try:
            ids = list(answers.keys() if exercises is None else exercises)
        except TypeError:
            return (Verdict("?", False, "exercises must be an iterable of exercise ids such as \"5.2\"."),)
        return tuple(check(ex_id, _lookup(answers, ex_id)) for ex_id in ids)
    except BaseException as exc:  # a hostile mapping: one verdict, never an exception
        return (Verdict("?", False, bounded(f"the answers could not be read ({type(exc).__name__})."),),)


def _lookup(answers: Any, ex_id: Any) -> Any:
    """The answer to ``ex_id`` in ``answers``, whichever way the key is written ("Exercise 5.2")."""
    want = normalize_id(ex_id)
    try:
        if type(answers) is not dict:
            answers = dict(answers.items())
        for key, value in answers.items():
            if type(key) is str and normalize_id(key) == want:
                return value
    except Exception:  # a mapping whose items raise: no answer
        return None
    return None
