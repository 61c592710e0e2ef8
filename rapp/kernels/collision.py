"""The collision backend, chosen here: the compiled kernel once loaded, numpy before and without it.

:func:`collides`, :func:`link_clearances` and :func:`segment_collision_free` are those of
:mod:`rapp.collision` (which documents them); each asks :func:`loaded` for the compiled
kernel of :mod:`rapp.kernels.collision_numba` (loaded once numba is imported or the checks
of the process reach :data:`LOAD_FROM` configurations) and otherwise runs
:mod:`rapp.kernels.collision_numpy`. The answers are the same either way.

Examples
--------
>>> from rapp import Arm, Circle
>>> collides(Arm([1.0, 1.0]), [[0.0, 0.0], [1.5, 0.0]], [Circle((1.5, 0.0), 0.2)]).tolist()
[True, False]
"""

from __future__ import annotations

import numpy as np

from rapp.arm import MAX_ANGLE
from rapp.kernels import collision_numba, collision_numpy
from rapp.kernels.collision_numba import LOAD_FROM, Kernels, by_identity, pack, pack_scene
from rapp.kernels.collision_numpy import check_segments

__all__ = ["collides", "link_clearances", "segment_collision_free", "kernels", "loaded", "pack",
           "by_identity", "Kernels", "LOAD_FROM", "collides_scene", "pack_scene"]

#: The answers of the one-configuration kernel (0 free, 1 collides) as numpy's own booleans.
_ANSWER = (np.False_, np.True_)


def kernels():
    """The compiled :class:`~rapp.kernels.collision_numba.Kernels`, or None without numba."""
    return collision_numba.kernels()


def loaded(work: int = 0):
    """The compiled kernels once worth loading (:func:`rapp.kernels.collision_numba.loaded`), else None."""
    return collision_numba.loaded(work)


def link_clearances(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.link_clearances` by the backend of the moment."""
    k = loaded(np.size(q) // arm.n)
    if k is None:
        return collision_numpy.link_clearances(arm, q, obstacles)
    packed = pack(obstacles)
    q = _checked(arm, q)
    return k.clearances(arm.lengths, q.reshape(-1, arm.n), *packed).reshape(q.shape)


def collides(arm, q, obstacles) -> np.ndarray:
    """:func:`rapp.collision.collides` by the backend of the moment."""
    n = arm.n
    if type(q) is np.ndarray and q.shape == (n,) and q.dtype == np.float64:
        # One configuration, as the sampling planners ask: the shortest way to the kernel.
        k = loaded(1)
        if k is not None:
            hit = k.collides_one(arm.lengths, q, *pack(obstacles), MAX_ANGLE)
            if hit < 0:  # the kernel checks the angles' range; the message is check_q's
                arm.check_q(q)
            return _ANSWER[hit]
    k = loaded(np.size(q) // n)
    if k is None:
        return collision_numpy.collides(arm, q, obstacles)
    packed = pack(obstacles)
    if type(q) is not np.ndarray or q.dtype != np.float64 or not q.ndim or q.shape[-1] != n:
        q = arm.check_q(q)
    hit, ok = k.collides(arm.lengths, q.reshape(-1, n), *packed, MAX_ANGLE)
    if not ok:  # the kernel checks the angles' range; the message is check_q's
        arm.check_q(q)
    return hit[0] if q.ndim == 1 else hit.reshape(q.shape[:-1])


def collides_scene(scene, q) -> int:
    """One configuration against a :func:`pack_scene` array (1 collides, 0 free, -1 an angle out
    of range, -2 a wrong length), by the backend of the moment.

    Examples
    --------
    >>> from rapp import Circle
    >>> scene = pack_scene([1.0, 1.0], [Circle((1.5, 0.0), 0.2)], MAX_ANGLE)
    >>> collides_scene(scene, np.array([0.0, 0.0])), collides_scene(scene, np.array([0.0, 0.0, 0.0]))
    (1, -2)
    """
    k = loaded(1)
    return (collision_numpy.collides_scene if k is None else k.collides_scene)(scene, q)


def _checked(arm, q):
    """``arm.check_q(q)``, with the common case (a float array in range) in two numpy calls."""
    if type(q) is np.ndarray and q.dtype == np.float64 and q.ndim and q.shape[-1] == arm.n \
            and q.size and np.abs(q).max() <= MAX_ANGLE:
        return q
    return arm.check_q(q)


def segment_collision_free(arm, q0, q1, obstacles, *, min_interval, max_intervals) -> np.ndarray:
    """:func:`rapp.collision.segment_collision_free` by the backend of the moment."""
    k = loaded(max(np.size(q0), np.size(q1)) // arm.n)
    if k is None:
        return collision_numpy.segment_collision_free(arm, q0, q1, obstacles, min_interval=min_interval,
                                                      max_intervals=max_intervals)
    packed = pack(obstacles)
    q0, q1, dq, bounds, shape, min_interval, cap = check_segments(arm, q0, q1, min_interval,
                                                                  max_intervals)
    if not len(obstacles):
        return np.ones(shape, dtype=bool)
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    code = k.certify(arm.lengths, q0, dq, bounds, *packed, min_interval, cap, touch)
    if (code < 0).any():  # more intervals than allowed: the numpy version raises the message
        i = int(np.argmax(code < 0))
        collision_numpy.segment_collision_free(arm, q0[i], q1[i], obstacles, min_interval=min_interval,
                                               max_intervals=cap)
    return (code > 0).reshape(shape)
