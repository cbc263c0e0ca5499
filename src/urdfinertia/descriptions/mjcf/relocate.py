"""Keep an MJCF model's files found when its main file is written to another folder.

MuJoCo resolves every relative path of a model against the main file's folder: an
`<include file>`; `<compiler meshdir>`, `texturedir` and `assetdir`; and, through
them, each asset's `file` (`mesh`, `hfield` and `skin` under `meshdir`,
`texture` under `texturedir`; `assetdir` stands for whichever of the two is not
set). Only the main file is written elsewhere, so only its bytes change, and as few as
possible:

- a relative `meshdir`, `texturedir` or `assetdir` of the main file's `<compiler>`
  is rewritten to name the same folder from the output's folder; the assets' own `file`
  values then stay as written;
- a kind of asset that has relative files but no folder set (they were relative to the
  model's folder) gets one: an attribute added to the main file's last `<compiler>`, or a
  new `<compiler>` element first in `<mujoco>`;
- a folder set by a `<compiler>` of an included file (which cannot be edited) is
  overridden by a `<compiler>` added last in the main file (the last one read wins);
- each relative `<include file>` of the main file is rewritten. Includes nested in
  included files are left: MuJoCo also looks for them next to the file that includes them.

A path that has no relative form from the output's folder (another drive) is written
absolute (`relocated`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from urdfinertia.descriptions.references import (
    is_relative_ref,
    relocated,
    same_folder,
    splice_edits,
)
from urdfinertia.descriptions.splice import attribute_text, line_indent, next_tag
from urdfinertia.errors import UrdfInertiaError

DIR_ATTRS = ("meshdir", "texturedir", "assetdir")
MESH_KIND = (b"mesh", b"hfield", b"skin")
"""Asset elements whose files are found under `meshdir` (else `assetdir`)."""
TEXTURE_FILES = ("file", "fileright", "fileleft", "fileup", "filedown", "filefront",
                 "fileback")
"""A texture's file attributes (a cube map may give one file per face)."""
_ATTR = re.compile(rb"""([^\s=]+)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
MAX_INCLUDES = 256
"""The included files read to learn what an included model needs (as the reader's bound)."""


@dataclass
class _Value:
    """An attribute's value and, in the main file, the byte span of its text."""

    text: str
    span: tuple[int, int] | None


@dataclass
class _Scan:
    """What the model sets and needs, in the order MuJoCo reads it."""

    dirs: dict[str, _Value] = field(default_factory=dict)
    """Directory attribute -> its last value (the one MuJoCo uses)"""
    main_dirs: list[_Value] = field(default_factory=list)
    """Every compiler directory attribute of the main file."""
    includes: list[_Value] = field(default_factory=list)
    needs_mesh_dir: bool = False
    needs_texture_dir: bool = False
    last_compiler: tuple[int, int] | None = None
    """End of the main file's last <compiler> start tag's attributes, and its closing bytes."""
    root_start_end: int | None = None
    root_end_start: int | None = None
    first_child_indent: bytes | None = None
    files_read: int = 0


def _attributes(attrs: bytes, offset: int) -> dict[str, _Value]:
    out: dict[str, _Value] = {}
    for m in _ATTR.finditer(attrs):
        group = 2 if m.group(2) is not None else 3
        try:
            text = attribute_text(m.group(group))
        except UnicodeDecodeError:
            continue
        start, end = m.span(group)
        out[m.group(1).decode("ascii", "replace")] = _Value(text, (offset + start,
                                                                   offset + end))
    return out


def _scan(data: bytes, scan: _Scan, model_dir: Path, file_dir: Path, main: bool,
          depth: int = 0) -> None:
    pos = 0
    level = 0
    while True:
        m = next_tag(data, pos)
        if m is None:
            return
        closing, name, attrs, selfclose = m.group(5, 6, 7, 8)
        pos = m.end()
        if closing:
            level -= 1
            if main and level == 0 and name == b"mujoco":
                scan.root_end_start = m.start()
            continue
        if main and level == 0:
            scan.root_start_end = m.end()
        elif main and level == 1 and scan.first_child_indent is None:
            scan.first_child_indent = line_indent(data, m.start())
        if not selfclose:
            level += 1
        values = _attributes(attrs, m.start(7)) if attrs else {}
        if not main:
            values = {k: _Value(v.text, None) for k, v in values.items()}
        if name == b"compiler":
            for attr in DIR_ATTRS:
                if attr in values:
                    scan.dirs[attr] = values[attr]
                    if main:
                        scan.main_dirs.append(values[attr])
            if main:
                scan.last_compiler = (m.start(7) + len(attrs), m.end())
        elif name == b"include" and "file" in values:
            value = values["file"]
            if main:
                scan.includes.append(value)
            _scan_include(value.text, scan, model_dir, file_dir, depth)
        elif name in MESH_KIND:
            file = values.get("file")
            if file is not None and is_relative_ref(file.text):
                scan.needs_mesh_dir = True
        elif name == b"texture":
            if any(a in values and is_relative_ref(values[a].text) for a in TEXTURE_FILES):
                scan.needs_texture_dir = True


def _scan_include(name: str, scan: _Scan, model_dir: Path, file_dir: Path,
                  depth: int) -> None:
    """Read what an included file sets and needs (MuJoCo's lookup: the model's folder,
    then the including file's). An unreadable one is the reader's to report."""
    from urdfinertia.descriptions.formats import read_bytes

    if depth >= 16 or scan.files_read >= MAX_INCLUDES or not is_relative_ref(name) \
            and not Path(name).is_absolute():
        return
    for folder in (model_dir, file_dir):
        path = folder / name
        if path.is_file():
            try:
                data = read_bytes(path)
            except UrdfInertiaError:
                return
            scan.files_read += 1
            try:
                _scan(data, scan, model_dir, path.parent, False, depth + 1)
            except UrdfInertiaError:
                pass
            return


def _quoted(text: str) -> bytes:
    escaped = text.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;")
    return f'"{escaped}"'.encode()


def _escaped(text: str) -> bytes:
    return _quoted(text)[1:-1]


def relocate_mjcf_refs(data: bytes, source_dir: Path, output_dir: Path,
                       ) -> tuple[bytes, int]:
    """`data` (an MJCF main file of `source_dir`) made to find its files when written
    in `output_dir` (see the module doc); and how many references were rewritten or
    added."""
    if same_folder(source_dir, output_dir):
        return data, 0
    scan = _Scan()
    _scan(data, scan, source_dir, source_dir, True)
    edits: list[tuple[int, int, bytes]] = []

    def moved(text: str) -> str:
        return relocated(text, source_dir, output_dir)

    for value in (*scan.main_dirs, *scan.includes):
        if value.span is not None and (value.text == "" or is_relative_ref(value.text)):
            new = moved(value.text)
            if new != value.text:
                edits.append((*value.span, _escaped(new)))
    added: dict[str, str] = {}
    overrides: dict[str, str] = {}
    kinds = [("meshdir", scan.needs_mesh_dir), ("texturedir", scan.needs_texture_dir)]
    for attr, needed in kinds:
        if not needed:
            continue
        current = scan.dirs.get(attr) or scan.dirs.get("assetdir")
        if current is None:
            added[attr] = moved("")
        elif current.span is None and (current.text == "" or is_relative_ref(current.text)):
            overrides[attr] = moved(current.text)
    if added.keys() == {"meshdir", "texturedir"} and "assetdir" not in scan.dirs:
        added = {"assetdir": added["meshdir"]}
    if added:
        text = b"".join(b" " + k.encode() + b"=" + _quoted(v) for k, v in added.items())
        if scan.last_compiler is not None:
            at = scan.last_compiler[0]
            edits.append((at, at, text))
        elif scan.root_start_end is not None:
            at = scan.root_start_end
            indent = scan.first_child_indent or b""
            newline = b"\r\n" if b"\r\n" in data else b"\n"
            edits.append((at, at, newline + indent + b"<compiler" + text + b"/>"))
    if overrides and scan.root_end_start is not None:
        at = scan.root_end_start
        text = b"".join(b" " + k.encode() + b"=" + _quoted(v) for k, v in overrides.items())
        edits.append((at, at, b"<compiler" + text + b"/>"))
    rewritten = len(edits) - bool(added) - bool(overrides)
    return splice_edits(data, edits), rewritten + len(added) + len(overrides)
