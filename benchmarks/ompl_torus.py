"""OMPL asked rapp's question: plan on the torus SO(2)^n, valid where ``rapp.collides`` says free.

Shared by ``bench_planners.py`` and ``compare_planners.py``, so both benchmarks pose OMPL the
same problem in one place. OMPL comes from ``benchmarks/requirements.txt``; importing this module
does not import it, calling :func:`torus_setup` does.
"""

from __future__ import annotations

import numpy as np

import rapp


def torus_setup(arm, obstacles, seed: int):
    """A ``SimpleSetup`` on SO(2)^n for ``arm``, OMPL's random generator seeded.

    Parameters
    ----------
    arm : rapp.Arm
    obstacles : sequence of rapp obstacles
        A state is valid when ``rapp.collides(arm, q, obstacles)`` is False: OMPL and rapp
        check the very same collisions.
    seed : int
        OMPL's generator gets ``seed + 1`` (it refuses 0).

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

    def valid(state):
        for i in range(arm.n):
            q[i] = state[i].value
        return not bool(rapp.collides(arm, q, obstacles))

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
