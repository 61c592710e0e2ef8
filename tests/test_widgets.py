"""rapp.widgets: every explorer is a view stack whose every view follows the model.

The book's static pages run no Python: the sliders pick among views drawn in advance. So the
tests read what a reader would see for given slider positions (:func:`rapp.view_stack.selected`:
the overlay and the status line) and check it against the package, for the default view and
after moving a slider.
"""

import dataclasses

import matplotlib

matplotlib.use("Agg", force=True)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rapp import Arm, Circle, clearance  # noqa: E402
from rapp import widgets as W  # noqa: E402
from rapp.collision import collides, line_distance_mis, segment_circle_distance  # noqa: E402
from rapp.view_stack import selected, values_of  # noqa: E402


@pytest.fixture(autouse=True)
def no_pyplot_figures_left():
    before = set(plt.get_fignums())
    yield
    assert set(plt.get_fignums()) == before  # explorers draw on pyplot-free figures


ARM = Arm([1.0, 1.0])
OBS = (Circle((1.2, 0.9), 0.35),)


def move(widget, name, value):
    """Put the slider of keyword ``name`` on its value nearest ``value``, as a reader would."""
    control = widget._controls[name]
    slider = W.sliders_of(widget)[control.description]
    slider.index = int(np.argmin([abs(v - value) for v in control.values]))
    return control.values[slider.index]


@pytest.mark.slow
def test_arm_explorer_views_follow_the_model():
    w = W.arm_explorer(ARM, OBS, cells=24, steps=13)
    sliders = W.sliders_of(w)
    assert list(sliders) == ["θ1 (rad)", "θ2 (rad)"]
    assert len(sliders["θ1 (rad)"].options) == 13
    svg, status = selected(w)
    assert "free" in status and not collides(ARM, [0.0, 0.0], OBS)
    # Point the arm at the obstacle: another drawing, and the status says collision.
    q1 = move(w, "q0", np.arctan2(0.9, 1.2))
    assert collides(ARM, [q1, 0.0], OBS)
    svg2, status2 = selected(w)
    assert svg2 != svg and "collision" in status2
    assert f"clearance {float(clearance(ARM, [q1, 0.0], OBS)):.3f} m" in status2
    move(w, "q0", 0.0)
    assert selected(w) == (svg, status)  # the same position shows the same view


@pytest.mark.slow
def test_arm_explorer_three_links_keeps_limits_and_at_most_400_views():
    arm = Arm([1.0, 0.7, 0.4], [None, (-2.0, 2.0), None])
    w = W.arm_explorer(arm, OBS, q=[0.3, 5.0, 0.0])
    sliders = W.sliders_of(w)
    assert len(sliders) == 3
    s2 = sliders["θ2 (rad)"]
    assert (float(s2.options[0]), float(s2.options[-1])) == (-2.0, 2.0)
    assert values_of(w)["q1"] == 2.0  # the default is the nearest value inside the limit
    assert np.prod([len(s.options) for s in sliders.values()]) <= 400


@pytest.mark.slow
def test_collision_explorer_flags_the_mis_false_collision():
    # 9 values per slider, 0.5 m apart (81 views, not the default 17 x 17 = 289): every view is
    # drawn by the same code whatever the resolution, and the positions this test visits are
    # all on the grid: the default (1.6, 0.1) snaps to (1.5, 0.0), still beyond the segment's
    # end on its line, and 0.5 and 1.5 are slider values.
    w = W.collision_explorer(steps=9)
    svg, text = selected(w)
    cx, cy = values_of(w)["cx"], values_of(w)["cy"]
    seg = float(segment_circle_distance((0, 0), (1, 0), (cx, cy), 0.3))
    line = float(line_distance_mis((0, 0), (1, 0), (cx, cy))) - 0.3
    assert seg > 0 >= line  # the default really is a false collision ...
    assert "false collision" in text  # ... and the view says so
    assert f"{seg:.3f}" in text and f"{line:.3f}" in text
    # Slide the centre over the segment: both formulas agree on a collision.
    move(w, "cx", 0.5)
    svg2, text = selected(w)
    assert svg2 != svg and "false collision" not in text and text.count("collision") == 2
    # Far off the line: both agree the segment is free.
    move(w, "cy", 1.5)
    assert "collision" not in selected(w)[1]


