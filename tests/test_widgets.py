"""rapp.widgets: each explorer shows a figure at construction and redraws when a control moves.

The static book shows only the saved default view, so every test first reads
the Output widget's outputs right after construction, then moves a control
and checks that the figure and the status line follow the model.
"""

import base64
import io

import matplotlib

matplotlib.use("Agg", force=True)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from rapp import Arm, Circle  # noqa: E402
from rapp import widgets as W  # noqa: E402
from rapp.collision import collides, line_distance_mis, segment_circle_distance  # noqa: E402


def shown_png(widget):
    """The figure in the explorer's Output widget, decoded (fails if there is none)."""
    outputs = W.output_of(widget).outputs
    assert len(outputs) == 1
    data = outputs[0]["data"]
    assert outputs[0]["output_type"] == "display_data"
    assert data["text/plain"].startswith("<Figure size")
    raw = base64.b64decode(data["image/png"])
    img = Image.open(io.BytesIO(raw))
    img.load()
    return raw, img


def status_of(widget):
    import ipywidgets

    return [c for c in widget.children if isinstance(c, ipywidgets.HTML)][-1].value


@pytest.fixture(autouse=True)
def no_pyplot_figures_left():
    before = set(plt.get_fignums())
    yield
    assert set(plt.get_fignums()) == before  # explorers draw on pyplot-free figures


ARM = Arm([1.0, 1.0])
OBS = (Circle((1.2, 0.9), 0.35),)


def test_arm_explorer_default_view_and_update():
    w = W.arm_explorer(ARM, OBS, cells=24)
    raw, img = shown_png(w)
    assert img.format == "PNG" and img.width > 2 * img.height * 0.9  # C-space beside workspace
    assert img.getpixel((2, 2))[:3] == (255, 255, 255)  # white background
    sliders = W.sliders_of(w)
    assert list(sliders) == ["θ1 (rad)", "θ2 (rad)"]
    assert "free" in status_of(w) and bool(collides(ARM, [0.0, 0.0], OBS)) is False
    # Point the arm at the obstacle: the figure changes and the status says collision.
    q_hit = np.array([np.arctan2(0.9, 1.2), 0.0])
    assert bool(collides(ARM, q_hit, OBS))
    sliders["θ1 (rad)"].value = float(q_hit[0])
    raw2, _ = shown_png(w)
    assert raw2 != raw
    assert "collision" in status_of(w)
    sliders["θ1 (rad)"].value = 0.0
    assert shown_png(w)[0] == raw  # the same state draws the same figure


def test_arm_explorer_three_links_shows_workspace_only():
    arm = Arm([1.0, 0.7, 0.4], [None, (-2.0, 2.0), None])
    w = W.arm_explorer(arm, OBS, q=[0.3, 5.0, 0.0])
    _, img = shown_png(w)
    assert img.width < 1.3 * img.height
    sliders = W.sliders_of(w)
    assert len(sliders) == 3
    assert sliders["θ2 (rad)"].value == 2.0  # the default is clipped to the joint limit
    assert (sliders["θ2 (rad)"].min, sliders["θ2 (rad)"].max) == (-2.0, 2.0)


def test_collision_explorer_flags_the_mis_false_collision():
    w = W.collision_explorer()
    raw, _ = shown_png(w)
    text = status_of(w)
    seg = float(segment_circle_distance((0, 0), (1, 0), (1.6, 0.1), 0.3))
    line = float(line_distance_mis((0, 0), (1, 0), (1.6, 0.1))) - 0.3
    assert seg > 0 >= line  # the default really is a false collision ...
    assert "false collision" in text  # ... and the view says so
    assert f"{seg:.3f}" in text and f"{line:.3f}" in text
    # Slide the centre over the segment: both formulas agree on a collision.
    W.sliders_of(w)["centre x (m)"].value = 0.5
    assert shown_png(w)[0] != raw
    text = status_of(w)
    assert "false collision" not in text and text.count("collision") == 2
    # Far off the line: both agree the segment is free.
    W.sliders_of(w)["centre y (m)"].value = 1.5
    assert "collision" not in status_of(w)


def test_trajectory_explorer_quintic_meets_accelerations_cubic_does_not():
    pytest.importorskip("rapp.trajectory")
    w = W.trajectory_explorer(a0=1.0, af=-0.5)
    raw, _ = shown_png(w)
    assert "quintic 1.000, -0.500" in status_of(w)
    W.sliders_of(w)["pf (rad)"].value = -1.0
    assert shown_png(w)[0] != raw
    # Rest-to-rest cubic from 0 to pf over tf: a(0) = 6 pf / tf^2 = -1.5 at tf = 2.
    assert "cubic -1.500, 1.500" in status_of(w)


def test_planner_playground_default_is_the_given_plan():
    planner = pytest.importorskip("rapp.planner")
    from rapp.scenario import load_scenario

    s = load_scenario("default")
    w = W.planner_playground(s)
    raw, img = shown_png(w)
    assert img.width > 1.8 * img.height  # C-space beside workspace
    assert "planned" in status_of(w)
    ref = planner.plan(s)
    assert f"path_cells {ref.metrics['path_cells']}" in status_of(w)
    sliders = W.sliders_of(w)
    assert sliders["cells / joint"].value == max(s.planner.cells)
    # Weighted A* needs w >= 1; the slider offers nothing it would refuse.
    assert sliders["heuristic w"].min == 1.0
    # A coarser grid re-plans: another figure, another path.
    sliders["cells / joint"].value = 40
    assert shown_png(w)[0] != raw
    assert f"path_cells {ref.metrics['path_cells']}" not in status_of(w)
    # An unreachable goal is reported as a planning answer, with a figure.
    sliders["goal x (m)"].value = sliders["goal x (m)"].max
    sliders["goal y (m)"].value = sliders["goal y (m)"].max
    assert "NoIKSolution" in status_of(w)
    shown_png(w)


def test_planner_playground_weight_changes_the_figure_and_the_expanded_cells():
    from rapp.scenario import load_scenario

    s = load_scenario("default")
    w = W.planner_playground(s)
    raw, _ = shown_png(w)

    def expanded():
        text = status_of(w)
        return int(text.split(" cells expanded")[0].rsplit(">", 1)[1])

    before = expanded()
    W.sliders_of(w)["heuristic w"].value = 3.0
    after = expanded()
    # Weighted A* expands fewer cells, and the figure shades what it expanded.
    assert 0 < after < before
    assert shown_png(w)[0] != raw


def test_plan_expanded_is_the_search_closed_set():
    from rapp.planner import plan
    from rapp.scenario import load_scenario

    p = plan(load_scenario("default"))
    assert p.expanded.shape == p.occupancy.shape
    assert int(p.expanded.sum()) == p.metrics["expansions"]
    assert not (p.expanded & p.occupancy).any()


@pytest.mark.parametrize("value, lo, hi, step", [
    (0.8, -np.pi, np.pi, 0.05), (0.6, -np.pi, np.pi, 0.01), (-3.2, -np.pi, np.pi, 0.01),
    (1.234, -2.0, 2.0, 0.02), (0.45, -2.6, 2.6, 0.1)])
def test_slider_defaults_lie_on_the_step_grid(value, lo, hi, step):
    s = W._slider("x", value, lo, hi, step)
    # The browser snaps to min + k * step; a value already there is never re-sent.
    for v in (s.value, s.max):
        k = (v - s.min) / step
        assert abs(k - round(k)) < 1e-9
    assert lo <= s.min <= s.value <= s.max <= hi
    assert abs(s.value - value) <= step / 2 + 1e-12 or s.value in (s.min, s.max)
