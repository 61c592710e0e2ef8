"""rapp.Roadmap: a lazy PRM built once and queried many times. Every query's path is proved free
by the independent checks, what the queries learn of its edges is kept (and only true), it grows
when a query's ends are not joined, and it saves and loads back identical (bad files refused in
one line naming the field)."""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import rapp
from rapp import reference
from rapp.errors import FileNotFound, InvalidFormat, InvalidSetting, NoPathFound
from rapp.roadmap import FORMAT, VERSION, Roadmap

from tests.scenes import LINKS3, OBSTACLES3, dense_free, scattered_obstacles


@st.composite
def problems(draw):
    n = draw(st.integers(2, 3))
    limited = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    arm = rapp.Arm(draw(st.lists(st.floats(0.4, 1.0), min_size=n, max_size=n)),
                   [(-2.5, 2.5) if lim else None for lim in limited])
    reach = sum(arm.link_lengths)
    obstacles = scattered_obstacles(draw, reach, count=(1, 3), near=(0.5, 1.1),
                                    radius=(0.1, 0.3), side=(0.1, 0.4))
    ends = np.array(draw(st.lists(st.lists(st.floats(-2.4, 2.4), min_size=n, max_size=n),
                                  min_size=6, max_size=6)))
    return arm, obstacles, ends


def free_ends(arm, obstacles, ends):
    return ends[~rapp.collides(arm, ends, obstacles)]


def assert_certified(arm, res, start, goal, obstacles):
    assert np.array_equal(res.path[0], start)
    assert np.abs(arm.joint_delta(res.path[-1], goal)).max() < 1e-12
    assert reference.segment_collision_free(arm, res.path[:-1], res.path[1:], obstacles).all()
    assert dense_free(arm, res.path, obstacles)


def known(roadmap):
    """The roadmap's edges, their lengths and what is known of them."""
    return roadmap.edges.state()


