"""Figures and animations of arms, obstacles, C-space and plans.

Every function draws on an optional ``ax`` (a new figure when it is ``None``)
and returns what it drew on, so that figures compose. Nothing here computes a
plan: the functions take the values :func:`rapp.plan` returns. Nothing calls
``plt.show()``.

Figures are meant to be read in a dark-mode notebook as well as on paper: the
figure and axes backgrounds are white *explicitly* (a transparent figure on a
dark page hides black text), text is dark, and the colours are the Okabe-Ito
palette, which stays distinguishable under the common colour-vision
deficiencies.

References
----------
SRS of 2D-RAPP (seed 000): R5. MIS of 2D-RAPP (seed 001): the Plotting module.
Okabe & Ito (2008), Color Universal Design: the colour palette.
"""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType

import numpy as np
import matplotlib
import matplotlib.pyplot as plt
from matplotlib import animation, patches
from matplotlib.collections import LineCollection
from matplotlib.colors import ListedColormap, to_rgba
from matplotlib.lines import Line2D
from matplotlib.patheffects import withStroke
from matplotlib.ticker import MaxNLocator

from rapp.collision import closest_point_on_segment
from rapp.cspace import cell_extent
# The colours live in rapp.palette and split_at_seam in rapp.paths (no matplotlib there), so that
# code that draws nothing can name them; both stay importable from here.
from rapp.palette import (ARM, COLORS, EFFECTOR, GOAL, JOINT_COLORS, OBSTACLE, OCCUPIED, PATH,
                          START, TEXT)
from rapp.paths import even_indices, split_at_seam

__all__ = [
    "COLORS",
    "BOOK_STYLE",
    "BOOK_WIDTH_IN",
    "book_style",
    "smallest_text_px",
    "book_png",
    "html_table",
    "plot_speedups",
    "plot_call_counts",
    "plot_parts",
    "style_axes",
    "plot_arm",
    "plot_obstacles",
    "plot_workspace",
    "plot_cspace",
    "plot_cspace_growth",
    "plot_thick_links",
    "plot_plan",
    "plot_profiles",
    "plot_metrics",
    "plot_astar_step",
    "animate_astar",
    "plot_rrt_step",
    "animate_rrt",
    "plot_polynomials",
    "plot_segment_circle",
    "split_at_seam",
    "legend_outside",
    "plot_ratios",
    "plot_tree",
    "plot_f_contours",
    "plot_link_clearances",
    "plot_sweep",
    "plot_certification",
    "plot_value_grid",
    "animate",
    "save_gif",
    "animation_html",
    "close_animation",
]

_LIGHT = MappingProxyType({
    "figure.facecolor": "white",
    "axes.facecolor": "white",
    "savefig.facecolor": "white",
    "text.color": TEXT,
    "axes.labelcolor": TEXT,
    "axes.edgecolor": TEXT,
    "xtick.color": TEXT,
    "ytick.color": TEXT,
    "legend.facecolor": "white",
    "legend.edgecolor": "#bbbbbb",
    "legend.labelcolor": TEXT,
    # The book's type sizes. A figure is shown at most BOOK_WIDTH_IN wide, about the book's
    # content column (720-800 CSS px at 1280 px), so a point stays at least a CSS pixel on
    # screen: inline figures are drawn at 100 dpi (1.39 px per point), widget figures at 72
    # dpi (1 px per point). "small" (ticks, legends) is 10 pt, the smallest text we draw.
    "font.size": 12.0,
    "axes.titlesize": "medium",
    "axes.labelsize": "medium",
    "xtick.labelsize": "small",
    "ytick.labelsize": "small",
    "legend.fontsize": "small",
    "legend.title_fontsize": "small",
    "figure.titlesize": "large",
})

#: The widest a book figure is drawn, in inches: 750 px at the inline backend's 100 dpi, the
#: width of the book's content column at 1280 px. Wider figures are scaled down to it (the type
#: keeps its size in points, so it grows relative to the figure and stays legible).
BOOK_WIDTH_IN = 7.5

#: The book-wide figure style: white figure, dark text, the book's type sizes, constrained
#: layout, 100 dpi. :func:`book_style` applies it; every figure this module makes uses it.
BOOK_STYLE = MappingProxyType(dict(_LIGHT, **{
    "figure.dpi": 100,
    "savefig.dpi": 100,
    "figure.figsize": (7.0, 4.2),
    "figure.constrained_layout.use": True,
}))


def smallest_text_px(fig, dpi=None):
    """The size of the smallest visible text of ``fig``, in pixels of its image at ``dpi``.

    Tick labels, legends, titles, annotations: every non-empty visible ``Text`` (tick labels
    exist once the figure was drawn). ``None`` when the figure has no text. Multiplied by the displayed width over the image's natural width,
    this is the size a reader sees (``scripts/check_book.py`` does that in the browser).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(dpi=72); ax = fig.add_subplot(); t = ax.set_title("x", fontsize=12)
    >>> ax.tick_params(labelsize=9); fig.draw_without_rendering(); smallest_text_px(fig)
    9.0
    >>> smallest_text_px(fig, dpi=144)
    18.0
    """
    from matplotlib.text import Text

    sizes = [t.get_fontsize() for t in fig.findobj(Text)
             if t.get_text().strip() and t.get_visible() and t.figure is fig
             and (t.axes is None or t.axes.get_visible())]
    if not sizes:
        return None
    return float(min(sizes)) * (fig.dpi if dpi is None else dpi) / 72.0


def book_png(fig, *, max_width=BOOK_WIDTH_IN):
    """``fig`` as the book shows it: a PNG at most ``max_width`` inches wide, with its type size.

    A wider figure is scaled down (its type keeps its point size). The PNG carries
    ``rapp:text-px`` (the smallest text, in pixels of the image) and ``rapp:dpi`` as text
    chunks, so the book check can compute the size a reader sees. Colours are reduced to a
    palette when that makes the file smaller (line art: about three times).

    Examples
    --------
    >>> import io; from PIL import Image; from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(12, 3)); ax = fig.add_subplot(); _ = ax.plot([0, 1])
    >>> im = Image.open(io.BytesIO(book_png(fig)))
    >>> im.width <= 100 * BOOK_WIDTH_IN + 20, float(im.info["rapp:text-px"]) >= 13.0
    (True, True)
    """
    import io

    from PIL import Image
    from PIL.PngImagePlugin import PngInfo

    w, h = fig.get_size_inches()
    if w > max_width:
        fig.set_size_inches(max_width, h * max_width / w)
    dpi = fig.dpi
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight", facecolor="white")
    px = smallest_text_px(fig, dpi)  # after the drawing, which fills in the tick labels
    chunks = PngInfo()
    chunks.add_text("rapp:dpi", f"{dpi:g}")
    chunks.add_text("rapp:text-px", "" if px is None else f"{px:.2f}")
    rgb = Image.open(buf).convert("RGB")
    encoded = []
    for img in (rgb, rgb.quantize(colors=256, dither=Image.Dither.NONE)):
        out = io.BytesIO()
        img.save(out, format="PNG", optimize=True, pnginfo=chunks)
        encoded.append(out.getvalue())
    return min(encoded, key=len)


