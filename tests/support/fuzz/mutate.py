"""Mutators of description documents (URDF, xacro, SDFormat, MJCF, usda text).

Each mutator is ``(data, rng, profile) -> Edit | None``: the mutated bytes and the
file-system objects they refer to (:class:`Fixture`), or None when the document holds
nothing it applies to. They work on the bytes with regular expressions rather than a
parser, so that they can produce what no parser would write (misnested, duplicated or
truncated elements) while most mutants still parse and reach the code past the reader.
A mutant that names a file the case makes writes it as ``@CASE@/NAME``; the case replaces
the marker with its folder's absolute path (:func:`support.fuzz.cases.materialize`).
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable
from dataclasses import dataclass, field

CASE_MARK = b"@CASE@"


@dataclass(frozen=True)
class Fixture:
    """A file-system object a mutant refers to, made in the case folder.

    kind : "fifo", "dir", "sparse" (``size`` bytes, no data), "loop" (two symbolic links
        naming each other), "link" (a symbolic link to ``target``), "empty", "bytes"
        (``data``).
    """

    kind: str
    name: str
    size: int = 0
    target: str = ""
    data: bytes = b""


@dataclass(frozen=True)
class Edit:
    kind: str
    data: bytes
    fixtures: tuple[Fixture, ...] = ()


@dataclass(frozen=True)
class Profile:
    """What a format's documents are made of, for the structure-aware mutators."""

    elements: tuple[str, ...]  # tags worth deleting or duplicating
    named: tuple[str, ...]  # tags whose name attribute identifies them
    mass: re.Pattern[bytes]  # group 1: a mass value
    mesh_ref: re.Pattern[bytes]  # group 1: a mesh (or included file) reference
    tensor: re.Pattern[bytes]  # group 1: one moment or product of inertia
    parent_child: re.Pattern[bytes] | None = None  # group 1: parent name, group 2: child
    xml: bool = True
    extra: tuple[str, ...] = field(default=())


_Q = rb"[\"']"
PROFILES: dict[str, Profile] = {
    "urdf": Profile(
        elements=("link", "joint", "inertial", "collision", "visual", "geometry", "origin",
                  "mass", "inertia", "mesh", "box", "cylinder", "sphere", "parent", "child"),
        named=("link", "joint"),
        mass=re.compile(rb"<mass\s+value=" + _Q + rb"([^\"']*)" + _Q),
        mesh_ref=re.compile(rb"<mesh\b[^>]*?filename=" + _Q + rb"([^\"']*)" + _Q),
        tensor=re.compile(rb"\bi(?:xx|yy|zz|xy|xz|yz)=" + _Q + rb"([^\"']*)" + _Q),
        parent_child=re.compile(rb"<parent\s+link=" + _Q + rb"([^\"']*)" + _Q + rb"\s*/>\s*"
                                rb"<child\s+link=" + _Q + rb"([^\"']*)" + _Q),
    ),
    "sdf": Profile(
        elements=("link", "joint", "inertial", "collision", "visual", "geometry", "pose",
                  "mass", "inertia", "mesh", "box", "cylinder", "sphere", "model", "uri",
                  "parent", "child"),
        named=("link", "joint", "model", "collision", "visual"),
        mass=re.compile(rb"<mass>([^<]*)</mass>"),
        mesh_ref=re.compile(rb"<uri>([^<]*)</uri>"),
        tensor=re.compile(rb"<i(?:xx|yy|zz|xy|xz|yz)>([^<]*)</i"),
        parent_child=re.compile(rb"<parent>([^<]*)</parent>\s*<child>([^<]*)</child>"),
    ),
    "mjcf": Profile(
        elements=("body", "geom", "joint", "inertial", "mesh", "site", "default", "include",
                  "compiler", "freejoint"),
        named=("body", "geom", "joint", "mesh"),
        mass=re.compile(rb"\bmass=" + _Q + rb"([^\"']*)" + _Q),
        mesh_ref=re.compile(rb"\b(?:file|meshdir|assetdir)=" + _Q + rb"([^\"']*)" + _Q),
        tensor=re.compile(rb"\b(?:diaginertia|fullinertia)=" + _Q + rb"([^\"']*)" + _Q),
        extra=("quat", "euler", "axisangle", "fromto", "size", "pos", "density", "scale"),
    ),
    "usd": Profile(
        elements=(),
        named=(),
        mass=re.compile(rb"physics:mass\s*=\s*([^\s\n]+)"),
        mesh_ref=re.compile(rb"@([^@]*)@"),
        tensor=re.compile(rb"physics:diagonalInertia\s*=\s*\(([^)]*)\)"),
        xml=False,
        extra=("metersPerUnit", "kilogramsPerUnit", "physics:centerOfMass",
               "physics:principalAxes", "physics:density", "size", "radius", "height"),
    ),
}
PROFILES["xacro"] = PROFILES["urdf"]

