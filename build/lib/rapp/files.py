"""Writing output files so that the user's work is never lost.

:func:`atomic_output` hands out a temporary path *beside* the target; only when
the writer has finished is it renamed over the target (``os.replace`` is atomic
on one file system). A crash, an error or Ctrl-C while writing leaves the
previous file untouched and removes the temporary one.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager

from rapp.interrupts import deferred

__all__ = ["atomic_output", "OutputBatch"]


def _new_temporary(path: str, suffix: str) -> str:
    """An empty temporary file beside ``path`` with the mode the target has or would get."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".rapp-", suffix=suffix, dir=folder)
    os.close(fd)
    try:
        if os.path.exists(path):
            mode = os.stat(path).st_mode & 0o777
        else:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(tmp, mode)  # mkstemp makes 0600; keep what a plain open() would give
    except BaseException:
        _remove(tmp)
        raise
    return tmp


def _remove(tmp: str) -> None:
    try:
        os.unlink(tmp)
    except OSError:
        pass


@contextmanager
def atomic_output(path, suffix: str = ".tmp"):
    """Context manager: yield a temporary file path; on success rename it to ``path``.

    The temporary file lies in the target's folder (so the rename stays on one
    file system) and ends in ``suffix`` (a writer that picks its format from
    the extension, like matplotlib, can be given the target's extension).
    The new file gets the permissions of the file it replaces, or those of a
    plain ``open()`` (0644 before the umask) when there was none.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     target = os.path.join(d, "out.txt")
    ...     with atomic_output(target) as tmp:
    ...         _ = open(tmp, "w").write("done")
    ...     print(open(target).read(), sorted(os.listdir(d)))
    done ['out.txt']
    """
    path = os.fspath(path)
    with deferred():  # an interrupt lands before the file exists or after it is in hand
        tmp = _new_temporary(path, suffix)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        _remove(tmp)
        raise


class OutputBatch:
    """Several output files of one run, put in place together at the end, or not at all.

    :meth:`stage` hands out a temporary path beside each target; the writers fill them while
    the run goes on. Leaving the ``with`` block normally renames every one of them over its
    target, with SIGINT and SIGTERM held back meanwhile (:func:`rapp.interrupts.deferred`),
    so an interrupt leaves either every previous file or every new one; leaving it by an
    exception (Ctrl-C included) removes the temporary files and keeps every previous file.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     a, b = os.path.join(d, "a.txt"), os.path.join(d, "b.txt")
    ...     with OutputBatch() as batch:
    ...         _ = open(batch.stage(a), "w").write("A")
    ...         _ = open(batch.stage(b), "w").write("B")
    ...         before = sorted(n for n in os.listdir(d) if not n.startswith(".rapp-"))
    ...     print(before, sorted(os.listdir(d)), open(a).read() + open(b).read())
    [] ['a.txt', 'b.txt'] AB
    """

    def __init__(self):
        self._staged: list = []  # (temporary path, target path)

    def stage(self, path, suffix: str = ".tmp") -> str:
        """A temporary file for ``path`` (ending in ``suffix``), renamed over it on success."""
        path = os.fspath(path)
        with deferred():
            tmp = _new_temporary(path, suffix)
            self._staged.append((tmp, path))
        return tmp

    def commit(self) -> None:
        """Rename every staged file over its target (interrupts held back until done)."""
        with deferred():
            while self._staged:
                tmp, path = self._staged[0]
                os.replace(tmp, path)
                self._staged.pop(0)

    def discard(self) -> None:
        """Remove every staged file; the targets keep their previous contents."""
        with deferred():
            while self._staged:
                _remove(self._staged.pop()[0])

    def __enter__(self):
        return self

    def __exit__(self, kind, value, tb):
        if kind is None:
            try:
                self.commit()
            except BaseException:
                self.discard()
                raise
        else:
            self.discard()
        return False
