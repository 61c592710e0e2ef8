"""The backend seam: for each algorithm a numpy and a numba implementation side by side, one dispatcher.

=================  =====================================  =====================
dispatcher         numpy                                  numba
=================  =====================================  =====================
``collision``      ``collision_numpy``                    ``collision_numba``
``occupancy``      ``occupancy_numpy``                    ``occupancy_numba``
``search`` (A*)    ``search_python`` (heapq, no numpy)    ``search_numba``
``sampling``       the planners' own ``_grow``            ``sampling_numba``
``ik``             :func:`rapp.ik_numeric`'s iteration    ``ik_numba``
=================  =====================================  =====================

The public modules (:mod:`rapp.collision`, :mod:`rapp.cspace`, :mod:`rapp.search`, the
sampling planners, :mod:`rapp.ik`) call the dispatcher; the
dispatcher is the one place that chooses the backend (numba once it is loaded, or once the
work is large enough to pay for loading it; numpy without numba). Both backends give the same
answers, which the tests check against the slow oracles of :mod:`rapp.reference` (imported only
by tests and benchmarks). A public package: the rest of rapp, the tests and the benchmarks reach a
backend through its dispatcher (or name one implementation to compare it), never through a
private name; a reader of the book meets the algorithms in the modules above instead.

Examples
--------
>>> from rapp.kernels import collision
>>> collision.collides.__module__
'rapp.kernels.collision'
"""

#: The dispatchers, one per algorithm: the seam the rest of rapp calls.
__all__ = ["collision", "occupancy", "search", "sampling", "ik"]
