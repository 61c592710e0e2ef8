"""Loaded first by ``make check`` and ``make test`` (``-p tests.pytest_fast_start``), before nbval.

nbval imports nbformat, which imports jsonschema, whose optional format checkers for IRIs and
ISO durations build parsers when they are imported: rfc3987_syntax compiles an Earley grammar,
about 1.5 s in every test process, two workers and their controller. Notebooks and the tests'
schemas use neither format, so the test processes go without those two checkers: marked
missing here, jsonschema skips them as it does when they are not installed. Nothing else
changes; a bare ``pytest`` (without this plugin) runs the same tests, only slower to start.
"""

import sys

for _name in ("rfc3987_syntax", "isoduration"):
    sys.modules.setdefault(_name, None)  # `import` of a None entry raises ImportError
