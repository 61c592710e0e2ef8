"""What every exercise check shares: the verdict, the exercise record, and the two judges.

A *numeric* exercise is judged by :func:`numeric`: the expected value is computed from the
package when the check runs (never typed in), the reader's answer is compared within a
tolerance, and a wrong answer that matches a known mistake (degrees for radians, the wrap
forgotten, an off-by-one) gets that mistake's hint. An *implement* exercise is judged by
:func:`implement`: the reader's function runs on hidden randomized cases in a child process with
a time limit, against the package's own function, and the first failing input is reported. An
*argue* exercise asks for a proof or a design; its check judges the artefact the argument
produces (a counterexample, a heuristic, a bound) with one of the same two judges.

A judge never raises and never prints the expected answer.

Examples
--------
>>> ex = Exercise("0.1", 0, "numeric", "Two plus two", 1, "a number",
...               numeric(lambda: 4.0, mistakes=[(lambda: 22.0, "add, do not concatenate")]))
>>> bool(ex.judge(4)), ex.judge(22).message
(True, '22: add, do not concatenate')
"""

from __future__ import annotations

import copy
import textwrap
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from rapp.exercises.sandbox import Died, Limits, Opaque, Raised, Remote, Sandbox, TimedOut

__all__ = ["Verdict", "Exercise", "Judgement", "numeric", "implement", "close_numbers", "describe", "as_number_array", "KINDS", "close",
           "TOLERANCE", "TOLERANCE_ANGLES", "TOLERANCE_COUNT", "REL_TOL", "ABS_TOL", "CLOSE_FACTOR"]

KINDS = ("numeric", "implement", "argue")


@dataclass(frozen=True)
class Verdict:
    """The result of :func:`rapp.exercises.check`: truthy when the answer is right.

    Attributes
    ----------
    exercise_id : str
    correct : bool
    message : str
        What is right, or what is wrong and a hint; never the expected answer.
    """

    exercise_id: str
    correct: bool
    message: str

    def __bool__(self) -> bool:
        return self.correct

    def __str__(self) -> str:
        mark = "correct" if self.correct else "not yet"
        return f"Exercise {self.exercise_id}: {mark}. {self.message}"

    def __repr__(self) -> str:
        # Shown under the reader's check cell: wrapped to the width of a book page.
        return "\n".join(textwrap.wrap(str(self), width=80, subsequent_indent="  ",
                                        break_long_words=False, break_on_hyphens=False))


@dataclass(frozen=True)
class Exercise:
    """One exercise of the book.

    Attributes
    ----------
    id : str
        The book's number, ``"chapter.position"``: Exercise 5.2 has id ``"5.2"``.
    chapter : int
    kind : str
        ``"numeric"``, ``"implement"`` or ``"argue"``.
    title : str
    difficulty : int
        1 (a few minutes), 2 (a page of work) or 3 (a project).
    expects : str
        What :func:`rapp.exercises.check` wants as the answer.
    judge : callable
        ``judge(answer) -> (correct, message)``; see :func:`numeric` and :func:`implement`.
    """

    id: str
    chapter: int
    kind: str
    title: str
    difficulty: int
    expects: str
    judge: Callable[[Any], "Judgement"] = field(repr=False, compare=False)

    @property
    def tolerance(self) -> str | None:
        """The precision sentence the statement prints (numeric answers), or None."""
        return getattr(self.judge, "tolerance", None)

    @property
    def time_limit(self) -> float:
        """Seconds the reader's object may run for while this exercise is checked."""
        return float(getattr(self.judge, "time_limit", 5.0))


@dataclass(frozen=True)
class Judgement:
    """What a judge says: correct or not, and why."""

    correct: bool
    message: str

    def __bool__(self) -> bool:
        return self.correct


