"""rapp.plotting: every figure draws headless, shows the data it was given, and stays readable.

The checks read the artists back (line data, patch geometry, image extent
and pixels) and compare them with what the model computes, so a figure that
draws the wrong thing fails, not only one that crashes.
"""

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg", force=True)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import assume, given, settings, strategies as st  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402
from PIL import Image  # noqa: E402

from rapp import Arm, Circle, Polygon  # noqa: E402
from rapp import plotting as P  # noqa: E402
from rapp.cspace import JointGrid, occupancy  # noqa: E402

WHITE = (1.0, 1.0, 1.0, 1.0)
ARM = Arm([1.0, 1.0])
OBSTACLES = (Circle((1.2, 0.9), 0.35), Polygon.rectangle((-1.6, -1.2), 0.5, 0.4, 0.3))


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def dark(color):
    """Perceived luminance below one third: dark enough on white."""
    r, g, b, _ = to_rgba(color)
    return 0.2126 * r + 0.7152 * g + 0.0722 * b < 1 / 3


def assert_readable(ax):
    """White figure and axes, dark labels, title and tick labels."""
    assert to_rgba(ax.figure.get_facecolor()) == WHITE
    assert to_rgba(ax.get_facecolor()) == WHITE
    for text in [ax.xaxis.label, ax.yaxis.label, ax.title]:
        if text.get_text():
            assert dark(text.get_color()), text.get_text()
    for tick in ax.get_xticklabels() + ax.get_yticklabels():
        assert dark(tick.get_color())


def fake_plan(arm, obstacles, cells=24, k=50):
    """The fields of rapp.Plan that plotting reads, from a straight joint-space move."""
    grid = JointGrid(arm, cells)
    t = np.linspace(0.0, 4.0, k)
    q = np.linspace([2.6, -0.4] + [0.2] * (arm.n - 2), [4.0, 1.0] + [0.5] * (arm.n - 2), k)
    qd = np.gradient(q, t, axis=0)
    return SimpleNamespace(t=t, q=q, qd=qd, qdd=np.gradient(qd, t, axis=0),
                           xy=arm.end_effector(q), grid=grid,
                           occupancy=occupancy(arm, obstacles, grid),
                           metrics={"time_cspace_s": 0.03, "time_search_s": 0.01,
                                    "time_trajectory_s": 0.002, "path_length": 2.1})


def scenario_of(arm, obstacles, goal_xy=None):
    return SimpleNamespace(arm=arm, obstacles=obstacles, start=(2.6, -0.4), goal_q=None,
                           goal_xy=goal_xy)


# ----------------------------------------------------------------------------- style


def test_style_survives_a_dark_matplotlib_style():
    plan = fake_plan(ARM, OBSTACLES)
    with plt.style.context("dark_background"):
        fig = P.plot_plan(plan, scenario_of(ARM, OBSTACLES, goal_xy=(-1.0, 0.5)))
        prof = P.plot_profiles(plan)
    for ax in fig.axes + prof.axes:
        assert_readable(ax)
        legend = ax.get_legend()
        assert legend is not None
        assert to_rgba(legend.get_frame().get_facecolor())[:3] == (1.0, 1.0, 1.0)
        assert all(dark(t.get_color()) for t in legend.get_texts())


def test_palette_is_distinct_and_visible_on_white():
    colors = np.array([to_rgba(c)[:3] for c in P.JOINT_COLORS])
    d = np.linalg.norm(colors[:, None] - colors[None], axis=-1)
    assert d[~np.eye(len(colors), dtype=bool)].min() > 0.2
    assert all(not np.allclose(c, 1.0) for c in colors)


# ----------------------------------------------------------------------------- arm, obstacles


@pytest.mark.slow
@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.2, 3.0), min_size=1, max_size=4).flatmap(
    lambda L: st.tuples(st.just(L), st.lists(st.floats(-4, 4), min_size=len(L), max_size=len(L)))))
