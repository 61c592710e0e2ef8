"""The plan figure drawn with Pillow: C-space beside workspace, as a PNG, without matplotlib.

:func:`render_plan` draws what :func:`rapp.plotting.plot_plan` draws, in the
same colours (:mod:`rapp.palette`) and layout: a 1050 x 500 pixel image (the
matplotlib figure is 10.5 x 5 inches at 100 dpi), white, two framed panels
with titles, axis labels, ticks and legends. Left, the occupancy of the
plan's joint grid (grey level: the fraction of the other joints' values in
collision when there are more than two joints) or the joint space alone for
a sampling planner, with the joint path, start and goal; right, the
workspace annulus, the obstacles, ghost arms along the path, the end-effector
trace, the start and final arms and the Cartesian goal.

Why a second renderer: importing matplotlib takes about 0.8 s, twice what
``python -m rapp plan`` takes in all, so the command line's ``--plot fig.png``
could not stay within 1.6 times of a plan without a figure. Pillow (a
dependency of matplotlib, so always installed with it) imports in about
40 ms. Vector formats (SVG, PDF, ...) are still matplotlib's.

Each panel's contents (and its legend's box and symbols) are drawn three
times larger and reduced by averaging (supersampling), so lines and discs are
antialiased; frames and ticks lie on whole pixels and text is drawn at the
final size, where FreeType antialiases it crisply. Lengths given in points
(line widths, marker sizes) follow matplotlib's: a point is 100/72 pixels.

:func:`plan_panels` returns where each panel lies and how data coordinates
map to pixels (:class:`Panel`), so a caller (or a test) can find what was
drawn where.

Examples
--------
>>> from rapp import load_scenario, plan
>>> s = load_scenario("default")
>>> image = render_plan(plan(s), s)
>>> image.size, image.mode
((1050, 500), 'RGB')
"""

from __future__ import annotations

import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageColor, ImageDraw, ImageFont

from rapp.cspace import cell_extent
from rapp.palette import ARM, COLORS, EFFECTOR, GOAL, OBSTACLE, OCCUPIED, PATH, START, TEXT
from rapp.paths import even_indices, split_at_seam

__all__ = ["WIDTH", "HEIGHT", "Panel", "plan_panels", "render_plan", "save_plan", "pi_ticks",
           "nice_ticks"]

#: Size of the image in pixels: matplotlib's 10.5 x 5 inch figure at 100 dpi.
WIDTH, HEIGHT = 1050, 500
#: Lines are drawn this many times larger, then the image is reduced by averaging.
SUPERSAMPLE = 3
#: Pixels per typographic point at 100 dpi, to size lines and markers as matplotlib does.
PT = 100 / 72

# Margins of each half of the image around its panel's frame (pixels): room for the title
# above, the tick labels and axis label below and on the left.
_MARGIN_LEFT, _MARGIN_RIGHT, _MARGIN_TOP, _MARGIN_BOTTOM = 78, 14, 28, 50
_FONT_SIZE, _LEGEND_FONT_SIZE = 14, 12  # 10 pt and matplotlib's "small" (8.3 pt) at 100 dpi
_TICK = 5  # tick length (pixels), outward as in matplotlib
_GRID = "#e6e6e6"  # the workspace's grid lines
_LEGEND_EDGE = "#bbbbbb"
_WHITE = (255, 255, 255)


@dataclass(frozen=True)
class Panel:
    """Where a panel lies in the image and how its data coordinates map to pixels.

    The drawing area is the pixels ``left <= column < right``,
    ``top <= row < bottom``; its frame lies on the pixels just outside.
    ``xlim`` maps to the left and right edges, ``ylim`` to the bottom and
    top edges (y grows upwards). Both axes have the same scale (equal
    aspect).

    Examples
    --------
    >>> p = Panel(10, 20, 110, 70, (-2.0, 2.0), (-1.0, 1.0))
    >>> p.to_pixel([[-2.0, 1.0], [0.0, 0.0], [2.0, -1.0]]).tolist()
    [[10.0, 20.0], [60.0, 45.0], [110.0, 70.0]]
    >>> p.scale
    25.0
    """

    left: int
    top: int
    right: int
    bottom: int
    xlim: tuple
    ylim: tuple

    @property
    def scale(self) -> float:
        """Pixels per data unit (the same on both axes)."""
        return (self.right - self.left) / (self.xlim[1] - self.xlim[0])

    def to_pixel(self, xy) -> np.ndarray:
        """Pixel coordinates ``(column, row)`` of data points ``(..., 2)``, as floats.

        The pixel holding a point is ``np.floor`` of its coordinates.
        """
        xy = np.asarray(xy, dtype=float)
        u = self.left + (xy[..., 0] - self.xlim[0]) * self.scale
        v = self.bottom - (xy[..., 1] - self.ylim[0]) * self.scale
        return np.stack((u, v), axis=-1)


