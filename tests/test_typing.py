"""The package is typed: rapp.__all__ is annotated (measured here) and mypy passes on rapp
with the configuration in pyproject.toml (``[tool.mypy]``), as a user's type checker will read
it (``py.typed`` is shipped)."""

import inspect
import os
from pathlib import Path

import pytest

import rapp

ROOT = Path(__file__).resolve().parents[1]


def unannotated(obj) -> list:
    """The parameters (and ``return``) of a function, or of a class's ``__init__``, that carry
    no annotation; ``self`` and ``cls`` excepted. A class whose ``__init__`` is inherited from
    outside rapp (an exception's) has nothing of its own to annotate."""
    fn = obj
    if inspect.isclass(obj):
        fn = next((c.__dict__["__init__"] for c in obj.__mro__
                   if c.__module__.startswith("rapp") and "__init__" in c.__dict__), None)
        if fn is None:
            return []
    sig = inspect.signature(inspect.unwrap(fn))
    out = [p.name for p in sig.parameters.values()
           if p.name not in ("self", "cls") and p.annotation is inspect.Parameter.empty]
    if sig.return_annotation is inspect.Signature.empty:
        out.append("return")
    return out


def test_the_measure_sees_a_missing_annotation():
    def f(a: int, b) -> None: ...

    def g(a: int):
        ...

    class C:
        def __init__(self, x: int) -> None: ...

    assert unannotated(f) == ["b"] and unannotated(g) == ["return"] and unannotated(C) == []


def test_at_least_95_percent_of_the_public_names_are_fully_annotated():
    missing = {name: unannotated(getattr(rapp, name)) for name in rapp.__all__}
    missing = {name: m for name, m in missing.items() if m}
    share = 1 - len(missing) / len(rapp.__all__)
    assert share >= 0.95, f"{share:.0%} fully annotated; missing: {missing}"


def test_mypy_passes_on_the_package():
    api = pytest.importorskip("mypy.api")
    cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rapp" / "mypy"
    out, err, status = api.run(["--config-file", str(ROOT / "pyproject.toml"),
                                "--cache-dir", str(cache), "--no-error-summary",
                                "--hide-error-context", str(ROOT / "rapp")])
    errors = [line for line in out.splitlines() if ": error:" in line]
    assert status == 0 and not errors, "\n".join(errors) or out + err
