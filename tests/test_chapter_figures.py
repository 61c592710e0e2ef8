"""The chapters' figure modules (rapp.plot_*): each figure draws headless and shows the data it was given.

The checks read the artists back (line data, titles, legends, images) and compare them with the
values passed in or with what the model computes, so a figure that draws the wrong thing fails.
"""

import matplotlib

matplotlib.use("Agg", force=True)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import rapp  # noqa: E402
from rapp import plot_arms, plot_benchmark, plot_cspace_views, plot_ik, plot_motion, plot_search  # noqa: E402
from rapp.cartesian import line_path, tip_along_edges  # noqa: E402
from rapp.compare import group_runs, mean_interval, recorded_results, wilson  # noqa: E402
from rapp.ik import ik_2link, iterate_ik  # noqa: E402
from rapp.time_scaling import peak_rates, trapezoidal  # noqa: E402

ARM = rapp.Arm([1.0, 1.0])


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _lines_xy(ax):
    return [line.get_xydata() for line in ax.lines]


# --------------------------------------------------------------------------- plot_arms

def test_first_arm_draws_the_joints_it_is_given():
    arm, q = rapp.Arm([1.0, 0.8]), np.array([np.pi / 4, -np.pi / 3])
    fig = plot_arms.plot_first_arm(arm, q, rapp.Circle([1.2, 1.2], 0.3), "t")
    ax = fig.axes[0]
    assert np.allclose(ax.lines[0].get_xydata(), arm.joint_positions(q))
    assert np.allclose(ax.patches[0].center, (1.2, 1.2)) and ax.patches[0].radius == 0.3
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["obstacle", "links and joints",
                                                                   "end effector", "base"]


def test_elbow_sweep_traces_the_tip_on_a_circle_about_the_elbow():
    arm = rapp.Arm([1.0, 0.8])
    anim = plot_arms.animate_elbow_sweep(arm, shoulder=0.8, frames=6)
    line, trace = anim._func(5)
    tips = trace.get_xydata()
    elbow = arm.joint_positions([0.8, 0.0])[1]
    assert len(tips) == 6 and np.allclose(np.linalg.norm(tips - elbow, axis=1), 0.8)
    assert np.allclose(line.get_xydata()[1], elbow)


def test_joint_angles_figure_labels_every_joint_and_the_last_absolute_angle():
    arm, q = rapp.Arm([1.0, 0.8, 0.5]), [0.4, 1.0, -0.6]
    fig = plot_arms.plot_joint_angles(arm, q)
    texts = [t.get_text() for t in fig.axes[0].texts]
    for i in (1, 2, 3):
        assert rf"$\theta_{i}$" in texts and rf"$L_{i}$" in texts
    assert r"$\varphi_3$" in texts and r"$\mathbf{p}_3$" in texts
    assert np.allclose(fig.axes[0].lines[0].get_xydata(), arm.joint_positions(q))


def test_sampled_workspaces_draw_one_panel_per_arm():
    arms = {"(1, 0.8)": rapp.Arm([1.0, 0.8]), "(0.3, 1.7)": rapp.Arm([0.3, 1.7])}
    samples = {k: (a, a.end_effector(np.random.default_rng(0).uniform(-3, 3, (50, 2))), [0.0, np.pi])
               for k, a in arms.items()}
    fig = plot_arms.plot_sampled_workspaces(samples)
    assert [ax.get_title() for ax in fig.axes] == [
        "links (1, 0.8) m: reach 0.2 to 1.8 m", "links (0.3, 1.7) m: reach 1.4 to 2.0 m"]
    assert np.allclose(fig.axes[0].collections[0].get_offsets(), samples["(1, 0.8)"][1])


def test_plan_wide_keeps_the_plan_figure_and_moves_the_legend_outside():
    scenario = rapp.load_scenario("default")
    fig = plot_arms.plot_plan_wide(rapp.plan(scenario), scenario)
    assert np.allclose(fig.get_size_inches(), (12.5, 5.0))
    assert fig.axes[1].get_legend()._loc == 2                   # upper left, anchored outside