def test_trajectory_explorer_quintic_meets_accelerations_cubic_does_not():
    # Four values per slider (16 views, not the default 11 x 11 = 121): the views visited below
    # (a0 = 1, af = -1 and then 3) are among them, and each view is drawn by the same code
    # whatever the other slider values are.
    w = W.trajectory_explorer(a0=1.0, af=-1.0, accelerations=[-3.0, -1.0, 1.0, 3.0])
    svg, text = selected(w)
    assert "quintic 1.000, -1.000" in text
    # Rest-to-rest cubic from 0 to 1 over 2 s: a(0) = 6 pf / tf^2 = 1.5, whatever is asked.
    assert "cubic 1.500, -1.500" in text
    move(w, "af", 3.0)
    svg2, text = selected(w)
    assert svg2 != svg and "quintic 1.000, 3.000" in text and "cubic 1.500, -1.500" in text


def test_planner_playground_weights_expand_fewer_cells_and_failures_are_shown():
    from rapp.planner import plan
    from rapp.scenario import load_scenario

    s = load_scenario("default")
    unreachable = dataclasses.replace(s, goal_xy=(5.0, 5.0))
    w = W.planner_playground({"default": s, "unreachable": unreachable}, cells=(12, 90),
                             weights=(1.0, 3.0))
    assert list(W.sliders_of(w)) == ["scenario", "cells / joint", "heuristic w"]
    svg, text = selected(w)
    ref = plan(dataclasses.replace(s, planner=dataclasses.replace(s.planner, cells=(90, 90))))
    assert "planned" in text and f"a path of {ref.metrics['path_cells']} steps" in text
    assert "_" not in text.split("</span>", 1)[1] and "&#x27;" not in text  # sentences, plain

    def expanded():
        return int(selected(w)[1].split("A* expanded ")[1].split(" of")[0].replace(",", ""))

    before = expanded()
    move(w, "weight", 3.0)
    assert 0 < expanded() < before and selected(w)[0] != svg
    move(w, "cells", 12)  # a coarser grid re-plans: another path
    assert f"a path of {ref.metrics['path_cells']} steps" not in selected(w)[1]
    # An unreachable goal is a planning answer, shown with its figure.
    W.sliders_of(w)["scenario"].index = 1
    svg3, text3 = selected(w)
    assert "planned" not in text3 and "NoIKSolution" in text3 and svg3.startswith("<svg")


class _Report:
    def __init__(self, failed=()):
        self.failed = tuple(type("Check", (), {"name": n}) for n in failed)
        self.ok = not failed


_METRICS = {"expansions": 422, "expansions_total": 845, "grid_cells": 1600, "path_cells": 43,
            "bfs_optimum_cells": 43, "certification_repairs": 1, "shortcut_waypoints": 3,
            "waypoint_length_rad": 5.8174, "shortcut_length_rad": 4.4419}


@pytest.mark.parametrize("repairs,steps,weight,failed", [
    (0, 43, 1.0, ()), (1, 43, 1.0, ()), (2, 47, 3.0, ()), (0, 45, 1.0, ("goal reached",))])
def test_playground_status_says_each_number_once_in_sentences(repairs, steps, weight, failed):
    m = dict(_METRICS, certification_repairs=repairs, path_cells=steps)
    text = W.playground_status(m, _Report(failed), weight=weight)
    assert "_" not in text and "<" not in text                    # no metric names, no markup
    assert text.count(". ") == 1 and text.endswith(".")         # two sentences
    assert text.startswith("A* expanded 422 of the grid's 1,600 cells (shaded blue)")
    assert f"a path of {steps} steps" in text
    assert ("the fewest possible on this grid" in text) == (steps == 43)
    assert (f"{steps - 43} more than the fewest possible (43)" in text) == (steps > 43)
    assert ("heuristic weight 3 trades length" in text) == (weight > 1 and steps > 43)
    assert ("845 in all" in text) == (repairs > 0)
    assert ("1 move between free cells" in text) == (repairs == 1)
    assert ("2 moves between free cells" in text) == (repairs == 2)
    assert "3 waypoints, 4.44 rad of joint motion instead of 5.82 rad" in text
    assert text.endswith("the verification passed.") == (not failed)
    assert ("the verification failed (goal reached)" in text) == bool(failed)
    assert "shaded" not in W.playground_status(m, _Report(), shaded=False)
    same = W.playground_status(dict(m, shortcut_length_rad=5.8174), _Report())
    assert "3 waypoints, the same 5.82 rad of joint motion, and" in same and "instead" not in same


def test_plan_expanded_is_the_search_closed_set():
    from rapp.planner import plan
    from rapp.scenario import load_scenario

    p = plan(load_scenario("default"))
    assert p.expanded.shape == p.occupancy.shape
    assert int(p.expanded.sum()) == p.metrics["expansions"]
    assert not (p.expanded & p.occupancy).any()