def html_table(header, rows):
    """A plain HTML table for a notebook (IPython ``HTML``): a header row, then ``rows``.

    Cells are inserted as given (they may hold markup such as ``<sub>``).

    Examples
    --------
    >>> html_table(["a", "b"], [(1, 2)]).data
    '<table><thead><tr><th>a</th><th>b</th></tr></thead><tbody><tr><td>1</td><td>2</td></tr></tbody></table>'
    """
    from IPython.display import HTML

    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{v}</td>" for v in r) + "</tr>" for r in rows)
    return HTML(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")


def book_style():
    """Apply the book's figure style to this session (call once, in a chapter's first cell).

    Sets :data:`BOOK_STYLE` as matplotlib's defaults and, inside IPython, shows every
    figure through :func:`book_png`: at most the width of the book's column, with the size of
    its smallest text recorded in the image. Returns the style applied.

    Examples
    --------
    >>> import matplotlib as mpl
    >>> with mpl.rc_context():
    ...     _ = book_style()
    ...     mpl.rcParams["font.size"], mpl.rcParams["figure.dpi"]
    (12.0, 100.0)
    """
    matplotlib.rcParams.update(BOOK_STYLE)
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython is in the environment
        return BOOK_STYLE
    shell = get_ipython()
    if shell is not None and hasattr(shell, "display_formatter"):
        from matplotlib.figure import Figure
        formatter = shell.display_formatter.formatters["image/png"]
        formatter.for_type(Figure, book_png)
        # One image per figure: the inline backend would also offer its own formats.
        for mime in ("image/svg+xml", "application/pdf", "image/jpeg", "image/retina+png"):
            if mime in shell.display_formatter.formatters:
                shell.display_formatter.formatters[mime].pop(Figure, None)
    return BOOK_STYLE


def style_axes(ax):
    """Give ``ax`` and its figure the white-background, dark-text style.

    Safe to call repeatedly; it also recolours titles, labels and legends
    that already exist, so a dark matplotlib style cannot leak in.

    Examples
    --------
    >>> fig, ax = plt.subplots()
    >>> ax = style_axes(ax)
    >>> ax.get_facecolor() == fig.get_facecolor() == (1.0, 1.0, 1.0, 1.0)
    True
    >>> plt.close(fig)
    """
    fig = ax.figure
    fig.patch.set_facecolor("white")
    ax.set_facecolor("white")
    for spine in ax.spines.values():
        spine.set_edgecolor(TEXT)
    ax.tick_params(colors=TEXT, which="both")
    ax.xaxis.label.set_color(TEXT)
    ax.yaxis.label.set_color(TEXT)
    ax.title.set_color(TEXT)
    for text in (ax._left_title, ax._right_title):
        text.set_color(TEXT)
    legend = ax.get_legend()
    if legend is not None:
        legend.get_frame().set_facecolor("white")
        legend.get_frame().set_edgecolor("#bbbbbb")
        for text in legend.get_texts():
            text.set_color(TEXT)
        legend.get_title().set_color(TEXT)
    if getattr(fig, "_suptitle", None) is not None:
        fig._suptitle.set_color(TEXT)
    return ax


def _axes(ax, figsize=(5.0, 5.0)):
    if ax is not None:
        return ax
    with plt.rc_context(_LIGHT):
        fig, ax = plt.subplots(figsize=figsize, layout="constrained")
    return style_axes(ax)


def _figure(fig, figsize):
    """A white figure: the caller's (for example a pyplot-free one in a widget) or a new one."""
    if fig is None:
        with plt.rc_context(_LIGHT):
            fig = plt.figure(figsize=figsize, layout="constrained")
    fig.patch.set_facecolor("white")
    return fig


def subplots(fig, *args, **kwargs):
    """``fig.subplots(...)`` in the book's light style (white axes, dark text).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> len(subplots(Figure(), 1, 2))
    2
    """
    with plt.rc_context(_LIGHT):
        return fig.subplots(*args, **kwargs)


def _legend(ax, **kwargs):
    kwargs.setdefault("fontsize", "small")
    kwargs.setdefault("framealpha", 0.9)
    ax.legend(**kwargs)
    return style_axes(ax)


def legend_outside(ax, extra=()):
    """The legend of ``ax`` (plus the artists ``extra``) to the right of the axes, covering nothing.

    ``extra`` holds handles the axes did not draw (a patch standing for an image's colour, say);
    each gives its label. Returns ``ax``.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> ax = Figure().subplots()
    >>> _ = ax.plot([0, 1], [0, 1], label="path")
    >>> ax = legend_outside(ax, [patches.Patch(color="0.3", label="obstacle")])
    >>> [t.get_text() for t in ax.get_legend().get_texts()]
    ['path', 'obstacle']
    """
    handles, labels = ax.get_legend_handles_labels()
    ax.legend(handles + list(extra), labels + [p.get_label() for p in extra],
              loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    return style_axes(ax)


def plot_speedups(cases, naive, fast, ax=None):
    """Pairs of bars, the naive code's time (grey) and rapp's (blue), on a log axis, with the
    speed-up ``naive / fast`` written above each pair. Returns ``ax``.

    Examples
    --------
    >>> ax = plot_speedups(["grid", "search"], [10.0, 2.0], [0.01, 0.5])
    >>> [t.get_text() for t in ax.texts], len(ax.patches)
    (['1,000×', '4×'], 4)
    >>> plt.close(ax.figure)
    """
    naive, fast = np.asarray(naive, dtype=float), np.asarray(fast, dtype=float)
    ax = _axes(ax, figsize=(8, 4))
    x = np.arange(len(cases))
    ax.bar(x - 0.2, naive, 0.4, label="naive", color="tab:gray")
    ax.bar(x + 0.2, fast, 0.4, label="rapp", color="tab:blue")
    for xi, top, k in zip(x, naive, naive / fast):
        ax.annotate(f"{k:,.0f}×", (xi, top), xytext=(0, 4), textcoords="offset points", ha="center")
    ax.set_yscale("log")
    ax.set_ylim(fast.min() / 3, naive.max() * 8)
    ax.set_xticks(x, cases)
    ax.set_xlabel("case")
    ax.set_ylabel("best time (s)")
    ax.legend(loc="upper left")
    return style_axes(ax)


def plot_call_counts(n, k, sizes, naive_calls, rapp_calls, ax=None):
    """Calls of the disc test against the cells per joint ``M`` (log-log): the naive loop's
    ``n k M**n`` (grey) and rapp's ``n k`` array calls (blue), with the counts measured on
    the grids ``sizes`` as crosses. Returns ``ax``.

    Examples
    --------
    >>> ax = plot_call_counts(2, 3, [8, 16], [384, 1536], [6, 6])
    >>> [line.get_label() for line in ax.lines][:3]
    ['naive: $nKM^n$ Python calls', 'rapp: $nK$ array calls', 'counted']
    >>> plt.close(ax.figure)
    """
    ms = np.array([8, 16, 32, 64, 128, 360])
    ax = _axes(ax, figsize=(6, 3.5))
    ax.loglog(ms, n * k * ms.astype(float) ** n, "o-", color="tab:gray", label="naive: $nKM^n$ Python calls")
    ax.loglog(ms, np.full(ms.shape, n * k), "s-", color="tab:blue", label="rapp: $nK$ array calls")
    ax.loglog(sizes, naive_calls, "kx", ms=9, label="counted")
    ax.loglog(sizes, rapp_calls, "kx", ms=9)
    ax.set_xlabel("cells per joint $M$")
    ax.set_ylabel("calls of the disc test (count)")
    ax.legend(loc="center right")
    return style_axes(ax)


def plot_parts(parts, label, ax=None):
    """One horizontal bar of consecutive parts (``name -> seconds``, in order), each its colour,
    named in a legend above. Returns ``ax``.

    Examples
    --------
    >>> ax = plot_parts({"import": 0.1, "plan": 0.3}, "plan")
    >>> [round(float(b.get_x()), 6) for b in ax.patches], ax.get_legend().get_texts()[1].get_text()
    ([0.0, 0.1], 'plan')
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax, figsize=(8, 2.4))
    left = 0.0
    colours = ["tab:gray", "tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:red", "tab:brown"]
    for (name, seconds), colour in zip(parts.items(), colours):
        ax.barh(0, seconds, left=left, height=0.5, color=colour, label=name)
        left += seconds
    ax.set_yticks([0], [label])
    ax.set_ylim(-0.5, 1.2)
    ax.set_xlim(0, left * 1.05)
    ax.set_xlabel("time in one process (s)")
    ax.legend(loc="upper center", ncol=3, fontsize=8)
    return style_axes(ax)


def plot_ratios(labels, ratios, goals, ax=None, *, fmt=None):
    """Horizontal bars of speed ratios (a peer's time over rapp's) on a log axis, with goal ticks.

    Bars start at 1 (parity): to the right rapp is faster. A bar is blue where its ratio meets its
    goal, red where it misses it and grey where ``goals`` holds ``None`` (no goal set); a black
    tick marks each goal. ``fmt`` writes the ratio at a bar's end (default: two significant
    digits). The first label is drawn at the top. Returns ``ax``.

    Examples
    --------
    >>> ax = plot_ratios(["grid", "search"], [12.0, 0.8], [4, None])
    >>> [round(float(b.get_width()) + 1, 6) for b in ax.patches]   # bar ends: the ratios
    [12.0, 0.8]
    >>> plt.close(ax.figure)
    """
    ratios = np.asarray(ratios, dtype=float)
    fmt = fmt or (lambda k: f"{k:.2f}×")
    met = [None if goal is None else bool(k >= goal) for k, goal in zip(ratios, goals)]
    ax = _axes(ax, figsize=(8, 0.36 * len(ratios) + 1.2))
    y = np.arange(len(ratios))[::-1]
    colour = {True: COLORS["blue"], False: COLORS["vermillion"], None: "#999999"}
    ax.barh(y, ratios - 1, left=1, height=0.6, color=[colour[ok] for ok in met])
    for yi, k, goal in zip(y, ratios, goals):
        end = k if goal is None else max(k, goal) if k >= 1 else min(k, goal)   # clear of the tick
        ax.annotate(fmt(k), (end, yi), xytext=(4 if k >= 1 else -4, 0), textcoords="offset points",
                    va="center", ha="left" if k >= 1 else "right", fontsize="small")
        if goal is not None:
            ax.plot([goal, goal], [yi - 0.4, yi + 0.4], color="black", lw=2.5)
    ax.axvline(1, color="black", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlim(min(ratios.min(), 0.5) / 40, ratios.max() * 12)
    ax.set_yticks(y, labels, fontsize="small")
    ax.set_xlabel("peer's time / rapp's time (right of 1: rapp faster)")
    shown = [v for v in (True, False, None) if v in met]   # only the verdicts that occur
    names = {True: "goal met", False: "goal missed", None: "no goal set"}
    handles = [patches.Patch(color=colour[v], label=names[v]) for v in shown]
    handles.append(Line2D([], [], color="black", lw=2.5, label="goal"))
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=4, fontsize="small")
    return style_axes(ax)


def _workspace_frame(ax, arm, unit="m"):
    """Square, equal-aspect limits around the reach, grown to hold every patch drawn so far.

    Obstacles often stand at the edge of the reach; a frame of the reach alone
    would cut them off, and they are what the reader is looking at.
    """
    r = arm.reach[1] * 1.1
    for patch in ax.patches:
        pts = patch.get_patch_transform().transform(patch.get_path().vertices)
        r = max(r, 1.05 * float(np.abs(pts).max(initial=0.0)))
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.grid(True, color="#e6e6e6", linewidth=0.6, zorder=0)
    ax.set_axisbelow(True)
    return style_axes(ax)


def plot_arm(arm, q, ax=None, *, color=ARM, alpha=1.0, label=None, ghost_alpha=(0.15, 0.6),
             unit="m", frame=True):
    """Draw the arm: links, joints, base and end effector.

    Parameters
    ----------
    arm : rapp.Arm
    q : array_like, shape (n,) or (k, n)
        One configuration, drawn solid; or a few configurations, drawn as
        ghosts whose opacity rises from ``ghost_alpha[0]`` to ``ghost_alpha[1]``
        in order (one LineCollection, one scatter of end effectors).
    ax : matplotlib Axes, optional
    frame : bool
        Set equal aspect, limits of the reach and axis labels in ``unit``.

    Returns
    -------
    Axes

    Examples
    --------
    >>> from rapp import Arm
    >>> ax = plot_arm(Arm([1.0, 1.0]), [0.0, np.pi / 2])
    >>> ax.lines[0].get_xydata().round(12).tolist()   # base, elbow, end effector
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    q = np.asarray(q, dtype=float)
    pts = arm.joint_positions(q)
    if q.ndim == 1:
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=color, lw=3, ms=6, mfc="white", mec=color,
                mew=1.5, alpha=alpha, label=label, zorder=3, solid_capstyle="round")
        ax.plot([0.0], [0.0], "s", color=TEXT, ms=9, alpha=alpha, zorder=4)
        ax.plot(pts[-1:, 0], pts[-1:, 1], "o", color=EFFECTOR, ms=7, alpha=alpha, zorder=5)
    elif q.ndim == 2:
        pts = pts.reshape(-1, arm.n + 1, 2)
        a = np.linspace(ghost_alpha[0], ghost_alpha[1], len(pts))
        rgba = np.tile(to_rgba(color), (len(pts), 1))
        rgba[:, 3] = a * alpha
        ax.add_collection(LineCollection(pts, colors=rgba, linewidths=2, label=label, zorder=2,
                                         capstyle="round"))
        ee = np.tile(to_rgba(EFFECTOR), (len(pts), 1))
        ee[:, 3] = a * alpha
        ax.scatter(pts[:, -1, 0], pts[:, -1, 1], s=12, c=ee, zorder=2)
    else:
        raise ValueError(f"q must have shape (n,) or (k, n), got {q.shape}")
    if frame:
        _workspace_frame(ax, arm, unit)
    return ax