def test_plot_arm_draws_forward_kinematics(case):
    lengths, q = case
    arm = Arm(lengths)
    fig, ax = plt.subplots()
    assert P.plot_arm(arm, q, ax) is ax
    links, base, tip = ax.lines
    np.testing.assert_allclose(links.get_xydata(), arm.joint_positions(q))
    np.testing.assert_allclose(base.get_xydata(), [[0.0, 0.0]])
    np.testing.assert_allclose(tip.get_xydata(), [arm.end_effector(q)])
    assert ax.get_aspect() == 1.0
    assert ax.get_xlim()[1] >= arm.reach[1] and ax.get_ylim()[0] <= -arm.reach[1]
    assert "(m)" in ax.get_xlabel() and "(m)" in ax.get_ylabel()
    assert_readable(ax)
    plt.close(fig)


def test_plot_arm_ghosts_one_collection_fading_in():
    q = np.linspace([0.0, 0.0], [2.0, 1.0], 5)
    ax = P.plot_arm(ARM, q)
    (coll,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    segs = coll.get_segments()
    assert len(segs) == 5
    np.testing.assert_allclose(np.array(segs), ARM.joint_positions(q))
    alpha = coll.get_colors()[:, 3]
    assert np.all(np.diff(alpha) > 0)
    with pytest.raises(ValueError):
        P.plot_arm(ARM, np.zeros((2, 2, 2)))


def test_plot_obstacles_one_patch_each_with_their_geometry():
    ax = P.plot_obstacles(OBSTACLES)
    circle, poly = ax.patches
    assert circle.center == OBSTACLES[0].center and circle.radius == OBSTACLES[0].radius
    np.testing.assert_allclose(poly.get_xy()[:4], OBSTACLES[1].array)
    # Patches are filled and their containment agrees with the model's.
    pts = np.random.default_rng(0).uniform(-2, 2, (300, 2))
    for patch, ob in zip(ax.patches, OBSTACLES):
        disp = ax.transData.transform(pts)
        drawn = np.array([patch.contains_point(p) for p in disp])
        model = ob.contains(pts)
        assert (drawn == model).mean() > 0.97  # differ only on the anti-aliased rim
    assert_readable(ax)


@pytest.mark.parametrize("lengths", [[2.0, 1.0], [1.0, 1.0], [1.0, 0.5, 0.3]])
def test_plot_workspace_shades_exactly_the_annulus(lengths):
    arm = Arm(lengths)
    r_min, r_max = arm.reach
    ax = P.plot_workspace(arm)
    assert len(ax.patches) == 1
    assert len(ax.lines) == (2 if r_min > 0 else 1)
    radii = sorted(np.linalg.norm(line.get_xydata(), axis=1).mean() for line in ax.lines)
    np.testing.assert_allclose(radii, [r for r in (r_min, r_max) if r > 0])
    # What the reader sees: pixels tinted blue exactly inside the annulus.
    ax.grid(False)
    fig = ax.figure
    fig.set_dpi(100)
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3] / 255.0
    rng = np.random.default_rng(1)
    r = rng.uniform(0, 1.05 * r_max, 400)
    th = rng.uniform(0, 2 * np.pi, 400)
    pts = np.stack((r * np.cos(th), r * np.sin(th)), axis=-1)
    keep = (np.abs(r - r_min) > 0.03 * r_max) & (np.abs(r - r_max) > 0.03 * r_max)
    px = ax.transData.transform(pts)
    col = rgb[(rgb.shape[0] - px[:, 1]).astype(int), px[:, 0].astype(int)]
    tinted = col[:, 2] - col[:, 0] > 0.05
    np.testing.assert_array_equal(tinted[keep], ((r >= r_min) & (r <= r_max))[keep])
    assert ax.get_aspect() == 1.0


# ----------------------------------------------------------------------------- C-space


@pytest.mark.parametrize("limits", [None, [None, (-2.0, 1.5)], [(-1.0, 2.0), (-2.5, 2.5)]])
def test_plot_cspace_image_is_the_grid(limits):
    arm = Arm([1.0, 1.0], limits)
    grid = JointGrid(arm, (30, 20))
    occ = occupancy(arm, OBSTACLES, grid)
    ax = P.plot_cspace(occ, grid)
    (im,) = ax.images
    np.testing.assert_array_equal(im.get_array(), occ.T.astype(float))
    assert im.origin == "lower"
    x0, x1, y0, y1 = im.get_extent()
    for (lo, hi), axis, m in (((x0, x1), grid.axes[0], 30), ((y0, y1), grid.axes[1], 20)):
        centres = lo + (np.arange(m) + 0.5) * (hi - lo) / m
        np.testing.assert_allclose(centres, axis, atol=1e-12)
    assert ax.get_xlabel() == "θ1 (rad)" and ax.get_ylabel() == "θ2 (rad)"
    assert_readable(ax)


