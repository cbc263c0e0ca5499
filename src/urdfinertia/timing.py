"""Wall-clock time per stage of a run (XML, mesh read, repair, integration, ...).

A :class:`StageTimes` is plain data (a dict of seconds), so worker processes return theirs
with their results and the parent adds them up.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager

#: Stage names in the order reports print them.
STAGES = (
    "xml",  # read and parse the URDF
    "mesh read",  # parse mesh files into triangles
    "repair",  # weld, orient, close: mesh -> repaired bodies
    "union",  # boolean unions of overlapping bodies (manifold3d), not counted in repair
    "integration",  # volume integrals of the repaired bodies
    "cache",  # hash mesh bytes, read and write cache entries
    "assemble",  # parts -> link totals -> patched document
    "write",  # write output files
)


class StageTimes:
    """Seconds spent per stage, accumulated over any number of timed blocks."""

    def __init__(self, seconds: Mapping[str, float] | None = None) -> None:
        self.seconds: dict[str, float] = dict(seconds or {})

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Time the ``with`` block and add it to ``name`` (also when the block raises)."""
        start = time.perf_counter()
        try:
            yield
        finally:
            self.add(name, time.perf_counter() - start)

    def add(self, name: str, seconds: float) -> None:
        self.seconds[name] = self.seconds.get(name, 0.0) + seconds

    def merge(self, other: StageTimes | Mapping[str, float]) -> None:
        """Add another timer's stages into this one."""
        items = other.seconds if isinstance(other, StageTimes) else other
        for name, seconds in items.items():
            self.add(name, seconds)

    def get(self, name: str) -> float:
        return self.seconds.get(name, 0.0)

    def total(self) -> float:
        return sum(self.seconds.values())

    def ordered(self) -> list[tuple[str, float]]:
        """Known stages first in :data:`STAGES` order, then any others by name."""
        known = [(s, self.seconds[s]) for s in STAGES if s in self.seconds]
        extra = sorted((k, v) for k, v in self.seconds.items() if k not in STAGES)
        return known + extra

    def __repr__(self) -> str:
        body = ", ".join(f"{k}={v:.3f}s" for k, v in self.ordered())
        return f"StageTimes({body})"


class OverBudget(Exception):
    """Raised by :meth:`Deadline.check` once its time is up."""


class Deadline:
    """A limit on the CPU time of this process that long computations check between steps.

    CPU time, not wall time: on a loaded machine (a CI runner, a shared build host) the
    same work takes the same CPU time, so a result does not depend on what else ran.
    ``seconds`` None never expires. Checking is cheap (one clock read), so loops check
    once per step and the caller that set the deadline catches :class:`OverBudget`.
    """

    def __init__(self, seconds: float | None) -> None:
        self.seconds = seconds
        self.end = None if seconds is None else time.process_time() + seconds

    def expired(self) -> bool:
        return self.end is not None and time.process_time() > self.end

    def check(self) -> None:
        """Raise :class:`OverBudget` when the time is up."""
        if self.expired():
            raise OverBudget(f"over the time budget of {self.seconds:g} s")
