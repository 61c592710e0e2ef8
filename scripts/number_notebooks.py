"""Give every chapter notebook the book's numbers in JupyterLab: one front-matter cell per chapter.

The HTML book numbers chapter N's exercises, algorithms, equations and figures N.1, N.2, … from the
chapter's place in ``_toc.yml``. JupyterLab (jupyterlab-myst) numbers a notebook on its own, from 1,
unless the notebook's first markdown cell starts with MyST front matter; this script writes that
cell::

    ---
    numbering:
      enumerator: "5.%s"
    ---

jupyterlab-myst reads front matter only from the first markdown cell (not from the notebook's
metadata), and Jupyter Book 1.x (myst-nb) turns the front-matter rule off inside notebooks, where a
``---`` block would print as a rule and a heading. So the front matter gets a cell of its own,
first, tagged ``remove-cell``: myst-nb drops it from the HTML book, Lab reads it. The cell is
recognised by its metadata (``"rapp": {"frontmatter": true}``), never by its text, and is rewritten
from the toc on every run: run it after any change to ``_toc.yml`` or after merging notebooks
(``python scripts/number_notebooks.py``; ``--check`` only reports, exit status 1 when a notebook
is out of date). Only that cell changes; nothing else in a notebook is touched.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import nbformat
import yaml

ROOT = Path(__file__).resolve().parents[1]
MARK = "frontmatter"


def chapter_numbers(toc_path: Path = ROOT / "_toc.yml") -> dict[str, int]:
    """Chapter number of every file in the numbered parts of the toc, as the book numbers them.

    The numbered parts share one sequence (``use_multitoc_numbering``): the first chapter of a
    part continues from the last chapter of the part before.

    >>> numbers = chapter_numbers()
    >>> numbers["notebooks/05_astar"]
    5
    """
    toc = yaml.safe_load(toc_path.read_text(encoding="utf-8"))
    numbers: dict[str, int] = {}
    for part in toc.get("parts", []):
        if not part.get("numbered"):
            continue
        for chapter in part.get("chapters", []):
            numbers[chapter["file"]] = len(numbers) + 1
    return numbers


def front_matter(number: int) -> str:
    """The source of chapter ``number``'s front-matter cell.

    ``enumerator`` is a template for every numbered kind (exercise, algorithm, equation, figure);
    equations keep their parentheses, as in the book: (5.1).

    >>> print(front_matter(5))
    ---
    numbering:
      enumerator: "5.%s"
    ---
    """
    return "\n".join(["---", "numbering:", f'  enumerator: "{number}.%s"', "---"])


def is_front_matter_cell(cell) -> bool:
    return cell.cell_type == "markdown" and bool(cell.metadata.get("rapp", {}).get(MARK))


def numbered(nb, number: int):
    """A copy of notebook ``nb`` whose first cell is chapter ``number``'s front matter."""
    nb = nbformat.from_dict(nb)
    cells = [c for c in nb.cells if not is_front_matter_cell(c)]
    cell = nbformat.v4.new_markdown_cell(
        front_matter(number), metadata={"tags": ["remove-cell"], "rapp": {MARK: True}})
    cell.id = f"rapp-frontmatter-{number:02d}"  # stable, so a re-run changes nothing
    nb.cells = [cell, *cells]
    return nb


def _write_atomic(nb, path: Path) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".ipynb")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            nbformat.write(nb, f)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="change nothing; exit 1 when a notebook's front matter is out of date")
    args = parser.parse_args(argv)
    stale = []
    for docname, number in chapter_numbers().items():
        path = ROOT / f"{docname}.ipynb"
        if not path.exists():
            continue  # a Markdown page: Sphinx numbers it, Lab never opens it
        nb = nbformat.read(path, as_version=4)
        new = numbered(nb, number)
        if nbformat.writes(new) == nbformat.writes(nb):
            continue
        stale.append(path.relative_to(ROOT).as_posix())
        if not args.check:
            _write_atomic(new, path)
    verb = "out of date" if args.check else "numbered"
    for name in stale:
        print(f"{verb}: {name}")
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
