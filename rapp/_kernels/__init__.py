"""rapp's kernels: for each algorithm a numpy and a numba implementation side by side, one dispatcher.

=================  ==================================  =====================================
dispatcher         numpy                               numba
=================  ==================================  =====================================
``collision``      ``collision_numpy``                 ``collision_numba``
``occupancy``      ``occupancy_numpy``                 ``occupancy_numba``
``search`` (A*)    ``search_python`` (heapq, no numpy)  ``search_numba``
``sampling``       the planners' own ``_grow``          ``sampling_numba``
``ik``             :func:`rapp.ik_numeric`'s iteration  ``ik_numba``
=================  ==================================  =====================================

The public modules (:mod:`rapp.collision`, :mod:`rapp.cspace`, :mod:`rapp.search`, the
sampling planners, :mod:`rapp.ik`) call the dispatcher; the
dispatcher is the one place that chooses the backend (numba once it is loaded, or once the
work is large enough to pay for loading it; numpy without numba). Both backends give the same
answers, which the tests check against the slow oracles of :mod:`rapp.reference` (imported only
by tests and benchmarks). Private: the rest of rapp reaches these modules, nothing else should.

Examples
--------
>>> from rapp._kernels import collision
>>> collision.collides.__module__
'rapp._kernels.collision'
"""
