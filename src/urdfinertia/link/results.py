"""What a fix produced: one :class:`LinkResult` per link and the patched document."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Inertial, Robot
    from urdfinertia.link.assemble import Assembly


@dataclass(frozen=True, eq=False)
class LinkResult:
    """What happened to one link."""

    name: str
    status: str  # "recomputed" | "untouched" | "failed" (formats that isolate links)
    geometry: str  # "collision" | "visual" | "spec" | "none"
    assembly: Assembly | None
    previous: Inertial | None
    warnings: tuple[str, ...] = ()

    @property
    def size(self) -> float:
        """A length scale of the link (radius of gyration plus CoM offset), m."""
        if self.assembly is None:
            return 0.0
        import numpy as np

        t = self.assembly.total
        return float(np.sqrt(np.trace(t.inertia) / t.mass) + np.linalg.norm(t.com))


@dataclass(frozen=True, eq=False)
class FixResult:
    path: Path
    robot: Robot
    links: tuple[LinkResult, ...]
    original: bytes
    output: bytes

    @property
    def failed(self) -> tuple[LinkResult, ...]:
        """Links that could not be computed and were left as written."""
        return tuple(r for r in self.links if r.status == "failed")

    @property
    def changed(self) -> bool:
        return self.output != self.original
