"""The student edition drops every solution and keeps the exercises, numbered the same.

A small book made of one chapter's real exercise and solution blocks is built twice with the
same Sphinx extensions as the book, with and without the student edition's setting, so the
test can fail; ``make student-book`` builds the whole book with it and runs the same check.
"""

from pathlib import Path

import pytest
import yaml

from tests.helpers import load_script

ROOT = Path(__file__).resolve().parents[2]
student_config = load_script("scripts/student_book_config.py").student_config
_check = load_script("scripts/check_student_book.py")
book_blocks, problems, telltales = _check.book_blocks, _check.problems, _check.telltales


def test_the_student_config_is_the_books_with_solutions_hidden():
    book = yaml.safe_load((ROOT / "_config.yml").read_text())
    student = student_config(book)
    assert student["sphinx"]["config"]["hide_solutions"] is True
    assert student["sphinx"]["extra_extensions"] == book["sphinx"]["extra_extensions"]
    assert all(Path(p).is_dir() for p in student["sphinx"]["local_extensions"].values())
    assert "hide_solutions" not in book["sphinx"].get("config", {})  # the book itself keeps them


def _build(tmp: Path, hide: bool) -> str:
    from sphinx.application import Sphinx

    src = tmp / "src"
    src.mkdir()
    (src / "conf.py").write_text(
        "extensions = ['myst_parser', 'sphinx_exercise']\n"
        "myst_enable_extensions = ['colon_fence', 'dollarmath', 'amsmath']\n"
        f"hide_solutions = {hide}\nexclude_patterns = ['_build']\n")
    blocks = (ROOT / "notebooks" / "01_introduction.ipynb").read_text()
    import json

    cells = ["".join(c["source"]) for c in json.loads(blocks)["cells"] if c["cell_type"] == "markdown"]
    exercises = "\n\n".join(c for c in cells if ":::{exercise}" in c)
    (src / "index.md").write_text("# Chapter\n\n" + exercises.replace("{eq}", "{math:numref}") + "\n")
    out = tmp / "html"
    app = Sphinx(str(src), str(src), str(out), str(tmp / "doctrees"), "html", status=None, warning=None,
                 freshenv=True)
    app.build()
    return (out / "index.html").read_text()


@pytest.mark.slow
@pytest.mark.parametrize("hide", [True, False], ids=["student", "teacher"])
def test_a_chapters_exercises_built_with_and_without_solutions(tmp_path, hide):
    html = _build(tmp_path, hide)
    exercises, solutions = book_blocks()
    ours = {k: v for k, v in solutions.items() if k.startswith("ex-1-")}
    shown = [run for body in ours.values() for run in telltales(body) if run in " ".join(html.split())]
    for label, title in exercises.items():
        if label.startswith("ex-1-"):
            assert title in html
    assert "Exercise 5" in html  # numbered the same: the fifth exercise of the chapter is still there
    found = problems(tmp_path / "html")  # what make student-book runs on the whole book
    if hide:
        assert shown == [] and 'class="solution' not in html
        assert not [f for f in found if "shown" in f or "solution block" in f]
    else:
        assert shown and 'class="solution' in html
        assert [f for f in found if "is shown" in f] and [f for f in found if "solution block" in f]


def test_the_syllabus_covers_every_teaching_chapter_and_names_real_exercises():
    import re

    from rapp.exercises import catalog

    text = (ROOT / "book" / "syllabus.md").read_text()
    assert "book/syllabus" in (ROOT / "_toc.yml").read_text()
    rows = [r for r in text.splitlines() if re.match(r"\| \d+ \|", r)]
    assert len(rows) == 10
    ids = {ex.id for ex in catalog()}
    named = set(re.findall(r"\b(\d{1,2}\.\d)\b", text))
    assert named <= ids and named == ids  # every exercise has a place, lab or homework
    kinds = {ex.id: ex.kind for ex in catalog()}
    for row in rows:
        lab, homework = row.split("|")[3], row.split("|")[4]
        assert all(kinds[i] == "implement" for i in re.findall(r"\d+\.\d", lab)), row
        assert all(kinds[i] != "implement" for i in re.findall(r"\d+\.\d", homework)), row
