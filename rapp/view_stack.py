"""Explorers that work with no kernel: every view drawn in advance, the controls pick one.

A static HTML page keeps the widgets' saved state but runs no Python, so a control wired to a
Python callback moves and changes nothing. A *view stack* moves the work to build time: the
figure's unchanging part (axes, grid, obstacles, an occupancy image) is drawn once as a PNG, and
for every combination of the controls' values the part that changes (the arm, a point, a tree, a
title) is drawn by the same :mod:`rapp.plotting` functions and saved as a small transparent SVG
overlay. The overlays sit in nested ``Stack`` widgets whose ``selected_index`` is ``jslink``-ed to
the sliders' ``index``: the browser switches views itself, offline, in the book as in JupyterLab.

Each overlay holds only what changed, through matplotlib's own SVG renderer, so a 2-joint explorer
with 19 x 19 views costs about a megabyte of page and a second or two to build.

Examples
--------
>>> from matplotlib.figure import Figure
>>> fig = Figure(figsize=(3, 3))
>>> ax = fig.add_subplot()
>>> ax.set_xlim(0, 1); ax.set_ylim(0, 1)
(0.0, 1.0)
(0.0, 1.0)
>>> def view(x):
...     ax.plot([x], [0.5], "o")
...     return f"x = {x:.1f}"
>>> w = view_stack(fig, {"x": Control("x", [0.1, 0.5, 0.9], default=0.5)}, view)
>>> [s.index for s in sliders_of(w)], len(overlays_of(w).children)
([1], 3)
"""

from __future__ import annotations

import html
import io
import itertools
import re
import zlib
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import ipywidgets as widgets
import matplotlib
import numpy as np
from ipywidgets.widgets.widget_string import HTMLStyle
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.backends.backend_svg import RendererSVG
from PIL import Image
from PIL.PngImagePlugin import PngInfo

from rapp.plotting import smallest_text_px

__all__ = ["Control", "view_stack", "sliders_of", "overlays_of", "statuses_of", "selected",
           "values_of", "render_overlay"]

# SVG is measured in points; drawing both layers at 72 dpi makes a point a pixel of the PNG.
_DPI = 72
_WIDTH = "720px"


@dataclass(frozen=True)
class Control:
    """One slider: its label and the values it steps through.

    Attributes
    ----------
    description : str
        The slider's label, with the unit, e.g. ``"θ1 (rad)"``.
    values : sequence
        The values in slider order.
    default : object, optional
        The value shown first (the nearest one when not in ``values``); the middle one when None.
    fmt : str
        How the slider prints a value. A value that prints as zero prints without a minus sign
        (``-1e-17`` and ``-0.0`` read ``0.00``, not ``-0.00``).

    Examples
    --------
    >>> Control("x (m)", [-0.3, -0.0, -1e-17, 0.3]).labels()
    ['-0.30', '0.00', '0.00 (1)', '0.30']
    """

    description: str
    values: Sequence[Any]
    default: Any = None
    fmt: str = "{:.2f}"

    def labels(self) -> list[str]:
        out = []
        for v in self.values:
            try:
                text = self.fmt.format(v)
            except (TypeError, ValueError):
                text = str(v)
            # "-0.00" is a rounding artefact of a value that is zero to the digits shown
            if text.startswith("-") and "0" in text and text.strip("-0.") == "":
                text = text[1:]
            out.append(text)
        # SelectionSlider needs distinct labels.
        seen: dict[str, int] = {}
        for i, text in enumerate(out):
            if text in seen:
                seen[text] += 1
                out[i] = f"{text} ({seen[text]})"
            else:
                seen[text] = 0
        return out

    def default_index(self) -> int:
        if self.default is None:
            return len(self.values) // 2
        for i, v in enumerate(self.values):
            if v is self.default or _equal(v, self.default):
                return i
        try:
            return int(np.argmin([abs(float(v) - float(self.default)) for v in self.values]))
        except (TypeError, ValueError):
            return 0


def _equal(a, b) -> bool:
    try:
        return bool(np.all(np.asarray(a) == np.asarray(b)))
    except Exception:
        return False


def _dynamic_artists(fig, before: dict) -> list:
    """Artists added since ``before``, plus titles whose text changed, in drawing order."""
    found = []
    for ax in fig.axes:
        old = before.get(id(ax), set())
        for artist in ax.get_children():
            if id(artist) not in old and artist.get_visible():
                found.append(artist)
        for title in (ax.title, ax._left_title, ax._right_title):
            if title.get_text():
                found.append(title)
    found.extend(t for t in fig.texts if id(t) not in before.get("fig", set()))
    found.extend(lg for lg in fig.legends if id(lg) not in before.get("fig", set()))
    return sorted(found, key=lambda a: a.get_zorder())


def _snapshot(fig) -> dict:
    snap = {id(ax): {id(a) for a in ax.get_children()} for ax in fig.axes}
    snap["fig"] = {id(t) for t in [*fig.texts, *fig.legends]}
    return snap