def plot_link_clearances(arm, q, discs, ax=None):
    """Each link's clearance from its nearest disc, drawn as a dashed gap labelled ``d_j``.

    For one configuration ``q`` of ``arm`` and discs (``rapp.Circle``), link ``j``'s gap runs from
    its closest point to the nearest disc's rim; its label gives the clearance in metres. Returns
    ``ax``; the arm and discs themselves are drawn by :func:`plot_arm` and :func:`plot_obstacles`.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> ax = plot_link_clearances(Arm([1.0, 1.0]), [0.0, 0.0], [Circle((1.0, 0.5), 0.2)])
    >>> [t.get_text() for t in ax.texts]
    ['$d_1$ = 0.30 m', '$d_2$ = 0.30 m']
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    p = arm.joint_positions(np.asarray(q, dtype=float))
    for j in range(arm.n):
        near = [closest_point_on_segment(p[j], p[j + 1], c.center) for c in discs]
        gaps = [float(np.linalg.norm(x - c.center)) - c.radius for x, c in zip(near, discs)]
        k = int(np.argmin(gaps))
        centre, x = np.asarray(discs[k].center, dtype=float), near[k]
        rim = centre + discs[k].radius * (x - centre) / np.linalg.norm(x - centre)
        ax.plot(*np.array([x, rim]).T, "--", color=COLORS["vermillion"], lw=1.5,
                label="clearance of a link" if j == 0 else None)
        side = -1 if j % 2 else 1   # alternate sides so that neighbouring labels do not meet
        ax.text(*((x + rim) / 2 + [side * 0.05, 0.0]), f"$d_{j + 1}$ = {gaps[k]:.2f} m",
                fontsize="small", color="#A04000", ha="left" if side > 0 else "right", va="center")
    return ax


def plot_sweep(arm, qs, obstacles, ax=None):
    """A motion as poses: its two ends in green, the poses between blue where free, red where not.

    ``qs`` (k, n) are the configurations in order. Returns ``ax``.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> qs = np.linspace([0.0, 0.0], [np.pi, 0.0], 9)
    >>> ax = plot_sweep(Arm([1.0, 1.0]), qs, [Circle((0.0, 1.5), 0.3)])
    >>> sorted(t.get_text() for t in ax.get_legend().get_texts())
    ['colliding poses', 'free poses', 'start and end (free)']
    >>> plt.close(ax.figure)
    """
    from rapp.collision import collides

    ax = _axes(ax)
    qs = np.asarray(qs, dtype=float)
    hit = collides(arm, qs, obstacles)
    inner, inner_hit = qs[1:-1], hit[1:-1]
    if (~inner_hit).any():
        plot_arm(arm, inner[~inner_hit], ax, color=COLORS["blue"], label="free poses", frame=False,
                 ghost_alpha=(0.45, 0.45))
    if inner_hit.any():
        plot_arm(arm, inner[inner_hit], ax, color=COLORS["vermillion"], label="colliding poses",
                 frame=False, ghost_alpha=(0.8, 0.8))
    ends = "free" if not (hit[0] or hit[-1]) else "colliding"
    plot_arm(arm, qs[0], ax, color=COLORS["green"], label=f"start and end ({ends})")
    plot_arm(arm, qs[-1], ax, color=COLORS["green"], frame=False)
    ax.legend(loc="lower center", ncols=2, fontsize="small")
    return style_axes(ax)


def plot_certification(arm, q0, q1, obstacles, log, axes=None, *, title=None):
    """A certified segment check at work: the clearance along the motion, and its intervals.

    ``log`` lists the check's intervals in order, ``(lo, hi, outcome)`` with ``outcome`` one of
    ``"certified"``, ``"bisected"`` or ``"collision"`` (as chapter 3's step-by-step version of
    :func:`rapp.collision.segment_collision_free` records them). The top axes draw the arm's
    clearance along ``q0 + t (q1 - q0)``, each interval's midpoint coloured by its outcome and,
    over a certified interval, the lower bound the motion bounds prove there; the bottom axes draw
    the intervals by bisection depth. ``axes`` is ``(top, bottom)``; returns it.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> top, bottom = plot_certification(Arm([1.0, 1.0]), [0.0, 0.0], [0.5, 0.0],
    ...                                  [Circle((0.0, 1.5), 0.3)], [(0.0, 1.0, "certified")])
    >>> len(bottom.patches), top.lines[0].get_label()
    (1, 'clearance of the arm')
    >>> plt.close(top.figure)
    """
    from rapp.collision import clearance, link_clearances, motion_bounds

    if axes is None:
        with plt.rc_context(_LIGHT):
            fig, axes = plt.subplots(2, 1, figsize=(6, 7), sharex=True, height_ratios=(3, 2),
                                     layout="constrained")
    top, bottom = axes
    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
    colours = {"certified": COLORS["green"], "bisected": "#999999", "collision": COLORS["vermillion"]}
    bounds = motion_bounds(arm, q1 - q0)
    ts = np.linspace(0.0, 1.0, 801)
    top.plot(ts, clearance(arm, q0 + ts[:, None] * (q1 - q0), obstacles), color=COLORS["blue"], lw=2,
             label="clearance of the arm")
    labelled = False
    for lo, hi, outcome in log:
        t_m = (lo + hi) / 2
        d = link_clearances(arm, q0 + t_m * (q1 - q0), obstacles)
        top.plot(t_m, d.min(), "o", color=colours[outcome], ms=6, zorder=4)
        if outcome == "certified":     # the proved lower bound min_j (d_j - B_j |t - t_m|)
            tt = np.linspace(lo, hi, 41)
            tent = (d[None, :] - bounds[None, :] * np.abs(tt - t_m)[:, None]).min(axis=1)
            top.plot(tt, tent, "-", color=colours[outcome], lw=1.2,
                     label=None if labelled else "proved lower bound")
            labelled = True
        bottom.barh(np.log2(1.0 / (hi - lo)), hi - lo, left=lo, height=0.7, color=colours[outcome],
                    edgecolor="white", label=f"interval {outcome}")
    top.axhline(0.0, color=TEXT, lw=0.8)
    top.set_ylabel("clearance (m)")
    if title:
        top.set_title(title, fontsize="medium")
    top.legend(loc="lower left", fontsize="small")
    bottom.invert_yaxis()
    bottom.set_xlabel("segment parameter t (dimensionless)")
    bottom.set_ylabel("bisection depth")
    bottom.set_xlim(0.0, 1.0)
    for ax in (top, bottom):
        style_axes(ax)
    return top, bottom


def plot_value_grid(values, half, xticks, yticks, ax=None, *, cmap="Oranges", clim=None):
    """A table of means as a heat map: each cell its mean and, under it, ``± half``.

    ``values`` and ``half`` are ``(len(xticks), len(yticks))``; a NaN mean prints "-", a NaN
    half-width prints nothing. Text is white on the dark cells. Returns the image (for a colour bar).

    Examples
    --------
    >>> im = plot_value_grid(np.array([[1.0, np.nan]]), np.array([[0.25, np.nan]]), ["a"], ["x", "y"])
    >>> [t.get_text().split() for t in im.axes.texts]
    [['1.00', '±', '0.25'], ['-']]
    >>> plt.close(im.axes.figure)
    """
    ax = _axes(ax)
    values, half = np.asarray(values, dtype=float), np.asarray(half, dtype=float)
    im = ax.imshow(values.T, origin="lower", cmap=cmap, aspect="auto", clim=clim)
    dark = im.norm(values) > 0.6   # white on the dark cells, dark text on the light ones
    for (i, j), v in np.ndenumerate(values):
        text = "-" if np.isnan(v) else f"{v:.2f}" + ("" if np.isnan(half[i, j]) else f"\n± {half[i, j]:.2f}")
        ax.text(i, j, text, ha="center", va="center", fontsize="small",
                color="white" if dark[i, j] else TEXT)
    ax.set_xticks(range(len(xticks)), xticks)
    ax.set_yticks(range(len(yticks)), yticks)
    style_axes(ax)
    return im


def plot_obstacles(obstacles, ax=None, *, color=OBSTACLE, label="obstacle"):
    """Draw circles and convex polygons as filled patches (one patch each).

    Examples
    --------
    >>> from rapp import Circle, Polygon
    >>> ax = plot_obstacles([Circle((1, 1), 0.5), Polygon.rectangle((0, 0), 1, 2)])
    >>> len(ax.patches)
    2
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    for i, ob in enumerate(obstacles):
        kw = dict(facecolor=color, edgecolor=TEXT, linewidth=1.0, alpha=0.85, zorder=1,
                  label=label if i == 0 else None)
        if hasattr(ob, "radius"):
            patch = patches.Circle(ob.center, ob.radius, **kw)
        elif hasattr(ob, "vertices"):
            patch = patches.Polygon(np.asarray(ob.vertices, dtype=float), closed=True, **kw)
        else:
            raise ValueError(f"cannot draw obstacle {ob!r}: expected a Circle or a Polygon")
        ax.add_patch(patch)
    ax.set_aspect("equal")
    return style_axes(ax)


def plot_workspace(arm, ax=None, *, unit="m", color=COLORS["sky"]):
    """Shade the reachable annulus ``r_min <= |x| <= r_max`` and draw its circles.

    Returns the axes; it holds one shaded patch and one Line2D per boundary
    circle (the inner one only when ``r_min > 0``).

    Examples
    --------
    >>> from rapp import Arm
    >>> ax = plot_workspace(Arm([2.0, 1.0]))
    >>> len(ax.patches), len(ax.lines)
    (1, 2)
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    r_min, r_max = arm.reach
    width = None if r_min <= 0 else r_max - r_min
    ax.add_patch(patches.Wedge((0.0, 0.0), r_max, 0.0, 360.0, width=width, facecolor=color,
                               alpha=0.18, edgecolor="none", zorder=0, label="workspace"))
    th = np.linspace(0.0, 2 * np.pi, 361)
    ring = np.stack((np.cos(th), np.sin(th)), axis=-1)
    ax.plot(*(r_max * ring).T, "--", color=COLORS["blue"], lw=1, zorder=1)
    if r_min > 0:
        ax.plot(*(r_min * ring).T, ":", color=COLORS["blue"], lw=1, zorder=1)
    return _workspace_frame(ax, arm, unit)


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


def _pi_ticks(axis, lo, hi):
    """Ticks at multiples of pi/2 within [lo, hi], labelled with pi."""
    ticks = pi_ticks(lo, hi)
    if ticks:
        axis.set_ticks([v for v, _ in ticks], [label for _, label in ticks])


def plot_cspace(occupancy, grid, ax=None, path=None, start=None, goal=None, *, title=None,
                expanded=None):
    """Show the occupancy of a joint grid; optionally a path, start and goal in joint angles.

    Parameters
    ----------
    occupancy : bool array of ``grid.shape``
    grid : rapp.JointGrid
        ``grid.axes`` (the sample angles of each joint) gives the image
        extent, one pixel centred on each sample, origin lower.
    path : array_like, shape (k, n), optional
        Joint angles (radians). Split where a free joint wraps, so the line
        never crosses the plot along the seam.
    start, goal : array_like, shape (n,), optional
    expanded : bool array of ``grid.shape``, optional
        Cells a search expanded (its closed set), shaded light blue; 2-joint grids.

    For three or more joints, the image is a projection over the joints
    after the second: the grey level is the fraction of their grid values in
    collision (black: every value collides); the title says so.

    Returns
    -------
    Axes

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> axes = [np.linspace(-np.pi, np.pi, 8, endpoint=False)] * 2
    >>> grid = SimpleNamespace(axes=axes, shape=(8, 8), wraps=(True, True))
    >>> ax = plot_cspace(np.eye(8, dtype=bool), grid, path=[[3.0, 0.0], [-3.0, 0.0]])
    >>> len(ax.images), ax.get_xlabel()
    (1, 'θ1 (rad)')
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    occ = np.asarray(occupancy)
    if occ.ndim < 2:
        raise ValueError("plot_cspace draws grids of two or more joints")
    ext = cell_extent(grid)
    if occ.ndim == 2:
        img = occ.astype(float)
        cmap = ListedColormap(["white", OCCUPIED])
        default_title = "C-space: grey = collision"
        if expanded is not None:
            # 0 free, 1 collision, 0.5 expanded: one image, so the colours cannot disagree.
            img = np.where(np.asarray(expanded, bool) & ~occ, 0.5, img)
            cmap = ListedColormap(["white", COLORS["sky"], OCCUPIED])
            default_title = "C-space: grey = collision, blue = expanded"
    else:
        img = occ.reshape(occ.shape[:2] + (-1,)).mean(axis=-1)
        cmap = matplotlib.colormaps["Greys"]
        rest = ", ".join(f"θ{i + 1}" for i in range(2, occ.ndim))
        default_title = f"projection over {rest}: fraction in collision"
    # imshow puts the first array axis on y; the first joint belongs on x.
    ax.imshow(img.T, origin="lower", extent=ext, cmap=cmap, vmin=0.0, vmax=1.0,
              interpolation="nearest", aspect="equal", zorder=0)
    ax.set_xlim(ext[0], ext[1])
    ax.set_ylim(ext[2], ext[3])
    _pi_ticks(ax.xaxis, ext[0], ext[1])
    _pi_ticks(ax.yaxis, ext[2], ext[3])
    ax.set_xlabel("θ1 (rad)")
    ax.set_ylabel("θ2 (rad)")
    ax.set_title(default_title if title is None else title, fontsize="medium")
    lo = np.array([ext[0], ext[2]])
    span = np.array([ext[1] - ext[0], ext[3] - ext[2]])
    wraps = np.asarray(grid.wraps[:2], dtype=bool)
    labelled = False
    if path is not None:
        p = np.asarray(path, dtype=float)
        p = p.reshape(-1, p.shape[-1])[:, :2]
        seg = split_at_seam(p, lo, span, wraps)
        ax.plot(seg[:, 0], seg[:, 1], "-", color=PATH, lw=2, label="path", zorder=2)
        labelled = True
    for q, color, marker, name in ((start, START, "o", "start"), (goal, GOAL, "*", "goal")):
        if q is not None:
            q = split_at_seam(np.asarray(q, dtype=float)[:2], lo, span, wraps)[0]
            ax.plot(q[0], q[1], marker, color=color, ms=11 if marker == "*" else 8, mec="white",
                    mew=1, label=name, zorder=3)
            labelled = True
    if labelled:
        _legend(ax, loc="upper right")
    return style_axes(ax)