# --------------------------------------------------------------------------- plot_ik

def test_redundancy_figure_draws_both_elbows_and_every_fourth_of_the_family():
    arm2, arm3 = rapp.Arm([1.0, 0.8]), rapp.Arm([1.0, 0.8, 0.5])
    q2 = ik_2link(arm2, [1.0, 0.6])
    q3 = rapp.ik(arm3, [1.0, 0.9], q0=[0.3, 0.5, 0.5])
    fig = plot_ik.plot_redundancy(arm2, q2, [1.0, 0.6], arm3, q3, [1.0, 0.9])
    left, right = fig.axes
    arms = [line.get_xydata() for line in left.lines if len(line.get_xydata()) == 3]
    assert np.allclose(arms[0], arm2.joint_positions(q2[0])) and np.allclose(arms[1], arm2.joint_positions(q2[1]))
    ghosts = right.collections[-2].get_segments()
    assert len(ghosts) == len(q3[::4])
    assert np.allclose(np.array(ghosts)[:, -1], [1.0, 0.9], atol=1e-9)   # every ghost reaches the target


def test_solution_family_picks_evenly_by_the_first_joint():
    q = np.column_stack([np.linspace(-1, 1, 9), np.zeros(9), np.zeros(9)])[::-1]
    fig = plot_ik.plot_solution_family(rapp.Arm([1.0, 0.8, 0.5]), q, [1.0, 0.9], "t", shown=3)
    ends = np.array(fig.axes[0].collections[-2].get_segments())[:, 1]     # the elbows
    assert np.allclose(np.arctan2(ends[:, 1], ends[:, 0]), [-1.0, 0.0, 1.0])


def test_singular_arms_are_stretched_and_folded():
    fig = plot_ik.plot_singular_arms([rapp.Arm([1.0, 0.6]), rapp.Arm([1.0, 1.0])])
    for ax, a in zip(fig.axes, ([1.0, 0.6], [1.0, 1.0])):
        tips = [line.get_xydata()[-1] for line in ax.lines if len(line.get_xydata()) == 3]
        assert np.isclose(np.linalg.norm(tips[0]), sum(a)) and np.isclose(np.linalg.norm(tips[1]), a[0] - a[1])


def test_convergence_plots_the_chosen_start_floored_on_the_log_axis():
    err, travel, _ = iterate_ik(ARM, [1.0, 1.0], [[0.2, 1.2], [0.1, 1.0]], lam=0.05, iterations=10)
    fig = plot_ik.plot_convergence({"DLS": (err, travel, "b")}, 1)
    assert np.allclose(fig.axes[0].lines[0].get_ydata(), np.maximum(err[:, 1], 1e-17))
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), travel[:, 1])


def test_tip_error_histogram_counts_every_target():
    errors = np.array([0.0, 1e-16, 2e-16, 1e-15])
    fig = plot_ik.plot_tip_errors(errors, 1e-9, "t")
    assert sum(p.get_height() for p in fig.axes[0].patches) == len(errors)


# --------------------------------------------------------------------------- plot_motion

def test_duration_scaling_halves_the_peak_speed():
    w = np.array([[0.0, 0.0], [0.8, 0.2], [1.2, 1.0]])
    fig, peaks = plot_motion.plot_duration_scaling(w, np.linspace(0, 4, 81), (2.0, 4.0))
    assert np.allclose(peaks[4.0][0], peaks[2.0][0] / 2) and np.allclose(peaks[4.0][1], peaks[2.0][1] / 4)
    assert [line.get_label() for line in fig.axes[0].lines] == ["T = 2 s", "T = 4 s"]


