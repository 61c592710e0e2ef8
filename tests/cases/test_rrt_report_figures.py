"""rapp.cases.rrt_report_figures: what each figure draws (its data, labels and limits), not pixels."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rapp import Arm, Polygon  # noqa: E402
from rapp.rrt import rrt  # noqa: E402
from rapp.view_stack import Control, selected  # noqa: E402
from rapp.cases import rrt_report_figures as rf  # noqa: E402
from rapp.cases.rrt_report import alpha_beta_experiment, mean_interval, seed_problem, wilson_interval  # noqa: E402


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def problem():
    return seed_problem()


@pytest.fixture(scope="module")
def experiment():
    arm = Arm([1.0, 1.0])
    return alpha_beta_experiment(arm, [0.0, 0.0], [0.0, 2.0], [], [0.25, 0.5, 1.0], [0.1, 1.0], 4,
                                 max_iterations=100)


def test_plot_straight_vs_rrt_draws_both_motions(problem):
    arm, obs, s, g = problem
    straight = np.linspace(s, g, 5)
    fig = rf.plot_straight_vs_rrt(arm, obs, s, g, straight, straight[:2])
    titles = [ax.get_title() for ax in fig.axes]
    assert titles == ["moving every joint at once hits the square", "RRT goes round it: every edge certified free"]
    labels = [t.get_text() for t in fig.axes[1].get_legend().get_texts()]
    assert "RRT path (2 nodes)" in labels and "square (0.2 m)" in labels


def test_plot_axis_projections_draws_the_intervals_on_both_axes():
    square, a, b = Polygon.rectangle((0.0, 0.0), 1.0, 1.0), np.array([1.5, -1.0]), np.array([2.5, 0.5])
    ax = rf.plot_axis_projections(square, a, b)
    data = {line.get_label(): line.get_xydata() for line in ax.lines}
    assert np.allclose(data["square projected"][:, 1], [0.0, 1.0])
    assert np.allclose(data["link projected"][:, 1], [-1.0, 0.5])
    assert np.allclose(ax.lines[-1].get_xdata(), [1.5, 2.5])        # the link projected on x


def test_plot_tree_projection_draws_every_edge_and_the_path():
    arm = Arm([1.0, 1.0], joint_limits=[(-3, 3), (-3, 3)])
    res = rrt(arm, [0.0, 0.0], [1.0, 1.0], [], step=0.3, seed=1)
    ax = rf.plot_tree_projection(res, arm, [0.0, 0.0], [1.0, 1.0], plt.figure().add_subplot(), "T")
    segs = ax.collections[0].get_segments()
    assert len(segs) == len(res.nodes) - 1
    assert np.allclose(segs[0], [res.nodes[res.parent[1]], res.nodes[1]])
    path = next(line for line in ax.lines if line.get_label() == "path")
    assert np.allclose(path.get_xydata(), res.path) and ax.get_title() == "T"
    assert np.allclose(ax.get_xlim(), (-3, 3))


def test_plot_goal_run_draws_the_goal_circle_and_the_tip(problem):
    arm, obs, s, g = problem
    res = rrt(arm, s, g, [], step=0.3, goal_bias=0.5, seed=0)   # quick: no obstacle
    goal_xy = arm.end_effector(g)
    fig = rf.plot_goal_run(arm, res, obs, s, g, goal_xy)
    circle = fig.axes[1].patches[-1]
    assert np.allclose(circle.center, goal_xy) and circle.get_radius() == 0.05
    tip = next(line for line in fig.axes[1].lines if line.get_label() == "tip")
    assert np.allclose(tip.get_xydata(), arm.end_effector(res.path))


def test_plot_alpha_beta_plots_the_rates_and_their_wilson_intervals(experiment):
    fig = rf.plot_alpha_beta(experiment, experiment, 4)
    ax1, ax2 = fig.axes[:2]
    lo, hi = wilson_interval(experiment["successes"], 4)
    rates = ax1.containers[0]                       # beta = 0.1
    assert np.allclose(rates.lines[0].get_ydata(), experiment["success_rate"][:, 0])
    seg = rates.lines[2][0].get_segments()
    assert np.allclose([s[:, 1] for s in seg], np.stack((lo[:, 0], hi[:, 0]), -1))
    m, _ = mean_interval(experiment["trial_iterations"])
    assert np.allclose(ax2.containers[1].lines[0].get_ydata(), m[:, 1])
    assert np.allclose(ax1.containers[0].lines[0].get_xdata() - ax1.containers[1].lines[0].get_xdata(), -0.016)


def test_plot_cost_heatmaps_one_panel_per_run(experiment):
    fig = rf.plot_cost_heatmaps({"a": experiment, "b": experiment})
    assert [ax.get_title() for ax in fig.axes[:2]] == ["mean path cost, a", "mean path cost, b"]
    image = fig.axes[0].images[0].get_array()
    m, _ = mean_interval(experiment["trial_cost"])
    assert np.allclose(np.ma.filled(image, np.nan), m.T, equal_nan=True)   # beta up, alpha across


def test_plot_cost_and_time_bars_and_the_straight_line():
    cmp = {"rrt_cost": 3.0, "astar_cost": 2.5, "straight_distance": 2.0, "rrt_seconds": 0.1, "astar_seconds": 0.4}
    ax1, ax2 = rf.plot_cost_and_time(cmp).axes
    assert [p.get_height() for p in ax2.patches] == [0.1, 0.4]
    assert np.allclose(ax1.lines[0].get_ydata(), 2.0)


@pytest.mark.slow
def test_tree_explorer_grows_one_tree_per_view(problem):
    arm, obs, s, g = problem
    grown = {}
    w = rf.tree_explorer(arm, s, g, arm.end_effector(g), obs,
                         {"alpha": Control("a", [0.4], default=0.4), "beta": Control("b", [1.0], default=1.0),
                          "seed": Control("s", [0], default=0)}, grown, max_iterations=20)
    assert set(grown) == {(0.4, 1.0, 0)}
    r = grown[0.4, 1.0, 0]
    assert selected(w)[1].startswith(f"α = 0.4 rad, β = 1, seed 0: {len(r.nodes)} nodes")