#: Numbers that are not finite, too large, denormal, signed zero, or not numbers at all.
BAD_NUMBERS = ("nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e307", "1.7976931348623157e308",
               "1e-320", "5e-324", "-0", "-0.0", "0", "1e9", "1e10", "-1", "1e30", "1e-30",
               "9" * 400, "", "1e", "0x10", "1_000", "+1", ".5", "1e400", "-1e-320",
               "\u0661\u0662", " 1 ", "1,5")
#: Names that are empty, long, or unusual text.
BAD_NAMES = ("", " ", "a" * 5000, "\u0141\u012b\u00f1\u049a_\u202e_\u540d\u524d_\U0001f916",
             "../../etc/passwd", "a b", "\u0000", "x" * 70000, "&amp;", "\u200b")
#: Text inserted to break encodings or the XML lexer.
BAD_BYTES = (b"\xff\xfe", b"\xef\xbb\xbf", b"\x00", b"\xc3\x28", b"\xed\xa0\x80", b"]]>",
             b"<!--", b"&", b"<", b"\r", "\u2028".encode(), "\U0001f916".encode())

_NUMBER = re.compile(rb"(?<![\w.])-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def _attr_value_spans(data: bytes) -> list[tuple[int, int]]:
    return [m.span(1) for m in re.finditer(rb"\s[\w:.-]+=\"([^\"]*)\"", data)]


def _element_spans(data: bytes, tags: tuple[str, ...]) -> list[tuple[int, int]]:
    if not tags:
        return []
    alt = "|".join(re.escape(t) for t in tags).encode()
    pattern = re.compile(rb"<(" + alt + rb")\b(?:[^>]*?/>|.*?</\1\s*>)", re.S)
    return [m.span() for m in pattern.finditer(data)]


def _replace(data: bytes, span: tuple[int, int], new: bytes) -> bytes:
    return data[: span[0]] + new + data[span[1]:]


# --- byte level ----------------------------------------------------------------------

def flip_bytes(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    if not data:
        return None
    out = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return Edit("flip", bytes(out))


def truncate(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    if len(data) < 2:
        return None
    return Edit("truncate", data[: rng.randrange(1, len(data))])


def splice(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """A piece of the document copied somewhere else."""
    if len(data) < 2:
        return None
    start = rng.randrange(len(data))
    piece = data[start: start + rng.randint(1, 200)]
    at = rng.randrange(len(data))
    return Edit("splice", data[:at] + piece + data[at:])


def insert_bytes(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    at = rng.randrange(len(data) + 1)
    return Edit("bad-bytes", data[:at] + rng.choice(BAD_BYTES) + data[at:])


# --- values --------------------------------------------------------------------------

def bad_number(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = [m.span() for m in _NUMBER.finditer(data)]
    if not spans:
        return None
    return Edit("number", _replace(data, rng.choice(spans), rng.choice(BAD_NUMBERS).encode()))


def bad_numbers_everywhere(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """One bad value for every number of one attribute or element kind (all masses...)."""
    value = rng.choice(("nan", "1e308", "-1", "1e-320", "0", "inf", "1e307"))
    pattern = rng.choice((profile.mass, profile.tensor))
    found = list(pattern.finditer(data))
    if not found:
        return None
    for m in reversed(found):
        old = m.group(1)
        new = _NUMBER.sub(value.encode(), old) if _NUMBER.search(old) else value.encode()
        data = _replace(data, m.span(1), new)
    return Edit("number-all", data)


def negative_mass(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    found = list(profile.mass.finditer(data))
    if not found:
        return None
    value = rng.choice((b"-1", b"-1e-9", b"-0", b"0", b"-1e8", b"1e-320"))
    return Edit("negative-mass", _replace(data, rng.choice(found).span(1), value))


def huge_mass(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    found = list(profile.mass.finditer(data))
    if not found:
        return None
    value = rng.choice((b"1e307", b"1e308", b"1e9", b"9.9e8", b"1e18", b"1e-300"))
    return Edit("huge-mass", _replace(data, rng.choice(found).span(1), value))


def broken_tensor(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """One moment or product made far larger or negative: not positive definite, or
    A + B < C."""
    found = list(profile.tensor.finditer(data))
    if not found:
        return None
    m = rng.choice(found)
    numbers = list(_NUMBER.finditer(m.group(1)))
    value = rng.choice((b"1e3", b"-1e-3", b"1e30", b"1e-300", b"100", b"-100", b"1e8"))
    if not numbers:
        return Edit("tensor", _replace(data, m.span(1), value))
    n = rng.choice(numbers)
    start = m.start(1) + n.start()
    return Edit("tensor", _replace(data, (start, start + len(n.group())), value))


def other_attribute(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """A format-specific number (MJCF quat, fromto, size; USD metersPerUnit ...) made
    zero, non-finite or huge."""
    if not profile.extra:
        return None
    name = rng.choice(profile.extra).encode()
    if profile.xml:
        pattern = re.compile(rb"\b" + re.escape(name) + rb"=[\"']([^\"']*)[\"']")
    else:
        pattern = re.compile(re.escape(name) + rb"\s*=\s*(\([^)]*\)|[^\s\n]+)")
    found = list(pattern.finditer(data))
    if not found:
        return None
    m = rng.choice(found)
    count = max(1, len(_NUMBER.findall(m.group(1))))
    value = rng.choice(("0", "nan", "-1", "1e308", "1e-320", "inf"))
    body = " ".join([value] * count) if profile.xml else (
        "(" + ", ".join([value] * count) + ")" if m.group(1).startswith(b"(") else value)
    return Edit(f"attr-{name.decode()}", _replace(data, m.span(1), body.encode()))


def huge_string(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = _attr_value_spans(data) or [m.span(1) for m in re.finditer(rb"\"([^\"\n]*)\"",
                                                                           data)]
    if not spans:
        return None
    size = rng.choice((1000, 100_000, 1_000_000, 11_000_000))
    piece = rng.choice((b"A", "\u00e9".encode(), b"9", b" "))
    return Edit("huge-string", _replace(data, rng.choice(spans), piece * (size // len(piece))))


def unicode_value(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = _attr_value_spans(data)
    if not spans:
        return insert_bytes(data, rng, profile)
    text = rng.choice(BAD_NAMES[3:4] + ("\u202e1.0", "\u00bd", "\u2212" "1", "１", "1\u200b"))
    return Edit("unicode", _replace(data, rng.choice(spans), text.encode()))


# --- structure -----------------------------------------------------------------------

def delete_element(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = _element_spans(data, profile.elements)
    if not spans:
        return _delete_line(data, rng)
    return Edit("delete-element", _replace(data, rng.choice(spans), b""))


def _delete_line(data: bytes, rng: random.Random) -> Edit | None:
    lines = data.split(b"\n")
    if len(lines) < 3:
        return None
    del lines[rng.randrange(1, len(lines))]
    return Edit("delete-line", b"\n".join(lines))


def duplicate_element(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = _element_spans(data, profile.elements)
    if not spans:
        lines = data.split(b"\n")
        if len(lines) < 3:
            return None
        i = rng.randrange(1, len(lines))
        lines.insert(i, lines[i])
        return Edit("duplicate-line", b"\n".join(lines))
    start, end = rng.choice(spans)
    copies = rng.choice((1, 1, 2, 50))
    return Edit("duplicate-element", data[:end] + data[start:end] * copies + data[end:])


def delete_attribute(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    spans = [m.span() for m in re.finditer(rb"\s[\w:.-]+=[\"'][^\"']*[\"']", data)]
    if not spans:
        return None
    return Edit("delete-attribute", _replace(data, rng.choice(spans), b""))


def duplicate_attribute(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    found = [m for m in re.finditer(rb"\s[\w:.-]+=[\"'][^\"']*[\"']", data)]
    if not found:
        return None
    m = rng.choice(found)
    return Edit("duplicate-attribute", data[: m.end()] + m.group() + data[m.end():])


def rename(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """An element's name made empty, odd, or the same as another element's."""
    if profile.xml:
        alt = "|".join(profile.named).encode()
        found = list(re.finditer(rb"<(?:" + alt + rb")\b[^>]*?\bname=[\"']([^\"']*)[\"']",
                                 data))
    else:
        found = list(re.finditer(rb"def\s+\w+\s+\"([^\"]*)\"", data))
    if not found:
        return None
    m = rng.choice(found)
    if rng.random() < 0.5 and len(found) > 1:
        new = rng.choice([f for f in found if f is not m]).group(1)
        kind = "duplicate-name"
    else:
        new = rng.choice(BAD_NAMES).encode()
        kind = "bad-name"
    return Edit(kind, _replace(data, m.span(1), new))


def joint_cycle(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """A joint whose child is an ancestor (or itself): the tree becomes a cycle."""
    if profile.parent_child is None:
        return None
    found = list(profile.parent_child.finditer(data))
    if not found:
        return None
    m = rng.choice(found)
    how = rng.choice(("swap", "self", "root"))
    parent, child = m.group(1), m.group(2)
    if how == "swap":
        new_parent, new_child = child, parent
    elif how == "self":
        new_parent, new_child = parent, parent
    else:  # the first joint's parent is (usually) the root: make it every joint's child
        new_parent, new_child = parent, found[0].group(1)
    out = _replace(data, m.span(2), new_child)
    out = _replace(out, m.span(1), new_parent)
    return Edit(f"cycle-{how}", out)


#: What a mesh reference may be replaced with: (name, the reference, fixtures to make).
def _hostile_targets(fmt: str) -> list[tuple[str, bytes, tuple[Fixture, ...]]]:
    ext = ".usda" if fmt == "usd" else ".stl"
    c = CASE_MARK.decode()
    return [
        ("passwd", b"/etc/passwd", ()),
        ("dev-zero", b"/dev/zero", ()),
        ("dir", f"{c}/folder{ext}".encode(), (Fixture("dir", f"folder{ext}"),)),
        ("fifo", f"{c}/pipe{ext}".encode(), (Fixture("fifo", f"pipe{ext}"),)),
        ("sparse", f"{c}/huge{ext}".encode(), (Fixture("sparse", f"huge{ext}",
                                                        size=2 << 30),)),
        ("sparse-small", f"{c}/zeros{ext}".encode(), (Fixture("sparse", f"zeros{ext}",
                                                               size=8 << 20),)),
        ("loop", f"{c}/loop{ext}".encode(), (Fixture("loop", f"loop{ext}"),)),
        ("empty", f"{c}/empty{ext}".encode(), (Fixture("empty", f"empty{ext}"),)),
        ("link-passwd", f"{c}/passwd{ext}".encode(), (Fixture("link", f"passwd{ext}",
                                                              target="/etc/passwd"),)),
        ("missing", b"does/not/exist.stl", ()),
        ("url", b"http://127.0.0.1:9/robot.stl", ()),
        ("package", b"package://no_such_package/mesh.stl", ()),
        ("file-host", b"file://remote.example/mesh.stl", ()),
        ("self", b"", ()),  # the mutant's own path: filled in by the case
    ]


def hostile_reference(data: bytes, rng: random.Random, profile: Profile,
                      fmt: str = "urdf") -> Edit | None:
    """A mesh (or included layer) reference pointed at /etc/passwd, /dev/zero, a folder,
    a FIFO, a 2 GiB sparse file, a symbolic-link loop, a URL ..."""
    found = list(profile.mesh_ref.finditer(data))
    if not found:
        return None
    name, target, fixtures = rng.choice(_hostile_targets(fmt))
    if name == "self":
        target = CASE_MARK + b"/SELF"
    every = rng.random() < 0.3
    for m in reversed(found if every else [rng.choice(found)]):
        data = _replace(data, m.span(1), target)
    return Edit(f"path-{name}", data, fixtures)


_BOMB = (b'<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">'
         b'<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;">]>')
_XXE = b'<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
_DTD = b'<!DOCTYPE robot SYSTEM "http://127.0.0.1:9/robot.dtd">'


def entity_bomb(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    if not profile.xml:
        return None
    decl = rng.choice((_BOMB, _XXE, _DTD))
    end = data.find(b"?>") + 2 if data.startswith(b"<?xml") else 0
    out = data[:end] + b"\n" + decl + b"\n" + data[end:]
    spans = _attr_value_spans(out)
    if spans and decl is not _DTD:
        out = _replace(out, rng.choice(spans), b"&d;" if decl is _BOMB else b"&x;")
    return Edit("entity", out)


def xacro_expression(data: bytes, rng: random.Random, profile: Profile) -> Edit | None:
    """A xacro ``${...}`` expression (or a number) made to evaluate to something bad.

    Kept to values (division by zero, NaN, huge numbers, undefined names): what xacro
    expansion may reach on the file system or how long it may run is tested elsewhere."""
    expressions = list(re.finditer(rb"\$\{([^}]*)\}", data))
    numbers = list(_NUMBER.finditer(data))
    if not expressions and not numbers:
        return None
    new = rng.choice((b"1/0", b"float('nan')", b"1e308*10", b"undefined_name", b"-1e308",
                      b"(", b"1e-320", b"'text'", b"[1,2]"))
    if expressions:  # the expression's body replaced
        return Edit("xacro-expr", _replace(data, rng.choice(expressions).span(1), new))
    return Edit("xacro-expr", _replace(data, rng.choice(numbers).span(), b"${" + new + b"}"))


Mutator = Callable[[bytes, random.Random, Profile], "Edit | None"]

#: The description mutators, with their weights.
MUTATORS: tuple[tuple[Mutator, int], ...] = (
    (flip_bytes, 2), (truncate, 2), (splice, 1), (insert_bytes, 1),
    (bad_number, 6), (bad_numbers_everywhere, 2), (negative_mass, 2), (huge_mass, 3),
    (broken_tensor, 3), (other_attribute, 3), (huge_string, 1), (unicode_value, 1),
    (delete_element, 3), (duplicate_element, 2), (delete_attribute, 2),
    (duplicate_attribute, 1), (rename, 2), (joint_cycle, 2), (hostile_reference, 4),
    (entity_bomb, 1),
)


def mutate(data: bytes, fmt: str, rng: random.Random) -> Edit:
    """One mutation of a ``fmt`` document; falls back to a byte flip when the drawn
    mutator finds nothing it applies to."""
    profile = PROFILES[fmt]
    table = list(MUTATORS) + ([(xacro_expression, 4)] if fmt == "xacro" else [])
    funcs = [f for f, _ in table]
    weights = [w for _, w in table]
    for _ in range(8):
        func = rng.choices(funcs, weights)[0]
        if func is hostile_reference:
            edit = hostile_reference(data, rng, profile, fmt)
        else:
            edit = func(data, rng, profile)
        if edit is not None:
            return edit
    return flip_bytes(data, rng, profile) or Edit("append", data + b"<")