def drawn_segments(line):
    xy = line.get_xydata()
    seg = np.stack((xy[:-1], xy[1:]), axis=1)
    return seg[~np.isnan(seg).any(axis=(1, 2))]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(-1.2, 1.2), st.floats(-1.2, 1.2)), min_size=2, max_size=40),
       st.tuples(st.floats(-10, 10), st.floats(-10, 10)))
def test_seam_split_no_jump_across_the_plot(steps, q0):
    """A torus walk drawn in [-pi, pi)^2 has no segment longer than half the span, and
    still visits every (wrapped) sample, breaking once per seam crossing."""
    q = np.asarray(q0) + np.concatenate([[[0.0, 0.0]], np.cumsum(steps, axis=0)])
    lo, span = np.full(2, -np.pi), np.full(2, 2 * np.pi)
    p = P.split_at_seam(q, lo, span, [True, True])
    seg = np.stack((p[:-1], p[1:]), axis=1)
    seg = seg[~np.isnan(seg).any(axis=(1, 2))]
    assert np.abs(seg[:, 1] - seg[:, 0]).max() <= np.pi + 1e-9
    wrapped = (q - lo) % span + lo
    finite = p[~np.isnan(p).any(axis=1)]
    for w in wrapped:
        assert np.isclose(finite, w, atol=1e-9).all(axis=1).any()
    crossings = np.any(np.abs(np.diff(np.floor((q - lo) / span), axis=0)) > 0, axis=1).sum()
    assert np.isnan(p[:, 0]).sum() == crossings
    # Each drawn piece moves by the true (unwrapped) steps: nothing is bent.
    pieces = np.split(p, np.flatnonzero(np.isnan(p[:, 0])))
    total = sum(np.abs(np.diff(x[~np.isnan(x[:, 0])], axis=0)).sum(axis=0) for x in pieces)
    d = np.diff(q, axis=0)
    short = np.abs((d + np.pi) % (2 * np.pi) - np.pi).sum(axis=0)
    assert np.all(total >= short - 1e-9)


def test_seam_split_leaves_bounded_axis_alone():
    q = np.array([[3.0, -2.0], [-3.0, 2.0]])
    p = P.split_at_seam(q, [-np.pi, -2.5], [2 * np.pi, 5.0], [True, False])
    assert np.isnan(p).any()  # q1 wraps: a break
    p = P.split_at_seam(q, [-np.pi, -2.5], [2 * np.pi, 5.0], [False, False])
    np.testing.assert_array_equal(p, q)  # neither wraps: the line is drawn as given


def test_plot_cspace_path_across_seam_in_the_axes():
    grid = JointGrid(ARM, 16)
    q = np.linspace([2.5, 0.0], [4.0, 0.5], 30)  # crosses q1 = pi
    ax = P.plot_cspace(np.zeros(grid.shape, bool), grid, path=q, start=q[0], goal=q[-1])
    path = ax.lines[0]
    seg = drawn_segments(path)
    span = np.diff(ax.get_xlim())[0]
    assert np.abs(seg[:, 1] - seg[:, 0]).max() < span / 2
    assert np.isnan(path.get_xydata()).any()
    np.testing.assert_allclose(ax.lines[1].get_xydata()[0], q[0])
    np.testing.assert_allclose(ax.lines[2].get_xydata()[0], [4.0 - 2 * np.pi, 0.5])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path", "start", "goal"]


def test_plot_cspace_three_joints_projects_and_says_so():
    arm = Arm([1.0, 0.8, 0.5])
    grid = JointGrid(arm, (12, 10, 6))
    occ = occupancy(arm, OBSTACLES, grid)
    ax = P.plot_cspace(occ, grid)
    np.testing.assert_allclose(ax.images[0].get_array(), occ.mean(axis=2).T)
    assert "projection over θ3" in ax.get_title()
    with pytest.raises(ValueError):
        P.plot_cspace(np.zeros(5, bool), grid)


