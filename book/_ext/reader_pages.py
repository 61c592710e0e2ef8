"""Sphinx extension: pages a phone can read and a screen reader can use, with a clean console.

- **Figures on a phone.** Every book figure (rapp.plotting.book_png) records its smallest text, in
  pixels of the PNG, in the text chunk ``rapp:text-px``. A figure shown narrower than it was
  drawn shrinks its text with it: a 750 px figure with 13.9 px text, squeezed into a 358 px phone
  column, shows 6.6 px text. Each such ``<img>`` gets ``style="--rapp-min-w: Wpx"``, the width at
  which its smallest text shows at :data:`MIN_TEXT_PX` CSS px (never more than the PNG's own
  width), and is wrapped in ``span.rapp-figure-scroll``. rapp.css makes that width a
  ``min-width``: where the column is narrower (a phone), the figure's own box scrolls sideways
  inside the column, its caption staying put, instead of shrinking the text past legibility.
  Where the column is wider (a laptop), nothing changes.
- **No console errors.** sphinx-thebe's inline script (``const THEBE_JS_URL = …``) is registered
  twice by Jupyter Book, and a second ``const`` of the same name is a SyntaxError on every page;
  after the build, each page's head keeps one copy of each script. The pydata theme logs "Got invalid theme mode" when no default mode is
  set; it is set to light (the figures are drawn on white).
- **Animations described.** A cell's ``metadata.rapp.alt`` becomes the alt text of its
  animation's frame (myst-nb's ``mystnb.image.alt`` does it for a figure's PNG).
- **MathJax 2's API for the widget manager.** The ipywidgets HTML manager typesets a widget's label
  with ``MathJax.Hub.Queue`` (MathJax 2); the book serves MathJax 3. ``mathjax_hub.js``
  (book/_static_book) gives MathJax 3 that one entry point, loaded before the widget manager.
"""

from __future__ import annotations

import html
import math
import re
import struct
import zlib
from pathlib import Path

from docutils import nodes

MIN_TEXT_PX = 9.0  # the smallest figure text a reader should see, CSS px (scripts/check_book.py)

_IMG = re.compile(r'<img\b[^>]*?\bsrc="([^"]*_images/([^"/]+\.png))"[^>]*>')


def png_text(data: bytes) -> dict[str, str]:
    """The ``tEXt`` chunks of a PNG, read up to its image data.

    >>> import io, PIL.Image, PIL.PngImagePlugin
    >>> info = PIL.PngImagePlugin.PngInfo(); info.add_text("rapp:text-px", "13.89")
    >>> buf = io.BytesIO(); PIL.Image.new("RGB", (4, 4)).save(buf, "PNG", pnginfo=info)
    >>> png_text(buf.getvalue())["rapp:text-px"]
    '13.89'
    """
    out: dict[str, str] = {}
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return out
    i = 8
    while i + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[i:i + 8])
        if kind in (b"IDAT", b"IEND"):
            break
        body = data[i + 8:i + 8 + length]
        if kind == b"tEXt" and b"\0" in body:
            key, value = body.split(b"\0", 1)
            out[key.decode("latin-1")] = value.decode("latin-1")
        elif kind == b"zTXt" and b"\0" in body:
            key, rest = body.split(b"\0", 1)
            out[key.decode("latin-1")] = zlib.decompress(rest[1:]).decode("latin-1")
        i += 12 + length
    return out


def png_width(data: bytes) -> int:
    """The PNG's width in pixels, from its IHDR chunk."""
    return struct.unpack(">I", data[16:20])[0]


def legible_width(data: bytes, min_px: float = MIN_TEXT_PX) -> int | None:
    """The narrowest width (CSS px) at which the figure's smallest text shows at ``min_px``.

    None for an image without a recorded text size. Never more than the PNG's own width: a
    figure is not blown up past the size it was drawn at.

    >>> import io, PIL.Image, PIL.PngImagePlugin
    >>> info = PIL.PngImagePlugin.PngInfo(); info.add_text("rapp:text-px", "13.5")
    >>> buf = io.BytesIO(); PIL.Image.new("RGB", (750, 10)).save(buf, "PNG", pnginfo=info)
    >>> legible_width(buf.getvalue())
    500
    """
    try:
        text_px = float(png_text(data).get("rapp:text-px") or "nan")
    except ValueError:
        return None
    if not text_px > 0:
        return None
    width = png_width(data)
    return min(width, math.ceil(width * min_px / text_px))


