"""The sampling planners' backend, chosen here: their compiled loops, or None for the numpy path.

RRT-Connect, RRT* and PRM (:mod:`rapp.rrt_connect`, :mod:`rapp.rrt_star`, :mod:`rapp.prm`) run
their iterations either in Python over numpy arrays (their own ``_grow``, the reference of
the pair) or, with numba, in the compiled loops of :mod:`rapp.kernels.sampling_numba`, which
grow the same trees node for node (``tests/test_sampling_kernel.py``). :func:`kernels` is
the one place that chooses: the compiled :data:`Loops`, or None without numba or with the
collision kernel switched off. The named tuples the loops take are re-exported here.

Examples
--------
>>> k = kernels()
>>> k is None or sorted(k._fields)[:3] == ['bisect', 'connect', 'draw']
True
"""

from __future__ import annotations

from rapp.kernels import sampling_numba
from rapp.kernels.sampling_numba import (CONNECT_FULL, CONNECT_LIMIT, CONNECT_MEET,
                                          CONNECT_MORE, EXTEND_ROWS, GRID_FROM, Cells, Loops, NearSet, Scene,
                                          StarProblem, StarTree, Trees)

__all__ = ["kernels", "Loops", "Scene", "Trees", "StarProblem", "StarTree", "Cells", "NearSet",
           "GRID_FROM", "EXTEND_ROWS", "CONNECT_MEET", "CONNECT_FULL", "CONNECT_LIMIT", "CONNECT_MORE"]


def kernels():
    """The compiled :data:`Loops` (:func:`rapp.kernels.sampling_numba.kernels`), or None: the
    planners then run their numpy path."""
    return sampling_numba.kernels()
