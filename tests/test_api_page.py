"""The book's API reference page lists every public name and module, and is what
scripts/api_page.py writes from rapp.__all__ (run it after adding a name or a module)."""

import importlib.util
import pkgutil
import re
import sys
from pathlib import Path

import rapp

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "book" / "api.md").read_text(encoding="utf-8")


def api_page():
    spec = importlib.util.spec_from_file_location("api_page", ROOT / "scripts" / "api_page.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_page_is_what_the_script_writes():
    assert PAGE == api_page().page(), "run: python scripts/api_page.py"


def test_every_public_name_and_module_is_documented_on_the_page():
    documented = set(re.findall(r"^\.\. auto(?:function|class|exception):: rapp\.(\w+)$", PAGE, re.M))
    assert documented == set(rapp.__all__)
    modules = set(re.findall(r"^\.\. automodule:: (rapp\.\w+)$", PAGE, re.M))
    public = {f"rapp.{m.name}" for m in pkgutil.iter_modules(rapp.__path__) if not m.name.startswith("_")}
    assert modules == public and "rapp.schema" in modules


def test_the_page_is_in_the_book_and_linked_from_its_pages():
    toc = (ROOT / "_toc.yml").read_text(encoding="utf-8")
    assert "- file: book/api\n" in toc
    for page in ("intro.md", "scenario_format.md"):
        assert "{doc}`api`" in (ROOT / "book" / page).read_text(encoding="utf-8")
    config = (ROOT / "_config.yml").read_text(encoding="utf-8")
    for ext in ("sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon"):
        assert f"- {ext}\n" in config
