"""The numerical IK's backend, chosen here: the compiled per-target loop, or numpy's batch.

:func:`rapp.ik_numeric` asks :func:`loaded` for the compiled solver of
:mod:`rapp.kernels.ik_numba` (loaded once numba is imported, or for a batch of at least
:data:`LOAD_FROM` targets); None means its own numpy iteration (in :mod:`rapp.ik`), which
gives the same successes (``tests/test_ik_kernel.py``). The constants both share are
re-exported here.

Examples
--------
>>> loaded(LOAD_FROM) is solver()
True
"""

from __future__ import annotations

import sys

from rapp.kernels import ik_numba
from rapp.kernels.ik_numba import (LAMBDA_MAX, LOAD_FROM, NO_START, NOT_OK, OK, SIGMA_FLOOR,
                                    UNSURE, Kernels)

__all__ = ["loaded", "solver", "Kernels", "LOAD_FROM", "SIGMA_FLOOR", "LAMBDA_MAX", "OK", "NOT_OK",
           "UNSURE", "NO_START"]


def solver():
    """The compiled :data:`~rapp.kernels.ik_numba.Kernels`, or None without numba."""
    return ik_numba.solver()


def loaded(targets: int):
    """:func:`solver` for a batch of ``targets`` once numba is imported or the batch has
    at least :data:`LOAD_FROM` targets, else None (numpy then solves it, with the same
    successes)."""
    if targets >= LOAD_FROM or "numba" in sys.modules:
        return solver()
    return None
