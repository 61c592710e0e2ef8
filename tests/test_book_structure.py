"""The book's structure: the toc, the committed notebooks and the SRS page.

Notebooks are committed with their outputs, and nbval re-runs them; these tests check what nbval
does not: that the saved outputs come from one clean top-to-bottom run (scripts/execute_notebooks.py),
that widgets carry the saved state the static book needs, and that every SRS item has its label.
"""

from __future__ import annotations

import re
from pathlib import Path

import nbformat
import pytest
import yaml

from rapp.traceability import SRS_ITEMS, srs_label

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
WIDGET_STATE = "application/vnd.jupyter.widget-state+json"

SRS_LABELS = [srs_label(item) for item in SRS_ITEMS]
# Printed timings differ run to run, so nbval would fail on them, and they belong in benchmarks/.
TIMING = re.compile(r"Wall time|CPU times|per loop|[Ee]lapsed|took \d|\d\s*(ms|µs|us)\b")
TIMING_MAGIC = re.compile(r"^\s*%{1,2}(time|timeit|prun)\b", re.MULTILINE)
# Animation frames are base64 images inside to_jshtml's HTML; their letters can spell "7ms".
BASE64_DATA = re.compile(r"data:[\w/+.-]+;base64,[A-Za-z0-9+/=\\\s]+")


def resolve(entry: str) -> Path | None:
    for suffix in ("", ".md", ".ipynb"):
        path = ROOT / (entry + suffix)
        if path.is_file():
            return path
    return None


from test_traceability import toc_files  # noqa: E402  one reader of _toc.yml for both checks

TOC = toc_files(yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8")))


def test_toc_lists_the_pages_of_the_book():
    assert TOC[0] == "book/intro"
    for required in ("book/srs", "notebooks/09_requirements", "book/references", "book/glossary"):
        assert required in TOC
    assert len(TOC) == len(set(TOC)), "a page is listed twice"


@pytest.mark.parametrize("entry", TOC)
def test_toc_entry_exists(entry):
    assert resolve(entry) is not None, f"_toc.yml lists {entry}, which is not a .md or .ipynb file"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_every_notebook_is_in_the_toc(path):
    assert path.relative_to(ROOT).with_suffix("").as_posix() in TOC, (
        f"{path.name} is not in _toc.yml, so it is not in the book"
    )


def test_config_does_not_execute_notebooks():
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["execute"]["execute_notebooks"] == "off"
    assert config["only_build_toc_files"] is True
    static = config["sphinx"]["config"]["html_static_path"]
    assert "_static" not in static and all(not s.startswith("http") for s in static)


def code_cells(nb):
    return [cell for cell in nb.cells if cell.cell_type == "code"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_starts_with_matplotlib_inline(path):
    cells = code_cells(nbformat.read(path, as_version=4))
    assert cells, "a chapter without code"
    first_line = cells[0].source.strip().splitlines()[0].strip()
    assert first_line == "%matplotlib inline"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_was_executed_top_to_bottom_without_errors(path):
    cells = code_cells(nbformat.read(path, as_version=4))
    counts = [cell.execution_count for cell in cells]
    assert counts == list(range(1, len(cells) + 1)), (
        "execute with scripts/execute_notebooks.py: code cells must run once, in order, from 1"
    )
    for cell in cells:
        assert cell.source.strip(), "empty code cell"
        for output in cell.outputs:
            assert output.output_type != "error", f"error output in cell {cell.execution_count}"
            if output.output_type == "stream" and output.name == "stderr":
                assert "Traceback" not in output.text


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_widgets_have_saved_state(path):
    nb = nbformat.read(path, as_version=4)
    views = [
        output.data[WIDGET_VIEW]["model_id"]
        for cell in code_cells(nb)
        for output in cell.outputs
        if WIDGET_VIEW in output.get("data", {})
    ]
    uses_widgets = any("ipywidgets" in cell.source for cell in code_cells(nb))
    if not (views or uses_widgets):
        return
    assert views, "ipywidgets imported but no widget view saved in the outputs"
    state = nb.metadata.get("widgets", {}).get(WIDGET_STATE, {}).get("state", {})
    missing = [model for model in views if model not in state]
    assert state and not missing, (
        "widget state not saved (blank in the book): execute with scripts/execute_notebooks.py"
    )


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_prints_no_timings(path):
    nb = nbformat.read(path, as_version=4)
    for cell in code_cells(nb):
        assert not TIMING_MAGIC.search(cell.source), "timing magic in a chapter"
        assert "execution" not in cell.metadata, "cell timing metadata saved"
        for output in cell.outputs:
            texts = [output.get("text", "")] + [
                value for key, value in output.get("data", {}).items()
                if key in ("text/plain", "text/html") and isinstance(value, str)
            ]
            for text in texts:
                text = BASE64_DATA.sub("", text)
                assert not TIMING.search(text), f"a timing printed in cell {cell.execution_count}"


@pytest.mark.parametrize("label", SRS_LABELS)
def test_srs_page_has_every_item_label(label):
    text = (ROOT / "book" / "srs.md").read_text(encoding="utf-8")
    assert re.search(rf"^\({re.escape(label)}\)=\s*\n#+ ", text, re.MULTILINE), (
        f"book/srs.md needs `({label})=` right above a heading"
    )


def test_book_sources_do_not_point_outside_the_repository():
    sources = list((ROOT / "book").glob("*.md")) + NOTEBOOKS
    for path in sources:
        text = path.read_text(encoding="utf-8")
        assert "/work/" not in text and "file://" not in text, path.name
        assert "](../../" not in text, f"{path.name} links outside the repository"
