"""Sphinx extension: the ``exercise-catalog`` directive, a table of every exercise of the book.

The table is made from :func:`rapp.exercises.catalog` when the book builds, so the instructors'
page can never disagree with the checks: one row per exercise with its number (a link to it),
title, kind, difficulty and what ``rapp.exercises.check`` wants as the answer.
"""

from __future__ import annotations

from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx.addnodes import pending_xref

COLUMNS = (("Exercise", 8), ("Title", 30), ("Kind", 10), ("Difficulty", 8), ("check() wants", 44))


def _row(cells) -> nodes.row:
    row = nodes.row()
    for cell in cells:
        entry = nodes.entry()
        entry += cell if isinstance(cell, nodes.Node) else nodes.paragraph(text=str(cell))
        row += entry
    return row


class ExerciseCatalog(Directive):
    """One table per chapter would repeat headers; one table, grouped by chapter, reads better."""

    has_content = False

    def run(self):
        from rapp.exercises import catalog

        table = nodes.table(classes=["exercise-catalog"])
        group = nodes.tgroup(cols=len(COLUMNS))
        table += group
        for _, width in COLUMNS:
            group += nodes.colspec(colwidth=width)
        head = nodes.thead()
        head += _row(name for name, _ in COLUMNS)
        group += head
        body = nodes.tbody()
        for ex in catalog():
            label = "ex-" + ex.id.replace(".", "-")
            link = pending_xref("", refdomain="std", reftype="ref", reftarget=label,
                                refexplicit=True, refwarn=True)
            link += nodes.inline(text=ex.id)
            para = nodes.paragraph()
            para += link
            body += _row([para, ex.title, ex.kind, "★" * ex.difficulty, ex.expects])
        group += body
        return [table]


def setup(app):
    app.add_directive("exercise-catalog", ExerciseCatalog)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
