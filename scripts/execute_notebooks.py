"""Execute the book's notebooks top to bottom and save them with their outputs.

Usage:
    python scripts/execute_notebooks.py                 # every notebooks/*.ipynb
    python scripts/execute_notebooks.py notebooks/01_introduction.ipynb ...

Each notebook runs in a fresh kernel with notebooks/ as the working directory, and is written
back in place. Widget state is stored in the notebook metadata (JupyterLab does not do this by
default, and a widget without saved state renders blank in the book); cell timings are not
recorded, so re-executing an unchanged notebook changes only what the code changes. Exit status
is non-zero when any cell raises.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = ROOT / "notebooks"
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"


def execute(path: Path, timeout: int) -> None:
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(
        nb,
        timeout=timeout,
        kernel_name="python3",
        resources={"metadata": {"path": str(NOTEBOOKS)}},
        record_timing=False,
        store_widget_state=True,
        allow_errors=False,
    )
    client.execute(cwd=str(NOTEBOOKS))
    # A notebook that shows no widget any more keeps no saved widget state: the book would
    # embed it in the page all the same (megabytes of views nobody sees).
    if not any(WIDGET_VIEW in out.get("data", {}) for cell in nb.cells if cell.cell_type == "code"
               for out in cell.outputs):
        nb.metadata.pop("widgets", None)
    # nbclient leaves per-cell "execution" metadata only when record_timing is on; drop any
    # left over from JupyterLab so the saved file carries no timings.
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
    nbformat.validate(nb)
    nbformat.write(nb, path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", type=Path, help="notebooks (default: notebooks/*.ipynb)")
    parser.add_argument("--timeout", type=int, default=600, help="seconds per cell (default 600)")
    args = parser.parse_args(argv)

    # A backend forced from the environment (e.g. MPLBACKEND=Agg) removes inline figures.
    os.environ.pop("MPLBACKEND", None)
    paths = [p.resolve() for p in args.paths] or sorted(NOTEBOOKS.glob("*.ipynb"))
    failed = []
    for path in paths:
        start = time.perf_counter()
        try:
            execute(path, args.timeout)
        except CellExecutionError as err:
            failed.append(path)
            print(f"FAIL {path.relative_to(ROOT)}\n{err}", file=sys.stderr)
            continue
        print(f"ok   {path.relative_to(ROOT)} ({time.perf_counter() - start:.1f} s)")
    print(f"executed {len(paths) - len(failed)} of {len(paths)} notebooks")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