def describe(value: Any, limit: int = 120) -> str:
    """A short, readable rendering of an input or an answer for a message.

    Examples
    --------
    >>> describe(np.array([0.123456, 2.0]))
    '[0.1235, 2]'
    >>> describe("x" * 300)[-3:]
    '...'
    """
    try:
        if isinstance(value, np.ndarray):
            text = np.array2string(value, separator=", ", threshold=12, max_line_width=10_000,
                                   formatter={"float_kind": lambda v: f"{v:.4g}"})
        elif isinstance(value, float):
            text = f"{value:.6g}"
        elif isinstance(value, tuple):
            inner = ", ".join(describe(v, limit) for v in value)
            text = f"({inner}{',' if len(value) == 1 else ''})"
        elif isinstance(value, list):
            text = "[" + ", ".join(describe(v, limit) for v in value) + "]"
        else:
            text = repr(value)
    except Exception:  # an object whose repr raises still gets a name
        text = f"<{type(value).__name__}>"
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


REL_TOL = 5e-3
"""Relative tolerance of a numeric answer: three significant figures (0.5 %)."""

ABS_TOL = 5e-4
"""Absolute tolerance of a numeric answer near zero: three decimals."""

CLOSE_FACTOR = 10.0
"""Within this many tolerances of the exact value, a wrong answer is told "close: give more digits"."""

TOLERANCE = ("*Precision:* give at least three significant figures: an answer within 0.5 % of the "
             "exact value (or within 0.0005 of it) is right.")
"""The tolerance policy, as every exercise with a real-valued answer prints it."""

TOLERANCE_ANGLES = TOLERANCE[:-1] + "; angles may differ by whole turns."
"""The policy of an exercise whose answer is made of angles."""

TOLERANCE_COUNT = "*Precision:* a whole number, exactly."
"""The policy of an exercise whose answer is a count."""


def close(got: Any, want: Any, factor: float = 1.0, *, angles: bool = False,
          rel_tol: float = REL_TOL, abs_tol: float = ABS_TOL) -> bool:
    """True when every entry of ``got`` is within ``factor`` tolerances of ``want`` (the policy).

    Examples
    --------
    >>> close(0.283, 0.28318530717958623), close(1.41, 2 ** 0.5), close(1.4, 2 ** 0.5)
    (True, True, False)
    >>> close(1.4, 2 ** 0.5, CLOSE_FACTOR), close(np.pi / 2 + 2 * np.pi, np.pi / 2, angles=True)
    (True, True)
    """
    g, w = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    if g.shape != w.shape:
        return False
    diff = g - w
    if angles:
        diff = (diff + np.pi) % (2 * np.pi) - np.pi
    with np.errstate(invalid="ignore", over="ignore"):
        return bool(np.all(np.abs(diff) <= factor * np.maximum(rel_tol * np.abs(w), abs_tol)))


def _distance(a: np.ndarray, b: np.ndarray, angles: bool) -> float:
    diff = a - b
    if angles:
        diff = (diff + np.pi) % (2 * np.pi) - np.pi
    return float(np.max(np.abs(diff))) if diff.size else 0.0


def as_number_array(answer: Any) -> np.ndarray | str:
    """The answer as a float array, or the reason it is not a number.

    ``answer`` is plain data here (the sandbox converted the reader's object); a function
    arrives as a :class:`rapp.exercises.sandbox.Remote`.
    """
    if answer is None:
        return "no answer yet"
    if isinstance(answer, (bool, np.bool_)):
        return f"got the bool {answer}, not a number"
    if isinstance(answer, (str, bytes)):
        return f"got the string {describe(answer)}, not a number (leave out the quotes)"
    if callable(answer):
        return "got a function; this exercise wants a value"
    if isinstance(answer, Opaque):
        return f"got {answer.type_name} {describe(answer)}, which is not a number"
    try:
        arr = np.asarray(answer, dtype=float)
    except Exception:
        return f"got {type(answer).__name__} {describe(answer)}, which is not a number"
    if not np.all(np.isfinite(arr)):
        return f"got {describe(answer)}, which is not finite"
    return arr