def plot_cspace_growth(occupancies, grid, radii, ax=None, *, unit="m"):
    """C-space obstacles as the links thicken: one occupancy per link radius, nested shades.

    Parameters
    ----------
    occupancies : sequence of bool arrays of ``grid.shape`` (two joints)
        The occupancy for each radius of ``radii``, in increasing order of radius (each holds
        the one before: a thicker link touches wherever a thinner one does).
    grid : rapp.JointGrid
    radii : sequence of float
        The link radius of each occupancy, shown in the legend.

    A cell is drawn in the shade of the thinnest link that collides there: the darkest
    region is the zero-width C-space obstacle, each lighter ring what the next radius adds.

    Returns
    -------
    Axes

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> axes = [np.linspace(-np.pi, np.pi, 8, endpoint=False)] * 2
    >>> grid = SimpleNamespace(axes=axes, shape=(8, 8), wraps=(True, True))
    >>> thin = np.eye(8, dtype=bool)
    >>> ax = plot_cspace_growth([thin, thin | np.roll(thin, 1, 0)], grid, [0.0, 0.1])
    >>> len(ax.images), len(ax.get_legend().get_texts())
    (1, 2)
    >>> plt.close(ax.figure)
    """
    occ = np.asarray([np.asarray(o, dtype=bool) for o in occupancies])
    if occ.ndim != 3 or len(occ) != len(radii):
        raise ValueError("plot_cspace_growth draws one two-joint occupancy per radius")
    k = len(occ)
    # Index of the thinnest link colliding at each cell; k where none does.
    level = np.where(occ.any(axis=0), np.argmax(occ, axis=0), k)
    shades = [matplotlib.colormaps["Greys"](0.85 - 0.6 * i / max(k - 1, 1)) for i in range(k)]
    ax = plot_cspace(np.zeros(occ.shape[1:], bool), grid, ax,
                     title="C-space as the links thicken")
    ext = cell_extent(grid)
    ax.images[0].remove()
    ax.imshow(level.T, origin="lower", extent=ext, cmap=ListedColormap(shades + ["white"]),
              vmin=-0.5, vmax=k + 0.5, interpolation="nearest", aspect="equal", zorder=0)
    handles = [patches.Patch(color=shades[i], label=f"link radius {r:g} {unit}")
               for i, r in enumerate(radii)]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    return ax


def plot_thick_links(arm, obstacles, occupancies, grid, radii, *, grown_by=None, figsize=(10, 4.8)):
    """Thick links, side by side: the obstacles grown in the workspace, the C-space swelling.

    Left: the arm's workspace with ``obstacles`` and each grown by ``grown_by`` (default the
    largest of ``radii``) into the exact pieces of :func:`rapp.obstacles.grown`. Right:
    :func:`plot_cspace_growth` of ``occupancies`` (one per radius of ``radii``) on ``grid``.

    Returns
    -------
    Figure

    Examples
    --------
    >>> from rapp import Arm, Circle, JointGrid, occupancy
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((1.2, 0.8), 0.3)]
    >>> grid = JointGrid(arm, 24)
    >>> occ = [occupancy(Arm([1.0, 1.0], link_radius=r), obs, grid) for r in (0.0, 0.1)]
    >>> fig = plot_thick_links(arm, obs, occ, grid, [0.0, 0.1])
    >>> len(fig.axes), fig.axes[0].get_title()
    (2, 'obstacles grown by 0.1 m')
    >>> plt.close(fig)
    """
    from rapp.obstacles import grown
    d = float(max(radii) if grown_by is None else grown_by)
    fig = plt.figure(figsize=figsize, layout="constrained")
    ax_w, ax_c = fig.subplots(1, 2)
    plot_workspace(arm, ax_w)
    plot_obstacles([p for ob in obstacles for p in grown(ob, d)], ax_w, color=COLORS["sky"],
                   label=f"grown by {d:g} m")
    plot_obstacles(obstacles, ax_w)
    ax_w.set_title(f"obstacles grown by {d:g} m")
    plot_cspace_growth(occupancies, grid, radii, ax_c)
    return fig


#: Size (inches) of :func:`plot_plan`'s figure; ``python -m rapp plan --plot`` draws at 100 dpi.
PLAN_FIGSIZE = (10.5, 4.7)


def plot_plan(plan, scenario=None, *, fig=None, ghosts=6, unit="m", expanded=None, axes=None):
    """C-space beside workspace, the plan drawn in both.

    Left: occupancy of ``plan.grid`` with the joint path, start and goal.
    Right: workspace annulus, obstacles, ghost arms along the path, the
    end-effector trace ``plan.xy``, the start and final arms, and the
    Cartesian goal when the scenario has one.

    Parameters
    ----------
    plan : rapp.Plan
    scenario : rapp.Scenario, optional
        The plan's own (``plan.scenario``) when None.
    fig : Figure, optional
        Drawn into (cleared); a new pyplot figure when None.
    expanded : bool array of ``plan.grid.shape``, optional
        The search's closed set, shaded in the C-space panel (see :func:`plot_cspace`).
    axes : pair of Axes, optional
        The C-space and workspace axes to draw into as they are; else ``fig`` is cleared
        and given two.

    Returns
    -------
    Figure

    Examples
    --------
    >>> from rapp import load_scenario, plan
    >>> s = load_scenario("default")
    >>> fig = plot_plan(plan(s))
    >>> [ax.get_title() for ax in fig.axes]
    ['C-space: grey = collision', 'workspace']
    >>> plt.close(fig)
    """
    if axes is None:
        fig = _figure(fig, PLAN_FIGSIZE)
        fig.clear()
        fig.patch.set_facecolor("white")
        ax_c, ax_w = subplots(fig, 1, 2)
    else:
        ax_c, ax_w = axes
        fig = ax_c.figure
    q = np.asarray(plan.q, dtype=float)
    scenario = plan.scenario if scenario is None else scenario
    arm = scenario.arm
    grid = getattr(plan, "grid", None)
    occ = getattr(plan, "occupancy", None)
    if grid is not None and occ is not None and np.ndim(occ) >= 2:
        plot_cspace(occ, grid, ax_c, path=q, start=q[0], goal=q[-1], expanded=expanded)
    else:
        # No grid (for example a sampling planner): the joint path alone.
        lo, hi = arm.lower[:2], arm.upper[:2]
        seg = split_at_seam(q[:, :2], lo, hi - lo, ~arm.limited[:2])
        ax_c.plot(seg[:, 0], seg[:, 1], "-", color=PATH, lw=2, label="path")
        ax_c.plot(*q[0, :2], "o", color=START, label="start")
        ax_c.plot(*q[-1, :2], "*", color=GOAL, ms=11, label="goal")
        ax_c.set_xlim(lo[0], hi[0])
        ax_c.set_ylim(lo[1], hi[1])
        ax_c.set_aspect("equal")
        ax_c.set_xlabel("θ1 (rad)")
        ax_c.set_ylabel("θ2 (rad)")
        ax_c.set_title("joint space", fontsize="medium")
        _legend(ax_c, loc="upper right")
    plot_workspace(arm, ax_w, unit=unit)
    plot_obstacles(scenario.obstacles, ax_w)
    plot_arm(arm, q[even_indices(len(q), ghosts + 2)[1:-1]], ax_w, frame=False)
    xy = np.asarray(plan.xy, dtype=float)
    ax_w.plot(xy[:, 0], xy[:, 1], "-", color=PATH, lw=2, label="end-effector path", zorder=4)
    plot_arm(arm, q[0], ax_w, color=START, label="start", frame=False)
    plot_arm(arm, q[-1], ax_w, color=ARM, label="final", frame=False)
    goal_xy = getattr(scenario, "goal_xy", None)
    if goal_xy is not None:
        ax_w.plot(*np.asarray(goal_xy, dtype=float), "*", color=GOAL, ms=14, mec=TEXT, mew=0.8,
                  label="goal", zorder=6)
    _workspace_frame(ax_w, arm, unit)
    ax_w.set_title("workspace", fontsize="medium")
    # Below each panel, where no legend can hide the path, the obstacles or the goal.
    for ax in (ax_c, ax_w):
        if ax.get_legend_handles_labels()[0]:
            _legend(ax, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=3)
    return fig


def plot_profiles(plan, *, fig=None, unit="m"):
    """Joint angles, velocities, accelerations and end-effector x, y against time.

    Four stacked axes sharing t: ``q``, ``q'``, ``q''`` (one line per joint)
    and ``x(t)``, ``y(t)``.

    Returns
    -------
    Figure

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> z = np.zeros((5, 2))
    >>> fig = plot_profiles(SimpleNamespace(t=t, q=z, qd=z, qdd=z, xy=z))
    >>> [len(ax.lines) for ax in fig.axes]
    [2, 2, 2, 2]
    >>> plt.close(fig)
    """
    fig = _figure(fig, (7.5, 7.0))
    fig.clear()
    axs = subplots(fig, 4, 1, sharex=True)
    t = np.asarray(plan.t, dtype=float)
    rows = ((plan.q, "θ (rad)", "θ"), (plan.qd, "θ' (rad/s)", "θ'"),
            (plan.qdd, "θ'' (rad/s²)", "θ''"))
    for ax, (values, ylabel, sym) in zip(axs, rows):
        values = np.asarray(values, dtype=float).reshape(len(t), -1)
        for j in range(values.shape[1]):
            ax.plot(t, values[:, j], color=JOINT_COLORS[j % len(JOINT_COLORS)],
                    label=f"{sym}{j + 1}")
        ax.set_ylabel(ylabel)
    xy = np.asarray(plan.xy, dtype=float)
    axs[3].plot(t, xy[:, 0], color=COLORS["blue"], label="x")
    axs[3].plot(t, xy[:, 1], "--", color=COLORS["vermillion"], label="y")
    axs[3].set_ylabel(f"x, y ({unit})")
    axs[3].set_xlabel("t (s)")
    for ax in axs:
        ax.grid(True, color="#e6e6e6", linewidth=0.6)
        _legend(ax, loc="upper right", ncols=2)
    return fig


_TIME_WORDS = ("time", "seconds")


def _stage_times(metrics):
    for key in ("stage_times", "times", "timings"):
        if isinstance(metrics.get(key), dict):
            return {str(k): float(v) for k, v in metrics[key].items()}
    out = {}
    for k, v in metrics.items():
        name = str(k).lower()
        if isinstance(v, (int, float, np.number)) and not isinstance(v, bool) and (
            any(w in name for w in _TIME_WORDS) or name.endswith("_s") or name.startswith("t_")
        ):
            out[str(k)] = float(v)
    return out


def _num(v):
    """Three significant digits without an exponent for everyday magnitudes."""
    return f"{v:.0f}" if abs(v) >= 100 else f"{v:.3g}"


