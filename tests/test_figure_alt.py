"""Every figure of the book is described, and shown at a size a phone can read (issues 38.2, 33.1).

Alt texts: a chapter's figure is a code cell's PNG output; myst-nb writes the cell's
``metadata.mystnb.image.alt`` as the ``<img>``'s alt (without it, the alt is the image's own file
path). A matplotlib animation (to_jshtml) gets ``metadata.rapp.alt`` on its frame
(book/_ext/reader_pages.py). The text must say what a reader sees, so it is long enough to do so
and is not the caption again. The texts are written by /work/wt/apply_alt_texts.py-style edits
of the metadata only; these tests read the notebooks as they are committed, without running them.

Legible width: reader_pages.legible_width reads the smallest text a figure records
(rapp.plotting.book_png's ``rapp:text-px``) and gives the width at which it shows at 9 CSS px.
"""

from __future__ import annotations

import difflib
import importlib.util
import io
import re
import sys
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
MIN_ALT = 80          # characters: room for a shape, a place and a comparison
MAX_CAPTION_LIKE = 0.6  # difflib ratio above which an alt text is the caption reworded

spec = importlib.util.spec_from_file_location("reader_pages", ROOT / "book" / "_ext" / "reader_pages.py")
reader_pages = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = reader_pages
spec.loader.exec_module(reader_pages)


def figure_cells():
    """(id, kind, alt, caption) for every code cell with a PNG or an animation among its outputs."""
    found = []
    for path in NOTEBOOKS:
        nb = nbformat.read(path, as_version=4)
        for k, cell in enumerate(nb.cells):
            if cell.cell_type != "code":
                continue
            kinds = set()
            for out in cell.get("outputs", []):
                data = out.get("data", {})
                if "image/png" in data:
                    kinds.add("image")
                elif "_anim_img" in "".join(data.get("text/html", "")):
                    kinds.add("animation")
            if not kinds:
                continue
            meta = cell.metadata
            kind = "image" if "image" in kinds else "animation"
            alt = (meta.get("mystnb", {}).get("image", {}).get("alt") if kind == "image"
                   else meta.get("rapp", {}).get("alt"))
            caption = meta.get("mystnb", {}).get("figure", {}).get("caption", "")
            found.append((f"{path.stem}[{k}]", kind, alt, caption))
    return found


FIGURES = figure_cells()


def words(text: str) -> str:
    """Lower-case words only: TeX, markup and punctuation removed."""
    text = re.sub(r"\$[^$]*\$|\{[a-z]+\}`[^`]*`", " ", text or "")
    return " ".join(re.findall(r"[a-z0-9]+", text.lower()))


def test_the_book_has_figures_and_animations():
    kinds = [kind for _, kind, _, _ in FIGURES]
    assert kinds.count("image") >= 60 and kinds.count("animation") >= 3


@pytest.mark.parametrize("name,kind,alt,caption", FIGURES, ids=[f[0] for f in FIGURES])
def test_every_figure_says_what_a_reader_sees(name, kind, alt, caption):
    assert alt, f"{name}: no alt text ({'mystnb.image.alt' if kind == 'image' else 'rapp.alt'})"
    assert len(alt) >= MIN_ALT, f"{name}: {len(alt)} characters say too little"
    assert not re.search(r"_images/|[0-9a-f]{32}", alt), "the file path is not a description"
    a, c = words(alt), words(caption)
    if c:
        assert a not in c and c not in a, "the caption again"
        assert difflib.SequenceMatcher(None, a, c).ratio() < MAX_CAPTION_LIKE, "the caption reworded"


def test_alt_texts_are_not_repeated():
    alts = [alt for _, _, alt, _ in FIGURES if alt]
    assert len(alts) == len(set(alts))


def test_the_caption_check_can_fail():
    caption = "The benchmark in the plane (left: two 1 m links, three discs)."
    assert difflib.SequenceMatcher(None, words(caption), words(caption + " Shown.")).ratio() >= MAX_CAPTION_LIKE


def test_legible_width_shows_the_smallest_text_at_9_px():
    from matplotlib.figure import Figure

    from rapp.plotting import book_png

    fig = Figure(figsize=(7.0, 3.0))
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1])
    ax.set_xlabel("x (m)")
    data = book_png(fig)
    text_px = float(reader_pages.png_text(data)["rapp:text-px"])
    width = reader_pages.png_width(data)
    shown = reader_pages.legible_width(data)
    assert text_px * shown / width >= 9.0 > text_px * (shown - 1) / width
    assert shown <= width


def test_a_figure_without_a_text_size_keeps_its_width():
    from PIL import Image

    buf = io.BytesIO()
    Image.new("RGB", (300, 20)).save(buf, "PNG")
    assert reader_pages.legible_width(buf.getvalue()) is None
    assert reader_pages.png_text(b"not a png") == {}


def test_a_figure_drawn_with_small_text_is_not_blown_up():
    from PIL import Image
    from PIL.PngImagePlugin import PngInfo

    info = PngInfo()
    info.add_text("rapp:text-px", "6")
    buf = io.BytesIO()
    Image.new("RGB", (400, 20)).save(buf, "PNG", pnginfo=info)
    assert reader_pages.legible_width(buf.getvalue()) == 400


def test_a_script_repeated_in_the_head_is_kept_once():
    page = ('<head><script>const A = 1</script>\n<script src="x.js"></script>\n'
            '<script>const A = 1</script>\n</head><body><script>f()</script><script>f()</script></body>')
    assert reader_pages.dedupe_head_scripts(page) == (
        '<head><script>const A = 1</script>\n<script src="x.js"></script>\n'
        '</head><body><script>f()</script><script>f()</script></body>')
    assert reader_pages.dedupe_head_scripts("<p>no head</p>") == "<p>no head</p>"
