"""Argument checks shared by every module: a bad argument is a ValueError that names it.

Examples
--------
>>> positive_integer(3, "cells"), finite_number(0.5, "min_interval", above=0.0)
(3, 0.5)
>>> positive_integer(2.5, "samples", lo=2)
Traceback (most recent call last):
...
ValueError: samples must be an integer >= 2, got 2.5
"""

from __future__ import annotations

import math
import operator

import numpy as np

__all__ = ["positive_integer", "finite_number", "sorted_unique"]


def positive_integer(value, name: str, lo: int = 1) -> int:
    """``value`` as an int when it is an integer (not a bool, not a float) ``>= lo``.

    Examples
    --------
    >>> positive_integer(None, "max_intervals", lo=2)
    Traceback (most recent call last):
    ...
    ValueError: max_intervals must be an integer >= 2, got None
    """
    try:
        if isinstance(value, bool):
            raise TypeError
        v = operator.index(value)
    except TypeError:
        v = None
    if v is None or v < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {value!r}")
    return v


def finite_number(value, name: str, *, above: float | None = None, at_least: float | None = None) -> float:
    """``value`` as a finite float, strictly above ``above`` and not below ``at_least``.

    Examples
    --------
    >>> finite_number("x", "heuristic_weight", at_least=1.0)
    Traceback (most recent call last):
    ...
    ValueError: heuristic_weight must be a finite number >= 1, got 'x'
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    ok = math.isfinite(v) and (above is None or v > above) and (at_least is None or v >= at_least)
    if not ok:
        bound = (f" > {above:g}" if above is not None else "") + (
            f" >= {at_least:g}" if at_least is not None else "")
        raise ValueError(f"{name} must be a finite number{bound}, got {value!r}")
    return v


def sorted_unique(values):
    """The distinct values of a 1-D array, sorted: ``np.unique(values)`` for numbers without NaN.

    ``np.unique`` imports ``numpy.ma`` on its first call (some 20 ms, a fifth of
    ``python -m rapp plan``'s start-up); sorting and dropping repeats does not.

    Examples
    --------
    >>> sorted_unique(np.array([3, 1, 3, 2])).tolist()
    [1, 2, 3]
    """
    values = np.sort(np.asarray(values).ravel())
    return values[np.r_[True, values[1:] != values[:-1]]] if values.size else values
