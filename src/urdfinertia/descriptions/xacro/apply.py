"""Apply a write-back plan: verify in memory, write the sources, verify again from disk,
and restore every source if the second check fails (nothing is left half-written)."""

from __future__ import annotations

from pathlib import Path

from urdfinertia.atomic import atomic_write_bytes, write_in_place
from urdfinertia.descriptions.urdf.write import scan_links
from urdfinertia.descriptions.xacro.expand import Expansion, XacroSettings, expand_xacro
from urdfinertia.descriptions.xacro.trace import SLOTS, elements, link_inertials
from urdfinertia.descriptions.xacro.writeback import Plan
from urdfinertia.errors import UrdfError


def verification_mismatch(original: bytes, fixed: bytes, again: bytes,
                          written: set[str]) -> str | None:
    """The first difference between the re-expanded sources and what was asked, or None.

    Every written link's inertial values must equal the fixed URDF's (as printed there);
    every other byte of the expansion must equal the original expansion's.
    """
    want = link_inertials(elements(fixed))
    got = link_inertials(elements(again))
    for name in sorted(written):
        if name not in got:
            return f"link '{name}' is missing from the expansion"
        for slot, *_ in SLOTS:
            a, b = want[name].slots[slot].text, got[name].slots[slot].text
            if _num(a) != _num(b):
                return (f"link '{name}' {slot}: the fixed URDF has {a}, the edited sources "
                        f"expand to {b}")
    rest_a, rest_b = _without(original, written), _without(again, written)
    if rest_a != rest_b:
        lines_a, lines_b = rest_a.splitlines(), rest_b.splitlines()
        for i, (x, y) in enumerate(zip(lines_a, lines_b, strict=False)):
            if x != y:
                return (f"expansion changed outside the written inertials: "
                        f"{x.strip().decode(errors='replace')!r} became "
                        f"{y.strip().decode(errors='replace')!r} (line {i + 1})")
        return "expansion changed length outside the written inertials"
    return None


def _num(text: str | None) -> float | None:
    try:
        return float(text) if text is not None else None
    except ValueError:
        return None


def _without(document: bytes, links: set[str]) -> bytes:
    """`document` without the <inertial> elements of `links`."""
    spans = scan_links(document)
    cuts: list[tuple[int, int]] = []
    for name in links:
        span = spans.get(name)
        if span is not None and span.inertial is not None:
            cuts.append(span.inertial)
    cuts.sort()
    out, pos = [], 0
    for start, end in cuts:
        line = document.rfind(b"\n", 0, start)
        if line >= 0 and not document[line + 1:start].strip():
            start = line  # the element's line goes whole: an added one leaves no blank
        out += [document[pos:start]]
        pos = end
    return b"".join(out) + document[pos:]


def apply_plan(path: str | Path, exp: Expansion, fixed: bytes, plan: Plan,
               settings: XacroSettings, *, backup: bool = True) -> list[Path]:
    """Write the plan's edits; returns the files written.

    Raises `UrdfError` (exit 2) naming the first mismatch when the edited sources
    do not expand to the fixed URDF: before writing when the in-memory check fails
    (nothing written), after writing when the check from disk fails (sources restored).
    """
    path = Path(path).absolute()
    if not plan.edits:
        return []
    new = plan.new_sources(exp)
    main = exp.sources[0]
    again = expand_xacro(path, new.get(main, exp.source_bytes[0]), settings=settings,
                         overrides=new)
    mismatch = verification_mismatch(exp.document, fixed, again.document, plan.written)
    if mismatch:
        raise UrdfError(f"write-back check failed, nothing written: {mismatch}", file=path)
    originals = dict(zip(exp.sources, exp.source_bytes, strict=True))
    for file in new:  # the sources must still be what was expanded
        try:
            current = file.read_bytes()
        except OSError as exc:
            raise UrdfError(f"cannot read: {exc.strerror or exc}", file=file) from None
        if current != originals[file]:
            raise UrdfError("changed on disk during the run; nothing written", file=file)
    written: list[Path] = []
    try:
        for file, data in new.items():
            written.append(write_in_place(file, data) if backup else
                           atomic_write_bytes(file, data))
        check = expand_xacro(path, settings=settings)
        mismatch = verification_mismatch(exp.document, fixed, check.document, plan.written)
    except BaseException:
        _restore(written, originals)
        raise
    if mismatch:
        _restore(written, originals)
        raise UrdfError(f"write-back check failed, sources restored: {mismatch}", file=path)
    return written


def _restore(written: list[Path], originals: dict[Path, bytes]) -> None:
    for file in written:
        atomic_write_bytes(file, originals[Path(file)])
