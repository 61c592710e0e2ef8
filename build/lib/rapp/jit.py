"""Compiling rapp's kernels with numba, lazily: numba is imported by the first call, not by rapp.

A kernel is a plain Python function over numpy arrays and scalars; :func:`jit` compiles it
(``numba.njit``, cached on disk, releasing the GIL) or returns None when numba cannot be
imported, and the caller then runs its own fallback. Importing this module does not import
numba.

Examples
--------
>>> def add(a, b):
...     return a + b
>>> f = jit(add)
>>> (f or add)(2, 3)
5
"""

from __future__ import annotations

__all__ = ["jit", "numba_available"]


def numba_available() -> bool:
    """Whether numba can be imported (importing it, the first time: about half a second)."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def jit(f, **options):
    """``f`` compiled by numba (``njit``, ``nogil``, cached on disk), or None without numba.

    ``options`` go to ``numba.njit`` as they are (``inline="always"``, ``error_model="numpy"``).
    Where no cache directory can be written, ``f`` is compiled on every run instead.
    """
    try:
        import numba
    except ImportError:
        return None
    try:
        return numba.njit(cache=True, nogil=True, **options)(f)
    except RuntimeError:  # no writable cache directory: compile on every run
        return numba.njit(nogil=True, **options)(f)
