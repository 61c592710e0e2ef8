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


def numbered_pages() -> list[tuple[int, Path]]:
    """(chapter number, notebook) in reading order: a plain walk over the numbered parts of the
    toc, where a chapter's ``sections`` (at any depth) are further pages of the same chapter."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    pages = []

    def files(entry):
        return [entry["file"]] + [f for s in entry.get("sections", []) for f in files(s)]

    chapters = [c for p in toc["parts"] if p.get("numbered") for c in p["chapters"]]
    for number, chapter in enumerate(chapters, 1):
        pages += [(number, ROOT / f"{f}.ipynb") for f in files(chapter)]
    return [(n, path) for n, path in pages if path.exists()]


PAGES = numbered_pages()
CHAPTERS = [(n, p) for i, (n, p) in enumerate(PAGES) if i == 0 or PAGES[i - 1][0] != n]
SPLIT = sorted({n for n, _ in PAGES if sum(m == n for m, _ in PAGES) > 1})
IDS = [p.stem for _, p in PAGES]


@functools.cache
@functools.lru_cache(maxsize=None)
def book_targets():
    """The script's table of the book's numbered targets, built once per process."""
    return number_notebooks.book_targets()


@functools.lru_cache(maxsize=None)
def load(path: Path):
    # Read and validated once per notebook and process (no test changes a notebook).
    return nbformat.read(path, as_version=4)


@functools.lru_cache(maxsize=None)
def body(path: Path) -> str:
    """The page's own Markdown: every Markdown cell but the script's first one."""
    return "\n\n".join(c.source for c in load(path).cells[1:] if c.cell_type == "markdown")


_BOX = r"^(?:`{3,}|:{3,})\{%s\}[^\n]*\n((?:[ \t]*:[\w-]+:[^\n]*\n)*)"
_EQ = r"\$\$.+?\$\$[ \t]*\(([\w.:-]+)\)"


@functools.lru_cache(maxsize=None)
def counted(path: Path) -> dict[str, list[str]]:
    """kind -> labels ("" when none) of the page's numbered items, in reading order, counted by
    hand: code cells' captioned figures, exercise and pseudocode boxes, labelled equations."""
    nb, text = load(path), body(path)
    found = {"figure": [c.metadata["mystnb"]["figure"].get("name", "") for c in nb.cells
                        if c.cell_type == "code"
                        and c.metadata.get("mystnb", {}).get("figure", {}).get("caption")],
             "equation": re.findall(_EQ, text, re.S)}
    for kind, directive in [("exercise", "exercise"), ("proof:algorithm", "prf:algorithm")]:
        opts = [m.group(1) for m in re.finditer(_BOX % directive, text, re.M)]
        found[kind] = [(re.findall(r":label:\s*(\S+)", o) or [""])[0] for o in opts
                       if ":nonumber:" not in o]
    return found


def earlier(number: int, path: Path) -> dict[str, int]:
    """How many of each kind the chapter's pages before ``path`` hold."""
    counts: dict[str, int] = {}
    for n, p in PAGES:
        if p == path:
            return counts
        if n == number:
            for kind, labels in counted(p).items():
                counts[kind] = counts.get(kind, 0) + len(labels)
    raise AssertionError(f"{path} is not in the toc")


def test_every_notebook_is_up_to_date_with_the_toc():
    # The script in --check mode changes nothing and names every stale notebook.
    assert number_notebooks.main(["--check"]) == 0, (
        "run: python scripts/number_notebooks.py (after a toc change or a notebook merge)")


def test_the_split_chapters_are_walked():
    # The toc's sections are pages of their chapter, numbered with it (not chapters of their own).
    numbers = number_notebooks.chapter_numbers()
    assert SPLIT, "no chapter has sections: this file's split-page tests test nothing"
    for n, path in PAGES:
        assert numbers[path.relative_to(ROOT).with_suffix("").as_posix()] == n
    assert max(numbers.values()) == len(CHAPTERS)


@pytest.mark.parametrize("number,path", PAGES, ids=IDS)
def test_first_cell_is_lab_only_front_matter_with_the_chapter_number(number, path):
    nb = load(path)
    first = nb.cells[0]
    assert first.cell_type == "markdown"
    assert "remove-cell" in first.metadata.get("tags", []), "the HTML book must not show it"
    m = re.match(r"---\n(.*?)\n---\n?", first.source, re.S)
    assert m, "jupyterlab-myst reads front matter only at the very top of the first cell"
    front = yaml.safe_load(m.group(1))
    # A later page of a split chapter continues its numbers: jupyterlab-myst's per-kind
    # `start` is the first number Lab gives that kind on this page.
    starts = {kind: {"start": k + 1} for kind, k in earlier(number, path).items() if k}
    assert front == {"numbering": {"enumerator": f"{number}.%s", **starts}}
    # exactly one such cell, and the page's own first cell (its title, maybe labelled) follows it
    assert sum(number_notebooks.is_front_matter_cell(c) for c in nb.cells) == 1
    assert nb.cells[1].cell_type == "markdown"
    assert re.match(r"(\([\w.:-]+\)=\n)?# ", nb.cells[1].source), (
        "the page does not open with its title: text before it shows above the title in the "
        "book and in Lab")


@pytest.mark.parametrize("number,path", CHAPTERS, ids=[p.stem for _, p in CHAPTERS])
def test_lab_numbers_exercises_as_the_catalog_does(number, path):
    # rapp.exercises.check("N.k") is the k-th exercise box of chapter N, in reading order across
    # the chapter's pages; Lab numbers each page's boxes from its front matter's start.
    boxes = sum(len(counted(p)["exercise"]) for n, p in PAGES if n == number)
    ids = sorted(int(e.id.split(".")[1]) for e in rapp.exercises.catalog() if e.chapter == number)
    assert ids == list(range(1, boxes + 1))


@pytest.mark.parametrize("number,path", PAGES, ids=IDS)
def test_lab_counts_to_the_books_numbers(number, path):
    # Lab counts the page's own exercises, algorithms and equations from the front matter's
    # start (figures come from code cells, numbered in the index); the book counts over the
    # chapter. Each labelled one must get the same number from both.
    targets = book_targets()
    start = earlier(number, path)
    for kind in ("equation", "exercise", "proof:algorithm"):
        for k, label in enumerate(counted(path)[kind], start.get(kind, 0) + 1):
            # (a label also used by a heading is the heading's in the script's table)
            if label and targets[label].kind == kind:
                assert targets[label].number == f"{number}.{k}", (kind, label)


@pytest.mark.parametrize("number,path", PAGES, ids=IDS)
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
    targets = book_targets()
    assert [targets[n].number for n in names] == [f"5.{k}" for k in range(1, len(names) + 1)]
    index = nb.cells[0].source
    for k, name in enumerate(names, 1):
        assert f":label: {name}\n:enumerator: 5.{k}\n" in index


@pytest.mark.parametrize("number,path", PAGES, ids=IDS)
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