# ----------------------------------------------------------------------------- plan


def test_plot_plan_shows_the_plan_in_both_spaces():
    plan = fake_plan(ARM, OBSTACLES)
    fig = P.plot_plan(plan, scenario_of(ARM, OBSTACLES, goal_xy=(-1.0, 0.5)))
    ax_c, ax_w = fig.axes
    assert len(ax_c.images) == 1 and len(ax_w.images) == 0
    traces = [ln for ln in ax_w.lines if ln.get_label() == "end-effector path"]
    np.testing.assert_allclose(traces[0].get_xydata(), plan.xy)
    ghosts = [c for c in ax_w.collections if isinstance(c, LineCollection)][0]
    assert 1 <= len(ghosts.get_segments()) <= 6
    # Obstacles plus the workspace annulus.
    assert len(ax_w.patches) == len(OBSTACLES) + 1
    final = [ln for ln in ax_w.lines if ln.get_label() == "final"][0]
    np.testing.assert_allclose(final.get_xydata(), ARM.joint_positions(plan.q[-1]))
    assert ax_w.get_aspect() == 1.0


def test_plot_plan_without_grid_draws_joint_path():
    plan = fake_plan(ARM, OBSTACLES)
    plan.grid = plan.occupancy = None
    fig = P.plot_plan(plan, scenario_of(ARM, OBSTACLES))
    ax_c = fig.axes[0]
    assert not ax_c.images
    assert np.isnan(ax_c.lines[0].get_xydata()).any()  # the straight move crosses q1 = pi


def test_plot_profiles_draws_every_joint_and_xy():
    arm = Arm([1.0, 0.8, 0.5])
    plan = fake_plan(arm, OBSTACLES, cells=(8, 8, 4))
    fig = P.plot_profiles(plan)
    assert [len(ax.lines) for ax in fig.axes] == [3, 3, 3, 2]
    for ax, values in zip(fig.axes, (plan.q, plan.qd, plan.qdd)):
        for j, line in enumerate(ax.lines):
            np.testing.assert_allclose(line.get_xydata(), np.stack((plan.t, values[:, j]), 1))
    np.testing.assert_allclose(fig.axes[3].lines[1].get_ydata(), plan.xy[:, 1])
    assert fig.axes[3].get_xlabel() == "t (s)"
    assert [ax.get_ylabel() for ax in fig.axes] == ["θ (rad)", "θ' (rad/s)", "θ'' (rad/s²)",
                                                     "x, y (m)"]


def test_plot_metrics_bars_are_the_stage_times():
    m = fake_plan(ARM, OBSTACLES).metrics
    ax = P.plot_metrics(m)
    widths = [b.get_width() for b in ax.patches]
    np.testing.assert_allclose(widths, [30.0, 10.0, 2.0])  # ms; path_length is not a time
    labels = [t.get_text() for t in ax.texts]
    assert labels == ["30 ms", "10 ms", "2 ms"]
    ax = P.plot_metrics({"stage_times": {"ik": 0.5, "search": 1.5, "total": 2.0}, "nodes": 99})
    assert [t.get_text() for t in ax.get_yticklabels()] == ["ik", "search"]
    assert ax.get_title() == "time per stage (total 2000 ms)"
    with pytest.raises(ValueError, match="no stage times"):
        P.plot_metrics({"path_length": 1.0})


@settings(max_examples=25, deadline=None)
@given(st.tuples(*[st.floats(-2, 2)] * 6), st.floats(0.05, 1.0))
def test_plot_segment_circle_marks_the_closest_point(abc, r):
    a, b, c = np.array(abc[:2]), np.array(abc[2:4]), np.array(abc[4:])
    fig, ax = plt.subplots()
    P.plot_segment_circle(a, b, c, r, ax)
    near = ax.lines[2].get_xydata()[0]
    s = np.linspace(0, 1, 2001)[:, None]
    brute = np.linalg.norm(a + s * (b - a) - c, axis=1).min()
    assert np.linalg.norm(near - c) <= brute + 1e-9
    foot = ax.lines[3].get_xydata()[0]
    if np.linalg.norm(b - a) > 1e-6:
        assert abs(np.dot(foot - c, b - a)) < 1e-6 * max(1, np.linalg.norm(b - a))
    plt.close(fig)