def test_limited_moves_draw_the_limits_and_each_profile():
    moves = {"trapezoidal": trapezoidal(0.0, 1.2, 1.0, 2.0)}
    ts = np.linspace(0, 2.4, 49)
    fig = plot_motion.plot_limited_moves(moves, ts, 1.0, 2.0)
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), moves["trapezoidal"].evaluate(ts, 1)[:, 0])
    assert sorted(line.get_ydata()[0] for line in fig.axes[2].lines[1:]) == [-2.0, 2.0]


def test_synchronization_draws_both_timings():
    plan = rapp.plan("default")
    p0, pf = plan.shortcut[2], plan.shortcut[3]
    ts = np.linspace(0, 1, 7)
    q = np.linspace(p0, pf, 7)
    fig = plot_motion.plot_synchronization(plan, ts, q, q[::-1], np.zeros(7, bool))
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), q[:, 0])
    assert np.allclose(fig.axes[1].lines[1].get_ydata(), q[::-1, 0])
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "each joint alone" in labels and r"$\theta_2$ synchronized" in labels


def test_joint_velocities_mark_the_stops():
    pp = trapezoidal([0.0, 0.0], [1.0, 1.0], 1.0, 1.0)
    fig = plot_motion.plot_joint_velocities({"trapezoidal": pp}, [0.0, pp.duration], 1.0)
    assert np.allclose(fig.axes[0].lines[1].get_xdata(), [0.0, pp.duration])
    assert np.isclose(max(fig.axes[0].lines[0].get_ydata()), peak_rates(pp)[0][0])


def test_line_following_distances_against_the_line():
    a, b = np.array([1.0, 0.5]), np.array([1.5, 0.5])
    q = line_path(ARM, ik_2link(ARM, a)[0], b)
    fig, d_line, d_edge, s = plot_motion.plot_line_following(ARM, a, b, q, q[[0, -1]])
    tips = tip_along_edges(ARM, q)
    assert np.allclose(d_line, np.abs(tips[:, 1] - 0.5), atol=1e-12)     # the line is horizontal
    assert np.allclose(s, (tips[:, 0] - 1.0) / 0.5)
    assert d_line.max() <= 1e-3 < d_edge.max()
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), 1e3 * d_line)


def test_velocity_ellipse_has_the_singular_values_as_semi_axes():
    ax = plt.figure().add_subplot()
    q = [0.4, 1.1]
    (s1, s2), _ = rapp.manipulability_ellipse(ARM, q)
    e = plot_motion.plot_velocity_ellipse(ax, ARM, q, 0.5)
    assert np.isclose(e.width, s1) and np.isclose(e.height, s2)
    assert np.allclose(e.center, ARM.end_effector(q))


def test_manipulability_along_a_line_matches_the_closed_form():
    a, b = np.array([1.0, 0.5]), np.array([1.5, 0.5])
    q = line_path(ARM, ik_2link(ARM, a)[0], b)
    fig, s, w, kappa = plot_motion.plot_manipulability_along(ARM, a, b, q)
    assert np.allclose(w, np.abs(np.sin(q[:, 1])))                     # L1 = L2 = 1
    assert np.allclose(kappa, rapp.condition_number(ARM, q))
    from matplotlib.patches import Ellipse
    assert sum(isinstance(p, Ellipse) for p in fig.axes[0].patches) == 7


def test_timed_path_passes_the_waypoints_at_the_breakpoints():
    w = np.array([[0.0, 0.0], [0.8, 0.2], [1.2, 1.0]])
    timed = rapp.time_path(w, 4.0, "spline")
    fig = plot_motion.plot_timed_path(w, timed, np.linspace(0, 4, 41))
    assert np.allclose(fig.axes[0].lines[0].get_xydata(), w)
    assert np.allclose(fig.axes[1].lines[1].get_xydata(), np.column_stack([timed.breakpoints, w[:, 0]]))


def test_conditioning_floors_exact_zeros():
    fig = plot_motion.plot_conditioning(np.array([1.0, 10.0]), np.array([10.0, 1e4]), np.array([1e-15, 1e-12]),
                                        np.array([0.0, 1e-16]))
    assert np.allclose(fig.axes[0].lines[2].get_ydata(), [1e-17, 1e-16])


