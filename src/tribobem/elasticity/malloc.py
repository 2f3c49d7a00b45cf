"""Returning freed grid arrays to the system (glibc's malloc, Linux).

glibc serves an allocation above its mmap threshold with its own mapping, unmapped when the
array is freed; below it, from a heap that keeps freed memory for later use.  The threshold
starts at 128 kB and rises to the size of each mapped block freed, up to 32 MB, so after the
first large temporaries the arrays of a mid-size or large grid come from the heap, and what
fragmentation leaves there counts in the resident set: measured on a 2048^2 free-boundary
candidate-set solve, 60-64 bytes per node at the peak against 42-47 with a fixed threshold
(benchmarks/peers.py).  Large grids therefore fix the threshold once per process
(:func:`lean_allocator`): arrays from ``THRESHOLD`` bytes up are mapped and returned on free.
Their pages are faulted in anew at each allocation; the solvers keep their per-iteration
arrays in reused work buffers, so that costs little.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys

__all__ = ["lean_allocator", "THRESHOLD"]

#: Arrays of at least this many bytes are mapped (and returned to the system when freed).
THRESHOLD = 4 << 20
_M_MMAP_THRESHOLD = -3  # mallopt's parameter number (malloc.h)
_done: bool | None = None


def lean_allocator() -> bool:
    """Fix glibc's mmap threshold at ``THRESHOLD`` (once per process; Linux glibc only).

    The environment variable ``TRIBOBEM_MALLOC_MMAP_THRESHOLD`` sets another threshold in
    bytes; 0 leaves the allocator as it is.

    Returns
    -------
    bool
        Whether the threshold is fixed in this process.
    """
    global _done
    if _done is not None:
        return _done
    _done = False
    env = os.environ.get("TRIBOBEM_MALLOC_MMAP_THRESHOLD")
    threshold = int(env) if env else THRESHOLD
    if threshold <= 0 or not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        _done = bool(libc.mallopt(_M_MMAP_THRESHOLD, ctypes.c_int(threshold)))
    except (OSError, AttributeError):  # not glibc
        _done = False
    return _done