def test_plot_polynomials_velocity_is_the_slope():
    fig = P.plot_polynomials({"cubic": [0.0, 0.0, 0.75, -0.25]}, 0.0, 2.0)
    p, v, a = (ax.lines[0] for ax in fig.axes)
    t = p.get_xdata()
    inner = slice(1, -1)  # central differences only
    np.testing.assert_allclose(np.gradient(p.get_ydata(), t)[inner], v.get_ydata()[inner], atol=1e-3)
    np.testing.assert_allclose(np.gradient(v.get_ydata(), t)[inner], a.get_ydata()[inner], atol=1e-3)


# ----------------------------------------------------------------------------- animation


def test_animate_subsamples_and_moves_the_arm(tmp_path):
    q = np.stack([np.linspace(0, 2 * np.pi, 500), np.sin(np.linspace(0, 3, 500))], -1)
    t = np.linspace(0, 5, 500)
    anim = P.animate(ARM, q, OBSTACLES, t=t)
    assert anim._save_count == 60
    np.testing.assert_allclose(anim._interval, 5000 / 59)  # real time
    ax = anim._fig.axes[0]
    links = ax.lines[-4]
    anim._func(59)
    np.testing.assert_allclose(links.get_xydata(), ARM.joint_positions(q[-1]))
    assert ax.get_title() == "t = 5.00 s"
    trace = ax.lines[-1]
    assert len(trace.get_xydata()) == 60
    assert_readable(ax)
    short = P.animate(ARM, q[:7], trail=False)
    assert short._save_count == 7


def test_save_gif_writes_every_frame(tmp_path):
    q = np.linspace([0.0, 0.0], [np.pi, 1.0], 5)
    anim = P.animate(ARM, q, OBSTACLES, ax=plt.subplots(figsize=(2, 2))[1])
    path = P.save_gif(anim, tmp_path / "arm.gif", fps=10, dpi=40)
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 5
        assert im.info["duration"] == 100


def test_animation_html_has_controls_and_closes_the_figure():
    q = np.linspace([0.0, 0.0], [np.pi, 1.0], 4)
    fig, ax = plt.subplots(figsize=(2, 2), dpi=40)
    anim = P.animate(ARM, q, ax=ax)
    html = P.animation_html(anim)
    assert not plt.fignum_exists(fig.number)
    assert 'class="anim-controls"' in html and 'class="anim-slider"' in html
    assert html.count("data:image/png;base64") == 4


def test_workspace_frame_holds_obstacles_beyond_the_reach():
    arm = Arm([1.0, 1.0])
    far = [Circle((1.75, 0.75), 0.6), Polygon.rectangle((-3.0, -0.2), 0.4, 0.4)]
    ax = P.plot_obstacles(far, plt.subplots()[1])
    P.plot_arm(arm, [0.0, 0.0], ax)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x1 >= 1.75 + 0.6 and x0 <= -3.0 and (x0, x1) == (y0, y1) == (-x1, x1)
    plt.close(ax.figure)


@pytest.mark.slow
@settings(max_examples=12, deadline=None)
@given(width=st.floats(2.0, 16.0), height=st.floats(1.5, 6.0), size=st.floats(6.0, 14.0))
def test_book_png_fits_the_column_and_records_its_smallest_text(width, height, size):
    import io

    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100)
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1])
    ax.set_title("title", fontsize=size + 2)
    ax.tick_params(labelsize=size)
    img = Image.open(io.BytesIO(P.book_png(fig)))
    # Tight bounding box: at most the column plus the labels that stick out of the figure.
    assert img.width <= 100 * P.BOOK_WIDTH_IN + 40
    assert float(img.info["rapp:text-px"]) == pytest.approx(size * 100 / 72, abs=0.01)
    assert img.info["rapp:dpi"] == "100"