def _image_sources(app) -> dict[str, Path]:
    """Image file name in _images/ -> the file Sphinx copies there."""
    return {uniq: Path(app.srcdir) / src for src, (_docs, uniq) in app.env.images.items()}


def _page(app, pagename, templatename, context, doctree):
    body = context.get("body")
    if not body or "_images/" not in body:
        return
    sources = _image_sources(app)
    widths: dict[str, int | None] = {}

    def widen(m: re.Match) -> str:
        tag, name = m.group(0), m.group(2)
        if name not in widths:
            path = sources.get(name)
            widths[name] = legible_width(path.read_bytes()) if path and path.is_file() else None
        width = widths[name]
        if width is None or "--rapp-min-w" in tag:
            return tag
        img = tag[:4] + f' style="--rapp-min-w: {width}px"' + tag[4:]
        # Its own sideways-scrolling box, so that the caption below stays in the column.
        return f'<span class="rapp-figure-scroll">{img}</span>'

    context["body"] = _IMG.sub(widen, body)


def _describe_animations(app, doctree, docname=None):
    """Put a cell's ``metadata.rapp.alt`` on its animation's frame (matplotlib's to_jshtml).

    The player shows one ``<img id="_anim_img…">`` at a time; its alt text (and the player's
    role and name) gives a screen reader what a sighted reader sees moving.
    """
    for cell in doctree.findall(nodes.container):
        text = (cell.get("cell_metadata") or {}).get("rapp", {}).get("alt")
        if not text:
            continue
        alt = html.escape(text, quote=True)
        for raw in cell.findall(nodes.raw):
            source = raw.astext()
            if "_anim_img" not in source or 'id="_anim_img' not in source:
                continue
            new = re.sub(r'<img id="_anim_img', f'<img alt="{alt}" id="_anim_img', source, count=1)
            raw.children = [nodes.Text(new)]
            raw["rapp_described"] = True


_SCRIPT = re.compile(r"<script\b[^>]*>.*?</script>\s*", re.S)


def dedupe_head_scripts(page: str) -> str:
    """``page`` with every repeated ``<script>`` element of its ``<head>`` removed, the first
    copy kept; the body is left as it is (tests/test_figure_alt.py)."""
    end = page.find("</head>")
    if end < 0:
        return page
    seen: set[str] = set()

    def once(m: re.Match) -> str:
        tag = m.group(0).strip()
        if tag in seen:
            return ""
        seen.add(tag)
        return m.group(0)

    return _SCRIPT.sub(once, page[:end]) + page[end:]


def _dedupe_scripts(app, exception):
    """Jupyter Book registers sphinx-thebe's inline script twice; the second ``const`` of the
    same name throws on every page. Each page's head keeps one copy of each script."""
    if exception is not None or app.builder.format != "html":
        return
    for path in Path(app.outdir).rglob("*.html"):
        page = path.read_text(encoding="utf-8")
        new = dedupe_head_scripts(page)
        if new != page:
            path.write_text(new, encoding="utf-8")


def _config(app, config):
    # pydata-sphinx-theme reads its default colour mode from the template context.
    context = dict(config.html_context or {})
    context.setdefault("default_mode", "light")
    config.html_context = context


def setup(app):
    app.connect("config-inited", _config)
    app.connect("doctree-resolved", _describe_animations)  # after myst-nb picks the output
    app.connect("html-page-context", _page, priority=900)
    app.connect("build-finished", _dedupe_scripts)
    # Before the widget manager (nb_ipywidgets_js, priority 500) and MathJax (defer).
    app.add_js_file("mathjax_hub.js", priority=150)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