def pi_ticks(lo: float, hi: float) -> list:
    """Ticks ``(value, label)`` at the multiples of pi/2 within ``[lo, hi]``; empty if fewer than 2.

    Examples
    --------
    >>> [label for _, label in pi_ticks(-np.pi, np.pi)]
    ['−π', '−π/2', '0', 'π/2', 'π']
    >>> pi_ticks(0.0, 1.0)
    []
    """
    k = np.arange(np.ceil(lo / (np.pi / 2) - 1e-9), np.floor(hi / (np.pi / 2) + 1e-9) + 1)
    names = {-4: "−2π", -3: "−3π/2", -2: "−π", -1: "−π/2", 0: "0", 1: "π/2", 2: "π",
             3: "3π/2", 4: "2π"}
    if len(k) < 2:
        return []
    return [(float(i * np.pi / 2), names.get(int(i), f"{i / 2:g}π")) for i in k]


def nice_ticks(lo: float, hi: float, most: int = 7) -> list:
    """Ticks ``(value, label)`` at round numbers within ``[lo, hi]``: at most ``most`` of them.

    The step is 1, 2, 2.5 or 5 times a power of ten, the smallest that keeps
    the count within ``most``; labels use a true minus sign, as matplotlib's.

    Examples
    --------
    >>> [label for _, label in nice_ticks(-2.42, 2.42)]
    ['−2', '−1', '0', '1', '2']
    >>> [label for _, label in nice_ticks(0.0, 0.6)]
    ['0.0', '0.1', '0.2', '0.3', '0.4', '0.5', '0.6']
    """
    span = hi - lo
    if not span > 0:
        return [(float(lo), _number(lo, 0))]
    base = 10.0 ** math.floor(math.log10(span / most))
    for m in (1, 2, 2.5, 5, 10, 20):
        step = m * base
        first, last = math.ceil(lo / step - 1e-9), math.floor(hi / step + 1e-9)
        if last - first + 1 <= most:
            break
    digits = max(0, -math.floor(math.log10(step) + 1e-9)) + (m in (2.5,) and step < 10)
    return [(i * step, _number(i * step, digits)) for i in range(first, last + 1)]


def _number(value: float, digits: int) -> str:
    text = f"{value:.{digits}f}"
    if float(text) == 0:
        text = text.lstrip("-")
    return text.replace("-", "−")


# --------------------------------------------------------------------------- layout


def _cspace_frame(plan, arm):
    """Limits, seam data and occupancy of the C-space panel (None: no grid)."""
    grid = getattr(plan, "grid", None)
    occ = getattr(plan, "occupancy", None)
    if grid is not None and occ is not None and np.ndim(occ) >= 2:
        ext = cell_extent(grid)
        lo = np.array([ext[0], ext[2]])
        span = np.array([ext[1] - ext[0], ext[3] - ext[2]])
        return lo, span, np.asarray(grid.wraps[:2], dtype=bool), np.asarray(occ)
    lo, hi = np.asarray(arm.lower[:2], dtype=float), np.asarray(arm.upper[:2], dtype=float)
    return lo, hi - lo, ~np.asarray(arm.limited[:2], dtype=bool), None


def _workspace_half_width(arm, obstacles) -> float:
    """Half the side of the square workspace frame: the reach and 10 %, grown to hold every
    obstacle with 5 % to spare (obstacles often stand at the edge of the reach, and they are
    what the reader looks at). The same rule as rapp.plotting's frame, which measures its
    patches: the largest coordinate, not the distance from the base."""
    r = arm.reach[1] * 1.1
    for ob in obstacles:
        if hasattr(ob, "radius"):
            far = np.abs(np.asarray(ob.center, dtype=float)).max() + ob.radius
        else:
            far = np.abs(np.asarray(ob.vertices, dtype=float)).max()
        r = max(r, 1.05 * float(far))
    return r


