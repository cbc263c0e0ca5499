"""What a fix produced: one :class:`LinkResult` per link and the patched document."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Inertial, Problem, Robot
    from urdfinertia.errors import UrdfError
    from urdfinertia.link.assemble import Assembly
    from urdfinertia.link.errorbar import ErrorBar
    from urdfinertia.link.save import SaveReport


#: Problem kinds that ``--strict`` refuses ("lenient" readings are warnings even then).
STRICT_KINDS = ("dropped", "ignored")


@dataclass(frozen=True, eq=False)
class LinkResult:
    """What happened to one link.

    status : "recomputed"; "untouched" (nothing to compute from: no geometry, nothing
        wrong); "left" (it should have been computed but no usable geometry was left, or
        its parts could not be combined: its inertial is left exactly as written and
        ``reason`` says why).
    problems : the link's elements dropped and values ignored (read and compute time).
    """

    name: str
    status: str  # "recomputed" | "repaired" | "kept" | "untouched" | "left" (with a reason)
    geometry: str  # "collision" | "visual" | "spec" | "none" | "as written"
    assembly: Assembly | None
    previous: Inertial | None
    warnings: tuple[str, ...] = ()
    problems: tuple[Problem, ...] = ()
    reason: str | None = None
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

    def save(self, path: str | Path | None = None, *, in_place: bool = False,
             backup: bool = True, keep_mesh_paths: bool = False) -> SaveReport:
        """Write the fixed document, as ``urdf-inertia fix -o PATH`` (or ``--in-place``).

        Relative references are rewritten to resolve from ``path``'s folder, the write is
        atomic, and ``in_place`` keeps ``<input>.bak`` unless ``backup=False``. See
        :func:`urdfinertia.link.save.save_result` for the parameters and errors.

        Returns
        -------
        SaveReport
            The file written, whether it was, and the references rewritten.
        """
        from urdfinertia.link.save import save_result

        return save_result(self, path, in_place=in_place, backup=backup,
                           keep_mesh_paths=keep_mesh_paths)

    @property
    def left(self) -> tuple[LinkResult, ...]:
        """Links that should have been computed and were left as they were."""
        return tuple(r for r in self.links if r.status == "left")

    def left_error(self, r: LinkResult) -> UrdfError:
        """A link left as it was, as an error naming file, line and link."""
        from urdfinertia.errors import UrdfError

        line = r.previous.line if r.previous is not None else None
        if line is None:
            try:
                line = self.robot.link(r.name).line
            except KeyError:
                pass
        return UrdfError(r.reason or "left as it was", file=self.path, line=line,
                         link=r.name)

    def strict_refusal(self) -> UrdfError | None:
        """What ``--strict`` refuses: the first element dropped or value ignored, else
        the first link left as it was; None when the result is whole."""
        from urdfinertia.errors import UrdfError

        for p in self.problems:
            # a joint's value is never needed for inertials: not even --strict refuses it
            if p.kind in STRICT_KINDS and p.link is not None:
                cause = f"{p.element}: {p.cause}" if p.element else p.cause
                return UrdfError(cause, file=self.path, line=p.line, link=p.link)
        left = self.left
        return self.left_error(left[0]) if left else None

    @property
    def problems(self) -> tuple[Problem, ...]:
        """Everything read past: the document's own notes, then each link's problems."""
        own = tuple(p for p in self.robot.problems if p.link is None)
        return own + tuple(p for r in self.links for p in r.problems)
