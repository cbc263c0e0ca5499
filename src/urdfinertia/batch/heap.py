"""Hand the memory freed by one mesh back to the system before the next one is read.

A worker process repairs mesh after mesh. glibc's allocator keeps much of what a large
mesh's arrays freed on its heap (numpy's large blocks move its mmap threshold up, so
later ones come from the heap too), and the next mesh's peak adds to what the process
already holds. ``malloc_trim(0)`` returns the free pages; the arrays themselves, hence
the results, are untouched.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
from collections.abc import Callable

#: glibc's ``malloc_trim``, once looked up; False where there is none.
_TRIM: Callable[[int], int] | bool | None = None


def _malloc_trim() -> Callable[[int], int] | None:
    global _TRIM
    if _TRIM is None:
        _TRIM = False
        if sys.platform.startswith("linux"):
            try:
                libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
                trim = libc.malloc_trim  # absent from musl: AttributeError
                trim.argtypes = [ctypes.c_size_t]
                trim.restype = ctypes.c_int
                _TRIM = trim
            except (OSError, AttributeError):
                pass
    return _TRIM if callable(_TRIM) else None


def release_free_memory() -> bool:
    """Return the allocator's free memory to the system (glibc's ``malloc_trim(0)``).

    Returns whether it was done: False where there is no glibc or the call failed; the
    process then goes on as it was.
    """
    trim = _malloc_trim()
    if trim is None:
        return False
    try:
        trim(0)
    except OSError:
        return False
    return True