def _fit(half: int, xlim, ylim) -> Panel:
    """The largest equal-aspect panel for these limits in half ``half`` (0 left, 1 right)."""
    x0 = half * WIDTH // 2 + _MARGIN_LEFT
    x1 = (half + 1) * WIDTH // 2 - _MARGIN_RIGHT
    y0, y1 = _MARGIN_TOP, HEIGHT - _MARGIN_BOTTOM
    sx, sy = xlim[1] - xlim[0], ylim[1] - ylim[0]
    scale = min((x1 - x0) / sx, (y1 - y0) / sy)
    w, h = int(round(sx * scale)), int(round(sy * scale))
    left, top = x0 + (x1 - x0 - w) // 2, y0 + (y1 - y0 - h) // 2
    # Whole pixels keep the frame crisp; the limits absorb the rounding so the scale stays equal.
    cx, cy = (xlim[0] + xlim[1]) / 2, (ylim[0] + ylim[1]) / 2
    scale = min(w / sx, h / sy)
    xlim = (cx - w / scale / 2, cx + w / scale / 2)
    ylim = (cy - h / scale / 2, cy + h / scale / 2)
    return Panel(left, top, left + w, top + h, xlim, ylim)


def plan_panels(plan, scenario) -> tuple:
    """The C-space and workspace panels of :func:`render_plan`'s image for this plan.

    Returns
    -------
    (Panel, Panel)
        Left: joint 1 on x, joint 2 on y (radians), limits the cell edges of
        ``plan.grid`` or, without a grid, the joint bounds. Right: x and y in
        the scenario's length unit, a square around the reach and the
        obstacles.

    Examples
    --------
    >>> from rapp import load_scenario, plan
    >>> s = load_scenario("default")
    >>> cspace, workspace = plan_panels(plan(s), s)
    >>> workspace.to_pixel([0.0, 0.0]).round().tolist()   # the base, in the right panel's middle
    [819.0, 239.0]
    """
    lo, span, _, _ = _cspace_frame(plan, scenario.arm)
    r = _workspace_half_width(scenario.arm, scenario.obstacles)
    return (_fit(0, (lo[0], lo[0] + span[0]), (lo[1], lo[1] + span[1])),
            _fit(1, (-r, r), (-r, r)))


# --------------------------------------------------------------------------- drawing helpers


def _rgb(color) -> tuple:
    return ImageColor.getrgb(color)[:3]


def _rgba(color, alpha: float) -> tuple:
    return _rgb(color) + (int(round(255 * alpha)),)


class _Layer:
    """A panel's drawing area, SUPERSAMPLE times larger; whatever leaves it is clipped."""

    def __init__(self, panel: Panel, background=None):
        """``background``: an RGB image of ``_Layer.size(panel)`` to draw on, else white."""
        self.panel = panel
        self.image = background if background is not None else Image.new("RGB", self.size(panel),
                                                                           _WHITE)
        # "RGBA" on an RGB image blends translucent ink into what is drawn already.
        self.draw = ImageDraw.Draw(self.image, "RGBA")

    @staticmethod
    def size(panel: Panel) -> tuple:
        return ((panel.right - panel.left) * SUPERSAMPLE, (panel.bottom - panel.top) * SUPERSAMPLE)

    def xy(self, data) -> np.ndarray:
        """Data points -> supersampled layer coordinates."""
        p = self.panel.to_pixel(data)
        return (p - (self.panel.left, self.panel.top)) * SUPERSAMPLE

    def polyline(self, data, color, lw_pt, round_ends=True):
        """A line through ``data`` (k, 2), broken at rows of NaN; width in points."""
        pts = self.xy(np.asarray(data, dtype=float).reshape(-1, 2))
        width = max(1, int(round(lw_pt * PT * SUPERSAMPLE)))
        ok = np.isfinite(pts).all(axis=1)
        # Runs of finite rows: one line each, so no segment joins across a seam.
        edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(int), [0]))))
        for a, b in zip(edges[::2], edges[1::2]):
            run = [tuple(p) for p in pts[a:b]]
            if len(run) > 1:
                self.draw.line(run, fill=color, width=width, joint="curve")
            if round_ends:
                for p in (run[0], run[-1]):
                    self.disc_px(p, width / 2, color)

    def disc_px(self, centre, radius, fill, outline=None, edge=0):
        x, y = centre
        self.draw.ellipse((x - radius, y - radius, x + radius, y + radius), fill=fill,
                          outline=outline, width=int(round(edge)))

    def marker(self, data, kind, size_pt, fill, edge_color=None, edge_pt=0.0):
        """A matplotlib-like marker centred on the data point: "o", "s" or "*"."""
        self.marker_px(self.xy(data), kind, size_pt, fill, edge_color, edge_pt)

    def marker_px(self, centre, kind, size_pt, fill, edge_color=None, edge_pt=0.0):
        """:meth:`marker` at a point of the layer (supersampled pixels), as legends place them."""
        x, y = centre
        r = size_pt * PT * SUPERSAMPLE / 2
        e = edge_pt * PT * SUPERSAMPLE
        if kind == "o":
            self.disc_px((x, y), r + e / 2, edge_color or fill)
            if edge_color is not None:
                self.disc_px((x, y), r - e / 2, fill)
        elif kind == "s":
            self.draw.rectangle((x - r, y - r, x + r, y + r), fill=fill)
        else:  # a five-pointed star, point up, inner radius as matplotlib's
            star = _star(x, y, r)
            if edge_color is not None:
                self.draw.polygon(_star(x, y, r + e * 0.8), fill=edge_color)
            self.draw.polygon(star, fill=fill)


