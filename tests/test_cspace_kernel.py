"""The compiled occupancy (rapp.cspace_kernel) against the numpy version and rapp.collides.

Properties: on random arms (1 to 4 links, free, limited and multi-turn joints), obstacles
(discs and convex polygons, also around the base, a joint or across the +-pi seam) and small
grids, the compiled ``occupancy`` equals ``occupancy_numpy`` and ``collides`` on every
configuration, except where a link touches an obstacle to within 1e-12 (where rounding
decides either way); painting the kernel's own intervals gives the same grid; without numba
``occupancy`` is the numpy version; importing the kernel module does not import numba.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from rapp import Arm, Circle, JointGrid, Polygon, clearance, collides, cspace
from rapp.kernels import occupancy_numba as cspace_kernel
from rapp.cspace import grid_q, occupancy, occupancy_numpy

from tests.scenes import LINKS3, OBSTACLES3, interval_scenes  # noqa: E402  defined once

pytestmark = pytest.mark.skipif(cspace_kernel.kernels() is None, reason="numba is not installed")

#: Cells where the arm touches an obstacle to within this clearance may round either way.
TOUCHING = 1e-12


def compiled(arm, obstacles, grid):
    """The kernel's occupancy whatever the grid's size (occupancy() picks it only from
    COMPILE_FROM cells or once numba is loaded)."""
    return cspace_kernel.run(cspace_kernel.kernels(),
                             cspace_kernel.levels(grid, [list(obstacles)] * arm.n)
                             ).reshape(grid.shape)


def agree_but_touching(arm, obstacles, grid, a, b):
    """a == b on every cell whose |clearance| exceeds TOUCHING; the cells that differ."""
    diff = a != b
    if diff.any():
        c = np.abs(clearance(arm, grid_q(grid)[diff], obstacles))
        assert np.all(c <= TOUCHING), (int(diff.sum()), float(c.max()))
    return int(diff.sum())


@settings(max_examples=50, deadline=None)
@given(interval_scenes())
def test_compiled_occupancy_equals_numpy_and_collides(scene):
    grid, obstacles = scene
    arm = grid.arm
    occ = compiled(arm, obstacles, grid)
    assert occ.shape == grid.shape and occ.dtype == bool
    agree_but_touching(arm, obstacles, grid, occ, occupancy_numpy(arm, obstacles, grid))
    agree_but_touching(arm, obstacles, grid, occ, collides(arm, grid_q(grid), obstacles))


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(interval_scenes())
def test_compiled_occupancy_equals_numpy_and_collides_on_many(scene):
    test_compiled_occupancy_equals_numpy_and_collides.hypothesis.inner_test(scene=scene)


@settings(max_examples=30, deadline=None)
@given(interval_scenes())
def test_painting_the_kernels_own_intervals_gives_the_same_grid(scene):
    # The benchmark's floor paints intervals computed beforehand: it must paint the same grid.
    grid, obstacles = scene
    k = cspace_kernel.kernels()
    lv = cspace_kernel.levels(grid, [obstacles] * grid.n)
    occ, kept = cspace_kernel.run(k, lv, keep=True)
    for x, (rows, starts, widths) in zip(lv, kept):
        assert rows.shape == starts.shape == widths.shape
        assert np.all(np.diff(rows) >= 0) and np.all(widths >= 0)
        assert np.all(np.bincount(rows, minlength=1) <= len(obstacles))
    assert np.array_equal(cspace_kernel.paint(k, lv, kept), occ)
    assert np.array_equal(cspace_kernel.paint(k, lv, cspace_kernel.one_per_cell(lv, kept)), occ)


@pytest.mark.slow
@settings(max_examples=100, deadline=None)
@given(interval_scenes())
def test_painting_the_kernels_own_intervals_gives_the_same_grid_on_many(scene):
    test_painting_the_kernels_own_intervals_gives_the_same_grid.hypothesis.inner_test(scene=scene)


@settings(max_examples=100, deadline=None)
@given(interval_scenes())
def test_each_levels_polygon_tolerance_is_the_numpy_versions(scene):
    # _polygon_hits' tol: 1e-12 of the largest of 1, the link, the polygon's coordinates and
    # the level's base points (the kernel skips computing the last where it cannot matter).
    grid, obstacles = scene
    polys = [ob for ob in obstacles if isinstance(ob, Polygon)]
    for i, x in enumerate(cspace_kernel.levels(grid, [obstacles] * grid.n)):
        pmax = float(np.abs(cspace.prefix_grid(grid, i)[0]).max(initial=0.0))
        want = [1e-12 * max(1.0, grid.arm.link_lengths[i], float(np.abs(p.array).max()), pmax)
                for p in polys]
        assert x.tol.tolist() == want


@settings(max_examples=60, deadline=None)
@given(interval_scenes())
def test_the_compiled_set_up_computes_numpys_numbers_to_the_bit(scene):
    # _polygons and _reaches work one element at a time; _polygon_hits (and the numpy
    # version of the set-up this replaced) on whole arrays: the same operations, bit for bit.
    grid, obstacles = scene
    polys = [ob for ob in obstacles if isinstance(ob, Polygon)]
    for x in cspace_kernel.levels(grid, [obstacles] * grid.n):
        at = 0
        for p, poly in enumerate(polys):
            v = poly.array
            e = np.roll(v, -1, axis=0) - v
            ee = np.einsum("ij,ij->i", e, e)
            rows = slice(at, at + len(v))
            at += len(v)
            assert np.array_equal(x.e[rows], e) and np.array_equal(x.ee[rows], ee)
            assert np.array_equal(x.slack[rows], x.tol[p] / np.sqrt(ee))
            assert np.array_equal(x.etol[rows], -x.tol[p] * np.sqrt(ee))
            c = v.mean(axis=0)
            assert [x.ox[-len(polys) + p], x.oy[-len(polys) + p]] == c.tolist()
            rad = np.sqrt(((v - c) ** 2).sum(axis=1).max())
            assert x.rho[-len(polys) + p] == x.L + rad + 2 * x.tol[p]
            assert x.box[p].tolist() == [v[:, 0].min(), v[:, 0].max(), v[:, 1].min(),
                                         v[:, 1].max()]
        circles = [ob for ob in obstacles if isinstance(ob, Circle)]
        assert x.rho[:len(circles)].tolist() == [x.L + ob.radius for ob in circles]


def test_the_set_up_without_numba_is_the_same_function_uncompiled(monkeypatch):
    compiled_levels = cspace_kernel._levels(JointGrid(Arm(LINKS3), 12), [OBSTACLES3] * 3)
    monkeypatch.setattr(cspace_kernel, "kernels", lambda: None)
    plain = cspace_kernel._levels(JointGrid(Arm(LINKS3), 12), [OBSTACLES3] * 3)
    for a, b in zip(compiled_levels, plain):
        for name, u, w in zip(a._fields, a, b):
            assert np.array_equal(u, w), name


def test_levels_are_cached_per_grid_and_obstacles(monkeypatch):
    # An empty cache: what other tests left in it must not evict an entry mid-test.
    monkeypatch.setattr(cspace_kernel, "_LEVELS", {})
    arm = Arm(LINKS3)
    lv = cspace_kernel.levels(JointGrid(arm, 12), [OBSTACLES3] * 3)
    assert cspace_kernel.levels(JointGrid(arm, 12), [list(OBSTACLES3)] * 3) is lv
    assert cspace_kernel.levels(JointGrid(arm, 13), [OBSTACLES3] * 3) is not lv
    # Arms are equal by value: an equal arm's grid has the same levels.
    assert cspace_kernel.levels(JointGrid(Arm(LINKS3), 12), [OBSTACLES3] * 3) is lv
    assert cspace_kernel.levels(JointGrid(Arm([1.0, 0.8, 0.6]), 12), [OBSTACLES3] * 3) is not lv
    other = cspace_kernel.levels(JointGrid(arm, 12), [OBSTACLES3[:2]] + [OBSTACLES3] * 2)
    assert other is not lv and other[0].ox.size == 2 and other[1].ox.size == 5


def test_a_call_while_the_buffers_are_in_use_gets_its_own():
    # Another thread holding the kept buffers: this call allocates fresh ones, same grid.
    arm = Arm(LINKS3)
    grid = JointGrid(arm, 24)
    whole = compiled(arm, OBSTACLES3, grid)
    with cspace_kernel._BUFFERS_LOCK:
        assert np.array_equal(compiled(arm, OBSTACLES3, grid), whole)


def test_batches_of_intervals_paint_the_same_grid(monkeypatch):
    arm = Arm(LINKS3)
    grid = JointGrid(arm, (24, 20, 16))
    whole = compiled(arm, OBSTACLES3, grid)
    for batch in (7, 2):   # several batches per level; fewer than one row's obstacles
        monkeypatch.setattr(cspace_kernel, "BATCH", batch)
        assert np.array_equal(compiled(arm, OBSTACLES3, grid), whole)


def test_the_3link_benchmark_grid_matches_numpy_and_collides():
    arm = Arm(LINKS3)
    grid = JointGrid(arm, (40, 36, 32))
    occ = occupancy(arm, OBSTACLES3, grid)   # 46,080 cells: compiled once numba is loaded
    assert np.array_equal(occ, compiled(arm, OBSTACLES3, grid))
    assert agree_but_touching(arm, OBSTACLES3, grid, occ,
                              occupancy_numpy(arm, OBSTACLES3, grid)) == 0
    agree_but_touching(arm, OBSTACLES3, grid, occ, collides(arm, grid_q(grid), OBSTACLES3))
    assert 0.1 < occ.mean() < 0.5


@pytest.mark.parametrize("M", [100, 360])
def test_2link_grids_match_numpy(M):
    arm = Arm([1.0, 1.0])
    obs = [Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25)]
    grid = JointGrid(arm, M)
    assert np.array_equal(compiled(arm, obs, grid), occupancy_numpy(arm, obs, grid))


def test_no_obstacles_and_the_base_inside_one():
    arm = Arm([1.0, 0.5])
    grid = JointGrid(arm, 16)
    assert not compiled(arm, [Circle((5.0, 5.0), 0.1)], grid).any()
    assert not occupancy(arm, [], grid).any()
    for ob in (Circle((0.0, 0.0), 0.2), Polygon.rectangle((-0.1, -0.1), 0.2, 0.2)):
        assert compiled(arm, [ob], grid).all()


def test_without_numba_occupancy_is_the_numpy_version(monkeypatch):
    arm = Arm(LINKS3)
    grid = JointGrid(arm, 48)   # above COMPILE_FROM: the kernel would be used
    assert grid.shape[0] ** 3 >= cspace.COMPILE_FROM
    monkeypatch.setattr(cspace_kernel, "kernels", lambda: None)
    assert np.array_equal(occupancy(arm, OBSTACLES3, grid), occupancy_numpy(arm, OBSTACLES3, grid))


def test_importing_the_kernel_or_a_small_grid_does_not_import_numba():
    code = ("import sys, rapp, rapp.kernels.occupancy_numba\n"
            "arm = rapp.Arm([1.0, 1.0])\n"
            "rapp.occupancy(arm, [rapp.Circle((1.5, 0.0), 0.3)], rapp.JointGrid(arm, 64))\n"
            "print('numba' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_pack_keeps_the_polygons_geometry():
    circles, polys = cspace_kernel.pack([Polygon.rectangle((0, 0), 2, 1), Circle((3, 0), 0.5),
                                         Polygon([(0, 0), (1, 0), (0, 1)])])
    assert circles.tolist() == [[3.0, 0.0, 0.5]]
    assert polys.offsets.tolist() == [0, 4, 7]
    assert np.allclose(polys.norm ** 2, polys.ee)
    assert np.allclose(polys.e[:4].sum(axis=0), 0) and np.allclose(polys.e[4:].sum(axis=0), 0)
    assert np.allclose(polys.radius, [np.hypot(1.0, 0.5), np.hypot(2 / 3, 1 / 3)])


@settings(max_examples=20, deadline=None)
@given(interval_scenes())
def test_compiled_certified_free_equals_numpy(scene):
    # certified_free paints each link against the obstacles grown for it: the same kernel.
    grid, obstacles = scene
    arm = grid.arm
    fast = cspace.certified_free(arm, obstacles, grid)     # numba is loaded: compiled
    monkey = cspace_kernel.kernels
    try:
        cspace_kernel.kernels = lambda: None
        slow = cspace.certified_free(arm, obstacles, grid)
    finally:
        cspace_kernel.kernels = monkey
    diff = fast != slow
    if diff.any():   # only where a link's clearance is the certificate's margin, to rounding
        from rapp.collision import link_clearances, motion_bounds
        need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)
        c = link_clearances(arm, grid_q(grid)[diff], obstacles) - need
        assert np.all(np.abs(c).min(axis=-1) <= TOUCHING)


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(interval_scenes())
def test_compiled_certified_free_equals_numpy_on_many(scene):
    test_compiled_certified_free_equals_numpy.hypothesis.inner_test(scene=scene)


@settings(max_examples=60, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(0.0, 3.0), st.floats(0.0, 2.0),
       st.floats(-7.0, 7.0), st.sampled_from([None, (-1.0, 2.0), (-5.0, 6.0), (0.3, 0.31)]),
       st.integers(2, 3000), st.floats(-1e-9, 1e-9), st.integers(0, 1))
def test_the_arc_of_rows_holds_every_row_the_exact_test_accepts(dx, dy, rho, Lp, phi, limits,
                                                               m, nudge, at_the_edge):
    # _collect visits only the rows of _arc; a row it leaves out must fail the exact test.
    cspace_kernel.kernels()
    arc = cspace_kernel._arc
    if at_the_edge:   # the obstacle's reach just touching the circle of base points
        rho = abs(math.hypot(dx, dy) - Lp) * (1 + nudge)
    arm = Arm([1.0], [limits])
    ax = JointGrid(arm, m).axes[0]
    step, periods = float(JointGrid(arm, m).step[0]), cspace_kernel._periods(ax)
    cp, sp = math.cos(phi), math.sin(phi)
    c = cp * np.cos(ax) - sp * np.sin(ax)
    s = sp * np.cos(ax) + cp * np.sin(ax)
    px, py = Lp * c, Lp * s   # the parent point at the origin, the centre at (dx, dy)
    accepted = (dx - px) ** 2 + (dy - py) ** 2 <= rho * rho * (1.0 + 1e-9)
    for j0, j1 in ((0, m), (m // 3, m - m // 4)):
        spans = np.empty((max(min(periods, m), 1), 2), dtype=np.int64)
        # The parent cell at the origin, its link Lp, the obstacle's centre and reach.
        level = cspace_kernel.Level(
            Pp=np.zeros((1, 2)), phip=np.array([phi]), cp=np.ones(1), sp=np.zeros(1), axp=ax,
            cap=np.cos(ax), sap=np.sin(ax), stepp=step, periodsp=periods, Lp=float(Lp), L=1.0,
            circles=np.zeros((0, 3)), v=np.zeros((0, 2)), e=np.zeros((0, 2)), ee=np.zeros(0),
            offsets=np.zeros(1, dtype=np.int64), slack=np.zeros(0), etol=np.zeros(0),
            tol=np.zeros(0), box=np.zeros((0, 4)), ox=np.array([dx]), oy=np.array([dy]),
            rho=np.array([rho]), ax=ax, step=step, periods=periods)
        ns = arc(0, 0, level, j0, j1, spans, abs(ax[0]) + abs(ax[-1]))
        visited = np.zeros(m, dtype=int)
        for a, b in spans[:ns]:
            assert j0 <= a < b <= j1
            visited[a:b] += 1
        assert visited.max(initial=0) <= 1        # no row twice: no interval collected twice
        want = accepted.copy()
        want[:j0] = want[j1:] = False
        assert np.all(visited[want] == 1), np.flatnonzero(want & (visited == 0))


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(0.0, 3.0), st.floats(0.0, 2.0),
       st.floats(-7.0, 7.0), st.sampled_from([None, (-1.0, 2.0), (-5.0, 6.0), (0.3, 0.31)]),
       st.integers(2, 3000), st.floats(-1e-9, 1e-9), st.integers(0, 1))
def test_the_arc_of_rows_holds_every_row_the_exact_test_accepts_on_many(dx, dy, rho, Lp, phi, limits, m, nudge, at_the_edge):
    test_the_arc_of_rows_holds_every_row_the_exact_test_accepts.hypothesis.inner_test(dx=dx, dy=dy, rho=rho, Lp=Lp, phi=phi, limits=limits, m=m, nudge=nudge, at_the_edge=at_the_edge)


@pytest.mark.parametrize("lo", [2e9, 1e12, 1e14])
def test_joints_limited_far_from_zero_get_the_numpy_grid(lo):
    # Found by review: at such angles a cell's angle is rounded by more than the arc's fixed
    # margins, and rows that collide were left out; the margins now grow with the angles.
    arm = Arm([1.0, 1.0], [(lo, lo + 0.01), None])
    grid = JointGrid(arm, (12, 8))
    rng = np.random.default_rng(int(np.log10(lo)))
    scenes = [[Circle((-1.2751179023996746, 1.244894013170779), 0.5)]]   # the review's case
    scenes += [[Circle(tuple(rng.uniform(-2, 2, 2)), float(rng.uniform(0.1, 0.6)))]
               for _ in range(40)]
    for obs in scenes:
        agree_but_touching(arm, obs, grid, compiled(arm, obs, grid),
                           occupancy_numpy(arm, obs, grid))


@pytest.mark.parametrize("span", [1e10, 1e19, 1e30])
def test_a_joint_of_very_many_turns_is_painted_without_a_huge_allocation(span):
    # Found by review: a buffer of one row per 2 pi piece of the parent's axis (1e10 / 2 pi
    # of them) was allocated; the number of pieces overflowed an int64 beyond 1e19.
    arm = Arm([1.0, 1.0], [(-span, span), None])
    grid = JointGrid(arm, (300, 300))
    obs = [Circle((1.2, 0.4), 0.3), Polygon.rectangle((-1.5, -0.5), 0.4, 0.8)]
    agree_but_touching(arm, obs, grid, compiled(arm, obs, grid), occupancy_numpy(arm, obs, grid))