def plot_f_contours(occupied, start, goal, ax=None, *, closed=None, path=None):
    """The value of :math:`f = g^* + h` on every free cell of a 2-joint torus grid, as A* sees it.

    :math:`g^*` is the true step distance from ``start`` (breadth-first search) and :math:`h` the
    toroidal Manhattan distance GD1 to ``goal``. Cells of one value of ``f`` share a colour (its
    contour) and print it; blocked cells are grey, unreachable ones blank. ``closed`` (a boolean
    grid, e.g. the closed set of :func:`rapp.search.astar_search`) outlines the expanded cells;
    ``path`` (cells) is drawn in orange. Returns ``ax``.

    Examples
    --------
    >>> occ = np.zeros((6, 6), bool); occ[3, :5] = True
    >>> ax = plot_f_contours(occ, (1, 2), (5, 2))
    >>> sorted({int(t.get_text()) for t in ax.texts})   # f = 2 on the shortest routes (the seam)
    [2, 4, 6, 8, 10]
    >>> plt.close(ax.figure)
    """
    from rapp.search import bfs_distances, toroidal_manhattan

    occupied = np.asarray(occupied, dtype=bool)
    if occupied.ndim != 2:
        raise ValueError(f"plot_f_contours draws grids of two joints, got {occupied.ndim}")
    ax = _axes(ax, figsize=(6.0, 5.0))
    g = bfs_distances(occupied, tuple(start))
    cells = np.argwhere(np.ones(occupied.shape, bool)).reshape(occupied.shape + (2,))
    f = np.where(g >= 0, g + toroidal_manhattan(cells, tuple(goal), occupied.shape), -1)
    levels = np.unique(f[f >= 0])
    palette = [COLORS[c] for c in ("sky", "green", "yellow", "orange", "purple", "vermillion")]
    index = np.searchsorted(levels, f)
    rgba = np.ones(occupied.shape + (4,))
    for k in range(len(levels)):
        rgba[index == k] = to_rgba(palette[k % len(palette)], 0.55)
    rgba[f < 0] = (1.0, 1.0, 1.0, 1.0)
    rgba[occupied] = to_rgba(OCCUPIED)
    ax.imshow(rgba.transpose(1, 0, 2), origin="lower", interpolation="nearest")
    for (i, j), v in np.ndenumerate(f):
        if v >= 0:
            ax.text(i, j, str(int(v)), ha="center", va="center", fontsize="small", color=TEXT)
    if closed is not None:
        for i, j in np.argwhere(closed):
            ax.add_patch(patches.Rectangle((i - 0.5, j - 0.5), 1, 1, fill=False, edgecolor=TEXT, lw=1.4))
    if path is not None:
        segments = split_at_seam(np.asarray(path, dtype=float), [-0.5, -0.5], list(occupied.shape),
                                 [True, True])
        ax.plot(segments[:, 0], segments[:, 1], "-", color=COLORS["orange"], lw=2.5)
    ax.plot(*start, "o", color=START, ms=9)
    ax.plot(*goal, "*", color=GOAL, ms=13)
    handles = [patches.Patch(facecolor=to_rgba(palette[k % len(palette)], 0.55), label=f"f = {int(v)}")
               for k, v in enumerate(levels)]
    if closed is not None:
        handles.append(patches.Patch(fill=False, edgecolor=TEXT, label="expanded"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    ax.set_xlabel("cell index, joint 1")
    ax.set_ylabel("cell index, joint 2")
    return style_axes(ax)


def _check_astar_step(trace, k):
    if trace.occupied.ndim != 2:
        raise ValueError(f"plot_astar_step draws grids of two joints, got {trace.occupied.ndim}")
    if not 0 <= k <= trace.expansions:
        raise ValueError(
            f"step k must be in 0..{trace.expansions} (the last shows the path), got {k}")


def _relaxed_arrows(ax, current, relaxed) -> None:
    """Purple arrows from ``current`` to each relaxed neighbour; one across the seam leaves
    here and re-enters on the other side."""
    arrow = dict(arrowstyle="-|>", color=COLORS["purple"], lw=1.8, mutation_scale=12)
    u = np.array(current, dtype=float)
    for v in relaxed:
        v = np.array(v, dtype=float)
        d = v - u
        crossed = np.abs(d) > 1
        if crossed.any():
            d = -np.sign(d) * crossed + d * ~crossed
            ax.annotate("", xy=u + 0.75 * d, xytext=u + 0.2 * d, arrowprops=arrow, zorder=6)
            ax.annotate("", xy=v - 0.2 * d, xytext=v - 0.75 * d, arrowprops=arrow, zorder=6)
        else:
            ax.annotate("", xy=u + 0.8 * d, xytext=u + 0.2 * d, arrowprops=arrow, zorder=6)


def _astar_step_title(trace, k, g, closed, frontier, current) -> str:
    """The title of :func:`plot_astar_step`: the expansion with g, h and f, or the end."""
    if current is None:
        return (f"end: goal taken off the open list after {trace.expansions} expansions;\n"
                f"path of cost {trace.cost} rebuilt from the parent map")
    gu = int(g[current])
    hu = float(trace.h[current])
    # trace.h is the weighted heuristic w·h: name it so when the weight is not 1.
    d = np.abs(np.subtract(current, trace.goal))
    gd1 = int(np.where(trace.wraps, np.minimum(d, np.array(trace.occupied.shape) - d), d).sum())
    h_name = "h" if hu == gd1 else "w·h"
    seam = any((np.abs(np.subtract(v, current)) > 1).any() for v in trace.relaxed[k])
    return (f"step {k + 1} of {trace.expansions}: expand {current}, "
            f"g = {gu}, {h_name} = {hu:g}, f = {gu + hu:g}\n"
            f"closed: {int(closed.sum())} cells, open list: {int(frontier.sum())} cells"
            + ("; a step across the seam" if seam else ""))


def plot_astar_step(trace, k, ax=None, *, annotate=True, legend=True):
    """One step of A* on a 2-joint grid: closed set, open list, current cell, the wrap.

    Parameters
    ----------
    trace : rapp.search.AStarTrace
        What :func:`rapp.search.astar_steps` recorded.
    k : int
        The step, ``0 <= k < trace.expansions``: the state right after the
        ``k``-th expansion, with the current cell, the neighbours it relaxed
        (purple arrows; an arrow that leaves the grid re-enters on the other
        side, across the seam) and the chain of parents back to the start.
        ``k == trace.expansions`` is the end: the goal taken off the open list
        and the path reconstructed from the parent map.
    annotate : bool
        Write ``g`` in every reached cell.
    legend : bool
        A legend outside the grid, on the right.

    The first array axis (joint 1) is drawn along x, the second along y, one
    square per cell, indices in cells. Dashed lines mark the seams of the
    wrapping axes.

    Returns
    -------
    Axes

    Examples
    --------
    >>> from rapp.search import astar_steps
    >>> occ = np.zeros((6, 5), bool); occ[2, 1:4] = True
    >>> t = astar_steps(occ, (1, 2), (4, 2))
    >>> ax = plot_astar_step(t, 0)
    >>> ax.get_xlabel(), ax.get_legend() is not None
    ('joint 1 cell index (cells)', True)
    >>> plt.close(ax.figure)
    """
    _check_astar_step(trace, k)
    ax = _axes(ax, figsize=(8.4, 5.6))
    occ = trace.occupied
    M0, M1 = occ.shape
    end = k == trace.expansions
    last = max(k - 1, 0) if end else k
    have = trace.expansions > 0
    closed = trace.closed[last] if have else np.zeros(occ.shape, bool)
    frontier = trace.frontier[last] if have else np.zeros(occ.shape, bool)
    if have:
        g = trace.g[last]
    else:  # the start is the goal: nothing was expanded
        g = np.full(occ.shape, -1)
        g[trace.start] = 0
    kind = np.zeros(occ.shape, dtype=int)
    kind[occ] = 1
    kind[closed] = 2
    kind[frontier] = 3
    colours = ["white", OCCUPIED, COLORS["sky"], COLORS["yellow"], COLORS["orange"]]
    current = None
    if not end:
        current = tuple(int(i) for i in trace.current[k])
        kind[current] = 4
    ext = (-0.5, M0 - 0.5, -0.5, M1 - 0.5)
    ax.imshow(kind.T, origin="lower", extent=ext, cmap=ListedColormap(colours), vmin=-0.5,
              vmax=4.5, interpolation="nearest", aspect="equal", zorder=0)
    ax.set_xticks(np.arange(M0 + 1) - 0.5, minor=True)
    ax.set_yticks(np.arange(M1 + 1) - 0.5, minor=True)
    ax.grid(True, which="minor", color="#cccccc", linewidth=0.6)
    ax.tick_params(which="minor", length=0)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True, steps=[1, 2, 5, 10]))
    ax.yaxis.set_major_locator(MaxNLocator(integer=True, steps=[1, 2, 5, 10]))
    ax.set_xlim(ext[0] - 0.9, ext[1] + 0.9)
    ax.set_ylim(ext[2] - 0.9, ext[3] + 0.9)
    ax.set_xlabel("joint 1 cell index (cells)")
    ax.set_ylabel("joint 2 cell index (cells)")
    handles = [
        patches.Patch(facecolor=OCCUPIED, edgecolor=TEXT, label="blocked"),
        patches.Patch(facecolor=COLORS["sky"], edgecolor=TEXT, label="closed set"),
        patches.Patch(facecolor=COLORS["yellow"], edgecolor=TEXT, label="open list (frontier)"),
    ]
    # The same entries in every frame, so that an animation's legend does not jump.
    handles.append(patches.Patch(facecolor=COLORS["orange"], edgecolor=TEXT, label="current cell"))
    seam = dict(color=TEXT, ls="--", lw=1.6, zorder=3)
    for axis, w in enumerate(trace.wraps):
        if w:
            for x in (-0.5, (M0, M1)[axis] - 0.5):
                (ax.axvline if axis == 0 else ax.axhline)(x, **seam)
    if any(trace.wraps):
        handles.append(Line2D([], [], label="seam (wraps round)", **seam))
    if annotate:
        for c in np.argwhere(g >= 0):
            ax.text(c[0], c[1], str(int(g[tuple(c)])), ha="center", va="center",
                    fontsize="small", color=TEXT, zorder=6,
                    path_effects=[withStroke(linewidth=2.5, foreground="white")])
    lo, span = np.array([-0.5, -0.5]), np.array([M0, M1], dtype=float)
    line = trace.path if end else trace.chain(k)
    seg = split_at_seam(line.astype(float), lo, span, trace.wraps)
    name = f"path, cost {trace.cost}" if end else "parents back to the start"
    ax.plot(seg[:, 0], seg[:, 1], "-", color=COLORS["blue"], lw=2.5, alpha=0.9, zorder=5,
            label=name)
    handles.append(Line2D([], [], color=COLORS["blue"], lw=2.5, label=name))
    if not end:
        _relaxed_arrows(ax, current, trace.relaxed[k])
    handles.append(Line2D([], [], color=COLORS["purple"], lw=1.8, marker=">",
                          label="neighbours relaxed"))
    ax.plot(*trace.start, "o", color=START, ms=12, mec=TEXT, mew=1.0, zorder=7)
    ax.plot(*trace.goal, "*", color=GOAL, ms=17, mec=TEXT, mew=0.8, zorder=7)
    handles += [
        Line2D([], [], ls="", marker="o", color=START, mec=TEXT, ms=10,
                                label="start"),
        Line2D([], [], ls="", marker="*", color=GOAL, mec=TEXT, ms=14,
                                label="goal"),
    ]
    ax.set_title(_astar_step_title(trace, k, g, closed, frontier, current), fontsize="medium")
    if legend:
        _legend(ax, handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                borderaxespad=0.0, fontsize="small")
    return style_axes(ax)


def animate_astar(trace, *, ax=None, interval=800, annotate=True, dpi=80):
    """Animate :func:`plot_astar_step` over every step of a trace, then the reconstructed path.

    Parameters
    ----------
    trace : rapp.search.AStarTrace
    ax : Axes, optional
        Drawn on; by default a new 8.4 x 5.6 inch figure at ``dpi`` (672 x 448
        pixels at 80 dpi), the grid on the left and the legend on the right.
    interval : float
        Milliseconds per frame.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        ``trace.expansions + 1`` frames. Show it with :func:`animation_html`.

    Examples
    --------
    >>> from rapp.search import astar_steps
    >>> anim = animate_astar(astar_steps(np.zeros((5, 5), bool), (0, 0), (4, 2)))
    >>> anim._save_count
    4
    >>> close_animation(anim)
    """
    _check_astar_step(trace, 0)
    return _step_animation(lambda i, ax: plot_astar_step(trace, i, ax, annotate=annotate),
                           trace.expansions + 1, ax, (0.08, 0.09, 0.58, 0.78), interval, dpi)


