"""What a fix produced: one :class:`LinkResult` per link and the patched document."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Inertial, Robot
    from urdfinertia.link.assemble import Assembly
    from urdfinertia.link.errorbar import ErrorBar


@dataclass(frozen=True, eq=False)
class LinkResult:
    """What happened to one link."""

    name: str
    status: str  # "recomputed" | "repaired" | "kept" | "untouched"
    geometry: str  # "collision" | "visual" | "spec" | "none" | "as written"
    assembly: Assembly | None
    previous: Inertial | None
    warnings: tuple[str, ...] = ()
    #: the policy's decision in words ("kept: plausible", "recomputed: inertia-zero", ...)
    decision: str = ""
    #: which of "mass", "com", "tensor" were kept as written and which derived
    kept: tuple[str, ...] = ()
    derived: tuple[str, ...] = ()
    #: expected error of a tensor derived from homogeneous geometry (None otherwise)
    error_bar: ErrorBar | None = None

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
    def changed(self) -> bool:
        return self.output != self.original
