"""How much of each chapter's code is hidden, and how often its visible text names the sources.

    python scripts/notebook_stats.py            # a table, one notebook a line
    python scripts/notebook_stats.py --json     # the same numbers as JSON (tests/test_notebook_text.py)

*Hidden non-assert lines* count the lines of cells tagged ``remove-input``, ``hide-input`` or
``remove-cell`` that are not blank, not comments and not part of an ``assert`` statement: the
plumbing that only nbval runs (the book's budget: 1,200 book-wide, ARCHITECTURE.md).

*Audit mentions* count the words seed(s), SRS and MIS in what a reader sees without unfolding
anything: markdown outside ``{dropdown}`` blocks and ``:class: dropdown`` admonitions, and the
source of visible code cells (a random generator's ``seed=`` is not a source document). The budget
is 15 for each of chapters 1 to 8.

*Main-path words* count the words of the markdown a reader sees without unfolding anything (as
for the audit mentions, hidden cells left out), from the top of the page to its optional
``## Going further`` section, if it has one: what a first reading reads. Code and its output are
not counted.
"""

from __future__ import annotations

import io
import json
import re
import sys
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HIDDEN = {"remove-input", "hide-input", "remove-cell"}
MENTION = re.compile(r"\b(?:[Ss]eed(?:s|'s)?|SRS|MIS)\b")
OPTIONAL = re.compile(r"^#{1,3}\s+Going further\b", re.M)
FENCE = re.compile(r"^\s*(:{3,}|`{3,})\{([\w-]+)\}")


def _source(cell) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def assert_lines(code: str) -> set[int]:
    """Line numbers (1-based) of ``code`` that belong to an ``assert`` statement."""
    lines: set[int] = set()
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(code).readline))
    except (tokenize.TokenError, IndentationError, SyntaxError):
        return lines
    start = None
    for tok in tokens:
        if tok.type == tokenize.NAME and tok.string == "assert" and start is None:
            start = tok.start[0]
        elif tok.type in (tokenize.NEWLINE, tokenize.ENDMARKER) and start is not None:
            lines.update(range(start, tok.end[0] + 1))
            start = None
    return lines


def hidden_non_assert_lines(nb: dict) -> int:
    """Lines of hidden code cells that are neither blank, comments nor assert statements."""
    n = 0
    for cell in nb["cells"]:
        tags = set(cell.get("metadata", {}).get("tags", []))
        if cell["cell_type"] != "code" or not tags & HIDDEN:
            continue
        code = _source(cell)
        asserts = assert_lines(code)
        for i, line in enumerate(code.splitlines(), 1):
            text = line.strip()
            if text and not text.startswith(("#", "%")) and i not in asserts:
                n += 1
    return n


def unfolded(markdown: str) -> str:
    """``markdown`` without its folded blocks (a dropdown directive or a dropdown admonition)."""
    out, lines, i = [], markdown.split("\n"), 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m:
            j, folded = i + 1, m.group(2) == "dropdown"
            while j < len(lines) and lines[j].strip().startswith(":") and not FENCE.match(lines[j]):
                folded |= bool(re.match(r"\s*:class:.*\bdropdown\b", lines[j]))
                j += 1
            if folded:
                k = i + 1
                while k < len(lines) and lines[k].strip() != m.group(1):
                    k += 1
                i = k + 1
                continue
        out.append(lines[i])
        i += 1
    return "\n".join(out)


def audit_mentions(nb: dict) -> int:
    """Words seed(s)/SRS/MIS a reader sees without unfolding anything."""
    n = 0
    for cell in nb["cells"]:
        tags = set(cell.get("metadata", {}).get("tags", []))
        text = _source(cell)
        if cell["cell_type"] == "markdown":
            n += len(MENTION.findall(unfolded(text)))
        elif cell["cell_type"] == "code" and not tags & HIDDEN:
            text = re.sub(r"\bseed\s*=|default_rng\([^)]*\)", "", text)
            n += len(MENTION.findall(text))
    return n


def main_path_words(nb: dict) -> int:
    r"""Words of the markdown a reader sees unfolded, up to the optional "Going further" section.

    >>> md = lambda text: {"cell_type": "markdown", "source": text}
    >>> main_path_words({"cells": [md("# A title\n\nfour words of text"),
    ...     md(":::{dropdown} Folded\nnot counted here\n:::\nTwo more."),
    ...     md("## Going further\n\noptional words"), md("after it")]})
    9
    """
    n = 0
    for cell in nb["cells"]:
        tags = set(cell.get("metadata", {}).get("tags", []))
        if cell["cell_type"] != "markdown" or "remove-cell" in tags:
            continue
        text = unfolded(_source(cell))
        stop = OPTIONAL.search(text)
        n += len(text[:stop.start()].split()) if stop else len(text.split())
        if stop:
            break
    return n


def stats(root: Path = ROOT) -> dict:
    """``{notebook name: {"hidden_non_assert", "audit_mentions", "main_path_words": int}}``."""
    out = {}
    for path in sorted((root / "notebooks").glob("*.ipynb")):
        nb = json.loads(path.read_text(encoding="utf-8"))
        out[path.name] = {"hidden_non_assert": hidden_non_assert_lines(nb),
                          "audit_mentions": audit_mentions(nb),
                          "main_path_words": main_path_words(nb)}
    return out


def main(argv: list[str]) -> int:
    s = stats()
    if "--json" in argv:
        print(json.dumps(s))
        return 0
    for name, v in s.items():
        print(f"{name:42s} hidden non-assert {v['hidden_non_assert']:5d}   audit mentions "
              f"{v['audit_mentions']:4d}   main-path words {v['main_path_words']:6,d}")
    print(f"{'book':42s} hidden non-assert {sum(v['hidden_non_assert'] for v in s.values()):5d}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
