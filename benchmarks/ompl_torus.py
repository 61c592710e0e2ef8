"""OMPL asked rapp's question: plan on the torus SO(2)^n, valid where ``rapp.collides`` says free.

Shared by ``bench_planners.py`` and ``compare_planners.py``, so both benchmarks pose OMPL the
same problem in one place. OMPL comes from ``benchmarks/requirements.txt``; importing this module
does not import it, calling :func:`torus_setup` does.
"""

from __future__ import annotations

import numpy as np

import rapp


def kernel_validity(arm, obstacles):
    """OMPL's state validity checker as a thin callable around rapp's compiled collision kernel.

    The state's angles are copied into one preallocated array and the kernel's ``collides``
    is called on it directly: no argument checks, no ``rapp.collides`` wrapper, the least
    Python a checker called from OMPL's C++ can cost. The same answers as ``rapp.collides``.
    """
    from rapp.kernels import collision as collision_backend
    from rapp.arm import MAX_ANGLE

    kernel = collision_backend.kernels()
    if kernel is None:
        raise RuntimeError("numba is not installed: no compiled checker to give OMPL")
    packed, lengths, n = collision_backend.pack(list(obstacles)), arm.lengths, arm.n
    q = np.zeros((1, n))
    row = q[0]
    collides = kernel.collides

    def valid(state):
        for i in range(n):
            row[i] = state[i].value
        return not collides(lengths, q, *packed, MAX_ANGLE)[0][0]

    return valid


def torus_setup(arm, obstacles, seed: int, valid=None):
    """A ``SimpleSetup`` on SO(2)^n for ``arm``, OMPL's random generator seeded.

    Parameters
    ----------
    arm : rapp.Arm
    obstacles : sequence of rapp obstacles
        A state is valid when ``rapp.collides(arm, q, obstacles)`` is False: OMPL and rapp
        check the very same collisions.
    seed : int
        OMPL's generator gets ``seed + 1`` (it refuses 0).
    valid : callable, optional
        The state validity checker (e.g. :func:`kernel_validity`); by default one that calls
        ``rapp.collides``.

    Returns
    -------
    ss : ompl.geometric.SimpleSetup
        Start, goal and planner are the caller's to set.
    space : ompl.base.CompoundStateSpace
    """
    from ompl import base as ob, geometric as og, util as ou

    ou.setLogLevel(ou.LOG_NONE)
    space = ob.CompoundStateSpace()
    for _ in range(arm.n):
        space.addSubspace(ob.SO2StateSpace(), 1.0)
    q = np.empty(arm.n)

    def checked(state):
        for i in range(arm.n):
            q[i] = state[i].value
        return not bool(rapp.collides(arm, q, obstacles))

    valid = checked if valid is None else valid

    ou.RNG.setSeed(seed + 1)
    ss = og.SimpleSetup(space)
    ss.setStateValidityChecker(valid)
    ss._rapp_valid = valid  # the checker lives as long as the setup, whatever the bindings keep
    return ss, space


def state(space, angles):
    """An OMPL state of ``space`` holding ``angles`` (radians), wrapped to [-π, π)."""
    s = space.allocState()
    for i, a in enumerate(angles):
        s[i].value = float(rapp.wrap_angle(a))
    return s


def path_of(ss, n: int) -> np.ndarray:
    """The solution path of ``ss`` as a ``(k, n)`` array of joint angles."""
    return np.array([[s[i].value for i in range(n)] for s in ss.getSolutionPath().getStates()])
