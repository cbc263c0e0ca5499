"""Hand the memory freed by one mesh back to the system before the next one is read.

A worker process repairs mesh after mesh. glibc's allocator keeps much of what a large
mesh's arrays freed on its heap (numpy's large blocks move its mmap threshold up, so
later ones come from the heap too), and the next mesh's peak adds to what the process
already holds. `malloc_trim(0)` returns the free pages; the arrays themselves, hence
the results, are untouched. A trim costs system time (the pages it returns fault in again
for the next mesh), so it is done only while the process holds more than
`TRIM_ABOVE`: after a large mesh, not between small ones.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys
from collections.abc import Callable

try:
    _PAGE = os.sysconf("SC_PAGE_SIZE")
except (AttributeError, ValueError, OSError):  # not a POSIX system
    _PAGE = 4096

TRIM_ABOVE = 192 * 2**20
"""Resident size (bytes) above which freed memory is handed back: a worker holds about 150 MB after
its imports; only a large mesh's leftovers take it past this.
"""

_TRIM: Callable[[int], int] | bool | None = None
"""Glibc's `malloc_trim`, once looked up; False where there is none."""


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


def resident_bytes() -> int | None:
    """The process's resident set size, from `/proc/self/statm`; None where unreadable."""
    try:
        with open("/proc/self/statm", "rb") as f:
            pages = int(f.read().split()[1])
    except (OSError, ValueError, IndexError):
        return None
    return pages * _PAGE


def release_free_memory(above: int | None = TRIM_ABOVE) -> bool:
    """Return the allocator's free memory to the system (glibc's `malloc_trim(0)`).

    Only while the process holds more than `above` bytes (None: always). Returns
    whether it was done: False below that size, where there is no glibc or the call
    failed; the process then goes on as it was.
    """
    trim = _malloc_trim()
    if trim is None:
        return False
    if above is not None:
        resident = resident_bytes()
        if resident is not None and resident <= above:
            return False
    try:
        trim(0)
    except OSError:
        return False
    return True
