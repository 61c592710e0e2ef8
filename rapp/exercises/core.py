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
...               numeric(lambda: 4.0, tol=1e-9, mistakes=[(lambda: 22.0, "add, do not concatenate")]))
>>> bool(ex.judge(4)), ex.judge(22).message
(True, '22: add, do not concatenate')
"""

from __future__ import annotations

import inspect
import textwrap
import multiprocessing
import os
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

__all__ = ["Verdict", "Exercise", "Judgement", "numeric", "implement", "close_numbers", "describe", "KINDS"]

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


def _as_number_array(answer: Any) -> np.ndarray | str:
    """The answer as a float array, or the reason it is not a number."""
    if answer is None:
        return "no answer yet"
    if isinstance(answer, (bool, np.bool_)):
        return f"got the bool {answer}, not a number"
    if isinstance(answer, (str, bytes)):
        return f"got the string {describe(answer)}, not a number (leave out the quotes)"
    if callable(answer):
        return "got a function; this exercise wants a value"
    try:
        arr = np.asarray(answer, dtype=float)
    except Exception:
        return f"got {type(answer).__name__} {describe(answer)}, which is not a number"
    if not np.all(np.isfinite(arr)):
        return f"got {describe(answer)}, which is not finite"
    return arr


def numeric(expected: Callable[[], Any], *, tol: float, relative: bool = False,
            mistakes: Sequence[tuple[Callable[[], Any], str]] = (),
            hint: str = "", exact_integer: bool = False) -> Callable[[Any], Judgement]:
    """A judge for a value: a number, or an array of numbers of a fixed shape.

    Parameters
    ----------
    expected : callable
        Computes the right value from the package when the check runs.
    tol : float
        Absolute tolerance (relative to ``|expected|`` when ``relative``).
    mistakes : sequence of (callable, str)
        Values a known mistake produces, with the hint to give when the answer matches one.
    hint : str
        Said when the answer is wrong and matches no known mistake.
    exact_integer : bool
        The answer is a count: a non-integer answer is told so.
    """

    def judge(answer: Any) -> Judgement:
        got = _as_number_array(answer)
        if isinstance(got, str):
            return Judgement(False, got + ".")
        want = np.asarray(expected(), dtype=float)
        if got.shape != want.shape:
            if want.shape == ():
                return Judgement(False, f"expected a single number, got an array of shape {got.shape}.")
            return Judgement(False, f"expected {want.size} numbers in shape {want.shape}, "
                                    f"got shape {got.shape}.")
        if exact_integer and not np.all(got == np.round(got)):
            return Judgement(False, f"{describe(answer)} is not a whole number; this is a count.")

        def close(a, b) -> bool:
            scale = np.maximum(np.abs(b), 1e-300) if relative else 1.0
            return bool(np.all(np.abs(a - b) <= tol * scale))

        if close(got, want):
            within = "" if exact_integer else f" (to within {tol:g}{' relative' if relative else ''})"
            return Judgement(True, f"{describe(answer)} is right{within}.")
        for wrong, why in mistakes:
            try:
                w = np.asarray(wrong(), dtype=float)
            except Exception:
                continue
            if w.shape == got.shape and close(got, w):
                return Judgement(False, f"{describe(answer)}: {why}")
        return Judgement(False, f"{describe(answer)} is not it" + (f"; {hint}" if hint else "."))

    # For the tests that prove no message gives the value away (the source is public anyway).
    judge.expected = expected
    return judge


# --- running a reader's function -------------------------------------------------------------

def _call_cases(fn, reference, cases, compare, report) -> None:
    """Run every case and ``report`` each step; the child process (or thread) runs this."""
    for i, args in enumerate(cases):
        report(("start", i))
        try:
            got = fn(*_fresh(args))
        except BaseException as exc:  # SystemExit and KeyboardInterrupt from a reader's code too
            report(("raised", i, f"{type(exc).__name__}: {exc}"))
            return
        try:
            problem = compare(got, reference(*_fresh(args)), args)
        except BaseException as exc:
            problem = f"returned {describe(got)}, which could not be compared ({type(exc).__name__})"
        if problem:
            report(("wrong", i, problem))
            return
    report(("ok",))


def _fresh(args: tuple) -> tuple:
    """Copies of array arguments, so a function that writes into its input harms no later case."""
    return tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)


def _run_in_child(fn, reference, cases, compare, time_limit: float) -> tuple:
    """Run the cases in a forked process; the last report, or ("timeout", i)."""
    ctx = multiprocessing.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)

    def child() -> None:
        recv.close()
        try:
            _call_cases(fn, reference, cases, compare, send.send)
        finally:
            send.close()
            os._exit(0)  # skip the parent's atexit handlers (a Jupyter kernel has several)

    proc = ctx.Process(target=child, daemon=True)
    proc.start()
    send.close()
    last: tuple = ("died", -1)
    deadline = time.monotonic() + time_limit
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not recv.poll(left):
                last = ("timeout", last[1] if last[0] == "start" else -1)
                break
            try:
                msg = recv.recv()
            except EOFError:
                if last[0] == "start":
                    last = ("died", last[1])
                break
            last = msg
            if msg[0] != "start":
                break
    finally:
        recv.close()
        if proc.is_alive():
            proc.kill()
        proc.join(1.0)
    return last


def _run_in_thread(fn, reference, cases, compare, time_limit: float) -> tuple:
    """Where fork is unavailable: a daemon thread, abandoned when it runs out of time."""
    reports: list = []
    worker = threading.Thread(target=_call_cases, args=(fn, reference, cases, compare, reports.append),
                              daemon=True)
    worker.start()
    worker.join(time_limit)
    if worker.is_alive() or not reports:
        started = [r[1] for r in reports if r[0] == "start"]
        return ("timeout", started[-1] if started else -1)
    return reports[-1]


def _signature_problem(fn, call: str, n_args: int) -> str | None:
    """Why ``fn`` cannot be called with ``n_args`` positional arguments, or None."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return None  # a builtin or a C function: just try it
    try:
        sig.bind(*range(n_args))
    except TypeError:
        return f"your function takes {sig}, but this exercise calls it as {call}."
    return None


