"""A chapter's links open in JupyterLab, whichever way Lab is started (issue 33.7).

The README starts Lab with ``jupyter lab notebooks/`` (Lab's root is notebooks/); each chapter page
of the book says ``jupyter lab notebooks/NN_x.ipynb`` from the repository root (Lab's root is the
repository). A chapter links to the book's reference pages (``../book/srs.md``, sources, notation)
and, through scripts/number_notebooks.py, to other chapters. Lab resolves a relative link as
JupyterLab's URL resolver does, ``PathExt.resolve(dirname(notebook), url)`` with ``/`` as the
root, so ``../book/srs.md`` from a notebook at Lab's root is ``book/srs.md``; and it opens the
file through jupyter_server's contents manager, which refuses a path outside its root. The
symlink ``notebooks/book -> ../book`` makes the reference pages a part of Lab's root in the
README's way. These tests resolve every link of every chapter both ways and ask jupyter_server's
own contents manager for the file, as Lab would.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

import nbformat
import pytest
from jupyter_server.services.contents.filemanager import FileContentsManager

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))

# Markdown links [text](target) and HTML href/src attributes of a Markdown cell.
_LINK = re.compile(r"\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)|\b(?:href|src)=\"([^\"]+)\"")


def local_links(path: Path) -> list[str]:
    """The relative link targets (no scheme, no pure #anchor) of a notebook's Markdown cells,
    without their #anchor."""
    nb = nbformat.read(path, as_version=4)
    found = []
    for cell in nb.cells:
        if cell.cell_type != "markdown":
            continue
        for m in _LINK.finditer(cell.source):
            url = (m.group(1) or m.group(2)).split("#", 1)[0]
            if not url or re.match(r"^[a-z][a-z0-9+.-]*:", url, re.I) or url.startswith("/"):
                continue
            found.append(url)
    return found


def lab_path(notebook: str, url: str) -> str:
    """JupyterLab's resolution of ``url`` in the notebook at ``notebook`` (a path under Lab's
    root): path-browserify's ``posix.resolve`` from ``/``, leading slash removed.

    >>> lab_path("01_introduction.ipynb", "../book/srs.md")
    'book/srs.md'
    >>> lab_path("notebooks/01_introduction.ipynb", "../book/srs.md")
    'book/srs.md'
    >>> lab_path("notebooks/01_introduction.ipynb", "02_forward_kinematics.ipynb")
    'notebooks/02_forward_kinematics.ipynb'
    """
    return posixpath.normpath(posixpath.join("/", posixpath.dirname(notebook), url)).lstrip("/")


def test_chapters_link_to_the_reference_pages():
    # What this file guards: the reference pages are linked from chapters (else it tests nothing).
    targets = {url for nb in NOTEBOOKS for url in local_links(nb)}
    assert {"../book/srs.md", "../book/sources.md", "../book/notation.md"} <= targets


def test_the_reference_pages_are_inside_labs_root():
    link = ROOT / "notebooks" / "book"
    assert link.is_symlink() and link.resolve() == (ROOT / "book").resolve()


@pytest.mark.parametrize("root", ["notebooks", "."], ids=["jupyter lab notebooks/", "jupyter lab notebooks/NN.ipynb"])
def test_every_link_of_a_chapter_opens_in_lab(root):
    lab_root = (ROOT / root).resolve()
    contents = FileContentsManager(root_dir=str(lab_root))
    broken = []
    for nb in NOTEBOOKS:
        where = nb.relative_to(lab_root).as_posix()
        for url in dict.fromkeys(local_links(nb)):
            path = lab_path(where, url)
            try:
                contents.get(path, content=False)
            except Exception as err:  # jupyter_server's HTTPError: what Lab shows as a 404
                broken.append(f"{nb.name}: {url} -> {path} ({type(err).__name__})")
    assert broken == []