def _star(x, y, r):
    a = np.pi / 2 + np.arange(10) * np.pi / 5
    rad = np.where(np.arange(10) % 2 == 0, r, 0.381966 * r)
    return [(x + rr * math.cos(t), y - rr * math.sin(t)) for rr, t in zip(rad, a)]


def _dashed_circle(layer: _Layer, radius, color, lw_pt, dash_pt):
    """A circle of data radius ``radius`` round the origin, dashed as (on, off) points x lw."""
    cx, cy = layer.xy([0.0, 0.0])
    r = radius * layer.panel.scale * SUPERSAMPLE
    on, off = (d * lw_pt * PT * SUPERSAMPLE for d in dash_pt)
    n = max(1, int(round(2 * np.pi * r / (on + off))))
    width = max(1, int(round(lw_pt * PT * SUPERSAMPLE)))
    # Each dash a short polyline: far faster than ImageDraw.arc, which walks the whole ellipse.
    t = (np.arange(n)[:, None] + np.linspace(0.0, on / (on + off), 4)[None]) * (2 * np.pi / n)
    for a in t:
        layer.draw.line(list(zip(cx + r * np.cos(a), cy - r * np.sin(a))), fill=color,
                        width=width)


def _fonts():
    """DejaVu Sans (matplotlib's default font, found without importing matplotlib) at the two
    sizes; Pillow's own font when matplotlib's files are not there."""
    path = None
    try:
        spec = importlib.util.find_spec("matplotlib")
    except (ImportError, ValueError):
        spec = None
    for folder in (spec.submodule_search_locations or []) if spec is not None else []:
        candidate = Path(folder, "mpl-data", "fonts", "ttf", "DejaVuSans.ttf")
        if candidate.is_file():
            path = candidate
            break
    fonts = []
    for size in (_FONT_SIZE, _LEGEND_FONT_SIZE):
        try:
            fonts.append(ImageFont.truetype(str(path), size) if path else
                         ImageFont.load_default(size=size))
        except OSError:
            fonts.append(ImageFont.load_default(size=size))
    return tuple(fonts)


# --------------------------------------------------------------------------- legends

# A legend entry: (label, handle), the handle one of
#   ("line", color, lw_pt, marker or None, marker fill)    ("patch", fill, alpha, edge or None)
#   ("marker", kind, size_pt, fill, edge color, edge_pt)


def _legend_box(panel: Panel, entries, font, ink) -> tuple:
    """The legend's box (final pixels) in the corner of ``panel`` that covers the fewest of
    ``ink`` (pixel points of the plan), upper right first on a tie, as matplotlib's "best"."""
    row = int(round(_LEGEND_FONT_SIZE * 1.5))
    pad, handle, gap = 6, 26, 8
    w = pad * 2 + handle + gap + int(max(font.getlength(label) for label, _ in entries))
    h = pad * 2 + row * len(entries)
    inset = 6
    boxes = [(panel.right - inset - w, panel.top + inset), (panel.left + inset, panel.top + inset),
             (panel.left + inset, panel.bottom - inset - h),
             (panel.right - inset - w, panel.bottom - inset - h)]
    ink = np.asarray(ink, dtype=float).reshape(-1, 2)

    def covered(box):
        x, y = box
        return int(np.count_nonzero((ink[:, 0] >= x - 3) & (ink[:, 0] <= x + w + 3)
                                    & (ink[:, 1] >= y - 3) & (ink[:, 1] <= y + h + 3)))

    x, y = min(boxes, key=covered)  # min keeps the first of equals
    return x, y, w, h, row, pad, handle, gap


