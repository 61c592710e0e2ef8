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
from the toc on every run. A chapter split over pages (``sections`` in the toc) numbers on across
them in the book; its later pages' front matter says where each kind starts::

    numbering:
      enumerator: "12.%s"
      figure:
        start: 6
 One more thing Lab cannot follow is rewritten in the chapters' text:
a ``{doc}`` role, which Lab turns into a link to a file that does not exist, becomes a Markdown
link to the notebook or page with the same title as its text (:func:`doc_links`), and a role
whose text runs over a line break is put on one line (:func:`one_line_roles`). A link to a
reference page reads ``../book/srs.md``: JupyterLab resolves it from its root, so with Lab started
as ``jupyter lab notebooks/`` it asks for ``book/srs.md``, which the symlink ``notebooks/book ->
../book`` provides (tests/test_lab_links.py opens every link both ways). Nothing else in a
notebook changes. Run it after any change to ``_toc.yml`` and after merging notebooks
(``python scripts/number_notebooks.py``); ``--check`` changes nothing and exits 1 when a notebook
is out of date.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import nbformat
import yaml

ROOT = Path(__file__).resolve().parents[1]
MARK = "frontmatter"


def read(path: Path):
    """A notebook, unvalidated: nbformat.read validates it against the schema, which takes longer
    than everything else here, and every notebook is read several times."""
    return nbformat.v4.reads(path.read_text(encoding="utf-8"))


def toc_pages(toc_path: Path = ROOT / "_toc.yml") -> list[tuple[str, int | None]]:
    """(file, chapter number or None) for every page of the toc, in reading order.

    A chapter's ``sections`` (at any depth) are pages of that chapter and carry its number; the
    numbered parts share one sequence (``use_multitoc_numbering``): the first chapter of a part
    continues from the last chapter of the part before. The root page comes first, unnumbered.

    >>> pages = dict(toc_pages())
    >>> pages["notebooks/05_astar"], pages["book/intro"]
    (5, None)
    """
    toc = yaml.safe_load(toc_path.read_text(encoding="utf-8"))
    pages: list[tuple[str, int | None]] = [(toc["root"], None)]

    def walk(entries, number):
        for entry in entries or []:
            if "file" in entry:
                pages.append((entry["file"], number))
            walk(entry.get("sections"), number)

    chapter = 0
    for part in toc.get("parts", []):
        for entry in part.get("chapters", []):
            if part.get("numbered"):
                chapter += 1
            walk([entry], chapter if part.get("numbered") else None)
    return pages


def chapter_numbers(toc_path: Path = ROOT / "_toc.yml") -> dict[str, int]:
    """Chapter number of every file in the numbered parts of the toc, sub-pages included.

    >>> numbers = chapter_numbers()
    >>> numbers["notebooks/05_astar"]
    5
    >>> numbers["notebooks/12_case_rrt_planning"]
    12
    """
    return {f: n for f, n in toc_pages(toc_path) if n is not None}


@dataclass(frozen=True)
class Target:
    """Something the book numbers or links to: where it is, what kind, its number and its text."""

    label: str
    kind: str        # "figure", "equation", "exercise", "proof:algorithm", ..., "section"
    docname: str     # the toc file it lives in, e.g. "notebooks/04_configuration_space"
    number: str      # "4.1"; "" for a section or an unnumbered page
    text: str        # caption, title, TeX or heading


_DIRECTIVE = re.compile(r"^(?P<fence>`{3,}|:{3,})\{(?P<name>[\w:-]+)\}[ \t]*(?P<arg>[^\n]*)\n"
                        r"(?P<opts>(?:[ \t]*:[\w-]+:[^\n]*\n)*)", re.M)
_LABEL = re.compile(r"^\((?P<label>[\w.:-]+)\)=[ \t]*\n+(?P<line>[^\n]*)", re.M)
_DOLLAR = re.compile(r"\$\$(?P<tex>.+?)\$\$[ \t]*\((?P<label>[\w.:-]+)\)", re.S)
_KIND = {"exercise": "exercise", "figure": "figure", "glue:figure": "figure", "math": "equation"}