@settings(max_examples=2, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(problem=problems(), seed=st.integers(0, 2**16))
def test_every_query_path_is_certified_and_what_it_learns_is_true(problem, seed):
    check_queries(problem, seed)


@pytest.mark.slow
@settings(max_examples=24, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(problem=problems(), seed=st.integers(0, 2**16))
def test_every_query_path_is_certified_and_what_it_learns_is_true_on_many(problem, seed):
    check_queries(problem, seed)


def check_queries(problem, seed):
    """Each query's path certified by the oracle; every edge the roadmap says it knows, true."""
    arm, obstacles, ends = problem
    ends = free_ends(arm, obstacles, ends)
    roadmap = Roadmap(arm, obstacles, samples=80, seed=seed, max_samples=160)
    n0 = len(roadmap.nodes)
    for a, b in zip(ends[:-1], ends[1:]):
        res = roadmap.query(a, b, raise_on_failure=False)
        if res.success:
            assert_certified(arm, res, a, b, obstacles)
        else:
            assert res.status and len(res.path) == 0
        # A query's own nodes are forgotten; the roadmap only grows by whole batches.
        assert len(roadmap.nodes) in range(n0, 161, 80)
    ij, w, done = known(roadmap)
    nodes = roadmap.nodes
    assert ij.max() < len(nodes)
    # Every edge said certified is free, every one refuted is not (the oracle's bisection).
    a, b = nodes[ij[:, 0]], nodes[ij[:, 1]]
    q1 = a + arm.joint_delta(a, b)
    if done.any():
        assert reference.segment_collision_free(arm, a[done], q1[done], obstacles).all()
    refuted = np.isinf(w)
    if refuted.any():
        assert not reference.segment_collision_free(arm, a[refuted], q1[refuted], obstacles).any()
    assert not (done & refuted).any()
    # Built for many queries, the roadmap checked every edge of its own at the build.
    assert (done | refuted).all()


def three_link():
    return rapp.Arm(LINKS3), OBSTACLES3


def test_queries_remember_their_certificates_and_repeat_their_answers():
    arm, obs = three_link()
    roadmap = Roadmap(arm, obs, samples=300, seed=2)
    first = roadmap.query((0, 0, 0), (-2, 0.5, 0.5))
    certified = known(roadmap)[2].sum()
    assert first.success and certified > 0
    again = roadmap.query((0, 0, 0), (-2, 0.5, 0.5))
    # The same path, found by the first search: every edge of it is already certified.
    assert np.array_equal(again.path, first.path) and again.iterations == 1
    assert known(roadmap)[2].sum() == certified


def test_a_roadmap_too_small_grows_until_the_query_is_answered():
    arm, obs = three_link()
    roadmap = Roadmap(arm, obs, samples=3, seed=0, max_samples=600)
    res = roadmap.query((0, 0, 0), (-2, 0.5, 0.5))
    assert res.success and len(roadmap.nodes) > 3 and len(roadmap.nodes) % 3 == 0
    assert_certified(arm, res, np.zeros(3), (-2, 0.5, 0.5), obs)


def test_a_full_roadmap_says_so():
    # One limited joint, its range cut in two by a disc: no path, whatever the samples.
    arm, obs = rapp.Arm([1.0], [(-1.0, 1.0)]), [rapp.Circle((0.8, 0.0), 0.1)]
    roadmap = Roadmap(arm, obs, samples=2, seed=0, max_samples=4)
    res = roadmap.query([-0.5], [0.5], raise_on_failure=False)
    assert not res.success and res.status == "node cap" and len(roadmap.nodes) == 4
    with pytest.raises(NoPathFound, match="max_samples 4"):
        roadmap.query([-0.5], [0.5])


def test_the_one_query_prm_keeps_its_contract():
    arm, obs = three_link()
    a = rapp.prm(arm, (0, 0, 0), (-2, 0.5, 0.5), obs, seed=3)
    b = rapp.prm(arm, (0, 0, 0), (-2, 0.5, 0.5), obs, seed=3)
    assert a.success and np.array_equal(a.path, b.path) and np.array_equal(a.parent, b.parent)
    assert np.array_equal(a.nodes[0], np.zeros(3))  # start first, then the goal, then samples
    assert_certified(arm, a, np.zeros(3), (-2, 0.5, 0.5), obs)


def test_save_and_load_give_the_same_roadmap_and_the_same_answers(tmp_path):
    arm = rapp.Arm([1.0, 0.8], [None, (-2.5, 2.5)], link_radius=0.02)
    obs = [rapp.Circle((0.0, 1.3), 0.3), rapp.Polygon(((1.2, -1.2), (1.6, -1.2), (1.6, -0.8)))]
    roadmap = Roadmap(arm, obs, samples=60, seed=4, margin=0.01, neighbours=6)
    roadmap.query((0.0, 0.0), (2.5, 0.5), raise_on_failure=False)
    path = tmp_path / "map.npz"
    roadmap.save(path)
    loaded = Roadmap.load(path)
    assert loaded.arm == arm and loaded.obstacles == obs and loaded.margin == 0.01
    assert (loaded.samples, loaded.neighbours, loaded.max_samples) == (60, 6, 1200)
    assert np.array_equal(loaded.nodes, roadmap.nodes)
    for x, y in zip(known(loaded), known(roadmap)):
        assert np.array_equal(x, y)
    # The same answers afterwards, growth (the random stream) included.
    for a, b in [((0.0, 0.0), (-2.0, 1.0)), ((3.0, 2.0), (0.1, -2.0))]:
        r1 = roadmap.query(a, b, raise_on_failure=False)
        r2 = loaded.query(a, b, raise_on_failure=False)
        assert r1.success == r2.success and np.array_equal(r1.path, r2.path)
    assert np.array_equal(loaded.nodes, roadmap.nodes)
    with pytest.raises(InvalidSetting, match="loaded from") as err:
        loaded.save(path)  # never over its input
    assert err.value.setting == "path"


def test_bad_roadmap_files_are_refused_in_one_line_naming_the_field(tmp_path):
    arm, obs = rapp.Arm([1.0, 1.0]), [rapp.Circle((0.0, 1.3), 0.3)]
    good = tmp_path / "good.npz"
    Roadmap(arm, obs, samples=20, seed=0).save(good)
    entries = dict(np.load(good))

    def written(**change):
        path = tmp_path / f"bad{len(os.listdir(tmp_path))}.npz"
        with open(path, "wb") as f:
            np.savez(f, **{k: v for k, v in {**entries, **change}.items() if v is not None})
        return path

    cases = [(written(version=np.array(VERSION + 1)), "version"),
             (written(format=np.array("something else")), "format"),
             (written(nodes=None), "nodes"),
             (written(meta=np.array("{not json")), "meta"),
             (written(ij=entries["ij"][:, ::-1].copy()), "ij"),
             (written(done=entries["done"][:-1]), "done"),
             (written(nodes=entries["nodes"][:, :1]), "nodes")]
    corrupt = tmp_path / "corrupt.npz"
    corrupt.write_bytes(good.read_bytes()[:100])
    cases.append((corrupt, "path"))
    for path, field in cases:
        with pytest.raises(InvalidFormat) as err:
            Roadmap.load(path)
        assert err.value.field == field and "\n" not in str(err.value), (field, str(err.value))
    with pytest.raises(FileNotFound):
        Roadmap.load(tmp_path / "missing.npz")
    assert str(np.load(good)["format"]) == FORMAT


def test_a_roadmap_honours_a_users_checker_and_is_not_saved(tmp_path):
    arm, obs = rapp.Arm([1.0, 1.0]), [rapp.Circle((0.0, 1.3), 0.3)]

    def elbow_down(q):
        return q[:, 1] <= 0.5  # the user's rule: the elbow never bends far up

    roadmap = Roadmap(arm, obs, samples=150, seed=1, validity=elbow_down,
                      validity_resolution=0.02)
    assert (roadmap.nodes[:, 1] <= 0.5).all()
    res = roadmap.query((0.0, 0.0), (2.5, -1.0))
    assert res.success and not res.details["certified"]
    dense = np.concatenate([np.linspace(a, b, 50) for a, b in zip(res.path[:-1], res.path[1:])])
    assert (arm.wrap(dense)[:, 1] <= 0.5 + 1e-9).all()
    with pytest.raises(InvalidSetting, match="validity"):
        roadmap.save(tmp_path / "map.npz")


@pytest.mark.slow
def test_twenty_queries_each_on_a_roadmap_built_once_on_the_benchmark_problem():
    arm, obs = three_link()
    roadmap = Roadmap(arm, obs, seed=1)
    rng = np.random.default_rng(5)
    ends = rng.uniform(-np.pi, np.pi, (200, 3))
    ends = ends[~rapp.collides(arm, ends, obs)][:21]
    for a, b in zip(ends[:-1], ends[1:]):
        res = roadmap.query(a, b)
        assert res.success
        assert_certified(arm, res, a, b, obs)


def test_the_one_query_prm_doubles_its_roadmap_up_to_max_samples():
    # No path whatever the samples (a limited joint cut in two by a disc): the roadmap grows
    # 3, 6, 12, then the 8 that reach max_samples 20 exactly, and says it is full.
    arm, obs = rapp.Arm([1.0], [(-1.0, 1.0)]), [rapp.Circle((0.8, 0.0), 0.1)]
    res = rapp.prm(arm, [-0.5], [0.5], obs, samples=3, max_samples=20, raise_on_failure=False)
    assert not res.success and res.status == "node cap" and len(res.nodes) == 2 + 20
    from rapp.prm import MAX_SAMPLES, largest_roadmap
    assert largest_roadmap(10) == MAX_SAMPLES and largest_roadmap(1000) == 20_000