def test_book_style_is_the_one_figure_style():
    with matplotlib.rc_context():
        P.book_style()
        fig, ax = plt.subplots()
        ax.plot([0, 1])
        fig.canvas.draw()
        # The smallest text (ticks) is 10 pt: at 100 dpi and the column's width, >= 10 CSS px.
        assert P.smallest_text_px(fig) == pytest.approx(10 * 100 / 72, abs=0.01)  # "small" of 12 pt
        assert fig.get_size_inches()[0] <= P.BOOK_WIDTH_IN and fig.get_facecolor() == WHITE
        plt.close(fig)


def test_legend_outside_lists_drawn_and_extra_handles_beyond_the_axes():
    from matplotlib.patches import Patch
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], label="path")
    P.legend_outside(ax, [Patch(color="0.3", label="obstacle")])
    legend = ax.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["path", "obstacle"]
    fig.canvas.draw()
    box = legend.get_window_extent()
    assert box.x0 >= ax.get_window_extent().x1   # to the right of the axes: it covers nothing
    assert_readable(ax)


@given(st.lists(st.tuples(st.floats(0.01, 1000.0), st.sampled_from([None, 0.5, 1.0, 3.0])),
                min_size=1, max_size=8))
@settings(max_examples=15, deadline=None)
def test_plot_ratios_draws_each_ratio_coloured_by_its_verdict(rows):
    ratios, goals = [r for r, _ in rows], [g for _, g in rows]
    ax = P.plot_ratios([f"case {i}" for i in range(len(rows))], ratios, goals)
    bars = [p for p in ax.patches]
    assert len(bars) == len(rows)
    colour = {True: to_rgba(P.COLORS["blue"]), False: to_rgba(P.COLORS["vermillion"]), None: to_rgba("#999999")}
    for bar, k, goal in zip(bars, ratios, goals):
        assert bar.get_x() == 1 and np.isclose(bar.get_x() + bar.get_width(), k)
        assert bar.get_facecolor() == colour[None if goal is None else k >= goal]
    ticks = [line for line in ax.lines if line.get_linewidth() == 2.5 and len(line.get_xdata()) == 2
             and line.get_xdata()[0] == line.get_xdata()[1]]
    assert sorted(t.get_xdata()[0] for t in ticks) == sorted(g for g in goals if g is not None)
    assert [t.get_text() for t in ax.get_yticklabels()][0] == "case 0"  # the first row on top
    assert_readable(ax)
    plt.close(ax.figure)


@given(st.lists(st.tuples(st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi)), min_size=2, max_size=12),
       st.data())
@settings(max_examples=10, deadline=None)
def test_plot_tree_draws_every_edge_the_short_way_and_seam_edges_twice(points, data):
    nodes = np.array(points)
    parent = np.array([-1] + [data.draw(st.integers(0, i - 1)) for i in range(1, len(nodes))])
    ax = P.plot_tree(ARM, nodes, parent)
    segments = [np.asarray(s) for s in ax.collections[0].get_segments()]
    d = ARM.joint_delta(nodes[parent[1:]], nodes[1:])
    crossing = np.abs(nodes[parent[1:]] + d - nodes[1:]).max(axis=1) > 1e-9
    assert len(segments) == len(nodes) - 1 + crossing.sum()
    for seg in segments:   # each drawn segment is one edge, the short way round
        step = seg[1] - seg[0]
        assert np.abs(step).max() <= np.pi + 1e-9
        assert any(np.allclose(step, di) for di in d)
    assert_readable(ax)
    plt.close(ax.figure)


@given(st.integers(0, 2**32 - 1))
@settings(max_examples=8, deadline=None)
def test_plot_f_contours_prints_g_star_plus_h_on_every_reachable_cell(seed):
    from rapp.search import astar_search, bfs_distances, toroidal_manhattan
    rng = np.random.default_rng(seed)
    occ = rng.random((7, 6)) < 0.25
    free = np.argwhere(~occ)
    start, goal = (tuple(int(v) for v in free[i]) for i in rng.choice(len(free), 2, replace=False))
    assume(bfs_distances(occ, start)[goal] >= 0)   # astar_search raises where no path exists
    r = astar_search(occ, start, goal)
    ax = P.plot_f_contours(occ, start, goal, closed=r.closed if r.path is not None else None)
    shown = {(round(t.get_position()[0]), round(t.get_position()[1])): int(t.get_text()) for t in ax.texts}
    g = bfs_distances(occ, start)   # the oracle: BFS, one cell at a time
    want = {(i, j): int(g[i, j] + toroidal_manhattan((i, j), goal, occ.shape))
            for i, j in np.argwhere(g >= 0)}
    assert shown == want
    if r.path is not None:   # A* expands no cell of f above the optimum (consistent GD1)
        assert max(want[tuple(c)] for c in np.argwhere(r.closed)) <= g[goal]
    plt.close(ax.figure)


