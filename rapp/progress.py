"""Progress of long work, for whoever wants to show it; algorithms never print.

An algorithm that may run for more than a moment calls :func:`report` now and then
(``report("RRT", done, total)``); that costs one context-variable lookup when nobody listens.
A caller that wants to show progress wraps the work in :func:`reporting` with a callback; the
command line passes a :class:`TerminalLine`, which keeps one line on stderr up to date while
stderr is a terminal (and stays silent with ``--quiet`` or when it is piped).

Examples
--------
>>> seen = []
>>> with reporting(lambda stage, done, total: seen.append((stage, done, total))):
...     report("search", 5, 10)
>>> report("search", 6, 10)   # nobody listens: nothing happens
>>> seen
[('search', 5, 10)]
"""

from __future__ import annotations

import contextvars
import time
from contextlib import contextmanager

__all__ = ["report", "reporting", "TerminalLine"]

_listener: contextvars.ContextVar = contextvars.ContextVar("rapp_progress", default=None)


def report(stage: str, done, total=None) -> None:
    """Tell the listener, if any, that ``done`` of ``total`` units of ``stage`` are done."""
    listener = _listener.get()
    if listener is not None:
        listener(stage, done, total)


@contextmanager
def reporting(listener):
    """Within: :func:`report` calls ``listener(stage, done, total)``."""
    token = _listener.set(listener)
    try:
        yield listener
    finally:
        _listener.reset(token)


class TerminalLine:
    """A listener that keeps one line of ``stream`` up to date: ``stage: done/total (pct)``.

    Nothing is shown during the first ``delay`` seconds (a short run stays quiet), and then at
    most every ``every`` seconds; :meth:`clear` erases the line (call it before printing).

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> line = TerminalLine(out, delay=0.0, every=0.0)
    >>> line("RRT", 50, 200); line.clear()
    >>> out.getvalue()
    '\\rRRT: 50/200 (25%)\\x1b[K\\r\\x1b[K'
    """

    def __init__(self, stream, *, delay: float = 1.0, every: float = 0.2):
        self.stream, self.delay, self.every = stream, delay, every
        self.t0 = time.monotonic()
        self.last = -float("inf")
        self.shown = False

    def __call__(self, stage, done, total=None) -> None:
        now = time.monotonic()
        if now - self.t0 < self.delay or now - self.last < self.every:
            return
        self.last = now
        text = f"{stage}: {done}" + (f"/{total} ({100 * done / total:.0f}%)" if total else "")
        try:
            self.stream.write(f"\r{text}\x1b[K")
            self.stream.flush()
            self.shown = True
        except (OSError, ValueError):
            pass

    def clear(self) -> None:
        if self.shown:
            try:
                self.stream.write("\r\x1b[K")
                self.stream.flush()
            except (OSError, ValueError):
                pass
            self.shown = False
