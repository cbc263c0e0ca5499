"""Where each inertial value of a xacro expansion is written, decided by evidence.

Method (for the links whose inertial changes between the expansion E0 and the fixed URDF):

1. The trace (`.expand`) names the source element each expanded element was copied
   from. A link's `<inertial>` copied from a source element that holds no `$` and is
   used once in the whole expansion is a literal: it is spliced as a whole, as for URDF.
2. Otherwise each changed value (mass, CoM xyz, rpy, six moments) is looked for among the
   source literals that could carry it: numbers in the attribute of its own source
   element, in `xacro:property`/`xacro:arg` values and defaults, macro parameter
   defaults, macro call attributes and YAML scalars, keeping those equal to its value.
3. Discovery: those candidates are replaced by distinct marker numbers and the sources
   expanded again (in memory); a value showing a candidate's marker comes from that
   literal unchanged. A failed expansion, or one whose structure changed, is split in
   halves until each candidate is tried alone.
4. Confirmation: the chosen literals are perturbed again, alone or in groups split on
   failure, and must move exactly their one value and nothing else in the expansion.
   A literal that also moves another value (a property used twice, a macro default used
   by two instances) is *shared*; a value showing no marker is *computed* (an expression).
5. A link is written only when every changed value has a confirmed literal; otherwise it
   is reported with where each value comes from (file:line and the expression).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from urdfinertia.descriptions.xacro.expand import Expansion, XacroSettings, expand_xacro
from urdfinertia.descriptions.xacro.literals import (
    Literal,
    element_literals,
    start_tag_at,
    xml_literals,
    yaml_literals,
    yaml_number,
)
from urdfinertia.descriptions.xacro.trace import (
    SLOTS,
    LinkInertial,
    Position,
    describe,
    elements,
    link_inertials,
    token_stream,
)
from urdfinertia.errors import UrdfInertiaError


@dataclass(frozen=True)
class ValueNote:
    """One changed value of a link and where it comes from."""

    slot: str
    current: str | None
    fixed: str
    source: str  # file:line, or "" when unknown
    expression: str  # the raw text there (an expression, or the literal's context)
    reason: str = ""  # why it is not written ("" when it is)


@dataclass(frozen=True)
class LinkOutcome:
    link: str
    status: str  # "written" | "reported" | "unchanged"
    detail: str  # where it was written, or why not
    values: tuple[ValueNote, ...] = ()


@dataclass
class Plan:
    outcomes: list[LinkOutcome]
    edits: list[tuple[Path, int, int, bytes]] = field(default_factory=list)
    """(source path, start, end, new bytes) per edit."""

    @property
    def written(self) -> set[str]:
        """The links whose values were written back."""
        return {o.link for o in self.outcomes if o.status == "written"}

    def new_sources(self, exp: Expansion) -> dict[Path, bytes]:
        """The edited bytes of every file touched, from the bytes the expansion read."""
        originals = dict(zip(exp.sources, exp.source_bytes, strict=True))
        by_file: dict[Path, list[tuple[int, int, bytes]]] = {}
        for path, start, end, text in self.edits:
            by_file.setdefault(path, []).append((start, end, text))
        out = {}
        for path, edits in by_file.items():
            data = originals[path]
            pieces, pos = [], 0
            for start, end, text in sorted(set(edits)):
                if start < pos:
                    raise UrdfInertiaError("two write-back edits overlap", file=path)
                pieces += [data[pos:start], text]
                pos = end
            out[path] = b"".join(pieces) + data[pos:]
        return out


def _float(text: str | None) -> float | None:
    try:
        return float(text) if text is not None else None
    except ValueError:
        return None


class _Prober:
    """Expansions of the sources with some literals replaced by marker numbers."""

    def __init__(self, path: Path, exp: Expansion, settings: XacroSettings) -> None:
        self.path, self.exp, self.settings = path, exp, settings
        self.els = elements(exp.document)
        self.structure, self.tokens = token_stream(self.els)
        self.markers: dict[Literal, str] = {}
        self.runs = 0

    def marker(self, lit: Literal) -> str:
        if lit not in self.markers:
            self.markers[lit] = f"{7001 + len(self.markers)}.123457"
        return self.markers[lit]

    def changes(self, lits: list[Literal]) -> dict[Position, str] | None:
        """Tokens that moved when `lits` are perturbed; None: expansion failed or its
        structure changed."""
        by_file: dict[int, list[Literal]] = {}
        for lit in lits:
            by_file.setdefault(lit.source, []).append(lit)
        overrides = {}
        for index, group in by_file.items():
            data = self.exp.source_bytes[index]
            pieces, pos = [], 0
            for lit in sorted(group, key=lambda x: x.start):
                pieces += [data[pos:lit.start], self.marker(lit).encode()]
                pos = lit.end
            overrides[self.exp.sources[index]] = b"".join(pieces) + data[pos:]
        self.runs += 1
        try:
            exp = expand_xacro(self.path, self.exp.source_bytes[0], settings=self.settings,
                               overrides=overrides)
            structure, tokens = token_stream(elements(exp.document))
        except UrdfInertiaError:
            return None
        if structure != self.structure:
            return None
        return {p: t for p, t in tokens.items() if self.tokens[p] != t}

    def owner(self, lits: list[Literal], token: str) -> Literal | None:
        value = _float(token)
        for lit in lits:
            if value is not None and value == float(self.marker(lit)):
                return lit
        return None

    def discover(self, lits: list[Literal], exact: dict[Literal, set[Position]]) -> None:
        if not lits:
            return
        moved = self.changes(lits)
        if moved is None:
            if len(lits) > 1:
                half = len(lits) // 2
                self.discover(lits[:half], exact)
                self.discover(lits[half:], exact)
            return
        for position, token in moved.items():
            lit = self.owner(lits, token)
            if lit is not None:
                exact.setdefault(lit, set()).add(position)

    def confirm(self, chosen: dict[Literal, Position], bad: dict[Literal, str]) -> None:
        if not chosen:
            return
        moved = self.changes(list(chosen))
        if moved is not None and set(moved) == set(chosen.values()) and all(
                _float(moved[p]) == float(self.marker(lit)) for lit, p in chosen.items()):
            return
        if len(chosen) > 1:
            items = list(chosen.items())
            half = len(items) // 2
            self.confirm(dict(items[:half]), bad)
            self.confirm(dict(items[half:]), bad)
            return
        (lit, position), = chosen.items()
        if moved is None:
            bad[lit] = "changing it changes the structure of the expansion"
        else:
            others = [describe(self.els, p) for p in sorted(moved) if p != position]
            more = f" and {len(others) - 3} more" if len(others) > 3 else ""
            bad[lit] = "shared: it also sets " + ", ".join(others[:3]) + more


def plan_write_back(path: str | Path, exp: Expansion, fixed: bytes,
                    settings: XacroSettings) -> Plan:
    """Decide, link by link, which source bytes to change so that expanding the sources
    gives `fixed` (the fixed expanded URDF; `exp` is the traced original expansion)."""
    path = Path(path).absolute()
    prober = _Prober(path, exp, settings)
    els = prober.els
    before = link_inertials(els)
    after = link_inertials(elements(fixed))
    uses: dict[tuple[int, int], int] = {}
    for loc in exp.locations:
        if loc is not None:
            uses[loc] = uses.get(loc, 0) + 1
    plan = Plan([])
    per_slot: dict[str, dict[str, tuple[str | None, str]]] = {}
    for name, old in before.items():
        new = after.get(name)
        changed = _changed(old, new) if new is not None else {}
        if new is None or not changed:
            plan.outcomes.append(LinkOutcome(name, "unchanged", "inertial unchanged"))
            continue
        whole = _whole_element(exp, old, new, uses, plan)
        if whole is not None:
            plan.outcomes.append(LinkOutcome(name, "written", whole))
            continue
        missing = [s for s in changed if old.slots[s].position is None]
        if missing:
            where = exp.where(exp.locations[old.inertial_index]) \
                if old.inertial_index is not None else exp.where(exp.locations[old.link_index])
            why = ("the link has no <inertial> and its <link> is not written once in the "
                   "sources" if old.inertial_index is None else
                   f"no {', '.join(missing)} in an <inertial> that is not a literal")
            plan.outcomes.append(LinkOutcome(name, "reported", f"{why} ({where})", tuple(
                ValueNote(s, changed[s][0], changed[s][1], where, "", why) for s in changed)))
            continue
        per_slot[name] = changed
    _plan_values(prober, exp, before, per_slot, plan)
    order = {name: i for i, name in enumerate(before)}
    plan.outcomes.sort(key=lambda o: order.get(o.link, len(order)))
    return plan


def _changed(old: LinkInertial, new: LinkInertial) -> dict[str, tuple[str | None, str]]:
    out = {}
    for name, *_ in SLOTS:
        a, b = old.slots[name].text, new.slots[name].text
        if b is None:
            continue
        if a is None or _float(a) != _float(b):
            out[name] = (a, b)
    return out


def _plan_values(prober: _Prober, exp: Expansion, before: dict[str, LinkInertial],
                 per_slot: dict[str, dict[str, tuple[str | None, str]]], plan: Plan) -> None:
    """Steps 2-5 of the method for the links that are not a literal <inertial>."""
    wanted = {_float(old) for changed in per_slot.values() for old, _ in changed.values()}
    candidates: dict[Literal, None] = {}
    own: dict[tuple[str, str], tuple[Literal | None, str, str]] = {}
    for name, changed in per_slot.items():
        for slot in changed:
            position = before[name].slots[slot].position
            assert position is not None
            el_index, attr, tok = position
            location = exp.locations[el_index]
            where, literal, raw = "", None, ""
            if location is not None:
                where = exp.where(location)
                tokens, raw_value = element_literals(exp.source_bytes[location[0]],
                                                     location[1], attr, location[0])
                raw = f"{attr}=\"{raw_value}\"" if raw_value is not None else ""
                if len(tokens) == len(els_value(prober, position)) and tok < len(tokens):
                    literal = tokens[tok][0]
            own[(name, slot)] = (literal, where, raw)
            if literal is not None:
                candidates[literal] = None
    for index, data in enumerate(exp.source_bytes):
        found = yaml_literals(data, index) if _is_yaml(exp.sources[index]) \
            else xml_literals(data, index)
        for lit in found:
            if lit.value in wanted:
                candidates[lit] = None
    exact: dict[Literal, set[Position]] = {}
    prober.discover([c for c in candidates if c.value in wanted], exact)
    by_position = {p: lit for lit, ps in exact.items() for p in ps}
    chosen: dict[Literal, Position] = {}
    notes: dict[str, list[ValueNote]] = {}
    for name, changed in per_slot.items():
        for slot, (old, new) in changed.items():
            position = before[name].slots[slot].position
            source_lit = by_position.get(position) if position is not None else None
            _, where, raw = own[(name, slot)]
            if source_lit is None or position is None:
                reason = f"computed by {raw or 'an expression'}" if raw else "computed"
                notes.setdefault(name, []).append(ValueNote(slot, old, new, where, raw, reason))
            elif len(exact[source_lit]) > 1:
                others = [describe(prober.els, p) for p in sorted(exact[source_lit])
                          if p != position]
                notes.setdefault(name, []).append(ValueNote(
                    slot, old, new, _lit_where(exp, source_lit), source_lit.context,
                    "shared: it also sets " + ", ".join(others[:3])))
            else:
                chosen[source_lit] = position
                notes.setdefault(name, []).append(ValueNote(
                    slot, old, new, _lit_where(exp, source_lit), source_lit.context))
    bad: dict[Literal, str] = {}
    prober.confirm(chosen, bad)
    literal_of = {p: lit for lit, p in chosen.items()}
    for name in per_slot:
        final = []
        for note in notes[name]:
            at = before[name].slots[note.slot].position
            traced = literal_of.get(at) if at is not None else None
            if traced is not None and traced in bad:
                note = ValueNote(note.slot, note.current, note.fixed, note.source,
                                 note.expression, bad[traced])
            final.append(note)
        blocked = [n for n in final if n.reason]
        if blocked:
            first = blocked[0]
            plan.outcomes.append(LinkOutcome(
                name, "reported", f"{first.slot}: {first.reason} ({first.source})",
                tuple(final)))
            continue
        places = []
        for note in final:
            at = before[name].slots[note.slot].position
            assert at is not None  # a note without a reason was traced to a literal here
            lit = literal_of[at]
            text = yaml_number(note.fixed) if lit.kind == "yaml" else note.fixed
            plan.edits.append((exp.sources[lit.source], lit.start, lit.end, text.encode()))
            places.append(f"{note.slot} at {note.source}")
        plan.outcomes.append(LinkOutcome(name, "written", "; ".join(places), tuple(final)))


def els_value(prober: _Prober, position: Position) -> list[str]:
    """The whitespace-separated words at `position` of the prober's expansion.

    Parameters
    ----------
    prober : _Prober
        An expansion with probe values.
    position : Position
        (element index, attribute or "#text", word index).

    Returns
    -------
    list of str
        The attribute's (or the text's) words.
    """
    el_index, attr, _ = position
    el = prober.els[el_index]
    return (el.text if attr == "#text" else el.get(attr, "")).split()


def _is_yaml(path: Path) -> bool:
    return path.suffix.lower() in (".yaml", ".yml")


def _lit_where(exp: Expansion, lit: Literal) -> str:
    return exp.where((lit.source, lit.start))


def _whole_element(exp: Expansion, old: LinkInertial, new: LinkInertial,
                   uses: dict[tuple[int, int], int], plan: Plan) -> str | None:
    """Splice a literal `<inertial>` written once (or insert one into a `<link>` written
    once that has none); the place in words, or None when that does not apply."""
    if old.inertial_index is not None:
        loc = exp.locations[old.inertial_index]
        if loc is None or uses.get(loc) != 1:
            return None
        data = exp.source_bytes[loc[0]]
        close = data.find(b"</inertial", loc[1])
        end = data.find(b">", close) + 1 if close >= 0 else 0
        tag = start_tag_at(data, loc[1])
        if tag is None:
            return None
        if tag[3]:
            end = tag[2]
        elif close < 0 or end <= 0:
            return None
        span = data[loc[1]:end]
        if b"$" in span or b"xacro:" in span:
            return None
        indent = _indent(data, loc[1])
        step = _step(span, indent)
        text = _inertial_text(new, indent, step, b"\r\n" if b"\r\n" in data else b"\n")
        plan.edits.append((exp.sources[loc[0]], loc[1], end, text))
        return f"literal <inertial> at {exp.where(loc)}"
    loc = exp.locations[old.link_index]
    if loc is None or uses.get(loc) != 1:
        return None
    data = exp.source_bytes[loc[0]]
    tag = start_tag_at(data, loc[1])
    if tag is None or tag[3]:
        return None
    indent = _indent(data, loc[1])
    newline = b"\r\n" if b"\r\n" in data else b"\n"
    child = indent + b"  "
    text = newline + child + _inertial_text(new, child, b"  ", newline)
    plan.edits.append((exp.sources[loc[0]], tag[2], tag[2], text))
    return f"<inertial> inserted into <link> at {exp.where(loc)}"


def _indent(data: bytes, pos: int) -> bytes:
    start = data.rfind(b"\n", 0, pos) + 1
    prefix = data[start:pos]
    return prefix if not prefix.strip() else b""


def _step(span: bytes, indent: bytes) -> bytes:
    for line in span.splitlines()[1:]:
        stripped = line.lstrip(b" \t")
        lead = line[:len(line) - len(stripped)]
        if stripped and len(lead) > len(indent) and lead.startswith(indent):
            return lead[len(indent):]
    return b"  "


def _inertial_text(new: LinkInertial, indent: bytes, step: bytes, newline: bytes) -> bytes:
    v = {name: new.slots[name].text or "0" for name, *_ in SLOTS}
    inner = indent + step
    lines = [
        b"<inertial>",
        inner + f'<origin xyz="{v["com x"]} {v["com y"]} {v["com z"]}" '
                f'rpy="{v["roll"]} {v["pitch"]} {v["yaw"]}"/>'.encode(),
        inner + f'<mass value="{v["mass"]}"/>'.encode(),
        inner + (f'<inertia ixx="{v["ixx"]}" ixy="{v["ixy"]}" ixz="{v["ixz"]}" '
                 f'iyy="{v["iyy"]}" iyz="{v["iyz"]}" izz="{v["izz"]}"/>').encode(),
        indent + b"</inertial>",
    ]
    return newline.join(lines)


def report_yaml(plan: Plan) -> str:
    """The reported links with where each value comes from, for a person to apply."""
    import yaml

    def note(n) -> dict:  # noqa: ANN001
        out = {"value": n.slot, "current": n.current, "fixed": n.fixed, "source": n.source,
               "written_as": n.expression}
        if n.reason:
            out["why_not_written"] = n.reason
        return out

    doc = {
        "reported": [{"link": o.link, "why": o.detail, "values": [note(n) for n in o.values]}
                     for o in plan.outcomes if o.status == "reported"],
        "written": [{"link": o.link, "where": o.detail}
                    for o in plan.outcomes if o.status == "written"],
        "unchanged": [o.link for o in plan.outcomes if o.status == "unchanged"],
    }
    return yaml.safe_dump(doc, sort_keys=False, width=100)
