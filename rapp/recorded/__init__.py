"""Benchmark results as recorded by the scripts in the repository's ``benchmarks/`` folder.

They are package data, so that the performance chapter reads the same numbers with only
``rapp`` installed, from any folder. Each file holds the machine it was recorded on (CPUs,
load, platform) and the date beside the timings; the scripts rewrite them
(``python benchmarks/bench_core.py`` writes ``rapp/recorded/core.json``, ...).

Examples
--------
>>> names()
['astar_cpp', 'cli', 'core', 'ik', 'kernel', 'live', 'memory', 'occupancy', 'planners', 'planners_cpu', 'planners_ompl', 'planners_ompl_kernel', 'search', 'time_scaling']
>>> core = load("core")
>>> core["machine"]["cpu_count"], sorted(core["results"])[:2]
(2, ['2link_M100', '2link_M360'])
"""

from __future__ import annotations

import json
from importlib import resources

__all__ = ["names", "load"]


def names() -> list[str]:
    """The recorded results, by name (a file ``NAME.json`` of this package), sorted."""
    return sorted(f.name[:-5] for f in resources.files(__name__).iterdir()
                  if f.name.endswith(".json"))


def load(name: str) -> dict:
    """The recorded result ``name`` (see :func:`names`), parsed from its JSON file.

    Raises
    ------
    KeyError
        When no result of that name is recorded; the message lists those that are.
    """
    if name not in names():
        raise KeyError(f"no recorded result {name!r}; recorded: {', '.join(names())}")
    return json.loads(resources.files(__name__).joinpath(f"{name}.json").read_text("utf-8"))
