"""The README's tour is code a reader will paste: it must run and say what it claims."""

import re
from pathlib import Path

import numpy as np

import rapp

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"```python\n(.*?)```", README, re.S)


def test_readme_python_blocks_run_and_plan_verifies(capsys):
    assert len(BLOCKS) >= 2
    ns: dict = {}
    for block in BLOCKS:
        exec(compile(block, "README.md", "exec"), ns)
    assert "verification: passed" in capsys.readouterr().out
    assert ns["plan"].report.ok
    path = ns["path"]
    assert path[0] == (50, 50) and path[-1] == (10, 80)
    assert len(path) - 1 == len(rapp.search.bfs(ns["occupied"], (50, 50), (10, 80))) - 1
    assert not any(ns["occupied"][cell] for cell in path)
    solutions = rapp.ik(ns["arm"], (1.2, 0.7))
    assert solutions.shape == (2, 2)
    assert np.allclose(ns["arm"].end_effector(solutions), (1.2, 0.7), atol=1e-12)
    # The composed motion: shortened, timed within its limits (the shortest), exported.
    assert len(ns["short"]) <= len(ns["raw"])
    assert np.all(ns["vmax"] <= 1.0 + 1e-9) and np.all(ns["amax"] <= 2.0 + 1e-9)
    assert max(ns["vmax"].max(), ns["amax"].max() / 2.0) > 1.0 - 1e-6
    points = ns["trajectory"]["points"]
    assert ns["trajectory"]["joint_names"] == ["shoulder", "elbow"] and len(points) > 2
    assert np.allclose(points[-1]["positions"], ns["short"][-1])


def test_readme_names_the_two_commands_ci_runs():
    ci = (Path(__file__).resolve().parents[1] / ".ci" / "run").read_text(encoding="utf-8")
    for command in ("make book", "make test"):
        assert command in README and command in ci


def test_readme_documents_the_fast_tier_that_make_check_runs():
    makefile = (Path(__file__).resolve().parents[1] / "Makefile").read_text(encoding="utf-8")
    recipe = re.search(r"^check:.*\n\t(.*)$", makefile, re.M)
    assert recipe and recipe.group(1).endswith('-m pytest $(PYTEST_START) -m "not slow"')
    start = re.search(r"^PYTEST_START := (.*)$", makefile, re.M)
    assert start and start.group(1) == "-p tests.pytest_fast_start"  # only a faster start: see the module
    assert "make check" in README and 'pytest -m "not slow"' in README and "tests.pytest_fast_start" in README
