"""Write book/api.md, the book's API reference: every name of ``rapp.__all__`` (grouped as
``rapp/__init__.py`` groups them) and every public module, documented by sphinx autodoc from
the docstrings. The page holds only directives; the text is the docstrings'.

Run it after adding a public name or a module: ``python scripts/api_page.py``
(``tests/test_api_page.py`` fails until the page is what this script writes).
"""

from __future__ import annotations

import inspect
import pkgutil
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "book" / "api.md"

HEAD = """# API reference

(api-reference)=

Every name of `rapp.__all__` (the package's contract, imported as `rapp.NAME`) and every
public module, generated from their docstrings by Sphinx's autodoc (numpy-style sections read
by napoleon). The {doc}`Scenario files <scenario_format>` page documents the file formats,
`python -m rapp --help` the command line. Install and versions: the README's "Use the library";
changes: `CHANGELOG.md`.

Angles are radians (relative joint angles, counter-clockwise, zero along the previous link),
lengths the scenario's unit (metres); configurations are `(..., n)` arrays and every function
works on a whole batch. `ArrayLike` in a signature is anything `numpy.asarray` takes.
"""


def groups() -> list[tuple[str, list[str]]]:
    """``rapp.__all__`` in the groups its comments give in ``rapp/__init__.py``."""
    import rapp

    text = (ROOT / "rapp" / "__init__.py").read_text(encoding="utf-8")
    block = re.search(r"__all__ = \[(.*?)\n\]", text, re.S).group(1)
    out: list[tuple[str, list[str]]] = []
    for line in block.splitlines():
        line = line.strip()
        if not line:
            continue
        if line.startswith("#"):
            out.append((line.lstrip("# ").rstrip(), []))
        else:
            out[-1][1].extend(re.findall(r'"(\w+)"', line))
    listed = [n for _, names in out for n in names]
    assert listed == list(rapp.__all__), "rapp/__init__.py's comments do not cover __all__"
    return out


def modules() -> list[str]:
    """The public modules and subpackages of rapp (no leading underscore), sorted."""
    import rapp

    return sorted(f"rapp.{m.name}" for m in pkgutil.iter_modules(rapp.__path__)
                  if not m.name.startswith("_"))


def directive(name: str) -> str:
    """The autodoc directive (reStructuredText) of ``rapp.NAME``."""
    import rapp

    obj = getattr(rapp, name)
    if inspect.isclass(obj):
        if issubclass(obj, BaseException):
            return f".. autoexception:: rapp.{name}\n"
        return f".. autoclass:: rapp.{name}\n   :members:\n"
    return f".. autofunction:: rapp.{name}\n"


def rst(lines: list[str]) -> str:
    """A MyST block whose content Sphinx reads as reStructuredText (autodoc writes reST)."""
    return "```{eval-rst}\n" + "\n".join(lines) + "```\n"


def page() -> str:
    import rapp

    parts = [HEAD]
    parts.append("## `rapp`: the public names\n")
    for title, names in groups():
        parts.append(f"### {title[0].upper() + title[1:]}\n")
        summary = ".. autosummary::\n\n" + "".join(f"   rapp.{n}\n" for n in names)
        parts.append(rst([summary] + [directive(n) for n in names]))
    parts.append("## The modules\n")
    parts.append("Each module's own notes (what it models, how, and what it shares by name); its "
                 "other public names are reached as `rapp.module.name`.\n")
    for m in modules():
        parts.append(f"### `{m}`\n")
        # A module named as a contract function (rapp.ik, rapp.prm, ...) is described without an
        # index entry: the entry rapp.ik is the function's.
        clash = m.split(".", 1)[1] in rapp.__all__
        parts.append(rst([f".. automodule:: {m}\n   :no-members:\n"
                          + ("   :no-index:\n" if clash else "")]))
    return "\n".join(parts)


def main() -> int:
    sys.path.insert(0, str(ROOT))
    PAGE.write_text(page(), encoding="utf-8")
    print(f"wrote {PAGE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