@given(st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi))
@settings(max_examples=10, deadline=None)
def test_plot_link_clearances_labels_each_link_with_its_clearance(t1, t2):
    from rapp.collision import link_clearances
    discs = [Circle((1.2, 0.9), 0.2), Circle((-1.0, -1.1), 0.3)]
    q = np.array([t1, t2])
    if (link_clearances(ARM, q, discs) <= 0).any():
        return   # a link inside a disc has no gap to draw
    ax = P.plot_link_clearances(ARM, q, discs)
    want = link_clearances(ARM, q, discs)   # the package's clearance, link by link
    got = [float(t.get_text().split("= ")[1].split(" m")[0]) for t in ax.texts]
    assert np.allclose(got, want, atol=0.006)
    for line, d in zip(ax.lines, want):   # each dashed gap is as long as the clearance
        xy = line.get_xydata()
        assert np.isclose(np.linalg.norm(xy[1] - xy[0]), d)
    plt.close(ax.figure)


def test_plot_sweep_colours_each_inner_pose_by_its_collision():
    from rapp.collision import collides
    disc = [Circle((0.0, 1.5), 0.3)]
    qs = np.linspace([0.0, 0.0], [np.pi, 0.0], 19)
    hit = collides(ARM, qs, disc)
    ax = P.plot_sweep(ARM, qs, disc)
    by_colour = {}
    for line in ax.lines:
        by_colour.setdefault(to_rgba(line.get_color())[:3], []).append(line)
    red = to_rgba(P.COLORS["vermillion"])[:3]
    assert hit[1:-1].sum() == 3 and red in by_colour   # the three colliding poses are drawn red
    assert_readable(ax)


def test_plot_certification_draws_every_logged_interval_at_its_depth():
    disc = [Circle((0.0, 1.5), 0.3)]
    log = [(0.0, 1.0, "bisected"), (0.0, 0.5, "certified"), (0.5, 1.0, "bisected"),
           (0.5, 0.75, "certified"), (0.75, 1.0, "collision")]
    top, bottom = P.plot_certification(ARM, [0.0, 0.0], [np.pi, 0.0], disc, log)
    bars = bottom.patches
    assert [(round(b.get_x(), 9), round(b.get_width(), 9)) for b in bars] == [(lo, hi - lo) for lo, hi, _ in log]
    assert [round(b.get_y() + b.get_height() / 2, 9) for b in bars] == [np.log2(1 / (hi - lo)) for lo, hi, _ in log]
    assert sum(line.get_label() == "proved lower bound" for line in top.lines) == 1
    assert_readable(top)
    assert_readable(bottom)


@given(st.integers(1, 4), st.integers(1, 4), st.integers(0, 2**32 - 1))
@settings(max_examples=10, deadline=None)
def test_plot_value_grid_prints_each_mean_and_half_width_in_its_cell(nx, ny, seed):
    rng = np.random.default_rng(seed)
    values = np.where(rng.random((nx, ny)) < 0.2, np.nan, rng.uniform(0, 10, (nx, ny)))
    half = np.where(rng.random((nx, ny)) < 0.3, np.nan, rng.uniform(0, 1, (nx, ny)))
    im = P.plot_value_grid(values, half, [str(i) for i in range(nx)], [str(j) for j in range(ny)])
    texts = {(round(t.get_position()[0]), round(t.get_position()[1])): t.get_text() for t in im.axes.texts}
    assert len(texts) == nx * ny
    for (i, j), text in texts.items():
        v, h = values[i, j], half[i, j]
        want = "-" if np.isnan(v) else f"{v:.2f}" + ("" if np.isnan(h) else f"\n± {h:.2f}")
        assert text == want
    plt.close(im.axes.figure)