def _step_animation(draw, frames, ax, box, interval, dpi):
    """A FuncAnimation that redraws ``draw(i, ax)`` from scratch for frame ``i``.

    Without ``ax``, a figure with a fixed layout is made: constrained layout would re-place
    the axes as the title changes from frame to frame.
    """
    if ax is None:
        with plt.rc_context(_LIGHT):
            fig = plt.figure(figsize=(8.4, 5.6), dpi=dpi)
            ax = fig.add_axes(box)
        style_axes(ax)

    def update(i):
        ax.clear()
        draw(i, ax)
        return ()

    update(0)
    return animation.FuncAnimation(ax.figure, update, frames=frames, interval=interval,
                                   blit=False, repeat=True, cache_frame_data=False)


def plot_metrics(metrics, ax=None, *, keys=None, unit="s"):
    """Horizontal bar chart of the stage times in ``metrics``, each bar annotated.

    Parameters
    ----------
    metrics : dict
        ``plan.metrics``. Stage times are taken from a nested ``stage_times``
        (or ``times``) dict when present, else from the numeric entries whose
        name says time (``*time*``, ``*_s``, ``t_*``); ``keys`` picks them
        explicitly. An entry ``total`` is shown in the title, not as a bar.
    unit : str
        Unit of the values; the bars are labelled in milliseconds when it is
        ``"s"``.

    Raises
    ------
    ValueError
        When no stage time is found (the MIS's PLOT_ERROR).

    Examples
    --------
    >>> ax = plot_metrics({"time_ik_s": 0.002, "time_search_s": 0.010, "path_length": 3.0})
    >>> [t.get_text() for t in ax.get_yticklabels()]
    ['time_ik_s', 'time_search_s']
    >>> plt.close(ax.figure)
    """
    times = ({k: float(metrics[k]) for k in keys} if keys is not None else _stage_times(metrics))
    # A total is the sum of the bars, not a stage: it goes in the title.
    total = times.pop("total", None) if keys is None else None
    if not times:
        raise ValueError("metrics holds no stage times to plot")
    ax = _axes(ax, figsize=(6.0, 0.5 + 0.45 * len(times)))
    names = list(times)
    vals = np.array([times[k] for k in names])
    scale, shown = (1e3, "ms") if unit == "s" else (1.0, unit)
    bars = ax.barh(np.arange(len(names)), vals * scale, color=COLORS["sky"], edgecolor=TEXT)
    ax.set_yticks(np.arange(len(names)), names)
    ax.invert_yaxis()
    ax.bar_label(bars, labels=[f"{_num(v * scale)} {shown}" for v in vals], padding=3, color=TEXT,
                 fontsize="small")
    ax.set_xlim(0, max(vals.max() * scale, 1e-12) * 1.25)
    ax.set_xlabel(f"time ({shown})")
    ax.set_title("time per stage" if total is None else
                 f"time per stage (total {_num(total * scale)} {shown})", fontsize="medium")
    return style_axes(ax)


def plot_polynomials(coefficients, t0, tf, *, fig=None, samples=200, axes=None):
    """Position, velocity and acceleration of polynomial segments on ``[t0, tf]``.

    Parameters
    ----------
    coefficients : dict of name -> array_like
        Coefficients in ascending powers of absolute time ``t`` (what
        :func:`rapp.cubic` and :func:`rapp.quintic` return).
    axes : sequence of three Axes, optional
        Drawn into as they are (not cleared); else ``fig`` is cleared and given three.

    Returns
    -------
    Figure
        Three stacked axes: p (rad), p' (rad/s), p'' (rad/s²) against t (s).

    Examples
    --------
    >>> fig = plot_polynomials({"line": [0.0, 1.0]}, 0.0, 2.0)
    >>> [len(ax.lines) for ax in fig.axes]
    [1, 1, 1]
    >>> plt.close(fig)
    """
    P = np.polynomial.polynomial
    if axes is None:
        fig = _figure(fig, (6.5, 6.0))
        fig.clear()
        axs = subplots(fig, 3, 1, sharex=True)
    else:
        axs = list(axes)
        fig = axs[0].figure
    t = np.linspace(t0, tf, samples)
    styles = ["-", "--", ":", "-."]
    for i, (name, c) in enumerate(coefficients.items()):
        c = np.asarray(c, dtype=float)
        color = JOINT_COLORS[i % len(JOINT_COLORS)]
        for d, ax in enumerate(axs):
            ax.plot(t, P.polyval(t, P.polyder(c, d) if d else c), styles[i % 4], color=color,
                    lw=2, label=name)
    for ax, lab in zip(axs, ("p (rad)", "p' (rad/s)", "p'' (rad/s²)")):
        ax.set_ylabel(lab)
        ax.grid(True, color="#e6e6e6", linewidth=0.6)
        _legend(ax, loc="best")
    axs[-1].set_xlabel("t (s)")
    return fig


def plot_segment_circle(a, b, center, radius, ax=None, *, unit="m"):
    """A segment, a disc, the clipped projection and the MIS's infinite-line foot.

    Draws the segment ``ab`` (solid) and the line through it (dotted), the
    disc, the closest point of the segment to the centre (clipped projection,
    TM:SegmentCircleCollision) and the foot of the perpendicular on the
    infinite line (the distance seed 001 uses), each joined to the centre.

    Returns
    -------
    Axes

    Examples
    --------
    >>> ax = plot_segment_circle((0, 0), (1, 0), (1.6, 0.1), 0.3)
    >>> ax.lines[2].get_xydata()[0].round(3).tolist()   # closest point: the segment's end
    [1.0, 0.0]
    >>> ax.lines[3].get_xydata()[0].round(3).tolist()   # foot on the infinite line
    [1.6, 0.0]
    >>> plt.close(ax.figure)
    """

    ax = _axes(ax)
    a, b, c = (np.asarray(v, dtype=float) for v in (a, b, center))
    ab = b - a
    den = float(ab @ ab)
    foot = a + (float((c - a) @ ab) / den if den > 0 else 0.0) * ab
    near = closest_point_on_segment(a, b, c)
    span = max(np.abs(np.concatenate([a, b, c])).max() + radius, 1.0) * 1.2
    u = ab / np.sqrt(den) if den > 0 else np.array([1.0, 0.0])
    far = np.stack((a - 4 * span * u, a + 4 * span * u))
    ax.plot(far[:, 0], far[:, 1], ":", color=COLORS["grey"], lw=1, label="infinite line (MIS)")
    ax.plot([a[0], b[0]], [a[1], b[1]], "-o", color=ARM, lw=3, ms=5, label="segment (link)")
    ax.plot(*near, "o", color=COLORS["green"], ms=8, zorder=5, label="closest point (clipped)")
    ax.plot(*foot, "x", color=COLORS["vermillion"], ms=9, mew=2, zorder=5,
            label="foot on line (MIS)")
    ax.plot([c[0], near[0]], [c[1], near[1]], "--", color=COLORS["green"], lw=1.5)
    ax.plot([c[0], foot[0]], [c[1], foot[1]], ":", color=COLORS["vermillion"], lw=1.5)
    ax.add_patch(patches.Circle(c, radius, facecolor=OBSTACLE, edgecolor=TEXT, alpha=0.6,
                                label="obstacle"))
    ax.set_xlim(-span, span)
    ax.set_ylim(-span, span)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.grid(True, color="#e6e6e6", linewidth=0.6)
    return _legend(ax, loc="lower left")


def _check_rrt_step(result, trace, k):
    if result.nodes.shape[1] < 2:
        raise ValueError("plot_rrt_step draws the first two joints; the arm has one")
    if not 0 <= k <= len(trace):
        raise ValueError(f"step k must be in 0..{len(trace)} (the last shows the path), got {k}")
    added = [s.node for s in trace if s.accepted]
    if added != list(range(1, len(added) + 1)) or len(added) + 1 > len(result.nodes):
        raise ValueError("trace is not the record of this result: pass the list that "
                         "rapp.rrt(..., trace=...) filled")


def _periodic_copies(seg, lo, span, wraps):
    """``seg`` (k, 2, 2) and its copies shifted by whole periods of the wrapping axes.

    An edge is drawn unwrapped from its first end; where it runs past a seam, a copy shifted by one
    period enters from the opposite border. Only copies that reach into the frame are kept; the
    axes clip the rest.
    """
    out = [seg]
    for sx in ((-1, 0, 1) if wraps[0] else (0,)):
        for sy in ((-1, 0, 1) if wraps[1] else (0,)):
            if sx == sy == 0:
                continue
            copy = seg + np.array([sx * span[0], sy * span[1]])
            inside = ((copy.max(1) > lo) & (copy.min(1) < lo + span)).all(-1)
            out.append(copy[inside])
    return np.concatenate(out)


_LIGHT_CSPACE = "#cfcfcf"


def plot_light_cspace(occupancy, grid, ax):
    """A 2-joint occupancy grid in light grey, under a tree or a trace; drawn once per axes.

    A second call on the same axes draws nothing, so a step-through that redraws its tree on
    every step keeps one image (and a view stack keeps it in its static background).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> grid = SimpleNamespace(axes=[np.linspace(-np.pi, np.pi, 4, endpoint=False)] * 2)
    >>> ax = plot_light_cspace(np.eye(4, dtype=bool), grid, plt.figure().add_subplot())
    >>> len(plot_light_cspace(np.eye(4, dtype=bool), grid, ax).images)
    1
    >>> plt.close(ax.figure)
    """
    occ = np.asarray(occupancy)
    if occ.ndim != 2 or grid is None:
        raise ValueError("occupancy must be a 2-joint grid, given with its grid")
    if not any(im.get_gid() == "light-cspace" for im in ax.images):
        ax.imshow(occ.T.astype(float), origin="lower", extent=cell_extent(grid),
                  cmap=ListedColormap(["white", _LIGHT_CSPACE]), vmin=0.0, vmax=1.0,
                  interpolation="nearest", aspect="equal", zorder=0, gid="light-cspace")
    return ax


def plot_tree(arm, nodes, parent, ax=None, *, color=COLORS["sky"]):
    """A planner's tree (or roadmap's shortest-path tree) in the C-space of a 2-joint ``arm``.

    ``nodes`` is ``(k, 2)`` and ``parent[i]`` the index of node ``i``'s parent (negative for a
    root). Each edge is drawn from its parent by :meth:`rapp.Arm.joint_delta` (the short way
    round), and an edge that crosses the seam of the torus is drawn a second time from its
    child's side, so it shows on both sides of the square. Returns ``ax``.

    Examples
    --------
    >>> from rapp import Arm
    >>> nodes = np.array([[0.0, 0.0], [0.5, 0.0], [3.0, 0.0], [-3.0, 0.0]])
    >>> ax = plot_tree(Arm([1.0, 1.0]), nodes, np.array([-1, 0, 1, 2]))
    >>> len(ax.collections[0].get_segments())   # 3 edges, one across the seam drawn twice
    4
    >>> plt.close(ax.figure)
    """
    ax = _axes(ax)
    nodes, parent = np.asarray(nodes, dtype=float), np.asarray(parent)
    child = np.flatnonzero(parent >= 0)
    if child.size:
        a = nodes[parent[child]]
        d = arm.joint_delta(a, nodes[child])
        edges = np.stack((a, a + d), 1)                          # from the parent, unwrapped
        seam = np.abs(a + d - nodes[child]).max(axis=1) > 1e-9   # ... and again from the child
        edges = np.concatenate((edges, np.stack((nodes[child][seam] - d[seam], nodes[child][seam]), 1)))
        ax.add_collection(LineCollection(edges, colors=color, linewidths=0.7))
    ax.plot(*nodes.T, ".", color=color, ms=2)
    return ax