def _option(opts: str, name: str) -> str:
    m = re.search(rf"^[ \t]*:{name}:[ \t]*(.*)$", opts, re.M)
    return m.group(1).strip() if m else ""


def _markdown_targets(text: str):
    """(kind, label, text, numbered) for each target of a Markdown text, in reading order."""
    found = []
    for m in _DIRECTIVE.finditer(text):
        name, opts = m["name"], m["opts"]
        kind = f"proof:{name[4:]}" if name.startswith("prf:") and name != "prf:ref" else _KIND.get(name)
        if kind is None:
            continue
        label = _option(opts, "label") or _option(opts, "name")
        numbered = "nonumber" not in opts
        found.append((m.start(), kind, label, m["arg"].strip(), numbered))
    for m in _LABEL.finditer(text):
        kind = "section" if m["line"].startswith("#") else "paragraph"
        found.append((m.start(), kind, m["label"], m["line"].lstrip("#").strip(), False))
    for m in _DOLLAR.finditer(text):
        found.append((m.start(), "equation", m["label"], m["tex"].strip(), True))
    return [f[1:] for f in sorted(found)]


def _page_blocks(root: Path, docname: str):
    path = root / f"{docname}.ipynb"
    if path.exists():
        return [c for c in read(path).cells if not is_front_matter_cell(c)]
    if (root / f"{docname}.md").exists():
        return [nbformat.v4.new_markdown_cell((root / f"{docname}.md").read_text(encoding="utf-8"))]
    return None


def book_numbering(root: Path = ROOT) -> tuple[dict[str, Target], dict[str, dict[str, int]]]:
    """The book's targets (as :func:`book_targets`) and, per page, how many of each numbered kind
    its chapter's earlier pages hold: the counts a sub-page's numbers continue from.

    Sphinx (numfig, ``numfig_secnum_depth`` 1) keys its counters by chapter, not by page, and
    walks the toc in reading order, so a chapter's second page continues its first page's
    figures, equations, exercises and algorithms; jupyterlab-myst starts every notebook at 1
    unless the front matter says where (:func:`front_matter`).
    """
    targets: dict[str, Target] = {}
    starts: dict[str, dict[str, int]] = {}
    chapter_counts: dict[int, dict[str, int]] = {}
    for docname, chapter in toc_pages(root / "_toc.yml"):
        blocks = _page_blocks(root, docname)
        if blocks is None:
            continue
        counts = chapter_counts.setdefault(chapter, {}) if chapter is not None else {}
        starts[docname] = dict(counts)

        def add(kind, label, text, numbered):
            number = ""
            if numbered and kind not in ("section", "paragraph") and chapter is not None:
                counts[kind] = counts.get(kind, 0) + 1
                number = f"{chapter}.{counts[kind]}"
            if label:
                targets.setdefault(label, Target(label, kind, docname, number, text))

        for cell in blocks:
            if cell.cell_type == "markdown":
                for found in _markdown_targets(cell.source):
                    add(*found)
            elif cell.cell_type == "code":
                meta = cell.metadata.get("mystnb", cell.metadata.get("myst", {})).get("figure")
                if meta and meta.get("caption"):
                    add("figure", meta.get("name", ""), meta["caption"], True)
    return targets, starts


def book_targets(root: Path = ROOT) -> dict[str, Target]:
    """Every label of the book's toc files, numbered as the HTML book numbers it.

    Chapter N's figures, equations (labelled ones: ``math_number_all`` is off), exercises and each
    kind of pseudocode block are counted separately, in reading order across the chapter's pages
    (its ``sections`` in the toc): N.1, N.2, …

    >>> t = book_targets()
    >>> t["alg-ch05-astar"].kind, t["alg-ch05-astar"].number
    ('proof:algorithm', '5.2')
    """
    return book_numbering(root)[0]


_REF = re.compile(r"\{(?:ref|numref|prf:ref|eq)\}`(?:[^`<]*<)?(?P<label>[^`<>\n]+)>?`")
_TERM = re.compile(r"\{term\}`(?:[^`<]*<)?(?P<term>[^`<>]+)>?`")


