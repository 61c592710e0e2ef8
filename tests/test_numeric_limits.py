"""Numeric limits stated and held (issue 31, item 7): the occupancy is the collision test
everywhere it accepts, and refuses, naming the obstacle, where its closed forms would lose
their digits (an obstacle within reach that extends beyond rapp.cspace.MAX_EXTENT_RATIO times
the arm's reach). Cells within 1e-9 of the reach scale of touching are not compared: there
touching is a rounding question."""

from __future__ import annotations

import numpy as np
import pytest

import rapp
from rapp.collision import collides, link_clearances
from rapp.cspace import MAX_EXTENT_RATIO, JointGrid, certified_free, grid_q, occupancy


def _agree(arm, obstacles, cells=40):
    grid = JointGrid(arm, cells)
    q = grid_q(grid)
    occ = occupancy(arm, obstacles, grid)
    want = collides(arm, q, obstacles)
    gap = np.abs(link_clearances(arm, q, obstacles)).min(axis=-1)
    keep = gap > 1e-9 * float(np.sum(arm.lengths))
    return int((occ != want)[keep].sum())


def test_the_issues_huge_polygon_is_refused_naming_it():
    arm = rapp.Arm([1.0, 1.0])
    big = rapp.Polygon([(1.5, -1e9), (1.5 + 1e9, -1e9), (1.5 + 1e9, 1e9), (1.5, 1e9)])
    with pytest.raises(ValueError, match=r"^obstacles\[1\] reaches .*MAX_EXTENT_RATIO"):
        occupancy(arm, [rapp.Circle((0.0, 1.5), 0.2), big], JointGrid(arm, 16))
    with pytest.raises(ValueError, match=r"^obstacles\[0\]"):
        certified_free(arm, [big], JointGrid(arm, 16))


def test_an_obstacle_out_of_reach_is_left_out_whatever_its_size():
    arm = rapp.Arm([1.0, 1.0])
    far = rapp.Polygon([(1e13, 0.0), (2e13, 0.0), (2e13, 1e13), (1e13, 1e13)])
    grid = JointGrid(arm, 16)
    assert not occupancy(arm, [far], grid).any() and not collides(arm, grid_q(grid), [far]).any()


@pytest.mark.parametrize("L", [1e-3, 1.0, 1e3])
def test_occupancy_is_collides_up_to_the_stated_extent(L):
    rng = np.random.default_rng(7)
    arm = rapp.Arm([L, 0.8 * L])
    X = 0.4 * MAX_EXTENT_RATIO * 1.8 * L  # corners within the ratio times the reach
    for _ in range(4):
        a = rng.uniform(0, 2 * np.pi)
        u, c = np.array([np.cos(a), np.sin(a)]), rng.uniform(0.5, 1.5) * L
        v = np.array([-u[1], u[0]])
        p0 = c * u  # an edge passing within reach, the square reaching X away
        square = rapp.Polygon([p0 - X * v, p0 - X * v + X * u, p0 + X * v + X * u, p0 + X * v])
        disc = rapp.Circle(tuple(-(c + 0.9 * X) * v), 0.9 * X)
        assert _agree(arm, [square]) == 0
        assert _agree(arm, [disc]) == 0


@pytest.mark.parametrize("angle", [1e9, 1e10])
def test_occupancy_is_collides_for_joints_limited_near_huge_angles(angle):
    arm = rapp.Arm([1.0, 0.8], [(angle, angle + 2.0), (-angle - 2.0, -angle)])
    obstacles = [rapp.Circle((1.2, 0.6), 0.3), rapp.Polygon.rectangle((-1.5, -0.5), 0.7, 0.4, 0.3)]
    assert _agree(arm, obstacles, cells=64) == 0


def test_a_scenario_refuses_an_obstacle_beyond_the_extent_naming_it():
    with pytest.raises(rapp.errors.InvalidValue) as info:
        rapp.load_scenario({
            "arm": {"link_lengths": [1e-3, 1e-3]},
            "obstacles": [{"type": "polygon",
                           "vertices": [[0.0015, -5e3], [1e4, -5e3], [1e4, 5e3], [0.0015, 5e3]]}],
            "start": [3.0, 0.0], "goal": {"joints": [2.0, 0.0]}})
    assert info.value.field == "obstacles[0]"
