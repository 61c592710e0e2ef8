"""The numbers JupyterLab shows are the book's: each chapter's front matter matches _toc.yml.

scripts/number_notebooks.py writes, into each chapter's first cell, the MyST front matter that
jupyterlab-myst reads (``numbering: enumerator: "N.%s"``) and a folded index of the targets Lab
cannot find by itself. These tests hold that cell to the toc and to the exercise catalog, with
oracles of their own (a plain walk over the toc, a plain count of directives), so a chapter that
moves in the toc, or a notebook merged without re-running the script, fails here.
"""

from __future__ import annotations

import functools
import importlib.util
import re
import sys
from pathlib import Path

import nbformat
import pytest
import yaml

import rapp

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("number_notebooks", ROOT / "scripts" / "number_notebooks.py")
number_notebooks = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = number_notebooks  # dataclasses look their module up there
spec.loader.exec_module(number_notebooks)


def numbered_chapters() -> list[tuple[int, Path]]:
    """(number, notebook) in book order: a plain walk over the numbered parts of the toc."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = [c["file"] for p in toc["parts"] if p.get("numbered") for c in p["chapters"]]
    return [(i, ROOT / f"{f}.ipynb") for i, f in enumerate(files, 1) if (ROOT / f"{f}.ipynb").exists()]


CHAPTERS = numbered_chapters()


@functools.cache
def load(path: Path):
    return nbformat.read(path, as_version=4)  # validated here, once per notebook


def test_every_notebook_is_up_to_date_with_the_toc():
    # The script in --check mode changes nothing and names every stale notebook.
    assert number_notebooks.main(["--check"]) == 0, (
        "run: python scripts/number_notebooks.py (after a toc change or a notebook merge)")


@pytest.mark.parametrize("number,path", CHAPTERS, ids=[p.stem for _, p in CHAPTERS])
def test_first_cell_is_lab_only_front_matter_with_the_chapter_number(number, path):
    nb = load(path)
    first = nb.cells[0]
    assert first.cell_type == "markdown"
    assert "remove-cell" in first.metadata.get("tags", []), "the HTML book must not show it"
    m = re.match(r"---\n(.*?)\n---\n?", first.source, re.S)
    assert m, "jupyterlab-myst reads front matter only at the very top of the first cell"
    front = yaml.safe_load(m.group(1))
    assert front == {"numbering": {"enumerator": f"{number}.%s"}}
    # exactly one such cell, and the chapter's own first cell (its title) follows it
    assert sum(number_notebooks.is_front_matter_cell(c) for c in nb.cells) == 1
    assert nb.cells[1].cell_type == "markdown" and nb.cells[1].source.startswith("# ")


@pytest.mark.parametrize("number,path", CHAPTERS, ids=[p.stem for _, p in CHAPTERS])
def test_lab_numbers_exercises_as_the_catalog_does(number, path):
    # rapp.exercises.check("N.k") is the k-th exercise box of chapter N, in reading order.
    nb = load(path)
    body = "\n\n".join(c.source for c in nb.cells[1:] if c.cell_type == "markdown")
    boxes = len(re.findall(r"^(?:`{3,}|:{3,})\{exercise\}", body, re.M))
    ids = sorted(int(e.id.split(".")[1]) for e in rapp.exercises.catalog() if e.chapter == number)
    assert ids == list(range(1, boxes + 1))


@pytest.mark.parametrize("number,path", CHAPTERS, ids=[p.stem for _, p in CHAPTERS])
def test_every_reference_has_a_target_in_lab(number, path):
    # What Lab parses: every Markdown cell, the front-matter cell's index included.
    nb = load(path)
    text = "\n\n".join(c.source for c in nb.cells if c.cell_type == "markdown")
    defined = set(re.findall(r"^\(([\w.:-]+)\)=", text, re.M))
    defined |= set(re.findall(r"^\s*:label:\s*(\S+)", text, re.M))
    defined |= set(re.findall(r"\$\$[ \t]*\(([\w.:-]+)\)", text))
    refs = {m.strip() for m in re.findall(r"\{(?:ref|numref|prf:ref|eq)\}`(?:[^`<]*<)?([^`<>\n]+)>?`", text)}
    assert refs - defined == set()


def test_figure_numbers_follow_the_notebook_order():
    # Chapter 5's code-cell figures, counted here by hand, against the script's index.
    nb = load(ROOT / "notebooks" / "05_astar.ipynb")
    names = [c.metadata["mystnb"]["figure"]["name"] for c in nb.cells
             if c.cell_type == "code" and "figure" in c.metadata.get("mystnb", {})]
    targets = number_notebooks.book_targets()
    assert [targets[n].number for n in names] == [f"5.{k}" for k in range(1, len(names) + 1)]
    index = nb.cells[0].source
    for k, name in enumerate(names, 1):
        assert f":label: {name}\n:enumerator: 5.{k}\n" in index


@pytest.mark.parametrize("number,path", CHAPTERS, ids=[p.stem for _, p in CHAPTERS])
def test_unlabelled_equations_come_after_the_labelled_ones(number, path):
    # The book numbers labelled display equations only (math_number_all off); jupyterlab-myst
    # numbers every one and has no per-equation switch that Sphinx also accepts. Their numbers
    # agree while no unlabelled equation comes before a labelled one.
    nb = load(path)
    body = "\n\n".join(c.source for c in nb.cells[1:] if c.cell_type == "markdown")
    kinds = ["L" if m.group(1) else "U"
             for m in re.finditer(r"\$\$.+?\$\$[ \t]*(\([\w.:-]+\))?", body, re.S)]
    assert "UL" not in "".join(kinds), (
        "an unlabelled $$ equation before a labelled one: Lab's numbers would run ahead of the "
        "book's; give it a label or move it")
