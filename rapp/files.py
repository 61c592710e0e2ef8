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

__all__ = ["atomic_output"]


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
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