def glossary(root: Path = ROOT) -> dict[str, str]:
    """The book's glossary: term -> definition (Markdown), from book/glossary.md."""
    text = (root / "book" / "glossary.md").read_text(encoding="utf-8")
    block = re.search(r"^(`{3,}|:{3,})\{glossary\}\n(.*?)^\1", text, re.M | re.S)
    terms: dict[str, str] = {}
    term = None
    for line in (block.group(2) if block else "").splitlines():
        if line.strip() and not line[0].isspace():
            term = line.strip()
            terms[term] = ""
        elif term and line.strip():
            terms[term] = (terms[term] + " " + line.strip()).strip()
    return terms


def _link(target: Target, here: str) -> str:
    suffix = ".ipynb" if (ROOT / f"{target.docname}.ipynb").exists() else ".md"
    rel = os.path.relpath(ROOT / f"{target.docname}{suffix}", (ROOT / here).parent)
    return f"[{Path(rel).name}]({Path(rel).as_posix()})"


def _entry(t: Target, here: str) -> str:
    where = "" if t.docname == here else f"In {_link(t, here)}."
    if t.kind == "section":
        # not a heading: Lab would lift the cell's first heading out of the fold as its title
        return f":::{{admonition}} {t.text}\n:label: {t.label}\n{where}\n:::"
    if t.kind == "paragraph":
        return f"({t.label})=\n{t.text} … {where}"
    number = f":enumerator: {t.number}\n" if t.number else ""
    if t.kind == "figure":
        return f":::{{figure}}\n:label: {t.label}\n{number}{' '.join(filter(None, [t.text, where]))}\n:::"
    if t.kind == "equation":
        return f":::{{math}}\n:label: {t.label}\n{number}{t.text}\n:::\n{where}"
    name = "exercise" if t.kind == "exercise" else "prf:" + t.kind.split(":", 1)[1]
    return f":::{{{name}}} {t.text}\n:label: {t.label}\n{number}\n{where}\n:::"


def lab_index(nb, docname: str, targets: dict[str, Target], terms: dict[str, str]) -> str:
    """The Lab-only part of a chapter's first cell: what jupyterlab-myst cannot find by itself.

    jupyterlab-myst renders Markdown cells only, and one notebook at a time: a figure made by a
    code cell has no caption there, and a label of another chapter or page is unresolved. This
    folded block gives Lab a target for each, numbered as the book numbers it, with a link to the
    notebook (or page) it lives in; and the glossary entries of the terms the chapter uses.
    """
    text = "\n\n".join(c.source for c in nb.cells
                        if c.cell_type == "markdown" and not is_front_matter_cell(c))
    local = [t for t in targets.values() if t.docname == docname and t.kind == "figure"]
    cited = dict.fromkeys(m["label"].strip() for m in _REF.finditer(text))
    outside = [targets[k] for k in cited if k in targets and targets[k].docname != docname]
    used = [t for t in dict.fromkeys(m["term"].strip() for m in _TERM.finditer(text)) if t in terms]
    parts = [_entry(t, docname) for t in local + outside]
    if used:
        parts.append(":::{glossary}\n" + "\n\n".join(f"{t}\n: {terms[t]}" for t in used) + "\n:::")
    if not parts:
        return ""
    return "\n\n".join(["::::{dropdown} The book's figures and references for this chapter",
                          *parts, "::::"])


_DOC = re.compile(r"\{doc\}`(?:(?P<text>[^`<]*?)\s*<(?P<target>[^`<>]+)>|(?P<bare>[^`<>]+))`")


def title_of(path: Path) -> str:
    """The first ``# `` heading of a notebook (its front-matter cell skipped) or Markdown page."""
    if path.suffix == ".ipynb":
        nb = read(path)
        text = "\n".join(c.source for c in nb.cells
                         if c.cell_type == "markdown" and not is_front_matter_cell(c))
    else:
        text = path.read_text(encoding="utf-8")
    m = re.search(r"^# +(.+?)\s*$", text, re.M)
    return m.group(1) if m else path.stem


