"""Ctrl-C and SIGTERM for the command line: one line, one exit code, no file left half-done.

A command-line run has two phases. While Python is still importing (numpy, the planners: the
larger part of a short run), no code of the run exists to clean up after, so
:func:`guard_startup` makes SIGINT and SIGTERM end the process at once with
``rapp: interrupted`` and exit code 130 (143 for SIGTERM). ``python -m rapp`` and the ``rapp``
script install it before anything heavy is imported (``rapp/__init__.py`` does it first thing
when it is being imported by them). Once the command runs, :func:`catching` turns SIGINT into
:class:`KeyboardInterrupt` and SIGTERM into :class:`Terminated` (a KeyboardInterrupt too), so
the ``finally`` blocks that remove temporary files run for both, and the command reports
them in one line.

Only the command line installs handlers; ``import rapp`` in a program changes nothing.
This module imports nothing but the standard library's ``os``, ``signal`` and ``sys``.

Examples
--------
>>> with catching():
...     pass
>>> issubclass(Terminated, KeyboardInterrupt)
True
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from contextlib import contextmanager

__all__ = ["Terminated", "guard_startup", "catching", "deferred", "EXIT_SIGINT", "EXIT_SIGTERM",
           "running_as_command", "mark_reported"]

#: Exit codes: 128 + the signal's number, as a shell reports a program the signal ended.
EXIT_SIGINT = 128 + signal.SIGINT
EXIT_SIGTERM = 128 + signal.SIGTERM

_SIGNALS = tuple(s for s in (signal.SIGINT, signal.SIGTERM))
_reported = False


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the run was (like Ctrl-C's KeyboardInterrupt) so that it unwinds."""


def running_as_command(argv=None, orig_argv=None) -> bool:
    """Whether this process is ``python -m rapp`` being started, or the ``rapp`` script.

    ``python -m rapp`` imports the package while it locates ``rapp.__main__``, with
    ``sys.argv[0] == "-m"`` meanwhile; the script is a file named ``rapp``.

    Examples
    --------
    >>> running_as_command(["-m"], ["python", "-m", "rapp", "plan"])
    True
    >>> running_as_command(["-m"], ["python", "-m", "pytest"]), running_as_command(["x.py"], [])
    (False, False)
    >>> running_as_command(["/venv/bin/rapp", "plan"], ["python", "/venv/bin/rapp", "plan"])
    True
    >>> running_as_command(["/home/me/rapp"], ["python"])   # a folder named rapp, say
    False
    """
    argv = sys.argv if argv is None else argv
    orig = getattr(sys, "orig_argv", []) if orig_argv is None else orig_argv
    if not argv:
        return False
    if argv[0] == "-m":
        for i, a in enumerate(orig):
            if a == "-m" and i + 1 < len(orig):
                return orig[i + 1] == "rapp"
            if a.startswith("-m") and len(a) > 2:
                return a[2:] == "rapp"
        return False
    # The script's own path is both argv[0] and the interpreter's first argument.
    return os.path.basename(argv[0]) == "rapp" and argv[0] in orig[1:2]


def _die(signum, frame):  # pragma: no cover - runs in a subprocess (tests/test_reliability.py)
    # Block both signals first: a second Ctrl-C cannot print a second line.
    try:
        signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)
    except (AttributeError, OSError, ValueError):
        pass
    code = EXIT_SIGTERM if signum == signal.SIGTERM else EXIT_SIGINT
    if not _reported:
        try:
            os.write(2, b"rapp: interrupted\n" if code == EXIT_SIGINT else b"rapp: terminated\n")
        except OSError:
            pass
    os._exit(code)


def guard_startup() -> None:
    """SIGINT and SIGTERM end the process at once with one line (start-up and shut-down).

    Called from the main thread of the command line only; a no-op elsewhere.
    """
    if threading.current_thread() is not threading.main_thread():
        return
    for s in _SIGNALS:
        signal.signal(s, _die)


def mark_reported() -> None:
    """The run has said ``rapp: interrupted``: a later signal ends the process silently."""
    global _reported
    _reported = True


def _raise_terminated(signum, frame):
    raise Terminated()


@contextmanager
def catching():
    """Within: SIGINT raises KeyboardInterrupt and SIGTERM :class:`Terminated`; restored after.

    A no-op outside the main thread (Python delivers signals to it alone).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {s: signal.getsignal(s) for s in _SIGNALS}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        for s, h in before.items():
            if h is not None:
                signal.signal(s, h)


@contextmanager
def deferred():
    """Within: SIGINT and SIGTERM wait; they are delivered when the block ends.

    For a few system calls that must happen together (creating a temporary file and
    recording it; renaming a run's outputs into place): an interrupt then lands before or
    after them, never between.

    Blocking the signals in this thread is not enough: a signal sent to the process goes
    to any other thread that does not block it (numpy's BLAS threads, say), and Python
    then runs the handler in the main thread all the same. So the handlers are swapped
    for one that only remembers the signal, and the first one remembered is raised again
    once the previous handlers are back.

    Examples
    --------
    >>> with deferred():
    ...     x = 1
    >>> x
    1
    """
    if threading.current_thread() is not threading.main_thread():
        yield  # Python runs signal handlers in the main thread alone: nothing lands here
        return
    before = {s: signal.getsignal(s) for s in _SIGNALS}
    held = []
    holding = [True]

    def hold(signum, frame):
        if holding[0]:
            held.append(signum)
        else:  # the block has ended but this handler is still installed: act as the previous one
            _deliver(signum, frame, before[signum])

    old = None
    try:
        # ``hold`` first: from then on nothing raises here (an interrupt between the two
        # installs meets the previous handler, and the ``finally`` puts both back).
        for s in _SIGNALS:
            signal.signal(s, hold)
        try:
            old = signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)
        except (AttributeError, OSError, ValueError):  # not POSIX: the handlers alone hold them
            pass
        yield
    finally:
        if old is not None:
            # A signal kept blocked here arrives now and is held like the others.
            signal.pthread_sigmask(signal.SIG_SETMASK, old)
        # One store ends the holding, so an interrupt while the handlers are put back (a new
        # signal) meets either the previous handler or ``hold`` acting as it: never a mix.
        holding[0] = False
        for s, h in before.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)
        if held:
            signal.raise_signal(held[0])


def _deliver(signum, frame, handler) -> None:
    """What ``handler`` (as :func:`signal.getsignal` gave it) does with the signal."""
    if callable(handler):
        handler(signum, frame)
    elif handler != signal.SIG_IGN:  # the default action (or none known): take it
        signal.signal(signum, signal.SIG_DFL)
        signal.raise_signal(signum)