def numeric(expected: Callable[[], Any], *, mistakes: Sequence[tuple[Callable[[], Any], str]] = (),
            hint: str = "", exact_integer: bool = False, angles: bool = False,
            abs_tol: float | None = None) -> Callable[[Any], Judgement]:
    """A judge for a value: a number, or an array of numbers of a fixed shape.

    The tolerance is the book's policy (:data:`TOLERANCE`): within 0.5 % or 0.0005 of the
    exact value, so an answer rounded to three significant figures, as the book prints values,
    is right; within ten times that the verdict says "close: give more digits". A count
    (``exact_integer``) must be exact. Where the answer is made of angles (``angles``), whole
    turns may be added to any of them.

    Parameters
    ----------
    expected : callable
        Computes the right value from the package when the check runs.
    mistakes : sequence of (callable, str)
        Values a known mistake produces, with the hint to give when the answer matches one
        (and is not close to the right value: a rounded answer never gets a mistake's hint).
    hint : str
        Said when the answer is wrong and matches no known mistake.
    exact_integer : bool
        The answer is a count: a non-integer answer is told so.
    angles : bool
        The answer is angles in radians: whole turns are accepted.
    abs_tol : float, optional
        Where three significant figures would accept a known mistake, the statement asks for
        more: the answer must be within ``abs_tol`` of the exact value (and says so).
    """
    tols = {"rel_tol": 0.0, "abs_tol": abs_tol} if abs_tol is not None else {}

    def near(a, b, factor=1.0) -> bool:
        return close(a, b, factor, angles=angles, **tols)

    def judge(answer: Any) -> Judgement:
        got = as_number_array(answer)
        if isinstance(got, str):
            return Judgement(False, got + ".")
        want = np.asarray(judge.expected(), dtype=float)
        if got.shape != want.shape:
            if want.shape == ():
                return Judgement(False, f"expected a single number, got an array of shape {got.shape}.")
            return Judgement(False, f"expected {want.size} numbers in shape {want.shape}, "
                                    f"got shape {got.shape}.")
        if exact_integer:
            near_integer = np.abs(got - np.round(got)) <= 1e-6
            if not np.all(near_integer):
                return Judgement(False, f"{describe(answer)} is not a whole number; this is a count.")
            got = np.round(got)
            if np.array_equal(got, want):
                return Judgement(True, f"{describe(answer)} is right.")
        elif near(got, want):
            return Judgement(True, f"{describe(answer)} is right (within the stated tolerance"
                                   f"{', modulo whole turns' if angles else ''}).")
        gap = _distance(got, want, angles)
        for wrong, why in mistakes:
            try:
                w = np.asarray(wrong(), dtype=float)
            except Exception:
                continue
            # A mistake's hint only for an answer nearer that mistake than the right value, so a
            # right value rounded too far is told "close", never a cause it does not have.
            if w.shape == got.shape and (np.array_equal(got, w) if exact_integer else
                                         near(got, w) and _distance(got, w, angles) < gap):
                return Judgement(False, f"{describe(answer)}: {why}")
        if not exact_integer and near(got, want, CLOSE_FACTOR):
            return Judgement(False, f"{describe(answer)} is close (within ten times the tolerance) "
                                    "but not right: if you rounded, give more digits, computed without "
                                    "rounding in between; if not, check your computation.")
        return Judgement(False, f"{describe(answer)} is not it" + (f"; {hint}" if hint else "."))

    # The variants (rapp.exercises.variants) replace this; tests read it (the book prints it anyway).
    judge.expected = expected
    if abs_tol is not None:
        # 11.3 asks for more digits (three figures would accept a known mistake); 4.6 for fewer
        # (its answer is read off a live explorer's drag, not computed).
        finer = abs_tol <= ABS_TOL
        judge.tolerance = (f"*Precision:* an answer within {abs_tol:g} of the exact value is right (this "
                           + ("exercise asks for more digits than three significant figures)."
                              if finer else "exercise is answered by reading the explorer, so fewer "
                              "digits are enough)."))
    else:
        judge.tolerance = TOLERANCE_COUNT if exact_integer else (TOLERANCE_ANGLES if angles else TOLERANCE)
    return judge