def _clear(fig, artists) -> None:
    for artist in artists:
        if any(artist is t for ax in fig.axes for t in (ax.title, ax._left_title, ax._right_title)):
            artist.set_text("")
            continue
        if artist.axes is not None and artist is artist.axes.legend_:
            artist.axes.legend_ = None
        artist.remove()


def render_overlay(fig, artists) -> str:
    """The given artists of ``fig`` as an SVG the size of the figure, transparent elsewhere.

    The figure must have been drawn once at 72 dpi (layout fixed), as :func:`view_stack` does.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(2, 1), dpi=72); ax = fig.add_subplot()
    >>> FigureCanvasAgg(fig).draw()
    >>> line, = ax.plot([0, 1], [0, 1])
    >>> svg = render_overlay(fig, [line])
    >>> svg.startswith("<svg") and "viewBox=\\"0 0 144 72\\"" in svg
    True
    """
    w, h = fig.get_size_inches() * _DPI
    buf = io.StringIO()
    # Text as <text> elements, not glyph outlines: a tenth of the bytes.
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        renderer = RendererSVG(w, h, buf, basename=None, image_dpi=_DPI)
        for artist in artists:
            artist.draw(renderer)
        renderer.finalize()
    svg = buf.getvalue()
    svg = svg[svg.index("<svg"):]
    # Scale with the page like the PNG under it: the viewBox keeps the geometry.
    svg = re.sub(r'<svg([^>]*?) width="[^"]*" height="[^"]*"',
                 r'<svg\1 width="100%" height="100%"', svg, count=1)
    svg = re.sub(r"<metadata>.*?</metadata>", "", svg, flags=re.S)
    svg = re.sub(r"<!--.*?-->", "", svg, flags=re.S)
    svg = re.sub(r'<g id="[^"]*">', "<g>", svg)
    # A hundredth of a pixel is finer than any screen: shorter numbers, same picture.
    svg = re.sub(r"(\d\.\d\d)\d+", r"\1", svg)
    # Ids must be unique in a page that holds hundreds of overlays.
    tag = f"v{zlib.crc32(svg.encode()):x}"
    svg = re.sub(r'id="([^"]+)"', lambda m: f'id="{tag}{m.group(1)}"', svg)
    svg = re.sub(r'url\(#([^)]+)\)', lambda m: f"url(#{tag}{m.group(1)})", svg)
    svg = re.sub(r'xlink:href="#([^"]+)"', lambda m: f'xlink:href="#{tag}{m.group(1)}"', svg)
    return " ".join(svg.split())


def _png(fig, text_px=None) -> bytes:
    """The figure as a palette PNG: line art compresses four times smaller, no visible change.

    ``text_px``, the smallest text of every view in pixels of the image, is kept in the PNG
    (``rapp:text-px``) for the book check, which scales it by the width the page shows.
    """
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=_DPI, facecolor="white")
    img = Image.open(io.BytesIO(buf.getvalue())).convert("RGB").quantize(colors=64, dither=Image.Dither.NONE)
    chunks = PngInfo()
    chunks.add_text("rapp:dpi", f"{_DPI:g}")
    chunks.add_text("rapp:text-px", "" if text_px is None else f"{text_px:.2f}")
    out = io.BytesIO()
    img.save(out, format="PNG", optimize=True, pnginfo=chunks)
    return out.getvalue()


def _nested(sizes: Sequence[int], leaf: Callable[[tuple], widgets.Widget], sliders, links: list,
            prefix: tuple = ()) -> widgets.Widget:
    """Stacks nested one level per slider; each level's ``selected_index`` follows its slider."""
    depth = len(prefix)
    if depth == len(sizes):
        return leaf(prefix)
    stack = widgets.Stack([_nested(sizes, leaf, sliders, links, prefix + (i,))
                           for i in range(sizes[depth])],
                          selected_index=sliders[depth].index)
    links.append(widgets.jslink((sliders[depth], "index"), (stack, "selected_index")))
    return stack


