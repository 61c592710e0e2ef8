"""Every notebook nbval checks runs alone: an empty folder, a copy of it, and only rapp to import.

:func:`install` (called by the root ``conftest.py``) wraps nbval's per-notebook setup so that
the kernel starts in :func:`alone`'s folder and environment. The run that checks a chapter's
committed outputs is then also the proof that the chapter runs from an empty folder with only
rapp installed, at no extra cost. ``tests/test_standalone_notebooks.py`` checks the mechanism.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import nbval.plugin

#: Chapters that still read files of the repository around them, run in notebooks/ until they
#: no longer do (tests/test_standalone_notebooks.py marks their scan as a strict xfail).
#: Notebooks that keep their old working folder, with the reason (none: every chapter runs alone).
RUN_IN_PLACE: dict = {}
RAPP_PACKAGE = Path(__file__).resolve().parent.parent / "rapp"


@contextmanager
def alone(notebook: Path):
    """An empty temporary folder holding a copy of ``notebook`` only, and the environment of a
    kernel that can import ``rapp`` and nothing else of the repository.

    Yields ``(folder, env)``. ``PYTHONPATH`` is a folder whose only entry is a link to this
    checkout's ``rapp`` (so a worktree's own package is the one imported, and the repository's
    root, with ``benchmarks/``, ``tests/`` and ``scripts/``, is not on the path).
    """
    with tempfile.TemporaryDirectory(prefix=f"rapp-{notebook.stem}-") as tmp:
        folder, site = Path(tmp) / "alone", Path(tmp) / "site"
        folder.mkdir()
        site.mkdir()
        shutil.copy(notebook, folder / notebook.name)
        (site / "rapp").symlink_to(RAPP_PACKAGE, target_is_directory=True)
        yield folder, dict(os.environ, PYTHONPATH=str(site))


_nbval_setup, _nbval_teardown = nbval.plugin.IPyNbFile.setup, nbval.plugin.IPyNbFile.teardown


def setup_alone(self):
    """nbval's setup, with the kernel started in :func:`alone`'s folder and environment."""
    notebook = Path(str(self.fspath))
    if notebook.name in RUN_IN_PLACE:
        return _nbval_setup(self)
    self._rapp_alone = alone(notebook)
    folder, env = self._rapp_alone.__enter__()
    real_kernel, saved = nbval.plugin.RunningKernel, dict(os.environ)
    nbval.plugin.RunningKernel = lambda name, cwd=None, **kw: real_kernel(name, cwd=str(folder), **kw)
    os.environ.clear()
    os.environ.update(env)  # the kernel process inherits it
    try:
        _nbval_setup(self)
    finally:
        nbval.plugin.RunningKernel = real_kernel
        os.environ.clear()
        os.environ.update(saved)


def teardown_alone(self):
    """nbval's teardown, then the folder of :func:`setup_alone` removed."""
    try:
        _nbval_teardown(self)
    finally:
        context = self.__dict__.pop("_rapp_alone", None)
        if context is not None:
            context.__exit__(None, None, None)


def install() -> None:
    """Make nbval run every notebook alone (once, however often it is called)."""
    nbval.plugin.IPyNbFile.setup, nbval.plugin.IPyNbFile.teardown = setup_alone, teardown_alone
