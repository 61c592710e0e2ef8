"""Sphinx extension: every chapter page says how to open the same chapter in JupyterLab.

A chapter of the book is a notebook of the repository. Under the page title this adds a short
box with the notebook's path and the one command that opens it in JupyterLab, where the chapter
runs, its widgets are live, and (scripts/number_notebooks.py) its exercises, algorithms, equations
and figures carry the numbers this page shows. Made here, from the docname, so that no notebook
carries a copy of the sentence and a renamed chapter cannot point at an old path.
"""

from __future__ import annotations

from pathlib import Path

from docutils import nodes

TITLE = "Open this chapter in JupyterLab"


def _literal(text: str) -> nodes.literal:
    return nodes.literal(text=text)


def note_for(notebook: str) -> nodes.admonition:
    """The box for ``notebook``, a path relative to the repository root."""
    # Folded (sphinx-togglebutton's "dropdown"): one line above the lesson, opened on a click.
    box = nodes.admonition(classes=["tip", "dropdown", "rapp-open-in-lab"])
    box += nodes.title(text=TITLE)
    para = nodes.paragraph()
    para += nodes.Text("This page is the notebook ")
    para += _literal(notebook)
    para += nodes.Text(" of the repository. From the repository root, after ")
    para += _literal("make test")
    para += nodes.Text(" or ")
    para += _literal("make book")
    para += nodes.Text(" has made the environment, run ")
    para += _literal(f".venv/bin/jupyter lab {notebook}")
    para += nodes.Text(" to run it and move its widgets. Exercises, algorithms, equations and "
                       "figures carry the same numbers there as here; ")
    para += _literal('rapp.exercises.check("N.k", answer)')
    para += nodes.Text(" checks Exercise N.k.")
    box += para
    return box


def add_note(app, doctree) -> None:
    docname = app.env.docname
    source = Path(app.env.doc2path(docname))
    if source.suffix != ".ipynb":
        return
    notebook = source.relative_to(Path(app.srcdir)).as_posix()
    section = next(iter(doctree.findall(nodes.section)), None)
    if section is None:
        return
    title = next(iter(section.findall(nodes.title)), None)
    section.insert(section.index(title) + 1 if title is not None else 0, note_for(notebook))


def setup(app):
    app.connect("doctree-read", add_note)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
