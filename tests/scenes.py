"""The scenes the tests share: the benchmarks' problem, random scenes and the dense check.

One module, imported as ``tests.scenes`` (the repository root is on the path under pytest), so
that no test reaches into another test file or into ``benchmarks/`` through ``sys.path``. The
benchmarks import their problem from here too (``benchmarks/bench_core.py``): it is defined once.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

import rapp
from rapp import Arm, Circle, JointGrid, Polygon
from rapp.collision import collides

# --- the benchmarks' problem -----------------------------------------------------------------
LINKS = [1.0, 1.0]
CIRCLES = [(1.75, 0.75, 0.6), (0.55, 1.5, 0.5), (0.0, -1.0, 0.25)]
START_Q = (0.0, 0.0)           # arm along +x, below the first circle
GOAL_Q = (np.pi / 2, 0.0)      # arm straight up, between the circles: the way round is long
LINKS3 = [1.0, 0.8, 0.5]
OBSTACLES3 = [
    Circle((1.4, 0.9), 0.35),
    Circle((-0.4, 1.5), 0.3),
    Circle((0.2, -1.3), 0.3),
    Circle((1.0, -1.0), 0.3),
    Polygon.rectangle((-1.9, -0.6), 0.5, 1.0),
]
START3, GOAL3 = (0.0, 0.0, 0.0), (-2.0, 0.5, 0.5)

coord = st.floats(-2.5, 2.5)


# --- random scenes for the occupancy: every kind of joint, obstacles where intervals are hard --
@st.composite
def interval_scenes(draw):
    n = draw(st.integers(1, 4))
    lengths = draw(st.lists(st.floats(0.2, 1.5), min_size=n, max_size=n))
    limits = []
    for _ in range(n):
        kind = draw(st.sampled_from(["free", "free", "limited", "wide"]))
        if kind == "free":
            limits.append(None)
        else:
            lo = draw(st.floats(-7.0, 3.0))
            # "wide": more than a turn, so an interval lands on the axis more than once.
            span = draw(st.floats(0.2, 3.0) if kind == "limited" else st.floats(6.0, 14.0))
            limits.append((lo, lo + span))
    arm = Arm(lengths, limits)
    top = {1: 40, 2: 18, 3: 9, 4: 6}[n]
    grid = JointGrid(arm, draw(st.lists(st.integers(2, top), min_size=n, max_size=n)))
    # Obstacles near the base or on the circle joint 1 sweeps, so that polygons and discs
    # contain the base or a joint in some cells; others anywhere (also across the -x axis,
    # where the intervals cross the +-pi seam).
    def centre():
        where = draw(st.sampled_from(["any", "base", "joint1", "seam"]))
        if where == "base":
            return (draw(st.floats(-0.3, 0.3)), draw(st.floats(-0.3, 0.3)))
        if where == "joint1":
            a = draw(st.floats(-np.pi, np.pi))
            return (lengths[0] * np.cos(a), lengths[0] * np.sin(a))
        if where == "seam":
            return (draw(st.floats(-3.0, -0.2)), draw(st.floats(-0.2, 0.2)))
        return (draw(coord), draw(coord))

    obstacles = []
    for _ in range(draw(st.integers(1, 4))):
        c = centre()
        r = draw(st.floats(0.05, 1.0))
        if draw(st.booleans()):
            obstacles.append(Circle(c, r))
        else:
            k = draw(st.integers(3, 6))
            gaps = np.array(draw(st.lists(st.floats(0.5, 1.0), min_size=k, max_size=k)))
            t = draw(st.floats(0, 6.3)) + 2 * np.pi * np.cumsum(gaps) / gaps.sum()
            obstacles.append(Polygon(np.c_[c[0] + r * np.cos(t), c[1] + r * np.sin(t)]))
    return grid, obstacles


# --- the sampling planners: scattered obstacles and an independent dense check --------------
def dense_free(arm, path, obstacles, per_rad=400):
    """Independent, slow check: sample every segment densely and test each configuration."""
    for a, b in zip(path[:-1], path[1:]):
        k = max(2, int(np.linalg.norm(b - a) * per_rad))
        q = a + np.linspace(0, 1, k)[:, None] * (b - a)
        if collides(arm, q, obstacles).any():
            return False
    return True


def scattered_obstacles(draw, reach, *, count, near, radius, side) -> list:
    """Discs and turned rectangles around the base, at ``near`` times the arm's reach."""
    obstacles = []
    for _ in range(draw(st.integers(*count))):
        r = draw(st.floats(*near)) * reach
        a = draw(st.floats(-np.pi, np.pi))
        c = (r * np.cos(a), r * np.sin(a))
        if draw(st.booleans()):
            obstacles.append(rapp.Circle(c, draw(st.floats(*radius))))
        else:
            obstacles.append(rapp.Polygon.rectangle(c, draw(st.floats(*side)), draw(st.floats(*side)), a))
    return obstacles