def doc_links(source: str, here: Path) -> str:
    """``source`` with each ``{doc}`` role written as a Markdown link to the file itself.

    Sphinx shows ``{doc}`04_configuration_space``` as the chapter's title; JupyterLab
    (jupyterlab-myst) makes it a link to ``04_configuration_space``, a file that does not exist.
    ``[Configuration space](04_configuration_space.ipynb)`` reads the same in the book (MyST
    turns a link to a source file into a link to its page) and opens the notebook in Lab.
    A target with no notebook or page behind it is left alone, for Sphinx to report.
    """
    def link(m: re.Match) -> str:
        target = (m["target"] or m["bare"]).strip()
        base = ROOT if target.startswith("/") else here.parent
        for suffix in (".ipynb", ".md"):
            path = (base / (target.lstrip("/") + suffix)).resolve()
            if path.exists():
                rel = Path(os.path.relpath(path, here.parent)).as_posix()
                return f"[{(m['text'] or '').strip() or title_of(path)}]({rel})"
        return m.group(0)

    return _DOC.sub(link, source)


_ROLE_ACROSS_LINES = re.compile(r"\{[\w:-]+\}`[^`]*\n[^`]*`")


def one_line_roles(source: str) -> str:
    """``source`` with each role whose text runs over a line break put on one line.

    Sphinx reads ``{ref}`[LaValle 1998]⏎  <ref-lavalle-rrt>``` as text and target; jupyterlab-myst
    takes all of it for the target and finds none. Joining the lines changes nothing in the book.

    >>> one_line_roles("see {ref}`[A]\\n  <ref-a>` and {eq}`x`")
    'see {ref}`[A] <ref-a>` and {eq}`x`'
    """
    return _ROLE_ACROSS_LINES.sub(lambda m: re.sub(r"\s*\n\s*", " ", m.group(0)), source)


def front_matter(number: int, starts: dict[str, int] | None = None) -> str:
    """The source of chapter ``number``'s front-matter cell.

    ``enumerator`` is a template for every numbered kind (exercise, algorithm, equation, figure);
    equations keep their parentheses, as in the book: (5.1).

    >>> print(front_matter(5))
    ---
    numbering:
      enumerator: "5.%s"
    ---

    On a chapter's later page, ``starts`` (kind -> how many its earlier pages hold) makes each
    kind continue where the earlier pages stopped. The keys are jupyterlab-myst's kinds
    (``proof:algorithm`` for ``prf:algorithm``), and its ``start`` is the first number:

    >>> print(front_matter(12, {"figure": 5, "exercise": 0}))
    ---
    numbering:
      enumerator: "12.%s"
      figure:
        start: 6
    ---
    """
    lines = ["---", "numbering:", f'  enumerator: "{number}.%s"']
    for kind, count in sorted((starts or {}).items()):
        if count:
            lines += [f'  "{kind}":' if ":" in kind else f"  {kind}:", f"    start: {count + 1}"]
    return "\n".join(lines + ["---"])


def is_front_matter_cell(cell) -> bool:
    return cell.cell_type == "markdown" and bool(cell.metadata.get("rapp", {}).get(MARK))


def numbered(nb, number: int, index: str = "", path: Path | None = None,
             starts: dict[str, int] | None = None):
    """A copy of notebook ``nb`` whose first cell is chapter ``number``'s front matter.

    ``starts`` (from :func:`book_numbering`) are the counts of the chapter's earlier pages.

    ``index`` (from :func:`lab_index`) follows the front matter in the same cell. With the
    notebook's ``path``, its ``{doc}`` roles become links to the files (:func:`doc_links`).
    """
    nb = nbformat.from_dict(nb)
    cells = [c for c in nb.cells if not is_front_matter_cell(c)]
    for c in cells:
        if c.cell_type == "markdown":
            text = one_line_roles(c.source)
            c.source = doc_links(text, path) if path is not None else text
    source = front_matter(number, starts) + (f"\n{index}" if index else "")
    cell = nbformat.v4.new_markdown_cell(
        source, metadata={"tags": ["remove-cell"], "rapp": {MARK: True}})
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
    (targets, starts), terms = book_numbering(), glossary()
    for docname, number in chapter_numbers().items():
        path = ROOT / f"{docname}.ipynb"
        if not path.exists():
            continue  # a Markdown page: Sphinx numbers it, Lab never opens it
        nb = read(path)
        new = numbered(nb, number, lab_index(nb, docname, targets, terms), path,
                       starts.get(docname))
        if new == nb:
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