def _rrt_iteration(ax, arm, nodes, s, draw, frame, blocked) -> str:
    """One RRT iteration ``s`` drawn (target, nearest node, the new edge); its title."""
    lo, span, wraps = frame
    near = nodes[s.nearest]
    target = arm.wrap(s.target)
    draw(near[None], (near + arm.joint_delta(near, target))[None], colors=COLORS["purple"],
         linewidths=1.8, linestyles=(0, (1.5, 2.0)), zorder=4)
    ax.plot(*target[:2], "D", color=COLORS["purple"], mec=TEXT, mew=0.8, ms=8, zorder=7)
    ax.plot(*near[:2], "o", mfc="none", mec=COLORS["orange"], mew=2.5, ms=14, zorder=6)
    ok = s.accepted
    colour = COLORS["blue"] if ok else TEXT
    draw(near[None], s.new[None], colors=colour, linewidths=3.0,
         linestyles="-" if ok else "--", zorder=5)
    shown = split_at_seam(np.asarray(s.new, dtype=float)[:2], lo, span, wraps)[0]
    ax.plot(*shown, "o" if ok else "X", color=colour, mec="white" if ok else TEXT, ms=9,
            zorder=6)
    what = ("the last edge, to the goal" if s.join else
            "target: the goal (goal bias)" if s.goal_biased else "target: a random sample")
    verdict = {"added": f"edge certified free, node {s.node} added",
               "blocked": "edge not certified free: rejected",
               "no move": "target is the nearest node: no move"}[s.status]
    return (f"iteration {s.iteration}, {what}\nnearest node {s.nearest}; {verdict} "
            f"({blocked + (s.status == 'blocked')} blocked so far)")


def _rrt_iteration_handles() -> list:
    """Legend entries of :func:`_rrt_iteration`'s marks."""
    return [
        Line2D([], [], ls=(0, (1.5, 2.0)), lw=1.8, marker="D", color=COLORS["purple"], mec=TEXT,
               ms=7, label="target, and the way to it"),
        Line2D([], [], ls="", marker="o", mfc="none", mec=COLORS["orange"], mew=2.5, ms=11,
               label="nearest node"),
        Line2D([], [], color=COLORS["blue"], lw=3, marker="o", mec="white",
               label="new edge: added"),
        Line2D([], [], color=TEXT, lw=2.5, ls="--", marker="X", label="new edge: blocked"),
    ]


def plot_rrt_step(arm, result, trace, k, ax=None, *, occupancy=None, grid=None, goal=None,
                  legend=True):
    """One iteration of RRT in the plane of the first two joints: sample, nearest, new edge.

    Parameters
    ----------
    arm : rapp.Arm
        The arm the tree was grown for (its bounds and which joints wrap).
    result : rapp.RRTResult
        What :func:`rapp.rrt` returned.
    trace : list of rapp.rrt.RRTStep
        The list passed as ``rrt(..., trace=...)``.
    k : int
        ``0 <= k < len(trace)``: the tree as it stood before record ``k``
        (sky blue), the target of that iteration (purple diamond; the goal
        when goal-biased), the nearest node (orange ring), the line toward the
        target (dotted) and the new edge, certified free and added (blue) or
        blocked (black dashed, ending in a cross). ``k == len(trace)`` is the
        end: the whole tree and the path (orange).
    occupancy, grid : optional
        A 2-joint occupancy grid and its :class:`rapp.JointGrid`, drawn
        light grey (the C-space obstacles).
    goal : array_like, shape (n,), optional
        The goal configuration, drawn as a star. By default, the target of
        the last record when that record joins the goal; else no star.
    legend : bool
        A legend outside the frame, on the right.

    Edges are drawn unwrapped from their parent; an edge that crosses the
    seam of a wrapping joint leaves the frame and re-enters on the other side.
    For more than two joints this is the projection on the first two.

    Returns
    -------
    Axes

    Examples
    --------
    >>> from rapp import Arm, Circle, rrt
    >>> arm, steps = Arm([1.0, 1.0]), []
    >>> res = rrt(arm, [0.0, 0.0], [2.0, 1.0], [Circle((1.2, 1.2), 0.3)], step=0.4, seed=0, trace=steps)
    >>> ax = plot_rrt_step(arm, res, steps, 0)
    >>> ax.get_xlabel(), ax.get_legend() is not None
    ('θ1 (rad)', True)
    >>> plt.close(ax.figure)
    """
    _check_rrt_step(result, trace, k)
    ax = _axes(ax, figsize=(8.4, 5.6))
    lo = np.array([arm.lower[0], arm.lower[1]])
    hi = np.array([arm.upper[0], arm.upper[1]])
    span = hi - lo
    wraps = ~np.asarray(arm.limited[:2], dtype=bool)
    end = k == len(trace)
    m = 1 + sum(s.accepted for s in trace[:k]) if not end else len(result.nodes)
    blocked = sum(s.status == "blocked" for s in trace[:k])
    nodes, parent = result.nodes[:m], result.parent[:m]
    handles = []
    if occupancy is not None:
        plot_light_cspace(occupancy, grid, ax)
        handles.append(patches.Patch(facecolor=_LIGHT_CSPACE, edgecolor=TEXT,
                                     label="C-space obstacle"))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    _pi_ticks(ax.xaxis, lo[0], hi[0])
    _pi_ticks(ax.yaxis, lo[1], hi[1])
    ax.set_xlabel("θ1 (rad)")
    ax.set_ylabel("θ2 (rad)")
    seam = dict(color=TEXT, ls="--", lw=1.2, zorder=1)
    for axis in (0, 1):
        if wraps[axis]:
            for x in (lo[axis], hi[axis]):
                (ax.axvline if axis == 0 else ax.axhline)(x, **seam)
    if wraps.any():
        handles.append(Line2D([], [], label="seam (wraps round)", **seam))

    def draw(a, b, **kw):  # a -> b, both (k, n); b unwrapped from a
        seg = np.stack((np.asarray(a, dtype=float)[..., :2], np.asarray(b, dtype=float)[..., :2]),
                       axis=-2).reshape(-1, 2, 2)
        ax.add_collection(LineCollection(_periodic_copies(seg, lo, span, wraps), **kw))

    if m > 1:
        base = nodes[parent[1:]]
        draw(base, base + arm.joint_delta(base, nodes[1:]), colors=COLORS["sky"], linewidths=1.4,
             zorder=2)
    ax.plot(*nodes[:, :2].T, "o", color=COLORS["sky"], mec=COLORS["blue"], mew=0.5, ms=4.5,
            zorder=3)
    handles.append(Line2D([], [], color=COLORS["sky"], lw=1.4, marker="o", ms=4.5,
                          mec=COLORS["blue"], mew=0.5, label=f"tree ({m} nodes)"))
    if goal is None and trace and trace[-1].join:
        goal = trace[-1].target
    if end:
        if result.success:
            p = split_at_seam(result.path[:, :2], lo, span, wraps)
            ax.plot(p[:, 0], p[:, 1], "-", color=PATH, lw=3, zorder=4)
            handles.append(Line2D([], [], color=PATH, lw=3,
                                  label=f"path ({len(result.path)} nodes)"))
            title = (f"end: goal reached after {result.iterations} iterations; path of "
                     f"{result.cost:.2f} rad\nread back from the parent map "
                     f"({m} nodes, {blocked} edges blocked)")
        else:
            title = f"end: no path in {result.iterations} iterations ({m} nodes)"
    else:
        title = _rrt_iteration(ax, arm, nodes, trace[k], draw, (lo, span, wraps), blocked)
        handles += _rrt_iteration_handles()
    q0 = result.nodes[0]
    ax.plot(*q0[:2], "o", color=START, ms=12, mec=TEXT, mew=1.0, zorder=8)
    handles.append(Line2D([], [], ls="", marker="o", color=START, mec=TEXT, ms=10, label="start"))
    if goal is not None:
        g = arm.wrap(np.asarray(goal, dtype=float))
        ax.plot(*g[:2], "*", color=GOAL, ms=18, mec=TEXT, mew=0.8, zorder=8)
        handles.append(Line2D([], [], ls="", marker="*", color=GOAL, mec=TEXT, ms=14,
                              label="goal"))
    ax.set_title(title, fontsize="medium")
    if legend:
        _legend(ax, handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                borderaxespad=0.0, fontsize="small")
    return style_axes(ax)


def animate_rrt(arm, result, trace, *, occupancy=None, grid=None, goal=None, ax=None,
                interval=900, dpi=80):
    """Animate :func:`plot_rrt_step` over every record of a trace, then the path.

    Parameters
    ----------
    arm, result, trace, occupancy, grid, goal
        As for :func:`plot_rrt_step`.
    ax : Axes, optional
        Drawn on; by default a new 8.4 x 5.6 inch figure at ``dpi`` (672 x 448
        pixels at 80 dpi), the C-space on the left and the legend on the right.
    interval : float
        Milliseconds per frame.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        ``len(trace) + 1`` frames. Show it with :func:`animation_html`.

    Examples
    --------
    >>> from rapp import Arm, rrt
    >>> arm, steps = Arm([1.0, 1.0]), []
    >>> res = rrt(arm, [0.0, 0.0], [0.5, 0.0], [], step=0.3, seed=0, trace=steps)
    >>> anim = animate_rrt(arm, res, steps)
    >>> anim._save_count == len(steps) + 1
    True
    >>> close_animation(anim)
    """
    _check_rrt_step(result, trace, 0)
    return _step_animation(
        lambda i, ax: plot_rrt_step(arm, result, trace, i, ax, occupancy=occupancy, grid=grid,
                                    goal=goal),
        len(trace) + 1, ax, (0.09, 0.09, 0.56, 0.78), interval, dpi)


def animate(arm, q, obstacles=(), t=None, trail=True, *, max_frames=60, interval=None, ax=None,
            unit="m", workspace=True):
    """Animate the arm along a trajectory.

    Parameters
    ----------
    arm : rapp.Arm
    q : array_like, shape (k, n)
    obstacles : sequence of Circle / Polygon
    t : array_like, shape (k,), optional
        Times of the samples; shown in the title and used for the frame
        interval so that the animation plays in real time.
    trail : bool
        Draw the end-effector trace up to the current frame.
    max_frames : int
        The trajectory is subsampled evenly to at most this many frames
        (first and last kept), which keeps GIFs and ``to_jshtml`` small.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Keep a reference; close its figure with :func:`close_animation`.

    Examples
    --------
    >>> from rapp import Arm
    >>> q = np.linspace([0.0, 0.0], [np.pi, np.pi / 2], 200)
    >>> anim = animate(Arm([1.0, 1.0]), q)
    >>> anim._save_count  # frames after subsampling 200 samples
    60
    >>> close_animation(anim)
    """
    q = np.asarray(q, dtype=float).reshape(-1, arm.n)
    idx = even_indices(len(q), max_frames)
    pts = arm.joint_positions(q[idx])
    times = None if t is None else np.asarray(t, dtype=float)[idx]
    ax = _axes(ax)
    fig = ax.figure
    if workspace:
        plot_workspace(arm, ax, unit=unit)
    plot_obstacles(obstacles, ax)
    _workspace_frame(ax, arm, unit)
    (links,) = ax.plot([], [], "-o", color=ARM, lw=3, ms=6, mfc="white", mec=ARM, mew=1.5,
                       zorder=3, solid_capstyle="round")
    ax.plot([0.0], [0.0], "s", color=TEXT, ms=9, zorder=4)
    (tip,) = ax.plot([], [], "o", color=EFFECTOR, ms=7, zorder=5)
    (trace,) = ax.plot([], [], "-", color=PATH, lw=1.5, zorder=2)
    title = ax.set_title("", fontsize="medium", color=TEXT)

    def update(i):
        links.set_data(pts[i, :, 0], pts[i, :, 1])
        tip.set_data(pts[i, -1:, 0], pts[i, -1:, 1])
        if trail:
            trace.set_data(pts[: i + 1, -1, 0], pts[: i + 1, -1, 1])
        title.set_text(f"t = {times[i]:.2f} s" if times is not None else f"frame {i + 1}/{len(pts)}")
        return links, tip, trace, title

    if interval is None:
        span = 0.0 if times is None else float(times[-1] - times[0])
        interval = 1000.0 * span / max(len(pts) - 1, 1) if span > 0 else 50.0
    update(0)
    return animation.FuncAnimation(fig, update, frames=len(pts), interval=interval, blit=False,
                                   repeat=True, cache_frame_data=False)


