"""What libraries print while they read a file, kept off the user's terminal.

trimesh reports a COLLADA texture it cannot load with ``log.warning(..., exc_info=True)``;
with no handler configured, Python's last-resort handler prints that with its traceback on
stderr (PR2's COLLADA files printed 15 during ``check``: the run was fine, but looked like
a crash). pycollada and numpy warn through :mod:`warnings`, and some readers print to
``sys.stderr`` directly. Inside :func:`library_output` all three are collected instead,
then handed on as debug records of the ``urdfinertia`` logger (``--debug`` shows them),
one line each, tracebacks folded into their last line. What a library says that matters
for the result reaches the user through the caller's own errors and notes, never through
a library's output.
"""

from __future__ import annotations

import contextlib
import io
import logging
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field

#: Loggers of the libraries that read meshes and descriptions.
LIBRARY_LOGGERS = ("trimesh", "collada", "pycollada", "xacro", "pxr", "PIL")
#: Where the collected lines go, at debug level.
LOGGER = logging.getLogger("urdfinertia")


@dataclass
class Captured:
    """The lines collected while reading ``what``."""

    what: str
    lines: list[str] = field(default_factory=list)


class _Collect(logging.Handler):
    def __init__(self, into: list[str]) -> None:
        super().__init__(logging.DEBUG)
        self._into = into

    def emit(self, record: logging.LogRecord) -> None:
        try:
            text = record.getMessage()
        except Exception:  # noqa: BLE001 - a malformed record must not fail the read
            text = str(record.msg)
        if record.exc_info and record.exc_info[1] is not None:
            exc = record.exc_info[1]
            text += f" ({type(exc).__name__}: {exc})"
        self._into.append(f"{record.name}: {record.levelname.lower()}: {text}")


@contextlib.contextmanager
def library_output(what: str) -> Iterator[Captured]:
    """Collect library log records, warnings and stderr text while reading ``what`` (a
    file name, for the debug lines); hand them on at debug level when the block ends,
    also when it raises."""
    found = Captured(what)
    handler = _Collect(found.lines)
    saved = []
    for name in LIBRARY_LOGGERS:
        lib = logging.getLogger(name)
        saved.append((lib, lib.propagate))
        lib.addHandler(handler)
        lib.propagate = False
    text = io.StringIO()
    try:
        with warnings.catch_warnings(record=True) as caught, \
                contextlib.redirect_stderr(text):
            warnings.simplefilter("always")
            yield found
    finally:
        for lib, propagate in saved:
            lib.removeHandler(handler)
            lib.propagate = propagate
        for w in caught:
            found.lines.append(f"warning: {w.category.__name__}: {w.message}")
        found.lines.extend(line.strip() for line in text.getvalue().splitlines()
                           if line.strip() and not line.startswith(" "))
        for line in found.lines:
            LOGGER.debug("%s: %s", what, line)
