"""Write the Jupyter Book configuration of the student edition: the book without solutions.

    python scripts/student_book_config.py _build/student_config.yml

The configuration is the book's ``_config.yml`` with sphinx-exercise's ``hide_solutions`` on
(every ``solution`` directive is dropped; the exercises stay, numbered the same), "student
edition" in the title, and the local extension paths made absolute so that the file can live
outside the repository root. ``make student-book`` builds with it into ``_build/student``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def student_config(config: dict) -> dict:
    """The student edition of a book configuration (a new dict; ``config`` is not changed).

    >>> c = student_config({"title": "T", "sphinx": {"local_extensions": {"x": "book/_ext"}}})
    >>> c["title"], c["sphinx"]["config"]["hide_solutions"], Path(c["sphinx"]["local_extensions"]["x"]).is_absolute()
    ('T (student edition)', True, True)
    """
    out = yaml.safe_load(yaml.safe_dump(config))
    out["title"] = f"{out.get('title', 'rapp')} (student edition)"
    sphinx = out.setdefault("sphinx", {})
    sphinx.setdefault("config", {})["hide_solutions"] = True
    sphinx["local_extensions"] = {name: str((ROOT / path).resolve())
                                  for name, path in (sphinx.get("local_extensions") or {}).items()}
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python scripts/student_book_config.py OUT.yml", file=sys.stderr)
        return 2
    target = Path(argv[0])
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".{target.name}.tmp")
    tmp.write_text(yaml.safe_dump(student_config(config), sort_keys=False), encoding="utf-8")
    os.replace(tmp, target)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