def view_stack(fig, controls: Mapping[str, Control], view: Callable[..., str], *,
               title: str = "") -> widgets.VBox:
    """An explorer whose every view is drawn in advance (see the module docstring).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Holds the static part already (axes, limits, labels, images that never change).
    controls : mapping of str to Control
        The keyword each control passes to ``view``, and its values.
    view : callable
        ``view(**values)`` draws what changes into ``fig``'s axes (new artists, titles) and
        returns the status line (HTML). It must not add axes. It is called once per
        combination of values, plus once to find what changes. Axis limits are those the
        caller set, else those of the default view: set them to cover every view.
    title : str
        Shown above the controls.

    Returns
    -------
    ipywidgets.VBox
        Title, sliders, status, and the figure: a PNG under the ``Stack`` of overlays.
    """
    names = list(controls)
    sliders = []
    for name in names:
        c = controls[name]
        sliders.append(widgets.SelectionSlider(
            options=c.labels(), index=c.default_index(), description=c.description,
            continuous_update=True, layout=widgets.Layout(width="420px"),
            style={"description_width": "110px"}))
    fig.set_dpi(_DPI)
    canvas = FigureCanvasAgg(fig)

    def draw(index: tuple) -> tuple[str, str]:
        values = {n: controls[n].values[i] for n, i in zip(names, index)}
        before = _snapshot(fig)
        status = view(**values)
        for ax, (xlim, ylim) in zip(fig.axes, frozen):  # a view that set limits drew on its own axes
            ax.set_xlim(xlim)
            ax.set_ylim(ylim)
        artists = _dynamic_artists(fig, before)
        svg = render_overlay(fig, artists)
        _clear(fig, artists)
        return svg, status

    # One call to learn what changes. Drawn with it, the figure takes its layout and, where the
    # caller set none, its axis limits from the default view; both are then frozen, so every
    # overlay lines up with the axes of the background, which is drawn without it.
    first = tuple(s.index for s in sliders)
    before = _snapshot(fig)
    view(**{n: controls[n].values[i] for n, i in zip(names, first)})
    canvas.draw()
    text_px = smallest_text_px(fig, _DPI)  # the first view's own text (titles) included
    fig.set_layout_engine("none")
    frozen = [(ax.get_xlim(), ax.get_ylim()) for ax in fig.axes]
    for ax in fig.axes:
        ax.set_autoscale_on(False)
    _clear(fig, _dynamic_artists(fig, before))
    background = _png(fig, text_px)

    sizes = [len(controls[n].values) for n in names]
    drawn = {index: draw(index) for index in itertools.product(*map(range, sizes))}
    # One layout and one style shared by every leaf: hundreds of views, a handful of models.
    overlay_layout = widgets.Layout(grid_area="figure", width="100%", height="100%")
    status_layout = widgets.Layout(min_height="1.6em")
    style = HTMLStyle()
    links: list = []
    overlays = _nested(sizes, lambda i: widgets.HTML(drawn[i][0], layout=overlay_layout, style=style),
                       sliders, links)
    statuses = _nested(sizes, lambda i: widgets.HTML(drawn[i][1], layout=status_layout, style=style),
                       sliders, links)
    overlays.layout = widgets.Layout(grid_area="figure")
    image = widgets.Image(value=background, format="png",
                          layout=widgets.Layout(grid_area="figure", width="100%", height="auto"))
    w_px = int(round(fig.get_size_inches()[0] * _DPI))
    figure = widgets.GridBox(
        [image, overlays],
        layout=widgets.Layout(grid_template_areas='"figure"', width=f"min(100%, {w_px}px)"))
    head = [widgets.HTML(f"<b>{html.escape(title)}</b>")] if title else []
    box = widgets.Box(sliders, layout=widgets.Layout(display="flex", flex_flow="row wrap"))
    out = widgets.VBox(head + [box, statuses, figure])
    out._links = links  # keep the links alive as long as the explorer (they are widgets too)
    out._controls = dict(controls)
    return out


def values_of(widget) -> dict:
    """The values the sliders of a view stack select now, by keyword.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(2, 2)); ax = fig.add_subplot()
    >>> w = view_stack(fig, {"k": Control("k", [1.25, 2.5], default=2.5)}, lambda k: "")
    >>> values_of(w)
    {'k': 2.5}
    """
    controls = widget._controls
    return {name: c.values[s.index] for (name, c), s in zip(controls.items(), sliders_of(widget))}


def sliders_of(widget) -> list:
    """The SelectionSliders of a view stack, in order."""
    if isinstance(widget, widgets.SelectionSlider):
        return [widget]
    return [s for child in getattr(widget, "children", ()) for s in sliders_of(child)]


def overlays_of(widget):
    """The outer Stack of overlays (inside the figure's GridBox)."""
    for child in getattr(widget, "children", ()):
        if isinstance(child, widgets.GridBox):
            return child.children[1]
        found = overlays_of(child)
        if found is not None:
            return found
    return None


def statuses_of(widget):
    """The outer Stack of status lines."""
    kids = [c for c in getattr(widget, "children", ()) if isinstance(c, (widgets.Stack, widgets.HTML))]
    stacks = [c for c in kids if isinstance(c, widgets.Stack)]
    return stacks[0] if stacks else None


def selected(widget) -> tuple[str, str]:
    """The overlay SVG and the status HTML the sliders select now (what a reader sees).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(2, 2)); ax = fig.add_subplot()
    >>> w = view_stack(fig, {"k": Control("k", [1, 2], default=2, fmt="{}")},
    ...                lambda k: ax.plot([0, k]) and f"k={k}")
    >>> selected(w)[1]
    'k=2'
    """
    # Links act in the browser; in Python, follow the sliders' indices directly.
    idx = [s.index for s in sliders_of(widget)]

    def follow(stack):
        node = stack
        for i in idx:
            node = node.children[i]
        return node.value

    return follow(overlays_of(widget)), follow(statuses_of(widget))