def _draw_legend_handles(layer: _Layer, layout, entries):
    """Box and handles, drawn on the panel's layer (so they are antialiased and clipped with
    it); the labels come later, at the final size."""
    x, y, w, h, row, pad, handle, gap = layout
    S = SUPERSAMPLE
    x, y = x - layer.panel.left, y - layer.panel.top
    draw = layer.draw
    # 90 % opaque, as matplotlib's legend (framealpha=0.9): what lies under it shows faintly.
    draw.rounded_rectangle((x * S, y * S, (x + w) * S, (y + h) * S), radius=3 * S,
                           fill=(255, 255, 255, 230), outline=_rgb(_LEGEND_EDGE), width=S)
    for i, (_, spec) in enumerate(entries):
        cy = (y + pad + row * i + row / 2) * S
        x0, x1 = (x + pad) * S, (x + pad + handle) * S
        cx = (x0 + x1) / 2
        kind = spec[0]
        if kind == "line":
            _, color, lw, marker, mfill = spec
            draw.line([(x0, cy), (x1, cy)], fill=_rgb(color), width=int(round(lw * PT * S)))
            if marker:  # the joints' marker of plot_arm
                layer.marker_px((cx, cy), marker, 6, _rgb(mfill), _rgb(color), 1.5)
        elif kind == "patch":
            _, fill, alpha, edge = spec
            hh = 0.35 * _LEGEND_FONT_SIZE * S
            draw.rectangle((x0, cy - hh, x1, cy + hh), fill=_WHITE)
            draw.rectangle((x0, cy - hh, x1, cy + hh), fill=_rgba(fill, alpha),
                           outline=_rgba(edge, alpha) if edge else None, width=S)
        else:
            _, mk, size, fill, edge, edge_pt = spec
            layer.marker_px((cx, cy), mk, size, _rgb(fill), _rgb(edge), edge_pt)


def _draw_legend_labels(draw, layout, entries, font):
    x, y, w, h, row, pad, handle, gap = layout
    for i, (label, _) in enumerate(entries):
        draw.text((x + pad + handle + gap, y + pad + row * i + row / 2), label, font=font,
                  fill=_rgb(TEXT), anchor="lm")


# --------------------------------------------------------------------------- the panels


