"""Test configuration shared by every test, doctest and notebook (at the root, so that it holds
however pytest is started: `pytest`, `pytest notebooks/05_astar.ipynb`, `pytest -m "not slow"`).

Under CI (``CI`` set in the environment, as ``.ci/run`` does) hypothesis runs
derandomized: the same examples every run, so a landing never depends on luck.
Locally it explores fresh examples each run, which is how it finds new bugs, and
remembers failing ones in a database kept in the user's cache folder, never in
the working tree (a test run leaves the checkout exactly as it found it).
"""

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import nbval.plugin
import pytest
from hypothesis import settings
from hypothesis.configuration import set_hypothesis_home_dir
from hypothesis.database import DirectoryBasedExampleDatabase

_cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rapp" / "hypothesis"
set_hypothesis_home_dir(str(_cache))  # its constants cache too, not ./.hypothesis
settings.register_profile("local", database=DirectoryBasedExampleDatabase(str(_cache / "examples")))
settings.register_profile("ci", derandomize=True, print_blob=True, database=None)
settings.load_profile("ci" if os.environ.get("CI") else "local")


@pytest.hookimpl(tryfirst=True)  # before pytest's own -m selection reads the marks
def pytest_collection_modifyitems(config, items):
    """Mark the slow tiers, then put the longest files first, so that two workers finish together.

    Every notebook cell and every JupyterLab browser test is marked ``slow``: ``make check``
    (``pytest -m "not slow"``) leaves them out, ``make test`` runs them. Other slow tests carry
    ``@pytest.mark.slow`` themselves.

    pytest-xdist (``--dist loadfile --no-loadscope-reorder``) hands out whole files in this
    order. The JupyterLab tests (two minutes in one file) and the notebooks (a kernel each)
    go first; a long file dealt out last would keep one worker busy while the other idles.
    Within a file the order is untouched: a notebook's cells must run in order.
    """
    def weight(item):
        path = str(item.fspath)
        if path.endswith("test_jupyterlab.py"):
            return 0
        if path.endswith(".ipynb"):
            return 1
        return 2

    slow = pytest.mark.slow
    for item in items:
        path = str(item.fspath)
        if path.endswith(".ipynb") or path.endswith("test_jupyterlab.py"):
            item.add_marker(slow)
    items.sort(key=weight)  # stable: each file's items keep their order


# ---- notebooks run alone ----------------------------------------------------------------------
#: Chapters that still read files of the repository around them, run in notebooks/ until they
#: no longer do (tests/test_standalone_notebooks.py marks their scan as a strict xfail).
RUN_IN_PLACE = {
    "14_completeness.ipynb": "reads ../benchmarks (harness and planners.json) until the planner "
                             "harness moves into rapp (issue 21 items 1-4)",
}
RAPP_PACKAGE = Path(__file__).resolve().parent / "rapp"


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
        env = dict(os.environ, PYTHONPATH=str(site))
        yield folder, env


_nbval_setup, _nbval_teardown = nbval.plugin.IPyNbFile.setup, nbval.plugin.IPyNbFile.teardown


def _setup_alone(self):
    """nbval's setup, with the kernel started in :func:`alone`'s folder and environment.

    So every `make test` proves that each chapter runs from an empty folder with only rapp
    installed, at no extra cost: the run that checks the committed outputs is that run.
    """
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


def _teardown_alone(self):
    try:
        _nbval_teardown(self)
    finally:
        context = self.__dict__.pop("_rapp_alone", None)
        if context is not None:
            context.__exit__(None, None, None)


nbval.plugin.IPyNbFile.setup, nbval.plugin.IPyNbFile.teardown = _setup_alone, _teardown_alone
