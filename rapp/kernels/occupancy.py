"""The occupancy backend, chosen here: compiled loops on large grids or once numba is loaded, else numpy.

:func:`hits` is the work of :func:`rapp.cspace.occupancy` and :func:`rapp.cspace.certified_free`
(which document it): link ``i`` against the obstacles ``per_link[i]`` on the whole grid, by
:mod:`rapp.kernels.occupancy_numba` when :func:`compiled_for` says so and by
:mod:`rapp.kernels.occupancy_numpy` otherwise. Both give the same cells.

Examples
--------
>>> from rapp import Arm, Circle, JointGrid
>>> arm = Arm([1.0, 1.0])
>>> int(hits(arm, [[Circle((1.75, 0.75), 0.6)]] * 2, JointGrid(arm, 8)).sum())
2
"""

from __future__ import annotations

import math
import sys

import numpy as np

from rapp.kernels import occupancy_numba, occupancy_numpy

__all__ = ["hits", "compiled_for", "COMPILE_FROM"]

#: Grids of at least this many cells use the compiled kernel even when numba is not imported
#: yet; smaller ones use numpy unless numba is already loaded. Importing numba costs a few
#: tenths of a second, more than numpy spends on such a grid; it is the threshold from which
#: :func:`rapp.astar` compiles its search too, so a grid planned on pays the import once.
COMPILE_FROM = 1 << 16


def compiled_for(grid):
    """The compiled kernels for ``grid`` (see :data:`COMPILE_FROM`), or None: use numpy."""
    if math.prod(grid.shape) >= COMPILE_FROM or "numba" in sys.modules:
        return occupancy_numba.kernels()
    return None


def hits(arm, per_link, grid) -> np.ndarray:
    """Where link ``i`` touches one of ``per_link[i]`` (checked obstacles), for any ``i``: bool ``grid.shape``."""
    if not any(len(obs) for obs in per_link):
        return np.zeros(grid.shape, dtype=bool)
    k = compiled_for(grid)
    if k is None:
        return occupancy_numpy.hits(arm, per_link, grid)
    return occupancy_numba.run(k, occupancy_numba.levels(grid, per_link)).reshape(grid.shape)