def implement(reference: Callable, cases: Callable[[np.random.Generator], list[tuple]], *,
              call: str, names: Sequence[str], compare: Callable[[Any, Any, tuple], str | None],
              seed: int, time_limit: float = 5.0) -> Callable[[Any], Judgement]:
    """A judge for a function: it must agree with ``reference`` on hidden randomized cases.

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
        all_cases = cases(np.random.default_rng(seed))
        problem = _signature_problem(answer, call, len(all_cases[0]))
        if problem:
            return Judgement(False, problem)
        run = _run_in_child if "fork" in multiprocessing.get_all_start_methods() else _run_in_thread
        last = run(answer, reference, all_cases, compare, time_limit)
        kind, i = last[0], (last[1] if len(last) > 1 else -1)
        where = ""
        if 0 <= i < len(all_cases):
            shown = ", ".join(f"{n}={describe(v)}" for n, v in zip(names, all_cases[i]))
            where = f" for {shown}"
        if kind == "ok":
            return Judgement(True, f"your function agrees with the package on all {len(all_cases)} "
                                   "test cases, edge cases included.")
        if kind == "raised":
            return Judgement(False, f"your function raised {last[2]}{where}.")
        if kind == "wrong":
            return Judgement(False, f"case {i + 1} of {len(all_cases)}{where}: your function {last[2]}")
        if kind == "timeout":
            return Judgement(False, f"your function did not finish within {time_limit:g} s{where}; "
                                    "is there a loop that never ends?")
        return Judgement(False, f"your function ended the process{where} (did it call exit?).")

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
        g = _as_number_array(got)
        if isinstance(g, str):
            return f"returned {describe(got)}, not a number." if got is not None else "returned None (a missing return?)."
        w = np.asarray(want, dtype=float)
        if g.shape != w.shape:
            return f"returned shape {g.shape}; expected shape {w.shape}."
        if not np.allclose(g, w, rtol=0.0, atol=atol, equal_nan=True):
            return f"returned {describe(got)}: that {what} is not right."
        return None

    return compare


