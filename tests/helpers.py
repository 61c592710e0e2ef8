"""What several test files need: running the command line in-process, and loading a script.

Imported as ``tests.helpers`` (the repository root is on the path under pytest).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

from rapp.cli import main

ROOT = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    """``python -m rapp *argv`` in this process: ``(exit code, stdout, stderr)``."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def one_line(err):
    """The one line of ``err`` (asserting there is exactly one, and no traceback)."""
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def write(tmp_path, content, name="s.json"):
    """``content`` (bytes, text, or a scenario dict as JSON) written to ``tmp_path / name``; its path."""
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content if isinstance(content, str) else json.dumps(content))
    return str(p)


def load_script(relative: str, name: str | None = None):
    """The module of a script of the repository (``benchmarks/x.py``, ``scripts/y.py``), loaded
    from its file: no folder is added to ``sys.path`` for it."""
    path = ROOT / relative
    name = name or path.stem
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