# --- running a reader's function -------------------------------------------------------------

def _fresh(args: tuple) -> tuple:
    """Deep copies of the arguments, so that nothing the reference gets was touched."""
    return copy.deepcopy(args)


def implement(reference: Callable, cases: Callable[[np.random.Generator], list[tuple]], *,
              call: str, names: Sequence[str], compare: Callable[[Any, Any, tuple], str | None],
              seed: int, time_limit: float = 5.0) -> Callable[[Any], Judgement]:
    """A judge for a function: it must agree with ``reference`` on hidden randomized cases.

    The reader's function runs in a sandbox (:mod:`rapp.exercises.sandbox`): each case is sent
    to it as a copy, and only the plain data it returns comes back; the reference runs here, on
    its own copy, and the comparison is made here.

    Parameters
    ----------
    reference : callable
        The package's function, or a thin wrapper of it, with the reader's signature.
    cases : callable
        ``cases(rng)`` returns the argument tuples: edge cases first, then random ones.
    call : str
        The call as the reader writes it, e.g. ``"h(a, b, shape)"``.
    names : sequence of str
        The argument names, used to print a failing input.
    compare : callable
        ``compare(got, want, args)`` returns None when ``got`` is right, else what is wrong with
        it, in words that do not give ``want`` away.
    seed : int
        Seeds the random cases, so the same wrong function gets the same report every time.
    time_limit : float
        Seconds for all the cases together; a function that loops is stopped.
    """

    def judge(answer: Any) -> Judgement:
        if answer is None:
            return Judgement(False, f"no answer yet: pass your function, called as {call}.")
        if not callable(answer):
            return Judgement(False, f"expected a function called as {call}; got "
                                    f"{type(answer).__name__} {describe(answer)}.")
        if not isinstance(answer, Remote):
            with Sandbox.of({0: answer}, Limits(wall=time_limit)) as box:
                return judge(Remote(box, 0))
        all_cases = cases(np.random.default_rng(seed))
        problem = answer.signature_problem(call, len(all_cases[0]))
        if problem:
            return Judgement(False, problem)
        for i, args in enumerate(all_cases):
            shown = ", ".join(f"{n}={describe(v)}" for n, v in zip(names, args))
            try:
                got = answer(*args)
            except Raised as exc:
                return Judgement(False, f"your function raised {exc} for {shown}.")
            except TimedOut:
                return Judgement(False, f"your function did not finish within {time_limit:g} s "
                                        f"(it was on {shown}); is there a loop that never ends?")
            except Died as exc:
                return Judgement(False, f"your function ended the process for {shown}: {exc}.")
            try:
                problem = compare(got, reference(*_fresh(args)), args)
            except Exception as exc:
                problem = f"returned {describe(got)}, which could not be compared ({type(exc).__name__})"
            if problem:
                return Judgement(False, f"case {i + 1} of {len(all_cases)} for {shown}: your function {problem}")
        return Judgement(True, f"your function agrees with the package on all {len(all_cases)} "
                               "test cases, edge cases included.")

    judge.time_limit = time_limit
    return judge


def close_numbers(*, atol: float, what: str = "value") -> Callable[[Any, Any, tuple], str | None]:
    """A ``compare`` for functions returning a number or an array of numbers.

    Examples
    --------
    >>> cmp = close_numbers(atol=1e-9)
    >>> cmp(1.0, 1.0, ()) is None, cmp("a", 1.0, ())
    (True, "returned 'a', not a number.")
    """

    def compare(got, want, args) -> str | None:
        g = as_number_array(got)
        if isinstance(g, str):
            return f"returned {describe(got)}, not a number." if got is not None else "returned None (a missing return?)."
        w = np.asarray(want, dtype=float)
        if g.shape != w.shape:
            return f"returned shape {g.shape}; expected shape {w.shape}."
        if not np.allclose(g, w, rtol=0.0, atol=atol, equal_nan=True):
            return f"returned {describe(got)}: that {what} is not right."
        return None

    return compare