def test_a_failure_view_shows_the_start_region_and_says_whether_the_goal_is_in_it():
    # The oracle: a plain flood fill over the grid's free cells (Python sets, no numpy tricks).
    from rapp.cspace import JointGrid, occupancy
    from rapp.scenario import load_scenario

    s = load_scenario("no_solution")
    w = W.planner_playground({"no_solution": s}, cells=(40,), weights=(1.0,))
    text = selected(w)[1]
    assert "NoPathFound" in text and "hatched: beyond the joint limits" in text
    grid = JointGrid(s.arm, 40)
    occ = occupancy(s.arm, s.obstacles, grid)
    start = tuple(int(i) for i in grid.index(np.asarray(s.start)))
    seen, todo = {start}, [start]
    while todo:
        i, j = todo.pop()
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            a, b = i + di, j + dj
            a, b = (a % 40 if grid.wraps[0] else a), (b % 40 if grid.wraps[1] else b)
            if 0 <= a < 40 and 0 <= b < 40 and not occ[a, b] and (a, b) not in seen:
                seen.add((a, b))
                todo.append((a, b))
    goal = tuple(int(i) for i in grid.index(np.asarray(s.goal_q)))
    assert f"The start reaches {len(seen)} of the grid's {int((~occ).sum())} free cells" in text
    assert ("the goal is not among them" in text) == (goal not in seen) and goal not in seen


def test_explorer_figures_record_their_smallest_text_at_book_size():
    # The book check scales rapp:text-px by the displayed width; at 72 dpi a point is a pixel,
    # and the book's smallest type is 10 pt, whatever the session's matplotlib defaults.
    import io

    from PIL import Image

    with matplotlib.rc_context({"font.size": 6.0}):
        w = W.collision_explorer(steps=3)
    image = next(c for c in w.children[-1].children if hasattr(c, "format"))
    info = Image.open(io.BytesIO(image.value)).info
    assert info["rapp:dpi"] == "72" and float(info["rapp:text-px"]) >= 10.0


@pytest.mark.slow
def test_comparison_run_reports_the_planners_own_result():
    from rapp import Arm, Circle, planners
    from rapp.widgets import comparison_run
    arm, obstacles = Arm([1.0, 1.0]), [Circle((1.2, 0.9), 0.3)]
    r, status = comparison_run(arm, [0.0, 0.0], [2.0, 1.0], obstacles, "rrt_connect", {"step": 0.3}, 3)
    same = planners.run("rrt_connect", arm, [0.0, 0.0], [2.0, 1.0], obstacles, seed=3, step=0.3,
                        raise_on_failure=False)
    assert np.array_equal(r.path, same.path)
    assert status == f"RRT-Connect, seed 3: a path of {r.cost:.2f} rad after {r.iterations} iterations, {len(r.nodes)} nodes"
    r, status = comparison_run(arm, [0.0, 0.0], [2.0, 1.0], obstacles, "astar", {"cells": 24}, 0)
    assert status.startswith("A* on 24 × 24 cells") and f"{r.metrics['path_cells']} steps" in status


@pytest.mark.slow
def test_planner_comparison_shows_each_planner_and_seed_with_its_status():
    from rapp import Arm, Circle
    from rapp.widgets import comparison_run, planner_comparison
    arm, obstacles = Arm([1.0, 1.0]), [Circle((1.2, 0.9), 0.3)]
    settings = {"astar": {"cells": 24}, "rrt_connect": {"step": 0.3}, "prm": {"samples": 40}}
    w = planner_comparison(arm, [0.0, 0.0], [2.0, 1.0], obstacles, settings, seeds=(0, 1), cells=24,
                           default="prm")
    assert sorted(w.results) == sorted((p, s) for p in settings for s in (0, 1))
    sliders = list(W.sliders_of(w).values())
    assert [s.options for s in sliders] == [("A*", "RRT-Connect", "PRM"), ("0", "1")]
    assert selected(w)[1] == comparison_run(arm, [0.0, 0.0], [2.0, 1.0], obstacles, "prm", settings["prm"], 0)[1]


def test_ik_explorer_shows_rapp_ik_at_every_target():
    from rapp import ik
    arm, targets = Arm([1.0, 0.8]), [-0.0, 0.3, 1.8]
    w = W.ik_explorer(arm, targets, default=(0.3, 0.3))
    sliders = list(W.sliders_of(w).values())
    assert [s.options for s in sliders] == [("0.00", "0.30", "1.80")] * 2   # no "-0.00"
    want = ik(arm, [0.3, 0.3])
    status = selected(w)[1]
    assert status.startswith("target (0.3, 0.3) m:") and f"({want[0][0]:.3f}, {want[0][1]:.3f})" in status
    sliders[0].index = sliders[1].index = 2                     # (1.8, 1.8): beyond the reach
    assert selected(w)[1] == "target (1.8, 1.8) m: no solution, out of reach"