def save_gif(anim, path, fps=15, dpi=80):
    """Write an animation to a GIF with Pillow; return the path.

    Examples
    --------
    >>> import tempfile, os
    >>> from rapp import Arm
    >>> anim = animate(Arm([1.0, 1.0]), np.linspace([0, 0], [1, 1], 3))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = save_gif(anim, os.path.join(d, "a.gif"))
    ...     open(p, "rb").read(6)
    b'GIF89a'
    >>> close_animation(anim)
    """
    path = Path(path)
    anim.save(str(path), writer=animation.PillowWriter(fps=fps), dpi=dpi)
    return path


def close_animation(anim) -> None:
    """Close the figure an animation draws on (after saving it, or when it is no longer shown).

    Examples
    --------
    >>> from rapp import Arm
    >>> anim = animate(Arm([1.0, 1.0]), np.linspace([0, 0], [1, 1], 3))
    >>> n = len(plt.get_fignums()); close_animation(anim); len(plt.get_fignums()) == n - 1
    True
    """
    plt.close(anim._fig)  # matplotlib keeps the figure of an Animation only here


def animation_html(anim, *, default_mode="loop"):
    """The animation as self-contained HTML (``to_jshtml``) with play controls.

    The figure is closed first: otherwise a notebook's inline backend shows
    its last frame as a still image below the player as well. Wrap the result
    in ``IPython.display.HTML`` to show it. The frames are stored as palette
    PNGs (256 colours, no dithering) when that is smaller: line art loses
    nothing visible and the page carries a third of the bytes.

    Examples
    --------
    >>> from rapp import Arm
    >>> anim = animate(Arm([1.0, 1.0]), np.linspace([0, 0], [1, 1], 3))
    >>> html = animation_html(anim)
    >>> "<script" in html, plt.fignum_exists(anim._fig.number)
    (True, False)
    """
    import base64
    import io
    import re

    from PIL import Image

    close_animation(anim)
    html = anim.to_jshtml(default_mode=default_mode)

    def smaller(match):
        raw = base64.b64decode(re.sub(r"[\\\n]", "", match.group(1)))  # to_jshtml wraps lines
        img = Image.open(io.BytesIO(raw)).convert("RGB").quantize(colors=256, dither=Image.Dither.NONE)
        out = io.BytesIO()
        img.save(out, format="PNG", optimize=True)
        best = min(raw, out.getvalue(), key=len)
        return "data:image/png;base64," + base64.b64encode(best).decode("ascii")

    return re.sub(r"data:image/png;base64,([A-Za-z0-9+/=\\\n]+)", smaller, html)


def plot_torus(occupancy, grid, ax=None, *, path=None, start=None, goal=None, major=2.0, minor=0.9,
               title=None, elev=-50.0, azim=90.0):
    """The C-space of a 2-link arm drawn as what it is, a torus: occupied cells, seams, a path.

    Joint 1 goes round the torus' central circle (radius ``major``), joint 2 round its tube
    (radius ``minor``); each grid cell is a patch of the surface, grey where the arm collides.
    The two red circles are the seams along which :func:`plot_cspace` cuts the torus open into
    its flat square (``θ1 = ±π`` and ``θ2 = ±π``); a path that leaves the square through one edge
    and comes back through the other is one unbroken curve here.

    Parameters
    ----------
    occupancy : bool array of ``grid.shape``, two axes that both wrap
    grid : rapp.JointGrid (or anything with ``axes``, ``shape`` and ``wraps``)
    ax : a 3-D Axes, optional (``projection="3d"``); a new figure when None
    path : array_like, shape (k, 2), optional
        Joint angles (radians), drawn just above the surface (its parts on the far side hidden).
    start, goal : array_like, shape (2,), optional
    major, minor : float
        Radii of the central circle and of the tube.
    elev, azim : float
        The viewpoint, degrees (matplotlib's ``view_init``).

    Returns
    -------
    Axes3D

    Examples
    --------
    >>> from rapp import Arm, Circle, JointGrid, occupancy
    >>> arm = Arm([1.0, 1.0]); g = JointGrid(arm, 24)
    >>> occ = occupancy(arm, [Circle((1.5, 0.5), 0.4)], g)
    >>> ax = plot_torus(occ, g, path=[[0.0, 0.0], [3.0, 0.0], [-3.0, 0.5]])
    >>> ax.name, len(ax.collections) >= 1, len(ax.lines)
    ('3d', True, 3)
    >>> plt.close(ax.figure)
    """
    occ = np.asarray(occupancy, dtype=bool)
    if occ.ndim != 2 or tuple(occ.shape) != tuple(grid.shape):
        raise ValueError(f"occupancy must have the grid's shape {tuple(grid.shape)}, got {occ.shape}")
    if not all(grid.wraps):
        raise ValueError("plot_torus draws a grid whose two axes wrap (joints without limits)")
    if ax is None:
        fig = plt.figure(figsize=(5.0, 5.0), layout="constrained")
        ax = fig.add_subplot(projection="3d")
    R, r = float(major), float(minor)

    eye = np.radians([elev, azim])
    eye = np.array([np.cos(eye[0]) * np.cos(eye[1]), np.cos(eye[0]) * np.sin(eye[1]), np.sin(eye[0])])

    def xyz(u, v, lift=1.0):
        rr = r * lift
        return (R + rr * np.cos(v)) * np.cos(u), (R + rr * np.cos(v)) * np.sin(u), rr * np.sin(v)

    def front(u, v, lift):
        """Points of a curve on the surface, NaN where the surface faces away from the eye:
        matplotlib does not sort lines against a surface, so a hidden part would show through."""
        x, y, z = xyz(u, v, lift)
        normal = np.stack([np.cos(v) * np.cos(u), np.cos(v) * np.sin(u), np.sin(v)], axis=-1)
        hidden = normal @ eye < -0.05
        return [np.where(hidden, np.nan, c) for c in (x, y, z)]

    # Cell edges: each sample angle is the centre of its patch, as in plot_cspace's image.
    edges = [np.asarray(a, float)[0] - np.pi / m + 2 * np.pi * np.arange(m + 1) / m
             for a, m in zip(grid.axes, grid.shape)]
    U, V = np.meshgrid(edges[0], edges[1], indexing="ij")
    # Shaded by hand (a light from the eye's side), so that free cells stay nearly white and
    # occupied ones clearly grey on every side of the tube.
    uc, vc = 0.5 * (U[1:, 1:] + U[:-1, :-1]), 0.5 * (V[1:, 1:] + V[:-1, :-1])
    normal = np.stack([np.cos(vc) * np.cos(uc), np.cos(vc) * np.sin(uc), np.sin(vc)], axis=-1)
    light = 0.72 + 0.28 * np.clip(normal @ eye, 0.0, 1.0)
    base = np.where(occ[..., None], np.array(to_rgba(OCCUPIED)[:3]) * 1.15, np.array([1.0, 1.0, 1.0]))
    colors = np.concatenate([np.clip(base * light[..., None], 0, 1), np.ones(occ.shape + (1,))], axis=-1)
    # Lines are drawn over the surface (no per-face depth sorting between them): the view is
    # chosen so that the path lies on the side facing the reader.
    ax.computed_zorder = False
    ax.plot_surface(*xyz(U, V), facecolors=colors, rstride=1, cstride=1, linewidth=0,
                    antialiased=False, shade=False, zorder=1)
    t = np.linspace(-np.pi, np.pi, 181)
    seam = dict(color=COLORS["vermillion"], lw=1.6, ls="--")
    ax.plot(*front(np.full_like(t, np.pi), t, 1.01), **seam, label="seam θ1 = ±π", zorder=3)
    ax.plot(*front(t, np.full_like(t, np.pi), 1.01), **seam, label="seam θ2 = ±π", zorder=3)
    if path is not None:
        p = np.asarray(path, float).reshape(-1, 2)
        # Densified along each step (by the shorter way round), so the curve hugs the surface.
        d = np.diff(p, axis=0)
        d = (d + np.pi) % (2 * np.pi) - np.pi
        s = np.linspace(0.0, 1.0, 6)[:-1]
        dense = np.concatenate([(p[:-1, None, :] + s[None, :, None] * d[:, None, :]).reshape(-1, 2), p[-1:]])
        ax.plot(*front(dense[:, 0], dense[:, 1], 1.04), color=PATH, lw=2.4, label="path", zorder=4)
    for q, color, name in ((start, START, "start"), (goal, GOAL, "goal")):
        if q is not None:
            x, y, z = front(*np.asarray(q, float), 1.06)
            ax.scatter([x], [y], [z], color=color, s=40, depthshade=False, label=name, zorder=5)
    lim = R + r
    ax.set(xlim=(-lim, lim), ylim=(-lim, lim), zlim=(-r, r))
    ax.set_box_aspect((1, 1, r / lim), zoom=1.35)
    ax.view_init(elev=elev, azim=azim)  # the eye of front()
    ax.set_axis_off()
    if title:
        ax.set_title(title)
    return ax


__all__.append("plot_torus")


def plot_tip_paths(arm, obstacles, keep_out, runs, ax=None, *, resolution=0.01):
    """The end effector's trace along each planner result, among the obstacles and a keep-out disc.

    Chapter 12's "Bring your own checker": ``keep_out`` (a :class:`rapp.Circle`) is the region a
    user's ``validity=`` checker kept the tip out of, drawn beside rapp's own obstacles.

    Parameters
    ----------
    arm : rapp.Arm
    obstacles : sequence of Circle or Polygon
    keep_out : rapp.Circle
    runs : mapping of label -> PlannerResult
        Each result's path is sampled every ``resolution`` rad (the short way round) and its
        tip drawn as a line, in the order given (grey, then orange, then the palette).
    ax : matplotlib Axes, optional

    Examples
    --------
    >>> import rapp
    >>> arm = rapp.Arm([1.0, 1.0])
    >>> r = rapp.rrt_connect(arm, [0.0, 0.0], [2.0, 0.5], seed=0)
    >>> ax = plot_tip_paths(arm, [], rapp.Circle((1.2, -0.3), 0.3), {"tip": r})
    >>> ax.lines[-1].get_label(), ax.get_legend() is not None
    ('tip', True)
    >>> plt.close(ax.figure)
    """
    from rapp.validity import motion_samples

    ax = ax if ax is not None else plt.subplots(figsize=(6.4, 5.4), layout="constrained")[1]
    plot_workspace(arm, ax)
    plot_obstacles(obstacles, ax)
    plot_obstacles([keep_out], ax, color=COLORS["purple"], label="keep-out disc (tip)")
    colors = ["grey", "orange"] + [c for c in COLORS if c not in ("grey", "orange")]
    for (label, r), color in zip(runs.items(), colors):
        tips = arm.end_effector(motion_samples(r.path[:-1], r.path[1:], resolution)[0])
        ax.plot(*tips.T, color=COLORS[color], lw=1.5, label=label)
    ax.legend(loc="lower left", fontsize="small")
    style_axes(ax)
    return ax


__all__.append("plot_tip_paths")
