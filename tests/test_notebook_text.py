"""What the notebooks' sources say: no private rapp name, the course before the audit, thin hidden code.

The numbers come from ``scripts/notebook_stats.py`` (run it to see them per notebook).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
#: rapp.x._y, rapp._x, or "from rapp... import _y" in a cell's source (outputs are not read: a
#: widget's saved state may hold its class's qualified name).
PRIVATE = re.compile(r"\brapp(?:\.[A-Za-z]\w*)*\._(?!_)\w+|\bfrom\s+rapp[\w.]*\s+import\s+(?:\(?\s*[\w\s,]*?\b)?_[A-Za-z]\w*")
#: Each of chapters 1 to 8 names seed(s)/SRS/MIS at most this often where a reader sees it unfolded.
AUDIT_BUDGET = 15
#: Hidden code that is not an assert, book-wide: 2,520 lines before this ceiling, 2,335 three
#: rounds later, 1,190 once the chapters' figures and helpers moved into tested package modules
#: (rapp.plot_*, rapp.cases.*_figures, rapp.recorded.quoted); the goal was at most 1,200. It may only shrink.
HIDDEN_CEILING = 1190
#: Chapter 3 teaches one idea: its main path (what a first reading reads, before the optional
#: "Going further") was 6,851 words, 4,429 before this bound (issue 33).
MAIN_PATH_WORDS = {"03_collision.ipynb": 3400}


@pytest.fixture(scope="module")
def stats():
    out = subprocess.run([sys.executable, str(ROOT / "scripts" / "notebook_stats.py"), "--json"],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_no_notebook_uses_a_private_rapp_name(path):
    nb = json.loads(path.read_text(encoding="utf-8"))
    found = [(i, m.group(0)) for i, cell in enumerate(nb["cells"])
             for m in PRIVATE.finditer("".join(cell.get("source", "")))]
    assert not found, f"private rapp names in {path.name} (cell, name): {found}"


@pytest.mark.parametrize("text, private", [
    ("from rapp.ik import _dls_step", True), ("rapp.cspace._circle_hits", True),
    ('mock.patch("rapp.cspace._paint")', True), ("from rapp.ik import dls_step", False),
    ("rapp.search.astar_search(occ)", False), ("from rapp import plotting, _x", True),
])
def test_the_private_name_pattern_finds_what_it_should(text, private):
    assert bool(PRIVATE.search(text)) == private


def test_chapters_1_to_8_teach_before_they_audit(stats):
    over = {name: v["audit_mentions"] for name, v in stats.items()
            if re.match(r"0[1-8]_", name) and v["audit_mentions"] > AUDIT_BUDGET}
    assert not over, f"more than {AUDIT_BUDGET} visible mentions of seed/SRS/MIS: {over}"


@pytest.mark.parametrize("name, most", sorted(MAIN_PATH_WORDS.items()))
def test_a_chapter_main_path_is_read_in_one_sitting(stats, name, most):
    assert stats[name]["main_path_words"] <= most, (
        f"{name}: {stats[name]['main_path_words']} words on the main path, at most {most}: "
        "fold a digression or move it to the optional '## Going further' section at the end")


def test_the_main_path_stops_at_going_further_and_skips_folds():
    from tests.helpers import load_script

    main_path_words = load_script("scripts/notebook_stats.py").main_path_words

    def md(text, tags=()):
        return {"cell_type": "markdown", "source": text, "metadata": {"tags": list(tags)}}

    nb = {"cells": [md("# Title\n\none two three"), md("hidden words", ["remove-cell"]),
                    {"cell_type": "code", "source": "x = 1 + 2", "metadata": {}},
                    md(":::{note}\n:class: dropdown\nfolded away\n:::\nfour"),
                    md("five\n\n## Going further\n\nnot read"), md("nor this")]}
    assert main_path_words(nb) == 7


def test_hidden_code_does_not_grow(stats):
    total = sum(v["hidden_non_assert"] for v in stats.values())
    assert total <= HIDDEN_CEILING, f"{total} hidden non-assert lines, ceiling {HIDDEN_CEILING}"
