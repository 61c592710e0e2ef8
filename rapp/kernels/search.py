"""The A* backend, chosen here: compiled (numba) on large grids or once numba is loaded, else Python.

:func:`astar_path` is the work of :func:`rapp.search.astar` (which documents it) on checked
arguments: :mod:`rapp.kernels.search_numba` when :func:`compiled_for` gives its kernel and the
grid fits its integer fields, :mod:`rapp.kernels.search_python` otherwise. Both expand the
same cells in the same order and return the same path.

Examples
--------
>>> import numpy as np
>>> astar_path(np.zeros((4, 4), bool), (True, True), (0, 0), (3, 0), 1.0, -1)[1]
[(0, 0), (3, 0)]
"""

from __future__ import annotations

import sys

import numpy as np

from rapp.kernels import search_numba, search_python

__all__ = ["astar_path", "compiled_for", "COMPILE_FROM"]

#: Grids of at least this many cells are searched by the compiled kernel even when numba is
#: not imported yet; smaller ones in Python (the same cells, the same path): importing numba
#: costs more than this Python loop spends on a small grid (a command planning on 100 x 100
#: cells would pay it for nothing); once it is imported, it is used.
COMPILE_FROM = 1 << 16


def compiled_for(occ):
    """The compiled kernel for the grid ``occ``, or None: search it in Python."""
    if occ.size < COMPILE_FROM and "numba" not in sys.modules:
        return None
    kernel = search_numba.kernel()
    # The kernel: g and cells in int32; keys h << sb | packed coordinates in int64.
    sb = sum((m - 1).bit_length() for m in occ.shape)
    if kernel is None or occ.size >= 2**31 - 1 or sb + sum(occ.shape).bit_length() > 62:
        return None
    return kernel


def astar_path(occ, wraps, start, goal, weight, limit) -> tuple:
    """``(status, cells)``: status 0 found (``cells`` the list of cells, tuples of ints, start to
    goal), 1 the goal is unreachable, 2 the expansion ``limit`` was hit (-1: none); on checked
    arguments."""
    kernel = compiled_for(occ)
    if kernel is None:
        status, flat, _, graph = search_python.astar(occ, wraps, wraps, start, goal, weight, limit)
        return status, _tuples(graph.path(flat).T) if status == 0 else None
    s = int(np.ravel_multi_index(start, occ.shape))
    t = int(np.ravel_multi_index(goal, occ.shape))
    status, _, flat = kernel(occ.ravel(), np.array(occ.shape, dtype=np.int64),
                             np.array(wraps, dtype=np.bool_), np.array(goal, dtype=np.int64),
                             s, t, float(weight), limit)
    if status:
        return status, None
    return 0, _tuples(np.unravel_index(flat, occ.shape))


def _tuples(coordinates) -> list:
    """Cells as tuples of Python ints, from one array of coordinates per axis."""
    return list(zip(*(c.tolist() for c in coordinates)))
