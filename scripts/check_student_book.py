"""Check a built student edition: no page holds a solution, every exercise is still there.

    python scripts/check_student_book.py _build/student/_build/html

Fails (exit 1, one line per problem) when a page has a solution block (sphinx-exercise's
``solution`` class) or the text of one of the book's solutions, or when an exercise of the
book is missing. The solutions' texts are read from the notebooks.
"""

from __future__ import annotations

import html
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_BLOCK = re.compile(r"^:::\{(exercise|solution)\}\s*(.*?)\n(.*?)^:::\s*$", re.S | re.M)


def book_blocks(notebooks: Path = ROOT / "notebooks") -> tuple[dict, dict]:
    """Exercise titles and solution texts by label, from the notebooks' markdown."""
    exercises, solutions = {}, {}
    for path in sorted(notebooks.glob("[0-9][0-9]_*.ipynb")):
        for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]:
            if cell["cell_type"] != "markdown":
                continue
            for kind, arg, body in _BLOCK.findall("".join(cell["source"])):
                label = re.search(r"^:label: (\S+)", body, re.M)
                if kind == "exercise" and label:
                    exercises[label.group(1)] = arg.strip()
                elif kind == "solution":
                    solutions[arg.strip()] = body
    return exercises, solutions


def telltales(solution: str) -> list[str]:
    """Runs of plain words from a solution (no markup) that a page showing it would contain."""
    text = re.sub(r"```.*?```|\$[^$]*\$|\{[^}]*\}`[^`]*`|`[^`]*`|^:\w+:[^\n]*$", "|", solution, flags=re.S | re.M)
    runs = re.findall(r"[A-Za-z][A-Za-z ,;']{40,}", text)
    return [" ".join(r.split()[:8]) for r in runs[:2] if len(r.split()) >= 6]


def _plain(text: str) -> str:
    """Text as a reader sees it: entities decoded, typographic quotes and dashes made plain, one space."""
    text = html.unescape(text).translate(str.maketrans({"\u2019": "'", "\u2018": "'", "\u201c": '"',
                                                        "\u201d": '"', "\u2013": "-", "\u2014": "-"}))
    return " ".join(text.split())


def problems(html_dir: Path) -> list[str]:
    pages = {p: p.read_text(encoding="utf-8", errors="replace") for p in Path(html_dir).rglob("*.html")}
    plain = {p: _plain(re.sub(r"<[^>]+>", " ", t)) for p, t in pages.items()}
    everything = "\n".join(plain.values())
    found = []
    for p, t in pages.items():
        if re.search(r'class="[^"]*\bsolution\b', t):
            found.append(f"{p}: has a solution block")
    exercises, solutions = book_blocks()
    for label, body in solutions.items():
        for run in telltales(body):
            if _plain(run) in everything:
                found.append(f"the solution {label} is shown: {run!r}")
    for label, title in exercises.items():
        if title and _plain(title) not in everything:
            found.append(f"the exercise {label} ({title}) is missing")
    return found


def main(argv: list[str]) -> int:
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("usage: python scripts/check_student_book.py HTML_DIR", file=sys.stderr)
        return 2
    found = problems(Path(argv[0]))
    for line in found:
        print(line)
    if not found:
        print(f"student edition: no solution in {argv[0]}, every exercise present")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