def test_derivatives_stack_position_velocity_acceleration():
    pp = rapp.time_path(np.array([[0.0], [1.0], [0.5]]), 2.0, "spline")
    ts = np.linspace(0, 2, 21)
    fig = plot_motion.plot_derivatives({"spline": pp}, ts, [("k", "-")], ([0, 1, 2], [0, 1, 0.5], "w"),
                                       ("q", "q'", "q''"), vlines=[1.0])
    for d, ax in enumerate(fig.axes):
        assert np.allclose(ax.lines[0].get_ydata(), pp.evaluate(ts, d)[:, 0])


# --------------------------------------------------------------------------- plot_search, plot_cspace_views

def test_search_panels_draw_the_path_and_shade_the_cells():
    grid = rapp.JointGrid(ARM, 12)
    occ = np.zeros((12, 12), bool)
    path = rapp.astar(occ, (0, 0), (3, 4))
    shaded = np.zeros((12, 12), bool)
    shaded[:4, :5] = True
    fig = plot_search.plot_searches([dict(occupancy=occ, grid=grid, start=(0, 0), goal=(3, 4), path=path,
                                          shaded=shaded, title="t")], (5, 4), shade_label="expanded")
    ax = fig.axes[0]
    assert np.array_equal(~ax.images[1].get_array().mask, shaded.T)
    assert ax.get_legend().get_texts()[-1].get_text() == "expanded"


def test_resolution_study_plots_the_numbers_given():
    fig = plot_search.plot_resolution_study([24, 48, 96], [6.0, 5.9, 5.8], [100, 400, 1600])
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), [100, 400, 1600])
    assert fig.axes[1].get_yscale() == "log"


def test_side_by_side_places_each_configuration_in_both_panels():
    grid = rapp.JointGrid(ARM, 16)
    qs = np.array([[0.0, 0.0], [0.45, 0.2]])
    fig = plot_cspace_views.plot_side_by_side(ARM, [], np.zeros((16, 16), bool), grid, qs, "C")
    assert np.allclose([line.get_xydata()[0] for line in fig.axes[1].lines[-2:]], qs)


def test_interval_edges_skip_where_the_link_cannot_reach():
    grid = rapp.JointGrid(ARM, 16)
    t1 = np.linspace(-np.pi, np.pi, 9)
    hw = np.where(np.arange(9) < 4, -1.0, 0.3)
    fig = plot_cspace_views.plot_interval_edges(np.zeros((16, 16), bool), grid, t1, hw, np.zeros(9), "t")
    y = fig.axes[0].lines[-1].get_ydata()
    assert np.isnan(y[:4]).all() and np.allclose(y[5:8], rapp.wrap_angle(0.3 - t1[5:8]))


def test_tiled_cspace_repeats_the_grid_twice_each_way():
    grid = rapp.JointGrid(ARM, 8)
    occ = np.zeros((8, 8), bool)
    occ[1, 2] = True
    fig = plot_cspace_views.plot_tiled(occ, grid)
    tiled = fig.axes[1].images[0].get_array()
    assert tiled.shape == (16, 16) and tiled[2, 1] == tiled[10, 9] == 1 and tiled.sum() == 4


def test_torus_and_square_draw_the_same_path():
    grid = rapp.JointGrid(ARM, 8)
    path = np.array([[0.0, 0.0], [0.5, 0.5]])
    fig = plot_cspace_views.plot_torus_and_square(np.zeros((8, 8), bool), grid, path)
    assert fig.axes[0].name == "3d" and fig.axes[1].get_title() == "the square it unrolls to"


# --------------------------------------------------------------------------- plot_benchmark

