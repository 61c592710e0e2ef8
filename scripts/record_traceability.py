"""Rewrite rapp/traceability_found.json: what the repository defines of the traceability map.

The record holds the map's section labels that a chapter of the table of contents defines and the
map's test node ids that name a test of their file, as tests/test_traceability.py finds them by
reading the chapters and parsing the test files. Chapter 9 checks the map against this record, so
that it runs wherever rapp is installed; tests/test_traceability.py fails while the record is stale.

Run from the repository root after changing the map, a chapter label or a test it names:
``python scripts/record_traceability.py``.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from test_traceability import defined_in  # noqa: E402  the repository's reader, one copy

from rapp.traceability import load_map  # noqa: E402


def main() -> None:
    out = ROOT / "rapp" / "traceability_found.json"
    record = defined_in(load_map(), ROOT)
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    os.replace(tmp, out)
    print(f"{out.relative_to(ROOT)}: {len(record['labels'])} labels, {len(record['tests'])} tests")


if __name__ == "__main__":
    main()
