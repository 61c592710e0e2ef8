"""Test configuration shared by every test, doctest and notebook (at the root, so that it holds
however pytest is started: `pytest`, `pytest notebooks/05_astar.ipynb`, `pytest -m "not slow"`).

Under CI (``CI`` set in the environment, as ``.ci/run`` does) hypothesis runs
derandomized: the same examples every run, so a landing never depends on luck.
Locally it explores fresh examples each run, which is how it finds new bugs, and
remembers failing ones in a database kept in the user's cache folder, never in
the working tree (a test run leaves the checkout exactly as it found it).
"""

import os
import sys
from pathlib import Path

import pytest
from hypothesis import settings
from hypothesis.configuration import set_hypothesis_home_dir
from hypothesis.database import DirectoryBasedExampleDatabase

_cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rapp" / "hypothesis"
set_hypothesis_home_dir(str(_cache))  # its constants cache too, not ./.hypothesis
settings.register_profile("local", database=DirectoryBasedExampleDatabase(str(_cache / "examples")))
settings.register_profile("ci", derandomize=True, print_blob=True, database=None)
settings.load_profile("ci" if os.environ.get("CI") else "local")


#: Doctests that take seconds (a docstring cannot carry a mark): they run in `make test` only.
SLOW_DOCTESTS = {
    "rapp.plotting.save_gif",              # writes a GIF, frame by frame
    "rapp.widgets.rrt_explorer",           # grows and draws every step of an RRT
    "rapp.cases.rrt_report.compare_with_astar",
    "rapp.widgets.arm_explorer",           # renders every view of the explorer
    # Each builds and renders a whole explorer (0.3-0.5 s): tests/test_widgets.py drives the
    # same explorers in the fast tier, so their docstrings' examples wait for `make test`.
    "rapp.widgets.collision_explorer",
    "rapp.widgets.sliders_of",
    "rapp.widgets.astar_explorer",
    "rapp.widgets.line_ride_explorer",
    "rapp.widgets.trajectory_explorer",
    "rapp.widgets.planner_playground",
    "rapp.plotting.animation_html",        # encodes an animation's frames
}


#: The longest test files of `make test`, longest first (measured with --durations).
LONG_FILES = ("test_jupyterlab.py", "test_grading.py", "test_sampling_kernel.py", "test_reliability.py",
              "test_live.py", "test_sandbox.py")


@pytest.hookimpl(tryfirst=True)  # before pytest's own -m selection reads the marks
def pytest_collection_modifyitems(config, items):
    """Mark the slow tiers, then put the longest files first, so that two workers finish together.

    Every notebook cell, every JupyterLab browser test and the doctests of ``SLOW_DOCTESTS`` are
    marked ``slow``: ``make check`` (``pytest -m "not slow"``) leaves them out, ``make test`` runs
    them. Other slow tests carry ``@pytest.mark.slow`` themselves.

    pytest-xdist (``--dist loadfile --no-loadscope-reorder``) hands out whole files in this
    order. The files of ``LONG_FILES`` (from a minute or two down to twenty seconds each: the
    JupyterLab tests, a class of 30 graded, the compiled planners against the numpy loops, ...)
    and the notebooks (a kernel each) go first, then the other files, largest first; a long
    file dealt out last would keep one worker busy while the other idles. Within a file the order is untouched: a notebook's cells must
    run in order.
    """
    sizes: dict = {}

    def weight(item):
        path = Path(str(item.fspath))
        if path.name in LONG_FILES:
            return LONG_FILES.index(path.name), 0
        if path.name.endswith(".ipynb"):
            return len(LONG_FILES), 0
        # The other files, larger first (a file's size stands for its tests' time): the
        # small ones dealt out last even out the two workers' ends.
        if path not in sizes:
            sizes[path] = path.stat().st_size if path.exists() else 0
        return len(LONG_FILES) + 1, -sizes[path]

    slow = pytest.mark.slow
    for item in items:
        path = str(item.fspath)
        if path.endswith(".ipynb") or path.endswith("test_jupyterlab.py") or item.name in SLOW_DOCTESTS:
            item.add_marker(slow)
    items.sort(key=weight)  # stable: each file's items keep their order


# ---- notebooks run alone (tests/notebook_kernels.py) ------------------------------------------
sys.path.insert(0, str(Path(__file__).resolve().parent / "tests"))
import notebook_kernels  # noqa: E402  one module object, shared with the tests that read it

notebook_kernels.install()