def test_success_by_budget_matches_wilson_intervals():
    found = {"RRT": np.array([2, 5]), "RRT-Connect": np.array([4, 5])}
    fig = plot_benchmark.plot_success_by_budget(found, [10, 100], 5)
    ax = fig.axes[0]
    assert np.allclose(ax.lines[0].get_ydata(), [0.4, 1.0]) and np.allclose(ax.lines[0].get_xdata(), [9.7, 97.0])
    lo = wilson(2, 5)[0]
    seg = ax.collections[0].get_segments()[0]                       # the first error bar
    assert np.isclose(seg[:, 1].min(), lo)


def test_cost_by_budget_draws_each_seed_and_the_baseline():
    costs = np.array([[3.0, 2.5], [3.2, 2.6], [3.1, 2.4]])
    fig = plot_benchmark.plot_cost_by_budget(costs, [100, 200], [mean_interval(c) for c in costs.T],
                                             mean_interval([4.0, 4.4]), 2.4)
    ax = fig.axes[0]
    assert [list(line.get_ydata()) for line in ax.lines[:3]] == costs.tolist()
    assert ax.get_title() == "three-disc benchmark, step 0.5 rad, 3 seeds"


def test_grid_gap_shades_what_the_coarse_grid_reaches():
    p = rapp.plan({"arm": {"link_lengths": [1, 1]}, "start": [0, 0], "goal": {"joints": [1, 1]},
                   "planner": {"cells": 24}})
    discs = [rapp.Circle((0.0, 1.5), 0.3)]
    fig, grid, occ, reach = plot_benchmark.plot_grid_gap(ARM, discs, [0, 0], [1, 1], p, cells=20)
    assert np.array_equal(occ, rapp.occupancy(ARM, discs, grid))
    assert np.array_equal(reach, rapp.bfs_distances(occ, tuple(grid.index([0, 0]).tolist())) >= 0)
    assert fig.axes[2].get_title() == "24 cells: a verified plan"


def test_narrow_gap_marks_each_seed_and_the_share_in_the_gap():
    q = np.zeros((4, 2))
    its = {0.1: [5, 7, 6], 0.05: [9, 12, 30]}
    fig = plot_benchmark.plot_narrow_gap(ARM, [], q[0], q[1], q, q, its, {0.1: 0.02, 0.05: 0.01})
    ax = fig.axes[1]
    assert [list(line.get_ydata()) for line in ax.lines[:2]] == [[5, 7, 6], [9, 12, 30]]
    assert [t.get_text() for t in ax.texts] == ["2.00 % of samples\nin the gap", "1.00 % of samples\nin the gap"]


@pytest.fixture(scope="module")
def groups():
    return group_runs(recorded_results())


def test_group_runs_reproduces_the_harness_summary(groups):
    from rapp.compare import FAMILY_NAMES

    summary = recorded_results()["summary"]
    for planner, name in FAMILY_NAMES.items():
        for cls, entry in summary.get(planner, {}).items():
            mine = groups.stats[name, cls]
            assert (mine["runs"], mine["successes"]) == (entry["runs"], entry["successes"])
            assert np.allclose(mine["interval"], entry["success_interval"])
    assert sum(groups.size.values()) == 30
    assert groups.summary().splitlines()[1].startswith("A* coarse")


def test_success_rates_and_times_show_every_family(groups):
    fig = plot_benchmark.plot_success_rates(groups)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == groups.families
    fig = plot_benchmark.plot_time_and_length(groups)
    assert {t.get_text() for t in fig.axes[0].get_yticklabels()} == set(groups.families)


def test_shortcuts_draw_the_shortcut_dashed():
    p = rapp.plan({"arm": {"link_lengths": [1, 1]}, "start": [-1, -1], "goal": {"joints": [1, 1]},
                   "planner": {"cells": 24}})
    fig = plot_benchmark.plot_shortcuts([p], ["a"])
    dashed = [line for line in fig.axes[0].lines if line.get_linestyle() == "--"]
    assert np.allclose(dashed[0].get_xydata(), p.shortcut)
