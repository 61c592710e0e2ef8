"""Progress of long work, for whoever wants to show it; algorithms never print.

An algorithm that may run for more than a moment calls :func:`report` now and then
(``report("RRT", done, total)``); that costs one context-variable lookup when nobody listens.
A caller that wants to show progress wraps the work in :func:`reporting` with a callback; the
command line uses a :class:`TerminalLine`, which keeps one line on stderr up to date while
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
import threading
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
    """A listener that keeps one line of ``stream`` up to date while work goes on.

    The line reads ``stage: done/total (pct), 12 s`` (or ``stage, 12 s`` when only a stage is
    known); it appears after ``delay`` seconds (a short run stays quiet) and is redrawn every
    ``every`` seconds by a small thread, so it moves even while one long numpy call runs.
    Use it as a context manager: leaving erases the line, so what is printed next starts clean.

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> with TerminalLine(out, delay=10.0) as line:   # the thread would draw after 10 s
    ...     line("RRT", 50, 200)
    ...     line.draw()
    >>> "RRT: 50/200 (25%), 0 s" in out.getvalue()
    True
    >>> out.getvalue().endswith(chr(13) + chr(27) + "[K")   # erased on leaving
    True
    """

    def __init__(self, stream, *, delay: float = 1.5, every: float = 0.25):
        self.stream, self.delay, self.every = stream, delay, every
        self.state = ("working", None, None)
        self.t0 = time.monotonic()
        self.shown = False
        self._lock = threading.Lock()
        self._done = threading.Event()
        self._thread = None

    def __call__(self, stage, done=None, total=None) -> None:
        self.state = (stage, done, total)

    def text(self) -> str:
        stage, done, total = self.state
        elapsed = f"{time.monotonic() - self.t0:.0f} s"
        if done is None:
            return f"{stage}, {elapsed}"
        if total:
            return f"{stage}: {done}/{total} ({100 * done / total:.0f}%), {elapsed}"
        return f"{stage}: {done}, {elapsed}"

    def draw(self) -> None:
        with self._lock:
            if self._done.is_set() and self._thread is not None:
                return
            try:
                self.stream.write(f"\r{self.text()}\x1b[K")
                self.stream.flush()
                self.shown = True
            except (OSError, ValueError):
                pass

    def _run(self) -> None:
        if self._done.wait(self.delay):
            return
        while not self._done.is_set():
            self.draw()
            self._done.wait(self.every)

    def __enter__(self):
        self._token = _listener.set(self)
        self._thread = threading.Thread(target=self._run, name="rapp-progress", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._done.set()
        self._thread.join()
        _listener.reset(self._token)
        with self._lock:
            if self.shown:
                try:
                    self.stream.write("\r\x1b[K")
                    self.stream.flush()
                except (OSError, ValueError):
                    pass
                self.shown = False
        return False
