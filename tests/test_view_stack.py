"""rapp.view_stack: every combination is drawn, the links wire each slider to its stacks, the
background holds only what never changes, and the figure is left as it was given."""

import io
import re

import ipywidgets as widgets
import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from rapp.view_stack import Control, overlays_of, selected, sliders_of, statuses_of, view_stack


def _explorer(calls=None):
    fig = Figure(figsize=(4, 3))
    ax = fig.add_subplot()
    ax.set_xlim(0, 4)
    ax.set_ylim(0, 3)
    ax.plot([0, 4], [1.5, 1.5], color="grey")  # static

    def view(x, y):
        if calls is not None:
            calls.append((x, y))
        ax.plot([x], [y], "o", color="red")
        ax.set_title(f"at {x}, {y}")
        return f"x={x} y={y}"

    controls = {"x": Control("x", [1, 2, 3], default=2, fmt="{}"),
                "y": Control("y", [0.5, 2.5], default=2.5, fmt="{}")}
    return fig, ax, view_stack(fig, controls, view, title="t")


def _stacks(widget):
    if isinstance(widget, widgets.Stack):
        yield widget
    for child in getattr(widget, "children", ()):
        yield from _stacks(child)


def test_every_combination_is_drawn_once_more_than_needed():
    calls = []
    _explorer(calls)
    assert sorted(set(calls)) == [(x, y) for x in (1, 2, 3) for y in (0.5, 2.5)]
    assert len(calls) == 6 + 1  # each view once, plus once to learn what changes


def test_links_wire_each_slider_to_every_stack_of_its_level():
    _, _, w = _explorer()
    sx, sy = sliders_of(w)
    assert (sx.index, sy.index) == (1, 1)
    for root in (overlays_of(w), statuses_of(w)):
        assert len(root.children) == 3 and all(len(c.children) == 2 for c in root.children)
    links = w._links
    assert len(links) == 2 * (1 + 3)
    stacks = {id(s) for s in _stacks(w)}
    for link in links:
        (src, src_trait), (dst, dst_trait) = link.source, link.target
        assert src in (sx, sy) and src_trait == "index" and dst_trait == "selected_index"
        assert id(dst) in stacks
        depth_one = dst in (overlays_of(w), statuses_of(w))
        assert (src is sx) == depth_one  # the outer stack follows x, the inner ones follow y


def test_selected_view_is_the_drawing_of_those_values():
    _, _, w = _explorer()
    svg, status = selected(w)
    assert status == "x=2 y=2.5" and ">at 2, 2.5<" in svg
    sliders_of(w)[0].index = 0
    svg0, status0 = selected(w)
    assert status0 == "x=1 y=2.5" and svg0 != svg


def test_overlays_hold_only_what_changes_and_ids_never_clash():
    _, _, w = _explorer()
    leaves = [leaf.value for outer in overlays_of(w).children for leaf in outer.children]
    ids = [i for svg in leaves for i in re.findall(r'id="([^"]+)"', svg)]
    assert len(ids) == len(set(ids))
    for svg in leaves:
        assert svg.count("<path") + svg.count("<use") <= 4  # the marker, not the static line
        assert 'width="100%"' in svg


def test_background_is_the_static_figure_and_the_figure_is_left_clean():
    fig, ax, w = _explorer()
    image = next(c for c in w.children[-1].children if isinstance(c, widgets.Image))
    png = Image.open(io.BytesIO(image.value)).convert("RGB")
    assert png.size == (288, 216)  # 4 x 3 inches at 72 dpi
    red = np.all(np.asarray(png) == [255, 0, 0], axis=-1)
    assert not red.any()  # no view's marker in the background
    assert len(ax.lines) == 1 and ax.get_title() == ""


def test_a_view_that_moves_the_limits_does_not_shift_its_overlay():
    fig = Figure(figsize=(3, 3))
    ax = fig.add_subplot()
    ax.set_xlim(0, 1)

    def view(k):
        ax.plot([0.5], [0.5], "o")
        ax.set_xlim(0, 10 * k)  # a plotting helper that sets limits of its own
        return ""

    w = view_stack(fig, {"k": Control("k", [1, 2], default=1, fmt="{}")}, view)
    a, b = (leaf.value for leaf in overlays_of(w).children)
    xy = [re.search(r'x="([\d.]+)" y="([\d.]+)"', svg).groups() for svg in (a, b)]
    assert xy[0] == xy[1]  # the marker sits at the same place over the same background axes
    assert ax.get_xlim() == pytest.approx((0, 10))


def test_a_value_that_rounds_to_zero_has_no_minus_sign():
    labels = Control("x (m)", [round(v, 1) for v in np.linspace(-1.8, 1.8, 13)]).labels()
    assert "0.00" in labels and not any(t.startswith("-0.00") for t in labels)
    assert Control("x", [-0.004, -0.006, -1.0]).labels() == ["0.00", "-0.01", "-1.00"]
