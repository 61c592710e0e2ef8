"""A journal: a JSON Lines file that grows one record at a time and survives any interruption.

Its first line is a header (what the records are records of); every other line is one record.
Each record is written as one line and flushed to disk before the next, so a run that is
interrupted, even killed mid-write, keeps every record it finished. Only the last line can be
torn (a kill between its first byte and its newline): :func:`read_journal` drops it, and
:class:`Journal` cuts it off before appending, so the file stays parseable line by line.
A damaged line anywhere else is not a kill's doing: it is refused, never skipped.

Examples
--------
>>> import os, tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     path = os.path.join(d, "log.jsonl")
...     with Journal(path, {"what": "demo"}) as j:
...         j.append({"k": 1})
...     with open(path, "a") as f:
...         _ = f.write('{"k": 2')          # a record torn by a kill
...     header, records = read_journal(path)
...     with Journal(path, {"what": "demo"}) as j:   # resumes after the last whole record
...         j.append({"k": 3})
...     header, records, read_journal(path)[1]
({'what': 'demo'}, [{'k': 1}], [{'k': 1}, {'k': 3}])
"""

from __future__ import annotations

import json
import os
from typing import Any

from rapp.errors import InvalidFormat, InvalidValue

__all__ = ["read_journal", "Journal"]


def _whole_lines(path) -> tuple[list, int]:
    """The file's whole, parseable lines and the byte length they span (a torn tail excluded)."""
    with open(path, "rb") as f:
        data = f.read()
    lines, end, start = [], 0, 0
    while start < len(data):
        stop = data.find(b"\n", start)
        if stop < 0:
            break  # no newline: the last line was torn
        try:
            lines.append(json.loads(data[start:stop]))
        except ValueError:
            if data.find(b"\n", stop + 1) >= 0 or data[stop + 1:].strip():
                raise InvalidFormat(f"{os.fspath(path)!r}: line {len(lines) + 1} is not JSON; "
                                    "the journal is damaged", field="journal") from None
            break  # a torn last line that happened to end in a newline byte of its own text
        start = end = stop + 1
    return lines, end


def read_journal(path) -> tuple[dict | None, list]:
    """``(header, records)`` of the journal at ``path``; ``(None, [])`` when there is none."""
    if not os.path.exists(path):
        return None, []
    lines, _ = _whole_lines(path)
    if not lines:
        return None, []
    if not isinstance(lines[0], dict):
        raise InvalidFormat(f"{os.fspath(path)!r} is not a journal (its first line is not an "
                            "object)", field="journal")
    return lines[0], lines[1:]


class Journal:
    """Append records to the journal at ``path`` (a context manager).

    A new or empty file gets ``header`` as its first line; an existing journal must have the
    same header (else :class:`rapp.errors.InvalidValue`: its records are of something else),
    and a torn last line is cut off first.
    """

    def __init__(self, path, header: dict, *, field: str = "journal"):
        self.path, self.header, self.field = os.fspath(path), header, field
        self._file: Any = None

    def __enter__(self):
        lines, end = _whole_lines(self.path) if os.path.exists(self.path) else ([], 0)
        canonical = json.loads(json.dumps(self.header))
        if lines and lines[0] != canonical:
            raise InvalidValue(f"{self.path!r} holds the records of another run (different "
                               "scenarios or settings); give another file or remove it",
                               field=self.field)
        self._file = open(self.path, "r+b" if os.path.exists(self.path) else "wb")
        self._file.truncate(end)
        self._file.seek(end)
        if not lines:
            self._write(self.header)
        return self

    def _write(self, obj) -> None:
        # One write of one whole line, then to disk: a kill tears at most this line.
        self._file.write(json.dumps(obj, allow_nan=True).encode() + b"\n")
        self._file.flush()
        os.fsync(self._file.fileno())

    def append(self, record: dict) -> None:
        """Write ``record`` as the journal's next line, on disk when this returns."""
        self._write(record)

    def __exit__(self, *exc):
        self._file.close()
        return False