def _densify(points_px, spacing=3.0) -> np.ndarray:
    """Points every ``spacing`` pixels along a polyline (NaN rows break it): ink to keep clear."""
    p = np.asarray(points_px, dtype=float).reshape(-1, 2)
    a, b = p[:-1], p[1:]
    ok = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
    a, b = a[ok], b[ok]
    k = np.maximum(1, (np.hypot(*(b - a).T) // spacing).astype(int))  # points per segment
    seg = np.repeat(np.arange(len(a)), k)
    t = (np.arange(seg.size) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k, k)
    return np.concatenate((p[np.isfinite(p).all(axis=1)], a[seg] + t[:, None] * (b - a)[seg]))


def _occupancy_image(occ, size) -> Image.Image:
    """The occupancy as an RGB image of ``size``, joint 1 along x, joint 2 up, one block a cell."""
    occ = np.asarray(occ)
    if occ.ndim == 2:
        rgb = np.where(occ.T[::-1, :, None], np.array(_rgb(OCCUPIED), np.uint8),
                       np.array(_WHITE, np.uint8)).astype(np.uint8)
        image = Image.fromarray(rgb, "RGB")
    else:
        # Grey level = fraction of the other joints' grid values in collision: white none,
        # black all (plot_cspace's "Greys" map, made linear so the level reads as the fraction).
        frac = occ.reshape(occ.shape[:2] + (-1,)).mean(axis=-1)
        grey = np.round(255.0 * (1.0 - frac.T[::-1])).astype(np.uint8)
        image = Image.fromarray(grey, "L").convert("RGB")
    return image.resize(size, Image.Resampling.NEAREST)


def _cspace(panel: Panel, plan, scenario):
    """Layer, title and legend entries of the C-space panel, and the ink for legend placement."""
    arm = scenario.arm
    lo, span, wraps, occ = _cspace_frame(plan, arm)
    layer = _Layer(panel, None if occ is None else _occupancy_image(occ, _Layer.size(panel)))
    if occ is not None:
        if occ.ndim == 2:
            title = "C-space: grey = collision"
        else:
            rest = ", ".join(f"θ{i + 1}" for i in range(2, occ.ndim))
            title = f"projection over {rest}: fraction in collision"
    else:
        title = "joint space"  # a sampling planner: no grid, the joint path alone
    q = np.asarray(plan.q, dtype=float)
    seg = split_at_seam(q[:, :2], lo, span, wraps)
    layer.polyline(seg, _rgb(PATH), 2.0)
    start = split_at_seam(q[0, :2], lo, span, wraps)[0]
    goal = split_at_seam(q[-1, :2], lo, span, wraps)[0]
    # Sizes as plot_cspace's: start ms 8, goal ms 11, both edged in white.
    layer.marker(start, "o", 8, _rgb(START), _WHITE, 1.0)
    layer.marker(goal, "*", 11, _rgb(GOAL), _WHITE, 1.0)
    entries = [("path", ("line", PATH, 2.0, None, None)),
               ("start", ("marker", "o", 8, START, "#ffffff", 1.0)),
               ("goal", ("marker", "*", 11, GOAL, "#ffffff", 1.0))]
    ink = np.concatenate([_densify(panel.to_pixel(seg)), panel.to_pixel([start, goal])])
    return layer, title, entries, ink


def _arm_markers(layer: _Layer, pts, color):
    """The markers of an arm as plot_arm draws them: white joints, dark base, effector dot.

    Its links (3 pt wide) are drawn separately: they lie under the end-effector trace, the
    markers over it."""
    for p in pts:
        layer.marker(p, "o", 6, _WHITE, _rgb(color), 1.5)
    layer.marker(pts[0], "s", 9, _rgb(TEXT))
    layer.marker(pts[-1], "o", 7, _rgb(EFFECTOR))


def _workspace(panel: Panel, plan, scenario, ghosts: int):
    arm = scenario.arm
    layer = _Layer(panel)
    S = SUPERSAMPLE
    # Grid lines first: everything else is drawn over them (matplotlib's axisbelow).
    for value, _ in nice_ticks(*panel.xlim):
        col = (math.floor(panel.to_pixel([value, 0.0])[0]) - panel.left) * S
        layer.draw.rectangle((col, 0, col + S - 1, layer.image.height), fill=_rgb(_GRID))
    for value, _ in nice_ticks(*panel.ylim):
        row = (math.floor(panel.to_pixel([0.0, value])[1]) - panel.top) * S
        layer.draw.rectangle((0, row, layer.image.width, row + S - 1), fill=_rgb(_GRID))
    # The reachable annulus, 18 % sky blue over the grid: a mask, so the hole stays untouched.
    r_min, r_max = arm.reach
    cx, cy = layer.xy([0.0, 0.0])
    ro, ri = r_max * panel.scale * S, r_min * panel.scale * S
    box = (int(cx - ro) - 1, int(cy - ro) - 1, int(cx + ro) + 2, int(cy + ro) + 2)
    mask = Image.new("L", (box[2] - box[0], box[3] - box[1]), 0)
    md = ImageDraw.Draw(mask)
    x, y = cx - box[0], cy - box[1]
    md.ellipse((x - ro, y - ro, x + ro, y + ro), fill=int(round(0.18 * 255)))
    if r_min > 0:
        md.ellipse((x - ri, y - ri, x + ri, y + ri), fill=0)
    layer.image.paste(_rgb(COLORS["sky"]), box, mask)
    blue = _rgb(COLORS["blue"])
    _dashed_circle(layer, r_max, blue, 1.0, (3.7, 1.6))
    if r_min > 0:
        _dashed_circle(layer, r_min, blue, 1.0, (1.0, 1.65))
    ink = []
    fill, edge = _rgba(OBSTACLE, 0.85), _rgba(TEXT, 0.85)
    width = max(1, int(round(PT * S)))
    for ob in scenario.obstacles:
        if hasattr(ob, "radius"):
            x, y = layer.xy(ob.center)
            r = ob.radius * panel.scale * S
            layer.draw.ellipse((x - r, y - r, x + r, y + r), fill=fill, outline=edge, width=width)
            t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
            ring = np.stack((np.cos(t), np.sin(t)), axis=-1)
            pts = np.concatenate([np.asarray(ob.center) + f * ob.radius * ring
                                  for f in (1.0, 0.66, 0.33)] + [np.asarray([ob.center])])
            ink.append(panel.to_pixel(pts))
        else:
            v = np.asarray(ob.vertices, dtype=float)
            layer.draw.polygon([tuple(p) for p in layer.xy(v)], fill=fill)
            closed = np.concatenate((v, v[:1]))
            layer.polyline(closed, edge, 1.0, round_ends=False)
            inner = v.mean(axis=0) + np.linspace(0.0, 1.0, 4)[:, None, None] * (v - v.mean(axis=0))
            ink.append(_densify(panel.to_pixel(closed)))
            ink.append(panel.to_pixel(inner.reshape(-1, 2)))
    q = np.asarray(plan.q, dtype=float)
    # Ghosts: a few arms along the path, fading in from the start (plot_plan's ghosts=6).
    idx = even_indices(len(q), ghosts + 2)[1:-1]
    alphas = np.linspace(0.15, 0.6, len(idx))
    ghost_w = max(1, int(round(2.0 * PT * S)))
    for a, pts in zip(alphas, arm.joint_positions(q[idx]).reshape(-1, arm.n + 1, 2)):
        layer.draw.line([tuple(p) for p in layer.xy(pts)], fill=_rgba(ARM, a), width=ghost_w,
                        joint="curve")
        layer.disc_px(layer.xy(pts[-1]), math.sqrt(12.0) * PT * S / 2, _rgba(EFFECTOR, a))
        ink.append(_densify(panel.to_pixel(pts)))
    xy = np.asarray(plan.xy, dtype=float)
    first = arm.joint_positions(q[0])
    last = arm.joint_positions(q[-1])
    # matplotlib's order: links (zorder 3) under the end-effector trace (4) under bases and dots.
    layer.polyline(first, _rgb(START), 3.0)
    layer.polyline(last, _rgb(ARM), 3.0)
    layer.polyline(xy, _rgb(PATH), 2.0)
    _arm_markers(layer, first, START)
    _arm_markers(layer, last, ARM)
    entries = [("workspace", ("patch", COLORS["sky"], 0.18, None)),
               ("obstacle", ("patch", OBSTACLE, 0.85, TEXT)),
               ("end-effector path", ("line", PATH, 2.0, None, None)),
               ("start", ("line", START, 3.0, "o", "#ffffff")),
               ("final", ("line", ARM, 3.0, "o", "#ffffff"))]
    goal_xy = getattr(scenario, "goal_xy", None)
    if goal_xy is not None:
        layer.marker(np.asarray(goal_xy, dtype=float), "*", 14, _rgb(GOAL), _rgb(TEXT), 0.8)
        entries.append(("goal", ("marker", "*", 14, GOAL, TEXT, 0.8)))
        ink.append(panel.to_pixel(np.asarray(goal_xy, dtype=float)[None]))
    ink += [_densify(panel.to_pixel(xy)), _densify(panel.to_pixel(first)),
            _densify(panel.to_pixel(last))]
    return layer, "workspace", entries, np.concatenate(ink)


def _axis_text(image, draw, panel: Panel, title, xlabel, ylabel, xticks, yticks, font):
    """Title, tick labels and axis labels of one panel, at the final size."""
    color = _rgb(TEXT)
    cx = (panel.left + panel.right) / 2
    draw.text((cx, panel.top - 7), title, font=font, fill=color, anchor="md")
    for u, label in xticks:
        draw.text((u + 0.5, panel.bottom + _TICK + 4), label, font=font, fill=color, anchor="mt")
    widest = 0.0
    for v, label in yticks:
        draw.text((panel.left - 1 - _TICK - 4, v + 0.5), label, font=font, fill=color,
                  anchor="rm")
        widest = max(widest, font.getlength(label))
    draw.text((cx, panel.bottom + _TICK + 4 + _FONT_SIZE + 8), xlabel, font=font, fill=color,
              anchor="mt")
    # The y label, turned a quarter to read upwards: drawn on its own mask, then rotated.
    x0, y0, x1, y1 = font.getbbox(ylabel, anchor="lt")
    mask = Image.new("L", (int(x1) + 2, int(y1) + 2), 0)
    ImageDraw.Draw(mask).text((1, 1), ylabel, font=font, fill=255, anchor="lt")
    mask = mask.rotate(90, expand=True)
    right = panel.left - 1 - _TICK - 4 - widest - 8
    top = (panel.top + panel.bottom) / 2 - mask.height / 2
    image.paste(color, (int(round(right - mask.width)), int(round(top))), mask)


def _ticks(panel: Panel, ticks):
    """Pixel columns and rows (snapped, so a 1-pixel mark is crisp) of ticks within the panel."""
    cols = [(math.floor(panel.to_pixel([v, panel.ylim[0]])[0]), label) for v, label in ticks[0]]
    rows = [(math.floor(panel.to_pixel([panel.xlim[0], v])[1]), label) for v, label in ticks[1]]
    cols = [(c, label) for c, label in cols if panel.left - 1 <= c <= panel.right]
    rows = [(r, label) for r, label in rows if panel.top - 1 <= r <= panel.bottom]
    return cols, rows


# --------------------------------------------------------------------------- the figure


def render_plan(plan, scenario, *, ghosts: int = 6, unit: str = "m",
                legend: bool = True) -> Image.Image:
    """The plan figure of :func:`rapp.plotting.plot_plan` as a Pillow image, 1050 x 500 RGB.

    Parameters
    ----------
    plan : rapp.Plan
        Or any object with ``q`` (k, n), ``xy`` (k, 2) and, for a grid
        planner, ``grid`` and ``occupancy``.
    scenario : rapp.Scenario
        Its arm, obstacles and Cartesian goal (``goal_xy``, when it has one).
    ghosts : int
        How many arms to draw along the path between the start and final ones.
    unit : str
        The length unit on the workspace axes.
    legend : bool
        Draw a legend in each panel, in the corner that hides the least of the plan.

    Returns
    -------
    PIL.Image.Image
        Where each panel lies: :func:`plan_panels`.

    Examples
    --------
    >>> from rapp import load_scenario, plan
    >>> s = load_scenario("three_link")
    >>> image = render_plan(plan(s), s)
    >>> image.getpixel((0, 0)), image.size
    ((255, 255, 255), (1050, 500))
    """
    panels = plan_panels(plan, scenario)
    image = Image.new("RGB", (WIDTH, HEIGHT), _WHITE)
    draw = ImageDraw.Draw(image)
    text_font, legend_font = _fonts()
    parts = [_cspace(panels[0], plan, scenario), _workspace(panels[1], plan, scenario, ghosts)]
    labels = (("θ1 (rad)", "θ2 (rad)"), (f"x ({unit})", f"y ({unit})"))
    for panel, (layer, title, entries, ink), (xlabel, ylabel) in zip(panels, parts, labels):
        layout = _legend_box(panel, entries, legend_font, ink) if legend else None
        if layout:
            _draw_legend_handles(layer, layout, entries)
        # Averaging each block of SUPERSAMPLE x SUPERSAMPLE pixels antialiases every edge.
        image.paste(layer.image.reduce(SUPERSAMPLE), (panel.left, panel.top))
        # Frame and ticks on whole pixels just outside the drawing area: 1 pixel wide, crisp.
        draw.rectangle((panel.left - 1, panel.top - 1, panel.right, panel.bottom),
                       outline=_rgb(TEXT))
        if panel is panels[0]:  # multiples of pi when the range holds two of them
            ticks = (pi_ticks(*panel.xlim) or nice_ticks(*panel.xlim),
                     pi_ticks(*panel.ylim) or nice_ticks(*panel.ylim))
        else:
            ticks = (nice_ticks(*panel.xlim), nice_ticks(*panel.ylim))
        cols, rows = _ticks(panel, ticks)
        for c, _ in cols:
            draw.line(((c, panel.bottom + 1), (c, panel.bottom + _TICK)), fill=_rgb(TEXT))
        for r, _ in rows:
            draw.line(((panel.left - 1 - _TICK, r), (panel.left - 2, r)), fill=_rgb(TEXT))
        _axis_text(image, draw, panel, title, xlabel, ylabel, cols, rows, text_font)
        if layout:
            _draw_legend_labels(draw, layout, entries, legend_font)
    return image


def save_plan(plan, scenario, file, format: str = "png", **params) -> None:
    """Write :func:`render_plan`'s image to ``file`` (a path or a binary file object).

    Parameters
    ----------
    format : str
        A format Pillow writes ("png", "webp", ...), whatever the file is called.
    **params
        Passed to ``PIL.Image.Image.save``. For PNG, ``compress_level``
        defaults to 1: the file is a few per cent larger than at zlib's level
        6 and written several times faster.

    Examples
    --------
    >>> import io
    >>> from rapp import load_scenario, plan
    >>> s = load_scenario("default")
    >>> buffer = io.BytesIO()
    >>> save_plan(plan(s), s, buffer)
    >>> buffer.getvalue()[:8]
    b'\\x89PNG\\r\\n\\x1a\\n'
    """
    if format.lower() == "png":
        params.setdefault("compress_level", 1)
    render_plan(plan, scenario).save(file, format=format.upper(), **params)
